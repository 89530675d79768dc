//! OpenNet's scanned-PLC instructions against `opennet.md`: timers in virtual time at several
//! `scan_ms` (§3, §5.8), counters and the vendor's counter-built timer (§5.9), shift registers
//! (§5.10), comparisons, word logic, shifts and BCD conversions (§5.11, §6), T/C word operands
//! (§4.3), master control and jumps (§5.12), the clocks (§3), the new assembler errors and the
//! MICRO3 warnings (§1, §5.1) and the runner's JSON (§9). Every expected value comes from the
//! spec's rules and examples; the comments derive it.

use servoscope_core::machine::opennet::OpenNet;
use servoscope_core::machine::opennet::assembler::assemble;
use servoscope_core::machine::plc::TimeBase;
use servoscope_core::machine::{Machine, MachineView, Severity};
use std::sync::Arc;

fn plc(src: &str, scan_ms: u32) -> OpenNet {
    let program = assemble(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    OpenNet::with_time(Arc::new(program), TimeBase { scan_ms })
}

fn get(m: &OpenNet, name: &str) -> u64 {
    m.read(m.find(name).unwrap_or_else(|| panic!("{name} exists")))
}

fn set(m: &mut OpenNet, name: &str, v: u64) {
    let loc = m.find(name).unwrap_or_else(|| panic!("{name} exists"));
    m.write(loc, v)
        .unwrap_or_else(|e| panic!("write {name}: {e:?}"));
}

/// Run until `n` scans have completed.
fn to_scan(m: &mut OpenNet, n: u64) {
    m.run_until(n, |_| false);
    assert_eq!(m.ticks(), n);
}

/// Run `count` more scans.
fn scans(m: &mut OpenNet, count: u64) {
    let t = m.ticks();
    to_scan(m, t + count);
}

/// One rising edge on `input`: on for one scan, then off for one scan.
fn pulse(m: &mut OpenNet, input: &str) {
    set(m, input, 1);
    scans(m, 1);
    set(m, input, 0);
    scans(m, 1);
}

fn values(m: &OpenNet, names: &[&str]) -> Vec<u64> {
    names.iter().map(|n| get(m, n)).collect()
}

/// `k` R bits from `Rfirst`.
fn r_bits(m: &OpenNet, first: usize, k: usize) -> Vec<u64> {
    (first..first + k)
        .map(|i| get(m, &format!("R{i}")))
        .collect()
}

/// `src` after `LOD M8120` (so its advanced instructions act in scan 0 only), one scan at 10 ms.
/// The program's line n is line n + 1 of the file.
fn once(src: &str) -> OpenNet {
    let mut m = plc(&format!("LOD M8120\n{src}"), 10);
    to_scan(&mut m, 1);
    m
}

fn timer(m: &OpenNet, t: &str) -> (u64, u64, u64) {
    (
        get(m, &format!("{t}.preset")),
        get(m, &format!("{t}.current")),
        get(m, t),
    )
}

fn counter(m: &OpenNet, c: &str) -> (u64, u64, u64) {
    timer(m, c)
}

fn last_error(m: &OpenNet) -> (&'static str, usize, u64) {
    let e = m
        .last_error
        .as_ref()
        .expect("an execution error was recorded");
    (e.kind, e.line, e.tick)
}

/// The increment of a timer instruction in ms (§5.8).
fn increment(op: &str) -> u64 {
    match op {
        "TML" => 1000,
        "TIM" => 100,
        "TMH" => 10,
        "TMS" => 1,
        _ => unreachable!("{op}"),
    }
}

/// The error diagnostics of `src` as (line, message); empty when it assembles.
fn errors(src: &str) -> Vec<(usize, String)> {
    match assemble(src) {
        Ok(_) => Vec::new(),
        Err(e) => e
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .map(|d| {
                assert!(d.to_string().contains(": error: "), "{d}");
                (d.line, d.message.clone())
            })
            .collect(),
    }
}

/// Require an error on `line` whose message contains one of the `|`-separated `words`
/// (case-insensitive; an empty `words` asks only for the line).
fn assert_error(src: &str, line: usize, words: &str) {
    let e = errors(src);
    let found = e.iter().any(|(l, msg)| {
        *l == line
            && (words.is_empty()
                || words
                    .split('|')
                    .any(|w| msg.to_lowercase().contains(&w.to_lowercase())))
    });
    assert!(
        found,
        "{src}\n---\n{e:#?}\nshould have an error on line {line} mentioning {words}"
    );
}

fn assert_assembles(src: &str) {
    if let Err(e) = assemble(src) {
        let text: Vec<String> = e.iter().map(ToString::to_string).collect();
        panic!("{src}\n---\nshould assemble:\n{}", text.join("\n"));
    }
}

/// The warnings of a program that assembles, as (line, message).
fn warnings(src: &str) -> Vec<(usize, String)> {
    let program = assemble(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    program
        .warnings
        .iter()
        .map(|d| {
            assert_eq!(d.severity, Severity::Warning, "{d}");
            assert!(d.to_string().contains(": warning: "), "{d}");
            (d.line, d.message.clone())
        })
        .collect()
}

// ---- §5.8 Timers ------------------------------------------------------------------------------

/// §5.8: with the input on from scan s, in scan s + j the current value is
/// max(0, P − ⌊j × scan_ms / inc⌋) and the output is on first in scan s + ⌈P × inc / scan_ms⌉;
/// before that (input off) current = preset and the output is 0. Each case lists that first j.
#[test]
fn timers_count_down_by_the_formula_at_every_scan_time() {
    // (instruction, preset P, scan_ms, ⌈P × inc / scan_ms⌉)
    let cases: [(&str, u64, u64, u64); 13] = [
        ("TIM", 30, 10, 300), // 3000 / 10
        ("TIM", 2, 33, 7),    // 200 / 33 = 6.06 → 7: on after 231 ms (§8)
        ("TIM", 3, 50, 6),    // 300 / 50
        ("TIM", 5, 1000, 1),  // 500 / 1000 → 1
        ("TIM", 1, 1, 100),   // 100 / 1
        ("TMH", 7, 10, 7),    // 70 / 10
        ("TMH", 7, 50, 2),    // 70 / 50 = 1.4 → 2
        ("TMS", 5, 1, 5),     // 5 / 1
        ("TMS", 25, 10, 3),   // 25 / 10 = 2.5 → 3
        ("TMS", 100, 33, 4),  // 100 / 33 = 3.03 → 4
        ("TML", 2, 10, 200),  // 2000 / 10
        ("TML", 1, 33, 31),   // 1000 / 33 = 30.3 → 31
        ("TML", 3, 1000, 3),  // 3000 / 1000
    ];
    const S: u64 = 3;
    for (op, p, scan_ms, on_at) in cases {
        let what = format!("{op} T0 {p} at {scan_ms} ms");
        let mut m = plc(&format!("LOD I0\n{op} T0 {p}\nEND"), scan_ms as u32);
        to_scan(&mut m, S);
        assert_eq!(timer(&m, "T0"), (p, p, 0), "{what}: input off");
        set(&mut m, "I0", 1);
        for j in 0..on_at + 3 {
            to_scan(&mut m, S + j + 1);
            let current = p.saturating_sub(j * scan_ms / increment(op));
            assert_eq!(get(&m, "T0.current"), current, "{what}: scan s+{j}");
            assert_eq!(get(&m, "T0"), u64::from(j >= on_at), "{what}: scan s+{j}");
        }
    }
}

/// §8's example: TIM at 33 ms with preset 2 is on after 231 ms. The remainder e goes 33, 66,
/// 99, 132 → current 1 (e 32), 65, 98, 131 → current 0: scan 7, which starts at 7 × 33 = 231 ms.
#[test]
fn tim_at_33_ms_with_preset_2_turns_on_in_the_scan_at_231_ms() {
    let mut m = plc("LOD I0\nTIM T0 2\nLOD T0\nOUT Q0", 33);
    set(&mut m, "I0", 1);
    let mut seen = Vec::new();
    for k in 1..=8 {
        to_scan(&mut m, k);
        seen.push((get(&m, "T0.current"), get(&m, "T0"), get(&m, "Q0")));
    }
    assert_eq!(
        seen,
        [
            (2, 0, 0),
            (2, 0, 0),
            (2, 0, 0),
            (2, 0, 0),
            (1, 0, 0),
            (1, 0, 0),
            (1, 0, 0),
            (0, 1, 1)
        ]
    );
}

/// §2 start values and §5.8 step 2: input off → current = preset, output 0; a restart's first
/// powered execution counts no time. TMH T0 5 at 10 ms counts one per scan.
#[test]
fn input_off_resets_the_timer_and_a_restart_counts_no_time_in_its_first_scan() {
    let mut m = plc("LOD I0\nTMH T0 5\nLOD T0\nOUT Q0", 10);
    assert_eq!(timer(&m, "T0"), (5, 5, 0), "start: current = preset");
    set(&mut m, "I0", 1);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "T0.current"), 3, "scans 0, 1, 2: 5, 4, 3");
    set(&mut m, "I0", 0);
    to_scan(&mut m, 4);
    assert_eq!(timer(&m, "T0"), (5, 5, 0), "off: back to the preset");
    set(&mut m, "I0", 1);
    to_scan(&mut m, 5);
    assert_eq!(get(&m, "T0.current"), 5, "scan 4: first powered, no time");
    to_scan(&mut m, 6);
    assert_eq!(get(&m, "T0.current"), 4);
    to_scan(&mut m, 9);
    assert_eq!(
        (get(&m, "T0.current"), get(&m, "Q0")),
        (1, 0),
        "scan 8 = s+4"
    );
    to_scan(&mut m, 10);
    assert_eq!(
        (get(&m, "T0.current"), get(&m, "Q0")),
        (0, 1),
        "scan 9 = s+5"
    );
    to_scan(&mut m, 12);
    assert_eq!(
        timer(&m, "T0"),
        (5, 0, 1),
        "stays on at 0 while the input is on"
    );
    set(&mut m, "I0", 0);
    to_scan(&mut m, 13);
    assert_eq!((timer(&m, "T0"), get(&m, "Q0")), ((5, 5, 0), 0));
}

