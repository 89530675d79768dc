//! The debugger window driven through egui_kittest: no window, no GPU. Widgets are found by
//! their accessible labels, clicked and typed into, and frames are stepped with `step`/
//! `run_steps` (a running simulation keeps asking for repaints).

use servoscope_core::debugger::Action;

use std::time::{Duration, Instant};

use egui::{Key, Modifiers};

use egui_kittest::Harness;

use egui_kittest::kittest::Queryable;

use servoscope::ui::{Prefs, ServoscopeApp};

use servoscope_core::debugger::Speed;

use servoscope_core::machine::silverlode::SilverLode;

use servoscope_core::machine::silverlode::view::{io, reg};

use servoscope_core::machine::{Machine, MachineView, RunState};

use crate::common;

fn sl(app: &ServoscopeApp) -> &SilverLode {
    app.debugger
        .machine_as::<SilverLode>()
        .expect("a SilverLode machine")
}

fn harness(app: ServoscopeApp) -> Harness<'static, ServoscopeApp> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(2);
    h
}

fn app_with(source: &str) -> ServoscopeApp {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("test.qsl", source);
    app
}

/// A file handed over by the window system, as egui sees it.
#[derive(Debug)]
struct Dropped(std::path::PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &std::path::Path {
        &self.0
    }
    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

fn step_n(h: &mut Harness<'static, ServoscopeApp>, n: usize) {
    for _ in 0..n {
        h.state_mut().debugger.step_command();
    }
    h.run_steps(2);
}

/// A session far into an endless program: its replay takes a while.
fn long_session(dir: &std::path::Path, ticks: u64) -> std::path::PathBuf {
    let path = dir.join(format!("long-{ticks}.ron"));
    let text = format!(
        "(format: 2, dialect: \"silverlode\", program: \"loop: CLC INC, 11\\nJMP loop\", at: (tick: {ticks}))"
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// A DL205 session at the most scans a replay is allowed (a billion) of a program of 21
/// instructions: a replay no machine finishes while a test waits for it (a 3-instruction one
/// at 400 million scans sometimes finished before Cancel was clicked), in slices short enough
/// for Cancel to be seen at once.
fn endless_plc_session(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("endless.ron");
    let program = "STR X0\nOUT Y0\n".repeat(10) + "END";
    let text = format!(
        "(format: 2, dialect: \"dl205\", program: \"{program}\", at: (tick: {}))",
        servoscope_core::session::MAX_REPLAY_TICKS
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// `WRP 20, n ; line n` on line n: a program whose text says where each line is.
fn numbered_program(lines: usize) -> String {
    (1..=lines)
        .map(|i| format!("WRP 20, {i} ; line {i}\n"))
        .collect()
}

mod dialects;
mod files;
mod stepping;
mod views;
