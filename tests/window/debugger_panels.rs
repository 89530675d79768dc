//! The Breakpoints, Watches and Log panels and the "who wrote this?" menus, driven through
//! egui_kittest.

use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use servoscope::ui::layout::Pane;
use servoscope::ui::{Command, Prefs, ServoscopeApp};
use servoscope_core::debugger::{BreakKind, Breakpoint, DataTrigger, Event, Speed};
use servoscope_core::machine::silverlode::view::reg;
use servoscope_core::machine::value_of;

use crate::common;

const LOOP: &str = common::ROUNDS;

fn harness(source: &str) -> Harness<'static, ServoscopeApp> {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("test.qsl", source);
    app.debugger.set_speed(Speed::Unlimited);
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(2);
    h
}

fn r12(h: &Harness<'_, ServoscopeApp>) -> i64 {
    value_of(h.state().debugger.machine(), reg(12))
}

/// Press Run and let the run finish.
fn run(h: &mut Harness<'_, ServoscopeApp>) {
    h.get_by_label("Run").click();
    for _ in 0..50 {
        h.step();
        if !h.state().debugger.is_running() {
            break;
        }
    }
    h.run_steps(2);
}

fn open_tab(h: &mut Harness<'_, ServoscopeApp>, pane: Pane) {
    h.state_mut().layout.focus(&pane);
    h.run_steps(2);
}

fn type_into(h: &mut Harness<'_, ServoscopeApp>, label: &str, text: &str) {
    h.get_by_label(label).focus();
    h.step();
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.get_by_label(label).type_text(text);
    h.run_steps(2);
}

#[test]
fn a_condition_typed_in_the_list_panel_decides_the_stop() {
    let mut h = harness(LOOP);
    h.get_by_label("Breakpoint line 3").click();
    h.run_steps(2);
    open_tab(&mut h, Pane::Breakpoints);
    type_into(&mut h, "Condition of breakpoint 1", "R12 == 6");
    assert_eq!(
        h.state().debugger.breakpoint_list()[0].condition,
        "R12 == 6"
    );
    run(&mut h);
    assert_eq!(h.state().debugger.event(), Some(&Event::Breakpoint(3)));
    assert_eq!(r12(&h), 6);
    h.get_by_label_contains("hits: 1");
    // A condition that does not parse says where, and the breakpoint is inactive.
    type_into(&mut h, "Condition of breakpoint 1", "R12 ==");
    h.get_by_label_contains("Inactive: condition, column 7");
    // Disabled from its switch, then deleted.
    h.get_by_label("Enable breakpoint 1").click();
    h.run_steps(2);
    assert!(!h.state().debugger.breakpoint_list()[0].enabled);
    assert!(h.state().debugger.breakpoints().is_empty());
    h.get_by_label("Delete breakpoint 1").click();
    h.run_steps(2);
    assert!(h.state().debugger.breakpoint_list().is_empty());
}

#[test]
fn a_data_breakpoint_from_the_form_and_a_log_point_from_the_list() {
    let mut h = harness(LOOP);
    open_tab(&mut h, Pane::Breakpoints);
    type_into(&mut h, "Data breakpoint location", "r12");
    h.get_by_label("Add data breakpoint").click();
    h.run_steps(2);
    assert_eq!(
        h.state().debugger.breakpoint_list(),
        [Breakpoint::data("R12", DataTrigger::Write)]
    );
    run(&mut h);
    assert!(matches!(
        h.state().debugger.event(),
        Some(Event::Watchpoint {
            line: 3,
            new,
            ..
        }) if new == "1"
    ));
    h.get_by_label_contains("R12 written at line 3: 0 -> 1");
    // Turn it into a log point: the run no longer stops, the Log panel shows the messages.
    type_into(&mut h, "Log message of breakpoint 1", "R12 is {R12}");
    run(&mut h);
    assert_eq!(h.state().debugger.event(), Some(&Event::Ended));
    open_tab(&mut h, Pane::Log);
    h.get_by_label_contains("Log point messages (9)");
    h.get_by_label_contains("R12 is 10");
    // An unknown location is said at once and adds nothing.
    open_tab(&mut h, Pane::Breakpoints);
    type_into(&mut h, "Data breakpoint location", "R999");
    h.get_by_label("Add data breakpoint").click();
    h.run_steps(2);
    h.get_by_label_contains("there is no location named 'R999'");
    assert_eq!(h.state().debugger.breakpoint_list().len(), 1);
}

