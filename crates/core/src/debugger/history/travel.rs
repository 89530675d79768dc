//! Going through recorded history: rebuilding any position from the nearest checkpoint,
//! searching back (for a write, or for a boundary a predicate wants), visiting each
//! instruction of a stretch.

use super::{Timeline, apply_due, replay};
use crate::machine::{Loc, Machine, Pos, StopReason};

impl<M: Machine> Timeline<M> {
    /// The last instruction boundary before `before` right after an instruction that wrote
    /// `loc`: only stretches whose write set may hold it are replayed. Leaves the machine
    /// where it was.
    pub fn find_write_back(&mut self, before: Pos, loc: Loc) -> Option<Pos> {
        let here = self.now();
        let mut i = self
            .checkpoints
            .partition_point(|c| c.pos() < before)
            .saturating_sub(1);
        let mut found = None;
        loop {
            if self.written.get(i).is_none_or(|w| w.may_hold(loc)) {
                let end = self
                    .checkpoints
                    .get(i + 1)
                    .map_or(before, |c| c.pos().min(before));
                self.restore(i);
                self.rerun(end, |m| {
                    if m.wrote(loc) {
                        found = Some(m.pos());
                    }
                    false
                });
                // The stretch's last boundary, at `end` itself, belongs to the next stretch
                // unless `end` is `before`; the run loop does not ask it either way.
            }
            if found.is_some() || i == 0 {
                break;
            }
            i -= 1;
        }
        self.goto(here);
        found
    }

    /// Re-run recorded history (at most to the furthest position): the trace and checkpoints
    /// already hold it, so nothing is recorded again.
    fn rerun<F: FnMut(&M) -> bool>(&mut self, limit: Pos, stop: F) -> StopReason {
        let limit = limit.min(self.furthest);
        replay(
            &mut self.machine,
            &self.events,
            &mut self.next_event,
            limit,
            stop,
            |_, _| {},
        )
    }

    /// Rebuild the state at `pos` (at most the furthest position reached); at the furthest
    /// position of a run that stopped there, the stop itself.
    pub fn goto(&mut self, pos: Pos) {
        let pos = pos.min(self.furthest);
        self.goto_live(pos);
        if pos == self.furthest && self.stopped && self.machine.run_state().is_live() {
            self.rerun_stop();
        }
    }

    /// Rebuild the state at `pos` as a run arrives there: at the furthest position of a run
    /// that stopped there, the moment before the stopping instruction (where stepping up to a
    /// SilverLode fault pauses, the fault not having moved the position).
    pub fn goto_live(&mut self, pos: Pos) {
        let pos = pos.min(self.furthest);
        let i = self
            .checkpoints
            .partition_point(|c| c.pos() <= pos)
            .saturating_sub(1);
        self.restore(i);
        self.rerun(pos, |_| false);
    }

    /// At the furthest position: run the instruction there if it ends or faults the run (tried
    /// on a copy first, so a run that goes on records nothing and `furthest` stays), recording
    /// the stop as running forward does. True when the machine is stopped.
    pub fn run_into_stop(&mut self) -> bool {
        if !self.machine.run_state().is_live() {
            return true;
        }
        let at = self.machine.pos();
        if at != self.furthest {
            return false;
        }
        let next = Pos {
            tick: at.tick,
            step: at.step.saturating_add(1),
        };
        let mut probe = self.machine.clone();
        let mut next_event = self.next_event;
        replay(
            &mut probe,
            &self.events,
            &mut next_event,
            next,
            |_| false,
            |_, _| {},
        );
        if probe.run_state().is_live() {
            return false;
        }
        self.forward(next, |_| false);
        !self.machine.run_state().is_live()
    }

    /// At the furthest position of a run that stopped there: run the instruction that ended or
    /// faulted it, so the stop shows as it happened (its fault, flags and message).
    fn rerun_stop(&mut self) {
        let at = self.machine.pos();
        let next = Pos {
            tick: at.tick,
            step: at.step.saturating_add(1),
        };
        replay(
            &mut self.machine,
            &self.events,
            &mut self.next_event,
            next,
            |_| false,
            |_, _| {},
        );
    }

    fn restore(&mut self, checkpoint: usize) {
        self.machine = M::clone(&self.checkpoints[checkpoint]);
        let at = self.machine.pos();
        self.next_event = self.events.partition_point(|e| e.at < at);
        apply_due(&mut self.machine, &self.events, &mut self.next_event);
    }

    /// The last position before `before` where an instruction was about to start and `wanted`
    /// holds, searching back one checkpoint interval at a time. `wanted` is told when a boundary
    /// is the first of a stretch replayed from a checkpoint (a predicate comparing with the
    /// previous boundary has nothing to compare with there); each stretch runs on to the first
    /// boundary of the stretch after it, so that boundary is also asked with its predecessor
    /// seen. Leaves the machine where it was.
    pub fn find_back<F: FnMut(&M, bool) -> bool>(
        &mut self,
        before: Pos,
        mut wanted: F,
    ) -> Option<Pos> {
        let mut search = BackSearch::new(before);
        while !search.is_done() {
            self.find_back_some(&mut search, u64::MAX, &mut wanted);
        }
        search.found()
    }

