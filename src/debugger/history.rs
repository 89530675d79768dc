//! Time travel: everything a run depends on besides the program is a timeline of user events
//! (input switches, register and status-bit edits, each at a tick), so any tick can be rebuilt
//! by deterministic re-execution from the nearest checkpoint.
//!
//! - A checkpoint (a clone of the machine, about 1 KB) is kept every [`CHECKPOINT_EVERY`] ticks,
//!   taken *before* that tick's events apply; going to tick N restores the checkpoint at or
//!   before N and re-executes at most that many ticks (well under a millisecond).
//! - The state shown at tick N includes the events of tick N.
//! - Editing at a tick before the furthest one reached rewrites history: the checkpoints,
//!   events and trace after it are discarded.

use serde::{Deserialize, Serialize};

use super::trace::Trace;
use crate::machine::silverlode::SilverLode;
use crate::machine::{Machine, StopReason};

pub const CHECKPOINT_EVERY: u64 = 16_384;

/// A change the user made, replayed at its tick.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Edit {
    Input { input: usize, high: bool },
    Register { register: usize, value: u32 },
    StatusBit { word: String, bit: u8, on: bool },
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct UserEvent {
    pub tick: u64,
    pub edit: Edit,
}

impl Edit {
    pub fn apply(&self, m: &mut SilverLode) {
        match self {
            Edit::Input { input, high } => m.set_input(*input, *high),
            Edit::Register { register, value } => m.set_register(*register, *value),
            Edit::StatusBit { word, bit, on } => {
                m.set_status_bit(word, *bit, *on);
            }
        }
    }
}

/// Where a run stopped, for the timeline's marks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkKind {
    Breakpoint,
    Fault,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mark {
    pub tick: u64,
    pub kind: MarkKind,
    pub line: usize,
}

/// The machine with its timeline: checkpoints, user events, the trace, the furthest tick.
pub struct Timeline {
    pub machine: SilverLode,
    pub trace: Trace,
    checkpoints: Vec<SilverLode>,
    events: Vec<UserEvent>,
    /// Index of the first event not applied yet (all events at or before the current tick are).
    next_event: usize,
    furthest: u64,
    marks: Vec<Mark>,
}

fn motion_values(m: &SilverLode) -> [i32; 4] {
    [m.reg(0), m.reg(1), m.reg(6), m.reg(7)]
}

impl Timeline {
    /// A fresh timeline at tick 0 of `start`, with `events` to replay as their ticks come.
    pub fn new(start: SilverLode, mut events: Vec<UserEvent>) -> Self {
        events.sort_by_key(|e| e.tick);
        let mut t = Timeline {
            machine: start.clone(),
            trace: Trace::default(),
            checkpoints: vec![start],
            events,
            next_event: 0,
            furthest: 0,
            marks: Vec::new(),
        };
        t.apply_due_events();
        t.trace.record(0, motion_values(&t.machine));
        t
    }

    pub fn now(&self) -> u64 {
        self.machine.ticks()
    }
    pub fn furthest(&self) -> u64 {
        self.furthest
    }
    pub fn events(&self) -> &[UserEvent] {
        &self.events
    }
    pub fn marks(&self) -> &[Mark] {
        &self.marks
    }
    /// Bytes held by checkpoints, events and the trace.
    pub fn memory_bytes(&self) -> usize {
        let checkpoint = std::mem::size_of::<SilverLode>() + 256;
        self.checkpoints.len() * checkpoint
            + self.events.len() * std::mem::size_of::<UserEvent>()
            + self.trace.memory_bytes()
    }

    fn apply_due_events(&mut self) {
        let now = self.machine.ticks();
        while let Some(e) = self.events.get(self.next_event).filter(|e| e.tick <= now) {
            e.edit.apply(&mut self.machine);
            self.next_event += 1;
        }
        if self.next_event > 0 {
            // A same-tick edit changes what the trace shows for this tick.
            self.trace.record(now, motion_values(&self.machine));
        }
    }

    /// Run forward until `tick_limit`, the end or a fault, or `stop` (asked before each command
    /// starts) — applying events at their ticks, recording the trace and keeping checkpoints.
    pub fn forward<F: FnMut(&SilverLode) -> bool>(
        &mut self,
        tick_limit: u64,
        mut stop: F,
    ) -> StopReason {
        loop {
            let next_event = self.events.get(self.next_event).map(|e| e.tick);
            let limit = next_event.map_or(tick_limit, |t| t.min(tick_limit));
            let Timeline {
                machine,
                trace,
                checkpoints,
                furthest,
                ..
            } = self;
            let reason = machine.run_observed(limit, &mut stop, |m| {
                let t = m.ticks();
                trace.record(t, motion_values(m));
                if t.is_multiple_of(CHECKPOINT_EVERY)
                    && checkpoints.last().is_none_or(|c| c.ticks() < t)
                {
                    checkpoints.push(m.clone());
                }
                *furthest = (*furthest).max(t);
            });
            self.apply_due_events();
            if reason == StopReason::TickLimit && self.machine.ticks() < tick_limit {
                continue;
            }
            return reason;
        }
    }

    /// Rebuild the state at `tick` (at most the furthest tick reached).
    pub fn goto(&mut self, tick: u64) {
        let tick = tick.min(self.furthest);
        let i = self
            .checkpoints
            .partition_point(|c| c.ticks() <= tick)
            .saturating_sub(1);
        self.restore(i);
        self.forward(tick, |_| false);
    }

    fn restore(&mut self, checkpoint: usize) {
        self.machine = self.checkpoints[checkpoint].clone();
        let at = self.machine.ticks();
        self.next_event = self.events.partition_point(|e| e.tick < at);
        self.apply_due_events();
    }

    /// The last tick before `before` where a command was about to start and `wanted` holds,
    /// searching back one checkpoint interval at a time. Leaves the machine where it was.
    pub fn find_back<F: FnMut(&SilverLode) -> bool>(
        &mut self,
        before: u64,
        mut wanted: F,
    ) -> Option<u64> {
        let here = self.now();
        let mut end = before;
        let mut found = None;
        while end > 0 && found.is_none() {
            let i = self
                .checkpoints
                .partition_point(|c| c.ticks() < end)
                .saturating_sub(1);
            let start = self.checkpoints[i].ticks();
            self.restore(i);
            self.forward(end, |m| {
                if m.ticks() < end && wanted(m) {
                    found = Some(m.ticks());
                }
                false
            });
            if start == 0 {
                break;
            }
            end = start;
        }
        self.goto(here);
        found
    }

    /// A user edit at the current tick. Returns true when it discarded a recorded future.
    pub fn edit(&mut self, edit: Edit) -> bool {
        let now = self.now();
        let discarded = now < self.furthest;
        if discarded {
            self.checkpoints.retain(|c| c.ticks() <= now);
            self.events.retain(|e| e.tick <= now);
            self.marks.retain(|m| m.tick <= now);
            self.trace.truncate_after(now);
            self.furthest = now;
        }
        self.next_event = self.events.len();
        self.events.push(UserEvent { tick: now, edit });
        self.apply_due_events();
        discarded
    }

    pub fn mark(&mut self, kind: MarkKind, line: usize) {
        self.mark_at(self.now(), kind, line);
    }

    pub fn mark_at(&mut self, tick: u64, kind: MarkKind, line: usize) {
        if !self.marks.iter().any(|m| m.tick == tick && m.kind == kind) {
            self.marks.push(Mark { tick, kind, line });
            self.marks.sort_by_key(|m| m.tick);
        }
    }
}