/// §5.8: preset 0 turns the output on in the first powered scan, constant or register.
#[test]
fn preset_zero_is_on_in_the_first_powered_scan() {
    for src in ["LOD I0\nTIM T0 0", "LOD I0\nTIM T0 D10"] {
        let mut m = plc(src, 10);
        to_scan(&mut m, 2);
        assert_eq!(timer(&m, "T0"), (0, 0, 0), "{src}: input off, output 0");
        set(&mut m, "I0", 1);
        to_scan(&mut m, 3);
        assert_eq!(
            timer(&m, "T0"),
            (0, 0, 1),
            "{src}: on in scan 2, its first powered scan"
        );
    }
}

/// §2: a register preset starts at 0; §5.8 step 1: every execution reads Dm.
/// TMH T0 D10, D10 = 4: input on from scan 1 → on in scan 1 + 4 = 5.
#[test]
fn a_register_preset_is_read_at_every_execution() {
    let mut m = plc("LOD I0\nTMH T0 D10", 10);
    assert_eq!(
        timer(&m, "T0"),
        (0, 0, 0),
        "start: preset 0 for a register preset"
    );
    set(&mut m, "D10", 4);
    to_scan(&mut m, 1);
    assert_eq!(
        timer(&m, "T0"),
        (4, 4, 0),
        "scan 0, input off: preset = D10, current = preset"
    );
    set(&mut m, "I0", 1);
    to_scan(&mut m, 5);
    assert_eq!(timer(&m, "T0"), (4, 1, 0), "scan 4 = s+3");
    to_scan(&mut m, 6);
    assert_eq!(timer(&m, "T0"), (4, 0, 1), "scan 5 = s+4");
}

/// §5.8: a preset changed while timing leaves the running current alone and is used from the
/// next start. TMH T0 (preset 5, one count a scan), input on from scan 0; at scan 3 the preset
/// becomes 20: current 2 in scan 3, on in scan 5 as before; off at 6, on again at 7 → current
/// 20 in scan 7 and on in scan 7 + 20 = 27. The same through a register and through `MOV(W) 20 T0`.
#[test]
fn a_preset_change_while_timing_is_used_from_the_next_start() {
    for (src, change) in [
        ("LOD I0\nTMH T0 D10", "D10"),
        ("LOD I1\nMOV(W) 20 T0\nLOD I0\nTMH T0 5", "I1"),
    ] {
        let mut m = plc(src, 10);
        if change == "D10" {
            set(&mut m, "D10", 5);
        }
        set(&mut m, "I0", 1);
        to_scan(&mut m, 3);
        assert_eq!(timer(&m, "T0"), (5, 3, 0), "{src}");
        if change == "D10" {
            set(&mut m, "D10", 20);
        } else {
            set(&mut m, "I1", 1);
        }
        to_scan(&mut m, 4);
        assert_eq!(
            timer(&m, "T0"),
            (20, 2, 0),
            "{src}: the running current is left alone"
        );
        to_scan(&mut m, 6);
        assert_eq!(
            timer(&m, "T0"),
            (20, 0, 1),
            "{src}: on in scan 5 as timed from 5"
        );
        set(&mut m, "I0", 0);
        to_scan(&mut m, 7);
        assert_eq!(timer(&m, "T0"), (20, 20, 0), "{src}: off → the new preset");
        set(&mut m, "I0", 1);
        to_scan(&mut m, 8);
        assert_eq!(get(&m, "T0.current"), 20, "{src}: scan 7, first powered");
        to_scan(&mut m, 27);
        assert_eq!(timer(&m, "T0"), (20, 1, 0), "{src}: scan 26 = s+19");
        to_scan(&mut m, 28);
        assert_eq!(timer(&m, "T0"), (20, 0, 1), "{src}: scan 27 = s+20");
    }
}

/// §4.3: a timer as a destination takes the preset. `MOV(W) 5 T0` in scan 0 before
/// `TMH T0 50` (input off) → preset 5, current 5; input on from scan 1 → on in scan 6.
#[test]
fn mov_to_a_timer_sets_its_preset() {
    let mut m = plc("LOD M8120\nMOV(W) 5 T0\nLOD I0\nTMH T0 50", 10);
    assert_eq!(timer(&m, "T0"), (50, 50, 0));
    to_scan(&mut m, 1);
    assert_eq!(timer(&m, "T0"), (5, 5, 0));
    set(&mut m, "I0", 1);
    to_scan(&mut m, 6);
    assert_eq!(timer(&m, "T0"), (5, 1, 0), "scan 5 = s+4");
    to_scan(&mut m, 7);
    assert_eq!(timer(&m, "T0"), (5, 0, 1), "scan 6 = s+5");
}

/// §5.8: a write to Tn of a timer whose preset is Dm is replaced by Dm at its next execution.
#[test]
fn a_register_preset_replaces_a_written_preset_at_the_next_execution() {
    let mut m = plc("LOD I0\nTMH T0 D10\nLOD I1\nMOV(W) 9 T0", 10);
    set(&mut m, "D10", 4);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "T0.preset"), 9, "the MOV ran after the timer");
    set(&mut m, "I1", 0);
    to_scan(&mut m, 2);
    assert_eq!(timer(&m, "T0"), (4, 4, 0), "the timer read D10 again");
}

/// §5.8: the current value and the output change only when the timer instruction executes,
/// so a contact or word read of T0 before it sees the previous scan's values.
/// TMH T0 3 on from scan 0: current 3, 2, 1, 0 in scans 0–3, on in scan 3.
#[test]
fn a_read_of_the_timer_before_its_instruction_sees_the_previous_scan() {
    let src = "LOD T0\nOUT Q1\nLOD M8125\nMOV(W) T0 D0\nLOD I0\nTMH T0 3\nLOD T0\nOUT Q0\nLOD M8125\nMOV(W) T0 D1";
    let mut m = plc(src, 10);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 1);
    assert_eq!(
        values(&m, &["D0", "D1"]),
        [3, 3],
        "start value 3, then scan 0 = 3"
    );
    to_scan(&mut m, 2);
    assert_eq!(values(&m, &["D0", "D1"]), [3, 2]);
    to_scan(&mut m, 4);
    assert_eq!(
        values(&m, &["D0", "D1", "Q0", "Q1"]),
        [1, 0, 1, 0],
        "scan 3"
    );
    to_scan(&mut m, 5);
    assert_eq!(
        values(&m, &["D0", "D1", "Q0", "Q1"]),
        [0, 0, 1, 1],
        "scan 4"
    );
}

/// §5.12, §8: in an MCS area that is off the timer's input is off, so it resets (current =
/// preset, output 0) and its next powered execution counts no time.
#[test]
fn a_timer_in_an_mcs_area_that_is_off_resets() {
    let mut m = plc("LOD I1\nMCS\nLOD I0\nTMH T0 10\nMCR", 10);
    set(&mut m, "I0", 1);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 4);
    assert_eq!(get(&m, "T0.current"), 7, "scans 0–3: 10, 9, 8, 7");
    set(&mut m, "I1", 0);
    to_scan(&mut m, 5);
    assert_eq!(timer(&m, "T0"), (10, 10, 0), "MC = 0: reset");
    set(&mut m, "I1", 1);
    to_scan(&mut m, 6);
    assert_eq!(get(&m, "T0.current"), 10, "scan 5: first powered again");
    to_scan(&mut m, 7);
    assert_eq!(get(&m, "T0.current"), 9);
}

/// §5.12, §8: a timer jumped over holds its current value and output and adds no time.
/// TMH T0 5 on from scan 0: 5, 4, 3 in scans 0–2; jumped over in scans 3–7; 2, 1, 0 in 8–10.
#[test]
fn a_jumped_over_timer_holds_and_resumes_without_the_skipped_time() {
    let mut m = plc("LOD I1\nJMP\nLOD I0\nTMH T0 5\nJEND\nLOD T0\nOUT Q0", 10);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "T0.current"), 3);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 8);
    assert_eq!(
        timer(&m, "T0"),
        (5, 3, 0),
        "five scans skipped: nothing changed"
    );
    set(&mut m, "I1", 0);
    to_scan(&mut m, 9);
    assert_eq!(get(&m, "T0.current"), 2, "one scan's time, not six");
    to_scan(&mut m, 11);
    assert_eq!((timer(&m, "T0"), get(&m, "Q0")), ((5, 0, 1), 1), "scan 10");
    // Jumped over with its input off: the output holds too.
    set(&mut m, "I0", 0);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 13);
    assert_eq!((timer(&m, "T0"), get(&m, "Q0")), ((5, 0, 1), 1), "held");
    set(&mut m, "I1", 0);
    to_scan(&mut m, 14);
    assert_eq!(
        (timer(&m, "T0"), get(&m, "Q0")),
        ((5, 5, 0), 0),
        "executed: reset"
    );
}

// ---- §5.9 Counters ------------------------------------------------------------------------------

/// §5.9 CNT (reset, pulse): a rising pulse adds 1 while current < preset; output = current ≥
/// preset; reset clears; reset wins over pulses.
#[test]
fn cnt_counts_rising_edges_stops_at_its_preset_and_resets() {
    let mut m = plc("LOD I0\nLOD I1\nCNT C0 3\nLOD C0\nOUT Q0", 10);
    assert_eq!(counter(&m, "C0"), (3, 0, 0), "§2 start values");
    pulse(&mut m, "I1");
    pulse(&mut m, "I1");
    assert_eq!((counter(&m, "C0"), get(&m, "Q0")), ((3, 2, 0), 0));
    set(&mut m, "I1", 1);
    scans(&mut m, 3);
    assert_eq!(
        (counter(&m, "C0"), get(&m, "Q0")),
        ((3, 3, 1), 1),
        "held on: one count"
    );
    set(&mut m, "I1", 0);
    scans(&mut m, 1);
    pulse(&mut m, "I1");
    assert_eq!(counter(&m, "C0"), (3, 3, 1), "stops at the preset");
    set(&mut m, "I0", 1);
    pulse(&mut m, "I1");
    assert_eq!(
        (counter(&m, "C0"), get(&m, "Q0")),
        ((3, 0, 0), 0),
        "reset wins"
    );
    set(&mut m, "I0", 0);
    pulse(&mut m, "I1");
    assert_eq!(counter(&m, "C0"), (3, 1, 0));
}

