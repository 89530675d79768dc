//! Hostile input to the debugger, sessions and the runner (issue: no hang, no abort, no lost
//! session): text in any script in every expression entry point, absurd numbers in session
//! files, edits of bits a location does not have, and sessions saved at a fault.

use crate::common;

use std::time::{Duration, Instant};

use common::every_value;
use servoscope_core::debugger::{
    BreakError, Breakpoint, ChannelChoice, Debugger, EditError, Speed,
};
use servoscope_core::machine::{Format, Loc, MachineView, RunState, SpaceKind};
use servoscope_core::registry::{self, DIALECTS, Dialect};
use servoscope_core::session::{Session, SessionError, ViewSettings};

fn debugger(dialect: &'static Dialect) -> Debugger {
    let (name, source) = dialect.examples[0];
    let d = Debugger::with_dialect(dialect, name, source);
    assert!(!d.has_errors(), "{name} assembles");
    d
}

/// The first data word of the machine (R0, V-memory, D0, a TML variable…).
fn a_word(m: &dyn MachineView) -> Loc {
    m.spaces()
        .into_iter()
        .enumerate()
        .filter(|(_, s)| s.kind == SpaceKind::Registers)
        .flat_map(|(space, s)| (0..s.len).map(move |i| Loc::new(space as u8, i)))
        .find(|&l| {
            m.info(l)
                .is_some_and(|i| i.editable && i.width > 1 && i.width < 64)
        })
        .expect("every dialect has an editable data word")
}

// ---- 1. any text in an expression -----------------------------------------------------------

#[test]
fn a_letter_outside_ascii_is_an_error_in_every_entry_point_not_a_hang() {
    for dialect in DIALECTS {
        let mut d = debugger(dialect);
        let started = Instant::now();
        let disabled = Breakpoint {
            enabled: false,
            ..Breakpoint::line(1).with_condition("é")
        };
        let b = d.add_breakpoint(disabled);
        assert!(
            matches!(d.breakpoint_error(b), Some(BreakError::Condition(e)) if e.col == 1),
            "{}",
            dialect.name
        );
        let b = d.add_breakpoint(Breakpoint::line(1).with_log("at {é}"));
        assert!(matches!(
            d.breakpoint_error(b),
            Some(BreakError::Message(_))
        ));
        let w = d.add_watch("R1 + é", Format::Signed);
        let e = d.watch_value(w).expect_err("not an expression");
        assert!(e.message.contains("A to Z"), "{e}");
        let mut channels = d.channel_choices().to_vec();
        channels.push(ChannelChoice {
            location: "é".to_string(),
            label: String::new(),
            group: 0,
        });
        d.set_channels(channels);
        d.step_command();
        assert!(
            // A guard against the old endless loop, not a speed claim.
            started.elapsed() < Duration::from_secs(20),
            "{}",
            dialect.name
        );
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
    /// Conditions, log messages, watches and plot channels take any text: it works or is
    /// refused, and the debugger goes on stepping.
    #[test]
    fn every_expression_entry_point_takes_any_text(text in "\\PC{0,24}", which in 0usize..4) {
        let dialect = DIALECTS[which];
        let mut d = debugger(dialect);
        d.add_breakpoint(Breakpoint::line(1).with_condition(text.clone()));
        d.add_breakpoint(Breakpoint::line(2).with_log(format!("v={{{text}}}")));
        d.add_breakpoint(Breakpoint::data(text.clone(), servoscope_core::debugger::DataTrigger::Change));
        let w = d.add_watch(text.clone(), Format::Hex);
        let _ = d.watch_value(w);
        let _ = d.evaluate(&text);
        d.set_channels(vec![ChannelChoice { location: text.clone(), label: text.clone(), group: 1 }]);
        d.set_speed(Speed::Unlimited);
        d.run();
        d.advance(0.016, Duration::from_millis(5));
        d.pause();
        d.step_command();
        d.reverse_continue();
    }
}

// ---- 2. numbers in a session are bounded before anything is sized by them -------------------

fn session_text(extra: &str) -> String {
    format!(
        "(format: 2, dialect: \"silverlode\", program: \"WRP 20, 1\\nloop: CLC INC, 20\\nJMP loop\\n\", {extra})"
    )
}

#[test]
fn a_breakpoint_far_past_the_last_line_is_dropped_with_a_warning() {
    let text = session_text(
        "breakpoints: [2, 99999999999], breakpoint_list: [(kind: Line(0x14294967295), condition: \"R20 > 3\"), (kind: Line(3))]",
    );
    let s = Session::from_ron(&text, "far.ron").expect("the file is readable");
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains(&0x14294967295usize.to_string())),
        "{:?}",
        s.warnings
    );
    assert!(s.warnings.iter().any(|w| w.contains("99999999999")));
    let d = s.restore("far.ron").expect("restores");
    assert_eq!(
        d.breakpoint_list()
            .iter()
            .filter_map(Breakpoint::line_number)
            .collect::<Vec<_>>(),
        vec![3]
    );
}

