//! Time travel: everything a run depends on besides the program is a timeline of user events
//! (input switches and edits of any location, each at a (tick, step) position), so any
//! position can be rebuilt by deterministic re-execution from the nearest checkpoint.
//!
//! - A checkpoint (a clone of the machine) is kept every [`CHECKPOINT_EVERY`] ticks, at the
//!   tick's start and *before* that position's events apply; going to a position restores the
//!   checkpoint at or before it and re-executes at most that many ticks.
//! - Checkpoints hold at most [`CHECKPOINT_BUDGET`] bytes: past it every other one goes and
//!   the interval doubles, so a run left going for hours keeps its memory (a SilverLode run
//!   unlimited made 18 000 checkpoints a second, 21 MB/s, without end) and going to a
//!   position replays at most one interval, however long the run.
//! - The state shown at a position includes the events of that position.
//! - Editing at a position before the furthest one reached rewrites history: the checkpoints,
//!   events, marks and trace after it are discarded.
//! - [`replay`] is the one implementation of "run with events" that the timeline and the
//!   headless runner share, so a run and a session always agree.

mod events;
mod forward;
mod travel;

use super::trace::{Channel, Trace};
use crate::machine::{Loc, Machine, MachineView, Pos, WriteError, WriteSet};

pub use events::{Change, Observed, UserEvent, replay, replay_bare, run_events, run_events_bare};
pub use travel::BackSearch;

use events::apply_due;

pub const CHECKPOINT_EVERY: u64 = 16_384;
/// Bytes the checkpoints of a timeline hold at most (their machines' own estimate).
pub const CHECKPOINT_BUDGET: usize = 256 << 20;
/// Ticks a quiet stretch must reach for the timeline to keep asking for quiet ones at once.
const QUIET_WORTH: u64 = 256;

/// Where a run stopped, for the timeline's marks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkKind {
    Breakpoint,
    Fault,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mark {
    pub at: Pos,
    pub kind: MarkKind,
    pub line: usize,
}

/// The machine with its timeline: checkpoints, user events, the trace, the furthest position.
pub struct Timeline<M: Machine> {
    pub machine: M,
    pub trace: Trace,
    channels: Vec<Channel>,
    /// Boxed: thinning a quarter of a gigabyte of them moves pointers, not machines (it was a
    /// frame of 170 ms on the worker's watch).
    checkpoints: Vec<Box<M>>,
    /// For each checkpoint's stretch (up to the next one): the locations its instructions
    /// wrote, as a 256-bit Bloom set (exact for up to 256 locations of a space). "Who wrote
    /// this?" replays only the stretches whose set may hold the location.
    written: Vec<WriteSet>,
    /// Ticks between checkpoints: [`CHECKPOINT_EVERY`], doubled each time the checkpoints
    /// outgrow `checkpoint_budget`.
    checkpoint_every: u64,
    checkpoint_budget: usize,
    events: Vec<UserEvent>,
    /// Index of the first event not applied yet (all events at or before the current position
    /// are).
    next_event: usize,
    furthest: Pos,
    /// The run ended or faulted at `furthest`. A fault leaves the position where the faulting
    /// instruction began, so a replay to `furthest` stops just before it: `goto` runs it again.
    stopped: bool,
    marks: Vec<Mark>,
}

impl<M: Machine> Timeline<M> {
    /// A fresh timeline at the start of `start`, with `events` to replay as their positions
    /// come and the trace recording `channels`.
    pub fn new(start: M, mut events: Vec<UserEvent>, channels: Vec<Channel>) -> Self {
        events.sort_by_key(|e| e.at);
        let mut t = Timeline {
            machine: start.clone(),
            trace: Trace::new(channels.len()),
            channels,
            checkpoints: vec![Box::new(start)],
            written: vec![WriteSet::default()],
            checkpoint_every: CHECKPOINT_EVERY,
            checkpoint_budget: CHECKPOINT_BUDGET,
            events,
            next_event: 0,
            furthest: Pos::default(),
            stopped: false,
            marks: Vec::new(),
        };
        apply_due(&mut t.machine, &t.events, &mut t.next_event);
        t.record_now();
        t
    }

