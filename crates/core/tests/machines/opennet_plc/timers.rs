//! OpenNet timers (spec opennet.md §5.8).

use super::*;

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