#[test]
fn a_breakpoint_past_the_end_set_through_the_api_sizes_nothing() {
    let mut d = Debugger::new("p", "WRP 20, 1\nEND\n");
    let b = d.add_breakpoint(Breakpoint::line(usize::MAX));
    assert_eq!(
        d.breakpoint_error(b),
        Some(BreakError::PastEnd {
            line: usize::MAX,
            last: 2
        })
    );
    d.toggle_breakpoint(2);
    d.set_speed(Speed::Unlimited);
    d.run();
    d.advance(0.016, Duration::from_millis(50));
    assert_eq!(d.machine().pc_line(), Some(2), "the other breakpoint works");
}

#[test]
fn counts_and_texts_beyond_reason_are_refused_clearly() {
    let channels: Vec<String> = (0..9).map(|i| format!("(location: \"R{i}\")")).collect();
    let cases = [
        session_text(&format!("channels: Some([{}])", channels.join(", "))),
        // A name comes from the program: cut, it would name something else.
        session_text(&format!(
            "events: [(at: (tick: 1), location: \"{}\", change: Set(1))]",
            "R".repeat(5_000)
        )),
        session_text(&format!("breakpoints: [{}]", vec!["1"; 10_001].join(", "))),
    ];
    for text in cases {
        match Session::from_ron(&text, "odd.ron") {
            Err(e @ SessionError::Unreasonable { .. }) => {
                assert!(e.to_string().starts_with("odd.ron"), "{e}")
            }
            other => panic!("{:?}", other.map(|_| ())),
        }
    }
}

#[test]
fn a_long_typed_text_saved_by_an_older_build_opens_cut_with_a_warning() {
    // Builds before the one limit saved what they took: a watch, a condition, a log message,
    // a lesson check over 4,096 characters.
    let long = "R1+".repeat(2_000) + "1";
    let text = session_text(&format!(
        "watches: [(expr: \"{long}\")], breakpoint_list: [(kind: Line(1), condition: \"{long}\", log: \"{long}\")], \
         lesson: Some((title: \"t\", steps: [(text: \"s\", checks: [\"{long}\"])]))"
    ));
    let session = Session::from_ron(&text, "old.ron").expect("opens");
    let most = servoscope_core::session::limits::TEXT;
    assert_eq!(session.watches[0].expr.chars().count(), most);
    assert!(long.starts_with(&session.watches[0].expr), "the start kept");
    assert_eq!(session.breakpoint_list[0].condition.chars().count(), most);
    assert_eq!(session.breakpoint_list[0].log.chars().count(), most);
    let lesson = session.lesson.as_ref().expect("a lesson");
    assert_eq!(lesson.steps[0].checks[0].chars().count(), most);
    assert_eq!(session.warnings.len(), 4, "{:?}", session.warnings);
    assert!(
        session.warnings[0].contains("6001 characters") && session.warnings[0].contains("4096"),
        "{}",
        session.warnings[0]
    );
    // Saved again, it reads back as it is, with nothing more to cut.
    let again = Session::from_ron(&session.to_ron().expect("encodes"), "again.ron").expect("opens");
    assert!(again.warnings.is_empty(), "{:?}", again.warnings);
    assert_eq!(again.watches, session.watches);
}

#[test]
fn what_the_window_saves_reads_back_whatever_was_typed() {
    // A watch typed through the API (the window's field stops at the limit) is cut when the
    // session is captured, so save never writes what load would refuse or change.
    let mut d = debugger(registry::default_dialect());
    d.add_watch("R1+".repeat(3_000) + "1", Format::Signed);
    let text = Session::capture(&d, None, ViewSettings::default())
        .to_ron()
        .expect("encodes");
    let back = Session::from_ron(&text, "w.ron").expect("opens");
    assert!(back.warnings.is_empty(), "{:?}", back.warnings);
    assert_eq!(
        back.watches[0].expr.chars().count(),
        servoscope_core::session::limits::TEXT
    );
}

