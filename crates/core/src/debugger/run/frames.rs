//! Running over frames: each frame's share of a run (commands at a slow speed, real time,
//! chunks of an unlimited run), lending the run to the worker thread and taking it back,
//! and what a run that stops reports.

use std::time::{Duration, Instant};

use super::{
    CHUNK_TICKS, Debugger, Event, FIRST_CHUNK_TICKS, Goal, MarkKind, Plan, STEP_TICKS_AT_ONCE,
    Speed, StopWhen, run_chunk,
};
use crate::machine::{Pos, StopReason};

impl Debugger {
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
            self.worker = crate::debugger::worker::Worker::spawn();
        }
        let Some(worker) = &self.worker else {
            return;
        };
        let spare = match self.spare.take() {
            Some(spare) => spare,
            None => crate::debugger::empty_engine(self.dialect, &self.settings),
        };
        let job = crate::debugger::worker::Job {
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
    pub(super) fn reached(&mut self, goal: Goal) {
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
    pub(super) fn breakpoint_event(
        &mut self,
        hit: Option<crate::debugger::breakpoints::Hit>,
    ) -> Event {
        let pc_line = self.machine().pc_line().unwrap_or(0);
        let data = hit.and_then(|h| {
            let b = self.breaks.get(h.index)?;
            match (&b.kind, h.values) {
                (crate::debugger::BreakKind::Data { location, .. }, Some((old, new))) => {
                    Some((location.clone(), old, new))
                }
                _ => None,
            }
        });
        match data {
            Some((location, old, new)) => {
                let m = self.machine();
                let line = m.last_line().unwrap_or(0);
                let (old, new) = match m.find(&location) {
                    Some(loc) => (
                        crate::machine::show_in_reading(m, loc, old as u64),
                        crate::machine::show_in_reading(m, loc, new as u64),
                    ),
                    None => (old.to_string(), new.to_string()),
                };
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
}
