//! The command line: OpenNet programs through the runner.
use crate::common;
use common::{scratch_file, servoscope};

// ---- Runner and examples --------------------------------------------------------------------

#[test]
fn the_runner_speaks_opennet() {
    let example = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/examples/batch_sotu.opennet"
    );
    let out = servoscope(&[
        "run",
        example,
        "--json",
        "--max-ticks",
        "10",
        "--input",
        "I1=2,4,6",
        "--input",
        "I1=8",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(j["dialect"], "opennet");
    assert_eq!(j["status"], "ended");
    assert_eq!(j["ticks"], 10);
    assert_eq!(j["steps"], 50);
    assert_eq!(j["fault"], serde_json::Value::Null);
    assert_eq!(j["registers"]["D0"], 2, "rising edges in scans 2 and 6");
    assert_eq!(j["registers"]["D3"], 500);
    assert_eq!(
        j["bits"]["I1"],
        serde_json::Value::Null,
        "off again from scan 8: toggles add up"
    );
    assert_eq!(j["flags"]["M8120"], 0, "the last scan was not scan 0");
    assert_eq!(j["error_count"], 0);
    let out = servoscope(&["run", example, "--json", "--max-ticks", "0"]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (j["ticks"].as_u64(), j["flags"]["M8121"].as_u64()),
        (Some(0), Some(0))
    );
    let out = servoscope(&["run", example, "--input", "I8=1"]);
    assert_eq!(out.status.code(), Some(2));
    let bad = scratch_file("bad.opennet", "LD I0\nOUT Q0\n");
    let out = servoscope(&["run", bad.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(
        (&j["dialect"], &j["status"]),
        (&"opennet".into(), &"not assembled".into())
    );
    assert_eq!(j["diagnostics"][0]["line"], 1, "{j}");
    let _ = std::fs::remove_file(bad);
}
