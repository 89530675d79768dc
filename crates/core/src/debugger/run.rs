//! Run control and time travel: stepping, running at a speed in bounded slices, pausing,
//! resetting, going to any position, stepping back and reverse-continue.

use std::cell::RefCell;
use std::time::{Duration, Instant};

use super::breakpoints::Checker;
use super::history::{BackSearch, MarkKind};
use super::{CHUNK_TICKS, Debugger, Engine, FIRST_CHUNK_TICKS, STEP_TICKS_AT_ONCE, StopWhen};
use crate::machine::{Pos, RunState, StopReason};

/// How fast Run goes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Speed {
    /// Commands per second (a step that waits, like DLY, counts as one command).
    PerSecond(f64),
    /// Simulated time at this factor of real time (1.0: a tick of 120 µs takes 120 µs), tick
    /// by tick, so an input switched by hand lands on the tick on screen.
    RealTime(f64),
    /// As fast as the machine goes, in slices that leave every frame its time.
    Unlimited,
}

impl Speed {
    pub const PRESETS: [Speed; 14] = [
        Speed::RealTime(0.01),
        Speed::RealTime(0.1),
        Speed::RealTime(1.0),
        Speed::RealTime(10.0),
        Speed::RealTime(100.0),
        Speed::PerSecond(1.0),
        Speed::PerSecond(2.0),
        Speed::PerSecond(5.0),
        Speed::PerSecond(10.0),
        Speed::PerSecond(100.0),
        Speed::PerSecond(1_000.0),
        Speed::PerSecond(10_000.0),
        Speed::PerSecond(100_000.0),
        Speed::Unlimited,
    ];

    /// The fastest and slowest of the presets: (commands per second, factor of real time).
    pub const RANGE: ((f64, f64), (f64, f64)) = ((100_000.0, 100.0), (1.0, 0.01));

    /// `1 command/s`, `10 commands/s`, `1k commands/s`: in the dialect's words for a step.
    pub fn label(self, step: &str, steps: &str) -> String {
        match self {
            Speed::Unlimited => "unlimited".to_string(),
            Speed::RealTime(f) => format!("×{f} real time"),
            Speed::PerSecond(n) if n >= 1000.0 => format!("{}k {steps}/s", n / 1000.0),
            Speed::PerSecond(1.0) => format!("1 {step}/s"),
            Speed::PerSecond(n) => format!("{n} {steps}/s"),
        }
    }
}

/// What the debugger is doing over frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Goal {
    /// Until a breakpoint, the end or a fault.
    Continue,
    /// Until the current command completes (a long DLY or move).
    FinishStep,
    /// Until the command on this line is about to run (or a breakpoint).
    ToLine(usize),
    /// Until this tick (beyond the furthest one reached so far).
    ToTick(u64),
    /// A search back (step back, reverse-continue) too long for one frame: it goes on over
    /// frames, and Pause cancels it where it started.
    Back,
    /// Step over a call or out of one: past `after`, until no more than `depth` calls are in
    /// progress (or a breakpoint).
    Out { after: Pos, depth: usize },
}

/// Why the debugger last stopped, for the status bar.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Event {
    Breakpoint(usize),
    /// "Break on error": the error lamp turned on; the line is the next instruction's.
    ErrorLamp(usize),
    ReachedLine(usize),
    ReachedTick(u64),
    Paused(Option<usize>),
    Stepped,
    SteppedBack,
    /// Reverse-continue found no earlier breakpoint: back at the start.
    NoEarlierBreakpoint,
    Ended,
    Faulted,
    Reset,
    /// The text has errors: nothing runs until they are fixed.
    NotAssembled(usize),
    Assembled,
    /// An edit in the past rewrote history from this tick on.
    FutureDiscarded(u64),
    /// A data breakpoint: `location` changed from `old` to `new` by the instruction on `line`.
    Watchpoint {
        location: String,
        line: usize,
        old: i64,
        new: i64,
    },
    /// "Who wrote this?" went to the write of `location` at `at`: by the instruction on
    /// `line`, or by the user's edit (no line).
    WrittenBy {
        location: String,
        at: crate::machine::Pos,
        line: Option<usize>,
        explanation: String,
    },
    /// "Who wrote this?" found no write: the location holds its value from the start.
    NeverWritten(String),
}