/// §5.9, §8: the pulse memory starts at 0, so a pulse already on in scan 0 counts; a pulse that
/// is on when the reset releases counts only when it rises again.
#[test]
fn cnt_pulse_memory_at_scan_0_and_at_reset_release() {
    let mut m = plc("LOD I0\nLOD I1\nCNT C0 5", 10);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "C0.current"), 1, "on in scan 0: counted");
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "C0.current"), 1);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 4);
    assert_eq!(get(&m, "C0.current"), 0);
    set(&mut m, "I0", 0);
    to_scan(&mut m, 6);
    assert_eq!(
        get(&m, "C0.current"),
        0,
        "I1 stayed on through the reset: no edge"
    );
    set(&mut m, "I1", 0);
    to_scan(&mut m, 7);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 8);
    assert_eq!(get(&m, "C0.current"), 1, "it rose again");
}

/// §5.9: every execution reads a register preset; a preset lowered below a CNT's current value
/// turns the output on at the next execution (the count stays: it only counts below the preset).
#[test]
fn a_register_preset_lowered_below_the_count_turns_cnt_on() {
    let mut m = plc("LOD I0\nLOD I1\nCNT C0 D10", 10);
    assert_eq!(
        counter(&m, "C0"),
        (0, 0, 0),
        "a register preset starts at 0"
    );
    set(&mut m, "D10", 5);
    for _ in 0..3 {
        pulse(&mut m, "I1");
    }
    assert_eq!(counter(&m, "C0"), (5, 3, 0));
    set(&mut m, "D10", 2);
    scans(&mut m, 1);
    assert_eq!(counter(&m, "C0"), (2, 3, 1), "3 ≥ 2");
    pulse(&mut m, "I1");
    assert_eq!(counter(&m, "C0"), (2, 3, 1), "3 is not below 2: no count");
}

/// §4.3, §5.9: `MOV(W) 7 C0` sets the preset of `CNT C0 3` (a constant preset is not read again).
#[test]
fn mov_to_a_counter_sets_its_preset() {
    let mut m = plc(
        "LOD M8120\nMOV(W) 7 C0\nLOD I0\nLOD I1\nCNT C0 3\nLOD C0\nOUT Q0",
        10,
    );
    to_scan(&mut m, 1);
    assert_eq!(counter(&m, "C0"), (7, 0, 0));
    for _ in 0..3 {
        pulse(&mut m, "I1");
    }
    assert_eq!(
        (counter(&m, "C0"), get(&m, "Q0")),
        ((7, 3, 0), 0),
        "3 < 7: off"
    );
    for _ in 0..4 {
        pulse(&mut m, "I1");
    }
    assert_eq!((counter(&m, "C0"), get(&m, "Q0")), ((7, 7, 1), 1));
}

/// §5.9 CDP (preset input, up, down): output = (current = 0), wrapping 65535 ↔ 0, both edges
/// together do nothing, the preset input wins.
#[test]
fn cdp_counts_up_and_down_and_wraps() {
    let mut m = plc("LOD I0\nLOD I1\nLOD I2\nCDP C0 5\nLOD C0\nOUT Q0", 10);
    assert_eq!(counter(&m, "C0"), (5, 0, 0), "§2: output 0 before any scan");
    to_scan(&mut m, 1);
    assert_eq!(
        (counter(&m, "C0"), get(&m, "Q0")),
        ((5, 0, 1), 1),
        "§8: at 0 before a preset: on"
    );
    pulse(&mut m, "I0");
    assert_eq!(
        counter(&m, "C0"),
        (5, 5, 0),
        "preset input: current = preset"
    );
    pulse(&mut m, "I1");
    assert_eq!(get(&m, "C0.current"), 6);
    pulse(&mut m, "I2");
    pulse(&mut m, "I2");
    assert_eq!(get(&m, "C0.current"), 4);
    set(&mut m, "I1", 1);
    set(&mut m, "I2", 1);
    scans(&mut m, 1);
    set(&mut m, "I1", 0);
    set(&mut m, "I2", 0);
    scans(&mut m, 1);
    assert_eq!(get(&m, "C0.current"), 4, "both rising: nothing");
    for _ in 0..4 {
        pulse(&mut m, "I2");
    }
    assert_eq!((counter(&m, "C0"), get(&m, "Q0")), ((5, 0, 1), 1));
    pulse(&mut m, "I2");
    assert_eq!(counter(&m, "C0"), (5, 65535, 0), "0 − 1 wraps");
    pulse(&mut m, "I1");
    assert_eq!(counter(&m, "C0"), (5, 0, 1), "65535 + 1 wraps");
    // The preset input wins over an up pulse in the same scan; that pulse does not count later.
    set(&mut m, "I0", 1);
    set(&mut m, "I1", 1);
    scans(&mut m, 1);
    set(&mut m, "I0", 0);
    scans(&mut m, 2);
    assert_eq!(counter(&m, "C0"), (5, 5, 0));
}

/// §5.9 CDP: an up pulse already on in scan 0 counts (memory 0 at start).
#[test]
fn cdp_up_pulse_on_in_scan_0_counts() {
    let mut m = plc("LOD I0\nLOD I1\nLOD I2\nCDP C0 5", 10);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 3);
    assert_eq!(counter(&m, "C0"), (5, 1, 0));
}

/// §5.9 CUD (preset input, pulse, up/down selection with 1 = up), wrapping; the selection
/// alone is not a pulse.
#[test]
fn cud_counts_in_the_selected_direction() {
    let mut m = plc("LOD I0\nLOD I1\nLOD I2\nCUD C0 3\nLOD C0\nOUT Q0", 10);
    pulse(&mut m, "I0");
    assert_eq!(counter(&m, "C0"), (3, 3, 0));
    set(&mut m, "I2", 1);
    pulse(&mut m, "I1");
    pulse(&mut m, "I1");
    assert_eq!(get(&m, "C0.current"), 5, "up twice");
    set(&mut m, "I2", 0);
    scans(&mut m, 1);
    set(&mut m, "I2", 1);
    scans(&mut m, 1);
    set(&mut m, "I2", 0);
    scans(&mut m, 1);
    assert_eq!(
        get(&m, "C0.current"),
        5,
        "toggling the selection counts nothing"
    );
    for _ in 0..5 {
        pulse(&mut m, "I1");
    }
    assert_eq!(
        (counter(&m, "C0"), get(&m, "Q0")),
        ((3, 0, 1), 1),
        "down five times"
    );
    pulse(&mut m, "I1");
    assert_eq!(counter(&m, "C0"), (3, 65535, 0));
    set(&mut m, "I2", 1);
    pulse(&mut m, "I1");
    assert_eq!(counter(&m, "C0"), (3, 0, 1));
}

/// §5.9, §5.12: with MC = 0 a counter holds its current value, its output is 0, reset does not
/// act and its pulse memories become 0 — so a pulse held on through the off scan counts when MC
/// returns. C0 (preset 3) and C1 (preset 100) count the same pulses.
#[test]
fn counters_in_an_mcs_area_that_is_off_hold_and_forget_their_pulse() {
    let src =
        "LOD I3\nMCS\nLOD I0\nLOD I1\nCNT C0 3\nLOD I0\nLOD I1\nCNT C1 100\nMCR\nLOD C0\nOUT Q0";
    let mut m = plc(src, 10);
    set(&mut m, "I3", 1);
    pulse(&mut m, "I1");
    pulse(&mut m, "I1");
    set(&mut m, "I1", 1);
    to_scan(&mut m, 5);
    assert_eq!(
        (counter(&m, "C0"), get(&m, "C1.current"), get(&m, "Q0")),
        ((3, 3, 1), 3, 1)
    );
    // Scan 5: MC = 0 with the reset on and I1 still on.
    set(&mut m, "I3", 0);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 6);
    assert_eq!(
        (counter(&m, "C0"), get(&m, "C1.current"), get(&m, "Q0")),
        ((3, 3, 0), 3, 0),
        "held, output 0, the reset did not act"
    );
    // Scan 6: MC = 1, reset off, I1 still on: the memory was cleared, so this is an edge.
    set(&mut m, "I3", 1);
    set(&mut m, "I0", 0);
    to_scan(&mut m, 7);
    assert_eq!(get(&m, "C1.current"), 4, "counted again");
    assert_eq!(
        counter(&m, "C0"),
        (3, 3, 1),
        "C0 stays at its preset, on again"
    );
}

/// §5.9, MICRO3 p.7-17: `LODN I1 / LOD M8122 / CNT C2 100`. At 10 ms M8122 is on in scans 0–4
/// of every 10 (§3), so it rises at scans 0, 10, 20, …; I1 on from scan 5 (M8122 off, memory
/// kept by the executions under reset) → edges at 10, 20, …: the 100th at scan 1000 (t = 10 s).
#[test]
fn the_vendors_counter_built_timer_takes_ten_seconds_at_10_ms() {
    let src = "LODN I1\nLOD M8122\nCNT C2 100";
    for start in [5, 3] {
        // From scan 3 (M8122 on since scan 0): the clock is not seen rising until scan 10.
        let mut m = plc(src, 10);
        to_scan(&mut m, start);
        assert_eq!(counter(&m, "C2"), (100, 0, 0), "reset on while I1 is off");
        set(&mut m, "I1", 1);
        to_scan(&mut m, 10);
        assert_eq!(get(&m, "C2.current"), 0, "from scan {start}");
        to_scan(&mut m, 11);
        assert_eq!(get(&m, "C2.current"), 1, "from scan {start}");
        to_scan(&mut m, 1000);
        assert_eq!(counter(&m, "C2"), (100, 99, 0), "from scan {start}");
        to_scan(&mut m, 1001);
        assert_eq!(
            counter(&m, "C2"),
            (100, 100, 1),
            "from scan {start}: scan 1000"
        );
    }
}

/// The same counter at other scan times (§3: the clock is sampled at scan start t = k × scan_ms).
/// 50 ms: M8122 = (50k mod 100 < 50) is on in even scans; I1 on from scan 1 → edges at 2, 4, …,
/// the 100th at scan 200 (t = 10 s). 100 ms: M8122 is always 1 (aliasing): it rises only at
/// scan 0 (memory 0 at start), so from scan 0 the count is 1 and from scan 2 it is 0 for ever.
#[test]
fn the_counter_built_timer_at_50_and_100_ms() {
    let src = "LODN I1\nLOD M8122\nCNT C2 100";
    let mut m = plc(src, 50);
    to_scan(&mut m, 1);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "C2.current"), 1, "scan 2");
    to_scan(&mut m, 200);
    assert_eq!(counter(&m, "C2"), (100, 99, 0));
    to_scan(&mut m, 201);
    assert_eq!(counter(&m, "C2"), (100, 100, 1), "scan 200, t = 10 000 ms");

    let mut m = plc(src, 100);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 300);
    assert_eq!(counter(&m, "C2"), (100, 1, 0), "only scan 0's edge");
    let mut m = plc(src, 100);
    to_scan(&mut m, 2);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 300);
    assert_eq!(counter(&m, "C2"), (100, 0, 0), "never rises");
}

