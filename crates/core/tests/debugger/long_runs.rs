//! A run left going keeps its memory: the timeline's checkpoints stay within their budget
//! (every other one goes and the interval doubles), and time travel over the thinned
//! history gives exactly what it gives over the full one.

use crate::common;

use servoscope_core::debugger::history::{CHECKPOINT_BUDGET, CHECKPOINT_EVERY, Change, Timeline};
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::view::reg;
use servoscope_core::machine::{Machine, MachineView, Pos};

const IDIOM: &str = include_str!("../../benches/common/idiom.qsl");

fn timeline(budget: Option<usize>) -> Timeline<SilverLode> {
    let mut t = Timeline::new(common::machine(IDIOM), Vec::new(), Vec::new());
    if let Some(bytes) = budget {
        t.set_checkpoint_budget(bytes);
    }
    t
}

/// The same run on both: forward in pieces, an edit of the step (R21) in the past, which
/// discards the future, and forward again.
fn drive(t: &mut Timeline<SilverLode>) {
    for k in 1..=8 {
        t.forward(Pos::at_tick(k * 8 * CHECKPOINT_EVERY + 77), |_| false);
    }
    t.goto(Pos::at_tick(41 * CHECKPOINT_EVERY + 5));
    t.edit(reg(21), Change::Set(9))
        .expect("R21 takes any value");
    t.forward(Pos::at_tick(96 * CHECKPOINT_EVERY + 3), |_| false);
}

#[test]
fn checkpoints_stay_within_their_budget_and_time_travel_is_unchanged() {
    let mut full = timeline(None);
    drive(&mut full);
    let each = full.machine.snapshot_bytes();
    // Room for about 10 checkpoints, where the run makes 97.
    let budget = 10 * (each + 32);
    let mut thinned = timeline(Some(budget));
    drive(&mut thinned);

    assert_eq!(full.checkpoint_interval(), CHECKPOINT_EVERY);
    assert!(
        thinned.checkpoint_bytes() <= budget,
        "{} bytes of checkpoints for a budget of {budget}",
        thinned.checkpoint_bytes()
    );
    // 97 checkpoints into at most 10: the interval doubled four times.
    assert_eq!(thinned.checkpoint_interval(), 16 * CHECKPOINT_EVERY);
    assert_eq!(thinned.furthest(), full.furthest());

    for tick in [
        0,
        1,
        CHECKPOINT_EVERY - 1,
        17 * CHECKPOINT_EVERY + 3,
        41 * CHECKPOINT_EVERY + 4,
        41 * CHECKPOINT_EVERY + 5,
        41 * CHECKPOINT_EVERY + 6,
        80 * CHECKPOINT_EVERY,
        96 * CHECKPOINT_EVERY + 3,
    ] {
        full.goto(Pos::at_tick(tick));
        thinned.goto(Pos::at_tick(tick));
        assert!(full.machine == thinned.machine, "the state at tick {tick}");
    }
    // The edit holds from its position: the step is 9 after it, 7 before.
    thinned.goto(Pos::at_tick(41 * CHECKPOINT_EVERY + 4));
    assert_eq!(thinned.machine.read(reg(21)), 7);
    thinned.goto(Pos::at_tick(60 * CHECKPOINT_EVERY));
    assert_eq!(thinned.machine.read(reg(21)), 9);

    // "Who wrote this?" over stretches merged by the thinning: R25 (the rounds) is written by
    // every round, R21 only by the program's start and the edit.
    let before = Pos::at_tick(90 * CHECKPOINT_EVERY + 11);
    for loc in [reg(25), reg(21)] {
        assert_eq!(
            thinned.find_write_back(before, loc),
            full.find_write_back(before, loc),
            "the last write of {loc:?}"
        );
    }
    assert!(
        full.find_write_back(before, reg(25))
            .is_some_and(|p| p.tick > 90 * CHECKPOINT_EVERY)
    );
}

#[test]
fn the_default_budget_bounds_an_unlimited_run_of_the_idiom() {
    let t = timeline(None);
    // 256 MiB of 1 KiB-scale checkpoints: a run of hours, not of seconds, reaches it.
    let checkpoints = CHECKPOINT_BUDGET / t.machine.snapshot_bytes();
    assert!(checkpoints > 100_000, "{checkpoints} checkpoints fit");
}

#[test]
fn a_plcs_checkpoint_counts_its_memory() {
    // DL205: V0–V37777 (octal), 16 bits each (spec §3): 32 KiB a copy.
    let dl = servoscope_core::machine::dl205::dialect::machine("STR X0\nOUT Y0\nEND\n")
        .expect("a DL205 program");
    assert!(
        dl.snapshot_bytes() >= 0o40000 * 2,
        "{}",
        dl.snapshot_bytes()
    );
    // OpenNet: D0–D7999, 16 bits each (spec §2).
    let on = servoscope_core::machine::opennet::dialect::machine("LOD I0\nOUT Q0\nEND\n")
        .expect("an OpenNet program");
    assert!(on.snapshot_bytes() >= 8000 * 2, "{}", on.snapshot_bytes());
}
