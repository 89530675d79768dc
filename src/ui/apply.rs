//! Carrying out what the user asked for.

use super::*;

impl ServoscopeApp {
    pub fn apply(&mut self, ctx: &egui::Context, command: Command) {
        let d = &mut self.debugger;
        match command {
            Command::Debug(action) => {
                // What the window keeps of an action besides the debugger's state.
                match &action {
                    Action::SetSpeed(speed) => {
                        let dialect = d.dialect().name.to_string();
                        self.prefs.speeds.insert(dialect, *speed);
                    }
                    Action::SetChannels(_) => self.plot.reset(),
                    _ => {}
                }
                let result = d.apply(action);
                self.report(result);
            }
            Command::EditSource(text) => *d.source_mut() = text,
            Command::EditFile(file, text) => {
                *d.file_text_mut(file) = text;
                // An `#include` typed in: its file is read from beside the top file.
                if let Some(dir) = self.path.as_ref().and_then(|p| p.parent()) {
                    d.add_new_includes(dir, &self.prefs.include_folders());
                }
            }
            Command::ShowAddresses(shown) => self.code.addresses = shown,
            Command::ToggleMaximise(tile) => {
                self.layout.maximised = (self.layout.maximised != Some(tile)).then_some(tile);
            }
            Command::OpenDialog => self.files.open.start(ctx),
            Command::OpenPath(path) => self.guarded(Pending::Open(path)),
            Command::SaveSession => match self.session_path.clone() {
                Some(path) => self.save_session_to(path),
                None => self.files.save.start(ctx),
            },
            Command::SaveSessionDialog => self.files.save.start(ctx),
            Command::SaveSessionTo(path) => self.save_session_to(path),
            Command::SaveProgram => match self.path.clone() {
                Some(path) => self.save_program_to(path),
                None => self.files.save_program.start(ctx),
            },
            Command::SaveProgramDialog => self.files.save_program.start(ctx),
            Command::SaveProgramTo(path) => self.save_program_to(path),
            Command::SaveSessionOver(path) => {
                self.confirm_replace = None;
                self.save_session(path, true);
            }
            Command::ExportDialog => self.files.export.start(ctx),
            Command::ExportCsv(path)
                if !self.may_export(
                    &path,
                    servoscope_core::output::Output::PlotCsv,
                    files::Purpose::ExportCsv,
                ) => {}
            Command::ExportCsv(path) => match self.debugger.export_trace_csv(&path) {
                Ok(rows) => {
                    self.files.export.close();
                    self.notice = Some(format!("Exported {rows} rows to {}", path.display()));
                }
                Err(e) => self.file_failed(
                    files::Purpose::ExportCsv,
                    format!("Cannot write {}: {e}", path.display()),
                ),
            },
            Command::LoadExample(i) => self.guarded(Pending::Example(i)),
            Command::LoadExampleProject(i) => self.guarded(Pending::ExampleProject(i)),
            Command::LoadLesson(i) => self.guarded(Pending::Lesson(i)),
            Command::NewProgram(name) => self.guarded(Pending::New(name)),
            Command::DiscardAndContinue => {
                if let Some(action) = self.pending.take() {
                    self.perform(action);
                    if self.allow_close {
                        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                    }
                }
            }
            Command::CancelPending => self.pending = None,
            Command::SetDark(dark) => self.prefs.dark = dark,
            Command::ShowPane(pane, shown) => self.layout.set_shown(&pane, shown),
            Command::ResetLayout => {
                let titles: Vec<&str> = self.panels.iter().map(|p| p.title()).collect();
                self.layout = layout::Layout::standard(&titles);
            }
            Command::AddBreakpoint(b) => {
                self.debugger.add_breakpoint(b);
                self.layout.set_shown(&layout::Pane::Breakpoints, true);
                self.layout.focus(&layout::Pane::Breakpoints);
            }
            Command::WhoWrote(loc) => {
                if self.debugger.who_wrote(loc).is_some() {
                    self.code.reset_view();
                }
            }
            Command::AddWatch(text) => {
                let format = self.debugger.watch_format_for(&text);
                self.debugger.add_watch(text, format);
                self.layout.set_shown(&layout::Pane::Watches, true);
                self.layout.focus(&layout::Pane::Watches);
            }
            Command::PlotWatch(i) => {
                if self.debugger.plot_watch(i) {
                    self.plot.reset();
                } else {
                    self.notice = Some(
                        "Not plotted: the watch does not compile, or all 8 channels are taken"
                            .to_string(),
                    );
                }
            }
            Command::ShowLine(line) => self.code.show_line(line),
            Command::FocusPane(pane) => self.layout.focus(&pane),
            Command::SelectLocation(loc) => {
                self.registers.select(loc, self.debugger.machine());
            }
            Command::ExportLadderDialog => self.files.export_ladder.start(ctx),
            Command::ExportLadder(path) => self.export_ladder(&path),
            Command::OpenHelp(mnemonic) => {
                self.help.open_at(mnemonic.as_deref());
                self.layout
                    .add_beside(layout::Pane::Help, &layout::Pane::Bits);
                self.layout.focus(&layout::Pane::Help);
            }
            Command::LessonStep(step) => {
                if let Some(l) = &mut self.lesson {
                    l.go_to(step);
                }
            }
            Command::LessonCheck => {
                if let Some(l) = &mut self.lesson {
                    l.check(&self.debugger);
                }
            }
            Command::LessonReset => self.reset_lesson(),
            Command::SaveAsLesson => {
                if self.lesson.is_none() {
                    let name = self.debugger.name();
                    let title = Path::new(name)
                        .file_stem()
                        .map_or(name.to_string(), |s| s.to_string_lossy().replace('_', " "));
                    let start = self.session();
                    let mut view = lesson::LessonView::new(
                        servoscope_core::lesson::Lesson {
                            title,
                            steps: vec![servoscope_core::lesson::LessonStep {
                                text: "# The task\n\nWrite here what the student should do."
                                    .to_string(),
                                checks: Vec::new(),
                            }],
                            // A PLC is graded after as many scans as the teacher ran (the
                            // runner's default is one scan); other programs run to their end.
                            max_ticks: (self.debugger.machine().is_plc()
                                && self.debugger.pos().tick > 1)
                                .then(|| self.debugger.pos().tick),
                            handed_out: false,
                        },
                        Some(start),
                    );
                    view.editing = true;
                    self.set_lesson(Some(view));
                }
                self.files.save.start(ctx);
            }
            Command::ExportLogDialog => self.files.export_log.start(ctx),
            Command::ExportLog(path)
                if !self.may_export(
                    &path,
                    servoscope_core::output::Output::LogCsv,
                    files::Purpose::ExportLog,
                ) => {}
            Command::ExportLog(path) => {
                let rows = self.log.log.rows.len();
                match servoscope_core::atomic::write_atomically(&path, |w| {
                    self.log.write_csv(w, self.debugger.project())
                }) {
                    Ok(()) => {
                        self.files.export_log.close();
                        self.notice =
                            Some(format!("Exported {rows} log entries to {}", path.display()));
                    }
                    Err(e) => self.file_failed(
                        files::Purpose::ExportLog,
                        format!("Cannot write {}: {e}", path.display()),
                    ),
                }
            }
            Command::OpenSettings => self.settings.open = true,
            Command::OpenIncludeFolders => self.include_folders.open = true,
            Command::AllowIncludeFolder(folder) => {
                let folder = std::path::absolute(&folder).unwrap_or(folder);
                if !folder.is_dir() {
                    self.notice = Some(format!("{} is not a folder", folder.display()));
                } else if !self.prefs.include_folders.contains(&folder) {
                    self.prefs.include_folders.push(folder);
                    // Includes refused before are read now, as they are on disk; a program
                    // that could not assemble without them assembles.
                    if let Some(dir) = self.path.clone().as_ref().and_then(|p| p.parent()) {
                        let folders = self.prefs.include_folders();
                        let was_dirty = self.is_dirty();
                        if self.debugger.add_new_includes(dir, &folders) > 0 {
                            if let Some(saved) = self.file_text.as_mut() {
                                let files = &self.debugger.project().files;
                                saved.extend(
                                    files[saved.len().min(files.len())..]
                                        .iter()
                                        .map(|f| f.text.clone()),
                                );
                            }
                            if self.debugger.has_errors() {
                                self.debugger.assemble();
                            }
                            // Read from disk, nothing the user did: nothing to save.
                            if !was_dirty {
                                self.mark_saved();
                            }
                        }
                    }
                }
            }
            Command::ForbidIncludeFolder(folder) => {
                self.prefs.include_folders.retain(|f| *f != folder);
            }
            Command::SetSettings(settings) => {
                self.debugger.set_settings(&settings);
                self.settings.draft = None;
            }
        }
    }

    /// A refused edit is said in the notice banner; nothing changed.
    pub(super) fn report(&mut self, result: Result<(), servoscope_core::debugger::EditError>) {
        if let Err(e) = result {
            self.notice = Some(format!("Not changed: {e}"));
        }
    }
}
