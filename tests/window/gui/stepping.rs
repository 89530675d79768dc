//! The window's first steps: opening, stepping, breakpoints, running, editing values and text, faults, inputs and opening files.

use super::*;

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