/// §5.1, §5.9: CC=/CC>= compare a counter's current value (its output plays no part), DC=/DC>=
/// a register, unsigned; they start a rung or push a block inside one.
#[test]
fn counter_and_data_comparison_contacts() {
    let src = "CC= C0 3\nOUT Q0\nCC>= C0 3\nOUT Q1\nDC= D0 5\nOUT Q2\nDC>= D0 5\nOUT Q3\n\
               LOD I2\nCC>= C0 3\nANDLOD\nOUT Q4\nLOD I2\nDC= D0 65535\nORLOD\nOUT Q5\n\
               DC>= D1 40000\nOUT Q6\nLOD I0\nLOD I1\nCNT C0 10";
    let qs = ["Q0", "Q1", "Q2", "Q3", "Q4", "Q5", "Q6"];
    let mut m = plc(src, 10);
    set(&mut m, "C0.current", 3);
    set(&mut m, "D0", 5);
    set(&mut m, "D1", 65535);
    to_scan(&mut m, 1);
    assert_eq!(values(&m, &qs), [1, 1, 1, 1, 0, 0, 1]);
    assert_eq!(get(&m, "C0"), 0, "3 < 10: the counter's output is off");
    set(&mut m, "C0.current", 4);
    set(&mut m, "D0", 65535);
    set(&mut m, "D1", 39999);
    set(&mut m, "I2", 1);
    to_scan(&mut m, 2);
    assert_eq!(values(&m, &qs), [0, 1, 0, 1, 1, 1, 0], "65535 ≥ 5 unsigned");
    set(&mut m, "C0.current", 2);
    set(&mut m, "D0", 4);
    to_scan(&mut m, 3);
    assert_eq!(values(&m, &qs), [0, 0, 0, 0, 0, 1, 0]);
}

// ---- §5.10 Shift registers ---------------------------------------------------------------------

/// §5.10 SFR R0 4 (reset I0, pulse I1, data I2): a rising pulse moves R0…R3 up (R3 lost) and
/// sets R0 = data; R4 is outside and keeps the 1 that SET put there. R0 as W is R0–R15 (§4.2).
#[test]
fn sfr_shifts_up_on_rising_pulses_and_reset_clears() {
    let src = "LOD M8120\nSET R4\nLOD I0\nLOD I1\nLOD I2\nSFR R0 4\nLOD R2\nOUT Q0\nLOD M8125\nMOV(W) R0 D0";
    let mut m = plc(src, 10);
    let shift = |m: &mut OpenNet, data: u64| {
        set(m, "I2", data);
        pulse(m, "I1");
        r_bits(m, 0, 5)
    };
    assert_eq!(shift(&mut m, 1), [1, 0, 0, 0, 1]);
    assert_eq!(shift(&mut m, 0), [0, 1, 0, 0, 1]);
    assert_eq!(shift(&mut m, 1), [1, 0, 1, 0, 1]);
    assert_eq!(shift(&mut m, 1), [1, 1, 0, 1, 1]);
    assert_eq!(
        shift(&mut m, 0),
        [0, 1, 1, 0, 1],
        "R3's 1 is lost, R4 untouched"
    );
    assert_eq!(get(&m, "Q0"), 1, "R2 as a contact");
    assert_eq!(get(&m, "D0"), 2 + 4 + 16, "R1, R2, R4 as bits 1, 2, 4");
    // A pulse held on shifts once.
    set(&mut m, "I2", 1);
    set(&mut m, "I1", 1);
    scans(&mut m, 3);
    assert_eq!(r_bits(&m, 0, 5), [1, 0, 1, 1, 1]);
    set(&mut m, "I1", 0);
    set(&mut m, "I0", 1);
    scans(&mut m, 1);
    assert_eq!(r_bits(&m, 0, 5), [0, 0, 0, 0, 1], "reset clears R0–R3 only");
    pulse(&mut m, "I1");
    assert_eq!(
        r_bits(&m, 0, 5),
        [0, 0, 0, 0, 1],
        "reset wins over the pulse"
    );
}

/// §5.10 SFRN R10 4: each rising pulse moves R10…R13 down (R10 lost) and sets R13 = data;
/// R9 and R14 are outside.
#[test]
fn sfrn_shifts_down() {
    let src = "LOD M8120\nSET R9\nSET R14\nLOD I0\nLOD I1\nLOD I2\nSFRN R10 4";
    let mut m = plc(src, 10);
    let shift = |m: &mut OpenNet, data: u64| {
        set(m, "I2", data);
        pulse(m, "I1");
        r_bits(m, 9, 6)
    };
    assert_eq!(shift(&mut m, 1), [1, 0, 0, 0, 1, 1]);
    assert_eq!(shift(&mut m, 0), [1, 0, 0, 1, 0, 1]);
    assert_eq!(shift(&mut m, 1), [1, 0, 1, 0, 1, 1]);
    assert_eq!(shift(&mut m, 1), [1, 1, 0, 1, 1, 1]);
    assert_eq!(shift(&mut m, 0), [1, 0, 1, 1, 0, 1], "R10's 1 is lost");
}

/// §5.10: a data input and a pulse on in scan 0 shift (the memory starts at 0).
#[test]
fn sfr_pulse_on_in_scan_0_shifts() {
    let mut m = plc("LOD I0\nLOD I1\nLOD I2\nSFR R0 3", 10);
    set(&mut m, "I1", 1);
    set(&mut m, "I2", 1);
    to_scan(&mut m, 3);
    assert_eq!(r_bits(&m, 0, 3), [1, 0, 0], "one shift for a pulse held on");
}

/// §5.10, §5.12: with MC = 0 the bits hold (reset does not act) and the pulse memory becomes 0.
#[test]
fn sfr_in_an_mcs_area_that_is_off_holds_and_forgets_its_pulse() {
    let mut m = plc("LOD I3\nMCS\nLOD I0\nLOD I1\nLOD I2\nSFR R0 4\nMCR", 10);
    set(&mut m, "I3", 1);
    set(&mut m, "I2", 1);
    pulse(&mut m, "I1");
    assert_eq!(r_bits(&m, 0, 4), [1, 0, 0, 0]);
    set(&mut m, "I2", 0);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 3);
    assert_eq!(r_bits(&m, 0, 4), [0, 1, 0, 0], "scan 2: a rising pulse");
    set(&mut m, "I3", 0);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 4);
    assert_eq!(r_bits(&m, 0, 4), [0, 1, 0, 0], "MC = 0: held, no reset");
    set(&mut m, "I3", 1);
    set(&mut m, "I0", 0);
    to_scan(&mut m, 5);
    assert_eq!(
        r_bits(&m, 0, 4),
        [0, 0, 1, 0],
        "I1 still on is an edge again"
    );
}

/// §4.2: R bits as word operands — `R16` as W is R16–R31, `R240` is R240–R255 — and as CMP
/// destinations.
#[test]
fn r_bits_are_word_operands() {
    let m = once("MOV(W) 8001h R16\nMOV(W) 8000h R240\nCMP=(W) 1 1 R5\nMOV(W) R16 D0");
    assert_eq!(
        values(&m, &["R16", "R17", "R30", "R31", "R32"]),
        [1, 0, 0, 1, 0]
    );
    assert_eq!(values(&m, &["R254", "R255", "R5"]), [0, 1, 1]);
    assert_eq!(get(&m, "D0"), 0x8001);
}

// ---- §5.11 Comparisons, word logic, shifts, conversions --------------------------------------

/// §5.11: the six comparisons, W.
#[test]
fn the_six_comparisons() {
    let m = once(
        "MOV(W) 3 D0\nCMP=(W) D0 5 M0\nCMP<>(W) D0 5 M1\nCMP<(W) D0 5 M2\nCMP>(W) D0 5 M3\n\
         CMP<=(W) D0 5 M4\nCMP>=(W) D0 5 M5\nCMP=(W) D0 3 M10\nCMP<>(W) D0 3 M11\nCMP<(W) D0 3 M12\n\
         CMP>(W) D0 3 M13\nCMP<=(W) D0 3 M14\nCMP>=(W) D0 3 M15\nCMP>(W) 5 3 Q0\nCMP>(W) 5 3 R7",
    );
    // 3 vs 5: = 0, <> 1, < 1, > 0, <= 1, >= 0; 3 vs 3: 1, 0, 0, 0, 1, 1.
    assert_eq!(
        values(&m, &["M0", "M1", "M2", "M3", "M4", "M5"]),
        [0, 1, 1, 0, 1, 0]
    );
    assert_eq!(
        values(&m, &["M10", "M11", "M12", "M13", "M14", "M15"]),
        [1, 0, 0, 0, 1, 1]
    );
    assert_eq!(values(&m, &["Q0", "R7"]), [1, 1]);
}

/// §5.11: signed for I and L, unsigned for W and D. FFFFh is 65535 as W but −1 as I.
#[test]
fn comparisons_are_signed_for_i_and_l_and_unsigned_for_w_and_d() {
    let m = once(
        "MOV(W) FFFFh D0\nMOV(D) FFFFFFFFh D2\nCMP<(W) D0 1 M0\nCMP<(I) D0 1 M1\nCMP<(D) D2 1 M2\n\
         CMP<(L) D2 1 M3\nCMP>(W) D0 32767 M4\nCMP>(I) D0 32767 M5\nMOV(D) 00010000h D10\n\
         CMP>(D) D10 0000FFFFh M6\nMOV(D) 80000000h D12\nCMP<(L) D12 -2147483647 M7\n\
         CMP>=(D) D12 7FFFFFFFh M10",
    );
    assert_eq!(
        values(&m, &["M0", "M1"]),
        [0, 1],
        "65535 < 1 no; −1 < 1 yes"
    );
    assert_eq!(
        values(&m, &["M2", "M3"]),
        [0, 1],
        "4294967295 < 1 no; −1 < 1 yes"
    );
    assert_eq!(
        values(&m, &["M4", "M5"]),
        [1, 0],
        "65535 > 32767; −1 > 32767 no"
    );
    assert_eq!(get(&m, "M6"), 1, "65536 > 65535: the upper word counts");
    assert_eq!(
        values(&m, &["M7", "M10"]),
        [1, 1],
        "80000000h: −2147483648 as L, 2147483648 as D"
    );
}

