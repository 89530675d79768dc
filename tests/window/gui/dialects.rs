//! Every dialect through the window: TML values, break on error, DL205 and OpenNet panels, searches back, recent files, the channels popup, the ladder and the I/O board.

use super::*;

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
        include_str!("../../../assets/examples/moves.tml"),
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
        include_str!("../../../assets/examples/traffic_light.dl205"),
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
        include_str!("../../../assets/examples/push_on_off.dl205"),
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
    let mut h = harness(app_with(include_str!(
        "../../../assets/examples/call_ret.qsl"
    )));
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
        include_str!("../../../assets/examples/traffic_light.opennet"),
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
    // Its comment is its label (#43 item 13).
    h.get_by_label("X0 lamp (start)").click();
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().read(x0), 1);
    // F8 stops at the breakpoint on line 3 inside the scan, then finishes the scan.
    h.key_press(Key::F8);
    h.run_steps(3);
    assert_eq!(
        h.state().debugger.event(),
        Some(&servoscope_core::debugger::Event::Breakpoint(3))
    );
    h.key_press(Key::F8);
    h.run_steps(3);
    // The rail again: the breakpoint goes.
    h.get_by_label("Ladder rung 1 rail").click();
    h.run_steps(2);
    assert!(!h.state().debugger.breakpoints().contains(&3));
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

/// #43 item 13: an input made a push button is on while the button is held and off when it is
/// released (a switch stays as clicked); a DirectSOFT nickname labels its lamp.
#[test]
fn an_input_push_button_is_on_only_while_held() {
    let dl205 = servoscope_core::registry::by_name("dl205").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        dl205,
        "t.dl205",
        "#BEGIN ELEMENT_DOC\n\"X0\",\"START_PB\",\"\",\"Start\"\n#END\nSTR X0\nOUT Y0\nEND\n",
    );
    let mut h = harness(app);
    h.get_by_label("I/O board").click();
    h.run_steps(2);
    let lamp = "X0 lamp (START_PB — Start)";
    h.get_by_label(lamp).click_secondary();
    h.run_steps(2);
    h.get_by_label("Make it a push button (on while held)")
        .click();
    h.run_steps(2);
    let x0 = h.state().debugger.machine().find("X0").expect("X0");
    let centre = h.get_by_label(lamp).rect().center();
    h.event(egui::Event::PointerMoved(centre));
    h.event(egui::Event::PointerButton {
        pos: centre,
        button: egui::PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    h.run_steps(3);
    assert_eq!(h.state().debugger.machine().read(x0), 1, "on while held");
    h.run_steps(3);
    assert_eq!(h.state().debugger.machine().read(x0), 1, "still held");
    h.event(egui::Event::PointerButton {
        pos: centre,
        button: egui::PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    h.run_steps(3);
    assert_eq!(
        h.state().debugger.machine().read(x0),
        0,
        "off when released"
    );
}
