//! The headless runner through the built binary: spec §8's flags, JSON shape and exit codes.

use std::process::Output;

use serde_json::Value;

fn program_file(text: &str) -> tempfile_lite::TempFile {
    tempfile_lite::TempFile::with(text)
}

fn servoscope(args: &[&str]) -> Output {
    crate::common::command()
        .args(args)
        .output()
        .expect("run servoscope")
}

fn json(out: &Output) -> Value {
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.lines().count(), 1, "exactly one line of JSON: {text}");
    serde_json::from_str(&text).expect("valid JSON")
}

/// A temporary file removed on drop (std only, so the tests need no extra crate).
mod tempfile_lite {
    use std::path::PathBuf;
    use std::sync::atomic::{AtomicUsize, Ordering};

    static COUNTER: AtomicUsize = AtomicUsize::new(0);

    pub struct TempFile(pub PathBuf);

    impl TempFile {
        pub fn with(text: &str) -> TempFile {
            let n = COUNTER.fetch_add(1, Ordering::SeqCst);
            let path =
                std::env::temp_dir().join(format!("servoscope-cli-{}-{n}.qsl", std::process::id()));
            std::fs::write(&path, text).expect("write temp program");
            TempFile(path)
        }
        pub fn path(&self) -> &str {
            self.0.to_str().expect("utf-8 temp path")
        }
    }

    impl Drop for TempFile {
        fn drop(&mut self) {
            let _ = std::fs::remove_file(&self.0);
        }
    }
}

#[test]
fn json_shape_of_an_ended_run() {
    let f = program_file(
        "CLD Q_INIT, 10, 27, 3\nCLD Q_PUSH_HEAD, 10, 27, 10\nCLD Q_PUSH_HEAD, 10, 27, 20\nCLD Q_PUSH_HEAD, 10, 27, 30\nCLD Q_POP_TAIL, 33, 27, 0\nWRP 50, -7\nEND\n",
    );
    let out = servoscope(&["run", f.path(), "--json"]);
    assert_eq!(out.status.code(), Some(0));
    let v = json(&out);
    assert_eq!(v["dialect"], "silverlode");
    assert_eq!(v["status"], "ended");
    assert_eq!(v["ticks"], 7);
    assert_eq!(v["steps"], 7);
    assert!(v["fault"].is_null());
    let regs = v["registers"].as_object().expect("registers object");
    assert_eq!(regs.len(), 200);
    assert!((0..200).all(|i| regs.contains_key(&i.to_string())));
    assert_eq!(regs["50"], -7, "signed decimal");
    assert_eq!(regs["33"], 10);
    assert_eq!(v["isw"], 0x82, "driver enabled + zero flag (queue success)");
    assert_eq!(v["psw"], 1 << 13);
    let q = &v["queues"][0];
    assert_eq!(
        (q["base"].as_u64(), q["size"].as_u64(), q["len"].as_u64()),
        (Some(27), Some(3), Some(2))
    );
    assert_eq!((q["head"].as_u64(), q["tail"].as_u64()), (Some(0), Some(1)));
    assert_eq!(
        q["items"],
        serde_json::json!([20, 30]),
        "oldest (tail) first"
    );
    let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "dialect",
            "fault",
            "isw",
            "psw",
            "queues",
            "registers",
            "status",
            "steps",
            "ticks"
        ]
    );
}

#[test]
fn a_fault_exits_1_with_kind_message_and_line() {
    let f = program_file("WRP 10, 5\n\nCLC DIV, 11\nEND\n");
    let out = servoscope(&["run", f.path(), "--json"]);
    assert_eq!(out.status.code(), Some(1));
    let v = json(&out);
    assert_eq!(v["status"], "faulted");
    assert_eq!(v["fault"]["kind"], "divide_by_zero");
    assert_eq!(v["fault"]["line"], 3);
    assert!(
        v["fault"]["message"]
            .as_str()
            .is_some_and(|m| !m.is_empty())
    );
    assert_eq!(v["registers"]["10"], 5);
    assert_eq!(v["ticks"], 1);
}

