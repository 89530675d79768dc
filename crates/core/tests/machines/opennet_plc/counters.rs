//! OpenNet counters (§5.9).

use super::*;

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
