//! Debug sessions: save → load rebuilds exactly the same state (machine, trace, history,
//! marks, breakpoints); corrupt, truncated, foreign and newer files are refused clearly; the
//! runner saves and resumes sessions exactly as spec §8 says; the example sessions load.

use crate::common;
use common::sessions::{busy_debugger, sl, temp};

use std::path::{Path, PathBuf};
use std::time::Duration;

use servoscope_core::debugger::history::CHECKPOINT_EVERY;
use servoscope_core::debugger::{Debugger, Speed};
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::view::io;
use servoscope_core::machine::{Machine, MachineView, RunState};
use servoscope_core::session::{Session, SessionError, ViewSettings};

#[test]
fn save_then_load_rebuilds_exactly_the_same_state() {
    let d = busy_debugger();
    let view = ViewSettings {
        selected: Some("R30".to_string()),
        formats: vec![("R31".to_string(), servoscope_core::machine::Format::Bcd)],
        ..ViewSettings::default()
    };
    let session = Session::capture(&d, Some(PathBuf::from("prog.qsl")), view.clone());
    let path = temp("busy.ron");
    session.save(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("format: 2"), "explicit version");
    assert!(
        text.contains("dialect: \"silverlode\""),
        "the dialect is recorded"
    );
    assert!(
        text.contains("location: \"IO2\""),
        "the input timeline is in the file, by input name"
    );
    assert!(text.lines().count() > 10, "pretty-printed, diffable");

    let loaded = Session::load(&path).unwrap();
    assert_eq!(loaded, session);
    assert_eq!(loaded.view, view);
    let r = loaded.restore("busy.ron").unwrap();
    assert!(
        r.machine_as::<SilverLode>() == d.machine_as::<SilverLode>(),
        "the whole machine state is identical"
    );
    assert_eq!(r.machine().ticks(), CHECKPOINT_EVERY + 123);
    assert_eq!(
        r.furthest_tick(),
        d.furthest_tick(),
        "the history reaches as far"
    );
    assert_eq!(r.events(), d.events());
    assert_eq!(r.marks(), d.marks());
    assert_eq!(r.breakpoints(), d.breakpoints());
    let (a, b) = (d.trace(), r.trace());
    assert_eq!(a.len(), b.len());
    assert!(a.samples().eq(b.samples()), "the plot trace is identical");
    // And the future replays identically from the loaded session.
    let mut d = d;
    let mut r = r;
    for t in [d.furthest_tick(), 10, CHECKPOINT_EVERY] {
        d.goto_tick(t);
        r.goto_tick(t);
        assert!(
            d.machine_as::<SilverLode>() == r.machine_as::<SilverLode>(),
            "tick {t}"
        );
    }
    let _ = std::fs::remove_file(&path);
}

#[test]
fn a_failed_save_leaves_the_old_file() {
    let path = temp("keep.ron");
    let old = Session::capture(&Debugger::new("old", "END"), None, ViewSettings::default());
    old.save(&path).unwrap();
    let before = std::fs::read(&path).unwrap();
    // A directory where the temporary file goes makes the write fail half-way (even as root).
    let blocker = path.with_file_name(".keep.ron.servoscope-tmp");
    std::fs::create_dir_all(&blocker).unwrap();
    let new = Session::capture(
        &Debugger::new("new", "WRP 11, 1\nEND"),
        None,
        ViewSettings::default(),
    );
    assert!(matches!(new.save(&path), Err(SessionError::Write { .. })));
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the old session is untouched"
    );
    assert_eq!(Session::load(&path).unwrap(), old, "and still loads");
    std::fs::remove_dir(&blocker).unwrap();
    new.save(&path).unwrap();
    assert_eq!(Session::load(&path).unwrap(), new, "a later save works");
    let _ = std::fs::remove_file(&path);
}

/// The lesson sessions as shipped, and the format-1 files kept unchanged as fixtures: both
/// must restore to the same moments.
const SESSION_DIRS: [&str; 2] = ["sessions", "crates/core/tests/fixtures/format1"];

fn example_in(dir: &str, name: &str) -> (Session, Debugger) {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join(dir)
        .join(name);
    let s = Session::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let d = s.restore(name).unwrap_or_else(|e| panic!("{e}"));
    (s, d)
}