impl Event {
    /// The event in words; `tick` is the dialect's word for a tick ("tick" or "scan").
    pub fn describe(&self, tick: &str) -> String {
        self.describe_with(tick, &|l| format!("line {l}"))
    }

    /// [`Event::describe`] with lines in the words `at_line` gives them ("line 12", or
    /// "main.tml:12" in a program of several files).
    pub fn describe_with(&self, tick: &str, at_line: &dyn Fn(usize) -> String) -> String {
        match self {
            Event::Breakpoint(l) => format!("Breakpoint hit at {}", at_line(*l)),
            Event::ErrorLamp(l) => format!("Execution error: stopped before {}", at_line(*l)),
            Event::ReachedLine(l) => format!("Reached {}", at_line(*l)),
            Event::ReachedTick(t) => format!("At {tick} {t}"),
            Event::Paused(Some(l)) => format!("Paused at {}", at_line(*l)),
            Event::Paused(None) => "Paused".to_string(),
            Event::Stepped => "Stepped".to_string(),
            Event::SteppedBack => "Stepped back".to_string(),
            Event::NoEarlierBreakpoint => "No earlier breakpoint: back at the start".to_string(),
            Event::Ended => "Program ended".to_string(),
            Event::Faulted => "Stopped on a fault".to_string(),
            Event::Reset => "Reset to the start".to_string(),
            Event::NotAssembled(n) => format!("{n} error(s) in the program: fix them to run"),
            Event::Assembled => "Program assembled".to_string(),
            Event::FutureDiscarded(t) => {
                format!("Edited at {tick} {t}: the recorded future after it was discarded")
            }
            Event::Watchpoint {
                location,
                line,
                old,
                new,
            } => format!("{location} written at {}: {old} -> {new}", at_line(*line)),
            Event::WrittenBy {
                location,
                at,
                line: Some(l),
                explanation,
            } => format!(
                "{location} was written at {tick} {at}, {}: {explanation}",
                at_line(*l)
            ),
            Event::WrittenBy {
                location,
                at,
                line: None,
                explanation,
            } => format!("{location} was set at {tick} {at} by {explanation}"),
            Event::NeverWritten(name) => {
                format!("Nothing wrote {name} before here: it holds its value from the start")
            }
        }
    }
}

/// Ticks per second over the last half second of a run (longer when no tick completes).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct RateMeter {
    window: Option<(Instant, u64)>,
    rate: Option<f64>,
}

impl RateMeter {
    #[cfg(test)]
    fn at(since: Instant, from: u64) -> Self {
        RateMeter {
            window: Some((since, from)),
            rate: None,
        }
    }

    pub fn note(&mut self, tick: u64) {
        let now = Instant::now();
        match self.window {
            Some((since, from)) => {
                let seconds = now.duration_since(since).as_secs_f64();
                // A slow run (a PLC scan stepped at 10 instructions a second) completes no
                // tick in half a second: the window stays open until one does (up to 5 s), so
                // the rate reads 0.8 scans/s rather than 0.
                if seconds >= 0.5 && (tick > from || seconds >= 5.0) {
                    self.rate = Some(tick.saturating_sub(from) as f64 / seconds);
                    self.window = Some((now, tick));
                }
            }
            None => self.window = Some((now, tick)),
        }
    }
}

/// What a run asks of each stretch it runs, whichever thread runs it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Plan {
    pub goal: Goal,
    /// Stop when the error lamp turns on (it was off as the run began).
    pub on_error: bool,
    /// Do not stop at the very first boundary (resuming from a breakpoint).
    pub skip_first: bool,
}

impl Plan {
    fn line(&self) -> Option<usize> {
        match self.goal {
            Goal::ToLine(l) => Some(l),
            _ => None,
        }
    }
}

