//! Settings, saving over files, long replays, long programs and the gutter, opening and saving files, lessons.

use super::*;

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

#[test]
fn a_long_replay_runs_in_the_background_and_can_be_cancelled() {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-long-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = harness(app_with("WRP 20, 5\nEND"));
    h.state_mut().open_path(endless_plc_session(&dir));
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

/// The `offset:(…)` of a scroll area's saved state in a session's window text.
fn saved_offset(window: &str, key: &str) -> Option<String> {
    let at = window.find(&format!("\"{key}\""))?;
    let rest = &window[at..];
    let start = rest.find("offset:")?;
    let end = start + rest[start..].find(')')?;
    Some(rest[start..=end].to_string())
}

/// #43 item 5: a reopened session shows the tabs in front and the code scrolled as they were
/// left.
#[test]
fn a_reopened_session_brings_back_its_tabs_and_scroll_positions() {
    let program: String = (0..120)
        .map(|i| format!("CLC INC, {}\n", 20 + i % 50))
        .collect();
    let mut h = harness(app_with(&format!("{program}END\n")));
    h.state_mut()
        .layout
        .focus(&servoscope::ui::layout::Pane::Log);
    h.state_mut().apply(
        &egui::Context::default(),
        servoscope::ui::Command::ShowLine(100),
    );
    h.run_steps(6);
    assert!(
        h.state()
            .layout
            .is_shown(&servoscope::ui::layout::Pane::Log)
    );
    let session = h.state().session();
    let window = session.window.clone().expect("the window's state");
    let code_offset = saved_offset(&window, "code").expect("the code view's scroll");
    assert!(
        !code_offset.contains("y:0.0"),
        "scrolled down: {code_offset}"
    );
    let dir = common::scratch_dir("window-state");
    let path = dir.join("left.ron");
    session.save(&path).expect("saved");

    let mut h = harness(app_with("END"));
    h.run_steps(2);
    assert!(
        !h.state()
            .layout
            .is_shown(&servoscope::ui::layout::Pane::Log),
        "a fresh window"
    );
    h.state_mut().open_path(path);
    h.run_steps(6);
    assert!(
        h.state()
            .layout
            .is_shown(&servoscope::ui::layout::Pane::Log),
        "the Log's tab in front"
    );
    let again = h.state().session().window.expect("the window's state");
    assert_eq!(saved_offset(&again, "code"), Some(code_offset));
    let _ = std::fs::remove_dir_all(&dir);
}

/// #43 item 12: a PLC program starts in real time (a 12 s traffic light at 10
/// instructions/s looked frozen), and a speed chosen for one dialect stays with it.
#[test]
fn each_dialect_starts_in_real_time_and_keeps_its_own_speed() {
    use servoscope_core::debugger::Speed;
    let dl205 = servoscope_core::registry::by_name("dl205").expect("DL205");
    let silverlode = servoscope_core::registry::by_name("silverlode").expect("SilverLode");
    let mut app = ServoscopeApp::new(Prefs::default());
    assert_eq!(app.debugger.speed(), Speed::RealTime(1.0));
    app.load_program_as(dl205, "lights.dl205", "STR X0\nOUT Y0\nEND\n");
    assert_eq!(app.debugger.speed(), Speed::RealTime(1.0));
    app.apply(
        &egui::Context::default(),
        servoscope::ui::Command::Debug(Action::SetSpeed(Speed::PerSecond(100.0))),
    );
    app.load_program_as(silverlode, "move.qsl", "WRP 20, 1\nEND\n");
    assert_eq!(
        app.debugger.speed(),
        Speed::RealTime(1.0),
        "not the PLC's choice"
    );
    app.load_program_as(dl205, "lights.dl205", "STR X0\nOUT Y0\nEND\n");
    assert_eq!(
        app.debugger.speed(),
        Speed::PerSecond(100.0),
        "the PLC's own again"
    );
}

#[test]
fn stored_preferences_naming_odd_files_change_nothing_about_opening_a_program() {
    // What a machine's stored preferences may hold after months of use: recent files since
    // deleted, a folder, a device, an absurd path, an include folder that is gone.
    let dir = std::env::temp_dir().join(format!("servoscope-gui-prefs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let program = dir.join("prog.qsl");
    std::fs::write(&program, "WRP 11, 7\nEND\n").unwrap();
    let odd = Prefs {
        recent: vec![
            dir.join("gone.qsl"),
            dir.clone(),
            std::path::PathBuf::from("/dev/null"),
            std::path::PathBuf::from("x".repeat(5_000)),
            program.clone(),
        ],
        include_folders: vec![dir.join("gone")],
        ..Prefs::default()
    };
    let opened = |prefs: Prefs| {
        let mut h = harness(ServoscopeApp::new(prefs));
        h.state_mut().open_path(program.clone());
        h.run_steps(3);
        let app = h.state();
        (
            app.debugger.name().to_string(),
            app.debugger.source().to_string(),
            app.debugger.has_errors(),
            app.path.clone(),
            app.notice.clone(),
        )
    };
    assert_eq!(opened(odd), opened(Prefs::default()));
    let _ = std::fs::remove_dir_all(&dir);
}