/// §5.11: ICMP>= S1 S2 S3 D1 gives 1 when a ≥ b and b ≥ c.
#[test]
fn icmp_checks_both_bounds() {
    let m = once(
        "MOV(W) FFFFh D0\nICMP>=(W) 10 5 1 M0\nICMP>=(W) 10 5 6 M1\nICMP>=(W) 4 5 1 M2\n\
         ICMP>=(W) 5 5 5 M3\nICMP>=(I) 5 D0 D0 M4\nICMP>=(W) 5 D0 D0 M5\nICMP>=(I) D0 -2 -3 M6\n\
         ICMP>=(W) D0 2 1 M7",
    );
    // 10≥5≥1; 5≥6 no; 4≥5 no; 5≥5≥5; 5≥−1≥−1; 5≥65535 no; −1≥−2≥−3; 65535≥2≥1.
    assert_eq!(
        values(&m, &["M0", "M1", "M2", "M3", "M4", "M5", "M6", "M7"]),
        [1, 0, 0, 1, 1, 0, 1, 1]
    );
}

/// §5.2, §5.11: with REP a marked CMP D1 advances one point per cycle (IDEC numbering: M37 is
/// followed by M40); an unmarked D1 ends with the last cycle's result.
#[test]
fn comparisons_with_rep() {
    let m = once(
        "MOV(W) 9 D10\nMOV(W) 6 D11\nMOV(W) 1 D12\nMOV(W) 5 D13\nCMP>(W) D10(R) 5 M0(R) REP 4\n\
         CMP>(W) D10(R) 5 M20 REP 4\nCMP>(W) D10(R) 4 M21 REP 4\nMOV(W) 9 D20(R) REP 10\n\
         CMP=(W) D20(R) 9 M30(R) REP 10",
    );
    assert_eq!(
        values(&m, &["M0", "M1", "M2", "M3", "M4"]),
        [1, 1, 0, 0, 0],
        "9, 6, 1, 5 > 5"
    );
    assert_eq!(
        values(&m, &["M20", "M21"]),
        [0, 1],
        "last cycle: 5 > 5 no, 5 > 4 yes"
    );
    let ten = [
        "M30", "M31", "M32", "M33", "M34", "M35", "M36", "M37", "M40", "M41",
    ];
    assert_eq!(values(&m, &ten), [1; 10]);
    assert_eq!(get(&m, "M42"), 0, "ten points only");
}

/// §5.11: comparisons act only while their input is on; otherwise D1 keeps its value.
#[test]
fn a_comparison_whose_input_is_off_keeps_its_result() {
    let mut m = plc("LOD I0\nCMP=(W) D0 0 M0", 10);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "M0"), 1);
    set(&mut m, "I0", 0);
    set(&mut m, "D0", 5);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "M0"), 1, "not an OUT: kept");
    set(&mut m, "I0", 1);
    to_scan(&mut m, 4);
    assert_eq!(get(&m, "M0"), 0);
}

/// §5.11: ANDW/ORW/XORW bit by bit in W and D, REP, a bit-operand destination; M8003 untouched.
#[test]
fn word_logic() {
    let m = once(
        "ADD(W) 65535 1 D90\nANDW(W) F0F0h 0FF0h D0\nORW(W) F0F0h 0FF0h D1\nXORW(W) F0F0h 0FF0h D2\n\
         ANDW(D) 12345678h 0000FFFFh D10\nORW(D) 12340000h 00005678h D12\n\
         XORW(D) FFFFFFFFh 0F0F0F0Fh D14\nMOV(W) 1234h D30\nMOV(W) ABCDh D31\n\
         ANDW(W) D30(R) 000Fh D40(R) REP 2\nANDW(W) D0 D1 Q0",
    );
    assert_eq!(values(&m, &["D0", "D1", "D2"]), [0x00F0, 0xFFF0, 0xFF00]);
    assert_eq!(values(&m, &["D10", "D11"]), [0x0000, 0x5678]);
    assert_eq!(values(&m, &["D12", "D13"]), [0x1234, 0x5678]);
    assert_eq!(values(&m, &["D14", "D15"]), [0xF0F0, 0xF0F0]);
    assert_eq!(values(&m, &["D40", "D41"]), [0x4, 0xD]);
    // 00F0h & FFF0h = 00F0h: bits 4–7 = Q4–Q7.
    assert_eq!(
        values(&m, &["Q0", "Q3", "Q4", "Q7", "Q10", "Q17"]),
        [0, 0, 1, 1, 0, 0]
    );
    assert_eq!(
        get(&m, "M8003"),
        1,
        "the ADD's carry: word logic leaves M8003 alone"
    );
}

/// §5.11's examples: `SFTL(W) D0 4` with D0 = 1234h → 2340h, M8003 = 1 (bit 12 of 1234h);
/// and the other shifts, each writing M8003 with the last bit out.
#[test]
fn sftl_and_sftr_write_the_last_bit_out_to_m8003() {
    for (src, d, m8003) in [
        ("MOV(W) 1234h D0\nSFTL(W) D0 4", vec![("D0", 0x2340)], 1),
        // 1234h >> 4 = 0123h; bit 3 of 1234h (the 4 = 0100b) is 0; the ADD's carry is rewritten.
        (
            "ADD(W) 65535 1 D9\nMOV(W) 1234h D0\nSFTR(W) D0 4",
            vec![("D0", 0x0123)],
            0,
        ),
        // 1234h >> 3 = 0246h; bit 2 of 1234h is 1.
        ("MOV(W) 1234h D0\nSFTR(W) D0 3", vec![("D0", 0x0246)], 1),
        // 1 << 15 = 8000h; bit 16 − 15 = 1 of 0001h is 0.
        ("MOV(W) 1 D0\nSFTL(W) D0 15", vec![("D0", 0x8000)], 0),
        // 12345678h << 4 = 23456780h; bit 28 (the 1) is 1.
        (
            "MOV(D) 12345678h D0\nSFTL(D) D0 4",
            vec![("D0", 0x2345), ("D1", 0x6780)],
            1,
        ),
        // 12345678h >> 4 = 01234567h; bit 3 (the 8 = 1000b) is 1.
        (
            "MOV(D) 12345678h D0\nSFTR(D) D0 4",
            vec![("D0", 0x0123), ("D1", 0x4567)],
            1,
        ),
    ] {
        let m = once(src);
        for (name, v) in d {
            assert_eq!(get(&m, name), v, "{src}: {name}");
        }
        assert_eq!(get(&m, "M8003"), m8003, "{src}");
    }
    // A bit operand: M0 as W (M0–M7, M10–M17) = 8001h; shifted left 1 → 0002h, bit 15 out.
    let m = once("MOV(W) 8001h M0\nSFTL(W) M0 1");
    assert_eq!(values(&m, &["M0", "M1", "M17", "M8003"]), [0, 1, 0, 1]);
}

/// §3, §5.11: an advanced instruction acts in every scan its input is on; each SFTL writes
/// M8003. D0 = 1 shifted once a scan: 8000h after scan 14, 0 after scan 15 with bit 15 out
/// (M8003 = 1), then 0 out (M8003 = 0).
#[test]
fn sftl_acts_every_scan_its_input_is_on() {
    let mut m = plc("LOD M8125\nSFTL(W) D0 1", 10);
    set(&mut m, "D0", 1);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "D0"), 8);
    to_scan(&mut m, 15);
    assert_eq!((get(&m, "D0"), get(&m, "M8003")), (0x8000, 0));
    to_scan(&mut m, 16);
    assert_eq!((get(&m, "D0"), get(&m, "M8003")), (0, 1));
    to_scan(&mut m, 17);
    assert_eq!((get(&m, "D0"), get(&m, "M8003")), (0, 0));
}

/// §5.11's examples: `HTOB(W) 1234 D0` gives 1234h; `BTOH(D) 12345678h D4` gives D4 = 00BCh,
/// D5 = 614Eh (12345678 = 00BC614Eh); and the widest values.
#[test]
fn htob_and_btoh_convert_between_binary_and_bcd() {
    let m = once(
        "HTOB(W) 1234 D0\nHTOB(W) 9999 D1\nHTOB(D) 12345678 D2\nHTOB(D) 99999999 D6\n\
         BTOH(D) 12345678h D4\nBTOH(W) 1234h D10\nBTOH(W) 9999h D11\nMOV(W) 56h D20\nBTOH(W) D20 D21",
    );
    assert_eq!(values(&m, &["D0", "D1"]), [0x1234, 0x9999]);
    assert_eq!(values(&m, &["D2", "D3"]), [0x1234, 0x5678]);
    assert_eq!(values(&m, &["D6", "D7"]), [0x9999, 0x9999]);
    assert_eq!(values(&m, &["D4", "D5"]), [0x00BC, 0x614E]);
    assert_eq!(values(&m, &["D10", "D11", "D21"]), [1234, 9999, 56]);
    assert_eq!((get(&m, "M8004"), m.error_count), (0, 0));
}

/// §5.11, §6: a value over 9999 (W) / 99999999 (D) is `bcd_range`, a nibble over 9 is
/// `bcd_digit`: the destination is unchanged, M8004 = 1, error_count 1, last_error at the
/// instruction's line in scan 0, and M8003 (1 from the ADD) untouched.
#[test]
fn bcd_execution_errors() {
    for (op, kind) in [
        ("HTOB(W) 10000 D0", "bcd_range"),
        ("HTOB(D) 100000000 D0", "bcd_range"),
        ("BTOH(W) 12A4h D0", "bcd_digit"),
        ("BTOH(W) F000h D0", "bcd_digit"),
        ("BTOH(D) 0000000Ah D0", "bcd_digit"),
    ] {
        // Lines: 1 LOD M8120, 2 ADD, 3 MOV, 4 MOV, 5 the conversion.
        let m = once(&format!(
            "ADD(W) 65535 1 D9\nMOV(W) 7 D0\nMOV(W) 8 D1\n{op}"
        ));
        assert_eq!(values(&m, &["D0", "D1"]), [7, 8], "{op}: nothing written");
        assert_eq!(get(&m, "M8004"), 1, "{op}");
        assert_eq!(m.error_count, 1, "{op}");
        assert_eq!(last_error(&m), (kind, 5, 0), "{op}");
        assert_eq!(get(&m, "M8003"), 1, "{op}: M8003 untouched");
    }
}

