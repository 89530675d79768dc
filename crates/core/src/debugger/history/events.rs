//! User events and running with them: what an edit changes, how it applies, and [`replay`],
//! the one loop that runs a machine applying each event at its position.

use crate::machine::{Loc, Machine, MachineView, Pos, StopReason, WriteError};

/// What an edit does to its location.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Change {
    /// Store this value (an input switch is a 1-bit location set to 0 or 1).
    Set(u64),
    /// Set or clear one bit, keeping the others as they are at that moment.
    Bit { bit: u8, on: bool },
    /// Force a bit to a level (Some) or release its force (None).
    Force(Option<bool>),
}

/// A change the user made, replayed when the run reaches its position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UserEvent {
    pub at: Pos,
    pub loc: Loc,
    pub change: Change,
}

impl UserEvent {
    pub fn apply<M: MachineView + ?Sized>(&self, m: &mut M) -> Result<(), WriteError> {
        let value = match self.change {
            Change::Force(level) => {
                let name = m.info(self.loc).map_or_else(String::new, |i| i.name);
                return match m.as_plc_mut() {
                    Some(plc) => plc.force(self.loc, level),
                    None => Err(WriteError::NotForceable(name)),
                };
            }
            Change::Set(v) => v,
            Change::Bit { bit, on } => {
                let v = m.read(self.loc);
                let b = 1u64.checked_shl(u32::from(bit)).unwrap_or(0);
                if on { v | b } else { v & !b }
            }
        };
        m.write(self.loc, value)
    }
}

/// Why `replay` calls its observer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Observed {
    /// A tick completed.
    Tick,
    /// Events were applied at the current position.
    Edits,
}

/// Run `m` until `limit`, a stop or `stop` (asked before each instruction starts), applying
/// each event of `events` (sorted by position) when the machine reaches its position. `next`
/// is the index of the first event not applied yet; `observe` runs after every tick and after
/// events apply.
pub fn replay<M: Machine, F: FnMut(&M) -> bool, O: FnMut(&M, Observed)>(
    m: &mut M,
    events: &[UserEvent],
    next: &mut usize,
    limit: Pos,
    mut stop: F,
    mut observe: O,
) -> StopReason {
    loop {
        if apply_due(m, events, next) {
            observe(m, Observed::Edits);
        }
        let until = events.get(*next).map_or(limit, |e| e.at.min(limit));
        let reason = m.run_observed(until, &mut stop, |m| observe(m, Observed::Tick));
        if apply_due(m, events, next) {
            observe(m, Observed::Edits);
        }
        if reason == StopReason::TickLimit && m.pos() < limit {
            continue;
        }
        return reason;
    }
}

/// [`replay`] with nothing asked and nothing observed: the headless runner's loop.
pub fn replay_bare<M: Machine>(
    m: &mut M,
    events: &[UserEvent],
    next: &mut usize,
    limit: Pos,
) -> StopReason {
    loop {
        apply_due(m, events, next);
        let until = events.get(*next).map_or(limit, |e| e.at.min(limit));
        let reason = m.run_bare(until);
        apply_due(m, events, next);
        if reason == StopReason::TickLimit && m.pos() < limit {
            continue;
        }
        return reason;
    }
}

/// Run `machine` until it stops or reaches `max_ticks`, applying each event when the machine
/// reaches its position; events before the current position count as already applied. This is
/// the timeline's own replay, so a run and a session agree.
/// `stop` is asked before every instruction.
pub fn run_events<M: Machine, F: FnMut(&M) -> bool>(
    machine: &mut M,
    events: &[UserEvent],
    max_ticks: u64,
    stop: F,
) -> StopReason {
    let mut events = events.to_vec();
    events.sort_by_key(|e| e.at);
    let mut next = events.partition_point(|e| e.at < machine.pos());
    replay(
        machine,
        &events,
        &mut next,
        Pos::at_tick(max_ticks),
        stop,
        |_, _| {},
    )
}

/// [`run_events`] with nothing to ask at the boundaries: the machine's fastest loop.
pub fn run_events_bare<M: Machine>(
    machine: &mut M,
    events: &[UserEvent],
    max_ticks: u64,
) -> StopReason {
    let mut events = events.to_vec();
    events.sort_by_key(|e| e.at);
    let mut next = events.partition_point(|e| e.at < machine.pos());
    replay_bare(machine, &events, &mut next, Pos::at_tick(max_ticks))
}

pub(super) fn apply_due<M: MachineView>(m: &mut M, events: &[UserEvent], next: &mut usize) -> bool {
    let now = m.pos();
    let mut applied = false;
    while let Some(e) = events.get(*next).filter(|e| e.at <= now) {
        // Refused edits were refused when recorded too; a damaged session's are skipped.
        let _ = e.apply(m);
        *next += 1;
        applied = true;
    }
    applied
}
