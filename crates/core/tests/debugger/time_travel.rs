//! Time travel: step back, reverse-continue, go to tick; moving back and forward again gives
//! states identical to a straight run (whole machine equality), across checkpoints, with input
//! switches and register edits replayed at their ticks.

use std::time::Duration;

use servoscope_core::debugger::history::{CHECKPOINT_EVERY, MarkKind};
use servoscope_core::debugger::{Debugger, Event, Speed};
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::view::{io, reg};
use servoscope_core::machine::{MachineView, RunState};

const PROGRAM: &str = "\
        CLD Q_INIT, 10, 40, 5
loop:   CLD Q_PUSH_HEAD, 11, 40, 7
        CLX Q_POP_TAIL, 12, 40, 0
        MRV 40, 3865000, 805306400
        CLC INC, 20
        WBS IO1
        DLY 1000
        CLD SUB, 21, 20, 200
        JMP loop, !ZERO
        END
";

fn sl(d: &Debugger) -> &SilverLode {
    d.machine_as::<SilverLode>().expect("a SilverLode machine")
}

fn run_all(d: &mut Debugger) {
    d.set_speed(Speed::Unlimited);
    d.run();
    while d.advance(0.016, Duration::from_secs(5)) {}
}

/// A straight run, one tick at a time, with IO1 switched on at tick 300, R30 edited at tick
/// 500 and R31 at the first checkpoint tick: every state, by tick.
fn straight(ticks: u64) -> Vec<SilverLode> {
    let mut d = Debugger::new("p", PROGRAM);
    let mut states = vec![sl(&d).clone()];
    for t in 0..ticks {
        if t == 300 {
            d.set_input(io(0), true).expect("an input");
            *states.last_mut().unwrap() = sl(&d).clone();
        }
        if t == 500 {
            d.set_value(reg(30), 1234).expect("a register edit");
            *states.last_mut().unwrap() = sl(&d).clone();
        }
        // An edit exactly on a checkpoint tick: restoring that checkpoint must replay it.
        if t == CHECKPOINT_EVERY {
            d.set_value(reg(31), 77).expect("a register edit");
            *states.last_mut().unwrap() = sl(&d).clone();
        }
        d.step_tick();
        states.push(sl(&d).clone());
    }
    states
}

#[test]
fn back_and_forth_gives_identical_states() {
    let total = 2 * CHECKPOINT_EVERY + 5_000;
    let reference = straight(total);
    assert!(
        reference.last().unwrap().run_state().is_live(),
        "the run spans the whole test"
    );

    // The same history built by running, not stepping.
    let mut d = Debugger::new("p", PROGRAM);
    d.set_speed(Speed::Unlimited);
    d.goto_tick(300);
    while d.advance(0.016, Duration::from_secs(5)) {}
    d.set_input(io(0), true).expect("an input");
    d.goto_tick(500);
    while d.advance(0.016, Duration::from_secs(5)) {}
    d.set_value(reg(30), 1234).expect("a register edit");
    d.goto_tick(CHECKPOINT_EVERY);
    while d.advance(0.016, Duration::from_secs(5)) {}
    d.set_value(reg(31), 77).expect("a register edit");
    d.goto_tick(total);
    while d.advance(0.016, Duration::from_secs(5)) {}
    assert_eq!(d.machine().ticks(), total);
    assert_eq!(d.furthest_tick(), total);

    for tick in [
        total,
        0,
        299,
        300,
        301,
        500,
        CHECKPOINT_EVERY - 1,
        CHECKPOINT_EVERY,
        CHECKPOINT_EVERY + 1,
        2 * CHECKPOINT_EVERY + 17,
        7,
        total - 1,
    ] {
        d.goto_tick(tick);
        assert_eq!(d.machine().ticks(), tick);
        assert!(
            sl(&d) == &reference[tick as usize],
            "state at tick {tick} differs from the straight run"
        );
    }
    // Step back tick by tick across a checkpoint.
    d.goto_tick(CHECKPOINT_EVERY + 3);
    for _ in 0..6 {
        d.step_back_tick();
        let t = d.machine().ticks();
        assert!(sl(&d) == &reference[t as usize], "tick {t}");
    }
    assert_eq!(d.machine().ticks(), CHECKPOINT_EVERY - 3);
    // And forward again by stepping: the same states, the recorded events replayed.
    d.goto_tick(250);
    for _ in 0..400 {
        d.step_tick();
        let t = d.machine().ticks();
        assert!(sl(&d) == &reference[t as usize], "tick {t}");
    }
    assert!(
        d.machine().read(io(0)) == 1,
        "the IO1 switch at tick 300 was replayed"
    );
    assert_eq!(sl(&d).reg(30), 1234, "the edit at tick 500 was replayed");
}

