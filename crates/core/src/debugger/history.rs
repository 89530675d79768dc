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

use super::trace::{Channel, Trace};
use crate::machine::{Loc, Machine, MachineView, Pos, Quiet, StopReason, WriteError, WriteSet};

pub const CHECKPOINT_EVERY: u64 = 16_384;
/// Bytes the checkpoints of a timeline hold at most (their machines' own estimate).
pub const CHECKPOINT_BUDGET: usize = 256 << 20;
/// Ticks a quiet stretch must reach for the timeline to keep asking for quiet ones at once.
const QUIET_WORTH: u64 = 256;

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

fn apply_due<M: MachineView>(m: &mut M, events: &[UserEvent], next: &mut usize) -> bool {
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
        let mut values = [0i64; super::trace::MAX_CHANNELS];
        let n = channels.len();
        // The trace's newest sample while it is known, so an unchanged tick costs a comparison.
        let mut held: Option<[i64; super::trace::MAX_CHANNELS]> = None;
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
                    let mut values = [0i64; super::trace::MAX_CHANNELS];
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

    /// Rebuild the state at `pos` (at most the furthest position reached).
    pub fn goto(&mut self, pos: Pos) {
        let pos = pos.min(self.furthest);
        let i = self
            .checkpoints
            .partition_point(|c| c.pos() <= pos)
            .saturating_sub(1);
        self.restore(i);
        self.rerun(pos, |_| false);
        if pos == self.furthest && self.stopped && self.machine.run_state().is_live() {
            self.rerun_stop();
        }
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

/// The channels' values as the trace stores them (sign-extended where the location is signed).
#[inline]
fn sample<M: MachineView>(m: &M, channels: &[Channel], out: &mut [i64]) {
    for (slot, c) in out.iter_mut().zip(channels) {
        *slot = c.sample(m);
    }
}
