//! The command line: TML programs through the runner.
use crate::common;
use common::{scratch_file, servoscope};

#[test]
fn the_runner_speaks_tml() {
    let example = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/examples/wait_input.tml"
    );
    let out = servoscope(&["run", example, "--json", "--input", "IN#2=120"]);
    assert_eq!(out.status.code(), Some(0));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(j["dialect"], "tml");
    assert_eq!(j["status"], "ended");
    assert_eq!(j["registers"]["found"], 1, "the sensor was seen");
    // IN#2 goes high before tick 120 runs; the event is checked at the end of tick 120, so
    // WAIT! completes in tick 121, where the program also ends: 122 ticks completed.
    assert_eq!(j["ticks"], 122);
    assert_eq!(j["flags"]["IN#2"], 1);
    assert_eq!(j["event"]["kind"], "IN");
    assert_eq!(j["event"]["input"], 2);
    assert_eq!(j["motion"]["mode"], serde_json::Value::Null);
    // Spec §9's order: the predefined data, PREG, then the user variables.
    let text = String::from_utf8_lossy(&out.stdout);
    let at = |key: &str| text.find(&format!("\"{key}\":")).unwrap_or(usize::MAX);
    let order = [
        "CPOS", "CSPD", "CACC", "TPOS", "SRL", "PROD", "PRODH", "PREG", "found",
    ];
    assert!(order.windows(2).all(|w| at(w[0]) < at(w[1])), "{text}");

    let fault = scratch_file("fault.tml", "RET;");
    let out = servoscope(&["run", fault.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(1));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["fault"]["kind"], "stack_underflow");
    assert_eq!(j["registers"]["DER"], 2);

    let bad = scratch_file("bad.tml", "int a;\na = ;\nGOTO x;");
    let out = servoscope(&["run", bad.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(j["status"], "not assembled");
    let lines: Vec<&serde_json::Value> = (j["diagnostics"].as_array().expect("a list").iter())
        .map(|d| &d["line"])
        .collect();
    assert_eq!(lines, [2, 3], "{j}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains(":2:") && stderr.contains(":3:"), "{stderr}");

    let endless = scratch_file("loop.tml", "int i;\nloop: i += 1; GOTO loop;");
    let out = servoscope(&[
        "run",
        endless.to_str().unwrap(),
        "--json",
        "--max-ticks",
        "50",
    ]);
    assert_eq!(out.status.code(), Some(3));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["status"], "limit");
    assert_eq!(j["ticks"], 50);
    assert_eq!(
        j["registers"]["i"], 250,
        "ten statements a tick, two per loop"
    );

    let out = servoscope(&["run", endless.to_str().unwrap(), "--input", "IN#16=3"]);
    assert_eq!(out.status.code(), Some(2), "no such input");
    for p in [fault, bad, endless] {
        let _ = std::fs::remove_file(p);
    }
}