    pub fn now(&self) -> Pos {
        self.machine.pos()
    }
    pub fn furthest(&self) -> Pos {
        self.furthest
    }
    /// Whether the run ended or faulted at the furthest position.
    pub fn stopped(&self) -> bool {
        self.stopped
    }
    pub fn events(&self) -> &[UserEvent] {
        &self.events
    }
    pub fn marks(&self) -> &[Mark] {
        &self.marks
    }
    pub fn channels(&self) -> &[Channel] {
        &self.channels
    }
    /// The machine at the start of the timeline (before any event).
    pub fn initial(&self) -> &M {
        &self.checkpoints[0]
    }

    /// Bytes held by checkpoints, events and the trace.
    pub fn memory_bytes(&self) -> usize {
        self.checkpoint_bytes()
            + self.events.len() * std::mem::size_of::<UserEvent>()
            + self.trace.memory_bytes()
    }

    /// Bytes held by the checkpoints (with their write sets).
    pub fn checkpoint_bytes(&self) -> usize {
        let each = self.checkpoints[0].snapshot_bytes() + std::mem::size_of::<WriteSet>();
        self.checkpoints.len() * each
    }

    /// Ticks between checkpoints now (see [`CHECKPOINT_BUDGET`]).
    pub fn checkpoint_interval(&self) -> u64 {
        self.checkpoint_every
    }

    /// Bound the checkpoints' memory by `bytes` instead of [`CHECKPOINT_BUDGET`] (tests, and
    /// tools that keep many timelines); applies from the next checkpoint.
    pub fn set_checkpoint_budget(&mut self, bytes: usize) {
        self.checkpoint_budget = bytes;
    }

    /// Past the budget, every other checkpoint goes (the first, at the timeline's start,
    /// stays) and the interval doubles until they fit; each dropped checkpoint's write set
    /// joins the stretch before it, which now runs through its own.
    fn thin_checkpoints(&mut self) {
        // (A write set per checkpoint, as everywhere a run has come back: a missing one would
        // read as "nothing written" once merged.)
        if self.written.len() != self.checkpoints.len() {
            return;
        }
        while self.checkpoints.len() > 2 && self.checkpoint_bytes() > self.checkpoint_budget {
            let every = self.checkpoint_every.saturating_mul(2);
            self.checkpoint_every = every;
            let checkpoints = std::mem::take(&mut self.checkpoints);
            let mut written = std::mem::take(&mut self.written).into_iter();
            for (i, c) in checkpoints.into_iter().enumerate() {
                let set = written.next().unwrap_or_default();
                if i == 0 || c.ticks().is_multiple_of(every) {
                    self.checkpoints.push(c);
                    self.written.push(set);
                } else if let Some(before) = self.written.last_mut() {
                    before.union(set);
                }
            }
        }
    }

    fn record_now(&mut self) {
        let mut values = [0i64; super::trace::MAX_CHANNELS];
        sample(&self.machine, &self.channels, &mut values);
        self.trace
            .record(self.machine.ticks(), &values[..self.channels.len()]);
    }

    /// A user edit at the current position. Returns whether it discarded a recorded future;
    /// a refused edit changes nothing.
    pub fn edit(&mut self, loc: Loc, change: Change) -> Result<bool, WriteError> {
        let now = self.now();
        let event = UserEvent {
            at: now,
            loc,
            change,
        };
        let mut probe = self.machine.clone();
        event.apply(&mut probe)?;
        let discarded = now < self.furthest;
        if discarded {
            self.checkpoints.retain(|c| c.pos() <= now);
            // The stretch holding `now` keeps its set: more than it needs, never less.
            self.written.truncate(self.checkpoints.len());
            self.events.retain(|e| e.at <= now);
            self.marks.retain(|m| m.at <= now);
            self.trace.truncate_after(now.tick);
            self.furthest = now;
            self.stopped = false;
        }
        self.next_event = self.events.len();
        self.events.push(event);
        apply_due(&mut self.machine, &self.events, &mut self.next_event);
        self.record_now();
        Ok(discarded)
    }

    pub fn mark(&mut self, kind: MarkKind, line: usize) {
        self.mark_at(self.now(), kind, line);
    }

    pub fn mark_at(&mut self, at: Pos, kind: MarkKind, line: usize) {
        if !self.marks.iter().any(|m| m.at == at && m.kind == kind) {
            self.marks.push(Mark { at, kind, line });
            self.marks.sort_by_key(|m| m.at);
        }
    }
}

/// The channels' values as the trace stores them (sign-extended where the location is signed).
#[inline]
fn sample<M: MachineView>(m: &M, channels: &[Channel], out: &mut [i64]) {
    for (slot, c) in out.iter_mut().zip(channels) {
        *slot = c.sample(m);
    }
}
