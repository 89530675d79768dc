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

#[test]
fn opens_the_built_in_example_ready_to_step() {
    let h = harness(ServoscopeApp::new(Prefs::default()));
    let app = h.state();
    assert!(app.window_title().starts_with("servoscope"));
    assert!(app.window_title().contains("fifo_moves.qsl"));
    assert!(app.debugger.diagnostics().is_empty());
    assert_eq!(
        app.debugger.machine().pc_line(),
        Some(12),
        "first command of the example"
    );
    h.get_by_label("Run");
    h.get_by_label("Step");
    h.get_by_label("Breakpoint line 12");
    h.get_by_label("ISW ZERO");
    h.get_by_label("R40");
}

#[test]
fn f10_moves_the_line_and_changes_a_register() {
    let mut h = harness(ServoscopeApp::new(Prefs::default()));
    let before = sl(h.state()).reg(40);
    h.key_press(Key::F10);
    h.run_steps(2);
    let m = sl(h.state());
    assert_eq!(
        m.pc_line(),
        Some(15),
        "the next command (after the comment lines)"
    );
    assert_ne!(m.reg(40), before, "Q_INIT wrote the queue header");
    assert_eq!(m.reg(40) as u32, 4 << 16);
    // The status bar explains the command with its values.
    h.get_by_label_contains("init queue R40 with 4 slots");
}

#[test]
fn a_breakpoint_clicked_in_the_gutter_stops_a_run() {
    let mut h = harness(app_with(
        "WRP 11, 3\nloop: CLC INC, 12\nCLC DEC, 11\nJMP loop, !ZERO\nEND",
    ));
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.get_by_label("Breakpoint line 3").click();
    h.run_steps(2);
    assert!(h.state().debugger.breakpoints().contains(&3));
    h.get_by_label("Run").click();
    h.run_steps(3);
    let d = &h.state().debugger;
    assert!(!d.is_running());
    assert_eq!(d.machine().pc_line(), Some(3));
    assert_eq!(
        d.machine_as::<SilverLode>()
            .expect("a SilverLode machine")
            .reg(12),
        1
    );
    h.get_by_label_contains("Breakpoint hit at line 3");
    // F9 on the same line (cursor not in the text: the pc line) removes it.
    h.key_press(Key::F9);
    h.run_steps(1);
    assert!(h.state().debugger.breakpoints().is_empty());
    h.key_press(Key::F5);
    h.run_steps(3);
    assert_eq!(h.state().debugger.machine().run_state(), RunState::Ended);
    assert_eq!(sl(h.state()).reg(12), 3);
}

#[test]
fn unlimited_run_keeps_frames_coming_and_pause_stops_it() {
    let mut h = harness(app_with("loop: CLC INC, 11\nJMP loop"));
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    let mut ticks = Vec::new();
    for _ in 0..20 {
        let started = Instant::now();
        h.step();
        // A guard against a blocking loop (an endless program never returns), not a speed
        // claim: frame times are measured with --frame-stats.
        assert!(
            started.elapsed() < Duration::from_secs(3),
            "a frame must not block"
        );
        ticks.push(h.state().debugger.machine().ticks());
    }
    assert!(
        ticks.windows(2).all(|w| w[1] > w[0]),
        "every frame advances the program: {ticks:?}"
    );
    assert!(
        h.state().debugger.is_running(),
        "the endless program is still running"
    );
    h.get_by_label("Pause").click();
    h.step();
    let paused_at = h.state().debugger.machine().ticks();
    assert!(!h.state().debugger.is_running());
    h.run_steps(5);
    assert_eq!(
        h.state().debugger.machine().ticks(),
        paused_at,
        "pause answers at once"
    );
}

#[test]
fn the_window_runs_unlimited_between_frames_and_shows_the_rate() {
    // The real window's frame: the run goes to the worker thread once a frame is drawn.
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .build_ui_state(
            |ui, app: &mut ServoscopeApp| app.frame(ui),
            app_with("loop: CLC INC, 11\nJMP loop"),
        );
    h.run_steps(2);
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    let started = Instant::now();
    while started.elapsed() < Duration::from_millis(900) {
        h.step();
        std::thread::sleep(Duration::from_millis(15));
    }
    h.get_by_label_contains("ticks/s (×");
    h.get_by_label("Pause").click();
    h.step();
    assert!(!h.state().debugger.is_running());
    let paused_at = h.state().debugger.machine().ticks();
    assert!(
        paused_at > 100_000,
        "the worker ran between frames: {paused_at}"
    );
    assert_eq!(
        h.state()
            .debugger
            .machine()
            .read(h.state().debugger.find("R11").expect("R11")),
        paused_at.div_ceil(2),
        "the state shown is the state reached"
    );
    h.run_steps(3);
    assert_eq!(h.state().debugger.machine().ticks(), paused_at);
}

#[test]
fn typing_a_value_into_a_register() {
    let mut h = harness(app_with("WRP 20, 5\nEND"));
    h.get_by_label("R20").click();
    h.run_steps(2);
    assert_eq!(h.state().registers.selected, Some(reg(20)));
    let field = h.get_by_label("Value of R20");
    field.focus();
    h.step();
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.get_by_label("Value of R20").type_text("0x10");
    h.step();
    h.get_by_label("Set").click();
    h.run_steps(2);
    assert_eq!(sl(h.state()).reg(20), 16);

    // A bad entry says why and changes nothing.
    h.get_by_label("Value of R20").focus();
    h.step();
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.get_by_label("Value of R20").type_text("banana");
    h.step();
    h.get_by_label("Set").click();
    h.run_steps(2);
    assert_eq!(sl(h.state()).reg(20), 16);
    h.get_by_label_contains("Not changed");
}

#[test]
fn clicking_a_bit_flips_it() {
    let mut h = harness(app_with("WRP 20, 5\nEND"));
    h.state_mut().debugger.step_command();
    h.get_by_label("R20").click();
    h.run_steps(2);
    h.get_by_label("R20 bit 3").click();
    h.run_steps(2);
    assert_eq!(sl(h.state()).reg(20), 5 | 8);
    h.get_by_label("R20 bit 31").click();
    h.run_steps(2);
    assert_eq!(sl(h.state()).reg(20) as u32, 0x8000_000D);
}

#[test]
fn an_invalid_program_shows_its_diagnostics_and_refuses_to_run() {
    let mut h = harness(app_with("CLK ADD, 1\nWRP 11, 1\nJMP nowhere\n"));
    h.get_by_label("Problems (2)");
    h.get_by_label_contains("did you mean CLC");
    h.get_by_label_contains("undefined label 'nowhere'");
    h.key_press(Key::F5);
    h.key_press(Key::F10);
    h.run_steps(3);
    let d = &h.state().debugger;
    assert!(!d.is_running());
    assert_eq!(d.machine().ticks(), 0);
    // The status line says why nothing runs, not which key would step.
    assert!(h.query_by_label_contains("Press F10").is_none());
    h.get_by_label_contains("does not assemble (2 error(s))");
    // Clicking a problem puts the cursor on its line.
    h.get_by_label_contains("undefined label 'nowhere'").click();
    h.run_steps(2);
    assert_eq!(h.state().code.cursor_line, Some(3));
}

#[test]
fn edits_assemble_on_ctrl_enter() {
    let mut h = harness(app_with("WRP 11, 1\nEND\n"));
    let editor = h.get_by_role(egui::Role::MultilineTextInput);
    editor.focus();
    h.step();
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.get_by_role(egui::Role::MultilineTextInput)
        .type_text("WRP 11, 7\nBOGUS\n");
    h.run_steps(2);
    assert!(h.state().debugger.is_edited());
    assert!(
        h.state().window_title().ends_with('●'),
        "unsaved edits are marked"
    );
    h.key_press_modifiers(Modifiers::COMMAND, Key::Enter);
    h.run_steps(2);
    assert_eq!(h.state().debugger.diagnostics().len(), 1);
    h.get_by_label("Problems (1)");
}