// ---- 3. edits are checked against the location --------------------------------------------

#[test]
fn a_bit_beyond_a_locations_width_is_refused_in_every_dialect() {
    for dialect in DIALECTS {
        let mut d = debugger(dialect);
        let loc = a_word(d.machine());
        let width = d.machine().info(loc).expect("exists").width;
        let before = d.machine().read(loc);
        for bit in [width, 63, 64, 200, 255] {
            assert!(
                matches!(d.toggle_bit(loc, bit), Err(EditError::NoSuchBit { .. })),
                "{} bit {bit}",
                dialect.name
            );
            assert!(matches!(
                d.set_bit(loc, bit, true),
                Err(EditError::NoSuchBit { .. })
            ));
        }
        assert_eq!(d.machine().read(loc), before, "nothing changed");
        assert!(d.events().is_empty(), "nothing recorded");
        d.toggle_bit(loc, width - 1).expect("its top bit is fine");
        assert_eq!(d.events().len(), 1);
    }
}

#[test]
fn a_session_with_an_impossible_edit_names_it_and_is_refused() {
    let text = session_text(
        "events: [(at: (tick: 1), location: \"R20\", change: Set(5)), (at: (tick: 2), location: \"R20\", change: Bit(bit: 200, on: true))]",
    );
    let s = Session::from_ron(&text, "bits.ron").expect("readable");
    match s.restore("bits.ron") {
        Err(e @ SessionError::BadEvent { index: 2, .. }) => {
            let text = e.to_string();
            assert!(text.contains("R20") && text.contains("bit 200"), "{text}");
        }
        other => panic!("{:?}", other.map(|_| ())),
    }
    let wide = session_text("events: [(at: (tick: 1), location: \"IO1\", change: Set(7))]");
    let s = Session::from_ron(&wide, "wide.ron").expect("readable");
    assert!(matches!(
        s.restore("wide.ron"),
        Err(SessionError::BadEvent { index: 1, .. })
    ));
}

// ---- 4. a session saved at a fault reopens faulted ------------------------------------------

/// What a restored debugger must equal: the run state, the fault, the position and every
/// location.
fn moment(d: &Debugger) -> (RunState, Option<String>, String, Vec<(String, u64)>) {
    let m = d.machine();
    (
        m.run_state(),
        m.fault()
            .map(|f| format!("{} line {}: {}", f.kind, f.line, f.message)),
        m.pos().to_string(),
        every_value(m),
    )
}

fn run_to_stop(dialect: &'static Dialect, source: &str) -> Debugger {
    let mut d = Debugger::with_dialect(dialect, "p", source);
    assert!(!d.has_errors(), "{:?}", d.diagnostics());
    d.set_speed(Speed::Unlimited);
    d.run();
    while d.advance(0.016, Duration::from_secs(5)) {}
    d
}

#[test]
fn a_session_saved_at_a_fault_reopens_faulted_in_every_dialect_that_faults() {
    let cases = [
        ("silverlode", "DLY 23\nCLD Q_PUSH_HEAD, 20, 40, 1\nEND\n"),
        ("tml", "int a;\na = 5;\nRET;\nEND;\n"),
    ];
    for (name, source) in cases {
        let dialect = registry::by_name(name).expect("registered");
        let d = run_to_stop(dialect, source);
        assert_eq!(d.machine().run_state(), RunState::Faulted, "{name}");
        let saved = moment(&d);
        let text = Session::capture(&d, None, ViewSettings::default())
            .to_ron()
            .expect("encodes");
        let back = Session::from_ron(&text, "f.ron")
            .and_then(|s| s.restore("f.ron"))
            .expect("restores");
        assert_eq!(moment(&back), saved, "{name}");
        assert_eq!(
            back.event().map(|e| e.describe("tick")),
            Some("Stopped on a fault".to_string()),
            "{name}: the banner"
        );
        // Choosing plot channels rebuilds the timeline: the fault stays.
        let mut back = back;
        let mut channels = back.channel_choices().to_vec();
        channels.truncate(1);
        back.set_channels(channels);
        assert_eq!(moment(&back), saved, "{name}: after new plot channels");
        // Going back and forth on the timeline shows the fault at its end too.
        let end = back.pos();
        back.goto_tick(0);
        back.goto(end);
        assert_eq!(moment(&back), saved, "{name}: after time travel");
    }
}

