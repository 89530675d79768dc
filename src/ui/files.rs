//! Choosing files: the native dialog on a worker thread (never blocking a frame), beside a
//! small window with a path field that always works (also when no dialog is available), and
//! drag-and-drop.

use std::path::PathBuf;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

use super::{Command, Prefs};

/// What a chosen path is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// A program or a session.
    OpenProgram,
    SaveSession,
    ExportCsv,
    /// The execution log, as CSV.
    ExportLog,
    /// The program's text, as a program file.
    SaveProgram,
    /// The ladder diagram, as SVG.
    ExportLadder,
}

impl Purpose {
    fn title(self) -> &'static str {
        match self {
            Purpose::OpenProgram => "Open a program or session",
            Purpose::SaveSession => "Save the session",
            Purpose::ExportCsv => "Export the trace as CSV",
            Purpose::ExportLog => "Export the execution log as CSV",
            Purpose::SaveProgram => "Save the program",
            Purpose::ExportLadder => "Export the ladder diagram as SVG",
        }
    }
    fn button(self) -> &'static str {
        match self {
            Purpose::OpenProgram => "Open",
            Purpose::SaveSession => "Save",
            Purpose::ExportCsv | Purpose::ExportLog | Purpose::ExportLadder => "Export",
            Purpose::SaveProgram => "Save program",
        }
    }
    fn command(self, path: PathBuf) -> Command {
        match self {
            Purpose::OpenProgram => Command::OpenPath(path),
            Purpose::SaveSession => Command::SaveSessionTo(path),
            Purpose::ExportCsv => Command::ExportCsv(path),
            Purpose::ExportLog => Command::ExportLog(path),
            Purpose::SaveProgram => Command::SaveProgramTo(path),
            Purpose::ExportLadder => Command::ExportLadder(path),
        }
    }
}

/// One pending choice of a path.
pub struct PathRequest {
    pub purpose: Purpose,
    pub window_open: bool,
    pub path_text: String,
    pub error: Option<String>,
    /// What happened to the system dialog, when the user should know ("none available").
    pub note: Option<String>,
    pending: Option<Receiver<Option<PathBuf>>>,
    started: Option<Instant>,
    /// Focus the path field (all of it selected) when the window next shows.
    focus_field: bool,
}

/// A system dialog that answers "nothing chosen" faster than this never showed: there is none
/// (no portal, no zenity) and the user is told so.
const NO_DIALOG_WITHIN: Duration = Duration::from_millis(400);

impl PathRequest {
    fn new(purpose: Purpose) -> Self {
        PathRequest {
            purpose,
            window_open: false,
            path_text: String::new(),
            error: None,
            note: None,
            pending: None,
            started: None,
            focus_field: false,
        }
    }

    /// Show the window and start the native dialog beside it.
    pub fn start(&mut self, ctx: &egui::Context) {
        if !self.window_open {
            self.focus_field = true;
        }
        self.window_open = true;
        self.error = None;
        if self.pending.is_some() {
            self.note = Some(
                "The system file dialog is already open (it may be behind this window).".into(),
            );
            return;
        }
        self.note = None;
        let (tx, rx) = channel();
        let ctx = ctx.clone();
        let purpose = self.purpose;
        let spawned = std::thread::Builder::new()
            .name("file-dialog".into())
            .spawn(move || {
                let dialog = rfd::FileDialog::new().set_title(purpose.title());
                let picked = match purpose {
                    Purpose::OpenProgram => dialog
                        .add_filter("Programs and sessions", &openable_extensions())
                        .add_filter("All files", &["*"])
                        .pick_file(),
                    Purpose::SaveSession => dialog
                        .add_filter("servoscope session", &["ron"])
                        .set_file_name("session.ron")
                        .save_file(),
                    Purpose::ExportCsv => dialog
                        .add_filter("CSV", &["csv"])
                        .set_file_name("trace.csv")
                        .save_file(),
                    Purpose::ExportLog => dialog
                        .add_filter("CSV", &["csv"])
                        .set_file_name("log.csv")
                        .save_file(),
                    Purpose::SaveProgram => dialog
                        .add_filter("Programs", &openable_extensions())
                        .save_file(),
                    Purpose::ExportLadder => dialog
                        .add_filter("SVG", &["svg"])
                        .set_file_name("ladder.svg")
                        .save_file(),
                };
                let _ = tx.send(picked);
                ctx.request_repaint();
            });
        match spawned {
            Ok(_) => {
                self.pending = Some(rx);
                self.started = Some(Instant::now());
            }
            Err(e) => self.note = Some(format!("No system file dialog ({e}): type the path.")),
        }
    }

