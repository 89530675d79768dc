//! Tests of run control: breakpoints, speeds, stepping, running to a line, edits.

use std::time::{Duration, Instant};

use super::*;

fn reg(d: &Debugger, r: u32) -> i32 {
    d.machine().read(Loc::new(0, r)) as u32 as i32
}

const LOOP: &str = "WRP 11, 3\nloop: CLC INC, 12\nCLC DEC, 11\nJMP loop, !ZERO\nEND\n";

#[test]
fn run_stops_at_a_breakpoint_and_resumes_past_it() {
    let mut d = Debugger::new("loop", LOOP);
    d.set_speed(Speed::Unlimited);
    d.toggle_breakpoint(2);
    d.run();
    assert!(!d.advance(0.016, Duration::from_millis(50)));
    assert_eq!(d.event(), Some(&Event::Breakpoint(2)));
    assert_eq!(reg(&d, 12), 0, "stopped before line 2 ran");
    d.run();
    d.advance(0.016, Duration::from_millis(50));
    assert_eq!(d.event(), Some(&Event::Breakpoint(2)));
    assert_eq!(reg(&d, 12), 1, "one round later");
    d.toggle_breakpoint(2);
    d.run();
    d.advance(0.016, Duration::from_millis(50));
    assert_eq!(d.event(), Some(&Event::Ended));
    assert_eq!(reg(&d, 12), 3);
}

#[test]
fn slow_speed_runs_the_commands_the_time_allows() {
    let mut d = Debugger::new("loop", LOOP);
    d.set_speed(Speed::PerSecond(10.0));
    d.run();
    // 0.25 s at 10 commands/s: 2.5 commands, so 2 now and the half carries over.
    d.advance(0.25, Duration::from_millis(50));
    assert_eq!(d.machine().steps(), 2);
    d.advance(0.05, Duration::from_millis(50));
    assert_eq!(d.machine().steps(), 3);
    assert!(d.is_running());
    d.pause();
    assert!(!d.is_running());
    assert_eq!(
        d.event(),
        Some(&Event::Paused(Some(4))),
        "three commands ran"
    );
}

#[test]
fn run_to_line_and_reset() {
    let mut d = Debugger::new("loop", LOOP);
    d.set_speed(Speed::Unlimited);
    d.run_to_line(5);
    d.advance(0.0, Duration::from_millis(50));
    assert_eq!(d.event(), Some(&Event::ReachedLine(5)));
    assert_eq!(d.machine().pc_line(), Some(5));
    let io2 = d.find("IO2").expect("SilverLode has IO2");
    d.set_input(io2, true).expect("inputs can be switched");
    d.reset();
    assert_eq!(d.machine().ticks(), 0);
    assert_eq!(
        d.machine().read(io2),
        0,
        "a new run starts with its inputs low, as the runner's does"
    );
    assert!(
        d.events().is_empty(),
        "nothing carried into the new timeline"
    );
    d.set_input(io2, true).expect("inputs can be switched");
    *d.source_mut() = "WRP 11, 2\nEND\n".to_string();
    d.assemble();
    assert_eq!(d.machine().read(io2), 0, "nor into a re-assembled program");
}

#[test]
fn unlimited_runs_in_bounded_slices() {
    let mut d = Debugger::new("forever", "loop: CLC INC, 11\nJMP loop");
    d.set_speed(Speed::Unlimited);
    d.run();
    let started = Instant::now();
    assert!(d.advance(0.016, Duration::from_millis(5)), "still running");
    assert!(
        // A guard against a blocking loop, not a speed claim.
        started.elapsed() < Duration::from_secs(3),
        "returned after its budget"
    );
    assert!(d.machine().ticks() > 0);
    d.pause();
    assert!(!d.advance(0.016, Duration::from_millis(5)));
}

#[test]
fn real_time_speed_advances_the_ticks_the_time_is_worth() {
    // An endless wait: only time passes.
    let mut d = Debugger::new("wait", "WBS IO1\nEND");
    d.set_speed(Speed::RealTime(1.0));
    d.run();
    // 12 ms of real time at ×1 is 100 ticks of 120 µs.
    assert!(d.advance(0.012, Duration::from_millis(50)));
    assert_eq!(d.machine().ticks(), 100);
    d.set_speed(Speed::RealTime(0.1));
    d.advance(0.012, Duration::from_millis(50));
    assert_eq!(d.machine().ticks(), 110, "×0.1: ten ticks");
    // A switch flipped between frames lands on the tick on screen.
    let io1 = d.find("IO1").expect("an input");
    d.set_input(io1, true).expect("switched");
    assert_eq!(d.events()[0].at.tick, 110);
    d.advance(0.012, Duration::from_millis(50));
    assert_eq!(d.event(), Some(&Event::Ended));
    assert_eq!(
        d.machine().ticks(),
        112,
        "WBS saw it in tick 111, END took 112"
    );
}

#[test]
fn a_long_step_continues_over_frames() {
    let mut d = Debugger::new("delay", "DLY 1000000\nEND");
    d.step_command();
    assert_eq!(d.goal(), Some(Goal::FinishStep));
    while d.advance(0.016, Duration::from_millis(50)) {}
    assert_eq!(d.machine().pc_line(), Some(2));
    assert_eq!(d.event(), Some(&Event::Stepped));
}

#[test]
fn errors_block_running_until_fixed() {
    let mut d = Debugger::new("bad", "WRP 11, 1\nBOGUS 3");
    assert_eq!(d.diagnostics().len(), 1);
    d.step_command();
    d.run();
    assert!(!d.is_running());
    assert_eq!(d.machine().ticks(), 0);
    assert_eq!(d.event(), Some(&Event::NotAssembled(1)));
    *d.source_mut() = "WRP 11, 1\nEND".to_string();
    d.step_command();
    assert_eq!(reg(&d, 11), 1, "edits assemble on the next step");
    assert!(d.diagnostics().is_empty());
}

#[test]
fn register_edits_parse_or_change_nothing() {
    let mut d = Debugger::new("p", "END");
    assert_eq!(d.set_text("R20", "0x10"), Ok(16));
    assert!(d.set_text("R20", "banana").is_err());
    assert_eq!(reg(&d, 20), 16);
    let r20 = d.find("r20").expect("R20 exists");
    d.toggle_bit(r20, 0).expect("a register bit flips");
    assert_eq!(reg(&d, 20), 17);
    assert!(matches!(
        d.set_text("R200", "1"),
        Err(EditError::Unknown(_))
    ));
    assert!(
        d.set_text("R20", "0x1_0000_0000").is_err(),
        "wider than 32 bits"
    );
    assert_eq!(reg(&d, 20), 17, "refused edits change nothing");
}
