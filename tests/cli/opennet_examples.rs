//! The OpenNet teaching examples (traffic light, parts counter, conveyor, alarm) run through the
//! runner and show, scan by scan, what their header comments promise.
//!
//! Every expected value is worked out by hand from the contract (`spec/opennet.md`): §3 the scan
//! and the clocks, §5.1 the rungs, §5.8 timers, §5.9 counters, §5.12 MCS/MCR, §9 the runner.
//! `--max-ticks N` runs scans 0 … N−1, so the JSON shows the state at the end of scan N−1:
//! "Q2 turns on in scan 500" is checked as off with `--max-ticks 500` and on with 501.
//! Timer rule used throughout (§5.8): with the input on from scan s, in scan s + j the current
//! value is max(0, P − ⌊j × scan_ms / 100⌋) (TIM) and the output is on first in scan
//! s + ⌈P × 100 / scan_ms⌉; the first powered scan counts no time.

use crate::common;

use common::servoscope;
use serde_json::Value;

fn path(name: &str) -> String {
    format!("{}/assets/examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Run `name` for `ticks` scans with the extra runner arguments `args`; the JSON object.
fn run(name: &str, ticks: u32, args: &[&str]) -> Value {
    let example = path(name);
    let ticks_text = ticks.to_string();
    let mut all = vec![
        "run",
        example.as_str(),
        "--json",
        "--max-ticks",
        ticks_text.as_str(),
    ];
    all.extend_from_slice(args);
    let out = servoscope(&all);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{name} --max-ticks {ticks} {args:?}: {stderr}"
    );
    assert!(
        !stderr.contains("warning"),
        "{name}: an example assembles without warnings: {stderr}"
    );
    let j: Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(j["dialect"], "opennet");
    assert_eq!(j["status"], "ended");
    assert_eq!(j["ticks"], ticks);
    assert_eq!(j["fault"], Value::Null);
    assert_eq!(j["error_count"], 0, "{name}: no execution errors");
    assert_eq!(j["last_error"], Value::Null);
    j
}

/// A bit from `bits` (a point not listed is 0).
fn bit(j: &Value, name: &str) -> u64 {
    match &j["bits"][name] {
        Value::Null => 0,
        v => v.as_u64().expect("a bit is 0 or 1"),
    }
}

/// A data register (one not listed is 0).
fn reg(j: &Value, name: &str) -> u64 {
    match &j["registers"][name] {
        Value::Null => 0,
        v => v.as_u64().expect("an unsigned register value"),
    }
}

/// (preset, current, output) of a timer or counter; `kind` is "timers" or "counters".
fn box_of(j: &Value, kind: &str, name: &str) -> (u64, u64, u64) {
    let b = &j[kind][name];
    assert!(b.is_object(), "{kind} lists {name}: {j}");
    (
        b["preset"].as_u64().unwrap(),
        b["current"].as_u64().unwrap(),
        b["output"].as_u64().unwrap(),
    )
}

/// The lamps of the traffic light as (red Q0, green Q1, yellow Q2).
fn lamps(j: &Value) -> (u64, u64, u64) {
    (bit(j, "Q0"), bit(j, "Q1"), bit(j, "Q2"))
}

const RED: (u64, u64, u64) = (1, 0, 0);
const GREEN: (u64, u64, u64) = (0, 1, 0);
const YELLOW: (u64, u64, u64) = (0, 0, 1);
const DARK: (u64, u64, u64) = (0, 0, 0);

// ---- traffic_light.opennet ------------------------------------------------------------------
//
// Program order: T0 (input I0 AND NOT T2, 50), T1 (input T0, 20), T2 (input T1, 50), then the
// lamps: green Q1 = I0 AND NOT T0, yellow Q2 = T0 AND NOT T1, red Q0 = T1. 16 instructions
// with END, no jumps: N scans are 16 N steps (§3).
// With I0 on from scan 0 and scan_ms = 10:
// - T0 first powered in scan 0 → on in scan 0 + ⌈50 × 100 / 10⌉ = 500; current after scan 299
//   = 50 − ⌊299 × 10 / 100⌋ = 21, after scan 499 = 50 − 49 = 1.
// - T1 is after T0 in the scan, so it sees T0 on from scan 500 → on in 500 + 200 = 700.
// - T2 sees T1 from scan 700 → on in 700 + 500 = 1200 (T1 still on: red).
// - Scan 1201: the contact T2 (on since scan 1200) takes T0's input away → T0, T1, T2 reset
//   in this order (§5.8 step 2); green = I0 AND NOT T0 = 1.
// - Scan 1202: T0 first powered again (counts no time) → on in 1702; T1 on in 1902.
// With scan_ms = 50: T0 on in ⌈5000 / 50⌉ = 100, T1 in 100 + 40 = 140, T2 in 140 + 100 = 240,
// reset (green) in 241, T0 starts again in 242; current after scan 59 = 50 − ⌊59 × 50 / 100⌋ = 21.

const TRAFFIC: &str = "traffic_light.opennet";

#[test]
fn the_traffic_light_changes_at_the_scans_its_header_names() {
    let at = |ticks| run(TRAFFIC, ticks, &["--input", "I0=0"]);

    let j = at(1);
    assert_eq!(lamps(&j), GREEN, "scan 0: green at once");
    assert_eq!(
        box_of(&j, "timers", "T0"),
        (50, 50, 0),
        "first powered: no time counted"
    );
    assert_eq!(j["steps"], 16);
    assert_eq!(j["settings"]["scan_ms"], 10, "the default scan time");
    assert_eq!(j["counters"], serde_json::json!({}), "no counters");

    let j = at(300);
    assert_eq!(lamps(&j), GREEN);
    assert_eq!(
        box_of(&j, "timers", "T0"),
        (50, 21, 0),
        "2.9 s gone: 50 − 29"
    );

    let j = at(500);
    assert_eq!(lamps(&j), GREEN, "scan 499: still green");
    assert_eq!(box_of(&j, "timers", "T0"), (50, 1, 0));
    let j = at(501);
    assert_eq!(lamps(&j), YELLOW, "scan 500: yellow");
    assert_eq!(box_of(&j, "timers", "T0"), (50, 0, 1));
    assert_eq!(
        box_of(&j, "timers", "T1"),
        (20, 20, 0),
        "T1 first powered in scan 500"
    );

    let j = at(700);
    assert_eq!(lamps(&j), YELLOW, "scan 699");
    assert_eq!(
        box_of(&j, "timers", "T1"),
        (20, 1, 0),
        "20 − ⌊199 × 10 / 100⌋"
    );
    let j = at(701);
    assert_eq!(lamps(&j), RED, "scan 700: red");
    assert_eq!(box_of(&j, "timers", "T1"), (20, 0, 1));

    let j = at(1200);
    assert_eq!(lamps(&j), RED, "scan 1199");
    assert_eq!(box_of(&j, "timers", "T2"), (50, 1, 0));
    let j = at(1201);
    assert_eq!(lamps(&j), RED, "scan 1200: T2 on, red still shows");
    assert_eq!(box_of(&j, "timers", "T2"), (50, 0, 1));
    let j = at(1202);
    assert_eq!(lamps(&j), GREEN, "scan 1201: the chain resets, green again");
    for (t, preset) in [("T0", 50), ("T1", 20), ("T2", 50)] {
        assert_eq!(box_of(&j, "timers", t), (preset, preset, 0), "{t} reset");
    }
    assert_eq!(j["steps"], 16 * 1202);

    // The second cycle is two scans longer than the first.
    assert_eq!(lamps(&at(1702)), GREEN, "scan 1701");
    assert_eq!(lamps(&at(1703)), YELLOW, "scan 1702");
    assert_eq!(lamps(&at(1902)), YELLOW, "scan 1901");
    assert_eq!(lamps(&at(1903)), RED, "scan 1902");
}

#[test]
fn the_traffic_light_is_dark_without_its_run_switch() {
    // No input at all: T0's input is off, so every timer stays reset and no lamp is lit.
    let j = run(TRAFFIC, 600, &[]);
    assert_eq!(lamps(&j), DARK);
    assert_eq!(box_of(&j, "timers", "T0"), (50, 50, 0));
    // I0 on in scans 0–549 (yellow from scan 500), then off: everything resets in scan 550.
    let j = run(TRAFFIC, 551, &["--input", "I0=0,550"]);
    assert_eq!(lamps(&j), DARK, "scan 550: I0 off");
    assert_eq!(
        box_of(&j, "timers", "T0"),
        (50, 50, 0),
        "back at its preset"
    );
    assert_eq!(box_of(&j, "timers", "T1"), (20, 20, 0));
    assert_eq!(bit(&j, "I0"), 0);
}

#[test]
fn the_traffic_light_keeps_its_seconds_at_a_50_ms_scan() {
    // The same controller time t: scan t / 10 at 10 ms is scan t / 50 at 50 ms (the scan
    // number divided by 5); `--max-ticks` one more than the scan shows the end of that scan.
    // At 10 ms: green while t < 5000, yellow 5000 ≤ t < 7000 (scans 500–699), red 7000 ≤ t ≤
    // 12000 (700–1200), green from 12010 (scan 1201). At 50 ms: yellow from scan 100 (5000),
    // red from 140 (7000) to 240 (12000), green from 241 (12050).
    for (t, lamp) in [
        (2950, GREEN),
        (4950, GREEN),
        (5000, YELLOW),
        (6950, YELLOW),
        (7000, RED),
        (11950, RED),
        (12000, RED),
        (12050, GREEN),
        (13000, GREEN),
    ] {
        let ten = run(TRAFFIC, t / 10 + 1, &["--input", "I0=0"]);
        let fifty = run(
            TRAFFIC,
            t / 50 + 1,
            &["--input", "I0=0", "--setting", "scan_ms=50"],
        );
        assert_eq!(ten["settings"]["scan_ms"], 10);
        assert_eq!(fifty["settings"]["scan_ms"], 50);
        assert_eq!(lamps(&ten), lamp, "10 ms, scan {}", t / 10);
        assert_eq!(lamps(&fifty), lamp, "50 ms, scan {}", t / 50);
    }
    // The exact scans at 50 ms: yellow in scan 100, red in 140, green again in 241.
    let at50 = |ticks| {
        run(
            TRAFFIC,
            ticks,
            &["--input", "I0=0", "--setting", "scan_ms=50"],
        )
    };
    let j = at50(60);
    assert_eq!(
        box_of(&j, "timers", "T0"),
        (50, 21, 0),
        "2.9 s gone, as at 10 ms"
    );
    assert_eq!(lamps(&at50(100)), GREEN, "scan 99 = 4.95 s");
    assert_eq!(lamps(&at50(101)), YELLOW, "scan 100 = 5.0 s");
    assert_eq!(lamps(&at50(140)), YELLOW, "scan 139");
    assert_eq!(lamps(&at50(141)), RED, "scan 140 = 7.0 s");
    assert_eq!(lamps(&at50(241)), RED, "scan 240 = 12.0 s: T2 on");
    assert_eq!(lamps(&at50(242)), GREEN, "scan 241: the chain resets");
}

// ---- parts_counter.opennet ------------------------------------------------------------------
//
// Program order: (LOD C0, AND I1, SOTU, INC(W) D1), (LOD I1 reset, LOD I0 pulse, CNT C0 10),
// (CC>= C0 5, OUT Q1), (LOD C0, OUT Q0), (LOD M8125, MOV(W) C0 D0), END: 14 steps a scan.
// Parts: I0 on in scans 10n … 10n + 4 for n = 1 … 12 (toggles 10n and 10n + 5), and in
// 200–204; I1 on in scans 150–159.
// - Part n rises in scan 10n (memory 0 from the off scan before) → current n, D0 = n (the MOV
//   after the counter reads the new current value, §4.3).
// - Scan 50: current 5 → CC>= C0 5 → Q1. Scan 100: current 10 = preset → C0, Q0 on.
// - Scans 110, 120: rising pulses, but current = preset: not counted (§5.9).
// - Scan 150: LOD C0 reads last scan's output 1, AND I1 = 1, SOTU memory 0 → INC D1 = 1; then
//   the reset: current 0, output 0 → Q1 = Q0 = 0, D0 = 0. Scans 151–159: C0 = 0, no more INC.
// - Scan 200: rising pulse, reset off → current 1, D0 = 1.

const PARTS: &str = "parts_counter.opennet";

fn parts_inputs() -> Vec<String> {
    let mut toggles: Vec<String> = Vec::new();
    for n in 1..=12 {
        toggles.push((10 * n).to_string());
        toggles.push((10 * n + 5).to_string());
    }
    toggles.push("200".into());
    toggles.push("205".into());
    vec![
        format!("I0={}", toggles.join(",")),
        "I1=150,160".to_string(),
    ]
}

fn parts_at(ticks: u32) -> Value {
    let inputs = parts_inputs();
    run(
        PARTS,
        ticks,
        &["--input", inputs[0].as_str(), "--input", inputs[1].as_str()],
    )
}

#[test]
fn the_parts_counter_fills_a_box_of_ten() {
    let j = parts_at(10);
    assert_eq!(reg(&j, "D0"), 0, "no part before scan 10");
    assert_eq!(box_of(&j, "counters", "C0"), (10, 0, 0));
    assert_eq!(j["timers"], serde_json::json!({}), "no timers");

    let j = parts_at(11);
    assert_eq!(reg(&j, "D0"), 1, "scan 10: the first part");
    assert_eq!(j["steps"], 14 * 11);

    let j = parts_at(50);
    assert_eq!((reg(&j, "D0"), bit(&j, "Q1")), (4, 0), "scan 49");
    let j = parts_at(51);
    assert_eq!((reg(&j, "D0"), bit(&j, "Q1")), (5, 1), "scan 50: half full");

    let j = parts_at(100);
    assert_eq!(reg(&j, "D0"), 9, "scan 99");
    assert_eq!(bit(&j, "Q0"), 0);
    assert_eq!(box_of(&j, "counters", "C0"), (10, 9, 0));
    let j = parts_at(101);
    assert_eq!(reg(&j, "D0"), 10, "scan 100: the tenth part");
    assert_eq!(bit(&j, "Q0"), 1, "box full");
    assert_eq!(box_of(&j, "counters", "C0"), (10, 10, 1));

    let j = parts_at(150);
    assert_eq!(
        reg(&j, "D0"),
        10,
        "parts in scans 110 and 120 are not counted"
    );
    assert_eq!((bit(&j, "Q0"), bit(&j, "Q1")), (1, 1));
    assert_eq!(reg(&j, "D1"), 0, "no box emptied yet");
}

#[test]
fn the_parts_counter_resets_and_counts_boxes() {
    let j = parts_at(151);
    assert_eq!(bit(&j, "I1"), 1, "scan 150: reset pressed");
    assert_eq!(reg(&j, "D1"), 1, "one full box emptied");
    assert_eq!(reg(&j, "D0"), 0);
    assert_eq!(box_of(&j, "counters", "C0"), (10, 0, 0));
    assert_eq!((bit(&j, "Q0"), bit(&j, "Q1")), (0, 0));

    let j = parts_at(160);
    assert_eq!(reg(&j, "D1"), 1, "once per press (SOTU)");

    let j = parts_at(200);
    assert_eq!(reg(&j, "D0"), 0, "scan 199");
    let j = parts_at(201);
    assert_eq!(reg(&j, "D0"), 1, "scan 200: a part in the new box");
    assert_eq!(reg(&j, "D1"), 1);
    assert_eq!(box_of(&j, "counters", "C0"), (10, 1, 0));
}

#[test]
fn a_part_already_there_in_scan_0_counts() {
    // The pulse memory starts at 0, so I0 on in scan 0 is a rising edge (§5.9).
    let j = run(PARTS, 1, &["--input", "I0=0"]);
    assert_eq!(reg(&j, "D0"), 1);
    assert_eq!(box_of(&j, "counters", "C0"), (10, 1, 0));
    // Held on, it counts once.
    let j = run(PARTS, 20, &["--input", "I0=0"]);
    assert_eq!(reg(&j, "D0"), 1);
}

// ---- conveyor.opennet -----------------------------------------------------------------------
//
// Program order: M0 = (I0 OR M0) AND NOT I1; Q2 = NOT M0; LOD M0, MCS; inside: LOD M8125,
// OUT Q0, TIM T0 30; LOD T0, OUT Q1; LOD I3, LOD I2, CNT C0 5; LOD C0, OUT Q3; MCR; END.
// 20 instructions with END, all executed in every scan, area on or off (§5.12): 20 N steps.
// Inputs: I0 on in scans 10–19 and 500–509, I1 on in 400–409, I2 on for 5 scans from 100, 150,
// 200, 250, 450 and 600.
// - Scans 0–9: M0 = 0 → MC = 0 inside: Q0 = 0, T0 reset (30, 30, 0); Q2 = 1.
// - Scan 10: M0 = 1 (then held by OR M0) → Q0 = 1, T0 first powered → on in 10 + 300 = 310;
//   current after scan 309 = 30 − ⌊299 × 10 / 100⌋ = 1.
// - Packages in 100, 150, 200, 250 → C0 current 4 (< 5: output 0).
// - Scan 400: I1 → M0 = 0 → MC = 0: Q0 = Q1 = 0, T0 reset to (30, 30, 0); C0 holds 4, output
//   0 (§5.9 with MC = 0); Q2 = 1. Scan 410: I1 off, M0 stays 0 (no start, no hold).
// - Package in 450 with MC = 0: the pulse memory becomes 0, nothing counted.
// - Scan 500: start → Q0 = 1, T0 first powered again → on in 800.
// - Package in 600 (rising: memory 0) → current 5 → C0 output 1, Q3 = 1.

const CONVEYOR: &str = "conveyor.opennet";

fn conveyor_at(ticks: u32) -> Value {
    run(
        CONVEYOR,
        ticks,
        &[
            "--input",
            "I0=10,20,500,510",
            "--input",
            "I1=400,410",
            "--input",
            "I2=100,105,150,155,200,205,250,255,450,455,600,605",
        ],
    )
}

/// (motor Q0, feeder Q1, stopped Q2, batch complete Q3).
fn conveyor_lamps(j: &Value) -> (u64, u64, u64, u64) {
    (bit(j, "Q0"), bit(j, "Q1"), bit(j, "Q2"), bit(j, "Q3"))
}

#[test]
fn the_conveyor_runs_its_area_only_while_m0_is_on() {
    let j = conveyor_at(10);
    assert_eq!(conveyor_lamps(&j), (0, 0, 1, 0), "scan 9: stopped");
    assert_eq!(box_of(&j, "timers", "T0"), (30, 30, 0));
    assert_eq!(j["steps"], 20 * 10, "the logic of an off area still runs");

    let j = conveyor_at(11);
    assert_eq!(bit(&j, "M0"), 1, "scan 10: started");
    assert_eq!(conveyor_lamps(&j), (1, 0, 0, 0), "the motor runs");
    assert_eq!(
        box_of(&j, "timers", "T0"),
        (30, 30, 0),
        "first powered: no time counted"
    );

    let j = conveyor_at(310);
    assert_eq!(conveyor_lamps(&j), (1, 0, 0, 0), "scan 309");
    assert_eq!(box_of(&j, "timers", "T0"), (30, 1, 0));
    let j = conveyor_at(311);
    assert_eq!(
        conveyor_lamps(&j),
        (1, 1, 0, 0),
        "scan 310: the feeder starts"
    );
    assert_eq!(box_of(&j, "timers", "T0"), (30, 0, 1));

    let j = conveyor_at(400);
    assert_eq!(conveyor_lamps(&j), (1, 1, 0, 0), "scan 399");
    assert_eq!(box_of(&j, "counters", "C0"), (5, 4, 0), "four packages");
}

#[test]
fn the_conveyor_area_off_resets_timers_and_holds_counts() {
    let j = conveyor_at(401);
    assert_eq!(bit(&j, "M0"), 0, "scan 400: stop pressed");
    assert_eq!(
        conveyor_lamps(&j),
        (0, 0, 1, 0),
        "outputs inside the area are off"
    );
    assert_eq!(
        box_of(&j, "timers", "T0"),
        (30, 30, 0),
        "the timer is reset"
    );
    assert_eq!(box_of(&j, "counters", "C0"), (5, 4, 0), "the count is held");
    assert_eq!(j["steps"], 20 * 401);

    let j = conveyor_at(500);
    assert_eq!(conveyor_lamps(&j), (0, 0, 1, 0), "scan 499: still stopped");
    assert_eq!(bit(&j, "M0"), 0);
    assert_eq!(
        box_of(&j, "counters", "C0"),
        (5, 4, 0),
        "the package in scan 450 is lost"
    );

    let j = conveyor_at(501);
    assert_eq!(conveyor_lamps(&j), (1, 0, 0, 0), "scan 500: running again");
    assert_eq!(
        box_of(&j, "timers", "T0"),
        (30, 30, 0),
        "timing from the start again"
    );

    let j = conveyor_at(800);
    assert_eq!(
        conveyor_lamps(&j),
        (1, 0, 0, 1),
        "scan 799: the fifth package came in 600"
    );
    assert_eq!(box_of(&j, "counters", "C0"), (5, 5, 1));
    assert_eq!(box_of(&j, "timers", "T0"), (30, 1, 0));
    let j = conveyor_at(801);
    assert_eq!(
        conveyor_lamps(&j),
        (1, 1, 0, 1),
        "scan 800: the feeder, 3 s after the restart"
    );
}

// ---- alarm.opennet --------------------------------------------------------------------------
//
// Program order: LOD M8120, MOV(W) 500 D10; LOD I1, INC(W) D10; LOD I2, DC>= D10 1, ANDLOD,
// DEC(W) D10; LOD M8125, CMP>=(W) D10 800 M0, CMP<(W) D10 200 M1; LOD I0, RST Q0; LOD M0,
// OR M1, SET Q0; LOD Q0, AND M8121, OUT Q1; END: 20 steps a scan.
// M8121 (§3): on in scan k when 10 k mod 1000 < 500, i.e. k mod 100 < 50.
// Run A: I1 on in 0–299, I0 on in 350 and 500–501, I2 on in 400–401.
// - Scan 0: MOV 500, then INC → 501. After scan k ≤ 299: D10 = 501 + k: 799 after scan 298,
//   800 after scan 299 → M0 = 1, SET Q0. Q1 = Q0 AND M8121: scan 299 has 299 mod 100 = 99
//   ≥ 50 → 0; scan 300 → 1; scan 349 → 1; scan 350 → 0; scan 400 → 1.
// - Scan 350: RST Q0, then SET Q0 (M0 still on): Q0 stays 1.
// - Scans 400, 401: DC>= D10 1 holds → DEC: 799, 798; M0 = 0; Q0 stays set.
// - Scan 500: RST Q0 and neither M0 nor M1: Q0 = 0, Q1 = 0.
// Run B: I2 on from scan 0: after scan k, D10 = 499 − k (MOV then DEC in scan 0); 200 after
// scan 299, 199 in scan 300 → M1, Q0 (and Q1, 300 mod 100 = 0); 0 in scan 499; from scan 500
// DC>= D10 1 is off, so D10 stays 0 (not listed in `registers`).

const ALARM: &str = "alarm.opennet";

fn alarm_at(ticks: u32) -> Value {
    run(
        ALARM,
        ticks,
        &[
            "--input",
            "I1=0,300",
            "--input",
            "I0=350,351,500,502",
            "--input",
            "I2=400,402",
        ],
    )
}

/// (level D10, high M0, low M1, alarm Q0, lamp Q1).
fn alarm_state(j: &Value) -> (u64, u64, u64, u64, u64) {
    (
        reg(j, "D10"),
        bit(j, "M0"),
        bit(j, "M1"),
        bit(j, "Q0"),
        bit(j, "Q1"),
    )
}

#[test]
fn the_alarm_latches_a_high_level_until_acknowledged() {
    let j = alarm_at(1);
    assert_eq!(alarm_state(&j), (501, 0, 0, 0, 0), "scan 0: 500, then +1");
    assert_eq!(j["steps"], 20);

    assert_eq!(alarm_state(&alarm_at(299)), (799, 0, 0, 0, 0), "scan 298");
    let j = alarm_at(300);
    assert_eq!(
        alarm_state(&j),
        (800, 1, 0, 1, 0),
        "scan 299: high; the clock is off"
    );
    assert_eq!(j["flags"]["M8121"], 0);
    let j = alarm_at(301);
    assert_eq!(
        alarm_state(&j),
        (800, 1, 0, 1, 1),
        "scan 300: the lamp lights"
    );
    assert_eq!(j["flags"]["M8121"], 1);
    assert_eq!(bit(&j, "I1"), 0, "filling stopped");

    assert_eq!(alarm_state(&alarm_at(350)), (800, 1, 0, 1, 1), "scan 349");
    let j = alarm_at(351);
    assert_eq!(bit(&j, "I0"), 1, "scan 350: acknowledge pressed");
    assert_eq!(
        alarm_state(&j),
        (800, 1, 0, 1, 0),
        "still high: the later SET wins; the lamp blinks off"
    );

    assert_eq!(alarm_state(&alarm_at(400)), (800, 1, 0, 1, 0), "scan 399");
    assert_eq!(
        alarm_state(&alarm_at(401)),
        (799, 0, 0, 1, 1),
        "scan 400: back in range, latched"
    );
    assert_eq!(alarm_state(&alarm_at(402)), (798, 0, 0, 1, 1), "scan 401");
    assert_eq!(
        alarm_state(&alarm_at(500)),
        (798, 0, 0, 1, 0),
        "scan 499: still latched"
    );
    let j = alarm_at(501);
    assert_eq!(alarm_state(&j), (798, 0, 0, 0, 0), "scan 500: acknowledged");
    assert_eq!(j["steps"], 20 * 501);
}

#[test]
fn the_alarm_sees_a_low_level_and_the_drain_stops_at_0() {
    let at = |ticks| run(ALARM, ticks, &["--input", "I2=0"]);
    assert_eq!(
        alarm_state(&at(1)),
        (499, 0, 0, 0, 0),
        "scan 0: 500, then −1"
    );
    assert_eq!(
        alarm_state(&at(300)),
        (200, 0, 0, 0, 0),
        "scan 299: 200 is not low"
    );
    assert_eq!(alarm_state(&at(301)), (199, 0, 1, 1, 1), "scan 300: low");
    let j = at(500);
    assert_eq!(alarm_state(&j), (0, 0, 1, 1, 0), "scan 499: empty");
    assert_eq!(j["registers"]["D10"], Value::Null, "0 is not listed");
    let j = at(600);
    assert_eq!(
        alarm_state(&j),
        (0, 0, 1, 1, 0),
        "scan 599: DC>= D10 1 keeps DEC from wrapping"
    );
}
