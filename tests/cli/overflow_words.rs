//! The command line: the runner's report of SilverLode's overflow words.
use crate::common;

/// Item 8: the runner's trace carries the explanation, and a DL205 scan's first LD writes ACC
/// only (it was traced as writing L1–L8 = 0).
#[test]
fn the_trace_carries_the_words_and_exact_writes() {
    let program = common::scratch_file(
        "carry.dl205",
        "STR SP1\nLD K1\nOUT V2010\nLD K9999\nADD V2010\nOUT V2000\nEND\n",
    );
    let trace = common::scratch_file("carry.jsonl", "");
    let out = common::servoscope(&[
        "run",
        program.to_str().expect("a path"),
        "--json",
        "--max-ticks",
        "1",
        "--trace",
        trace.to_str().expect("a path"),
    ]);
    assert!(out.status.success(), "{out:?}");
    let text = std::fs::read_to_string(&trace).expect("written");
    let rows: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object a line"))
        .collect();
    let first_ld = rows.iter().find(|r| r["line"] == 2).expect("line 2 ran");
    let written = first_ld["written"].as_object().expect("an object");
    assert_eq!(written.keys().collect::<Vec<_>>(), ["ACC"], "{first_ld}");
    assert_eq!(first_ld["explain"], "LD K1: ACC = 00000001");
    let add = rows.iter().find(|r| r["line"] == 5).expect("line 5 ran");
    assert_eq!(add["written"]["SP66"], 1, "{add}");
    assert!(
        add["explain"].as_str().expect("text").contains("SP66 = 1"),
        "{add}"
    );
    let _ = std::fs::remove_file(trace);
    let _ = std::fs::remove_file(program);
}