#[test]
fn ctrl_enter_in_the_frame_of_a_keystroke_assembles_the_text_on_screen() {
    let mut h = harness(app_with("WRP 11, 1\nEND\n"));
    h.get_by_role(egui::Role::MultilineTextInput).focus();
    h.step();
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.step();
    // The typing and the shortcut arrive in one frame.
    h.event(egui::Event::Text("WRP 11, 7\nEND\n".to_string()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::Enter);
    h.step();
    let d = &h.state().debugger;
    assert!(d.source().contains("WRP 11, 7"), "{}", d.source());
    assert!(!d.is_edited(), "what was assembled is the text on screen");
    assert!(d.diagnostics().is_empty());
}

#[test]
fn a_fault_shows_its_banner_and_keeps_the_state() {
    let mut h = harness(app_with("WRP 11, 0\nWRP 10, 9\nCLC DIV, 11\nEND"));
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    h.run_steps(3);
    h.get_by_label("Fault: divide_by_zero at line 3");
    let m = sl(h.state());
    assert_eq!(m.run_state(), RunState::Faulted);
    assert_eq!(m.reg(10), 9);
}

#[test]
fn inputs_toggle_while_running() {
    let mut h = harness(app_with("WBS IO2\nEND"));
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    h.run_steps(3);
    assert!(h.state().debugger.is_running(), "waiting for IO2");
    h.get_by_label("IO2").click();
    h.run_steps(3);
    assert!(h.state().debugger.machine().read(io(1)) == 1);
    assert_eq!(h.state().debugger.machine().run_state(), RunState::Ended);
}

#[test]
fn opening_a_path_typed_in_the_open_window() {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("typed.qsl");
    std::fs::write(&path, "WRP 30, 42\nEND\n").unwrap();
    let mut h = harness(ServoscopeApp::new(Prefs::default()));
    h.state_mut().files.open.window_open = true;
    h.run_steps(2);
    h.get_by_label("Path").focus();
    h.step();
    h.get_by_label("Path").type_text(path.to_str().unwrap());
    h.step();
    h.get_by_label("Open").click();
    h.run_steps(2);
    let app = h.state();
    assert_eq!(app.debugger.name(), "typed.qsl");
    assert!(app.window_title().contains("typed.qsl"));
    assert_eq!(app.prefs.recent.first(), Some(&path));
    // A missing file is reported and the current program stays.
    h.state_mut().open_path(dir.join("missing.qsl"));
    h.run_steps(2);
    assert_eq!(h.state().debugger.name(), "typed.qsl");
    h.get_by_label_contains("Cannot open");
    let _ = std::fs::remove_dir_all(&dir);
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

#[test]
fn dropping_a_file_on_the_window_opens_it() {
    let path = std::env::temp_dir().join(format!("servoscope-drop-{}.qsl", std::process::id()));
    std::fs::write(&path, "WRP 31, 7\nEND\n").unwrap();
    let mut h = harness(ServoscopeApp::new(Prefs::default()));
    h.input_mut()
        .dropped_files
        .push(std::sync::Arc::new(Dropped(path.clone())));
    h.run_steps(2);
    assert_eq!(
        h.state().debugger.name(),
        path.file_name().unwrap().to_str().unwrap()
    );
    h.key_press(Key::F10);
    h.run_steps(1);
    assert_eq!(sl(h.state()).reg(31), 7);
    let _ = std::fs::remove_file(&path);
}

fn step_n(h: &mut Harness<'static, ServoscopeApp>, n: usize) {
    for _ in 0..n {
        h.state_mut().debugger.step_command();
    }
    h.run_steps(2);
}

#[test]
fn a_queue_program_shows_its_ring_with_head_and_tail() {
    let mut h = harness(app_with(
        "CLD Q_INIT, 10, 40, 4\nCLD Q_PUSH_HEAD, 10, 40, 7\nCLD Q_PUSH_HEAD, 10, 40, 8\nCLD Q_POP_TAIL, 11, 40, 0\nEND",
    ));
    // No queue yet: the panel gives its room to the others until there is one.
    let queues = servoscope::ui::layout::Pane::Dialect("Queues".into());
    let shown = |h: &Harness<'static, ServoscopeApp>| {
        h.state()
            .layout
            .pane_rects()
            .iter()
            .any(|(p, _)| *p == queues)
    };
    assert!(!shown(&h));
    step_n(&mut h, 1);
    assert!(shown(&h));
    h.get_by_label("Queues (1)");
    h.get_by_label("Queue R40 head at slot 0");
    h.get_by_label("Queue R40 tail at slot 0");
    h.get_by_label("Queue R40 0/4 EMPTY");
    // A push moves the head and fills its slot.
    step_n(&mut h, 1);
    h.get_by_label("Queue R40 head at slot 1");
    h.get_by_label("Queue R40 tail at slot 0");
    h.get_by_label("Queue R40 slot 0 (R42) = 7");
    h.get_by_label("last: push head at slot 0 (R42)");
    step_n(&mut h, 2);
    h.get_by_label("Queue R40 tail at slot 1");
    h.get_by_label("last: pop tail at slot 0 (R42)");
    h.get_by_label("Queue R40 1/4");
    // The header words are decoded.
    h.get_by_label("size = 4");
    h.get_by_label("head = 2");
}

#[test]
fn full_failed_and_corrupt_queues_say_so() {
    let mut h = harness(app_with(
        "CLD Q_INIT, 10, 40, 1\nCLD Q_PUSH_HEAD, 10, 40, 5\nCLD Q_PUSH_HEAD, 10, 40, 6\nWRP 41, 0x00090000\nEND",
    ));
    step_n(&mut h, 2);
    h.get_by_label("Queue R40 1/1 FULL");
    step_n(&mut h, 1);
    h.get_by_label("last: push head FAILED (full)");
    step_n(&mut h, 1);
    h.get_by_label("Queue R40: not a valid queue any more");
}

#[test]
fn large_queues_switch_to_a_grid() {
    let mut h = harness(app_with(
        "CLD Q_INIT, 10, 50, 40\nCLD Q_PUSH_TAIL, 10, 50, 3\nEND",
    ));
    step_n(&mut h, 2);
    h.get_by_label("Queue R50 slot 39 (R91) = 3");
    h.get_by_label("Queue R50 tail at slot 39");
    h.get_by_label("Queue R50 head at slot 0");
}

#[test]
fn the_plot_appears_with_its_series_after_a_move() {
    let mut h = harness(app_with("MAV 500, 386500, 80530640\nDLY 200\nEND"));
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    h.run_steps(4);
    assert_eq!(h.state().debugger.machine().run_state(), RunState::Ended);
    h.get_by_label("Plot");
    h.get_by_label("target (R0)");
    h.get_by_label("actual (R1)");
    let trace = h.state().debugger.trace();
    assert_eq!(trace.at(trace.end_tick().unwrap()).unwrap().values[0], 500);
}

#[test]
fn csv_export_writes_the_trace() {
    let mut h = harness(app_with("WRP 0, 40\nDLY 30\nEND"));
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    h.run_steps(3);
    let path = std::env::temp_dir().join(format!("servoscope-trace-{}.csv", std::process::id()));
    h.state_mut().files.export.window_open = true;
    h.run_steps(2);
    h.get_by_label("Path").focus();
    h.step();
    h.get_by_label("Path").type_text(path.to_str().unwrap());
    h.step();
    h.get_by_label("Export").click();
    h.run_steps(2);
    let text = std::fs::read_to_string(&path).expect("CSV written");
    let _ = std::fs::remove_file(&path);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("tick,time_ms,target (R0),actual (R1),error (R6)"),
        "one column per plot channel, named as in the legend"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows[0], vec![0.0, 0.0, 0.0, 0.0, 0.0], "the start");
    assert_eq!(
        rows[1][..5],
        [1.0, 0.12, 40.0, 0.0, 40.0],
        "WRP 0, 40 in tick 1: error 40"
    );
    // Every row is the machine at that tick: replay and compare.
    let mut m = common::load("WRP 0, 40\nDLY 30\nEND").unwrap();
    for row in &rows {
        while m.ticks() < row[0] as u64 {
            m.step_tick();
        }
        let want = [m.reg(0), m.reg(1), m.reg(6)].map(f64::from);
        assert_eq!(row[2..], want, "tick {}", row[0]);
        assert!((row[1] - row[0] * 0.12).abs() < 1e-9);
    }
    h.get_by_label_contains("Exported");
}

