//! The command line: TML projects of several files through the runner.
use crate::common;
use common::{scratch_dir, servoscope, write};
use std::path::{Path, PathBuf};

const EXAMPLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/examples/easymotion_axis"
);

// ---- the example project through the runner, the debugger, sessions and the window -----------

fn example_top() -> PathBuf {
    Path::new(EXAMPLE).join("motion.tml")
}

#[test]
fn the_runner_names_each_file_as_reached_from_the_command_line() {
    let dir = scratch_dir("diag");
    write(&dir, "motion.tml", "#include \"main.tml\"\n");
    write(&dir, "main.tml", "int a;\na = 1;\n\n\n\n\na = CPOSS;\n");
    let top = dir.join("motion.tml");
    let out = servoscope(&["run", top.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    // The JSON names the included file and the line in it.
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let d = &j["diagnostics"][0];
    assert_eq!(d["file"], dir.join("main.tml").display().to_string(), "{j}");
    assert_eq!((&d["line"], &d["column"]), (&7.into(), &5.into()), "{j}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let want = format!(
        "{}:7:5: error: undeclared variable or undefined label 'CPOSS' (did you mean 'CPOS'?)",
        dir.join("main.tml").display()
    );
    assert!(stderr.contains(&want), "{stderr}");
    // A part run alone: its sibling's labels are undefined, and the error says it may be one.
    let part = Path::new(EXAMPLE).join("main.tml");
    let alone = servoscope(&["run", part.to_str().unwrap()]);
    assert_eq!(alone.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&alone.stderr);
    assert!(
        stderr.contains("error: undeclared variable or undefined label 'Homing1'"),
        "{stderr}"
    );
}

#[test]
fn table_b_data_are_in_the_json_only_when_the_program_names_them() {
    let plain = common::scratch_file("tb-plain.tml", "int a; a = 1; END;\n");
    let out = servoscope(&["run", plain.to_str().unwrap(), "--json"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        !text.contains("POSOKLIM") && !text.contains("TACC"),
        "{text}"
    );
    assert!(
        !text.contains("stack_files"),
        "one file reports as before: {text}"
    );
    let named = common::scratch_file("tb-named.tml", "int a; a = tonposok; posoklim = 3; END;\n");
    let out = servoscope(&["run", named.to_str().unwrap(), "--json"]);
    // In table order, after table A and before PREG (read from the text: a parsed map sorts).
    let text = String::from_utf8_lossy(&out.stdout);
    let at = |k: &str| {
        text.find(&format!("\"{k}\":"))
            .unwrap_or_else(|| panic!("{k}: {text}"))
    };
    assert!(
        at("PRODH") < at("POSOKLIM")
            && at("POSOKLIM") < at("TONPOSOK")
            && at("TONPOSOK") < at("PREG")
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let regs = &v["registers"];
    assert_eq!(regs["POSOKLIM"], 3);
    assert_eq!(regs["TONPOSOK"], 0);
}

#[test]
fn the_example_project_runs_headless_as_the_spec_works_out() {
    let top = example_top();
    let out = servoscope(&["run", top.to_str().unwrap(), "--json"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["ticks"], 7860);
    assert_eq!(v["steps"], 44);
    let r = &v["registers"];
    assert_eq!(r["APOS"], 115343);
    assert_eq!(r["ExecuteMain"], 0x4011);
    assert_eq!(r["ExecuteAutotuning"], 0x4009);
    assert_eq!(r["HOMINGTABLE_POINTER"], 0x402F);
    assert_eq!(r["HomingStopPos"], -20000);
    assert_eq!(r["POSOKLIM"], 2);
    assert_eq!(v["stack_files"], serde_json::json!([]));
    let found = servoscope(&[
        "run",
        top.to_str().unwrap(),
        "--json",
        "--input",
        "IN#0=600",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&found.stdout).expect("json");
    assert_eq!(v["ticks"], 6459);
    assert_eq!(v["registers"]["HomingStopPos"], -5990);
    // Stopped in the homing subroutine: its CALL is in main.tml.
    let early = servoscope(&["run", top.to_str().unwrap(), "--json", "--max-ticks", "2"]);
    let v: serde_json::Value = serde_json::from_slice(&early.stdout).expect("json");
    assert_eq!(v["status"], "limit");
    assert_eq!(v["stack"], serde_json::json!([12]));
    assert_eq!(v["stack_files"], serde_json::json!(["main.tml"]));
}

#[test]
fn faults_breaks_and_traces_name_their_file() {
    let dir = scratch_dir("fault");
    write(
        &dir,
        "motion.tml",
        "int p;\n#include \"sub.tml\"\nCALL f;\nEND;\n",
    );
    write(
        &dir,
        "sub.tml",
        "GOTO skip;\nf: p = 0x4001;\nCALL p;\nskip:\n",
    );
    let top = dir.join("motion.tml");
    let out = servoscope(&["run", top.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["fault"]["kind"], "bad_address");
    assert_eq!(v["fault"]["line"], 3);
    assert_eq!(v["fault"]["file"], "sub.tml");
    assert_eq!(v["stack"], serde_json::json!([3]));
    assert_eq!(v["stack_files"], serde_json::json!(["motion.tml"]));
    let trace = dir.join("trace.jsonl");
    let out = servoscope(&[
        "run",
        top.to_str().unwrap(),
        "--json",
        "--trace",
        trace.to_str().unwrap(),
        "--break",
        "p == 0x4001",
    ]);
    assert_eq!(out.status.code(), Some(4));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["break"]["line"], 3);
    assert_eq!(v["break"]["file"], "sub.tml");
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(&trace)
        .expect("trace")
        .lines()
        .map(|l| serde_json::from_str(l).expect("json line"))
        .collect();
    let files: Vec<(&str, u64)> = lines
        .iter()
        .map(|l| {
            (
                l["file"].as_str().unwrap_or(""),
                l["line"].as_u64().unwrap_or(0),
            )
        })
        .collect();
    assert_eq!(files, [("sub.tml", 1), ("motion.tml", 3), ("sub.tml", 2)]);
}

#[test]
fn the_runner_saves_and_reruns_a_session_of_a_project() {
    let dir = scratch_dir("runner-session");
    let session = dir.join("end.ron");
    let top = example_top();
    let out = servoscope(&[
        "run",
        top.to_str().unwrap(),
        "--json",
        "--save-session",
        session.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    let first: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let text = std::fs::read_to_string(&session).expect("saved");
    assert!(text.contains("format: 3"), "{text}");
    let again = servoscope(&["run", session.to_str().unwrap(), "--json"]);
    assert_eq!(
        again.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    let second: serde_json::Value = serde_json::from_slice(&again.stdout).expect("json");
    assert_eq!(first, second, "the session holds every file");
}
