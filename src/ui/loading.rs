//! Opening a session whose replay is long runs on a worker thread: the window keeps drawing,
//! shows how far the replay got, and Cancel stops it with the current session untouched.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError};

use servoscope_core::debugger::Debugger;
use servoscope_core::session::{Session, SessionError};

/// Sessions that replay at most this many ticks open at once (well under a frame's worth of
/// waiting is not guaranteed, but under a tenth of a second in a release build); longer ones
/// open in the background.
pub const REPLAY_AT_ONCE: u64 = 1_000_000;

pub struct Loading {
    pub path: PathBuf,
    /// The tick the replay must reach.
    pub total: u64,
    progress: Arc<AtomicU64>,
    cancel: Arc<AtomicBool>,
    result: Receiver<Result<(Session, Debugger), SessionError>>,
}

/// What became of a background open.
pub enum Outcome {
    Running,
    Done(Box<Session>, Box<Debugger>),
    Failed(String),
}

impl Loading {
    /// Start replaying `session` on a worker thread.
    pub fn start(path: PathBuf, session: Session) -> Loading {
        let total = session.furthest.max(session.at).tick;
        let progress = Arc::new(AtomicU64::new(0));
        let cancel = Arc::new(AtomicBool::new(false));
        let (send, result) = std::sync::mpsc::channel();
        let name = path.display().to_string();
        let (reached, stop) = (progress.clone(), cancel.clone());
        std::thread::spawn(move || {
            let restored = session.restore_with(&name, &mut |tick| {
                reached.store(tick, Ordering::Relaxed);
                !stop.load(Ordering::Relaxed)
            });
            // The window may have gone; nobody to tell then.
            let _ = send.send(restored.map(|d| (session, d)));
        });
        Loading {
            path,
            total,
            progress,
            cancel,
            result,
        }
    }

    /// Ticks replayed so far.
    pub fn reached(&self) -> u64 {
        self.progress.load(Ordering::Relaxed)
    }

    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    pub fn poll(&self) -> Outcome {
        match self.result.try_recv() {
            Err(TryRecvError::Empty) => Outcome::Running,
            Ok(Ok((session, debugger))) => Outcome::Done(Box::new(session), Box::new(debugger)),
            Ok(Err(e)) => Outcome::Failed(e.to_string()),
            Err(TryRecvError::Disconnected) => {
                Outcome::Failed(format!("opening {} failed", self.path.display()))
            }
        }
    }
}

/// The progress window; true when the user pressed Cancel.
pub fn window(ctx: &egui::Context, loading: &Loading) -> bool {
    let mut cancel = false;
    super::dialog("Opening session").show(ctx, |ui| {
        ui.label(format!(
            "Replaying {} to tick {} …",
            loading.path.display(),
            loading.total
        ));
        let done = loading.reached() as f32 / loading.total.max(1) as f32;
        ui.add(
            egui::ProgressBar::new(done.clamp(0.0, 1.0))
                .show_percentage()
                .desired_width(320.0),
        );
        let label = if loading.is_cancelled() {
            "Cancelling…"
        } else {
            "Cancel"
        };
        cancel = ui
            .add_enabled(!loading.is_cancelled(), egui::Button::new(label))
            .on_hover_text("Stop opening; the current session stays")
            .clicked();
    });
    cancel
}
