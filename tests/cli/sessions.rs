//! The command line: sessions through the runner.
use crate::common;
use common::servoscope;
use common::sessions::{PROGRAM, busy_debugger, sl, temp};
use servoscope_core::debugger::history::CHECKPOINT_EVERY;
use servoscope_core::session::{Session, SessionError, ViewSettings};
use std::path::{Path, PathBuf};

fn program_file(text: &str, name: &str) -> PathBuf {
    let path = temp(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn bad_files_are_refused_and_nothing_is_lost() {
    let good = Session::capture(&busy_debugger(), None, ViewSettings::default())
        .to_ron()
        .unwrap();
    let truncated = &good[..good.len() / 2];
    let cases: Vec<(&str, String)> = vec![
        ("truncated", truncated.to_string()),
        ("garbage", "\u{1}\u{2} not a session".to_string()),
        ("json", "{\"format\": 1}".to_string()),
        ("newer", good.replacen("format: 2", "format: 7", 1)),
        ("foreign", "(name: \"a recipe\", servings: 4)".to_string()),
        ("bad program", good.replacen("CLD Q_INIT", "CLK Q_INIT", 1)),
    ];
    for (what, text) in cases {
        let path = temp(&format!("{}.ron", what.replace(' ', "_")));
        std::fs::write(&path, &text).unwrap();
        let result = Session::load(&path).and_then(|s| s.restore("x"));
        let message = match result {
            Ok(_) => panic!("{what}: accepted"),
            Err(e) => e.to_string(),
        };
        assert!(!message.is_empty(), "{what}");
        if what == "newer" {
            assert!(message.contains("newer servoscope"), "{message}");
        }
        // The runner: exit 2 and a message on stderr; on stdout nothing, or for a program that
        // does not assemble, the one JSON object saying so.
        let out = servoscope(&["run", path.to_str().unwrap(), "--json"]);
        assert_eq!(out.status.code(), Some(2), "{what}");
        if what == "bad program" {
            let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
            assert_eq!(j["status"], "not assembled", "{what}");
        } else {
            assert!(out.stdout.is_empty(), "{what}");
        }
        assert!(!out.stderr.is_empty(), "{what}");
        let _ = std::fs::remove_file(&path);
    }
    let missing = Session::load(Path::new("/nonexistent/s.ron"));
    assert!(matches!(missing, Err(SessionError::Read { .. })));
}

#[test]
fn a_resumed_run_ends_identical_to_a_straight_one() {
    let prog = program_file(PROGRAM, "resume.qsl");
    let prog = prog.to_str().unwrap();
    let straight = servoscope(&["run", prog, "--input", "IO2=1500,1700", "--json"]);
    assert_eq!(straight.status.code(), Some(0));

    let saved = temp("resume.ron");
    let saved = saved.to_str().unwrap();
    let first = servoscope(&[
        "run",
        prog,
        "--input",
        "IO2=1500,1700",
        "--max-ticks",
        "1600",
        "--save-session",
        saved,
        "--json",
    ]);
    assert_eq!(first.status.code(), Some(3), "stopped by the limit");
    let session = Session::load(Path::new(saved)).unwrap();
    assert_eq!(session.at.tick, 1600);
    assert_eq!(
        session.events.len(),
        2,
        "both toggles, the second still to come"
    );

    let resumed = servoscope(&["run", saved, "--json"]);
    assert_eq!(resumed.status.code(), Some(0));
    assert_eq!(
        resumed.stdout, straight.stdout,
        "exactly what the straight run printed"
    );

    // --max-ticks counts from tick 0, as in a straight run.
    let limited = servoscope(&["run", saved, "--max-ticks", "3000", "--json"]);
    let straight_limited = servoscope(&[
        "run",
        prog,
        "--input",
        "IO2=1500,1700",
        "--max-ticks",
        "3000",
        "--json",
    ]);
    assert_eq!(limited.stdout, straight_limited.stdout);
    assert_eq!(limited.status.code(), Some(3));

    // A session cannot take extra inputs.
    let mixed = servoscope(&["run", saved, "--input", "IO1=5"]);
    assert_eq!(mixed.status.code(), Some(2));
}

#[test]
fn a_session_saved_in_the_debugger_resumes_in_the_runner() {
    let d = busy_debugger();
    let path = temp("from_gui.ron");
    Session::capture(&d, None, ViewSettings::default())
        .save(&path)
        .unwrap();
    let out = servoscope(&[
        "run",
        path.to_str().unwrap(),
        "--max-ticks",
        &(CHECKPOINT_EVERY + 123).to_string(),
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["ticks"], CHECKPOINT_EVERY + 123);
    assert_eq!(
        v["registers"]["30"], 0xBEEF,
        "the register edit was replayed"
    );
    assert_eq!(v["registers"]["20"], sl(&d).reg(20));
    assert_eq!(v["registers"]["1"], sl(&d).reg(1));
}