#[test]
fn stepping_back_with_the_keys() {
    let mut h = harness(app_with(
        "WRP 11, 1\nDLY 20\nWRP 12, 2\nloop: CLC INC, 13\nJMP loop",
    ));
    for _ in 0..3 {
        h.key_press(Key::F10);
        h.run_steps(1);
    }
    assert_eq!(sl(h.state()).reg(12), 2);
    h.key_press_modifiers(Modifiers::SHIFT, Key::F10);
    h.run_steps(2);
    let m = sl(h.state());
    assert_eq!(
        (m.reg(12), m.ticks(), m.pc_line()),
        (0, 21, Some(3)),
        "WRP 12 undone"
    );
    h.key_press_modifiers(Modifiers::SHIFT, Key::F8);
    h.run_steps(2);
    assert_eq!(
        h.state().debugger.machine().ticks(),
        20,
        "one tick back, inside the DLY"
    );
    // Reverse-continue to a breakpoint hit earlier in the run.
    h.state_mut().debugger.toggle_breakpoint(4);
    h.state_mut().debugger.goto_tick(200);
    h.run_steps(3);
    h.key_press_modifiers(Modifiers::SHIFT, Key::F5);
    h.run_steps(2);
    let m = sl(h.state());
    assert_eq!(m.pc_line(), Some(4));
    assert!(
        m.ticks() < 200 && m.ticks() > 190,
        "the last pass before tick 200: {}",
        m.ticks()
    );
}

#[test]
fn the_timeline_and_go_to_tick() {
    let mut h = harness(app_with("loop: CLC INC, 13\nJMP loop"));
    h.state_mut().debugger.goto_tick(1000);
    h.run_steps(3);
    assert_eq!(h.state().debugger.machine().ticks(), 1000);
    h.get_by_label("Timeline");
    h.get_by_label("Go to tick").focus();
    h.step();
    h.get_by_label("Go to tick").type_text("250");
    h.key_press(Key::Enter);
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().ticks(), 250);
    assert_eq!(sl(h.state()).reg(13), 125);
    assert_eq!(
        h.state().debugger.furthest_tick(),
        1000,
        "the future is kept"
    );
}

#[test]
fn clicking_the_plot_goes_to_that_tick() {
    let mut h = harness(app_with("MAV 2000, 386500, 80530640\nDLY 3000\nEND"));
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    h.run_steps(4);
    let end = h.state().debugger.machine().ticks();
    let header = h.get_by_label("Plot").rect();
    let target = egui::pos2(header.center().x + 120.0, header.bottom() + 80.0);
    h.input_mut().events.push(egui::Event::PointerMoved(target));
    h.step();
    for pressed in [true, false] {
        h.input_mut().events.push(egui::Event::PointerButton {
            pos: target,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        });
        h.step();
    }
    h.run_steps(2);
    let app = h.state();
    let selected = app.plot.selected_tick.expect("a tick was selected");
    assert!(selected < end, "somewhere inside the run");
    assert_eq!(
        app.debugger.machine().ticks(),
        selected,
        "and the debugger went there"
    );
}

#[test]
fn sessions_save_with_ctrl_s_and_reopen() {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-sessions-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let session_file = dir.join("work.ron");
    let mut h = harness(app_with("WRP 20, 5\nloop: CLC INC, 21\nJMP loop"));
    assert!(!h.state().window_title().ends_with('●'));
    h.key_press(Key::F10);
    h.key_press(Key::F10);
    h.run_steps(2);
    h.state_mut().debugger.toggle_breakpoint(3);
    h.state_mut()
        .debugger
        .set_value(reg(30), 77)
        .expect("a register edit");
    h.run_steps(1);
    assert!(
        h.state().window_title().ends_with('●'),
        "unsaved changes are marked"
    );
    h.state_mut().session_path = Some(session_file.clone());
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run_steps(2);
    assert!(session_file.exists());
    assert!(!h.state().window_title().ends_with('●'), "saved");
    assert!(h.state().window_title().contains("[work.ron]"));
    let saved_machine = sl(h.state()).clone();

    // More work, then open the session again: the prompt asks first.
    h.key_press(Key::F10);
    h.run_steps(2);
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::OpenPath(session_file.clone()),
    );
    h.run_steps(2);
    h.get_by_label("Unsaved changes");
    h.get_by_label("Cancel").click();
    h.run_steps(2);
    assert!(h.state().pending.is_none());
    assert_ne!(
        sl(h.state()),
        &saved_machine,
        "cancel kept the current state"
    );
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::OpenPath(session_file.clone()),
    );
    h.run_steps(2);
    h.get_by_label("Discard changes").click();
    h.run_steps(2);
    let app = h.state();
    assert_eq!(sl(app), &saved_machine, "exactly the saved moment");
    assert!(app.debugger.breakpoints().contains(&3));
    assert_eq!(sl(app).reg(30), 77);

    // A corrupt session is refused and the current one stays.
    let bad = dir.join("bad.ron");
    std::fs::write(&bad, "(format: 1, dialect: \"silverlode\", program: ").unwrap();
    h.state_mut().open_path(bad);
    h.run_steps(2);
    assert_eq!(sl(h.state()), &saved_machine);
    h.get_by_label_contains("not a readable session file");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_servo_model_is_settable_and_saved_with_the_session() {
    let mut h = harness(app_with("WRP 0, 1000\nDLY 3000\nEND"));
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::OpenSettings,
    );
    h.run_steps(2);
    h.get_by_label("Natural frequency (Hz)");
    h.get_by_label("Damping ratio");
    if let Some(draft) = h.state_mut().settings.draft.as_mut() {
        draft.insert("natural_frequency_hz".into(), 80.0);
        draft.insert("holding_error_limit".into(), 50.0);
    }
    h.run_steps(1);
    h.get_by_label("Apply").click();
    h.run_steps(2);
    let settings = h.state().debugger.settings().clone();
    assert_eq!(
        (
            settings["natural_frequency_hz"],
            settings["holding_error_limit"]
        ),
        (80.0, 50.0)
    );
    let servo = sl(h.state()).settings();
    assert_eq!(
        (servo.natural_frequency_hz, servo.holding_error_limit),
        (80.0, 50),
        "the machine uses them"
    );
    assert_eq!(
        h.state().session().settings,
        settings,
        "a saved session keeps them"
    );
    // A stiffer loop follows a step faster: after 100 ticks it is closer to the target.
    h.state_mut().debugger.goto_tick(100);
    h.run_steps(3);
    let stiff = sl(h.state()).reg(1);
    let mut soft = common::load("WRP 0, 1000\nDLY 3000\nEND").unwrap();
    for _ in 0..100 {
        soft.step_tick();
    }
    assert!(
        stiff > soft.reg(1),
        "80 Hz: {stiff}, 25 Hz: {}",
        soft.reg(1)
    );
}