    pub fn is_waiting(&self) -> bool {
        self.pending.is_some()
    }

    /// The path picked in the native dialog, once it answered. A cancelled or unavailable
    /// dialog leaves the path field for the user.
    fn poll(&mut self) -> Option<PathBuf> {
        let rx = self.pending.as_ref()?;
        let answer = match rx.try_recv() {
            Ok(picked) => picked,
            Err(TryRecvError::Empty) => return None,
            Err(TryRecvError::Disconnected) => None,
        };
        self.pending = None;
        let waited = self.started.take().map_or(Duration::MAX, |t| t.elapsed());
        self.answered(answer, waited)
    }

    /// The system dialog's answer after `waited`: a path, or nothing (cancelled, or no dialog
    /// at all, which the user is told).
    pub fn answered(&mut self, picked: Option<PathBuf>, waited: Duration) -> Option<PathBuf> {
        if picked.is_none() && waited < NO_DIALOG_WITHIN {
            self.note = Some("No system file dialog is available here: type the path.".into());
        }
        picked
    }

    pub fn close(&mut self) {
        self.window_open = false;
        self.error = None;
        self.note = None;
    }
}

pub struct Files {
    pub open: PathRequest,
    pub save: PathRequest,
    pub export: PathRequest,
    pub export_log: PathRequest,
    pub save_program: PathRequest,
    pub export_ladder: PathRequest,
}

impl Default for Files {
    fn default() -> Self {
        Files {
            open: PathRequest::new(Purpose::OpenProgram),
            save: PathRequest::new(Purpose::SaveSession),
            export: PathRequest::new(Purpose::ExportCsv),
            export_log: PathRequest::new(Purpose::ExportLog),
            save_program: PathRequest::new(Purpose::SaveProgram),
            export_ladder: PathRequest::new(Purpose::ExportLadder),
        }
    }
}

impl Files {
    /// The request for `purpose`.
    pub fn request(&mut self, purpose: Purpose) -> &mut PathRequest {
        match purpose {
            Purpose::OpenProgram => &mut self.open,
            Purpose::SaveSession => &mut self.save,
            Purpose::ExportCsv => &mut self.export,
            Purpose::ExportLog => &mut self.export_log,
            Purpose::SaveProgram => &mut self.save_program,
            Purpose::ExportLadder => &mut self.export_ladder,
        }
    }

    pub fn is_waiting(&self) -> bool {
        self.open.is_waiting()
            || self.save.is_waiting()
            || self.export.is_waiting()
            || self.export_log.is_waiting()
            || self.save_program.is_waiting()
            || self.export_ladder.is_waiting()
    }

    /// Commands for paths the native dialogs returned.
    pub fn poll(&mut self, out: &mut Vec<Command>) {
        for request in [
            &mut self.open,
            &mut self.save,
            &mut self.export,
            &mut self.export_log,
            &mut self.save_program,
            &mut self.export_ladder,
        ] {
            if let Some(path) = request.poll() {
                out.push(request.purpose.command(path));
            }
        }
    }

    pub fn windows(&mut self, ctx: &egui::Context, prefs: &Prefs, out: &mut Vec<Command>) {
        path_window(ctx, &mut self.open, &prefs.recent, out);
        path_window(ctx, &mut self.save, &[], out);
        path_window(ctx, &mut self.export, &[], out);
        path_window(ctx, &mut self.export_log, &[], out);
        path_window(ctx, &mut self.save_program, &[], out);
        path_window(ctx, &mut self.export_ladder, &[], out);
    }
}

