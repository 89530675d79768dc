//! OpenNet master control, jumps, clocks and steps (§5.12, §3).

use super::*;

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
