//! The command line: the runner's --break.
use crate::common;

const LOOP: &str = common::ROUNDS;

#[test]
fn the_runner_traces_every_step() {
    let program = common::scratch_file("trace.qsl", LOOP);
    let trace = common::scratch_file("trace.jsonl", "");
    let out = common::servoscope(&[
        "run",
        program.to_str().expect("a path"),
        "--json",
        "--trace",
        trace.to_str().expect("a path"),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = std::fs::read_to_string(&trace).expect("the trace was written");
    let rows: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("each line one JSON object"))
        .collect();
    // 2 set-up commands, 10 rounds of 4, WRP 13 and END.
    assert_eq!(rows.len(), 2 + 40 + 2);
    assert_eq!(rows[0]["n"], 1);
    assert_eq!(rows[0]["line"], 1);
    assert_eq!(rows[0]["mnemonic"], "WRP");
    assert_eq!(rows[0]["written"]["R13"], 5);
    assert_eq!(rows[2]["mnemonic"], "CLC", "the label is not the mnemonic");
    assert_eq!(rows[2]["written"]["R12"], 1);
    assert_eq!(rows[2]["tick"], 2, "where the instruction started");
    assert_eq!(rows.last().expect("rows")["mnemonic"], "END");
    let _ = std::fs::remove_file(trace);
    let _ = std::fs::remove_file(program);
}

#[test]
fn the_runner_stops_at_a_break_expression() {
    let program = common::scratch_file("break.qsl", LOOP);
    let path = program.to_str().expect("a path");
    let out = common::servoscope(&["run", path, "--json", "--break", "R12 == 3 && R11 == 7"]);
    assert_eq!(out.status.code(), Some(4), "{out:?}");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(report["status"], "break");
    assert_eq!(report["break"]["expr"], "R12 == 3 && R11 == 7");
    assert_eq!(
        report["break"]["line"], 6,
        "line 5 just took R11 to 7: the JMP is next"
    );
    assert_eq!(report["registers"]["12"], 3);
    // Never true: the run ends as usual.
    let out = common::servoscope(&["run", path, "--json", "--break", "R12 > 100"]);
    assert_eq!(out.status.code(), Some(0));
    // A malformed expression is an argument error, with its column.
    let out = common::servoscope(&["run", path, "--break", "R12 >"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("column 6"), "{err}");
    let _ = std::fs::remove_file(program);
}