fn path_window(
    ctx: &egui::Context,
    request: &mut PathRequest,
    recent: &[PathBuf],
    out: &mut Vec<Command>,
) {
    if !request.window_open {
        return;
    }
    let purpose = request.purpose;
    // Escape closes the dialog, as every dialog does.
    let mut open = !ctx.input(|i| i.key_pressed(egui::Key::Escape));
    egui::Window::new(purpose.title())
        .collapsible(false)
        .resizable(false)
        .open(&mut open)
        .show(ctx, |ui| {
            if request.is_waiting() {
                ui.label("Choose a file in the system dialog, or type its path here:");
            } else {
                ui.label("Type the path:");
            }
            ui.horizontal(|ui| {
                let label = ui.label("Path");
                let output = egui::TextEdit::singleline(&mut request.path_text)
                    .desired_width(360.0)
                    .show(ui);
                let edit = egui::Response::clone(&output.response).labelled_by(label.id);
                if std::mem::take(&mut request.focus_field) {
                    // All selected: typing replaces a path left from last time, and a click
                    // does not land in the middle of it.
                    let mut state = output.state;
                    let all = request.path_text.chars().count();
                    state
                        .cursor
                        .set_char_range(Some(egui::text::CCursorRange::two(
                            egui::text::CCursor::new(0),
                            egui::text::CCursor::new(all),
                        )));
                    state.store(ui.ctx(), edit.id);
                    edit.request_focus();
                }
                let entered = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                let text = request.path_text.trim();
                if (ui.button(purpose.button()).clicked() || entered) && !text.is_empty() {
                    out.push(purpose.command(PathBuf::from(text)));
                }
            });
            if ui.button("Browse…").clicked() {
                out.push(match purpose {
                    Purpose::OpenProgram => Command::OpenDialog,
                    Purpose::SaveSession => Command::SaveSessionDialog,
                    Purpose::ExportCsv => Command::ExportDialog,
                    Purpose::ExportLog => Command::ExportLogDialog,
                    Purpose::SaveProgram => Command::SaveProgramDialog,
                    Purpose::ExportLadder => Command::ExportLadderDialog,
                });
            }
            if let Some(note) = &request.note {
                ui.label(note);
            }
            if let Some(error) = &request.error {
                ui.colored_label(ui.visuals().error_fg_color, error);
            }
            if !recent.is_empty() {
                ui.separator();
                ui.label("Recent:");
                for path in recent {
                    if ui.link(path.display().to_string()).clicked() {
                        out.push(Command::OpenPath(path.clone()));
                    }
                }
            }
        });
    if !open {
        request.close();
    }
}

/// Files dropped on the window open like File > Open.
pub fn dropped_files(ctx: &egui::Context, out: &mut Vec<Command>) {
    let dropped: Vec<PathBuf> = ctx.input(|i| {
        i.raw
            .dropped_files
            .iter()
            .map(|f| f.path().to_path_buf())
            .filter(|p| !p.as_os_str().is_empty())
            .collect()
    });
    if let Some(path) = dropped.into_iter().next() {
        out.push(Command::OpenPath(path));
    }
}

/// Every dialect's program extensions, and `ron` for sessions.
pub fn openable_extensions() -> Vec<&'static str> {
    servoscope_core::registry::DIALECTS
        .iter()
        .flat_map(|d| d.extensions.iter().copied())
        .chain(["ron"])
        .collect()
}

/// The last part of `path`, for titles and names (the whole path when it has none).
pub fn file_name(path: &std::path::Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dialog_that_answers_nothing_at_once_was_never_shown() {
        let mut request = PathRequest::new(Purpose::OpenProgram);
        assert_eq!(request.answered(None, Duration::from_millis(20)), None);
        assert!(
            request
                .note
                .as_deref()
                .is_some_and(|n| n.contains("No system file dialog"))
        );

        // Cancelled after a while: the user saw it, nothing to say.
        let mut request = PathRequest::new(Purpose::OpenProgram);
        assert_eq!(request.answered(None, Duration::from_secs(3)), None);
        assert_eq!(request.note, None);

        let picked = PathBuf::from("/tmp/x.qsl");
        assert_eq!(
            request.answered(Some(picked.clone()), Duration::from_millis(5)),
            Some(picked)
        );
        assert_eq!(request.note, None);
    }
}