/// Run at most `ticks` ticks of a run that goes as fast as it can (unlimited, or a step or a
/// tick to reach): `Predicate` when the goal or a breakpoint stops it, `Stopped` at the end or
/// a fault, `TickLimit` when there is more to do.
pub(crate) fn run_chunk(
    engine: &mut dyn Engine,
    plan: &Plan,
    checker: Option<&RefCell<Checker>>,
    ticks: u64,
) -> StopReason {
    let chunk = Pos::at_tick(engine.machine().pos().tick.saturating_add(ticks));
    match plan.goal {
        // Mid-instruction, the next boundary ends the step; at one, it is over.
        Goal::FinishStep if engine.machine().run_state() == RunState::Running => {
            StopReason::Predicate
        }
        Goal::FinishStep => engine.forward(
            chunk,
            &StopWhen {
                any: true,
                ..StopWhen::default()
            },
        ),
        Goal::ToTick(t) => match engine.forward(chunk.min(Pos::at_tick(t)), &StopWhen::default()) {
            StopReason::TickLimit if engine.machine().pos().tick >= t => StopReason::Predicate,
            other => other,
        },
        // A search back is never run forward (`advance` goes on with it instead).
        Goal::Back => StopReason::Predicate,
        Goal::Continue | Goal::ToLine(_) => engine.forward(
            chunk,
            &StopWhen {
                checker,
                line: plan.line(),
                skip_first: plan.skip_first,
                on_error: plan.on_error,
                ..StopWhen::default()
            },
        ),
        Goal::Out { after, depth } => engine.forward(
            chunk,
            &StopWhen {
                checker,
                after: Some(after),
                depth_at_most: Some(depth),
                on_error: plan.on_error,
                ..StopWhen::default()
            },
        ),
    }
}

impl Debugger {
    // ---- run control -----------------------------------------------------------------------

    /// Execute one instruction (F10). One that waits long continues over later frames.
    pub fn step_command(&mut self) {
        if !self.ready() || !self.live() {
            return;
        }
        self.goal = None;
        let start = self.pos();
        let limit = Pos::at_tick(start.tick.saturating_add(STEP_TICKS_AT_ONCE));
        let stop = StopWhen {
            after: Some(start),
            ..StopWhen::default()
        };
        if self.engine.forward(limit, &stop) == StopReason::TickLimit {
            self.goal = Some(Goal::FinishStep);
        } else {
            self.after_stop(Event::Stepped);
        }
    }

    /// Step over (F10): one instruction, and when it was a call, the whole subroutine too
    /// (stopping early at a breakpoint inside it, the end or a fault).
    pub fn step_over(&mut self) {
        if !self.ready() || !self.live() {
            return;
        }
        let depth = self.machine().call_depth();
        self.step_command();
        if self.goal.is_none() && self.machine().call_depth() > depth && self.live() {
            self.run_out_to(depth);
        }
    }

    /// Step out (Shift+F11): run until the subroutine on hand returns; outside any, run on
    /// (as a debugger's step out of the outermost frame does).
    pub fn step_out(&mut self) {
        if !self.ready() || !self.live() {
            return;
        }
        match self.machine().call_depth().checked_sub(1) {
            Some(depth) => self.run_out_to(depth),
            None => self.run(),
        }
    }

    fn run_out_to(&mut self, depth: usize) {
        let after = self.pos();
        self.start(Goal::Out { after, depth });
        // A breakpoint on the subroutine's first line stops it: nothing to skip here.
        self.resume_past_breakpoint = false;
    }

    /// Step back over (Shift+F10): back one instruction, or over a whole call that just
    /// returned, to the CALL.
    pub fn step_back_over(&mut self) {
        let depth = self.machine().call_depth();
        self.search_back_to(false, Some(depth));
    }

    /// Step back out (Ctrl+Shift+F11): back to the CALL that entered the subroutine on hand;
    /// outside any, one instruction back.
    pub fn step_back_out(&mut self) {
        let depth = self.machine().call_depth().checked_sub(1);
        self.search_back_to(false, depth);
    }

    /// Advance to the end of the current tick (F11): one tick, or the rest of the scan.
    pub fn step_tick(&mut self) {
        if !self.ready() || !self.live() {
            return;
        }
        self.goal = None;
        let next = Pos::at_tick(self.pos().tick + 1);
        self.engine.forward(next, &StopWhen::default());
        self.after_stop(Event::Stepped);
    }