    /// Go on with `search` ([`Timeline::find_back`] over several calls): stretches, newest
    /// first, until it is done or `budget` ticks have been replayed (at least one stretch is
    /// replayed, unless it is done: a stretch is at most two checkpoint intervals of replay).
    /// Returns the ticks replayed. Leaves the machine where it was.
    ///
    /// A stretch inside one long instruction (a move, a delay: waiting at both ends with no
    /// instruction completed between) has no boundary and is passed over without replay, and a
    /// stretch that runs on into such an instruction jumps to the last checkpoint inside it:
    /// nothing is asked while a machine waits, and it leaves a wait only by completing the
    /// instruction, which the step counter counts.
    pub fn find_back_some<F: FnMut(&M, bool) -> bool>(
        &mut self,
        search: &mut BackSearch,
        budget: u64,
        mut wanted: F,
    ) -> u64 {
        let here = self.machine.clone();
        let here_next = self.next_event;
        let mut spent = 0u64;
        while !search.done && (spent == 0 || spent < budget) {
            let end = search.end;
            let i = self
                .checkpoints
                .partition_point(|c| c.pos() < end)
                .saturating_sub(1);
            let start = self.checkpoints[i].pos();
            let at_end = match self.checkpoints.get(i + 1) {
                Some(c) if c.pos() == end => Some(&**c),
                _ if end == here.pos() => Some(&here),
                _ => None,
            };
            let no_boundary = at_end.is_some_and(|e| waits_throughout(&*self.checkpoints[i], e));
            if !no_boundary {
                let (found, ticks) = self.ask_stretch(i, search.before, end, &mut wanted);
                spent = spent.saturating_add(ticks.max(1));
                if found.is_some() {
                    search.found = found;
                    search.done = true;
                }
            }
            if start == Pos::default() {
                search.done = true;
            }
            search.end = start;
        }
        self.machine = here;
        self.next_event = here_next;
        spent
    }

    /// Replay the stretch from checkpoint `i`, asking `wanted` at each boundary before
    /// `before`, on to the first boundary at or after `end`. Returns the last match and the
    /// ticks replayed.
    fn ask_stretch<F: FnMut(&M, bool) -> bool>(
        &mut self,
        i: usize,
        before: Pos,
        end: Pos,
        wanted: &mut F,
    ) -> (Option<Pos>, u64) {
        self.restore(i);
        let from = self.machine.ticks();
        let mut first = true;
        let mut found = None;
        let mut ask = |m: &M| {
            let p = m.pos();
            // Nothing at or after `before` is asked: a stateful predicate's record of its
            // last match is then the match `found` names.
            if p < before && wanted(m, std::mem::take(&mut first)) {
                found = Some(p);
            }
            p >= end
        };
        let reason = self.rerun(end, &mut ask);
        let mut ticks = self.machine.ticks() - from;
        if reason == StopReason::TickLimit && self.machine.pos() < before {
            // The next boundary may lie at the end of a long wait: skip to its last checkpoint.
            let m = &self.machine;
            let last = self
                .checkpoints
                .partition_point(|c| c.pos() <= before)
                .saturating_sub(1);
            if last > i && waits_throughout(m, &*self.checkpoints[last]) {
                self.restore(last);
            }
            let resumed = self.machine.ticks();
            self.rerun(before, &mut ask);
            ticks += self.machine.ticks() - resumed;
        }
        (found, ticks)
    }

    /// Call `f` after every instruction that ends in `from < p <= to` (p = `m.pos()`), in order,
    /// until it returns false; the last instruction of a run that ended or faulted counts.
    /// Leaves the machine where it was.
    pub fn visit<F: FnMut(&M) -> bool>(&mut self, from: Pos, to: Pos, mut f: F) {
        let here = self.now();
        let to = to.min(self.furthest);
        let i = self
            .checkpoints
            .partition_point(|c| c.pos() <= from)
            .saturating_sub(1);
        self.restore(i);
        let mut seen = self.machine.steps();
        let mut go = true;
        self.rerun(self.furthest, |m| {
            let p = m.pos();
            if p > to {
                return true;
            }
            if p > from && m.steps() > seen {
                go = f(m);
            }
            seen = m.steps();
            !go
        });
        // The last boundary (the furthest position, or after END or a fault) is not asked by
        // the run loop: nothing runs after it.
        let m = &self.machine;
        if go && m.steps() > seen && m.pos() > from && m.pos() <= to {
            f(m);
        }
        self.goto(here);
    }
}

/// A search back through the timeline that goes on over several calls
/// ([`Timeline::find_back_some`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BackSearch {
    before: Pos,
    /// Every boundary from here to `before` has been asked.
    end: Pos,
    found: Option<Pos>,
    done: bool,
}

impl BackSearch {
    /// A search for the last boundary before `before`.
    pub fn new(before: Pos) -> Self {
        BackSearch {
            before,
            end: before,
            found: None,
            done: before == Pos::default(),
        }
    }
    pub fn is_done(&self) -> bool {
        self.done
    }
    /// What it found (None while searching, or when nothing matched).
    pub fn found(&self) -> Option<Pos> {
        self.found
    }
    /// How far back it has searched.
    pub fn reached(&self) -> Pos {
        self.end
    }
}

/// Whether `later` is inside the same instruction as `earlier`: both wait, and no instruction
/// completed between them, so no instruction boundary lies between them.
fn waits_throughout<M: Machine>(earlier: &M, later: &M) -> bool {
    matches!(earlier.run_state(), crate::machine::RunState::Waiting(_))
        && matches!(later.run_state(), crate::machine::RunState::Waiting(_))
        && earlier.steps() == later.steps()
        && earlier.pos() <= later.pos()
}
