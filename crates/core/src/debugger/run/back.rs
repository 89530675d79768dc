//! Time travel: going to any position, stepping back and reverse-continue, with the search
//! back that goes on over frames.

use std::cell::RefCell;
use std::time::Instant;

use super::{BackSearch, Checker, Debugger, Event, Goal, StopWhen};
use crate::machine::Pos;

impl Debugger {
    // ---- time travel -----------------------------------------------------------------------

    /// Go to any tick (its start). Within the recorded timeline this is a replay from the
    /// nearest checkpoint; beyond it the program runs there over the next frames.
    pub fn goto_tick(&mut self, tick: u64) {
        self.goto(Pos::at_tick(tick));
    }

    /// Go to `pos` as a run arrives there: at the furthest position of a run that stopped
    /// there, the moment before the stopping instruction rather than the stop (a restored
    /// session paused there). Elsewhere the same as [`Debugger::goto`].
    pub fn goto_live(&mut self, pos: Pos) {
        self.goal = None;
        if self.has_errors() || self.is_edited() {
            return;
        }
        self.engine.goto_live(pos.min(self.furthest()));
    }

    /// Go to any position, inside a tick too.
    pub fn goto(&mut self, pos: Pos) {
        self.goal = None;
        if self.has_errors() || self.is_edited() {
            return;
        }
        if pos <= self.furthest() {
            self.engine.goto(pos);
            self.event = Some(Event::ReachedTick(self.pos().tick));
        } else if self.machine().run_state().is_live() || self.pos() < self.furthest() {
            self.engine.goto(self.furthest());
            if pos.step > 0 && pos.tick <= self.furthest().tick.saturating_add(1) {
                // Inside the scan at the edge of the history: a few instructions, at once.
                self.engine.forward(pos, &StopWhen::default());
                self.event = Some(Event::ReachedTick(self.pos().tick));
            } else {
                // Further on, the run goes there over the next frames (to the tick's start).
                self.goal = Some(Goal::ToTick(pos.tick));
            }
        }
    }

    /// Where the run is, when it can go back from there (not at the start, not with edits
    /// waiting to be assembled); stops a run in progress.
    fn going_back(&mut self) -> Option<Pos> {
        let now = self.pos();
        if now == Pos::default() || self.is_edited() {
            return None;
        }
        self.goal = None;
        Some(now)
    }

    /// Back to the start of the current tick, or of the previous one when already at a start
    /// (Shift+F11).
    pub fn step_back_tick(&mut self) {
        let Some(now) = self.going_back() else {
            return;
        };
        let to = if now.step > 0 {
            Pos::at_tick(now.tick)
        } else {
            Pos::at_tick(now.tick - 1)
        };
        self.engine.goto(to);
        self.event = Some(Event::SteppedBack);
    }

    /// Back to where the last instruction started (Shift+F10).
    pub fn step_back_command(&mut self) {
        self.search_back(false);
    }

    /// Back to the last time a breakpoint stopped a run, or the start (Shift+F5): line
    /// breakpoints before their line, data breakpoints after the write.
    pub fn reverse_continue(&mut self) {
        self.search_back(true);
    }

    /// Start a search back from the current position: up to [`BACK_TICKS_AT_ONCE`] ticks of
    /// replay now, the rest over the next frames (within each frame's budget) with the goal
    /// [`Goal::Back`]; Pause cancels it where it started.
    fn search_back(&mut self, breakpoints: bool) {
        self.search_back_to(breakpoints, None);
    }

    /// [`Debugger::search_back`] for a boundary with at most `depth` calls in progress.
    pub(super) fn search_back_to(&mut self, breakpoints: bool, depth: Option<usize>) {
        let Some(now) = self.going_back() else {
            return;
        };
        let checker = if breakpoints {
            crate::debugger::breakpoints::Checker::backward(
                &self.breaks,
                self.engine.machine(),
                &self.lines(),
            )
        } else {
            crate::debugger::breakpoints::Checker::default()
        };
        self.back = Some(Back {
            breakpoints,
            depth,
            search: BackSearch::new(now),
            checker: RefCell::new(checker),
        });
        self.goal = Some(Goal::Back);
        self.event = None;
        self.go_on_back(None);
    }

    /// Go on with the search back: one call of [`BACK_TICKS_AT_ONCE`] ticks without a
    /// `deadline`, else calls of one checkpoint interval until the deadline passes. True while
    /// it goes on.
    pub(super) fn go_on_back(&mut self, deadline: Option<Instant>) -> bool {
        let Some(mut back) = self.back.take() else {
            self.goal = None;
            return false;
        };
        let ticks = if deadline.is_some() {
            crate::debugger::history::CHECKPOINT_EVERY
        } else {
            BACK_TICKS_AT_ONCE
        };
        loop {
            let wanted = StopWhen {
                any: !back.breakpoints && back.depth.is_none(),
                checker: back.breakpoints.then_some(&back.checker),
                depth_at_most: back.depth,
                ..StopWhen::default()
            };
            self.engine.find_back_some(&mut back.search, ticks, &wanted);
            if back.search.is_done() {
                self.finish_back(back);
                return false;
            }
            if deadline.is_none_or(|d| Instant::now() >= d) {
                self.back = Some(back);
                return true;
            }
        }
    }

    fn finish_back(&mut self, back: Back) {
        self.goal = None;
        let found = back.search.found();
        self.engine.goto(found.unwrap_or_default());
        self.event = Some(if !back.breakpoints {
            Event::SteppedBack
        } else if found.is_some() {
            // The search's record of its last match is the match it went back to.
            let which = back.checker.into_inner().hit;
            self.breakpoint_event(which)
        } else {
            Event::NoEarlierBreakpoint
        });
    }

    /// How far back a search in progress has looked (the status bar's progress).
    pub fn back_searched_to(&self) -> Option<Pos> {
        match (self.goal, &self.back) {
            (Some(Goal::Back), Some(back)) => Some(back.search.reached()),
            _ => None,
        }
    }
}

/// Ticks a search back replays at once when it starts; a longer one goes on over frames.
pub const BACK_TICKS_AT_ONCE: u64 = 4 * crate::debugger::history::CHECKPOINT_EVERY;

/// A search back in progress.
pub(crate) struct Back {
    /// For a breakpoint (reverse-continue) or for any boundary (step back).
    breakpoints: bool,
    /// Only a boundary with at most this many calls in progress (step back over / out).
    depth: Option<usize>,
    search: BackSearch,
    checker: RefCell<Checker>,
}
