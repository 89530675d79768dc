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
