//! Recording history: running forward with the trace, checkpoints and write sets, and the
//! quiet loop that runs stretches where no plotted value changes.

use super::{Observed, QUIET_WORTH, Timeline, replay, sample};
use crate::machine::{Loc, Machine, Pos, Quiet, StopReason, WriteSet};

impl<M: Machine> Timeline<M> {
    /// Run forward until `limit`, the end or a fault, or `stop` (asked before each instruction
    /// starts): applying events at their positions, recording the trace and checkpoints.
    pub fn forward<F: FnMut(&M) -> bool>(&mut self, limit: Pos, mut stop: F) -> StopReason {
        let every = self.checkpoint_every;
        let had = self.checkpoints.len();
        let Timeline {
            machine,
            trace,
            channels,
            checkpoints,
            written,
            events,
            next_event,
            furthest,
            stopped,
            ..
        } = self;
        let mut values = [0i64; crate::debugger::trace::MAX_CHANNELS];
        let n = channels.len();
        // The trace's newest sample while it is known, so an unchanged tick costs a comparison.
        let mut held: Option<[i64; crate::debugger::trace::MAX_CHANNELS]> = None;
        // Writes are noted only where history is new (a re-run noted them the first time).
        // The run loop asks `stop` at every boundary; the observer only says when a checkpoint
        // began a new stretch, so the set stays in a local until then.
        let known = *furthest;
        let new_stretch = std::cell::Cell::new(false);
        let mut set = WriteSet::default();
        let mut note = |m: &M, set: &mut WriteSet| {
            if new_stretch.replace(false) {
                if let Some(last) = written.last_mut() {
                    last.union(std::mem::take(set));
                }
                written.push(WriteSet::default());
            }
            if m.pos() > known {
                m.note_writes(set);
            }
        };
        let reason = replay(
            machine,
            events,
            next_event,
            limit,
            |m| {
                note(m, &mut set);
                stop(m)
            },
            |m, why| {
                let t = m.ticks();
                sample(m, channels, &mut values);
                if held.is_some_and(|h| h[..n] == values[..n]) {
                    // Unchanged since the trace's newest sample: only its end moves.
                    trace.extend_to(t);
                } else if trace.record(t, &values[..n]) {
                    // (A second record of a tick, after an edit, replaces its values.)
                    held = Some(values);
                } else {
                    held = None;
                }
                if why == Observed::Tick
                    && t.is_multiple_of(every)
                    && checkpoints.last().is_none_or(|c| c.ticks() < t)
                {
                    checkpoints.push(Box::new(m.clone()));
                    new_stretch.set(true);
                }
            },
        );
        // The last boundary is not asked by the run loop.
        note(machine, &mut set);
        if let Some(last) = written.last_mut() {
            last.union(set);
        }
        *furthest = (*furthest).max(machine.pos());
        if !machine.run_state().is_live() && machine.pos() == *furthest {
            *stopped = true;
        }
        if self.checkpoints.len() > had {
            self.thin_checkpoints();
        }
        reason
    }

    /// [`Timeline::forward`] for a run nothing stops: stretches in which no plotted location
    /// changes run in the machine's quiet loop, and the trace's newest sample is only held
    /// longer; every other tick (and each checkpoint's and event's position) is observed as
    /// usual. Records exactly what `forward` records.
    pub fn forward_unstopped(&mut self, limit: Pos) -> StopReason {
        self.forward_lines(limit, Vec::new(), |_| false)
    }

    /// [`Timeline::forward_unstopped`] for a run that `stop` may end only before an
    /// instruction on one of `lines` (line breakpoints): the quiet loop also halts before
    /// those, and `stop` is asked there as usual.
    pub fn forward_lines<F: FnMut(&M) -> bool>(
        &mut self,
        limit: Pos,
        lines: Vec<usize>,
        stop: F,
    ) -> StopReason {
        self.forward_quiet(limit, lines, Vec::new(), stop)
    }

    /// [`Timeline::forward_lines`] for a run that `stop` may also end right after an
    /// instruction that wrote one of `guarded` (data breakpoints): the quiet loop halts before
    /// such an instruction, and the timeline runs it, asking as usual. Where the machine cannot
    /// see a write coming, every boundary is asked.
    pub fn forward_quiet<F: FnMut(&M) -> bool>(
        &mut self,
        limit: Pos,
        lines: Vec<usize>,
        guarded: Vec<Loc>,
        mut stop: F,
    ) -> StopReason {
        // A plotted expression may read anything: every tick must be looked at.
        if self.channels.iter().any(|c| c.expr.is_some()) {
            return self.forward(limit, stop);
        }
        let mut quiet = Quiet {
            watched: self.channels.iter().map(|c| c.loc).collect(),
            lines,
            guarded,
            ..Quiet::default()
        };
        // Ticks observed when the quiet loop could not start: more while it keeps failing, so
        // a program that always moves pays little for asking.
        let mut observed = 1u64;
        loop {
            let now = self.machine.pos();
            if now >= limit || !self.machine.run_state().is_live() {
                return self.forward(limit, &mut stop);
            }
            let every = self.checkpoint_every;
            let checkpoint_due = Pos::at_tick((now.tick / every + 1).saturating_mul(every));
            let event_due = self.events.get(self.next_event).map(|e| e.at);
            let until = limit.min(checkpoint_due).min(event_due.unwrap_or(limit));
            // Right after a write of a data breakpoint's location (where an observed stretch
            // ended, unasked), the boundary is the timeline's to ask.
            let unasked_write = quiet.guarded.iter().any(|&loc| self.machine.wrote(loc));
            let progressed = if until > now && !unasked_write {
                let Some(reason) = self.machine.run_quiet(until, &mut quiet, &mut stop) else {
                    return self.forward(limit, stop);
                };
                let reached = self.machine.pos();
                if let Some(last) = self.written.last_mut() {
                    last.union(std::mem::take(&mut quiet.written));
                }
                // Only the last tick run may have changed a plotted value.
                if reached > now && reached.step == 0 {
                    let mut values = [0i64; crate::debugger::trace::MAX_CHANNELS];
                    sample(&self.machine, &self.channels, &mut values);
                    self.trace
                        .record(reached.tick, &values[..self.channels.len()]);
                }
                self.trace.extend_to(reached.tick);
                self.furthest = self.furthest.max(reached);
                if !self.machine.run_state().is_live() && reached == self.furthest {
                    self.stopped = true;
                }
                if reached == checkpoint_due
                    && self.checkpoints.last().is_none_or(|c| c.pos() < reached)
                {
                    self.checkpoints.push(Box::new(self.machine.clone()));
                    // The write that ends at a checkpoint belongs to the stretch it begins.
                    let mut set = WriteSet::default();
                    self.machine.note_writes(&mut set);
                    self.written.push(set);
                    self.thin_checkpoints();
                }
                if reason != StopReason::TickLimit {
                    return reason;
                }
                // A few ticks between moves are not worth the switching back and forth.
                reached >= until || reached.tick >= now.tick.saturating_add(QUIET_WORTH)
            } else {
                false
            };
            observed = if progressed {
                1
            } else {
                observed.saturating_mul(2).min(1024)
            };
            let here = self.machine.pos();
            let next = limit.min(Pos::at_tick(here.tick.saturating_add(observed)));
            let reason = self.forward(next, &mut stop);
            if reason != StopReason::TickLimit {
                return reason;
            }
        }
    }
}
