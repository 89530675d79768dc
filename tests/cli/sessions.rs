//! The command line: sessions through the runner.
use crate::common;
use common::servoscope;
use servoscope_core::debugger::history::CHECKPOINT_EVERY;
use servoscope_core::debugger::{Debugger, Speed};
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::view::{ISW, io, reg};
use servoscope_core::session::{Session, SessionError, ViewSettings};
use std::path::{Path, PathBuf};
use std::time::Duration;

fn sl(d: &Debugger) -> &SilverLode {
    d.machine_as::<SilverLode>().expect("a SilverLode machine")
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("servoscope-sessions-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const PROGRAM: &str = "\
        CLD Q_INIT, 10, 40, 3
loop:   CLD Q_PUSH_HEAD, 11, 40, 5
        CLD Q_POP_TAIL, 12, 40, 0
        MRV 300, 386500, 80530640, IO2
        CLC INC, 20
        DLY 500
        CLD SUB, 21, 20, 40
        JMP loop, !ZERO
        END
";

fn busy_debugger() -> Debugger {
    let mut d = Debugger::new("prog.qsl", PROGRAM);
    d.set_speed(Speed::Unlimited);
    d.toggle_breakpoint(5);
    let drive = |d: &mut Debugger, tick: u64| {
        d.goto_tick(tick);
        while d.advance(0.016, Duration::from_secs(5)) {}
    };
    drive(&mut d, 2_000);
    d.set_input(io(1), true).expect("an input");
    drive(&mut d, 2_500);
    d.set_input(io(1), false).expect("an input");
    d.set_value(reg(30), 0xBEEF).expect("a register edit");
    d.set_bit(ISW, 12, true).expect("an ISW bit");
    drive(&mut d, CHECKPOINT_EVERY + 4_000);
    d.run();
    while d.advance(0.016, Duration::from_secs(5)) {}
    assert_eq!(
        d.event().map(|e| e.describe("tick")),
        Some("Breakpoint hit at line 5".to_string())
    );
    d.goto_tick(CHECKPOINT_EVERY + 123);
    d
}

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
        // The runner: exit 2, a message on stderr, nothing on stdout.
        let out = servoscope(&["run", path.to_str().unwrap(), "--json"]);
        assert_eq!(out.status.code(), Some(2), "{what}");
        assert!(out.stdout.is_empty(), "{what}");
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
