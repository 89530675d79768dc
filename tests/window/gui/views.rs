//! Queues, the plot, export, stepping back, the timeline and sessions saved and reopened.

use super::*;

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

/// #43 item 16: a big slot value reads as a number a student reads (it was `-2.1e9`), three
/// significant digits with k, M or G; small ones exactly.
#[test]
fn big_slot_values_read_in_k_m_and_g() {
    use servoscope::ui::dialects::silverlode::queues::compact;
    assert_eq!(compact(99_999), "99999");
    assert_eq!(compact(-99_999), "-99999");
    assert_eq!(compact(123_456), "123k");
    assert_eq!(compact(999_999), "1.00M", "not 1000k");
    assert_eq!(compact(1_234_567), "1.23M");
    assert_eq!(compact(i32::MIN), "-2.15G");
    assert_eq!(compact(i32::MAX), "2.15G");
}

/// #43 item 16: with head = tail the H and T letters never print on top of each other, in a
/// small ring (one "H T" outside) or a large one (H outside, T inside): the large one, in a
/// maximised Queues panel, drew both outside.
#[test]
fn head_and_tail_letters_never_overlap() {
    let mut h = harness(app_with("CLD Q_INIT, 10, 40, 4\nEND"));
    step_n(&mut h, 1);
    let queues = servoscope::ui::layout::Pane::Dialect("Queues".into());
    let letters = |h: &Harness<'static, ServoscopeApp>| {
        let head = h.get_by_label("Queue R40 head at slot 0").rect();
        let tail = h.get_by_label("Queue R40 tail at slot 0").rect();
        (head, tail)
    };
    // A small ring: one "H T" pair outside, both marks at its place.
    let (head, tail) = letters(&h);
    assert_eq!(head, tail, "one pair of letters");
    let tile = h
        .state()
        .layout
        .tree
        .tiles
        .find_pane(&queues)
        .expect("the Queues panel");
    let ctx = h.ctx.clone();
    h.state_mut()
        .apply(&ctx, servoscope::ui::Command::ToggleMaximise(tile));
    h.run_steps(3);
    assert!(h.state().layout.maximised.is_some());
    // A large ring: H outside, T inside, apart.
    let (head, tail) = letters(&h);
    assert!(!head.intersects(tail), "H {head:?} and T {tail:?}");
}