#[test]
fn step_back_one_command_returns_to_its_start() {
    let mut d = Debugger::new("p", "WRP 11, 1\nDLY 50\nWRP 12, 2\nEND");
    d.step_command();
    d.step_command();
    d.step_command();
    assert_eq!((d.machine().ticks(), d.machine().steps()), (52, 3));
    d.step_back_command();
    assert_eq!(
        (
            d.machine().ticks(),
            d.machine().steps(),
            d.machine().pc_line()
        ),
        (51, 2, Some(3))
    );
    assert_eq!(sl(&d).reg(12), 0, "WRP 12 undone");
    d.step_back_command();
    assert_eq!(
        (d.machine().ticks(), d.machine().pc_line()),
        (1, Some(2)),
        "back over the whole DLY"
    );
    d.step_back_command();
    assert_eq!((d.machine().ticks(), sl(&d).reg(11)), (0, 0));
    d.step_back_command();
    assert_eq!(d.machine().ticks(), 0, "nothing before the start");
    // Mid-command (stepped by ticks into the DLY), back goes to the DLY's start.
    d.step_command();
    for _ in 0..10 {
        d.step_tick();
    }
    d.step_back_command();
    assert_eq!((d.machine().ticks(), d.machine().pc_line()), (1, Some(2)));
}

#[test]
fn reverse_continue_finds_the_previous_breakpoint_hit() {
    let program = "WRP 11, 3\nloop: CLC INC, 12\nDLY 20000\nCLC DEC, 11\nJMP loop, !ZERO\nEND";
    let mut d = Debugger::new("p", program);
    run_all(&mut d);
    assert_eq!(d.machine().run_state(), RunState::Ended);
    let end = d.machine().ticks();
    d.toggle_breakpoint(2);
    d.reverse_continue();
    assert_eq!(d.machine().pc_line(), Some(2));
    assert_eq!(sl(&d).reg(12), 2, "the third pass, about to increment");
    let third = d.machine().ticks();
    d.reverse_continue();
    assert_eq!(sl(&d).reg(12), 1);
    assert!(d.machine().ticks() < third);
    d.reverse_continue();
    d.reverse_continue();
    assert_eq!(d.machine().ticks(), 0);
    assert_eq!(d.event(), Some(&Event::NoEarlierBreakpoint));
    d.goto_tick(end);
    assert_eq!(d.machine().run_state(), RunState::Ended);
}

#[test]
fn editing_in_the_past_discards_the_future_and_says_so() {
    let mut d = Debugger::new("p", "WBS IO2\nloop: CLC INC, 20\nJMP loop");
    d.set_speed(Speed::Unlimited);
    d.goto_tick(100);
    while d.advance(0.016, Duration::from_secs(1)) {}
    d.set_input(io(1), true).expect("an input");
    d.goto_tick(5000);
    while d.advance(0.016, Duration::from_secs(1)) {}
    assert_eq!(d.furthest_tick(), 5000);
    assert_eq!(d.events().len(), 1);
    d.goto_tick(50);
    d.set_value(reg(30), 9).expect("a register edit");
    assert_eq!(d.event(), Some(&Event::FutureDiscarded(50)));
    assert_eq!(d.furthest_tick(), 50);
    assert_eq!(
        d.events().len(),
        1,
        "the IO2 switch at 100 is gone, the edit at 50 is kept"
    );
    assert_eq!(d.trace().end_tick(), Some(50));
    // Editing at the front of the timeline discards nothing.
    d.set_value(reg(31), 1).expect("a register edit");
    assert_eq!(d.event(), Some(&Event::FutureDiscarded(50)), "unchanged");
    assert_eq!(d.events().len(), 2);
}

#[test]
fn going_beyond_the_furthest_tick_runs_there() {
    let mut d = Debugger::new("p", "loop: CLC INC, 20\nJMP loop");
    d.goto_tick(100_000);
    assert!(d.is_running());
    while d.advance(0.016, Duration::from_secs(1)) {}
    assert_eq!(d.machine().ticks(), 100_000);
    assert_eq!(d.event(), Some(&Event::ReachedTick(100_000)));
}

#[test]
fn breakpoint_hits_and_faults_are_marked_on_the_timeline() {
    let mut d = Debugger::new("p", "WRP 11, 0\nWRP 12, 1\nCLC DIV, 11\nEND");
    d.toggle_breakpoint(2);
    run_all(&mut d);
    run_all(&mut d);
    let marks: Vec<(u64, MarkKind, usize)> = d
        .marks()
        .iter()
        .map(|m| (m.at.tick, m.kind, m.line))
        .collect();
    assert_eq!(
        marks,
        vec![(1, MarkKind::Breakpoint, 2), (2, MarkKind::Fault, 3)]
    );
}
