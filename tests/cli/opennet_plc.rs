//! The command line: OpenNet programs through the runner (spec opennet.md §9).

use crate::common;
use common::{scratch_file, servoscope};
use std::process::Output;

// ---- §9 The runner -------------------------------------------------------------------------

/// A program file for the runner, removed when dropped.
struct Script(std::path::PathBuf);

impl Script {
    fn new(name: &str, src: &str) -> Self {
        Script(scratch_file(name, src))
    }

    fn run(&self, extra: &[&str]) -> Output {
        let mut args = vec!["run", self.0.to_str().unwrap(), "--json"];
        args.extend_from_slice(extra);
        servoscope(&args)
    }

    /// Run and require exit 0 with one JSON object on stdout.
    fn json(&self, extra: &[&str]) -> serde_json::Value {
        let out = self.run(extra);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{extra:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).expect("one JSON object")
    }
}

impl Drop for Script {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// TIM T0 5 on from scan 0 (on in scan 50 at 10 ms), CNT C0 3 counting I1's rises at scans 2,
/// 4 and 6, R3 driven by M8125. Nine instructions a scan.
const RUNNER_PROGRAM: &str =
    "LOD I0\nTIM T0 5\nLOD I2\nLOD I1\nCNT C0 3\nLOD T0\nOUT Q0\nLOD M8125\nOUT R3\n";

/// §9: timers, counters, settings, R bits and the flags M8125 (named) but not M8123.
#[test]
fn the_runner_reports_timers_counters_and_settings() {
    let s = Script::new("plc_timers.opennet", RUNNER_PROGRAM);
    let inputs = ["--input", "I0=0", "--input", "I1=2,3,4,5,6,7"];
    let j = s.json(&[&["--max-ticks", "60"][..], &inputs[..]].concat());
    assert_eq!(
        (j["dialect"].as_str(), j["ticks"].as_u64()),
        (Some("opennet"), Some(60))
    );
    assert_eq!(j["steps"], 9 * 60);
    assert_eq!(j["fault"], serde_json::Value::Null);
    assert_eq!(
        j["timers"],
        serde_json::json!({"T0": {"preset": 5, "current": 0, "output": 1}})
    );
    assert_eq!(
        j["counters"],
        serde_json::json!({"C0": {"preset": 3, "current": 3, "output": 1}})
    );
    assert_eq!(j["settings"]["scan_ms"], 10);
    assert_eq!(
        (
            j["bits"]["R3"].as_u64(),
            j["bits"]["Q0"].as_u64(),
            j["bits"]["I0"].as_u64()
        ),
        (Some(1), Some(1), Some(1))
    );
    assert!(j["bits"].get("I1").is_none(), "off from scan 7");
    assert_eq!(j["flags"]["M8125"], 1, "named by the program");
    assert!(j["flags"].get("M8123").is_none(), "not named");
    // After 50 scans the last is scan 49: current 5 − ⌊490 / 100⌋ = 1, output 0.
    let j = s.json(&[&["--max-ticks", "50"][..], &inputs[..]].concat());
    assert_eq!(
        j["timers"]["T0"],
        serde_json::json!({"preset": 5, "current": 1, "output": 0})
    );
    assert!(j["bits"].get("Q0").is_none());
}

/// §9: `--setting scan_ms=50` changes the outcome: after 11 scans (last scan 10, j = 10) the
/// current value is 5 − ⌊100/100⌋ = 4 at 10 ms but 5 − ⌊500/100⌋ = 0 (on) at 50 ms; after 10
/// scans at 50 ms it is 5 − ⌊450/100⌋ = 1. The last `--setting` wins.
#[test]
fn the_runner_scan_ms_setting_changes_a_timers_outcome() {
    let s = Script::new("plc_scan_ms.opennet", RUNNER_PROGRAM);
    let j = s.json(&["--max-ticks", "11", "--input", "I0=0"]);
    assert_eq!(
        j["timers"]["T0"],
        serde_json::json!({"preset": 5, "current": 4, "output": 0})
    );
    let j = s.json(&[
        "--max-ticks",
        "11",
        "--input",
        "I0=0",
        "--setting",
        "scan_ms=50",
    ]);
    assert_eq!(
        j["timers"]["T0"],
        serde_json::json!({"preset": 5, "current": 0, "output": 1})
    );
    assert_eq!(j["settings"]["scan_ms"], 50);
    assert_eq!(j["bits"]["Q0"], 1);
    let j = s.json(&[
        "--max-ticks",
        "10",
        "--input",
        "I0=0",
        "--setting",
        "scan_ms=10",
        "--setting",
        "scan_ms=50",
    ]);
    assert_eq!(j["settings"]["scan_ms"], 50, "the last one wins");
    assert_eq!(
        j["timers"]["T0"],
        serde_json::json!({"preset": 5, "current": 1, "output": 0})
    );
}

/// §9: a bad value, an unknown name or a missing `=` is an argument error: exit 2, no stdout.
#[test]
fn the_runner_rejects_bad_settings() {
    let s = Script::new("plc_bad_setting.opennet", RUNNER_PROGRAM);
    for bad in [
        "scan_ms=0",
        "scan_ms=1001",
        "scan_ms=ten",
        "scan_ms=2.5",
        "scan_ms=",
        "scan_ms",
        "speed=10",
    ] {
        let out = s.run(&["--setting", bad]);
        assert_eq!(out.status.code(), Some(2), "--setting {bad}");
        assert!(out.stdout.is_empty(), "--setting {bad}");
    }
    for good in ["scan_ms=1", "scan_ms=1000"] {
        assert_eq!(s.run(&["--setting", good]).status.code(), Some(0), "{good}");
    }
}

/// §9: with `--max-ticks 0` timers and counters show the start values of §2 (current = preset
/// for a timer, 0 for a counter; a register preset 0) and every flag is 0.
#[test]
fn the_runner_shows_start_values_with_no_scans() {
    let s = Script::new(
        "plc_zero.opennet",
        &format!("{RUNNER_PROGRAM}LOD I3\nTIM T1 D10\n"),
    );
    let j = s.json(&["--max-ticks", "0"]);
    assert_eq!(
        (j["ticks"].as_u64(), j["steps"].as_u64()),
        (Some(0), Some(0))
    );
    assert_eq!(
        j["timers"],
        serde_json::json!({
            "T0": {"preset": 5, "current": 5, "output": 0},
            "T1": {"preset": 0, "current": 0, "output": 0}
        })
    );
    assert_eq!(
        j["counters"],
        serde_json::json!({"C0": {"preset": 3, "current": 0, "output": 0}})
    );
    for (name, v) in j["flags"].as_object().unwrap() {
        assert_eq!(*v, 0, "{name}");
    }
}

/// §9: `timers` and `counters` are `{}` when the program names none, and `flags` has exactly
/// the five relays; naming M8123 and M8125 adds them. Timers and counters named only as a
/// contact or word operand (with all REP cycles) are listed too.
#[test]
fn the_runner_lists_what_the_program_names() {
    let s = Script::new("plc_none.opennet", "LOD I0\nOUT Q0\n");
    let j = s.json(&[]);
    assert_eq!(j["timers"], serde_json::json!({}));
    assert_eq!(j["counters"], serde_json::json!({}));
    let mut flags: Vec<&str> = j["flags"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    flags.sort();
    assert_eq!(flags, ["M8003", "M8004", "M8120", "M8121", "M8122"]);

    // T2 (register preset, D10 = 0) is on in its first powered scan (§5.8); T7 is only a
    // contact and C4–C6 only the REP cycles of a word operand.
    let s = Script::new(
        "plc_named.opennet",
        "LOD M8123\nOUT Q0\nLOD T7\nOUT Q1\nLOD M8125\nMOV(W) C4(R) D0 REP 3\nTIM T2 D10\n\
         LOD M8120\nMOV(W) 8000h R240\n",
    );
    let j = s.json(&["--max-ticks", "1"]);
    let mut flags: Vec<&str> = j["flags"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    flags.sort();
    assert_eq!(
        flags,
        [
            "M8003", "M8004", "M8120", "M8121", "M8122", "M8123", "M8125"
        ]
    );
    assert_eq!(
        (j["flags"]["M8123"].as_u64(), j["flags"]["M8125"].as_u64()),
        (Some(1), Some(1))
    );
    assert_eq!(
        j["timers"],
        serde_json::json!({
            "T2": {"preset": 0, "current": 0, "output": 1},
            "T7": {"preset": 0, "current": 0, "output": 0}
        })
    );
    let zero = serde_json::json!({"preset": 0, "current": 0, "output": 0});
    assert_eq!(
        j["counters"],
        serde_json::json!({"C4": zero, "C5": zero, "C6": zero})
    );
    assert_eq!(j["bits"]["R255"], 1, "canonical R name");
    assert_eq!(j["bits"]["Q0"], 1, "M8123 = 1 at t = 0");
}

/// §9: warnings go to stderr and do not change the exit code or the JSON.
#[test]
fn the_runner_prints_warnings_on_stderr_and_exits_0() {
    let s = Script::new("plc_warn.opennet", "LOD M303\nOUTN Q0\n");
    let out = s.run(&["--max-ticks", "2"]);
    assert_eq!(out.status.code(), Some(0));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("warning") && err.contains("M8003"), "{err}");
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(
        (j["ticks"].as_u64(), j["bits"]["Q0"].as_u64()),
        (Some(2), Some(1))
    );
}

/// §6, §9: a BCD error shows in error_count, last_error (1-based line, 0-based tick) and M8004;
/// it is not a fault.
#[test]
fn the_runner_reports_a_bcd_error() {
    let s = Script::new("plc_bcd.opennet", "LOD M8120\nHTOB(W) 10000 D0\n");
    let j = s.json(&["--max-ticks", "3"]);
    assert_eq!(j["fault"], serde_json::Value::Null);
    assert_eq!(j["error_count"], 1);
    assert_eq!(
        j["last_error"],
        serde_json::json!({"kind": "bcd_range", "line": 2, "tick": 0})
    );
    assert_eq!(j["flags"]["M8004"], 1, "latched");
    assert!(j["registers"].get("D0").is_none(), "D0 unchanged (0)");
}