#[test]
fn every_example_session_is_tested() {
    let mut names: Vec<String> = std::fs::read_dir(
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("sessions"),
    )
    .unwrap()
    .filter_map(|e| e.ok()?.file_name().into_string().ok())
    .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "dl205_bcd_stack_task.ron",
            "dl205_subs_walkthrough.ron",
            "dl205_timer_counter_task.ron",
            "fifo_lifo_task.ron",
            "fifo_queue_walkthrough.ron",
            "fixed_point_walkthrough.ron",
            "homing_on_input.ron",
            "opennet_overflow_task.ron",
            "opennet_overflow_walkthrough.ron",
            "opennet_timer_counter_task.ron",
            "q16_scaling_task.ron",
            "tml_fixed_point_walkthrough.ron",
            "tml_product_task.ron"
        ]
    );
}

/// The DL205 lesson opens on the SUBS with all eight stack levels full.
#[test]
fn dl205_lesson_opens_on_subs_with_the_stack_full() {
    let (_, mut d) = example_in("sessions", "dl205_subs_walkthrough.ron");
    let m = d
        .machine_as::<servoscope_core::machine::dl205::Dl205>()
        .expect("a DL205 machine");
    assert_eq!(m.depth, 8);
    assert_eq!(m.stack[0], 0x0017_2056);
    assert_eq!(m.stack[7], 1);
    assert_eq!(d.machine().pc_line(), Some(18), "SUBS is next");
    assert!(d.breakpoints().contains(&18));
    d.step_command();
    let m = d
        .machine_as::<servoscope_core::machine::dl205::Dl205>()
        .unwrap();
    assert_eq!((m.acc, m.depth), (0x0022_2970, 7));
}

/// The OpenNet lesson opens just after ADD(I) 30000 + 5000 overflowed: stored 0x08B8, M8003 on.
#[test]
fn opennet_lesson_opens_after_the_overflow() {
    let (s, d) = example_in("sessions", "opennet_overflow_walkthrough.ron");
    let m = d
        .machine_as::<servoscope_core::machine::opennet::OpenNet>()
        .expect("an OpenNet machine");
    assert_eq!(m.pos(), servoscope_core::machine::Pos { tick: 0, step: 4 });
    assert_eq!(m.d[2], 0x08B8);
    assert!(m.special[servoscope_core::machine::opennet::M8003]);
    assert_eq!(d.machine().last_line(), Some(6), "the ADD(I) just ran");
    assert!(d.breakpoints().contains(&6));
    assert_eq!(s.view.selected.as_deref(), Some("D2"));
}

/// The TML lesson opens just after the fixed × int multiply: PREG holds the 32.16 product and
/// the next statement reads its integer part from PRODH.
#[test]
fn tml_lesson_opens_on_the_multiply() {
    let (s, mut d) = example_in("sessions", "tml_fixed_point_walkthrough.ron");
    let m = d
        .machine_as::<servoscope_core::machine::tml::Tml>()
        .expect("a TML machine");
    assert_eq!(m.pos(), servoscope_core::machine::Pos { tick: 1, step: 3 });
    assert_eq!(m.preg_signed(), 1_747_626 * 10, "speed × 10 as 32.16");
    assert_eq!(m.last_multiply.map(|l| l.line), Some(31));
    assert_eq!(d.machine().pc_line(), Some(32), "cpm = PRODH is next");
    assert!(d.breakpoints().contains(&31));
    assert_eq!(s.view.selected.as_deref(), Some("speed"));
    d.step_command();
    let cpm = d.machine().find("cpm").unwrap();
    assert_eq!(d.machine().read(cpm), 266, "the integer part of 266.666");
}

#[test]
fn format_1_fixtures_are_format_1() {
    for name in [
        "fifo_queue_walkthrough.ron",
        "fixed_point_walkthrough.ron",
        "homing_on_input.ron",
    ] {
        let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .join("crates/core/tests/fixtures/format1")
            .join(name);
        let text = std::fs::read_to_string(path).unwrap();
        assert!(text.contains("format: 1,"), "{name} stays a format-1 file");
    }
}