#[test]
fn saving_over_a_file_that_is_not_a_session_asks_first() {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-replace-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let program = dir.join("prog.qsl");
    std::fs::write(&program, "WRP 11, 1\nEND\n").unwrap();
    let mut h = harness(app_with("WRP 20, 5\nEND"));
    h.state_mut().save_session_to(program.clone());
    h.run_steps(2);
    h.get_by_label("Keep it").click();
    h.run_steps(2);
    assert!(h.state().confirm_replace.is_none());
    assert_eq!(
        std::fs::read_to_string(&program).unwrap(),
        "WRP 11, 1\nEND\n"
    );
    h.state_mut().save_session_to(program.clone());
    h.run_steps(2);
    h.get_by_label("Replace it").click();
    h.run_steps(2);
    assert!(
        std::fs::read_to_string(&program)
            .unwrap()
            .contains("format: 2")
    );
    assert_eq!(h.state().session_path.as_deref(), Some(program.as_path()));
    let _ = std::fs::remove_dir_all(&dir);
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

/// A session far into a PLC program: the SilverLode loop above replays compiled, which may
/// finish within a few frames; scans replay at a few million a second at most.
fn long_plc_session(dir: &std::path::Path, scans: u64) -> std::path::PathBuf {
    let path = dir.join(format!("long-{scans}-scans.ron"));
    let text = format!(
        "(format: 2, dialect: \"dl205\", program: \"STR X0\\nOUT Y0\\nEND\", at: (tick: {scans}))"
    );
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_long_replay_runs_in_the_background_and_can_be_cancelled() {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-long-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = harness(app_with("WRP 20, 5\nEND"));
    h.state_mut().open_path(long_plc_session(&dir, 400_000_000));
    h.run_steps(3);
    assert!(h.state().loading.is_some(), "replaying in the background");
    h.get_by_label("Opening session");
    // Frames keep coming while it replays.
    let started = std::time::Instant::now();
    for _ in 0..20 {
        h.step();
    }
    assert!(
        h.state().loading.is_some(),
        "still replaying after 20 frames"
    );
    assert!(
        started.elapsed() < std::time::Duration::from_secs(20),
        "frames did not block"
    );
    h.get_by_label("Cancel").click();
    for _ in 0..500 {
        h.step();
        if h.state().loading.is_none() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    assert!(h.state().loading.is_none(), "cancelled");
    assert_eq!(
        h.state().debugger.name(),
        "test.qsl",
        "the current session stays"
    );
    h.get_by_label_contains("cancelled");

    // One that finishes: the state arrives when the replay is done.
    h.state_mut().open_path(long_session(&dir, 3_000_000));
    for _ in 0..3000 {
        h.step();
        if h.state().loading.is_none() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    assert!(h.state().loading.is_none(), "finished");
    assert_eq!(h.state().debugger.pos().tick, 3_000_000);
    assert_eq!(sl(h.state()).reg(11), 1_500_000, "one INC every two ticks");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `WRP 20, n ; line n` on line n: a program whose text says where each line is.
fn numbered_program(lines: usize) -> String {
    (1..=lines)
        .map(|i| format!("WRP 20, {i} ; line {i}\n"))
        .collect()
}

#[test]
fn a_long_program_shows_only_its_visible_rows_and_they_line_up() {
    let mut h = harness(app_with(&numbered_program(100_000)));
    h.run_steps(2);
    assert!(
        h.query_by_role(egui::Role::MultilineTextInput).is_none(),
        "the row view, not the editor"
    );
    h.get_by_label("Line 1: WRP 20, 1 ; line 1");
    h.get_by_label("Breakpoint line 1");
    assert!(
        h.query_by_label("Breakpoint line 50000").is_none(),
        "not laid out"
    );
    h.get_by_label("100000 lines");
    // Deep into the program: the row about to run is in view, its gutter beside its text.
    for (tick, line) in [
        (0u64, 1usize),
        (250, 251),
        (60_000, 60_001),
        (99_998, 99_999),
    ] {
        h.state_mut().debugger.goto_tick(tick);
        // Beyond the recorded history the run gets there over a few frames.
        for _ in 0..100 {
            h.step();
            if h.state().debugger.machine().pc_line() == Some(line) {
                break;
            }
        }
        assert_eq!(h.state().debugger.machine().pc_line(), Some(line));
        h.run_steps(2);
        let (text_label, gutter_label) = (
            format!("Line {line}: WRP 20, {line} ; line {line}"),
            format!("Breakpoint line {line}"),
        );
        let text = h.get_by_label(&text_label);
        let gutter = h.get_by_label(&gutter_label);
        let (t, g) = (text.rect(), gutter.rect());
        assert!(
            (t.center().y - g.center().y).abs() < 1.0,
            "same row at line {line}"
        );
        gutter.click();
        h.run_steps(2);
        assert!(
            h.state().debugger.breakpoints().contains(&line),
            "the gutter beside line {line} sets line {line}: {:?}",
            h.state().debugger.breakpoints()
        );
    }
}

#[test]
fn a_long_program_is_edited_in_place_on_request() {
    let lines = servoscope::ui::code::EDIT_IN_PLACE_LINES + 1;
    let mut h = harness(app_with(&numbered_program(lines)));
    assert!(h.query_by_role(egui::Role::MultilineTextInput).is_none());
    h.get_by_label("Edit text").click();
    h.run_steps(2);
    assert!(h.query_by_role(egui::Role::MultilineTextInput).is_some());
    h.get_by_label("Done editing").click();
    h.run_steps(2);
    assert!(h.query_by_role(egui::Role::MultilineTextInput).is_none());
    // A program at the limit is edited in place from the start.
    let h = harness(app_with(&numbered_program(lines - 1)));
    assert!(h.query_by_role(egui::Role::MultilineTextInput).is_some());
}

/// Issue #9, defect 1: the gutter drifted from the text in long programs. Each gutter row must
/// sit beside its text line (the editor's text rows divide its height evenly), scrolled to the
/// top, the middle and the end, and a click there must set that line's breakpoint.
#[test]
fn gutter_rows_stay_beside_their_text_lines() {
    for lines in [10usize, 300, 1000] {
        let mut h = harness(app_with(&numbered_program(lines)));
        for line in [1, lines / 2, lines - 1] {
            h.state_mut().debugger.goto_tick(line as u64 - 1);
            for _ in 0..50 {
                h.step();
                if h.state().debugger.machine().pc_line() == Some(line) {
                    break;
                }
            }
            h.run_steps(3);
            assert_eq!(h.state().debugger.machine().pc_line(), Some(line));
            let text = h.get_by_role(egui::Role::MultilineTextInput).rect();
            // Where egui puts line `line` of this text in this font: its own layout.
            let source = h.state().debugger.source().to_string();
            let font = egui::TextStyle::Monospace.resolve(&h.ctx.global_style());
            let galley = h
                .ctx
                .fonts_mut(|f| f.layout_no_wrap(source, font, egui::Color32::WHITE));
            let row = galley.rows[line - 1].rect();
            let want = text.top() + row.center().y;
            let label = format!("Breakpoint line {line}");
            let gutter = h.get_by_label(&label);
            assert!(
                (gutter.rect().center().y - want).abs() < row.height() / 2.0,
                "{lines} lines, line {line}: gutter at {}, text row at {want}",
                gutter.rect().center().y
            );
            gutter.click();
            h.run_steps(2);
            assert!(
                h.state().debugger.breakpoints().contains(&line),
                "{lines} lines: the gutter beside line {line} sets line {line}"
            );
        }
    }
}

/// The window over a dialect that is not SilverLode: a scanned machine with 16-bit words, an
/// input, flag relays and its own words for time ("scan", "instruction").
#[test]
fn the_window_shows_a_scanned_machine_in_its_own_words() {
    use common::scanned::{IN, PROGRAM, SCANNED};
    use servoscope_core::machine::Loc;
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(&SCANNED, "p.scan", PROGRAM);
    let mut h = harness(app);
    h.get_by_label("Scan");
    h.get_by_label("Scan back");
    h.get_by_label("X0");
    h.get_by_label("ZERO");
    h.get_by_label("FIRST");
    for _ in 0..3 {
        h.key_press(Key::F10);
        h.run_steps(1);
    }
    h.run_steps(1);
    h.get_by_label_contains("scan 0, instruction 3");
    // Inputs switch, relays the machine drives refuse with a notice.
    h.get_by_label("X0").click();
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().read(Loc::new(IN, 0)), 1);
    h.get_by_label("FIRST").click();
    h.run_steps(2);
    h.get_by_label_contains("cannot be written");
    // A 16-bit word: its bit grid has bits 15..0 and no more.
    h.get_by_label("V0").click();
    h.run_steps(2);
    h.get_by_label("V0 bit 15");
    assert!(h.query_by_label("V0 bit 16").is_none());
    h.get_by_label("Value of V0");
}

/// Issue #9, defect 5: after a step back the value field showed the old value, and Set then
/// wrote it back and discarded the recorded future.
#[test]
fn the_value_field_follows_the_location_unless_typed_in() {
    let mut h = harness(app_with("WRP 20, 5\nWRP 20, 7\nEND"));
    h.state_mut().debugger.step_command();
    h.state_mut().debugger.step_command();
    h.run_steps(1);
    h.get_by_label("R20").click();
    h.run_steps(2);
    let shown = |h: &Harness<'static, ServoscopeApp>| {
        h.get_by_label("Value of R20").value().unwrap_or_default()
    };
    assert_eq!(shown(&h), "7");
    h.key_press_modifiers(Modifiers::SHIFT, Key::F10);
    h.run_steps(2);
    assert_eq!(sl(h.state()).reg(20), 5);
    assert_eq!(shown(&h), "5", "the field shows the value at this step");
    let furthest = h.state().debugger.furthest_tick();
    h.get_by_label("Set").click();
    h.run_steps(2);
    assert_eq!(
        h.state().debugger.furthest_tick(),
        furthest,
        "Set with the current value keeps the recorded future"
    );
}

/// Issue #9, defects 6 and 7: a program that does not assemble replaced the text but left the
/// previous program's state, marked "edited" and ●; saving with edits not yet assembled left ●.
#[test]
fn opening_a_broken_program_clears_the_old_one_and_saving_clears_the_mark() {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-broken-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = harness(app_with("WRP 20, 5\nloop: CLC INC, 21\nJMP loop"));
    h.state_mut().debugger.set_input(io(0), true).unwrap();
    for _ in 0..5 {
        h.state_mut().debugger.step_command();
    }
    h.run_steps(1);
    let broken = dir.join("broken.qsl");
    std::fs::write(&broken, "WRP 20, 5\nBOGUS 1\n").unwrap();
    h.state_mut().open_path(broken);
    h.run_steps(2);
    let d = &h.state().debugger;
    assert!(d.has_errors());
    assert_eq!((d.pos().tick, d.furthest_tick()), (0, 0), "no old history");
    assert_eq!(sl(h.state()).reg(20), 0, "no old registers");
    assert_eq!(d.machine().read(io(0)), 0, "no old inputs");
    assert!(!d.is_edited(), "nothing was edited");
    assert!(!h.state().window_title().ends_with('●'));

    // Edits not yet assembled, saved: the session holds them, so nothing is unsaved.
    *h.state_mut().debugger.source_mut() = "WRP 20, 6\nEND\n".to_string();
    h.run_steps(1);
    assert!(h.state().window_title().ends_with('●'));
    let session = dir.join("s.ron");
    h.state_mut().save_session_to(session.clone());
    h.run_steps(2);
    assert!(h.state().debugger.is_edited(), "still not assembled");
    assert!(!h.state().window_title().ends_with('●'), "but saved");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue #9, smaller items: Escape closes the file dialogs; a session saved without an
/// extension gets `.ron` and an absolute path.
#[test]
fn escape_closes_dialogs_and_sessions_get_their_extension() {
    let mut h = harness(app_with("WRP 20, 5\nEND"));
    h.state_mut().files.open.window_open = true;
    h.run_steps(2);
    h.get_by_label("Path");
    h.key_press(Key::Escape);
    h.run_steps(2);
    assert!(!h.state().files.open.window_open, "Escape closed it");

    let dir = std::env::temp_dir().join(format!("servoscope-gui-ext-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    h.state_mut().save_session_to(dir.join("lesson"));
    h.run_steps(2);
    let saved = dir.join("lesson.ron");
    assert!(saved.exists(), "saved as lesson.ron");
    assert_eq!(h.state().session_path.as_deref(), Some(saved.as_path()));
    assert!(h.state().prefs.recent.iter().all(|p| p.is_absolute()));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue #9, gap 12: the lesson sessions are in the Examples menu beside the programs.
#[test]
fn lessons_open_from_the_examples_menu() {
    let mut h = harness(ServoscopeApp::new(Prefs::default()));
    let (index, _) = servoscope_core::registry::lessons()
        .enumerate()
        .find(|(_, (_, name, _))| *name == "homing_on_input.ron")
        .expect("the homing lesson is built in");
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::LoadLesson(index),
    );
    h.run_steps(2);
    assert_eq!(
        h.state().debugger.machine().ticks(),
        3001,
        "at the lesson's moment"
    );
    assert!(h.state().debugger.breakpoints().contains(&13));
    assert_eq!(h.state().session_path, None, "a save asks where");
    assert!(!h.state().window_title().ends_with('●'));
}

/// Issue #9, gap 10: programs are files: Save program (as), the title names the program and
/// marks text not yet saved to it.
#[test]
fn programs_are_saved_as_files() {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-prog-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = harness(app_with("WRP 20, 5\nEND\n"));
    assert!(!h.state().window_title().contains('*'));
    *h.state_mut().debugger.source_mut() = "WRP 20, 6\nEND\n".to_string();
    h.run_steps(1);
    assert!(
        h.state().window_title().contains("test.qsl*"),
        "unsaved text marked"
    );
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::SaveProgramTo(dir.join("mine")),
    );
    h.run_steps(2);
    let file = dir.join("mine.qsl");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "WRP 20, 6\nEND\n");
    assert_eq!(h.state().debugger.name(), "mine.qsl");
    assert!(!h.state().window_title().contains('*'));
    // Save program writes to the same file from now on.
    *h.state_mut().debugger.source_mut() = "WRP 20, 7\nEND\n".to_string();
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::SaveProgram,
    );
    h.run_steps(2);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "WRP 20, 7\nEND\n");
    // A program is never written as a session file.
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::SaveProgramTo(dir.join("oops.ron")),
    );
    h.run_steps(2);
    assert!(!dir.join("oops.ron").exists());
    h.get_by_label_contains("would be read as a session");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue #9 item 9: the path field takes the typing whole (a path left from last time is
/// selected, not clicked into), and a file dialog that cannot show says so.
#[test]
fn the_open_window_selects_its_path_and_says_when_no_dialog_shows() {
    let mut h = harness(app_with("WRP 20, 5\nEND"));
    h.state_mut().files.open.path_text = "/old/place/prog.qsl".into();
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.run_steps(3);
    assert!(h.get_by_label("Path").is_focused());
    h.get_by_label("Path").type_text("new.qsl");
    h.run_steps(2);
    assert_eq!(
        h.state().files.open.path_text,
        "new.qsl",
        "typing replaced it"
    );

    // Here (no display server, no portal) the system dialog answers at once with nothing.
    let started = Instant::now();
    while h.state().files.is_waiting() && started.elapsed() < Duration::from_secs(10) {
        h.step();
        std::thread::sleep(Duration::from_millis(10));
    }
    h.run_steps(2);
    h.get_by_label_contains("No system file dialog is available here");
    // The field still works.
    h.get_by_label("Path").focus();
    h.step();
    assert!(h.get_by_label("Path").is_focused());
}

/// Issue #10: a TML program in the window: step it, read a fixed value and the product
/// register.
#[test]
fn a_tml_program_steps_and_shows_fixed_values_and_preg() {
    let tml = servoscope_core::registry::by_name("tml").expect("TML is registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        tml,
        "speed.tml",
        "fixed speed; int ten;\nspeed = 26.6667;\nten = 10;\nspeed * ten;\nEND;",
    );
    let mut h = harness(app);
    for _ in 0..3 {
        h.key_press(Key::F10);
        h.run_steps(2);
    }
    let m = h.state().debugger.machine();
    assert_eq!(m.steps(), 3);
    // The fixed variable reads as Q16.16 in the table, under its declared name, in the
    // group of the program's variables.
    h.get_by_label("speed");
    h.get_by_label("Variables");
    h.get_by_label("26.666702");
    // PREG = 1747629 × 10 as 32.16: PRODH is the integer part, 266.
    h.get_by_label("Product register");
    h.get_by_label("0x0000010AAAC2 = 17476290");
    h.get_by_label("PRODH = 266   PROD = 17476290");
    h.get_by_label_contains("PREG = (speed 1747629 × ten 10) << 0");
    // Its bits: integer part over fraction, the binary point between, the exact decimal.
    let speed = h.state().debugger.machine().find("speed").expect("speed");
    h.state_mut().registers.selected = Some(speed);
    h.run_steps(2);
    h.get_by_label("● binary point: 26.6667022705078125 (exactly)");
    h.get_by_label("integer 31–16");
    h.get_by_label("fraction 15–0");
    // Sixteen inputs do not all fit the toolbar: those the program uses, and "+" for others.
    assert!(h.query_by_label("IN#0").is_none());
    h.get_by_label("+");
    // ... and all sixteen in the Drive panel, a tab beside the product register's.
    h.get_by_label("Drive").click();
    h.run_steps(2);
    h.get_by_label("Input IN#5").click();
    h.run_steps(2);
    let m = h.state().debugger.machine();
    assert_eq!(m.read(m.find("IN#5").unwrap()), 1);
}

/// Issue #12: an execution error with "Break on error" set stops the run on that scan, and
/// "Clear errors" turns the lamp off.
#[test]
fn break_on_error_stops_the_run_on_the_erring_scan() {
    let opennet = servoscope_core::registry::by_name("opennet").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        opennet,
        "err.opennet",
        "LOD I0\nDIV(W) 1 0 D0\nLOD M8121\nINC(W) D1\nEND",
    );
    let mut h = harness(app);
    // The dialect's panels stack as tabs: bring "Logic and errors" to the front.
    h.get_by_label("Logic and errors").click();
    h.run_steps(2);
    h.get_by_label("Break on error").click();
    h.run_steps(2);
    assert!(h.state().debugger.break_on_error());
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    h.run_steps(3);
    assert!(h.state().debugger.is_running(), "no error yet: it runs");
    // Switch I0 on: the next scan divides by zero and the run stops in it.
    let i0 = h.state().debugger.machine().find("I0").unwrap();
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::Debug(Action::SetInput(i0, true)),
    );
    h.run_steps(4);
    let d = &h.state().debugger;
    assert!(!d.is_running(), "stopped by the error");
    let m = d
        .machine_as::<servoscope_core::machine::opennet::OpenNet>()
        .unwrap();
    let e = m.last_error.expect("an error record");
    assert_eq!(e.kind, "divide_by_zero");
    assert_eq!(e.tick, m.ticks(), "stopped inside the scan that erred");
    assert_eq!(m.step, 2, "right after the DIV");
    h.get_by_label_contains("Execution error: stopped before line 3");
    h.get_by_label("M8004 ERROR");
    h.get_by_label("Clear errors").click();
    h.run_steps(2);
    assert!(!h.state().debugger.machine().error_lamp());
    h.get_by_label("M8004 no error");
}