#[test]
fn assembly_errors_exit_2_with_every_diagnostic_on_stderr() {
    let f = program_file("CLK ADD, 1\nWRP 11, 1\nJMP nowhere\n");
    let out = servoscope(&["run", f.path()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        out.stdout.is_empty(),
        "no report of a run that did not happen"
    );
    let out = servoscope(&["run", f.path(), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    // `--json` promises one object: a script records that the program did not assemble.
    let j = json(&out);
    assert_eq!(j["dialect"], "silverlode");
    assert_eq!(j["status"], "not assembled");
    let diagnostics = j["diagnostics"].as_array().expect("a list");
    assert_eq!(diagnostics.len(), 2, "{j}");
    assert_eq!(diagnostics[0]["file"], f.path());
    assert_eq!(
        (&diagnostics[0]["line"], &diagnostics[0]["column"]),
        (&Value::from(1), &Value::from(1))
    );
    assert_eq!(diagnostics[0]["severity"], "error");
    let first = diagnostics[0]["message"].as_str().expect("a message");
    assert!(first.starts_with("unknown command 'CLK'"), "{first}");
    assert_eq!(
        (&diagnostics[1]["line"], &diagnostics[1]["column"]),
        (&Value::from(3), &Value::from(5))
    );
    assert_eq!(diagnostics[1]["message"], "undefined label 'nowhere'");
    assert!(j.get("ticks").is_none(), "nothing ran: {j}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("{}:1:1: error: unknown command 'CLK'", f.path())),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "{}:3:5: error: undefined label 'nowhere'",
            f.path()
        )),
        "{err}"
    );
}

#[test]
fn bad_arguments_and_missing_files_exit_2() {
    let f = program_file("END\n");
    for args in [
        vec!["run", f.path(), "--bogus"],
        vec!["run", f.path(), "--max-ticks", "many"],
        vec!["run", f.path(), "--input", "IO4=5"],
        vec!["run", f.path(), "--input", "IO1=a,b"],
        vec!["run", "/nonexistent/program.qsl", "--json"],
        vec!["run"],
    ] {
        let out = servoscope(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(!out.stderr.is_empty(), "{args:?}");
    }
}

#[test]
fn the_tick_limit_exits_3() {
    let f = program_file("loop: CLC INC, 11\nJMP loop\n");
    let out = servoscope(&["run", f.path(), "--max-ticks", "1000", "--json"]);
    assert_eq!(out.status.code(), Some(3));
    let v = json(&out);
    assert_eq!(v["status"], "limit");
    assert_eq!(v["ticks"], 1000);
    assert_eq!(v["registers"]["11"], 500);
}

#[test]
fn inputs_toggle_at_their_ticks() {
    // Wait for IO1 high, then for it low again; count ticks in between.
    let f = program_file("WBS IO1\nWBS !IO1\nEND\n");
    let out = servoscope(&["run", f.path(), "--input", "IO1=100,250", "--json"]);
    assert_eq!(out.status.code(), Some(0));
    let v = json(&out);
    // Toggles apply when the tick counter equals the tick: IO1 is seen high in tick 101 and
    // low in tick 251; END takes tick 252.
    assert_eq!(v["ticks"], 252);
    let out = servoscope(&[
        "run",
        f.path(),
        "--input",
        "IO1=100",
        "--max-ticks",
        "500",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(3), "IO1 never goes low again");
}

#[test]
fn text_output_without_json() {
    let f = program_file("WRP 11, 42\nEND\n");
    let out = servoscope(&["run", f.path()]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("status: ended"), "{text}");
    assert!(text.contains("R11=42"), "{text}");
}

/// A program file with any extension (the dialect comes from it).
fn file_named(text: &str, name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("servoscope-cli-named-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

#[test]
fn the_dialect_comes_from_the_extension_or_dialect() {
    let txt = file_named("WRP 11, 42\nEND\n", "prog.txt");
    let txt = txt.to_str().expect("utf-8");
    let out = servoscope(&["run", txt, "--json"]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "an unknown extension is refused"
    );
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--dialect"), "says how to choose: {err}");
    assert!(
        err.contains("silverlode (.qsl)"),
        "lists the dialects: {err}"
    );

    let out = servoscope(&["run", txt, "--dialect", "silverlode", "--json"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(json(&out)["registers"]["11"], 42);

    let out = servoscope(&["run", txt, "--dialect", "cobol"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown dialect 'cobol'"));
}

#[test]
fn set_gives_locations_initial_values() {
    let f = program_file("CLD ADD, 12, 26, 1\nEND\n");
    let out = servoscope(&[
        "run",
        f.path(),
        "--set",
        "R26=-5",
        "--set",
        "acc=0x10",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let v = json(&out);
    assert_eq!(v["registers"]["26"], -5);
    assert_eq!(
        v["registers"]["12"], -4,
        "the program saw R26 = -5 from the start"
    );
    assert_eq!(v["registers"]["10"], 16, "by alias, in hex");
    for bad in ["R200=1", "R26", "R26=0x1_0000_0000", "R26=many"] {
        let out = servoscope(&["run", f.path(), "--set", bad]);
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(out.stdout.is_empty(), "{bad}");
    }
}

#[test]
fn set_and_inputs_are_recorded_in_a_saved_session() {
    let f = program_file("WBS IO2\nCLD ADD, 12, 26, 1\nEND\n");
    let saved = std::env::temp_dir().join(format!("servoscope-cli-set-{}.ron", std::process::id()));
    let saved = saved.to_str().expect("utf-8");
    let straight = servoscope(&[
        "run",
        f.path(),
        "--set",
        "R26=41",
        "--input",
        "IO2=7",
        "--json",
    ]);
    assert_eq!(json(&straight)["registers"]["12"], 42);
    let limited = servoscope(&[
        "run",
        f.path(),
        "--set",
        "R26=41",
        "--input",
        "IO2=7",
        "--max-ticks",
        "3",
        "--save-session",
        saved,
    ]);
    assert_eq!(limited.status.code(), Some(3));
    let text = std::fs::read_to_string(saved).expect("saved");
    assert!(text.contains("location: \"R26\""), "{text}");
    assert!(text.contains("location: \"IO2\""), "{text}");
    let resumed = servoscope(&["run", saved, "--json"]);
    assert_eq!(resumed.stdout, straight.stdout, "the session replays both");
    let _ = std::fs::remove_file(saved);
}

#[test]
fn a_failing_stdout_is_reported_not_a_panic() {
    let f = program_file("WRP 11, 1\nEND\n");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full exists on Linux");
    let out = crate::common::command()
        .args(["run", f.path(), "--json"])
        .stdout(full)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.contains("cannot write"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_closed_pipe_ends_quietly() {
    // Long enough that the reader is gone before the report is written.
    let f = program_file("loop: CLC INC, 11\nJMP loop\n");
    let mut child = crate::common::command()
        .args(["run", f.path(), "--max-ticks", "3000000", "--json"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("runs");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("ends");
    assert_ne!(out.status.code(), Some(101), "no panic");
    assert!(out.status.code().is_some(), "no signal either");
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn files_from_other_editors_run_as_written() {
    let want = servoscope(&[
        "run",
        program_file("WRP 11, 1\nWRP 12, 2\nEND\n").path(),
        "--json",
    ]);
    let want = json(&want);
    for text in [
        "WRP 11, 1\rWRP 12, 2\rEND\r",
        "WRP 11, 1\r\nWRP 12, 2\r\nEND\r\n",
        "\u{feff}WRP 11, 1\nWRP 12, 2\nEND\n",
    ] {
        let f = program_file(text);
        let out = servoscope(&["run", f.path(), "--json"]);
        assert_eq!(out.status.code(), Some(0), "{text:?}");
        assert_eq!(json(&out), want, "{text:?}");
    }
    let bad =
        std::env::temp_dir().join(format!("servoscope-cli-latin1-{}.qsl", std::process::id()));
    std::fs::write(&bad, b"WRP 11, 1 ; caf\xe9\nEND\n").expect("write");
    let out = servoscope(&["run", bad.to_str().expect("utf-8"), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("not UTF-8") && err.contains("offset 15"),
        "{err}"
    );
    let _ = std::fs::remove_file(&bad);
}

#[test]
fn messages_never_carry_raw_control_bytes() {
    let f = program_file("\u{1b}[2J\u{7}BOGUS 1\nEND\n");
    let out = servoscope(&["run", f.path()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        !out.stderr.iter().any(|&b| b == 0x1b || b == 0x07),
        "escaped: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("\\u{1b}"));
}

#[test]
fn a_file_of_errors_only_reports_a_bounded_list() {
    // Every line jumps to an undefined label: the worst case for "did you mean".
    let text: String = (0..20_000).map(|i| format!("a{i}: JMP b{i}\n")).collect();
    let f = program_file(&text);
    let out = servoscope(&["run", f.path()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(
        lines.len(),
        102,
        "100 errors, the count of the rest, the summary"
    );
    assert!(lines[100].contains("19900 more"), "{}", lines[100]);
    assert!(lines[101].contains("20000 error(s)"), "{}", lines[101]);
    assert!(lines[0].contains("undefined label 'b0'"), "{}", lines[0]);
}

#[test]
fn saving_a_session_never_destroys_what_is_not_one() {
    let f = program_file("WRP 11, 1\nEND\n");
    let before = std::fs::read(f.path()).expect("the program");
    // Onto the program itself: refused, even with --overwrite, the program intact.
    for overwrite in [None, Some("--overwrite")] {
        let mut args = vec!["run", f.path(), "--save-session", f.path(), "--json"];
        args.extend(overwrite);
        let out = servoscope(&args);
        assert_eq!(out.status.code(), Some(2));
        assert!(out.stdout.is_empty());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("never writes over a file it read"), "{err}");
        assert_eq!(std::fs::read(f.path()).expect("still there"), before);
    }
    // Onto another program: refused without --overwrite.
    let other = program_file("WRP 12, 1\nEND\n");
    let out = servoscope(&["run", f.path(), "--save-session", other.path()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--overwrite"));
    // Onto a device: refused, and the device stays a device.
    let out = servoscope(&["run", f.path(), "--save-session", "/dev/null"]);
    assert_eq!(out.status.code(), Some(2));
    let null = std::fs::metadata("/dev/null").expect("exists");
    assert!(!null.file_type().is_file(), "/dev/null is still a device");
    // With --overwrite the user asked for it.
    let out = servoscope(&[
        "run",
        f.path(),
        "--save-session",
        other.path(),
        "--overwrite",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let text = std::fs::read_to_string(other.path()).expect("replaced");
    assert!(text.contains("format: 2"), "now a session");
}
