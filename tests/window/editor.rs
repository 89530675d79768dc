//! The program editor as a user types in it: find, go to line, indentation kept on Enter,
//! PageUp/PageDown, a click below the text, a problem clicked, a value shown on hover.

use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use servoscope::ui::code::{find_match, hover_value};
use servoscope::ui::{Prefs, ServoscopeApp};

fn harness(source: &str) -> Harness<'static, ServoscopeApp> {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("test.qsl", source);
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(2);
    h
}

fn focus_editor(h: &mut Harness<'static, ServoscopeApp>) {
    h.get_by_role(egui::Role::MultilineTextInput).focus();
    h.run_steps(2);
}

fn caret(h: &Harness<'static, ServoscopeApp>) -> (Option<usize>, Option<usize>) {
    (h.state().code.cursor_line, h.state().code.cursor_char)
}

#[test]
fn clicking_a_problem_puts_the_caret_on_its_line_and_column() {
    let mut h = harness("WRP 20, 1\nWRP 20, 2\nJMP nowhere\n");
    h.get_by_label_contains("undefined label 'nowhere'").click();
    h.run_steps(3);
    // Line 3, column 5 (where `nowhere` starts): character 20 + 4.
    assert_eq!(caret(&h), (Some(3), Some(24)));
    assert!(
        h.get_by_role(egui::Role::MultilineTextInput).is_focused(),
        "typing goes to the editor"
    );
}

#[test]
fn ctrl_f_finds_the_next_and_previous_match() {
    let source = "WRP 20, 1\nCLC INC, 20\nWRP 20, 3\nEND\n";
    let mut h = harness(source);
    focus_editor(&mut h);
    h.key_press_modifiers(Modifiers::COMMAND, Key::F);
    h.run_steps(2);
    assert!(
        h.get_by_label("Find in program").is_focused(),
        "typing goes to the field"
    );
    h.get_by_label("Find in program").type_text("wrp");
    h.state_mut().code.cursor_char = Some(0);
    h.key_press(Key::Enter);
    h.run_steps(3);
    // From the start, the next match is the one on line 3 (case ignored), selected: the caret
    // at its end.
    let third = source.find("WRP 20, 3").unwrap();
    assert_eq!(caret(&h), (Some(3), Some(third + 3)));
    h.get_by_label_contains("2 of 2");
    assert_eq!(h.state().debugger.source(), source, "the text is untouched");
    h.get_by_label("Next").click();
    h.run_steps(3);
    assert_eq!(caret(&h), (Some(1), Some(3)), "wraps to the first");
    h.get_by_label_contains("1 of 2");
    h.get_by_label("Previous").click();
    h.run_steps(3);
    assert_eq!(caret(&h), (Some(3), Some(third + 3)), "back over the start");
    h.get_by_label("Find in program").focus();
    h.step();
    h.get_by_label("Find in program").type_text("x");
    h.get_by_label("Next").click();
    h.run_steps(2);
    h.get_by_label("not found");
    h.get_by_label("Close bar").click();
    h.run_steps(2);
    assert!(h.query_by_label("Find in program").is_none());
}

#[test]
fn ctrl_g_goes_to_a_line() {
    let source: String = (1..=200).map(|i| format!("WRP 20, {i}\n")).collect();
    let mut h = harness(&source);
    focus_editor(&mut h);
    h.key_press_modifiers(Modifiers::COMMAND, Key::G);
    h.run_steps(2);
    h.get_by_label("Go to line").type_text("150");
    h.key_press(Key::Enter);
    h.run_steps(3);
    assert_eq!(h.state().code.cursor_line, Some(150));
    assert!(h.query_by_label("Go to line").is_none(), "the bar closes");
    // The line is on screen, in the program panel.
    let row = h.get_by_label("Breakpoint line 150").rect();
    let program = h
        .state()
        .layout
        .pane_rect(&servoscope::ui::layout::Pane::Program)
        .expect("program shown");
    assert!(program.contains_rect(row), "{row:?} in {program:?}");

    h.key_press_modifiers(Modifiers::COMMAND, Key::G);
    h.run_steps(2);
    h.get_by_label("Go to line").type_text("900");
    h.key_press(Key::Enter);
    h.run_steps(2);
    h.get_by_label_contains("not a line: 1 to 200");
    assert_eq!(h.state().code.cursor_line, Some(150));
}