/// §6: one error per erring REP cycle; the other cycles run.
#[test]
fn bcd_errors_count_per_rep_cycle() {
    // Lines: 1 LOD M8120, 2–6 MOV, 7 HTOB.
    let m = once(
        "MOV(W) 5 D10\nMOV(W) 10000 D11\nMOV(W) 20000 D12\nMOV(W) 1 D21\nMOV(W) 1 D22\n\
         HTOB(W) D10(R) D20(R) REP 3",
    );
    assert_eq!(values(&m, &["D20", "D21", "D22"]), [0x5, 1, 1]);
    assert_eq!(m.error_count, 2);
    assert_eq!(last_error(&m), ("bcd_range", 7, 0));
}

/// §6: last_error's tick is the scan; M8004 stays on; SOTU makes the conversion act once.
#[test]
fn a_bcd_error_in_a_later_scan_records_its_tick() {
    let mut m = plc("LOD I0\nSOTU\nBTOH(W) D1 D0", 10);
    set(&mut m, "D1", 0x00A0);
    set(&mut m, "D0", 77);
    to_scan(&mut m, 3);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 6);
    assert_eq!(m.error_count, 1);
    assert_eq!(last_error(&m), ("bcd_digit", 3, 3));
    assert_eq!(values(&m, &["D0", "M8004", "M8003"]), [77, 1, 0]);
}

// ---- §4.3 T and C word operands --------------------------------------------------------------

/// §4.3: T or C as a source reads the current value, as a destination writes the preset.
#[test]
fn timer_and_counter_words_read_the_current_value_and_write_the_preset() {
    let src = "LOD I0\nTMH T0 10\nLOD M8125\nMOV(W) T0 D0\nMOV(I) T0 D1\nLOD I1\nMOV(W) 25 T0\n\
               LOD I2\nLOD I3\nCNT C0 50\nLOD M8125\nMOV(W) C0 D2\nLOD I4\nADD(W) T0 100 C0";
    let mut m = plc(src, 10);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 4);
    assert_eq!(values(&m, &["D0", "D1"]), [7, 7], "scan 3: 10 − 3");
    set(&mut m, "I1", 1);
    to_scan(&mut m, 5);
    assert_eq!(
        timer(&m, "T0"),
        (25, 6, 0),
        "preset written, current running on"
    );
    assert_eq!(get(&m, "D0"), 6);
    pulse(&mut m, "I3");
    pulse(&mut m, "I3");
    assert_eq!(get(&m, "D2"), 2, "C0's current value");
    // Scan 9 (the two pulses took scans 5–8): T0.current = 10 − 9 = 1, so C0.preset = 101.
    set(&mut m, "I4", 1);
    scans(&mut m, 1);
    assert_eq!(m.ticks(), 10);
    assert_eq!(get(&m, "T0.current"), 1);
    assert_eq!(
        counter(&m, "C0"),
        (101, 2, 0),
        "C0.preset = T0.current + 100"
    );
}

/// §4.3: a block of n words of T is n consecutive timers; (R) advances by one timer.
#[test]
fn rep_over_timers_advances_one_timer_a_cycle() {
    let src = "LOD I5\nMOV(W) D20(R) T0(R) REP 3\nLOD I0\nTIM T0 4\nTIM T1 5\nTIM T2 6\n\
               LOD M8125\nMOV(W) T0(R) D10(R) REP 3";
    let mut m = plc(src, 10);
    to_scan(&mut m, 1);
    assert_eq!(
        values(&m, &["D10", "D11", "D12"]),
        [4, 5, 6],
        "currents = presets while off"
    );
    for (i, v) in [7, 8, 9].into_iter().enumerate() {
        set(&mut m, &format!("D{}", 20 + i), v);
    }
    set(&mut m, "I5", 1);
    to_scan(&mut m, 2);
    assert_eq!(
        [timer(&m, "T0"), timer(&m, "T1"), timer(&m, "T2")],
        [(7, 7, 0), (8, 8, 0), (9, 9, 0)]
    );
    assert_eq!(values(&m, &["D10", "D11", "D12"]), [7, 8, 9]);
}

/// §5.2's example (MICRO3 p.11-2): C0…C3 at 10, 20, 30, 40 and `ADD(W) C0(R) D0 D0 REP 4`
/// leave D0 = 100. The currents come from CDP preset inputs (M8120) in scan 0.
#[test]
fn the_vendors_totaliser_over_counters() {
    let mut src = String::new();
    for (c, p) in [(0, 10), (1, 20), (2, 30), (3, 40)] {
        src.push_str(&format!("LOD M8120\nLOD I1\nLOD I2\nCDP C{c} {p}\n"));
    }
    src.push_str("LOD M8120\nADD(W) C0(R) D0 D0 REP 4");
    let mut m = plc(&src, 10);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "D0"), 100);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "D0"), 100, "M8120 is off after scan 0");
    assert_eq!(
        values(
            &m,
            &["C0.current", "C1.current", "C2.current", "C3.current"]
        ),
        [10, 20, 30, 40]
    );
}

/// The same totaliser with the counters' current values written by the debugger.
#[test]
fn the_vendors_totaliser_over_written_counters() {
    let mut src = String::new();
    for c in 0..4 {
        src.push_str(&format!("LOD I0\nLOD I1\nCNT C{c} 100\n"));
    }
    src.push_str("LOD M8120\nADD(W) C0(R) D0 D0 REP 4");
    let mut m = plc(&src, 10);
    for (c, v) in [10, 20, 30, 40].into_iter().enumerate() {
        set(&mut m, &format!("C{c}.current"), v);
    }
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "D0"), 100);
}

// ---- §5.12 Master control and jumps -----------------------------------------------------------

/// §5.12: while MC = 0, OUT writes 0, OUTN writes 1, SET, RST and advanced instructions do
/// nothing; MCR restores MC = 1.
#[test]
fn outputs_in_an_mcs_area_that_is_off() {
    let src = "LOD M8120\nSET Q3\nLOD I0\nMCS\nLOD I1\nOUT Q0\nLOD I1\nOUTN Q1\nLOD I1\nSET Q2\n\
               LOD I1\nRST Q3\nLOD I1\nINC(W) D0\nMCR\nLOD I1\nOUT Q4";
    let qs = ["Q0", "Q1", "Q2", "Q3", "Q4"];
    let mut m = plc(src, 10);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 2);
    assert_eq!(values(&m, &qs), [0, 1, 0, 1, 1], "I0 off: MC = 0 inside");
    assert_eq!(get(&m, "D0"), 0);
    assert_eq!(get(&m, "MC"), 1, "after MCR");
    set(&mut m, "I0", 1);
    to_scan(&mut m, 3);
    assert_eq!(values(&m, &qs), [1, 0, 1, 0, 1], "I0 on");
    assert_eq!(get(&m, "D0"), 1);
}

/// §5.12: MC follows MCS and MCR within the scan.
#[test]
fn mc_is_cleared_by_an_off_mcs_and_set_by_mcr() {
    let mut m = plc("LOD I0\nMCS\nLOD M8125\nOUT Q0\nMCR\nLOD M8125\nOUT Q1", 10);
    to_scan(&mut m, 1);
    assert_eq!(values(&m, &["MC", "Q0", "Q1"]), [1, 0, 1]);
    for _ in 0..2 {
        m.step_command(1); // LOD I0, MCS
    }
    assert_eq!(get(&m, "MC"), 0, "MCS with I0 off");
    for _ in 0..3 {
        m.step_command(1); // LOD M8125, OUT Q0, MCR
    }
    assert_eq!(get(&m, "MC"), 1, "MCR");
    to_scan(&mut m, 2);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 3);
    assert_eq!(values(&m, &["MC", "Q0", "Q1"]), [1, 1, 1]);
}

/// §5.12: several MCS share one MCR; an MCS inside an area that is off stays off.
#[test]
fn nested_mcs_inside_an_off_area_stays_off() {
    let src = "LOD I0\nMCS\nLOD I1\nMCS\nLOD M8125\nOUT Q0\nMCR\nLOD M8125\nOUT Q1";
    for (i0, i1, q0) in [(0, 1, 0), (1, 1, 1), (1, 0, 0), (0, 0, 0)] {
        let mut m = plc(src, 10);
        set(&mut m, "I0", i0);
        set(&mut m, "I1", i1);
        to_scan(&mut m, 1);
        assert_eq!(values(&m, &["Q0", "Q1"]), [q0, 1], "I0 {i0}, I1 {i1}");
    }
}

/// §5.12: SOTU in an off area gives 0 and its memory becomes 0, so an input held on through
/// the off scans gives a pulse when MC returns.
#[test]
fn sotu_in_an_off_area_pulses_when_mc_returns() {
    let src = "LOD I0\nMCS\nLOD I1\nSOTU\nOUT Q0\nMCR";
    let mut m = plc(src, 10);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "Q0"), 0, "MC = 0 in scans 0–2");
    set(&mut m, "I0", 1);
    to_scan(&mut m, 4);
    assert_eq!(get(&m, "Q0"), 1, "scan 3: the edge");
    to_scan(&mut m, 5);
    assert_eq!(get(&m, "Q0"), 0, "one scan");
    set(&mut m, "I0", 0);
    to_scan(&mut m, 6);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 7);
    assert_eq!(get(&m, "Q0"), 1, "off one scan, on again: a new pulse");
}

