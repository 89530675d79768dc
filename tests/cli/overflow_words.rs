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

/// The rows of a `--trace` of `program` (written as `name`), run for `ticks` ticks.
fn trace_rows(name: &str, program: &str, ticks: &str) -> Vec<serde_json::Value> {
    let program_file = common::scratch_file(name, program);
    let trace = common::scratch_file(&format!("{name}.jsonl"), "");
    let out = common::servoscope(&[
        "run",
        program_file.to_str().expect("a path"),
        "--json",
        "--max-ticks",
        ticks,
        "--trace",
        trace.to_str().expect("a path"),
    ]);
    assert!(out.status.code().is_some_and(|c| c <= 1), "{out:?}");
    let text = std::fs::read_to_string(&trace).expect("written");
    let _ = std::fs::remove_file(trace);
    let _ = std::fs::remove_file(program_file);
    text.lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object a line"))
        .collect()
}

/// #43 item 8: `written` names the flags an instruction sets even when it fails or is
/// ignored, each TML statement of a line is named by its own mnemonic, and values are in the
/// location's reading (a DL205 V word's BCD digits).
#[test]
fn the_trace_names_flag_writes_and_each_statements_mnemonic() {
    // A flag-variant pop of an empty queue fails: nothing changes but ISW's NEGATIVE flag.
    let rows = trace_rows(
        "empty_pop.qsl",
        "CLD Q_INIT, 20, 40, 3\nCLD Q_POP_TAIL, 21, 40, 0\nEND\n",
        "100",
    );
    let pop = rows.iter().find(|r| r["line"] == 2).expect("line 2 ran");
    let written = pop["written"].as_object().expect("an object");
    assert_eq!(written.keys().collect::<Vec<_>>(), ["ISW"], "{pop}");

    // Two statements on one line; UPD without MODE PP or a speed is ignored and sets MER/DER.
    let rows = trace_rows("two_on_a_line.tml", "int a;\na = 5; UPD;\nEND;\n", "100");
    let on_line_2: Vec<&serde_json::Value> = rows.iter().filter(|r| r["line"] == 2).collect();
    let words: Vec<&str> = on_line_2
        .iter()
        .map(|r| r["mnemonic"].as_str().expect("text"))
        .collect();
    assert_eq!(words, ["a", "UPD"]);
    let upd = on_line_2[1];
    let written = upd["written"].as_object().expect("an object");
    assert!(
        written.contains_key("MER") && written.contains_key("DER"),
        "{upd}"
    );
    let explain = upd["explain"].as_str().expect("text");
    assert!(
        explain.contains("no MODE PP") && explain.contains("CSPD is 0, not positive"),
        "{explain}"
    );

    // BCD: K0039 stored in V2000 is traced as 39, as the register view shows it.
    let rows = trace_rows("bcd.dl205", "STR SP1\nLD K39\nOUT V2000\nEND\n", "1");
    let out = rows.iter().find(|r| r["line"] == 3).expect("line 3 ran");
    assert_eq!(out["written"]["V2000"], 39, "{out}");
}
