//! Layers import downward only: the debugger (run control, history, replay) never reaches up
//! into the runner, the sessions or the window, so a reader following a run goes runner →
//! debugger → machine once, and the core builds without the window's crates.

use std::path::Path;

#[test]
fn the_debugger_never_calls_up_into_the_runner_the_sessions_or_the_window() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/debugger");
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).expect("src/debugger") {
        let path = entry.expect("a directory entry").path();
        let text = std::fs::read_to_string(&path).expect("a source file");
        for upward in [
            "crate::runner",
            "crate::session",
            "crate::ui",
            "egui::",
            "eframe",
        ] {
            assert!(!text.contains(upward), "{} uses {upward}", path.display());
        }
        files += 1;
    }
    assert!(files >= 5, "read the debugger's sources ({files} files)");
}
