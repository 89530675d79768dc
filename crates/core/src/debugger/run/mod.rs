//! Run control and time travel: stepping, running at a speed in bounded slices, pausing,
//! resetting, going to any position, stepping back and reverse-continue.

mod back;
mod event;
mod frames;

use std::cell::RefCell;
use std::time::Instant;

use super::breakpoints::Checker;
use super::history::{BackSearch, MarkKind};
use super::{CHUNK_TICKS, Debugger, Engine, FIRST_CHUNK_TICKS, STEP_TICKS_AT_ONCE, StopWhen};
use crate::machine::{Pos, RunState, StopReason};

pub use back::BACK_TICKS_AT_ONCE;
pub(crate) use back::Back;
pub use event::Event;

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
        // A breakpoint met inside the scan stops the step there, as Step over stops inside a
        // call (a data breakpoint on a counter fired on F5 but never on F8).
        let on_error = self.break_on_error && !self.machine().error_lamp();
        self.resume_past_breakpoint = false;
        let checker = (!self.checker.get_mut().is_empty()).then_some(&self.checker);
        let stop = StopWhen {
            checker,
            skip_first: true,
            on_error,
            ..StopWhen::default()
        };
        match self.engine.forward(next, &stop) {
            StopReason::Predicate => self.reached(Goal::Continue),
            _ => self.after_stop(Event::Stepped),
        }
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
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

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
