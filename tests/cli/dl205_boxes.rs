//! The command line: DL205 timers and counters through the runner.
use crate::common;
use common::servoscope;

// ---- The runner ----------------------------------------------------------------------------

#[test]
fn the_runner_takes_scan_ms_and_reports_time() {
    let dir = std::env::temp_dir().join(format!("servoscope-boxes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("t.dl205");
    std::fs::write(&file, "STR X1\nTMR T1 K30\nSTR T1\nOUT Y0\nEND\n").unwrap();
    let path = file.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["run", path, "--json", "--input", "X1=0"];
        args.extend_from_slice(extra);
        servoscope(&args)
    };
    let out = run(&["--max-ticks", "150", "--setting", "scan_ms=20"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (j["scan_ms"].as_u64(), j["time_ms"].as_u64()),
        (Some(20), Some(3000))
    );
    assert_eq!(j["bits"]["T1"], 1);
    assert_eq!(j["bits"]["Y0"], 1);
    assert_eq!(j["registers"]["V1"], 0x30);
    let out = run(&["--max-ticks", "149", "--setting", "scan_ms=20"]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(j["bits"].get("T1").is_none());
    // --set Vn=VALUE: decimal or 0x hex, 0–65535 (§8).
    let out = run(&["--set", "V2000=0x12", "--max-ticks", "0"]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["registers"]["V2000"], 0x12);
    for bad in ["V2000=-1", "V2000=65536", "V40000=1"] {
        let out = run(&["--set", bad]);
        assert_eq!(out.status.code(), Some(2), "--set {bad}");
        assert!(out.stdout.is_empty(), "--set {bad}");
    }
    for bad in [
        "scan_ms=0",
        "scan_ms=1001",
        "scan_ms=2.5",
        "scan=10",
        "scan_ms",
    ] {
        let out = run(&["--setting", bad]);
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(out.stdout.is_empty(), "{bad}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("--setting"),
            "{bad}"
        );
    }
}

// ---- The examples ----------------------------------------------------------------------------

/// The traffic light at 10 ms scans: green until 5.0 s, yellow until 7.0 s, red until 12.0 s,
/// then one scan resets the timer and green starts again (1201 scans a cycle). Through the
/// runner, as a grading script would run it; at 20 ms scans the same seconds come at half the
/// scans.
#[test]
fn the_traffic_light_keeps_its_seconds() {
    let lamps = |scans: u64, scan_ms: u32| {
        let out = servoscope(&[
            "run",
            "assets/examples/traffic_light.dl205",
            "--json",
            "--max-ticks",
            &scans.to_string(),
            "--setting",
            &format!("scan_ms={scan_ms}"),
        ]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let on = |y: &str| j["bits"].get(y).is_some();
        (on("Y1"), on("Y2"), on("Y0"))
    };
    const GREEN: (bool, bool, bool) = (true, false, false);
    const YELLOW: (bool, bool, bool) = (false, true, false);
    const RED: (bool, bool, bool) = (false, false, true);
    for (scans, want) in [
        (1, GREEN),
        (499, GREEN),
        (500, YELLOW),
        (699, YELLOW),
        (700, RED),
        (1200, RED),
        (1201, GREEN),
    ] {
        assert_eq!(lamps(scans, 10), want, "after {scans} scans of 10 ms");
    }
    assert_eq!(lamps(249, 20), GREEN);
    assert_eq!(lamps(250, 20), YELLOW);
    assert_eq!(lamps(350, 20), RED);
}
