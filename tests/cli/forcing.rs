//! `servoscope run --force`: bits forced from a scan on, in the runner's JSON.

const DL: &str = "STR X0\nOUT Y0\nSTR Y0\nOUT Y1\nEND\n";

fn servoscope(args: &[&str]) -> std::process::Output {
    crate::common::command().args(args).output().expect("runs")
}

#[test]
fn the_runner_forces_bits_from_a_scan_on() {
    let dir = std::env::temp_dir().join(format!("servoscope_force_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("p.dl205");
    std::fs::write(&file, DL).expect("written");
    let path = file.to_str().expect("utf-8");
    let run = servoscope(&[
        "run",
        path,
        "--max-ticks",
        "5",
        "--force",
        "Y0=1@3",
        "--json",
    ]);
    assert_eq!(
        run.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json = String::from_utf8_lossy(&run.stdout);
    assert!(
        json.contains("\"Y0\":1") && json.contains("\"Y1\":1"),
        "{json}"
    );
    // Forced off from the start: X0 pressed in scan 1 never reaches the program.
    let run = servoscope(&[
        "run",
        path,
        "--max-ticks",
        "5",
        "--input",
        "X0=1",
        "--force",
        "X0=0",
        "--json",
    ]);
    let json = String::from_utf8_lossy(&run.stdout);
    assert!(!json.contains("\"Y0\":1"), "{json}");
    // Bad specs: exit 2 and a message naming the problem.
    for (spec, says) in [
        ("Y0=2", "expected NAME=1|0"),
        ("Y0=1@soon", "expected NAME=1|0"),
        ("T0=1", "cannot be forced"),
        ("Q9=1", "no location"),
    ] {
        let run = servoscope(&["run", path, "--force", spec]);
        assert_eq!(run.status.code(), Some(2), "{spec}");
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(err.contains(says), "{spec}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