#[test]
fn a_fault_saved_by_an_older_build_reopens_faulted_from_its_mark() {
    // Before `stopped` was saved, the fault mark at the end was the only record of the stop.
    let text = "(format: 2, dialect: \"silverlode\", program: \"DLY 23\\nCLD Q_PUSH_HEAD, 20, 40, 1\\nEND\\n\", \
                at: (tick: 23), furthest: (tick: 23), marks: [(at: (tick: 23), fault: true, line: 2)])";
    let d = Session::from_ron(text, "old.ron")
        .and_then(|s| s.restore("old.ron"))
        .expect("restores");
    assert_eq!(d.machine().run_state(), RunState::Faulted);
    let fresh = run_to_stop(
        registry::default_dialect(),
        "DLY 23\nCLD Q_PUSH_HEAD, 20, 40, 1\nEND\n",
    );
    assert_eq!(moment(&d), moment(&fresh));
}

// ---- 5. nothing freezes the window: every long piece of work is counted out -----------------

#[test]
fn a_real_time_factor_from_a_file_is_clamped_and_a_frame_runs_what_its_budget_allows() {
    let text = session_text("view: (speed: RealTime(1e12))");
    let mut d = Session::from_ron(&text, "fast.ron")
        .and_then(|s| s.restore("fast.ron"))
        .expect("restores");
    d.set_speed(
        Session::from_ron(&text, "fast.ron")
            .expect("reads")
            .view
            .speed,
    );
    assert_eq!(d.speed(), Speed::RealTime(100.0), "the fastest offered");
    d.run();
    // A frame's worth at ×100: 0.25 s (the longest frame counted) of 120 µs ticks.
    d.advance(1.0, Duration::from_secs(60));
    let most = (100.0 * 0.25 / 120e-6) as u64 + 1;
    assert!(d.machine().ticks() <= most, "{} ticks", d.machine().ticks());
    // With its budget spent, a frame stops after its first chunk.
    let before = d.machine().ticks();
    d.advance(1.0, Duration::ZERO);
    assert_eq!(
        d.machine().ticks() - before,
        servoscope_core::debugger::FIRST_CHUNK_TICKS
    );
}

#[test]
fn the_first_frame_of_a_run_looks_at_the_clock_after_a_few_scans() {
    // 10,000 instructions a scan.
    let mut program = String::new();
    for i in 0..3_333 {
        program.push_str(&format!(
            "STR X{}\nAND X{}\nOUT Y{}\n",
            i % 8,
            (i + 1) % 8,
            i % 8
        ));
    }
    program.push_str("END\n");
    let dl205 = registry::by_name("dl205").expect("registered");
    let mut d = Debugger::with_dialect(dl205, "big.dl205", program);
    assert!(!d.has_errors(), "{:?}", d.diagnostics().first());
    d.set_speed(Speed::Unlimited);
    d.run();
    d.advance(0.016, Duration::ZERO);
    assert_eq!(
        d.machine().ticks(),
        servoscope_core::debugger::FIRST_CHUNK_TICKS
    );
}

/// Where the last instruction before `at` began, found the slow way: every tick from the
/// start.
fn last_boundary_before(mut m: servoscope_core::machine::silverlode::SilverLode, at: u64) -> u64 {
    use servoscope_core::machine::Machine;
    let mut last = 0;
    while m.ticks() < at {
        if m.run_state() == RunState::Running {
            last = m.ticks();
        }
        m.step_tick();
    }
    last
}

#[test]
fn a_search_back_inside_a_long_move_replays_a_bounded_stretch() {
    use servoscope_core::debugger::history::{BackSearch, CHECKPOINT_EVERY, Timeline};
    let source = include_str!("../../../../assets/examples/homing.qsl");
    let start = common::machine(source);
    let mut t = Timeline::new(start.clone(), Vec::new(), Vec::new());
    let now = servoscope_core::machine::Pos::at_tick(40 * CHECKPOINT_EVERY + 1234);
    t.forward(now, |_| false);
    assert_eq!(t.now(), now, "still moving");
    let mut search = BackSearch::new(now);
    let replayed = t.find_back_some(&mut search, 1, |m, _| m.run_state() == RunState::Running);
    assert!(search.is_done(), "one call finds it");
    assert!(
        replayed <= 2 * CHECKPOINT_EVERY,
        "{replayed} ticks replayed for a move of {} ticks",
        now.tick
    );
    assert_eq!(
        search.found().map(|p| p.tick),
        Some(last_boundary_before(start, now.tick))
    );
    assert_eq!(t.now(), now, "left where it was");
}

