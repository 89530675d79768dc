//! The seam between the dialect-neutral debugger and a dialect's concrete machine.
//!
//! [`Engine`] is object-safe: the debugger holds a `Box<dyn Engine>` and calls it once per
//! user action or per frame slice. [`Core`] implements it for any [`Machine`] with the
//! timeline's loops compiled for that machine, so breakpoint checks, event replay and trace
//! recording run without dynamic dispatch per executed instruction.

use std::cell::RefCell;

use super::breakpoints::Checker;
use super::history::{BackSearch, Change, Mark, MarkKind, Timeline, UserEvent};
use super::trace::{Channel, Trace};
use crate::machine::{Loc, Machine, MachineView, Pos, StopReason, WriteError};

/// When a forward run stops, as data, so the check is compiled into each dialect's loop.
#[derive(Clone, Copy, Default)]
pub struct StopWhen<'a> {
    /// The breakpoints (line and data, with conditions, counts and log points).
    pub checker: Option<&'a RefCell<Checker>>,
    /// Run to this line.
    pub line: Option<usize>,
    /// Stop at the first instruction boundary after this position (step one instruction).
    pub after: Option<Pos>,
    /// Stop at any instruction boundary.
    pub any: bool,
    /// Do not stop at the very first boundary (resuming from a breakpoint).
    pub skip_first: bool,
    /// Stop when the machine's error lamp is on (set only when it was off as the run began).
    pub on_error: bool,
    /// Stop only where at most this many calls are in progress (and past `after`, if set):
    /// step over and step out, forward and back.
    pub depth_at_most: Option<usize>,
}

impl StopWhen<'_> {
    /// Nothing can stop the run (going to a tick, replaying): the loop need not ask.
    pub fn is_never(&self) -> bool {
        !self.any
            && !self.on_error
            && self.after.is_none()
            && self.depth_at_most.is_none()
            && self.line.is_none()
            && self.checker.is_none()
    }

    /// The lines before which it may stop and the locations after whose writes it may stop,
    /// when those are the only boundaries it needs to see (breakpoints and run to line; not a
    /// step or the error lamp).
    pub fn quiet_plan(&self) -> Option<(Vec<usize>, Vec<Loc>)> {
        if self.any || self.on_error || self.after.is_some() || self.depth_at_most.is_some() {
            return None;
        }
        let (mut lines, written) = match self.checker {
            Some(c) => c.borrow().quiet_plan(),
            None => (Vec::new(), Vec::new()),
        };
        lines.extend(self.line);
        Some((lines, written))
    }

    /// Whether to stop before the instruction `m` is about to run.
    #[inline]
    pub fn holds<M: MachineView + ?Sized>(&self, m: &M) -> bool {
        if self.any || (self.on_error && m.error_lamp()) {
            return true;
        }
        match (self.depth_at_most, self.after) {
            (Some(depth), after)
                if after.is_none_or(|a| m.pos() > a) && m.call_depth() <= depth =>
            {
                return true;
            }
            (Some(_), _) => {}
            (None, Some(after)) if m.pos() > after => return true,
            _ => {}
        }
        if let Some(line) = self.line
            && m.pc_line() == Some(line)
        {
            return true;
        }
        self.checker.is_some_and(|c| c.borrow_mut().check(m))
    }
}