/// #43 item 1: "equals 12" on a DL205 V word is BCD 12 (0x0012), as the word is shown, and
/// the list says so in BCD.
#[test]
fn a_data_breakpoint_value_is_read_as_its_location_reads() {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        servoscope_core::registry::by_name("dl205").expect("DL205 is registered"),
        "parts.dl205",
        include_str!("../../assets/examples/parts_counter.dl205"),
    );
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(2);
    open_tab(&mut h, Pane::Breakpoints);
    type_into(&mut h, "Data breakpoint location", "V1000");
    h.get_by_label("Data breakpoint trigger").click();
    h.run_steps(2);
    h.get_by_label("equals").click();
    h.run_steps(2);
    type_into(&mut h, "Data breakpoint value", "12");
    h.get_by_label("Add data breakpoint").click();
    h.run_steps(2);
    assert_eq!(
        h.state().debugger.breakpoint_list(),
        [Breakpoint::data("V1000", DataTrigger::Equal(0x12))]
    );
    h.get_by_label("V1000 becomes 12");
}

#[test]
fn watches_show_their_value_and_join_the_plot() {
    let mut h = harness(LOOP);
    open_tab(&mut h, Pane::Watches);
    type_into(&mut h, "New watch", "R12 * 100 + R11");
    h.get_by_label("Add").click();
    h.run_steps(2);
    assert_eq!(h.state().debugger.watches().len(), 1);
    run(&mut h);
    open_tab(&mut h, Pane::Watches);
    h.get_by_label("Value of watch 1: 1000");
    h.get_by_label("Plot watch 1").click();
    h.run_steps(2);
    assert!(
        h.state()
            .debugger
            .channels()
            .iter()
            .any(|c| c.name == "R12 * 100 + R11")
    );
    h.get_by_label("Delete watch 1").click();
    h.run_steps(2);
    assert!(h.state().debugger.watches().is_empty());
}

#[test]
fn who_wrote_from_the_register_menu_walks_back() {
    let mut h = harness(LOOP);
    run(&mut h);
    h.get_by_label("R13").click_secondary();
    h.run_steps(2);
    h.get_by_label("Who wrote R13?").click();
    h.run_steps(2);
    let d = &h.state().debugger;
    assert_eq!(d.machine().last_line(), Some(7), "WRP 13, 7 wrote it last");
    assert!(matches!(
        d.event(),
        Some(Event::WrittenBy { line: Some(7), .. })
    ));
    h.get_by_label_contains("R13 was written at tick");
    // Again: the write before, by line 4.
    h.get_by_label("R13").click_secondary();
    h.run_steps(2);
    h.get_by_label("Who wrote R13?").click();
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().last_line(), Some(4));
    // From the same menu: a data breakpoint.
    h.get_by_label("R13").click_secondary();
    h.run_steps(2);
    h.get_by_label("Break when R13 changes").click();
    h.run_steps(2);
    assert!(matches!(
        &h.state().debugger.breakpoint_list()[0].kind,
        BreakKind::Data { location, trigger: DataTrigger::Change } if location == "R13"
    ));
}

