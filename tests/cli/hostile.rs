//! The command line: hostile files and arguments given to the binary.
use crate::common;
use common::servoscope;
use servoscope_core::machine::RunState;
use servoscope_core::session::Session;

#[test]
fn the_runner_refuses_a_break_condition_in_another_script() {
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/examples/call_ret.qsl");
    let out = servoscope(&["run", example, "--break", "é", "--json"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("column 1"), "{err}");
}

#[test]
fn the_runners_session_of_a_fault_reopens_faulted() {
    let dir = std::env::temp_dir().join(format!("servoscope-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temp dir");
    let program = dir.join("fault.qsl");
    std::fs::write(&program, "DLY 23\nCLD Q_PUSH_HEAD, 20, 40, 1\nEND\n").expect("written");
    let session = dir.join("fault.ron");
    let out = servoscope(&[
        "run",
        program.to_str().expect("utf-8"),
        "--save-session",
        session.to_str().expect("utf-8"),
    ]);
    assert!(session.exists(), "{}", String::from_utf8_lossy(&out.stderr));
    let d = Session::load(&session)
        .and_then(|s| s.restore("fault.ron"))
        .expect("restores");
    assert_eq!(d.machine().run_state(), RunState::Faulted);
    assert_eq!(d.machine().pos().tick, 23);
    let _ = std::fs::remove_dir_all(&dir);
}

// ---- 6. leftovers ----------------------------------------------------------------------------

#[test]
fn the_runner_refuses_a_device_or_a_huge_file_with_a_message() {
    let out = servoscope(&["run", "/dev/zero", "--dialect", "silverlode"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not a regular file"), "{err}");
}

/// A scratch folder of this test process's own.
fn folder(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("servoscope-out-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temp dir");
    dir
}

fn text(path: &std::path::Path) -> String {
    std::fs::read_to_string(path).expect("readable")
}

#[test]
fn no_output_replaces_the_program_or_a_file_that_is_not_its_kind() {
    let dir = folder("outputs");
    let program = dir.join("prog.dl205");
    let source = "STR X0\nOUT Y0\nEND\n";
    std::fs::write(&program, source).expect("written");
    let notes = dir.join("notes.txt");
    std::fs::write(&notes, "my notes\n").expect("written");
    let p = program.to_str().expect("utf-8");
    let n = notes.to_str().expect("utf-8");
    let s = |path: &std::path::Path| path.to_str().expect("utf-8").to_string();
    // The program itself, as --svg, --trace or --save-session, even with --overwrite.
    for args in [
        vec!["ladder", p, "--svg", p],
        vec!["ladder", p, "--svg", p, "--overwrite"],
        vec!["run", p, "--trace", p, "--overwrite"],
        vec!["run", p, "--save-session", p, "--overwrite"],
    ] {
        let out = servoscope(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("never writes over a file it read"),
            "{args:?}: {err}"
        );
        assert_eq!(text(&program), source, "{args:?}: the program stays");
    }
    // Another file: only with --overwrite.
    for args in [vec!["ladder", p, "--svg", n], vec!["run", p, "--trace", n]] {
        let out = servoscope(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("pass --overwrite"), "{err}");
        assert_eq!(text(&notes), "my notes\n");
    }
    let out = servoscope(&["run", p, "--trace", n, "--overwrite"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text(&notes).starts_with("{\"n\":1"),
        "replaced by the trace"
    );
    // Its own earlier output is replaced without asking.
    let svg = dir.join("prog.svg");
    for _ in 0..2 {
        let out = servoscope(&["ladder", p, "--svg", &s(&svg)]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let trace = dir.join("t.jsonl");
    for _ in 0..2 {
        let out = servoscope(&["run", p, "--trace", &s(&trace)]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // A stream (a device, a pipe) is written as the run goes, and stays what it is.
    let out = servoscope(&["run", p, "--trace", "/dev/null"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!std::fs::metadata("/dev/null").expect("exists").is_file());
    // Through a link in the folder to a file outside it: the file is what counts; a link to
    // nothing is refused (the write would create a file wherever it points).
    #[cfg(unix)]
    {
        let nowhere = dir.join("nowhere.svg");
        std::os::unix::fs::symlink(dir.join("missing/elsewhere.svg"), &nowhere).expect("a link");
        let out = servoscope(&["ladder", p, "--svg", &s(&nowhere), "--overwrite"]);
        assert_eq!(out.status.code(), Some(2));
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("link to a file that does not exist")
        );
        let outside = folder("outputs-outside").join("keep.txt");
        std::fs::write(&outside, "keep me\n").expect("written");
        let link = dir.join("out.svg");
        std::os::unix::fs::symlink(&outside, &link).expect("a link");
        let out = servoscope(&["ladder", p, "--svg", &s(&link)]);
        assert_eq!(out.status.code(), Some(2));
        assert_eq!(text(&outside), "keep me\n");
        let to_program = dir.join("prog-link.svg");
        std::os::unix::fs::symlink(&program, &to_program).expect("a link");
        let out = servoscope(&["ladder", p, "--svg", &s(&to_program), "--overwrite"]);
        assert_eq!(out.status.code(), Some(2));
        assert_eq!(text(&program), source);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn help_and_version_with_json_print_one_json_object() {
    for args in [
        vec!["run", "--help", "--json"],
        vec!["check", "-h", "--json"],
        vec!["-V", "--json"],
        vec!["--version", "--json"],
    ] {
        let out = servoscope(&args);
        assert!(out.status.success(), "{args:?}");
        let value: serde_json::Value = serde_json::from_slice(&out.stdout)
            .unwrap_or_else(|e| panic!("{args:?}: one JSON object: {e}"));
        assert!(
            value["help"].as_str().is_some_and(|h| h.contains("Usage"))
                || value["version"] == env!("CARGO_PKG_VERSION"),
            "{args:?}: {value}"
        );
    }
    // Without --json, clap's own text.
    let out = servoscope(&["run", "--help"]);
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("Run a program headless"));
}

#[test]
fn check_has_a_time_budget_and_a_lessons_tick_limit_is_bounded() {
    let dir = folder("budget");
    // A lesson asking for u64::MAX scans of a 2,001-instruction program, graded with a budget
    // of 0.3 s: it is bounded to 10,000,000 scans and stops in time.
    let lesson = dir.join("forever.ron");
    let program = "STR X0\\nOUT Y0\\n".repeat(1_000) + "END";
    std::fs::write(
        &lesson,
        format!(
            "(format: 2, dialect: \"dl205\", program: \"{program}\", \
             lesson: Some((title: \"Forever\", steps: [(text: \"s\", checks: [\"Y0 == 0\"])], max_ticks: Some(18446744073709551615))))"
        ),
    )
    .expect("written");
    let l = lesson.to_str().expect("utf-8");
    let started = std::time::Instant::now();
    let out = servoscope(&["check", l, "--json", "--timeout", "0.3"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.contains("graded over 10000000"),
        "the bound is said: {err}"
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one object");
    assert_eq!(report["run"]["status"], "timed out", "{report}");
    let check = &report["checks"][0];
    assert_eq!(check["pass"], false);
    assert!(
        check["error"]
            .as_str()
            .is_some_and(|e| e.contains("time budget")),
        "{check}"
    );
    // A budget, not a speed: the run stopped long before its 10,000,000 ticks would end.
    assert!(started.elapsed() < std::time::Duration::from_secs(60));
    // A budget that is no number of seconds, and a tick limit past the bound, are refused.
    for args in [
        vec!["check", l, "--timeout", "0"],
        vec!["check", l, "--timeout", "-1"],
        vec!["check", l, "--timeout", "NaN"],
        vec!["check", l, "--max-ticks", "1000000000"],
    ] {
        let out = servoscope(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn include_dir_lets_the_runner_read_a_shared_folder() {
    let root = folder("include-dir");
    let shared = root.join("shared");
    std::fs::create_dir_all(&shared).expect("a folder");
    std::fs::write(shared.join("setup.tml"), "int a;\n").expect("written");
    let project = root.join("axis");
    std::fs::create_dir_all(&project).expect("a folder");
    let top = project.join("main.tml");
    std::fs::write(&top, "#include \"../shared/setup.tml\"\na = 5;\nEND;\n").expect("written");
    let t = top.to_str().expect("utf-8");
    let refused = servoscope(&["run", t]);
    assert_eq!(refused.status.code(), Some(2));
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(err.contains("outside the program's folder"), "{err}");
    assert!(err.contains("--include-dir"), "{err}");
    let out = servoscope(&[
        "run",
        t,
        "--include-dir",
        shared.to_str().expect("utf-8"),
        "--json",
    ]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one object");
    assert_eq!(report["status"], "ended", "{report}");
    let _ = std::fs::remove_dir_all(&root);
}
