//! The fast paths agree with the slow ones: shared by the fast-loop tests of every dialect.

use proptest::prelude::*;
use servoscope_core::debugger::history::{Timeline, UserEvent};
use servoscope_core::debugger::trace::Channel;
use servoscope_core::machine::{Machine, Pos};

use super::channel_named;

/// `legs` runs to increasing positions: the fast loop and the executor agree at each.
pub fn fast_is_full<M: Machine>(start: M, legs: &[(u64, u32)]) -> Result<(), TestCaseError> {
    let mut fast = start.clone();
    let mut full = start;
    let mut tick = 0;
    for &(ticks, step) in legs {
        tick += ticks;
        let to = Pos { tick, step };
        let fast_reason = fast.run_bare(to);
        let full_reason = full.run_observed(to, |_| false, |_| {});
        prop_assert_eq!(fast_reason, full_reason);
        // (Machines hold thousands of registers: say where, not the whole state.)
        prop_assert!(fast == full, "the machines differ at {:?}", to);
    }
    Ok(())
}

/// The same run recorded through the quiet loop and scan by scan: the same recording.
pub fn quiet_is_observed<M: Machine>(
    start: M,
    events: Vec<UserEvent>,
    plotted: &[&str],
    written: &[&str],
    (first, end): (Pos, Pos),
) -> Result<(), TestCaseError> {
    let channels: Vec<Channel> = plotted.iter().map(|n| channel_named(&start, n)).collect();
    let mut quiet = Timeline::new(start.clone(), events.clone(), channels.clone());
    let mut observed = Timeline::new(start, events, channels);
    prop_assert_eq!(
        quiet.forward_unstopped(first),
        observed.forward(first, |_| false)
    );
    prop_assert_eq!(
        quiet.forward_unstopped(end),
        observed.forward(end, |_| false)
    );
    prop_assert!(quiet.machine == observed.machine, "the machines differ");
    prop_assert_eq!(quiet.furthest(), observed.furthest());
    prop_assert!(quiet.trace.samples().eq(observed.trace.samples()));
    prop_assert_eq!(quiet.trace.end_tick(), observed.trace.end_tick());
    let furthest = quiet.furthest();
    for at in [
        furthest,
        Pos::at_tick(furthest.tick / 2),
        Pos::at_tick(17_000),
    ] {
        for name in written {
            let loc = quiet.machine.find(name).expect("a location of the dialect");
            prop_assert_eq!(
                quiet.find_write_back(at, loc),
                observed.find_write_back(at, loc),
                "{} before {:?}",
                name,
                at
            );
        }
        quiet.goto(at);
        observed.goto(at);
        prop_assert!(quiet.machine == observed.machine, "the machines differ");
    }
    Ok(())
}
