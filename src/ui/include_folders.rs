//! View → Include folders…: the folders besides a program's own that its `#include`d files may
//! be read from (the runner's `--include-dir`). None until the user adds one: a student's file
//! must not read `/etc/passwd` into a grader's window.

use std::path::PathBuf;

use egui::RichText;

use super::Command;

#[derive(Default)]
pub struct IncludeFoldersView {
    pub open: bool,
    /// The folder being typed.
    pub new_folder: String,
}

pub fn window(
    ctx: &egui::Context,
    allowed: &[PathBuf],
    view: &mut IncludeFoldersView,
    out: &mut Vec<Command>,
) {
    if !view.open {
        return;
    }
    let mut open = true;
    egui::Window::new("Include folders")
        // In the middle, not over the program's tabs it is about.
        .pivot(egui::Align2::CENTER_CENTER)
        .default_pos(ctx.content_rect().center())
        .collapsible(false)
        .resizable(false)
        .open(&mut open)
        .show(ctx, |ui| {
            ui.label(
                "Included files are read from the program's own folder and its subfolders, \
                 and from these folders:",
            );
            if allowed.is_empty() {
                ui.label(RichText::new("(none)").italics());
            }
            for folder in allowed {
                ui.horizontal(|ui| {
                    ui.monospace(folder.display().to_string());
                    if ui
                        .button("Remove")
                        .on_hover_text("Included files are no longer read from here")
                        .clicked()
                    {
                        out.push(Command::ForbidIncludeFolder(folder.clone()));
                    }
                });
            }
            ui.separator();
            ui.horizontal(|ui| {
                ui.add(
                    egui::TextEdit::singleline(&mut view.new_folder)
                        .char_limit(servoscope_core::session::limits::TEXT)
                        .hint_text("/path/to/shared/folder")
                        .desired_width(260.0),
                )
                .widget_info(|| {
                    egui::WidgetInfo::labeled(egui::Role::TextInput, true, "Folder to allow")
                });
                let typed = view.new_folder.trim();
                if ui
                    .add_enabled(!typed.is_empty(), egui::Button::new("Allow"))
                    .clicked()
                {
                    out.push(Command::AllowIncludeFolder(PathBuf::from(typed)));
                    view.new_folder.clear();
                }
            });
            ui.label(
                RichText::new(
                    "Kept with your preferences, never in a session. A folder removed is no \
                     longer read from the next time a program is opened. The command line's \
                     --include-dir DIR does the same for one run.",
                )
                .small(),
            );
        });
    if !open {
        view.open = false;
    }
}
