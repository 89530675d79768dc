//! Every registered dialect, through every layer: its examples assemble and run, its lesson
//! sessions load, a session saved from it loads back into the same moment, the runner picks it
//! by extension, and the window opens it. A dialect is covered the moment it is registered.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use servoscope_core::debugger::{Debugger, Speed};
use servoscope_core::machine::{MachineView, all_locations};
use servoscope_core::registry::{self, DIALECTS, Dialect};
use servoscope_core::session::{Session, ViewSettings};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("servoscope-dialects-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// Run a debugger unlimited for a while (examples may run forever, like a PLC's scans).
fn run_some(d: &mut Debugger) {
    d.set_speed(Speed::Unlimited);
    d.run();
    for _ in 0..3 {
        if !d.advance(0.016, Duration::from_millis(20)) {
            break;
        }
    }
    d.pause();
}

/// Every location's value: two machines in the same state read the same everywhere.
fn snapshot(m: &dyn MachineView) -> Vec<u64> {
    all_locations(m).into_iter().map(|l| m.read(l)).collect()
}

#[test]
fn every_dialect_describes_itself_fully() {
    assert!(!DIALECTS.is_empty());
    for d in DIALECTS {
        assert!(!d.extensions.is_empty(), "{}", d.name);
        for ext in d.extensions {
            let path = PathBuf::from(format!("prog.{ext}"));
            assert_eq!(registry::by_path(&path), Some(*d), "{ext}");
        }
        assert_eq!(registry::by_name(d.name), Some(*d));
        assert!(!d.examples.is_empty(), "{} ships examples", d.name);
        let settings = d.default_settings();
        // The debugger stands on an empty program before anything assembles.
        assert!(
            d.open_text(d.empty_program, &settings).is_ok(),
            "{}: its empty program assembles",
            d.name
        );
        assert_eq!(settings.len(), d.settings.len(), "{}", d.name);
        let new = d.open_text(d.new_program, &settings);
        assert!(new.is_ok(), "{}: File → New's text assembles", d.name);
        let engine = new.unwrap_or_else(|_| unreachable!());
        let m = engine.machine();
        assert_eq!(m.dialect(), d.name);
        for c in d.default_channels {
            assert!(
                m.find(c.location).is_some(),
                "{}: default channel {} exists",
                d.name,
                c.location
            );
        }
        // Every location has a name that finds it again.
        for loc in all_locations(m) {
            let info = m.info(loc).expect("listed locations exist");
            assert!((1..=64).contains(&info.width), "{}", info.name);
            assert_eq!(m.find(&info.name), Some(loc), "{}", info.name);
        }
    }
}

fn check_examples(d: &'static Dialect) {
    for &(name, text) in d.examples {
        let mut debugger = Debugger::with_dialect(d, name, text);
        assert!(
            debugger.diagnostics().is_empty(),
            "{name}: {:?}",
            debugger.diagnostics()
        );
        run_some(&mut debugger);
        assert!(
            debugger.pos() > servoscope_core::machine::Pos::default(),
            "{name} ran"
        );
        // Save the moment, load it back: the same machine, history and breakpoints.
        debugger.toggle_breakpoint(1);
        let path = temp(&format!("{name}.ron"));
        let session = Session::capture(&debugger, None, ViewSettings::default());
        session.save(&path).expect("saves");
        let loaded = Session::load(&path).expect("loads");
        assert_eq!(loaded, session, "{name}");
        let restored = loaded.restore(name).expect("restores");
        assert_eq!(restored.dialect(), d);
        assert_eq!(restored.pos(), debugger.pos(), "{name}");
        assert_eq!(restored.furthest(), debugger.furthest(), "{name}");
        assert_eq!(
            snapshot(restored.machine()),
            snapshot(debugger.machine()),
            "{name}: every location as saved"
        );
        assert_eq!(restored.breakpoints(), debugger.breakpoints());
        let _ = std::fs::remove_file(&path);
    }
}

#[test]
fn every_example_runs_and_survives_a_session_round_trip() {
    for d in DIALECTS {
        check_examples(d);
    }
}

#[test]
fn every_lesson_session_loads() {
    for d in DIALECTS {
        for &(name, text) in d.lessons {
            let s = Session::from_ron(text, name).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(s.dialect(), *d, "{name}");
            let debugger = s.restore(name).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(debugger.pos(), s.at, "{name}: at the saved moment");
            // The shipped files are the ones in sessions/.
            let on_disk = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("sessions")
                .join(name);
            assert_eq!(
                std::fs::read_to_string(on_disk).expect("in sessions/"),
                text,
                "{name}"
            );
        }
    }
}

#[test]
fn the_runner_picks_every_dialect_by_extension() {
    for d in DIALECTS {
        let &(name, text) = d.examples.first().expect("an example");
        let path = temp(name);
        std::fs::write(&path, text).expect("write");
        let out =
            crate::common::with_scratch_home(&mut Command::new(env!("CARGO_BIN_EXE_servoscope")))
                .args([
                    "run",
                    path.to_str().expect("utf-8"),
                    "--max-ticks",
                    "50",
                    "--json",
                ])
                .output()
                .expect("runs");
        assert_ne!(out.status.code(), Some(2), "{name}: {:?}", out);
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
        assert_eq!(v["dialect"], d.name);
        for key in ["status", "ticks", "steps", "fault"] {
            assert!(v.get(key).is_some(), "{name}: the common header has {key}");
        }
        let _ = std::fs::remove_file(&path);
    }
}

#[test]
fn the_window_opens_every_example_of_every_dialect() {
    use egui_kittest::kittest::Queryable;
    use servoscope::ui::{Prefs, ServoscopeApp};
    let mut h = egui_kittest::Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .build_ui_state(
            |ui, app: &mut ServoscopeApp| app.show(ui),
            ServoscopeApp::new(Prefs::default()),
        );
    for (i, (d, name, _)) in registry::examples().enumerate() {
        h.state_mut().apply(
            &egui::Context::default(),
            servoscope::ui::Command::LoadExample(i),
        );
        h.run_steps(2);
        if h.state().pending.is_some() {
            h.get_by_label("Discard changes").click();
            h.run_steps(2);
        }
        assert_eq!(h.state().debugger.dialect(), d);
        assert_eq!(h.state().debugger.name(), name);
        h.key_press(egui::Key::F10);
        h.run_steps(2);
        assert!(
            h.state().debugger.pos() > servoscope_core::machine::Pos::default(),
            "{name} steps"
        );
        h.get_by_label("Step");
        h.get_by_label("Plot");
    }
    // File → New in each dialect: an empty program of that dialect, ready to step.
    for d in DIALECTS {
        h.state_mut().apply(
            &egui::Context::default(),
            servoscope::ui::Command::NewProgram(d.name),
        );
        h.run_steps(2);
        if h.state().pending.is_some() {
            h.get_by_label("Discard changes").click();
            h.run_steps(2);
        }
        assert_eq!(h.state().debugger.dialect(), *d);
        assert_eq!(h.state().debugger.source(), d.new_program);
        assert!(h.state().debugger.diagnostics().is_empty());
    }
}

#[test]
fn every_dialects_hints_use_its_own_names() {
    for d in DIALECTS {
        let debugger = servoscope_core::debugger::Debugger::with_dialect(d, "e", d.examples[0].1);
        let words = d.vocabulary;
        let hints = words
            .watch_hint
            .split(", ")
            .chain([words.location_hint, words.condition_hint]);
        for hint in hints {
            if let Err(e) = debugger.evaluate(hint) {
                panic!(
                    "{}: the hint '{hint}' is not an expression there: {e}",
                    d.name
                );
            }
        }
    }
}

#[test]
fn a_new_program_starts_without_the_last_ones_watches_and_breakpoints() {
    let dl205 = registry::by_name("dl205").expect("registered");
    let opennet = registry::by_name("opennet").expect("registered");
    let mut d = servoscope_core::debugger::Debugger::with_dialect(dl205, "a", dl205.examples[0].1);
    d.add_watch("V2000", servoscope_core::machine::Format::Bcd);
    d.toggle_breakpoint(2);
    d.load_as(opennet, "new.opennet", opennet.new_program);
    assert!(d.watches().is_empty());
    assert!(d.breakpoint_list().is_empty());
}