    /// Run until a breakpoint, the end or a fault (F5).
    pub fn run(&mut self) {
        self.start(Goal::Continue);
    }

    /// Run until the instruction on `line` is about to execute (Ctrl+F10).
    pub fn run_to_line(&mut self, line: usize) {
        self.start(Goal::ToLine(line));
    }

    fn start(&mut self, goal: Goal) {
        if !self.ready() || !self.live() {
            return;
        }
        self.goal = Some(goal);
        self.credit = 0.0;
        self.resume_past_breakpoint = true;
        self.event = None;
        self.lamp_was_on = self.machine().error_lamp();
        self.rate = RateMeter::default();
        self.chunk_ticks = FIRST_CHUNK_TICKS;
        self.chunk_floor = None;
        self.checker.get_mut().prime(self.engine.machine());
    }

    /// Stop running (F6). Answers at once: the run only advances inside `advance`.
    pub fn pause(&mut self) {
        if self.goal.take().is_some() {
            self.event = Some(Event::Paused(self.machine().pc_line()));
        }
    }

    /// Back to the start of the program with a fresh timeline (Ctrl+Shift+F5), assembling edits
    /// first. Inputs start low, as in every new run.
    pub fn reset(&mut self) {
        self.goal = None;
        if self.is_edited() || self.has_errors() {
            self.assemble();
        } else {
            self.restart();
        }
        self.event = Some(Event::Reset);
    }

    /// Stop a run when the machine's error lamp turns on.
    pub fn set_break_on_error(&mut self, on: bool) {
        self.break_on_error = on;
    }

    pub fn break_on_error(&self) -> bool {
        self.break_on_error
    }

    pub fn set_speed(&mut self, speed: Speed) {
        // Within the offered range: a factor from a damaged file or old preferences
        // (RealTime(1e12)) would ask a frame for more ticks than any frame can run.
        let (fastest, slowest) = Speed::RANGE;
        self.speed = match speed {
            Speed::PerSecond(n) if !(n.is_finite() && n > 0.0) => Speed::PerSecond(1.0),
            Speed::RealTime(f) if !(f.is_finite() && f > 0.0) => Speed::RealTime(1.0),
            Speed::PerSecond(n) => Speed::PerSecond(n.clamp(slowest.0, fastest.0)),
            Speed::RealTime(f) => Speed::RealTime(f.clamp(slowest.1, fastest.1)),
            s => s,
        };
        self.credit = 0.0;
    }

    fn live(&mut self) -> bool {
        let live = self.machine().run_state().is_live();
        if !live {
            self.after_stop(Event::Stepped);
        }
        live
    }

    pub(super) fn after_stop(&mut self, otherwise: Event) {
        let state = self.machine().run_state();
        self.event = Some(match state {
            RunState::Ended => Event::Ended,
            RunState::Faulted => {
                let line = self.machine().fault().map_or(0, |f| f.line);
                self.engine.mark(MarkKind::Fault, line);
                Event::Faulted
            }
            _ => otherwise,
        });
        if !state.is_live() {
            self.goal = None;
        }
    }