/// §5.12: SOTD in an off area sets its memory to 0, so a fall after it is not seen.
#[test]
fn sotd_in_an_off_area_loses_the_falling_edge() {
    let src = "LOD I0\nMCS\nLOD I1\nSOTD\nOUT Q1\nMCR";
    // Without MC going off the fall is seen.
    let mut m = plc(src, 10);
    set(&mut m, "I0", 1);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 3);
    set(&mut m, "I1", 0);
    to_scan(&mut m, 4);
    assert_eq!(get(&m, "Q1"), 1);
    // With one off scan between, it is not.
    let mut m = plc(src, 10);
    set(&mut m, "I0", 1);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 3);
    set(&mut m, "I0", 0);
    to_scan(&mut m, 4);
    assert_eq!(get(&m, "Q1"), 0);
    set(&mut m, "I0", 1);
    set(&mut m, "I1", 0);
    to_scan(&mut m, 6);
    assert_eq!(get(&m, "Q1"), 0, "no falling edge in scans 4 and 5");
}

/// §5.12: JMP does nothing while MC = 0: the instructions up to JEND then run (OUTN writes 1).
#[test]
fn jmp_in_an_off_area_is_not_taken() {
    let src = "LOD I0\nMCS\nLOD M8125\nJMP\nLOD M8125\nOUTN Q1\nJEND\nMCR";
    let mut m = plc(src, 10);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "Q1"), 0, "taken: OUTN skipped");
    set(&mut m, "I0", 0);
    to_scan(&mut m, 2);
    assert_eq!(get(&m, "Q1"), 1, "not taken: OUTN with MC = 0 writes 1");
    set(&mut m, "I0", 1);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "Q1"), 1, "taken again: held");
    // Steps: taken = LOD, MCS, LOD, JMP, JEND, MCR (6); not taken = all 8.
    assert_eq!(m.steps(), 6 + 8 + 6);
}

/// §5.12, §3: a taken jump skips to the JEND, which executes (one step); the skipped
/// instructions hold their outputs and registers.
#[test]
fn a_taken_jump_holds_the_skipped_part_and_counts_its_steps() {
    let src = "LOD I0\nJMP\nLOD I1\nOUT Q0\nLOD M8125\nINC(W) D0\nJEND\nLOD M8125\nINC(W) D1";
    let mut m = plc(src, 10);
    to_scan(&mut m, 1);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 3);
    assert_eq!(values(&m, &["D0", "D1", "Q0"]), [3, 3, 1]);
    assert_eq!(m.steps(), 3 * 9, "nine instructions a scan");
    set(&mut m, "I0", 1);
    set(&mut m, "I1", 0);
    to_scan(&mut m, 6);
    assert_eq!(
        values(&m, &["D0", "D1", "Q0"]),
        [3, 6, 1],
        "Q0 held though I1 is off"
    );
    assert_eq!(m.steps(), 27 + 3 * 5, "LOD I0, JMP, JEND, LOD, INC");
    set(&mut m, "I0", 0);
    to_scan(&mut m, 7);
    assert_eq!(values(&m, &["D0", "D1", "Q0"]), [4, 7, 0]);
    assert_eq!(m.steps(), 42 + 9);
}

/// §5.12: several JMP share one JEND; each taken JMP goes to the first JEND after it.
#[test]
fn several_jumps_share_one_jend() {
    let src = "LOD I0\nJMP\nLOD M8125\nINC(W) D0\nLOD I1\nJMP\nLOD M8125\nINC(W) D1\nJEND\n\
               LOD M8125\nINC(W) D2";
    let mut m = plc(src, 10);
    to_scan(&mut m, 1);
    assert_eq!(values(&m, &["D0", "D1", "D2"]), [1, 1, 1]);
    assert_eq!(m.steps(), 11);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 2);
    assert_eq!(values(&m, &["D0", "D1", "D2"]), [2, 1, 2]);
    assert_eq!(m.steps(), 11 + 9);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 3);
    assert_eq!(values(&m, &["D0", "D1", "D2"]), [2, 1, 3]);
    assert_eq!(m.steps(), 20 + 5);
}

/// §5.12: an MCS inside a skipped part does not run, so MC stays 1 after the JEND.
#[test]
fn an_mcs_inside_a_skipped_part_does_not_run() {
    let src = "LOD I1\nJMP\nLOD I0\nMCS\nJEND\nLOD M8125\nOUT Q0\nMCR";
    let mut m = plc(src, 10);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "Q0"), 0, "not skipped: MCS with I0 off");
    set(&mut m, "I1", 1);
    to_scan(&mut m, 2);
    assert_eq!(get(&m, "Q0"), 1, "skipped: MC stayed 1");
}

// ---- §3 Clocks and steps ----------------------------------------------------------------------

/// §3: scan k starts at t = k × scan_ms; M8121 = (t mod 1000 < 500), M8122 = (t mod 100 < 50),
/// M8123 = (t mod 10 < 5), M8125 = 1, M8120 = (k = 0) — seen by the program (OUT to M bits)
/// and read directly after the scan, at several scan times.
#[test]
fn clocks_follow_the_scan_start_time_at_every_scan_time() {
    let src = "LOD M8121\nOUT M0\nLOD M8122\nOUT M1\nLOD M8123\nOUT M2\nLOD M8125\nOUT M3\nLOD M8120\nOUT M4";
    for scan_ms in [1u64, 3, 7, 10, 33, 50, 100, 250, 1000] {
        let mut m = plc(src, scan_ms as u32);
        for k in 0..(2100 / scan_ms).max(12) {
            to_scan(&mut m, k + 1);
            let t = k * scan_ms;
            let want = [t % 1000 < 500, t % 100 < 50, t % 10 < 5, true, k == 0].map(u64::from);
            let seen = ["M0", "M1", "M2", "M3", "M4"].map(|n| get(&m, n));
            assert_eq!(seen, want, "scan_ms {scan_ms}, scan {k}, t {t}");
            let direct = ["M8121", "M8122", "M8123", "M8125", "M8120"].map(|n| get(&m, n));
            assert_eq!(
                direct, want,
                "scan_ms {scan_ms}, scan {k}: read after the scan"
            );
        }
    }
}

/// §3's literal cases: at 10 ms M8121 is on in scans 0–49 of every 100, M8122 in 0–4 of every
/// 10, M8123 always (aliased); at 1000 ms M8121 is always on; at 3 ms M8123 (t = 0, 3, 6, 9,
/// 12, 15, 18, 21, 24) is 1, 1, 0, 0, 1, 0, 0, 1, 1.
#[test]
fn clock_aliasing_cases() {
    let src = "LOD M8121\nOUT M0\nLOD M8122\nOUT M1\nLOD M8123\nOUT M2";
    let trace = |scan_ms: u32, n: u64, bit: &str| {
        let mut m = plc(src, scan_ms);
        (0..n)
            .map(|k| {
                to_scan(&mut m, k + 1);
                get(&m, bit)
            })
            .collect::<Vec<_>>()
    };
    let m0 = trace(10, 200, "M0");
    assert!(m0[..50].iter().all(|&b| b == 1) && m0[50..100].iter().all(|&b| b == 0));
    assert!(m0[100..150].iter().all(|&b| b == 1) && m0[150..].iter().all(|&b| b == 0));
    assert_eq!(
        trace(10, 20, "M1"),
        [1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0]
    );
    assert!(
        trace(10, 200, "M2").iter().all(|&b| b == 1),
        "M8123 at 10 ms"
    );
    assert!(
        trace(1000, 10, "M0").iter().all(|&b| b == 1),
        "M8121 at 1000 ms"
    );
    assert_eq!(trace(3, 9, "M2"), [1, 1, 0, 0, 1, 0, 0, 1, 1]);
    assert_eq!(
        trace(250, 8, "M0"),
        [1, 1, 0, 0, 1, 1, 0, 0],
        "t = 0, 250, 500, 750, …"
    );
    assert_eq!(
        trace(250, 4, "M1"),
        [1, 0, 1, 0],
        "t mod 100 = 0, 50, 0, 50"
    );
}

/// §3: without taken jumps N scans make N × (instructions up to and including END); NOP, the
/// logic in an off MCS area, timers, counters and shift registers each count one step.
#[test]
fn steps_are_scans_times_instructions() {
    let src = "LOD I0\nOUT Q0\nLOD I1\nMCS\nLOD M8125\nINC(W) D0\nMCR\nLOD I2\nTIM T0 5\n\
               LOD I3\nLOD I4\nCNT C0 3\nLOD I5\nLOD I6\nLOD I7\nSFR R0 4\nNOP\nEND";
    for i1 in [0, 1] {
        let mut m = plc(src, 10);
        set(&mut m, "I1", i1);
        to_scan(&mut m, 13);
        assert_eq!(m.steps(), 13 * 18, "I1 = {i1}");
        assert_eq!(get(&m, "D0"), 13 * i1);
    }
    let mut m = plc("LOD I0\nOUT Q0", 10);
    to_scan(&mut m, 7);
    assert_eq!(m.steps(), 14, "no END: two a scan");
}

// ---- §1, §5.1 The assembler ----------------------------------------------------------------

/// §1: operand kinds and ranges of the new forms, each on its line.
#[test]
fn operand_errors_of_the_new_forms() {
    for (src, line, words) in [
        ("LOD I0\nTIM D0 5", 2, "D0"),
        ("LOD I0\nTIM T0 M0", 2, "M0"),
        ("LOD I0\nTIM T256 5", 2, "T256"),
        ("LOD I0\nTMH T0 65536", 2, "65536"),
        ("LOD I0\nTIM T0 D8000", 2, "D8000"),
        ("LOD I0\nTIM T0", 2, "TIM"),
        ("LOD I0\nLOD I1\nCNT T0 5", 3, "T0"),
        ("LOD I0\nLOD I1\nCNT C256 5", 3, "C256"),
        ("CC= D0 5\nOUT Q0", 1, "D0"),
        ("DC= C0 5\nOUT Q0", 1, "C0"),
        ("CC>= C0 70000\nOUT Q0", 1, "70000"),
        ("LOD I0\nOUT T0", 2, "T0"),
        ("LOD I0\nSET C3", 2, "C3"),
        ("LOD I0\nOUT M8121", 2, "M8121"),
        ("LOD I0\nMOV(W) 1 M8121", 2, "M8121"),
        ("LOD I0\nCMP=(W) D0 D1 D2", 2, "D2"),
        ("LOD I0\nCMP=(W) D0 D1 T0", 2, "T0"),
        ("LOD I0\nANDW(I) D0 D1 D2", 2, "ANDW"),
        ("LOD I0\nHTOB(L) D0 D1", 2, "HTOB"),
        ("LOD I0\nSFTL(W) T0 1", 2, "T0"),
        ("LOD I0\nSFTL(W) D0 16", 2, "16"),
        ("LOD I0\nSFTR(D) D0 32", 2, "32"),
        ("LOD I0\nSFTL(W) D0 1 REP 2", 2, "REP"),
        ("LOD M8120\nMOV(W) 1 R241", 2, "R255"),
        ("LOD M8120\nMOV(W) 5 T255(R) REP 2", 2, "T255"),
    ] {
        assert_error(src, line, words);
    }
}