#[test]
fn the_log_lists_steps_goes_to_them_and_filters() {
    let mut h = harness(LOOP);
    for _ in 0..6 {
        h.key_press(Key::F10);
        h.run_steps(1);
    }
    open_tab(&mut h, Pane::Log);
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().steps(), 6, "six steps");
    let rows = &h.state().log.log.rows;
    assert_eq!(rows.len(), 6);
    assert_eq!(rows[0].line, 1);
    let third = rows[2].at;
    // The third step is line 3's CLC INC, which wrote R12 = 1.
    h.get_by_label_contains("-> R12=1").click();
    h.run_steps(3);
    assert_eq!(h.state().debugger.pos(), third, "going to the entry");
    assert_eq!(h.state().log.log.rows.len(), 3, "the log ends where we are");
    // Filter: writes to R13.
    h.state_mut().log.filter_kind = 2;
    h.run_steps(2);
    type_into(&mut h, "Log filter", "R13");
    h.run_steps(2);
    assert_eq!(h.state().log.log.rows.len(), 1, "only WRP 13 so far");
    // Export what is shown.
    let path = std::env::temp_dir().join(format!("servoscope-log-{}.csv", std::process::id()));
    h.state_mut()
        .apply(&egui::Context::default(), Command::ExportLog(path.clone()));
    let csv = std::fs::read_to_string(&path).expect("exported");
    assert_eq!(csv.lines().count(), 2, "header and one entry: {csv}");
    assert!(csv.lines().nth(1).is_some_and(|l| l.contains("R13=5")));
    let _ = std::fs::remove_file(path);
}

#[test]
fn the_gutter_menu_adds_a_log_point_and_marks_it() {
    let mut h = harness(LOOP);
    h.get_by_label("Breakpoint line 5").click_secondary();
    h.run_steps(2);
    h.get_by_label("Add a log point").click();
    h.run_steps(2);
    let list = h.state().debugger.breakpoint_list();
    assert_eq!(list.len(), 1);
    assert_eq!(list[0].kind, BreakKind::Line(5));
    assert!(!list[0].log.is_empty());
    assert!(
        h.state().layout.is_shown(&Pane::Breakpoints),
        "the list comes to the front"
    );
}

/// Issue #22 item 16: the Log opens on its newest entry, not scrolled to an older one (rows are
/// laid out only where they show, so the newest one's label exists only if it is in view).
#[test]
fn the_log_opens_on_its_newest_entry() {
    let mut h = harness("loop: CLC INC, 13\nJMP loop\n");
    for _ in 0..1000 {
        h.state_mut().debugger.step_command();
    }
    h.run_steps(1);
    open_tab(&mut h, Pane::Log);
    // The Log searches back in slices of a few ms a frame, adding older rows above: on a busy
    // machine (CI) that takes more frames. Count frames, not time, until it is done.
    let mut frames = 0;
    while h.state().log.searching_from().is_some() && frames < 2000 {
        h.run_steps(1);
        frames += 1;
    }
    h.run_steps(4);
    let rows = &h.state().log.log.rows;
    assert!(
        rows.len() >= 500,
        "{} rows after {frames} frames",
        rows.len()
    );
    let newest = format!("{:>9}", rows.last().expect("rows").at.to_string());
    assert!(
        h.query_all_by_label_contains(&newest).count() > 0,
        "the newest entry ({newest}) is in view"
    );
}

/// Issue #22 item 15: a long watch error goes under its row; the row's Plot and × stay in view.
#[test]
fn a_long_watch_error_leaves_the_buttons_in_view() {
    let mut h = harness(LOOP);
    let long = format!("R12 + {}", "no_such_register_with_a_long_name + ".repeat(6));
    h.state_mut().apply(
        &egui::Context::default(),
        Command::AddWatch(long.trim_end_matches(" + ").to_string()),
    );
    open_tab(&mut h, Pane::Watches);
    h.run_steps(2);
    let watches = h
        .state()
        .layout
        .pane_rect(&Pane::Watches)
        .expect("watches shown");
    for button in ["Plot watch 1", "Delete watch 1", "Format of watch 1"] {
        let rect = h.get_by_label(button).rect();
        assert!(
            watches.contains_rect(rect),
            "{button} at {rect:?}, panel {watches:?}"
        );
    }
    let error = h.get_by_label("Error of watch 1").rect();
    assert!(
        error.right() <= watches.right() + 1.0,
        "the error wraps: {error:?}"
    );
}