/// Issue #11: a DL205 scan stepped instruction by instruction, the accumulator stack panel
/// showing each push and pop.
#[test]
fn a_dl205_scan_steps_through_the_stack_panel() {
    let dl205 = servoscope_core::registry::by_name("dl205").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        dl205,
        "subs.dl205",
        "STR SP1\nLDD K00172056\nLDD K00395026\nSUBS\nOUTD V1500\nEND",
    );
    let mut h = harness(app);
    h.get_by_label("Accumulator stack");
    for _ in 0..3 {
        h.key_press(Key::F10);
        h.run_steps(2);
    }
    // The second load pushed the first into L1.
    h.get_by_label("00172056 pushed in");
    h.get_by_label("load pending: the next load pushes ACC");
    let m = h.state().debugger.machine();
    assert_eq!(m.read(m.find("L1").unwrap()), 0x0017_2056);
    h.key_press(Key::F10);
    h.run_steps(2);
    h.get_by_label("00172056 popped; levels rose");
    let m = h.state().debugger.machine();
    assert_eq!(m.read(m.find("ACC").unwrap()), 0x0022_2970);
    assert_eq!(m.pos(), servoscope_core::machine::Pos { tick: 0, step: 4 });
    // The rung panel (the stack panel's neighbour tab) shows the power after each instruction.
    h.get_by_label("Rung power").click();
    h.run_steps(2);
    h.get_by_label_contains("SP1 is closed");
    // Step back inside the scan: the push is back.
    h.state_mut().debugger.step_back_command();
    h.run_steps(2);
    let m = h.state().debugger.machine();
    assert_eq!(m.read(m.find("L1").unwrap()), 0x0017_2056);
    // The status bar speaks of scans.
    h.state_mut().debugger.goto_tick(0);
    h.run_steps(2);
    h.get_by_label("At scan 0");
}