    /// Run for this frame: `dt` seconds since the last frame (for slow speeds), `budget` the
    /// wall time it may take (for unlimited speed). Returns true while still running.
    ///
    /// After [`Debugger::hand_off`] the worker has been running meanwhile: this takes the run
    /// back and reports where it got to, without simulating in the frame.
    pub fn advance(&mut self, dt: f64, budget: Duration) -> bool {
        let back = self.take_back();
        let Some(goal) = self.goal else {
            return false;
        };
        self.rate.note(self.pos().tick);
        if let Some(reason) = back {
            return self.settle(goal, reason);
        }
        if goal == Goal::Back {
            return self.go_on_back(Some(Instant::now() + budget));
        }
        if !self.machine().run_state().is_live() {
            self.after_stop(Event::Stepped);
            return false;
        }
        if let (Goal::Continue | Goal::ToLine(_), Speed::RealTime(factor)) = (goal, self.speed) {
            return self.advance_in_real_time(goal, factor, dt, budget);
        }
        if self.worker.is_some() && self.runs_on_worker(goal) {
            // The worker runs it once the frame is drawn.
            return true;
        }
        let started = Instant::now();
        let mut commands = match (goal, self.speed) {
            (Goal::FinishStep | Goal::ToTick(_) | Goal::Out { .. }, _)
            | (_, Speed::Unlimited)
            | (_, Speed::RealTime(_)) => u64::MAX,
            (_, Speed::PerSecond(n)) => {
                self.credit += n * dt.clamp(0.0, 0.25);
                let whole = self.credit.floor();
                self.credit -= whole;
                whole as u64
            }
        };
        let checker = (!self.checker.get_mut().is_empty()).then_some(&self.checker);
        let mut plan = Plan {
            goal,
            on_error: self.break_on_error && !self.lamp_was_on,
            skip_first: false,
        };
        while commands > 0 {
            plan.skip_first = std::mem::take(&mut self.resume_past_breakpoint);
            let skip = plan.skip_first;
            let now = self.pos();
            let reason = if commands == u64::MAX {
                let chunk_started = Instant::now();
                let reason = run_chunk(self.engine.as_mut(), &plan, checker, self.chunk_ticks);
                // Chunks double while one fits in the frame's budget, so a frame ends at most
                // about twice its budget in (the last chunk is at most all those before it).
                // What a call costs whatever its length (a large program's tables) is the
                // shortest chunk seen: chunks may take twice that, or nothing would run.
                let took = chunk_started.elapsed();
                let overhead = *self.chunk_floor.get_or_insert(took);
                self.chunk_floor = Some(overhead.min(took));
                self.chunk_ticks = if took > budget.max(overhead * 2) {
                    (self.chunk_ticks / 2).max(1)
                } else {
                    self.chunk_ticks.saturating_mul(2).min(CHUNK_TICKS)
                };
                reason
            } else {
                let at_stop = StopWhen {
                    checker,
                    line: plan.line(),
                    on_error: plan.on_error,
                    ..StopWhen::default()
                };
                if !skip && at_stop.holds(self.machine()) {
                    StopReason::Predicate
                } else {
                    commands -= 1;
                    let one = StopWhen {
                        after: Some(now),
                        ..StopWhen::default()
                    };
                    let limit = Pos::at_tick(now.tick.saturating_add(STEP_TICKS_AT_ONCE));
                    match self.engine.forward(limit, &one) {
                        StopReason::Predicate => StopReason::TickLimit,
                        other => other,
                    }
                }
            };
            match reason {
                StopReason::Stopped => {
                    self.after_stop(Event::Stepped);
                    return false;
                }
                StopReason::Predicate => {
                    self.reached(goal);
                    return false;
                }
                StopReason::TickLimit => {
                    if started.elapsed() >= budget {
                        break;
                    }
                }
            }
        }
        true
    }

    /// Whether a run goes to the worker between frames: one that runs as fast as it can.
    fn runs_on_worker(&self, goal: Goal) -> bool {
        match goal {
            Goal::Back => false,
            // Stepping over or out of a call goes as fast as a step does.
            Goal::FinishStep | Goal::ToTick(_) | Goal::Out { .. } => true,
            Goal::Continue | Goal::ToLine(_) => self.speed == Speed::Unlimited,
        }
    }

    /// Lend the run in progress to the worker thread until the next [`Debugger::advance`] (the
    /// window calls this when a frame is drawn). Does nothing unless a run goes as fast as it
    /// can; without a thread the run goes on inside the frames.
    pub fn hand_off(&mut self) {
        let Some(goal) = self.goal else {
            return;
        };
        if self.lent || !self.runs_on_worker(goal) || !self.machine().run_state().is_live() {
            return;
        }
        if self.worker.is_none() {
            self.worker = super::worker::Worker::spawn();
        }
        let Some(worker) = &self.worker else {
            return;
        };
        let spare = match self.spare.take() {
            Some(spare) => spare,
            None => super::empty_engine(self.dialect, &self.settings),
        };
        let job = super::worker::Job {
            engine: std::mem::replace(&mut self.engine, spare),
            checker: std::mem::take(self.checker.get_mut()),
            plan: Plan {
                goal,
                on_error: self.break_on_error && !self.lamp_was_on,
                skip_first: std::mem::take(&mut self.resume_past_breakpoint),
            },
        };
        match worker.send(job) {
            Ok(()) => self.lent = true,
            Err(job) => {
                self.resume_past_breakpoint = job.plan.skip_first;
                self.spare = Some(std::mem::replace(&mut self.engine, job.engine));
                *self.checker.get_mut() = job.checker;
                self.worker = None;
            }
        }
    }