#[test]
fn fixed_point_lesson_opens_on_the_multiply() {
    for dir in SESSION_DIRS {
        fixed_point_lesson(dir);
    }
}

fn fixed_point_lesson(dir: &str) {
    let (s, d) = example_in(dir, "fixed_point_walkthrough.ron");
    assert_eq!(
        d.machine().pc_line(),
        Some(16),
        "about to run MULT_S64_SHR16"
    );
    assert_eq!(sl(&d).reg(20), 40000);
    assert!(d.breakpoints().contains(&16));
    assert_eq!(s.view.selected.as_deref(), Some("R21"));
    let mut d = d;
    d.step_command();
    assert_eq!(sl(&d).reg(21), 1016, "(40000 × 1665) >> 16");
}

#[test]
fn fifo_queue_lesson_has_its_breakpoints() {
    for dir in SESSION_DIRS {
        fifo_queue_lesson(dir);
    }
}

fn fifo_queue_lesson(dir: &str) {
    let (_, mut d) = example_in(dir, "fifo_queue_walkthrough.ron");
    assert_eq!(d.machine().ticks(), 0);
    d.set_speed(Speed::Unlimited);
    d.run();
    while d.advance(0.016, Duration::from_secs(5)) {}
    assert_eq!(d.machine().pc_line(), Some(19), "stops on the first pop");
    let h = sl(&d).queues()[0].header.clone().unwrap();
    assert_eq!(h.items, [1000, 2500, -500]);
}

#[test]
fn homing_session_opens_stopped_on_the_sensor() {
    for dir in SESSION_DIRS {
        homing_session(dir);
    }
}

fn homing_session(dir: &str) {
    let (_, d) = example_in(dir, "homing_on_input.ron");
    let m = sl(&d);
    assert_eq!(m.ticks(), 3001);
    assert_eq!(d.machine().read(io(2)), 1, "IO3 high");
    assert!(m.isw() & 1 << 11 != 0, "input found");
    // LAST_TRIG holds where the motor was when IO3 rose at tick 3000 (spec §5.5): the actual
    // position of a straight run stopped at that tick.
    let program = include_str!("../../../../assets/examples/homing.qsl");
    let mut straight = common::load(program).expect("assembles");
    straight.run_until(3000, |_| false);
    assert_eq!(m.reg(4), straight.reg(1), "R4 = R1 when IO3 rose");
    assert!(
        m.reg(4) > 0 && m.reg(4) < 1_000_000,
        "the search had started"
    );
    assert_eq!(m.run_state().label(), "waiting for move", "braking");
    let mut d = d;
    d.set_speed(Speed::Unlimited);
    d.run();
    while d.advance(0.016, Duration::from_secs(5)) {}
    assert_eq!(
        d.machine().pc_line(),
        Some(13),
        "the breakpoint on SUB_TARGET"
    );
    assert_ne!(d.machine().run_state(), RunState::Faulted);
}

/// Run until the debugger stops on its own (a breakpoint, the end), within a bound.
fn run_to_a_stop(d: &mut Debugger) {
    d.set_speed(Speed::Unlimited);
    d.run();
    for _ in 0..1000 {
        if !d.advance(0.016, Duration::from_millis(20)) {
            return;
        }
    }
    panic!("the run did not stop");
}