/// Issue #22 item 16: before the first scan the PLC is not running, so neither SP0 (first scan)
/// nor SP1 (always on) is lit; once scan 0 starts both are on, and from scan 1 only SP1.
#[test]
fn sp0_and_sp1_are_unlit_before_the_first_scan() {
    let dl205 = servoscope_core::registry::by_name("dl205").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(dl205, "sp.dl205", "STR X0\nOUT Y0\nEND");
    // A PLC opens with its I/O board in front of Bits: bring Bits forward.
    app.layout.focus(&servoscope::ui::layout::Pane::Bits);
    let mut h = harness(app);
    h.get_by_label("SP0 not driven before the first scan");
    h.get_by_label("SP1 not driven before the first scan");
    let chip = |h: &Harness<'static, ServoscopeApp>, name: &str| {
        egui_kittest::kittest::NodeT::accesskit_node(&h.get_by_label(name)).toggled()
            == Some(egui::accesskit::Toggled::True)
    };
    h.key_press(Key::F11);
    h.run_steps(2);
    assert!(
        chip(&h, "SP0") && chip(&h, "SP1"),
        "scan 0: first scan and always on"
    );
    h.state_mut().debugger.goto_tick(1);
    h.run_steps(2);
    h.key_press(Key::F11);
    h.run_steps(2);
    assert!(
        !chip(&h, "SP0") && chip(&h, "SP1"),
        "scan 1: only always on"
    );
}

