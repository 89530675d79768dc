//! The command line: DL205 programs through the runner.
use crate::common;
use common::servoscope;

// ---- Runner and examples ----------------------------------------------------------------------

#[test]
fn the_runner_speaks_dl205() {
    let example = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/examples/totaliser.dl205"
    );
    let out = servoscope(&[
        "run",
        example,
        "--json",
        "--max-ticks",
        "41",
        "--input",
        "X0=1",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(j["dialect"], "dl205");
    assert_eq!(j["status"], "ended");
    assert_eq!(
        (j["ticks"].as_u64(), j["steps"].as_u64()),
        (Some(41), Some(41 * 15))
    );
    assert_eq!(j["registers"]["V2001"], 1, "40 × 250 = 10000: carried");
    assert_eq!(
        j["registers"]["V2000"],
        serde_json::Value::Null,
        "0 is not listed"
    );
    assert_eq!(j["bits"]["X0"], 1);
    assert_eq!(j["stack_depth"], 0);
    // The twenty relays of §4.
    assert_eq!(j["flags"].as_object().unwrap().len(), 20);
    for key in ["ACC", "L1", "L8"] {
        assert!(j["registers"][key].is_u64(), "{key}");
    }
    let out = servoscope(&["run", example, "--json", "--max-ticks", "0"]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (
            j["ticks"].as_u64(),
            j["flags"]["SP1"].as_u64(),
            j["flags"]["SP0"].as_u64()
        ),
        (Some(0), Some(1), Some(0))
    );
    let out = servoscope(&["run", example, "--input", "Y0=1"]);
    assert_eq!(out.status.code(), Some(2));
    let out = servoscope(&["run", example, "--input", "X8=1"]);
    assert_eq!(out.status.code(), Some(2));
}