/// #43 item 5: a "from hit 3" breakpoint stops at the same place after a save and reopen as
/// without them (the reopened session had forgotten its hits and stopped two rounds early),
/// and the status bar says again why the debugger stopped.
#[test]
fn a_reopened_session_keeps_hit_counts_and_the_status() {
    let source = include_str!("../../../../assets/examples/call_ret.qsl");
    let line = 1 + source
        .lines()
        .position(|l| l.contains("CLC DEC, n"))
        .expect("the DEC line");
    let mut d = common::debugger("silverlode", source);
    d.add_breakpoint(servoscope_core::debugger::Breakpoint {
        hit_count: 3,
        ..servoscope_core::debugger::Breakpoint::line(line)
    });
    run_to_a_stop(&mut d);
    let n = |d: &Debugger| servoscope_core::machine::value_of(d.machine(), d.find("n").expect("n"));
    assert_eq!(n(&d), 8, "the third pass of the DEC line, before it runs");
    assert_eq!(d.breakpoint_hits(0), 3);
    let text = Session::capture(&d, None, ViewSettings::default())
        .to_ron()
        .expect("encodes");
    let mut reopened = Session::from_ron(&text, "s.ron")
        .and_then(|s| s.restore("s.ron"))
        .expect("reopens");
    assert_eq!(reopened.breakpoint_hits(0), 3, "{text}");
    assert_eq!(reopened.event(), d.event(), "the status bar's reason");
    // Every later pass stops: both go on to n = 7.
    run_to_a_stop(&mut d);
    run_to_a_stop(&mut reopened);
    assert_eq!(n(&d), 7);
    assert_eq!(reopened.pos(), d.pos());
    assert_eq!(reopened.breakpoint_hits(0), 4);
}

/// The session of `d` saved and reopened.
fn reopened(d: &Debugger) -> Debugger {
    let text = Session::capture(d, None, ViewSettings::default())
        .to_ron()
        .expect("encodes");
    Session::from_ron(&text, "s.ron")
        .and_then(|s| s.restore("s.ron"))
        .expect("reopens")
}

/// The reopened debugger is the original: state, position, history's end and marks.
fn assert_same_moment(what: &str, d: &Debugger, r: &Debugger) {
    let (a, b) = (d.machine(), r.machine());
    assert_eq!(b.run_state(), a.run_state(), "{what}: run state");
    assert_eq!(
        (b.pos(), b.steps(), b.pc_line()),
        (a.pos(), a.steps(), a.pc_line()),
        "{what}: position"
    );
    assert_eq!(
        common::every_value(b),
        common::every_value(a),
        "{what}: every location, status words included"
    );
    assert_eq!(r.furthest(), d.furthest(), "{what}: furthest");
    assert_eq!(
        r.stopped_at_furthest(),
        d.stopped_at_furthest(),
        "{what}: stopped"
    );
    assert_eq!(r.marks(), d.marks(), "{what}: marks");
}

fn run_out(d: &mut Debugger) {
    d.set_speed(Speed::Unlimited);
    d.run();
    for _ in 0..10_000 {
        if !d.advance(0.016, Duration::from_millis(200)) {
            break;
        }
    }
}

#[test]
fn paused_just_before_a_ret_that_faults_reopens_running() {
    // A RET with nothing to return to faults where it began (PSW bit 12, command error); the
    // user stepped back up to it and paused there, before it runs.
    let mut d = common::debugger("silverlode", "WRP 11, 1\nRET\n");
    run_out(&mut d);
    assert_eq!(d.machine().run_state(), RunState::Faulted);
    d.goto_tick(0);
    d.step_command();
    assert_eq!(d.pos(), d.furthest(), "at the RET, the history's end");
    assert_eq!(d.machine().run_state(), RunState::Running);
    assert!(d.stopped_at_furthest());
    assert_same_moment("silverlode", &d, &reopened(&d));
}

#[test]
fn a_run_stopped_by_break_on_error_reopens_with_the_same_furthest_in_every_dialect() {
    // Each program sets its dialect's error flag and goes on (break_on_error_flags_in_every_
    // dialect): the stop is live, with a fault mark at the history's end.
    for (dialect, source) in [
        (
            "silverlode",
            "CER handler\nWRP 10, 0\nCLC DIV, 10\nWRP 11, 1\nEND\nhandler: END\n",
        ),
        (
            "tml",
            "int a;\n        a = 1;\n        UPD;\n        a = 2;\n        END;\n",
        ),
        ("dl205", "STR SP1\nLD K4\nDIV V2002\nOUT V2000\nEND\n"),
        ("opennet", "LODN M0\nDIV(W) 5 0 D0\nMOV(W) 1 D1\nEND\n"),
    ] {
        let mut d = common::debugger(dialect, source);
        d.set_break_on_error(true);
        run_out(&mut d);
        assert!(d.machine().error_lamp(), "{dialect}: stopped on the error");
        assert_same_moment(dialect, &d, &reopened(&d));
    }
}