    /// The run lent to the worker, back: why the worker stopped it (`TickLimit`: it did not).
    /// `None` when nothing was lent.
    pub(crate) fn take_back(&mut self) -> Option<StopReason> {
        if !std::mem::take(&mut self.lent) {
            return None;
        }
        match self.worker.as_ref().and_then(|w| w.call_back()) {
            Some(done) => {
                self.spare = Some(std::mem::replace(&mut self.engine, done.engine));
                *self.checker.get_mut() = done.checker;
                Some(done.reason)
            }
            None => {
                // The thread died with the run (it never should): start over rather than show
                // the stand-in.
                self.worker = None;
                self.goal = None;
                self.restart();
                None
            }
        }
    }

    /// The rate the run in progress achieves, in ticks per second (measured over about half a
    /// second).
    pub fn run_rate(&self) -> Option<f64> {
        // A search back runs nothing forward: no rate to show.
        self.goal.filter(|&g| g != Goal::Back).and(self.rate.rate)
    }

    /// The run's goal came true (or a breakpoint): stop and say which.
    fn reached(&mut self, goal: Goal) {
        self.goal = None;
        let line = self.machine().pc_line().unwrap_or(0);
        let hit = self.checker.get_mut().hit.take();
        self.event = Some(match goal {
            Goal::FinishStep => Event::Stepped,
            Goal::ToTick(t) => Event::ReachedTick(t),
            Goal::ToLine(l) if l == line && hit.is_none() => Event::ReachedLine(line),
            _ if hit.is_none()
                && self.break_on_error
                && self.machine().error_lamp()
                && !self.lamp_was_on =>
            {
                self.engine.mark(MarkKind::Fault, line);
                Event::ErrorLamp(line)
            }
            Goal::Out { .. } if hit.is_none() => Event::Stepped,
            _ => self.breakpoint_event(hit),
        });
    }

    /// The event of a breakpoint hit, marked on the timeline.
    fn breakpoint_event(&mut self, hit: Option<super::breakpoints::Hit>) -> Event {
        let pc_line = self.machine().pc_line().unwrap_or(0);
        let data = hit.and_then(|h| {
            let b = self.breaks.get(h.index)?;
            match (&b.kind, h.values) {
                (super::BreakKind::Data { location, .. }, Some((old, new))) => {
                    Some((location.clone(), old, new))
                }
                _ => None,
            }
        });
        match data {
            Some((location, old, new)) => {
                let line = self.machine().last_line().unwrap_or(0);
                self.engine.mark(MarkKind::Breakpoint, line);
                Event::Watchpoint {
                    location,
                    line,
                    old,
                    new,
                }
            }
            None => {
                self.engine.mark(MarkKind::Breakpoint, pc_line);
                Event::Breakpoint(pc_line)
            }
        }
    }

    /// One frame at a factor of real time: exactly the ticks `dt` is worth (fractions carry
    /// over), stopping at breakpoints, in chunks within the frame's `budget`: what a frame
    /// cannot run in its budget is dropped (the run falls behind real time rather than
    /// freezing the window).
    fn advance_in_real_time(&mut self, goal: Goal, factor: f64, dt: f64, budget: Duration) -> bool {
        let started = Instant::now();
        let micros = f64::from(self.machine().tick_micros().max(1));
        let factor = if factor.is_finite() {
            factor.max(0.0)
        } else {
            1.0
        };
        self.credit += factor * dt.clamp(0.0, 0.25) * 1e6 / micros;
        let whole = self.credit.floor();
        self.credit -= whole;
        let target = Pos::at_tick(self.pos().tick.saturating_add(whole as u64));
        let checker = (!self.checker.get_mut().is_empty()).then_some(&self.checker);
        let mut stop = StopWhen {
            checker,
            line: match goal {
                Goal::ToLine(l) => Some(l),
                _ => None,
            },
            skip_first: std::mem::take(&mut self.resume_past_breakpoint),
            on_error: self.break_on_error && !self.machine().error_lamp(),
            ..StopWhen::default()
        };
        let mut chunk = FIRST_CHUNK_TICKS;
        loop {
            let next = target.min(Pos::at_tick(self.pos().tick.saturating_add(chunk)));
            let reason = self.engine.forward(next, &stop);
            // Only the run's very first boundary is skipped (resuming from a breakpoint).
            stop.skip_first = false;
            if reason != StopReason::TickLimit || self.pos() >= target {
                return self.settle(goal, reason);
            }
            if started.elapsed() >= budget {
                self.credit = 0.0;
                return true;
            }
            chunk = chunk.saturating_mul(2).min(CHUNK_TICKS);
        }
    }

