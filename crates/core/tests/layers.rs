//! Layers import downward only: machine ← debugger ← registry ← session, runner, lesson. A reader
//! following a run goes runner → debugger → machine once, the core builds without the window's
//! crates, and no file below the registry names a dialect outside the dialect's own folder, so a
//! new dialect is its folder and a line in the registry's list.

use std::path::{Path, PathBuf};

const LAYERS_ABOVE_THE_DEBUGGER: [&str; 5] = [
    "crate::registry",
    "crate::session",
    "crate::runner",
    "crate::lesson",
    "crate::output",
];
const WINDOW: [&str; 5] = ["egui", "eframe", "rfd", "winit", "servoscope::ui"];
const DIALECTS: [&str; 4] = ["silverlode", "tml", "opennet", "dl205"];

fn source_dir(sub: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src").join(sub)
}

/// Every `.rs` file under `dir` (or `dir` itself when it is a file), with its text.
fn sources(path: &Path) -> Vec<(PathBuf, String)> {
    if path.is_file() {
        let text = std::fs::read_to_string(path).expect("a source file");
        return vec![(path.to_path_buf(), text)];
    }
    let mut files = Vec::new();
    for entry in std::fs::read_dir(path).expect("a source folder") {
        files.extend(sources(&entry.expect("a directory entry").path()));
    }
    files.retain(|(p, _)| p.extension().is_some_and(|e| e == "rs"));
    files
}

/// The places where `text` names one of `paths` as a path (`crate::session::…`,
/// `use crate::session;`), not as part of a longer name.
fn names(text: &str, paths: &[&str]) -> Vec<String> {
    let mut found = Vec::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        for path in paths {
            let mut rest = code;
            while let Some(at) = rest.find(path) {
                let after = rest[at + path.len()..].chars().next();
                let before = rest[..at].chars().next_back();
                if !after.is_some_and(|c| c.is_alphanumeric() || c == '_')
                    && !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
                {
                    found.push(format!("{path} in `{}`", line.trim()));
                }
                rest = &rest[at + path.len()..];
            }
        }
    }
    found
}

fn assert_none(files: &[(PathBuf, String)], paths: &[&str]) {
    assert!(!files.is_empty(), "no sources read");
    for (path, text) in files {
        let found = names(text, paths);
        assert!(found.is_empty(), "{}: {found:#?}", path.display());
    }
}

#[test]
fn the_machines_never_name_the_layers_above_or_the_window() {
    let mut above = vec!["crate::debugger"];
    above.extend(LAYERS_ABOVE_THE_DEBUGGER);
    above.extend(WINDOW);
    assert_none(&sources(&source_dir("machine")), &above);
}

#[test]
fn the_debugger_never_names_the_registry_the_sessions_the_runner_or_the_window() {
    let mut above = LAYERS_ABOVE_THE_DEBUGGER.to_vec();
    above.extend(WINDOW);
    assert_none(&sources(&source_dir("debugger")), &above);
}

#[test]
fn the_registry_names_no_layer_above_it() {
    let mut above = LAYERS_ABOVE_THE_DEBUGGER[1..].to_vec();
    above.extend(WINDOW);
    assert_none(&sources(&source_dir("registry.rs")), &above);
}

#[test]
fn nothing_in_the_core_uses_the_window() {
    assert_none(&sources(&source_dir("")), &WINDOW);
}

#[test]
fn no_file_names_a_dialect_module_outside_its_folder_and_the_registry() {
    let dialect_paths: Vec<String> = DIALECTS.iter().map(|d| format!("machine::{d}")).collect();
    let dialect_paths: Vec<&str> = dialect_paths.iter().map(String::as_str).collect();
    let mut checked = 0;
    for (path, text) in sources(&source_dir("")) {
        let own = DIALECTS
            .iter()
            .find(|d| path.starts_with(source_dir("machine").join(d)));
        if path == source_dir("registry.rs") {
            continue;
        }
        // A dialect's folder may name its own module, never another's.
        let others: Vec<&str> = dialect_paths
            .iter()
            .copied()
            .filter(|p| own.is_none_or(|d| !p.ends_with(d)))
            .collect();
        let found = names(&text, &others);
        assert!(found.is_empty(), "{}: {found:#?}", path.display());
        checked += 1;
    }
    assert!(checked > 40, "read the core's sources ({checked} files)");
}

#[test]
fn the_check_finds_what_it_looks_for() {
    let upward = "use crate::session::Session;\nlet x = crate::sessions_of();\n// crate::runner\n";
    assert_eq!(names(upward, &["crate::session"]).len(), 1);
    assert_eq!(
        names(upward, &["crate::runner"]).len(),
        0,
        "comments do not count"
    );
    assert_eq!(names("egui::Ui", &WINDOW).len(), 1);
    assert_eq!(names("my_egui_like", &WINDOW).len(), 0);
}