#[test]
fn enter_keeps_the_indentation() {
    let mut h = harness("loop:\n    WRP 20, 1\n");
    h.state_mut().code.pending_jump = Some(servoscope::ui::code::Jump {
        line: 2,
        col: 100,
        len: 0,
    });
    h.run_steps(2);
    h.key_press(Key::Enter);
    h.run_steps(2);
    h.get_by_role(egui::Role::MultilineTextInput)
        .type_text("WRP 20, 2");
    h.run_steps(2);
    assert_eq!(
        h.state().debugger.source(),
        "loop:\n    WRP 20, 1\n    WRP 20, 2\n"
    );
}

#[test]
fn page_down_and_page_up_move_by_a_screen() {
    let source: String = (1..=300).map(|i| format!("WRP 20, {i}\n")).collect();
    let mut h = harness(&source);
    focus_editor(&mut h);
    h.state_mut().code.pending_jump = Some(servoscope::ui::code::Jump::line(1));
    h.run_steps(2);
    h.key_press(Key::PageDown);
    h.run_steps(2);
    let after = h.state().code.cursor_line.expect("a caret");
    assert!(after > 10, "moved a screenful down: line {after}");
    h.get_by_label(&format!("Breakpoint line {after}"));
    h.key_press(Key::PageUp);
    h.run_steps(2);
    assert_eq!(h.state().code.cursor_line, Some(1));
}

#[test]
fn a_click_below_the_last_line_puts_the_caret_at_the_end() {
    let mut h = harness("WRP 20, 1\nEND");
    let editor = h.get_by_role(egui::Role::MultilineTextInput).rect();
    // Well below the two lines, inside the program panel.
    let below = egui::pos2(editor.left() + 40.0, editor.bottom() + 60.0);
    h.input_mut().events.push(egui::Event::PointerMoved(below));
    h.step();
    for pressed in [true, false] {
        h.input_mut().events.push(egui::Event::PointerButton {
            pos: below,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        });
        h.step();
    }
    h.run_steps(2);
    assert_eq!(caret(&h), (Some(2), Some(13)));
    assert!(h.get_by_role(egui::Role::MultilineTextInput).is_focused());
}

#[test]
fn find_match_wraps_and_counts() {
    let text = "ab AB ab";
    assert_eq!(find_match(text, "ab", 0, false), Some((0, 3, 1)));
    assert_eq!(find_match(text, "ab", 1, false), Some((3, 3, 2)));
    assert_eq!(find_match(text, "ab", 7, false), Some((0, 3, 1)), "wraps");
    assert_eq!(find_match(text, "ab", 3, true), Some((0, 3, 1)));
    assert_eq!(
        find_match(text, "ab", 0, true),
        Some((6, 3, 3)),
        "wraps back"
    );
    assert_eq!(find_match(text, "zz", 0, false), None);
    assert_eq!(find_match(text, "", 0, false), None);
    // Character positions, not bytes, after non-ASCII text.
    assert_eq!(find_match("é ab", "AB", 0, false), Some((2, 1, 1)));
}

#[test]
fn hovering_shows_values_in_every_format() {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("test.qsl", "DEF speed = R30\nWRP speed, q16(1.5)\nEND\n");
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(2);
    h.key_press(Key::F10);
    h.run_steps(2);
    let m = h.state().debugger.machine();
    // R30 now holds 1.5 in Q16.16 = 98304.
    let by_name = hover_value(m, "speed").expect("a DEF name");
    let by_register = hover_value(m, "R30").expect("a register");
    assert_eq!(by_name, by_register);
    for expected in ["98304", "0x0001_8000", "1.5", "Q16.16", "BCD"] {
        assert!(by_name.contains(expected), "{expected} in {by_name}");
    }
    let literal = hover_value(m, "q16(1.5)").expect("a literal");
    assert!(literal.contains("98304") && literal.contains("0x0001_8000"));
    assert_eq!(hover_value(m, "WRP"), None);

    // Through the window: the pointer over `speed` on line 2 shows the same.
    let row = h.get_by_label("Breakpoint line 2").rect();
    let editor = h.get_by_role(egui::Role::MultilineTextInput).rect();
    let char_width = 7.0;
    let over = egui::pos2(editor.left() + char_width * 6.0, row.center().y);
    h.input_mut().events.push(egui::Event::PointerMoved(over));
    h.run_steps(6);
    h.get_by_label_contains("  Q16.16  1.5");
}

