//! A run lent to the worker thread between frames records exactly the run the frames would
//! make themselves: same positions, same state, same trace, input switches and breakpoints
//! included.

use std::time::Duration;

use servoscope_core::debugger::{Breakpoint, Debugger, Event, Speed};
use servoscope_core::machine::{Loc, Pos};

/// Moves forth while IO1 is high and back while it is low: the trace changes with the input.
const SHUTTLE: &str = "\
loop: WBS IO1
      MRV 4000, 3865, 67108864
      WBS !IO1
      MRV -2500, 3865, 67108864
      CLC INC, 30
      JMP loop
";

fn debugger(source: &str) -> Debugger {
    let d = Debugger::new("test", source);
    assert!(!d.has_errors(), "{:?}", d.diagnostics());
    d
}

/// Every location of every space, in order.
fn state(d: &Debugger) -> Vec<u64> {
    let m = d.machine();
    m.spaces()
        .iter()
        .enumerate()
        .flat_map(|(space, s)| (0..s.len).map(move |i| m.read(Loc::new(space as u8, i))))
        .collect()
}

/// Frames as the window makes them: take the run back, let `each_frame` act, lend it again.
fn frames(d: &mut Debugger, mut each_frame: impl FnMut(&mut Debugger, usize)) -> usize {
    let mut n = 0;
    while d.advance(0.016, Duration::from_millis(5)) {
        each_frame(d, n);
        n += 1;
        d.hand_off();
        std::thread::sleep(Duration::from_millis(1));
    }
    n
}

#[test]
fn a_run_on_the_worker_with_input_switches_is_the_straight_run() {
    let mut d = debugger(SHUTTLE);
    d.set_speed(Speed::Unlimited);
    let io1 = d.find("IO1").expect("IO1 exists");
    // Long enough to take a few frames in a release build too (400,000 ticks fitted in one).
    let end = 4_000_000;
    d.goto_tick(end);
    assert!(d.is_running(), "going past the furthest tick runs there");
    let mut high = false;
    let n = frames(&mut d, |d, frame| {
        if frame % 2 == 0 {
            high = !high;
            d.set_input(io1, high).expect("an input switch is taken");
        }
    });
    assert!(n >= 2, "the run took {n} frames");
    assert_eq!(d.pos(), Pos::at_tick(end));
    assert_eq!(d.event(), Some(&Event::ReachedTick(end)));
    let switches = d.events().to_vec();
    assert!(switches.len() >= 2, "{switches:?}");
    assert!(
        switches.iter().any(|e| e.at.tick > 0),
        "switches land where the worker had got to"
    );

    // The same program and switches, replayed straight in one go.
    let straight = Debugger::restore(
        d.dialect(),
        "straight",
        SHUTTLE,
        d.settings(),
        [],
        None,
        switches,
        Pos::at_tick(end),
    )
    .expect("the program assembles");
    assert_eq!(straight.pos(), d.pos());
    assert_eq!(state(&straight), state(&d));
    assert!(d.trace().len() > 2, "the motion is in the trace");
    assert!(
        straight.trace().samples().eq(d.trace().samples()),
        "the traces differ"
    );
    assert!(
        d.machine().read(d.find("R30").expect("R30")) > 0,
        "the shuttle went back and forth"
    );
}

#[test]
fn a_breakpoint_stops_the_worker_where_it_stops_a_run_in_the_frames() {
    let program = common_loop();
    let mut in_frames = debugger(&program);
    let mut threaded = debugger(&program);
    for d in [&mut in_frames, &mut threaded] {
        d.set_speed(Speed::Unlimited);
        d.add_breakpoint(Breakpoint::line(3).with_condition("R20 % 200000 == 0"));
        d.run();
    }
    while in_frames.advance(0.016, Duration::from_millis(50)) {}
    frames(&mut threaded, |_, _| {});
    assert_eq!(threaded.event(), Some(&Event::Breakpoint(3)));
    assert_eq!(threaded.event(), in_frames.event());
    assert_eq!(threaded.pos(), in_frames.pos());
    assert_eq!(state(&threaded), state(&in_frames));
    assert_eq!(threaded.breakpoint_hits(0), 1);

    // Continuing resumes past the breakpoint, on the worker too.
    threaded.run();
    in_frames.run();
    while in_frames.advance(0.016, Duration::from_millis(50)) {}
    frames(&mut threaded, |_, _| {});
    assert_eq!(threaded.pos(), in_frames.pos());
    assert_eq!(threaded.event(), in_frames.event());
    assert_eq!(threaded.breakpoint_hits(0), 2);
    assert_eq!(state(&threaded), state(&in_frames));
}

#[test]
fn pause_takes_the_run_back_from_the_worker_at_once() {
    let mut d = debugger(&common_loop());
    d.set_speed(Speed::Unlimited);
    d.run();
    assert!(d.advance(0.016, Duration::from_millis(1)));
    d.hand_off();
    std::thread::sleep(Duration::from_millis(20));
    assert!(d.advance(0.016, Duration::from_millis(1)), "still running");
    d.pause();
    assert!(!d.is_running());
    let paused = d.pos();
    assert!(paused.tick > 0, "the worker ran meanwhile");
    assert!(matches!(d.event(), Some(Event::Paused(Some(_)))));
    // The debugger has its engine back: stepping goes on from there.
    d.step_command();
    assert!(d.pos() > paused);
    d.hand_off();
    assert!(
        !d.advance(0.016, Duration::from_millis(1)),
        "nothing was running"
    );
}

#[test]
fn the_rate_of_a_run_is_measured() {
    let mut d = debugger(&common_loop());
    d.set_speed(Speed::Unlimited);
    assert_eq!(d.run_rate(), None);
    d.run();
    let started = std::time::Instant::now();
    frames(&mut d, |d, _| {
        if started.elapsed() > Duration::from_millis(700) {
            d.pause();
        }
    });
    let rate = d.run_rate();
    assert_eq!(rate, None, "a paused run has no rate");
    d.run();
    let started = std::time::Instant::now();
    let mut seen = None;
    frames(&mut d, |d, _| {
        if started.elapsed() > Duration::from_millis(700) {
            seen = d.run_rate();
            d.pause();
        }
    });
    let rate = seen.expect("a rate after half a second");
    assert!(rate > 1000.0, "{rate} ticks/s");
}

/// A loop long enough not to end during a test.
fn common_loop() -> String {
    "      WRP 21, 1\nloop: CLD ADD, 20, 20, 1\n      CLX ADD, 22, 22, 21\n      JMP loop\n"
        .to_string()
}
