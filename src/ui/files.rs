//! Opening programs: the native dialog on a worker thread (never blocking a frame), a path
//! field that always works (also when no dialog is available), and drag-and-drop.

use std::path::PathBuf;
use std::sync::mpsc::{Receiver, TryRecvError, channel};

use super::{Command, Prefs};

#[derive(Default)]
pub struct Files {
    pub window_open: bool,
    pub path_text: String,
    pub error: Option<String>,
    pending: Option<Receiver<Option<PathBuf>>>,
}

impl Files {
    /// Show the Open window and start the native dialog beside it.
    pub fn open_dialog(&mut self, ctx: &egui::Context) {
        self.window_open = true;
        self.error = None;
        if self.pending.is_some() {
            return;
        }
        let (tx, rx) = channel();
        let ctx = ctx.clone();
        let spawned = std::thread::Builder::new()
            .name("file-dialog".into())
            .spawn(move || {
                let picked = rfd::FileDialog::new()
                    .set_title("Open a program")
                    .add_filter("SilverLode program", &["qsl"])
                    .add_filter("All files", &["*"])
                    .pick_file();
                let _ = tx.send(picked);
                ctx.request_repaint();
            });
        if spawned.is_ok() {
            self.pending = Some(rx);
        }
    }

    pub fn is_waiting(&self) -> bool {
        self.pending.is_some()
    }

    /// A path picked in the native dialog, once it has answered. A cancelled or unavailable
    /// dialog leaves the path field for the user.
    pub fn poll(&mut self) -> Option<PathBuf> {
        let rx = self.pending.as_ref()?;
        match rx.try_recv() {
            Ok(picked) => {
                self.pending = None;
                picked
            }
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                self.pending = None;
                None
            }
        }
    }

    pub fn close(&mut self) {
        self.window_open = false;
        self.error = None;
    }
}

pub fn open_window(ctx: &egui::Context, files: &mut Files, prefs: &Prefs, out: &mut Vec<Command>) {
    if !files.window_open {
        return;
    }
    let mut open = true;
    egui::Window::new("Open a program")
        .collapsible(false)
        .resizable(false)
        .open(&mut open)
        .show(ctx, |ui| {
            if files.is_waiting() {
                ui.label("Choose a file in the system dialog, or type its path here:");
            } else {
                ui.label("Type the path of a .qsl program:");
            }
            ui.horizontal(|ui| {
                let label = ui.label("Path");
                let edit = ui
                    .add(egui::TextEdit::singleline(&mut files.path_text).desired_width(360.0))
                    .labelled_by(label.id);
                let entered = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                if (ui.button("Open").clicked() || entered) && !files.path_text.trim().is_empty() {
                    out.push(Command::OpenPath(PathBuf::from(files.path_text.trim())));
                }
            });
            if ui.button("Browse…").clicked() {
                out.push(Command::OpenDialog);
            }
            if let Some(error) = &files.error {
                ui.colored_label(ui.visuals().error_fg_color, error);
            }
            if !prefs.recent.is_empty() {
                ui.separator();
                ui.label("Recent:");
                for path in &prefs.recent {
                    if ui.link(path.display().to_string()).clicked() {
                        out.push(Command::OpenPath(path.clone()));
                    }
                }
            }
        });
    if !open {
        files.close();
    }
}

/// Files dropped on the window open like File → Open.
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
