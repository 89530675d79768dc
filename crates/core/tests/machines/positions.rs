//! (tick, step) positions for a scanned machine: a tick is a whole scan of many instructions;
//! the debugger steps, steps back, breaks and edits *inside* a scan, and replay reproduces it
//! exactly. SilverLode fills a tick with one command, so these run on a small scanned machine
//! written here against the same traits every dialect implements.

use crate::common;

use std::time::Duration;

use common::scanned::{IN, PROGRAM, SCANNED, Scanned, v};
use servoscope_core::debugger::history::{Change, UserEvent};
use servoscope_core::debugger::{Debugger, Event, Speed};
use servoscope_core::machine::{Loc, Pos};
use servoscope_core::registry::Settings;

fn scanned(d: &Debugger) -> &Scanned {
    d.machine_as::<Scanned>().expect("the scanned machine")
}

fn at(tick: u64, step: u32) -> Pos {
    Pos { tick, step }
}

#[test]
fn steps_walk_through_a_scan_and_back() {
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    assert!(d.diagnostics().is_empty());
    let mut seen = vec![d.pos()];
    for _ in 0..7 {
        d.step_command();
        seen.push(d.pos());
    }
    assert_eq!(
        seen,
        [
            at(0, 0),
            at(0, 1),
            at(0, 2),
            at(0, 3),
            at(0, 4),
            at(1, 0),
            at(1, 1),
            at(1, 2)
        ],
        "one instruction per step; END closes the scan"
    );
    assert_eq!(d.machine().pc_line(), Some(3), "about to read the input");
    assert_eq!(
        scanned(&d).v[..2],
        [2, 2],
        "scan 1 ran its ADD and its COPY"
    );

    d.step_back_command();
    assert_eq!(d.pos(), at(1, 1), "back one instruction inside the scan");
    d.step_back_command();
    d.step_back_command();
    assert_eq!(d.pos(), at(0, 4), "back across the scan boundary to END");
    d.step_tick();
    assert_eq!(d.pos(), at(1, 0), "the rest of the scan");
    d.step_command();
    d.step_tick();
    assert_eq!(d.pos(), at(2, 0));
    d.step_back_tick();
    assert_eq!(d.pos(), at(1, 0), "to the start of the previous scan");
    d.goto(at(1, 3));
    assert_eq!(d.pos(), at(1, 3));
    d.step_back_tick();
    assert_eq!(d.pos(), at(1, 0), "to the start of this scan");
}

/// A straight walk, one instruction at a time, with edits at positions inside scans; returns
/// the machine at every position.
fn straight(d: &mut Debugger, edits: &[(Pos, Loc, u64)], scans: u64) -> Vec<Scanned> {
    let mut states = vec![scanned(d).clone()];
    while d.pos() < at(scans, 0) {
        let now = d.pos();
        for &(_, loc, value) in edits.iter().filter(|e| e.0 == now) {
            d.set_value(loc, value).expect("an edit");
            *states.last_mut().expect("one state") = scanned(d).clone();
        }
        d.step_command();
        states.push(scanned(d).clone());
    }
    states
}

#[test]
fn edits_inside_a_scan_replay_exactly() {
    let edits = [
        (at(1, 2), v(0), 100),
        (at(2, 1), Loc::new(IN, 0), 1),
        (at(3, 4), v(3), 7),
        (at(5, 0), v(5), 9),
    ];
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    let reference = straight(&mut d, &edits, 8);
    assert_eq!(reference.len(), 8 * 5 + 1);
    // The edit at (1, 2) came after COPY of scan 1: V1 keeps 2, V0 jumps to 100.
    let after = &reference[5 + 2]; // scan 1, after its second instruction
    assert_eq!((after.v[0], after.v[1]), (100, 2));
    // X0 switched on at (2, 1) is read by IN at step 2 of that same scan.
    assert_eq!(reference[2 * 5 + 3].v[2], 1);

    // Every position, reached by going there, is the straight walk's state.
    for (i, want) in reference.iter().enumerate().rev() {
        let pos = at(i as u64 / 5, i as u32 % 5);
        d.goto(pos);
        assert_eq!(scanned(&d), want, "at {pos}");
    }

    // A debugger restored from the events (as a session does) walks the same states.
    let events: Vec<UserEvent> = d.events().to_vec();
    assert_eq!(events.len(), edits.len());
    let mut r = Debugger::restore(
        &SCANNED,
        "p.scan",
        PROGRAM,
        &Settings::new(),
        [],
        None,
        events,
        at(8, 0),
    )
    .expect("restores");
    assert_eq!(r.furthest(), at(8, 0));
    for (i, want) in reference.iter().enumerate() {
        r.goto(at(i as u64 / 5, i as u32 % 5));
        assert_eq!(scanned(&r), want, "restored, step {i}");
    }
}

#[test]
fn an_edit_in_the_past_inside_a_scan_discards_the_future() {
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    for _ in 0..12 {
        d.step_command();
    }
    assert_eq!(d.pos(), at(2, 2));
    d.goto(at(1, 3));
    d.set_value(v(7), 42).expect("an edit");
    assert_eq!(d.event(), Some(&Event::FutureDiscarded(1)));
    assert_eq!(d.furthest(), at(1, 3), "the recorded future is gone");
    assert_eq!(
        d.events()[0],
        UserEvent {
            at: at(1, 3),
            loc: v(7),
            change: Change::Set(42)
        }
    );
}

#[test]
fn breakpoints_stop_before_their_instruction_in_every_scan() {
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    d.set_speed(Speed::Unlimited);
    d.toggle_breakpoint(4);
    let mut stops = Vec::new();
    for _ in 0..3 {
        d.run();
        while d.advance(0.016, Duration::from_secs(5)) {}
        assert_eq!(d.event(), Some(&Event::Breakpoint(4)));
        stops.push(d.pos());
    }
    assert_eq!(stops, [at(0, 3), at(1, 3), at(2, 3)]);
    d.step_tick();
    d.reverse_continue();
    assert_eq!(d.pos(), at(2, 3), "the last hit before here");
    d.reverse_continue();
    assert_eq!(d.pos(), at(1, 3));
}

#[test]
fn stepping_a_scan_and_the_status_words() {
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    assert_eq!(d.dialect().vocabulary.tick, "scan");
    d.step_tick();
    d.step_tick();
    assert_eq!(d.pos(), at(2, 0));
    assert_eq!(
        d.machine().steps(),
        10,
        "five instructions a scan, END included"
    );
    assert_eq!(scanned(&d).v[3], 20);
}