/// Issue #22 item 18: at 900×600 the plot's buttons stay on one row above the plot (they
/// wrapped over the axis label) and one error's Problems list is as tall as its rows (it took
/// a third of the program's room).
#[test]
fn at_900x600_the_plot_buttons_fit_one_row_and_problems_fit_their_rows() {
    let tml = servoscope_core::registry::by_name("tml").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        tml,
        "moves.tml",
        include_str!("../../assets/examples/moves.tml"),
    );
    let mut h = Harness::builder()
        .with_size(egui::vec2(900.0, 600.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(3);
    let fit = h.get_by_label("Fit").rect();
    let csv = h.get_by_label("CSV…").rect();
    let channels = h.get_by_label("Channels").rect();
    assert!(
        (fit.top() - csv.top()).abs() < 1.0 && (channels.top() - csv.top()).abs() < 1.0,
        "one row: {fit:?} {channels:?} {csv:?}"
    );

    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(tml, "bad.tml", "int a;\na = ;\n");
    let mut h = Harness::builder()
        .with_size(egui::vec2(900.0, 600.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(3);
    let header = h.get_by_label_contains("Problems (1)").rect();
    let pane_bottom = h.get_by_label("Timeline").rect().top();
    assert!(
        pane_bottom - header.top() < 80.0,
        "the list is as tall as its one row: from {} to {pane_bottom}",
        header.top()
    );
}

/// Issue #23: the Timers & counters panel shows each box with its preset, its current value
/// as time, and its done bit; clicking the box shows its line.
#[test]
fn the_timers_panel_shows_time_and_done() {
    let dl205 = servoscope_core::registry::by_name("dl205").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        dl205,
        "traffic_light.dl205",
        include_str!("../../assets/examples/traffic_light.dl205"),
    );
    let mut h = harness(app);
    h.get_by_label("Timers & counters").click();
    h.run_steps(2);
    h.get_by_label("TMR T0");
    h.get_by_label("T0 not done");
    h.state_mut().debugger.goto_tick(300);
    h.run_steps(2);
    h.get_by_label("TA0 = 3.0 s");
    h.get_by_label("12.0 s");
    h.state_mut().debugger.goto_tick(1200);
    h.run_steps(2);
    h.get_by_label("T0 done");
    h.get_by_label("TMR T0").click();
    h.run_steps(2);
    assert_eq!(h.state().code.cursor_line, Some(7));
}

/// Issue #23: the Stages panel lists every SG/ISG with its state and the instruction that
/// last changed it; clicking that goes back to just after it.
#[test]
fn the_stages_panel_follows_the_stages() {
    let dl205 = servoscope_core::registry::by_name("dl205").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        dl205,
        "push_on_off.dl205",
        include_str!("../../assets/examples/push_on_off.dl205"),
    );
    let mut h = harness(app);
    // A program with stages opens on the Stages panel.
    let stages = servoscope::ui::layout::Pane::Dialect("Stages".into());
    assert!(h.state().layout.is_shown(&stages));
    h.get_by_label("S0 active");
    h.get_by_label("S1 off");
    h.state_mut().debugger.goto_tick(2);
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().ticks(), 2);
    let x0 = h.state().debugger.machine().find("X0").expect("X0");
    h.state_mut().debugger.set_value(x0, 1).expect("an input");
    h.state_mut().debugger.goto_tick(3);
    h.run_steps(2);
    h.get_by_label("S1 active");
    h.get_by_label("S0 clean-up pending");
    // Both stages were changed by the JMP: S0's row comes first.
    h.get_all_by_label_contains("changed by line 8 at scan 2")
        .next()
        .expect("S0's change")
        .click();
    h.run_steps(2);
    let m = h.state().debugger.machine();
    assert_eq!(m.ticks(), 2, "back in the scan of the jump");
    assert_eq!(m.read(m.find("S1").unwrap()), 1);
}

