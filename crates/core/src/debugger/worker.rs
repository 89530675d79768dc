//! Running on a worker thread. The engine travels: the window owns it while it draws a frame
//! (every reading and every command works as when stepping, and a command such as an input
//! switch lands at the exact position the run has reached), and lends it to the worker between
//! frames, which runs it forward in short chunks until the window calls it back, a breakpoint
//! stops it or the goal is reached. Only one thread holds the engine at a time and the worker
//! makes the same `forward` calls the window would, so the recorded timeline is the one a run
//! inside the frames records (a test compares them).

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::breakpoints::Checker;
use super::engine::Engine;
use super::run::{Plan, run_chunk};
use crate::machine::StopReason;

/// A run lent to the worker.
pub(crate) struct Job {
    pub engine: Box<dyn Engine>,
    pub checker: Checker,
    pub plan: Plan,
}

/// A run given back: why it stopped (`TickLimit` when called back still running).
pub(crate) struct Done {
    pub engine: Box<dyn Engine>,
    pub checker: Checker,
    pub reason: StopReason,
}

/// A chunk aims at this much wall time: short enough that a call back is answered at once,
/// long enough that the clock and the flag cost nothing.
const CHUNK_TIME: Duration = Duration::from_micros(400);

/// The simulation thread and the two channels to it.
pub(crate) struct Worker {
    jobs: Option<Sender<Job>>,
    done: Receiver<Done>,
    call_back: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    /// The thread, or `None` when the system gives none (the window then runs in its frames).
    pub fn spawn() -> Option<Worker> {
        let (jobs, job_rx) = channel::<Job>();
        let (done_tx, done) = channel::<Done>();
        let call_back = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&call_back);
        let thread = std::thread::Builder::new()
            .name("simulation".into())
            // At the window's own priority: a lower one starves the run as soon as another
            // process wants a core (the scheduler then puts it beside that process), for
            // frames hardly steadier (measured at several nice levels: docs/figures.md).
            .spawn(move || {
                // Ticks a chunk runs, adapted to the machine's speed and kept between jobs.
                let mut chunk = 1_000;
                while let Ok(job) = job_rx.recv() {
                    if done_tx.send(run_job(job, &flag, &mut chunk)).is_err() {
                        break;
                    }
                }
            })
            .ok()?;
        Some(Worker {
            jobs: Some(jobs),
            done,
            call_back,
            thread: Some(thread),
        })
    }

    /// Lend a run; the job comes back if the thread is gone.
    pub fn send(&self, job: Job) -> Result<(), Box<Job>> {
        self.call_back.store(false, Ordering::Release);
        match &self.jobs {
            Some(jobs) => jobs.send(job).map_err(|e| Box::new(e.0)),
            None => Err(Box::new(job)),
        }
    }

    /// Ask for the run back and wait for it (at most a chunk). `None` if the thread died.
    pub fn call_back(&self) -> Option<Done> {
        self.call_back.store(true, Ordering::Release);
        self.done.recv().ok()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.call_back.store(true, Ordering::Release);
        // Closing the job channel ends the thread's loop once the job in hand is given back.
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn run_job(job: Job, call_back: &AtomicBool, chunk: &mut u64) -> Done {
    let Job {
        mut engine,
        checker,
        mut plan,
    } = job;
    let checker = RefCell::new(checker);
    let active = (!checker.borrow().is_empty()).then_some(&checker);
    let reason = loop {
        let started = Instant::now();
        let reason = run_chunk(engine.as_mut(), &plan, active, *chunk);
        // Only the run's first stretch starts where it resumed.
        plan.skip_first = false;
        if reason != StopReason::TickLimit {
            break reason;
        }
        let took = started.elapsed();
        if took < CHUNK_TIME / 2 {
            *chunk = chunk.saturating_mul(2).min(1 << 26);
        } else if took > CHUNK_TIME * 2 {
            *chunk = (*chunk / 2).max(1);
        }
        if call_back.load(Ordering::Acquire) {
            break StopReason::TickLimit;
        }
    };
    Done {
        engine,
        checker: checker.into_inner(),
        reason,
    }
}