    /// What a stretch of a run ended with: stopped (false) or still running (true).
    fn settle(&mut self, goal: Goal, reason: StopReason) -> bool {
        match reason {
            StopReason::Stopped => {
                self.after_stop(Event::Stepped);
                false
            }
            StopReason::Predicate => {
                self.reached(goal);
                false
            }
            StopReason::TickLimit => true,
        }
    }

    // ---- time travel -----------------------------------------------------------------------

    /// Go to any tick (its start). Within the recorded timeline this is a replay from the
    /// nearest checkpoint; beyond it the program runs there over the next frames.
    pub fn goto_tick(&mut self, tick: u64) {
        self.goto(Pos::at_tick(tick));
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
    fn search_back_to(&mut self, breakpoints: bool, depth: Option<usize>) {
        let Some(now) = self.going_back() else {
            return;
        };
        let checker = if breakpoints {
            super::breakpoints::Checker::backward(
                &self.breaks,
                self.engine.machine(),
                &self.lines(),
            )
        } else {
            super::breakpoints::Checker::default()
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
    fn go_on_back(&mut self, deadline: Option<Instant>) -> bool {
        let Some(mut back) = self.back.take() else {
            self.goal = None;
            return false;
        };
        let ticks = if deadline.is_some() {
            super::history::CHECKPOINT_EVERY
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
pub const BACK_TICKS_AT_ONCE: u64 = 4 * super::history::CHECKPOINT_EVERY;

/// A search back in progress.
pub(crate) struct Back {
    /// For a breakpoint (reverse-continue) or for any boundary (step back).
    breakpoints: bool,
    /// Only a boundary with at most this many calls in progress (step back over / out).
    depth: Option<usize>,
    search: BackSearch,
    checker: RefCell<Checker>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run slower than a tick in half a second measures over the time a tick takes, not
    /// "0 ticks/s".
    #[test]
    fn a_slow_run_reads_its_rate_not_zero() {
        let start = Instant::now() - Duration::from_millis(800);
        let mut meter = RateMeter::at(start, 10);
        meter.note(10);
        assert_eq!(meter.rate, None, "no tick yet: the window stays open");
        let start = Instant::now() - Duration::from_millis(1250);
        let mut meter = RateMeter::at(start, 10);
        meter.note(11);
        let rate = meter.rate.expect("measured");
        assert!((0.7..0.85).contains(&rate), "{rate}");
        let mut meter = RateMeter::at(Instant::now() - Duration::from_secs(6), 10);
        meter.note(10);
        assert_eq!(meter.rate, Some(0.0), "a stalled run reads 0 after 5 s");
    }

    #[test]
    fn speeds_read_in_the_dialects_words() {
        assert_eq!(
            Speed::PerSecond(1.0).label("command", "commands"),
            "1 command/s"
        );
        assert_eq!(
            Speed::PerSecond(10.0).label("command", "commands"),
            "10 commands/s"
        );
        assert_eq!(
            Speed::PerSecond(1000.0).label("scan", "scans"),
            "1k scans/s"
        );
        assert_eq!(Speed::Unlimited.label("scan", "scans"), "unlimited");
        assert_eq!(
            Speed::RealTime(0.1).label("command", "commands"),
            "×0.1 real time"
        );
    }
}