#[test]
fn hovering_a_relay_or_an_input_says_on_or_off_only() {
    let opennet = servoscope_core::registry::by_name("opennet").expect("registered");
    let mut d = servoscope_core::debugger::Debugger::with_dialect(
        opennet,
        "relay.opennet",
        "LOD I0\nOUT M0\nEND\n",
    );
    let i0 = d.find("I0").expect("an input");
    d.set_input(i0, true).expect("switched");
    d.step_tick();
    let m0 = hover_value(d.machine(), "M0").expect("a relay");
    assert!(m0.lines().any(|l| l == "ON"), "{m0}");
    for reading in ["signed", "Q16.16", "-1", "−1"] {
        assert!(!m0.contains(reading), "{reading} in {m0}");
    }
    let q0 = hover_value(d.machine(), "Q0").expect("an output");
    assert!(q0.lines().any(|l| l == "OFF"), "{q0}");
}

/// Issue #22 item 5: a DEF constant shows its value on hover and may be used in watches and
/// conditions (`next * gain >> 16` said "no location named gain").
#[test]
fn a_def_constant_is_shown_on_hover_and_usable_in_watches_and_conditions() {
    let source = include_str!("../../assets/examples/fixed_point.qsl");
    let mut d = servoscope_core::debugger::Debugger::new("fixed_point.qsl", source);
    assert!(d.diagnostics().is_empty());
    // q16(0.0254) = round(0.0254 × 65536) = 1665 (the example's own comment).
    let hover = hover_value(d.machine(), "mm_per_count").expect("a constant");
    for expected in ["mm_per_count", "1665", "0x0000_0681", "Q16.16  0.025406"] {
        assert!(hover.contains(expected), "{expected} in {hover}");
    }
    d.step_command();
    assert_eq!(
        d.evaluate("counts * mm_per_count >> 16"),
        Ok((40000 * 1665) >> 16)
    );
    assert_eq!(d.evaluate("mm_per_count.0"), Ok(1), "1665 is odd");
    let w = d.add_watch(
        "counts * mm_per_count >> 16",
        servoscope_core::machine::Format::Signed,
    );
    assert_eq!(d.watch_value(w), Ok(1016));
    // A condition with the constant: false on line 16 (before the CLD), true on line 22.
    for line in [16, 22] {
        d.add_breakpoint(servoscope_core::debugger::Breakpoint {
            condition: "millimetres == counts * mm_per_count >> 16".into(),
            ..servoscope_core::debugger::Breakpoint::line(line)
        });
    }
    d.set_speed(servoscope_core::debugger::Speed::Unlimited);
    d.run();
    while d.advance(0.016, std::time::Duration::from_millis(200)) {}
    assert_eq!(
        d.machine().pc_line(),
        Some(22),
        "stopped where the condition holds"
    );
    assert!(
        d.evaluate("no_such_name").is_err(),
        "other names are still unknown"
    );
}

/// #43 item 11: when a long line is scrolled into view sideways, the
/// line numbers stay in view at the panel's left edge (they scrolled away with the text).
#[test]
fn line_numbers_stay_put_when_a_long_line_scrolls_sideways() {
    let long = format!("WRP 20, 1 ; {}\n", "a long comment ".repeat(40));
    let source = format!("{long}WRP 21, 2\nEND\n");
    let mut h = harness(&source);
    let program = h
        .state()
        .layout
        .pane_rect(&servoscope::ui::layout::Pane::Program)
        .expect("program shown");
    h.event(egui::Event::PointerMoved(program.center()));
    h.run_steps(1);
    for _ in 0..10 {
        h.event(egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(-300.0, 0.0),
            phase: egui::TouchPhase::Move,
            modifiers: Modifiers::NONE,
            source: egui::MouseWheelSource::Wheel,
        });
        h.step();
    }
    h.run_steps(4);
    let editor = h.get_by_role(egui::Role::MultilineTextInput).rect();
    assert!(
        editor.left() < program.left() - 100.0,
        "scrolled: {editor:?}"
    );
    for line in 1..=3 {
        let row = h.get_by_label(&format!("Breakpoint line {line}")).rect();
        assert!(
            row.left() >= program.left() && row.right() < program.left() + 80.0,
            "line {line}: {row:?} at the left of {program:?}"
        );
    }
}