#[test]
fn a_session_with_a_breakpoint_past_the_end_opens_and_says_what_it_dropped() {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-far-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let session = dir.join("far.ron");
    std::fs::write(
        &session,
        "(format: 2, dialect: \"silverlode\", program: \"WRP 20, 1\\nEND\\n\", \
         breakpoint_list: [(kind: Line(0x14294967295)), (kind: Line(2))])",
    )
    .unwrap();
    let mut h = harness(app_with("END"));
    h.state_mut().open_path(session);
    h.run_steps(2);
    h.get_by_label_contains("the breakpoint on line 1385472357013 was dropped");
    assert_eq!(
        h.state()
            .debugger
            .breakpoints()
            .into_iter()
            .collect::<Vec<_>>(),
        vec![2]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_long_search_back_says_so_in_the_status_bar_and_pause_cancels_it() {
    let mut h = harness(app_with("loop: CLC INC, 20\nJMP loop\n"));
    // Far enough that the search is still going after the frames a click takes (kittest steps
    // one frame per event: pointer move, press, release), also in a release build: at 10 times
    // the ticks searched at once, it was over before the click landed.
    let far = 400 * servoscope_core::debugger::BACK_TICKS_AT_ONCE;
    h.state_mut().debugger.goto_tick(far);
    for _ in 0..2_000 {
        h.step();
        if h.state().debugger.pos().tick == far {
            break;
        }
    }
    assert_eq!(h.state().debugger.pos().tick, far);
    h.state_mut()
        .debugger
        .add_breakpoint(servoscope_core::debugger::Breakpoint::line(1).with_condition("R20 < 0"));
    h.state_mut().debugger.reverse_continue();
    h.run_steps(1);
    h.get_by_label_contains("searching back");
    h.get_by_label("Pause").click();
    h.run_steps(2);
    assert!(!h.state().debugger.is_running());
    assert_eq!(h.state().debugger.pos().tick, far, "where it started");
}

#[test]
fn recent_files_are_remembered_as_absolute_paths() {
    // Tests run in the package's folder, so this relative path names a real file.
    let relative = std::path::PathBuf::from("assets/examples/call_ret.qsl");
    let mut h = harness(app_with("END"));
    h.state_mut().open_path(relative.clone());
    h.run_steps(1);
    let recent = &h.state().prefs.recent;
    assert!(recent[0].is_absolute(), "{recent:?}");
    assert_eq!(recent[0], std::env::current_dir().unwrap().join(&relative));
    // Opened again by either name: one entry.
    h.state_mut()
        .open_path(std::env::current_dir().unwrap().join(&relative));
    h.run_steps(1);
    assert_eq!(h.state().prefs.recent.len(), 1);
}

#[test]
fn the_channels_popup_stays_open_while_its_field_is_used() {
    let mut h = harness(app_with("WRP 20, 5\nEND\n"));
    h.get_by_label("Channels").click();
    h.run_steps(2);
    // A click into the field: the popup stays, the field takes the typing.
    h.get_by_label("Add channel").click();
    h.run_steps(2);
    h.get_by_label("Add channel").focus();
    h.run_steps(1);
    h.get_by_label("Add channel").type_text("R20");
    h.run_steps(1);
    h.key_press(Key::Enter);
    h.run_steps(2);
    assert!(
        h.state()
            .debugger
            .channel_choices()
            .iter()
            .any(|c| c.location == "R20"),
        "{:?}",
        h.state().debugger.channel_choices()
    );
}

#[test]
fn a_channels_plot_is_chosen_inside_the_channels_popup() {
    let mut h = harness(app_with("WRP 20, 5\nEND\n"));
    h.get_by_label("Channels").click();
    h.run_steps(2);
    let first = h.state().debugger.channel_choices()[0].clone();
    let other = if first.group == 2 { 4 } else { 3 };
    h.get_by_label(&format!("{} on plot {other}", first.location))
        .click();
    h.run_steps(2);
    assert_eq!(
        h.state().debugger.channel_choices()[0].group,
        other as u8 - 1
    );
    // The popup is still open.
    h.get_by_label("Add channel");
}

/// Issue #22 item 17: F10 steps over a CALL, F11 into it, Shift+F11 out of it; the toolbar
/// offers "Step out" inside a subroutine and the Debug menu names the keys.
#[test]
fn the_stepping_keys_go_over_into_and_out_of_a_call() {
    let mut h = harness(app_with(include_str!("../../assets/examples/call_ret.qsl")));
    let line = |h: &Harness<'static, ServoscopeApp>| h.state().debugger.machine().pc_line();
    h.key_press(Key::F10);
    h.run_steps(2);
    assert_eq!(line(&h), Some(11), "at the CALL");
    assert!(
        h.query_by_label("Step out").is_none(),
        "not inside a subroutine"
    );
    h.key_press(Key::F10);
    h.run_steps(3);
    assert_eq!(line(&h), Some(12), "over the CALL");
    for _ in 0..3 {
        h.key_press(Key::F10);
        h.run_steps(2);
    }
    assert_eq!(line(&h), Some(11));
    h.key_press(Key::F11);
    h.run_steps(2);
    assert_eq!(line(&h), Some(18), "into square_n");
    h.get_by_label("Step out");
    h.key_press_modifiers(Modifiers::SHIFT, Key::F11);
    h.run_steps(3);
    assert_eq!(line(&h), Some(12), "out to the caller");
    h.get_by_label("Debug").click();
    h.run_steps(2);
    h.get_by_label_contains("Step out (until the subroutine returns)");
    h.get_by_label_contains("Step into (one");
}

/// OpenNet's timers count down: the Timers & counters panel shows each with its preset, its
/// current value as time, the time gone and the scans to go, and its output lamp.
#[test]
fn the_opennet_timers_panel_counts_down() {
    let opennet = servoscope_core::registry::by_name("opennet").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        opennet,
        "traffic_light.opennet",
        include_str!("../../assets/examples/traffic_light.opennet"),
    );
    let mut h = harness(app);
    // A program with timers opens on their panel.
    let boxes = servoscope::ui::layout::Pane::Dialect("Timers & counters".into());
    assert!(h.state().layout.is_shown(&boxes));
    h.get_by_label("TIM T0");
    h.get_by_label("T0 not done");
    let i0 = h.state().debugger.machine().find("I0").expect("I0");
    h.state_mut()
        .debugger
        .set_input(i0, true)
        .expect("an input");
    // T0 (preset 50 × 100 ms) first powered in scan 0; after scan 299: 29 tenths and 90 ms
    // gone, 21 left: 2100 − 90 = 2010 ms = 201 scans to go (on in scan 500).
    h.state_mut().debugger.goto_tick(300);
    for _ in 0..200 {
        if h.state().debugger.machine().ticks() == 300 {
            break;
        }
        h.run_steps(1);
    }
    h.run_steps(2);
    h.get_by_label("T0.current = 2.1 s");
    assert!(
        h.get_all_by_label("2990 ms elapsed, 201 scans to go")
            .next()
            .is_some()
    );
    assert_eq!(
        h.get_all_by_label("5.0 s").count(),
        2,
        "T0 and T2 preset 5 s"
    );
    h.get_by_label("2.0 s");
    h.state_mut().debugger.goto_tick(501);
    for _ in 0..200 {
        if h.state().debugger.machine().ticks() == 501 {
            break;
        }
        h.run_steps(1);
    }
    h.run_steps(2);
    h.get_by_label("T0 done");
    h.get_by_label("TIM T0").click();
    h.run_steps(2);
    assert_eq!(h.state().code.cursor_line, Some(22));
}

/// A MICRO3 relay the program never writes is a warning in Problems; the program still runs.
#[test]
fn an_opennet_warning_is_listed_and_the_program_runs() {
    let opennet = servoscope_core::registry::by_name("opennet").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(opennet, "micro3.opennet", "LOD M303\nOUT Q0\n");
    let mut h = harness(app);
    h.run_steps(2);
    h.get_by_label("Problems (1)");
    h.get_by_label("Warnings only: the program runs.");
    h.get_by_label_contains("warning: M303 is the MICRO3 carry/borrow relay");
    h.key_press(egui::Key::F10);
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().steps(), 1, "F10 stepped");
}

/// OpenNet's scan time is in its settings window; applying it restarts the program on it.
#[test]
fn the_opennet_scan_time_is_a_setting() {
    let opennet = servoscope_core::registry::by_name("opennet").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(opennet, "t.opennet", "LOD M8125\nTIM T0 10\n");
    let mut h = harness(app);
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::OpenSettings,
    );
    h.run_steps(2);
    h.get_by_label("IDEC OpenNet settings");
    h.get_by_label("Scan time (ms)");
    if let Some(draft) = h.state_mut().settings.draft.as_mut() {
        draft.insert("scan_ms".into(), 50.0);
    }
    h.run_steps(1);
    h.get_by_label("Apply").click();
    h.run_steps(2);
    assert_eq!(h.state().debugger.settings()["scan_ms"], 50.0);
    assert_eq!(h.state().debugger.machine().tick_micros(), 50_000);
    assert_eq!(h.state().session().settings["scan_ms"], 50.0);
}

/// Issue #25: a PLC program opens with its Ladder beside the Program; clicking an element goes
/// to its line and register, clicking a rung's rail sets a breakpoint, stepping moves the power
/// flow, and the I/O board switches inputs and forces bits from a right-click.
#[test]
fn the_ladder_and_the_io_board_drive_the_debugger() {
    let dl205 = servoscope_core::registry::by_name("dl205").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        dl205,
        "t.dl205",
        "STR X0       // start\nOUT Y0\nSTR Y0\nOUT Y1\nEND\n",
    );
    let mut h = harness(app);
    assert!(
        h.state()
            .layout
            .is_shown(&servoscope::ui::layout::Pane::Dialect("Ladder".into())),
        "the Ladder opens with a PLC program"
    );
    // Click X0's contact: its line and its register.
    h.get_by_label("Ladder X0 line 1").click();
    h.run_steps(2);
    let x0 = h.state().debugger.machine().find("X0").expect("X0");
    assert_eq!(h.state().registers.selected, Some(x0));
    assert_eq!(
        h.state().code.cursor_line,
        Some(1),
        "the program is at its line"
    );
    // The rail of rung 1 toggles a breakpoint on its first line.
    h.get_by_label("Ladder rung 1 rail").click();
    h.run_steps(2);
    assert!(h.state().debugger.breakpoints().contains(&3));
    // The I/O board: a click switches X0, and the scan turns Y0 on.
    h.get_by_label("I/O board").click();
    h.run_steps(2);
    h.get_by_label("X0 lamp").click();
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().read(x0), 1);
    h.key_press(Key::F8);
    h.run_steps(3);
    let y1 = h.state().debugger.machine().find("Y1").expect("Y1");
    assert_eq!(
        h.state().debugger.machine().read(y1),
        1,
        "one scan: Y0 then Y1"
    );
    // Right-click Y0's lamp: Force Y0 OFF holds it off against the program.
    h.get_by_label("Y0 lamp").click_secondary();
    h.run_steps(2);
    h.get_by_label("Force Y0 OFF").click();
    h.run_steps(2);
    let y0 = h.state().debugger.machine().find("Y0").expect("Y0");
    assert_eq!(h.state().debugger.machine().forced(y0), Some(false));
    h.key_press(Key::F8);
    h.run_steps(3);
    let m = h.state().debugger.machine();
    assert_eq!(
        (m.read(y0), m.read(y1)),
        (0, 0),
        "forced off, and Y1 reads it"
    );
    // The forces list releases it.
    h.get_by_label("Release all").click();
    h.run_steps(2);
    assert!(h.state().debugger.machine().forces().is_empty());
}