#[test]
fn step_back_and_reverse_continue_inside_a_long_move_finish_in_their_first_slice() {
    let source = include_str!("../../../../assets/examples/homing.qsl");
    let mut d = Debugger::new("homing.qsl", source);
    d.toggle_breakpoint(11);
    d.toggle_breakpoint(15);
    d.goto_tick(700_000);
    while d.advance(0.016, Duration::from_secs(5)) {}
    assert_eq!(d.machine().ticks(), 700_000);
    d.step_back_command();
    assert!(
        !d.is_running(),
        "done within BACK_TICKS_AT_ONCE ticks of replay"
    );
    assert_eq!(d.pos().tick, 0, "the move began at the start");
    d.goto_tick(700_000);
    d.reverse_continue();
    assert!(!d.is_running());
    assert_eq!(d.pos().tick, 0);
    assert_eq!(
        d.event().map(|e| e.describe("tick")),
        Some("Breakpoint hit at line 11".to_string())
    );
}

#[test]
fn a_long_search_back_goes_on_over_frames_and_pause_cancels_it() {
    // A breakpoint whose condition never holds: reverse-continue searches the whole history.
    let mut d = Debugger::new("loop", "loop: CLC INC, 20\nJMP loop\n");
    let ticks = 3 * servoscope_core::debugger::BACK_TICKS_AT_ONCE;
    d.goto_tick(ticks);
    while d.advance(0.016, Duration::from_secs(5)) {}
    d.add_breakpoint(Breakpoint::line(1).with_condition("R20 < 0"));
    d.reverse_continue();
    assert!(d.is_running(), "still searching after its first slice");
    assert!(d.back_searched_to().is_some_and(|p| p.tick < ticks));
    assert_eq!(d.pos().tick, ticks, "the position stays until it is done");
    d.pause();
    assert!(!d.is_running());
    assert_eq!(d.pos().tick, ticks, "cancelled where it started");
    d.reverse_continue();
    while d.advance(0.016, Duration::from_millis(5)) {}
    assert_eq!(d.pos().tick, 0);
    assert_eq!(
        d.event().map(|e| e.describe("tick")),
        Some("No earlier breakpoint: back at the start".to_string())
    );
}

#[test]
fn the_execution_log_is_searched_a_bounded_stretch_at_a_time() {
    use servoscope_core::debugger::history::CHECKPOINT_EVERY;
    use servoscope_core::debugger::log::{LogFilter, LogSearch};
    let mut d = Debugger::new("loop", "loop: CLC INC, 20\nJMP loop\nEND\n");
    d.goto_tick(10 * CHECKPOINT_EVERY);
    while d.advance(0.016, Duration::from_secs(5)) {}
    // A line that never runs: the search goes all the way back.
    let whole = d.execution_log(LogFilter::Line(3), 500, u64::MAX);
    let mut search = LogSearch::new(LogFilter::Line(3), 500, u64::MAX, d.pos());
    let mut steps = 0;
    while !search.is_done() {
        let ticks = d.search_log(&mut search);
        assert!(ticks <= CHECKPOINT_EVERY, "{ticks}");
        steps += 1;
    }
    assert!(steps > 10);
    assert_eq!(d.log_found(&search), whole);
    assert!(whole.complete && whole.rows.is_empty());
}

#[test]
fn an_error_in_a_sessions_program_names_the_program_and_its_line() {
    let text = "(format: 2, dialect: \"silverlode\", program_name: \"move.qsl\", program: \"WRP 20, 1\\nBOGUS 3\\n\")";
    let s = Session::from_ron(text, "lesson.ron").expect("readable");
    let e = s.restore("lesson.ron").err().expect("does not assemble");
    let text = e.to_string();
    assert!(
        text.starts_with("lesson.ron: its program move.qsl"),
        "{text}"
    );
    assert!(text.contains("move.qsl:2:1"), "{text}");
}

#[test]
fn a_channel_on_a_plot_that_does_not_exist_moves_to_the_last_with_a_warning() {
    let text = session_text("channels: Some([(location: \"R20\", group: 255)])");
    let s = Session::from_ron(&text, "plots.ron").expect("readable");
    assert!(
        s.warnings.iter().any(|w| w.contains("plot 256")),
        "{:?}",
        s.warnings
    );
    let d = s.restore("plots.ron").expect("restores");
    assert_eq!(d.channel_choices()[0].group, 3);
}