/// §1: SFR's k is a constant 1–256 within R255, its first operand an R bit.
#[test]
fn shift_register_operand_errors() {
    for (src, words) in [
        ("LOD I0\nLOD I1\nLOD I2\nSFR R0 257", "257"),
        ("LOD I0\nLOD I1\nLOD I2\nSFR R250 7", "R255"),
        ("LOD I0\nLOD I1\nLOD I2\nSFRN R0 0", ""),
        ("LOD I0\nLOD I1\nLOD I2\nSFR M0 4", "M0"),
        ("LOD I0\nLOD I1\nLOD I2\nSFR R0 D0", "D0"),
    ] {
        assert_error(src, 4, words);
    }
    assert_assembles("LOD I0\nLOD I1\nLOD I2\nSFR R250 6");
    assert_assembles("LOD I0\nLOD I1\nLOD I2\nSFRN R0 256");
}

/// §1: the same timer (counter) number in two timer (counter) instructions is an error; a
/// timer and a counter may share a number, and a T or C may also be a contact or word operand.
#[test]
fn a_timer_or_counter_number_has_one_instruction() {
    assert_error("LOD I0\nTIM T0 5\nLOD I1\nTMH T0 7", 4, "T0");
    assert_error(
        "LOD I0\nLOD I1\nCNT C1 5\nLOD I2\nLOD I3\nLOD I4\nCDP C1 5",
        7,
        "C1",
    );
    assert_assembles("LOD I0\nTIM T0 5\nLOD I0\nLOD I1\nCNT C0 5");
    assert_assembles("LOD T0\nOUT Q0\nLOD I0\nTIM T0 5\nLOD M8125\nMOV(W) T0 D0\nMOV(W) C9 D1");
}

/// §1, §4.3: T and C are 16-bit operands: an error in a D or L instruction.
#[test]
fn timers_and_counters_are_not_d_or_l_operands() {
    for (src, words) in [
        ("LOD I0\nMOV(D) T0 D0", "T0"),
        ("LOD I0\nADD(L) D0 C1 D2", "C1"),
        ("LOD I0\nMOV(D) 5 T0", "T0"),
        ("LOD I0\nCMP=(D) C0 D0 M0", "C0"),
    ] {
        assert_error(src, 2, words);
    }
    assert_assembles("LOD I0\nMOV(I) T0 D0\nADD(W) C0 1 T1");
}

/// §1: the off-delay timers belong to later CPUs; TMR and BCD get "did you mean".
#[test]
fn later_cpu_timers_and_suggestions() {
    for op in ["TIMO", "TMHO", "TMLO", "TMSO"] {
        assert_error(&format!("LOD I0\n{op} T0 5"), 2, "FC5A");
    }
    assert_error("LOD I0\nTMR T0 5", 2, "did you mean");
    assert_error("LOD I0\nTMR T0 5", 2, "TIM");
    assert_error("LOD I0\nBCD D0 D1", 2, "did you mean");
    assert_error("LOD I0\nBCD D0 D1", 2, "HTOB");
}

/// §1: an untyped ADD (MICRO3 style) says the MICRO3 instruction is the W type.
#[test]
fn an_untyped_add_mentions_micro3_and_w() {
    assert_error("LOD I0\nADD D0 D1 D2", 2, "MICRO3");
    let e = errors("LOD I0\nADD D0 D1 D2");
    assert!(
        e.iter().any(|(l, msg)| *l == 2 && msg.contains('W')),
        "{e:?}"
    );
}

/// §5.1: a counter takes 2 (CNT) or 3 (CDP, CUD) LOD blocks and a shift register 3; a counter,
/// shift register, MCS or JMP ends its rung.
#[test]
fn counter_and_shift_register_rung_rules() {
    for (src, line) in [
        ("LOD I0\nCNT C0 5", 2),
        ("LOD I0\nLOD I1\nLOD I2\nCNT C0 5", 4),
        ("LOD I0\nLOD I1\nCDP C0 5", 3),
        ("LOD I0\nLOD I1\nCUD C0 5", 3),
        ("LOD I0\nLOD I1\nSFR R0 4", 3),
    ] {
        assert_error(src, line, "CNT|CDP|CUD|SFR|block|input");
    }
    for (src, line) in [
        ("LOD I0\nLOD I1\nCNT C0 5\nOUT Q0", 4),
        ("LOD I0\nLOD I1\nCNT C0 5\nAND I2\nOUT Q0", 4),
        ("LOD I0\nLOD I1\nLOD I2\nSFR R0 4\nOUT Q0", 5),
        ("LOD I0\nMCS\nOUT Q0\nMCR", 3),
        ("LOD I0\nJMP\nAND I1\nOUT Q0\nJEND", 3),
    ] {
        assert_error(src, line, "rung|LOD");
    }
    assert_assembles("LOD I0\nLOD I1\nCNT C0 5\nLOD I2\nLOD I3\nLOD I4\nCUD C1 5\nNOP\nEND");
    assert_assembles(
        "LOD I0\nMCS\nLOD I0\nLOD I1\nCNT C0 5\nMCR\nLOD I1\nJMP\nLOD I0\nLOD I1\nLOD I2\nSFR R0 4\nJEND",
    );
    assert_assembles("CC>= C0 5\nOUT Q0\nDC= D0 D1\nAND I0\nOUT Q1");
}

/// §5.1: MCR/JEND need an opener since the previous closer, openers must be closed (reported on
/// the first one left open), and MCR/JEND may not stand inside a rung's open logic.
#[test]
fn mcs_and_jmp_structure_errors() {
    assert_error("LOD I0\nOUT Q0\nMCR", 3, "MCS|MCR");
    assert_error("LOD I0\nMCS\nLOD I1\nOUT Q0\nMCR\nMCR", 6, "MCS|MCR");
    assert_error("LOD I0\nOUT Q0\nJEND", 3, "JMP|JEND");
    assert_error("LOD I0\nJMP\nLOD I1\nOUT Q0", 2, "JMP|JEND");
    assert_error("LOD I0\nJMP\nLOD I1\nJMP\nLOD I2\nOUT Q0", 2, "JMP|JEND");
    assert_error("LOD I0\nMCS\nLOD I1\nOUT Q0", 2, "MCS|MCR");
    assert_error("LOD I0\nMCS\nLOD I1\nOUT Q0\nLOD I2\nMCR", 6, "MCR|rung");
    assert_error("LOD I0\nJMP\nLOD I1\nOUT Q0\nLOD I2\nJEND", 6, "JEND|rung");
    assert_assembles(
        "LOD I0\nMCS\nLOD I1\nMCS\nLOD I2\nOUT Q0\nMCR\nLOD I0\nJMP\nLOD I1\nJMP\nJEND",
    );
}

// ---- §1 MICRO3 warnings ---------------------------------------------------------------------

/// §1: reading a MICRO3 special relay never written gives one warning per number, at its first
/// read, naming MICRO3 and the OpenNet relay to use.
#[test]
fn micro3_relays_read_but_never_written_warn_once_at_their_first_read() {
    let w = warnings("LOD M303\nOUT Q0\nLOD I0\nAND M303\nOUT Q1");
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].0, 1);
    assert!(
        w[0].1.contains("MICRO3") && w[0].1.contains("M8003"),
        "{w:?}"
    );
    for (relay, opennet, read) in [
        ("M301", "M8120", "LODN"),
        ("M303", "M8003", "AND"),
        ("M304", "M8004", "ANDN"),
        ("M311", "M8121", "OR"),
        ("M312", "M8122", "ORN"),
        ("M313", "M8123", "AND"),
    ] {
        let src = if read.starts_with("LOD") {
            format!("LOD I0\nOUT Q1\n{read} {relay}\nOUT Q0")
        } else {
            format!("LOD I0\nOUT Q1\nLOD I1\n{read} {relay}\nOUT Q0")
        };
        let line = if read.starts_with("LOD") { 3 } else { 4 };
        let w = warnings(&src);
        assert_eq!(w.len(), 1, "{src}: {w:?}");
        assert_eq!(w[0].0, line, "{src}");
        assert!(
            w[0].1.contains("MICRO3") && w[0].1.contains(opennet),
            "{src}: {w:?}"
        );
    }
    let w = warnings("LOD M301\nAND M312\nOUT Q0\nLODN M312\nOUT Q1");
    let mut lines: Vec<usize> = w.iter().map(|(l, _)| *l).collect();
    lines.sort_unstable();
    assert_eq!(lines, [1, 2], "one per number: {w:?}");
}

/// §1: a relay the program writes (OUT, OUTN, SET, RST, an advanced destination or SFTL/SFTR
/// operand) is not warned about; nor are other M3xx relays.
#[test]
fn a_written_micro3_relay_is_not_warned_about() {
    for src in [
        "LOD M303\nOUT Q0\nLOD I0\nOUT M303",
        "LOD M311\nOUT Q0\nLOD I0\nOUTN M311",
        "LOD M301\nOUT Q0\nLOD I0\nSET M301",
        "LOD M304\nOUT Q0\nLOD I0\nRST M304",
        "LOD M312\nOUT Q0\nLOD I0\nMOV(W) 0 M300",
        "LOD M313\nOUT Q0\nLOD I0\nSFTL(W) M300 1",
        "LOD M302\nOUT Q0\nLOD M317\nOUT Q1",
    ] {
        let w = warnings(src);
        assert!(w.is_empty(), "{src}: {w:?}");
    }
}

/// §1: warnings never stop assembly; the relay is an ordinary one, 0 here.
#[test]
fn a_program_with_warnings_runs_and_the_relay_is_0() {
    let mut m = plc("LOD M303\nOUT Q0\nLOD M303\nOUTN Q1", 10);
    to_scan(&mut m, 2);
    assert_eq!(values(&m, &["Q0", "Q1", "M303"]), [0, 1, 0]);
}