/// A machine with its timeline, seen through a dialect-neutral interface.
pub trait Engine: Send {
    fn machine(&self) -> &dyn MachineView;
    /// A fresh timeline at the start of the same program and settings, with these events.
    fn restarted(&self, events: Vec<UserEvent>, channels: Vec<Channel>) -> Box<dyn Engine>;
    fn furthest(&self) -> Pos;
    /// Whether the run ended or faulted at the furthest position.
    fn stopped(&self) -> bool;
    /// Run forward to `limit` or until `stop` holds (never before the first instruction when
    /// `skip_first`).
    fn forward(&mut self, limit: Pos, stop: &StopWhen<'_>) -> StopReason;
    /// Rebuild the state at `pos` (clamped to the furthest position).
    fn goto(&mut self, pos: Pos);
    /// [`Engine::goto`], but at a stopped run's furthest position the moment before the stop.
    fn goto_live(&mut self, pos: Pos);
    /// At the furthest position, run the instruction there if it stops the run (see
    /// [`Timeline::run_into_stop`]); true when the machine is stopped.
    fn run_into_stop(&mut self) -> bool;
    /// The last instruction boundary before `before` where `wanted` holds.
    fn find_back(&mut self, before: Pos, wanted: &StopWhen<'_>) -> Option<Pos>;
    /// Go on with a search back for `wanted`, replaying about `budget` ticks at most (see
    /// [`Timeline::find_back_some`]); returns the ticks replayed.
    fn find_back_some(
        &mut self,
        search: &mut BackSearch,
        budget: u64,
        wanted: &StopWhen<'_>,
    ) -> u64;
    /// The last boundary before `before` right after an instruction that wrote `loc`.
    fn find_write_back(&mut self, before: Pos, loc: Loc) -> Option<Pos>;
    /// Call `f` after each recorded instruction ending in `from < p <= to`, until it says stop.
    fn visit(&mut self, from: Pos, to: Pos, f: &mut dyn FnMut(&dyn MachineView) -> bool);
    /// A user edit at the current position; `Ok(true)` when it discarded a recorded future.
    fn edit(&mut self, loc: Loc, change: Change) -> Result<bool, WriteError>;
    fn events(&self) -> &[UserEvent];
    fn marks(&self) -> &[Mark];
    fn mark(&mut self, kind: MarkKind, line: usize);
    fn mark_at(&mut self, at: Pos, kind: MarkKind, line: usize);
    fn trace(&self) -> &Trace;
    fn channels(&self) -> &[Channel];
    fn memory_bytes(&self) -> usize;
    /// Run the machine straight to `limit` with `events`, recording nothing (the headless
    /// runner). The timeline's history is not kept: use only on a fresh engine.
    fn run_headless(&mut self, events: &[UserEvent], max_ticks: u64);
    /// [`Engine::run_headless`], asking `stop` at every instruction boundary (the runner's
    /// `--trace` and `--break`).
    fn run_headless_observed(
        &mut self,
        events: &[UserEvent],
        max_ticks: u64,
        stop: &mut dyn FnMut(&dyn MachineView) -> bool,
    ) -> StopReason;
}

/// A boundary asked by a search back: data breakpoints compare with the first boundary of a
/// replayed stretch from there on.
fn asked_going_back<M: MachineView>(wanted: &StopWhen<'_>, m: &M, first: bool) -> bool {
    if first && let Some(c) = wanted.checker {
        c.borrow_mut().prime(m);
    }
    wanted.holds(m)
}

/// The engine for one dialect's machine type.
pub struct Core<M: Machine> {
    timeline: Timeline<M>,
}

/// A debuggable engine for `machine` at its start, with no events and no channels.
pub fn engine<M: Machine>(machine: M) -> Box<dyn Engine> {
    Box::new(Core {
        timeline: Timeline::new(machine, Vec::new(), Vec::new()),
    })
}

impl<M: Machine> Engine for Core<M> {
    fn machine(&self) -> &dyn MachineView {
        &self.timeline.machine
    }
    fn restarted(&self, events: Vec<UserEvent>, channels: Vec<Channel>) -> Box<dyn Engine> {
        Box::new(Core {
            timeline: Timeline::new(self.timeline.initial().clone(), events, channels),
        })
    }
    fn furthest(&self) -> Pos {
        self.timeline.furthest()
    }
    fn stopped(&self) -> bool {
        self.timeline.stopped()
    }
    fn forward(&mut self, limit: Pos, stop: &StopWhen<'_>) -> StopReason {
        if stop.is_never() {
            return self.timeline.forward_unstopped(limit);
        }
        // Resuming from a breakpoint skips the position the run starts at, wherever the first
        // question comes (a quiet stretch asks only before breakpoint lines).
        let start = self.timeline.now();
        let skip = stop.skip_first;
        let asked = move |m: &M| {
            if skip && m.pos() == start {
                return false;
            }
            stop.holds(m)
        };
        if let Some((lines, written)) = stop.quiet_plan() {
            return self.timeline.forward_quiet(limit, lines, written, asked);
        }
        self.timeline.forward(limit, asked)
    }
    fn goto(&mut self, pos: Pos) {
        self.timeline.goto(pos);
    }
    fn goto_live(&mut self, pos: Pos) {
        self.timeline.goto_live(pos);
    }
    fn run_into_stop(&mut self) -> bool {
        self.timeline.run_into_stop()
    }
    fn find_back(&mut self, before: Pos, wanted: &StopWhen<'_>) -> Option<Pos> {
        self.timeline
            .find_back(before, |m, first| asked_going_back(wanted, m, first))
    }
    fn find_back_some(
        &mut self,
        search: &mut BackSearch,
        budget: u64,
        wanted: &StopWhen<'_>,
    ) -> u64 {
        self.timeline.find_back_some(search, budget, |m, first| {
            asked_going_back(wanted, m, first)
        })
    }
    fn find_write_back(&mut self, before: Pos, loc: Loc) -> Option<Pos> {
        self.timeline.find_write_back(before, loc)
    }
    fn visit(&mut self, from: Pos, to: Pos, f: &mut dyn FnMut(&dyn MachineView) -> bool) {
        self.timeline.visit(from, to, |m| f(m));
    }
    fn edit(&mut self, loc: Loc, change: Change) -> Result<bool, WriteError> {
        self.timeline.edit(loc, change)
    }
    fn events(&self) -> &[UserEvent] {
        self.timeline.events()
    }
    fn marks(&self) -> &[Mark] {
        self.timeline.marks()
    }
    fn mark(&mut self, kind: MarkKind, line: usize) {
        self.timeline.mark(kind, line);
    }
    fn mark_at(&mut self, at: Pos, kind: MarkKind, line: usize) {
        self.timeline.mark_at(at, kind, line);
    }
    fn trace(&self) -> &Trace {
        &self.timeline.trace
    }
    fn channels(&self) -> &[Channel] {
        self.timeline.channels()
    }
    fn memory_bytes(&self) -> usize {
        self.timeline.memory_bytes()
    }
    fn run_headless(&mut self, events: &[UserEvent], max_ticks: u64) {
        super::history::run_events_bare(&mut self.timeline.machine, events, max_ticks);
    }
    fn run_headless_observed(
        &mut self,
        events: &[UserEvent],
        max_ticks: u64,
        stop: &mut dyn FnMut(&dyn MachineView) -> bool,
    ) -> StopReason {
        super::history::run_events(&mut self.timeline.machine, events, max_ticks, |m| stop(m))
    }
}
