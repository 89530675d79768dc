//! Opening and saving: programs, sessions, lessons and exports, with the questions asked
//! before unsaved changes go.

use super::*;

impl ServoscopeApp {
    /// Open a program (dialect by extension) or a session (`.ron`). On failure the current
    /// session stays and the user is told why.
    pub fn open_path(&mut self, path: PathBuf) {
        self.open_path_as(path, None);
    }

    pub(super) fn open_path_as(&mut self, path: PathBuf, dialect: Option<&'static Dialect>) {
        let result = if is_session_path(&path) {
            self.open_session(&path)
        } else {
            self.open_program(&path, dialect).map(|()| true)
        };
        match result {
            Ok(true) => self.opened(&path),
            // Replaying in the background: `poll_loading` finishes the job.
            Ok(false) => {}
            Err(message) => self.open_failed(message),
        }
    }

    pub(super) fn opened(&mut self, path: &Path) {
        self.remember(path);
        self.files.open.close();
        self.mark_saved();
    }

    pub(super) fn open_failed(&mut self, message: String) {
        self.file_failed(files::Purpose::OpenProgram, message);
    }

    /// Whether an export of `kind` may write `path`: never over the program's files or the
    /// session, and not over a file of another kind (the dialog says so and stays open).
    pub(super) fn may_export(
        &mut self,
        path: &Path,
        kind: servoscope_core::output::Output,
        purpose: files::Purpose,
    ) -> bool {
        let mut inputs = match &self.path {
            Some(top) => servoscope_core::output::program_inputs(top, self.debugger.project()),
            None => Vec::new(),
        };
        inputs.extend(
            (self.session_path.iter())
                .map(|s| servoscope_core::output::Input::new(s, "the open session")),
        );
        match servoscope_core::output::may_write(path, kind, &inputs, false) {
            Ok(()) => true,
            Err(e) => {
                self.file_failed(purpose, format!("{e}: choose another name"));
                false
            }
        }
    }

    /// File → Export ladder…: the diagram at the current position, as SVG.
    pub(super) fn export_ladder(&mut self, path: &std::path::Path) {
        use servoscope_core::output::Output;
        if !self.may_export(path, Output::LadderSvg, files::Purpose::ExportLadder) {
            return;
        }
        let d = &self.debugger;
        let m = d.machine();
        let Some(diagram) = servoscope_core::machine::plc::ladder::with_comments(
            m,
            d.source(),
            d.dialect().classify,
        ) else {
            self.notice = Some("This program has no ladder diagram".to_string());
            return;
        };
        let at = m.pos();
        let title = if at.step == 0 {
            format!("{} — at scan {}", d.name(), at.tick)
        } else {
            format!("{} — scan {}, instruction {}", d.name(), at.tick, at.step)
        };
        let svg = servoscope_core::machine::plc::ladder::svg_of(m, &diagram, &title);
        match servoscope_core::atomic::write_atomically(path, |w| w.write_all(svg.as_bytes())) {
            Ok(()) => {
                self.files.export_ladder.close();
                self.notice = Some(format!(
                    "Exported {} rungs to {}",
                    diagram.rungs.len(),
                    path.display()
                ));
            }
            Err(e) => self.file_failed(
                files::Purpose::ExportLadder,
                format!("Cannot write {}: {e}", path.display()),
            ),
        }
    }

    pub(super) fn file_failed(&mut self, purpose: files::Purpose, message: String) {
        self.files.request(purpose).error = Some(message.clone());
        self.notice = Some(message);
    }

    /// Finish (or give up) a background open.
    pub(super) fn poll_loading(&mut self, ctx: &egui::Context) {
        let Some(job) = &self.loading else {
            return;
        };
        match job.poll() {
            loading::Outcome::Running => {
                if loading::window(ctx, job) {
                    job.cancel();
                }
                ctx.request_repaint();
            }
            loading::Outcome::Done(session, debugger) => {
                let path = job.path.clone();
                self.loading = None;
                self.install_session(&path, &session, *debugger);
                self.opened(&path);
            }
            loading::Outcome::Failed(message) => {
                self.loading = None;
                self.open_failed(format!("{message}; the current session stays"));
            }
        }
    }

    /// Start over on a program given as text (an example, or a test's program), in the
    /// current dialect.
    pub fn load_program(&mut self, name: &str, text: &str) {
        let dialect = self.debugger.dialect();
        self.load_program_as(dialect, name, text);
    }

    /// Start over on a program given as text in `dialect`.
    pub fn load_program_as(&mut self, dialect: &'static Dialect, name: &str, text: &str) {
        self.set_lesson(None);
        self.debugger.load_as(dialect, name, text);
        self.file_text = Some(file_texts(&self.debugger));
        self.path = None;
        self.session_path = None;
        self.fresh_views();
        self.mark_saved();
    }

    pub(super) fn open_program(
        &mut self,
        path: &Path,
        dialect: Option<&'static Dialect>,
    ) -> Result<(), String> {
        let dialect = match dialect {
            Some(d) => d,
            None => registry::choose(path, None).map_err(|e| e.to_string())?,
        };
        // The top file of a project opens with every file it includes.
        let project = dialect
            .load_with(path, &self.prefs.include_folders())
            .map_err(|e| format!("Cannot open the program: {e}"))?;
        // A student opening an answer keeps the lesson open: its checks apply to any program
        // of its dialect.
        if self.debugger.dialect() != dialect {
            self.set_lesson(None);
        }
        if project.is_multi() {
            self.debugger.load_project(dialect, project);
        } else {
            self.debugger
                .load_as(dialect, files::file_name(path), project.top_text());
        }
        self.file_text = Some(file_texts(&self.debugger));
        self.path = Some(path.to_path_buf());
        self.session_path = None;
        self.fresh_views();
        Ok(())
    }

    /// Open a session: at once when its replay is short (true), else in the background
    /// (false), with a progress window and Cancel.
    pub(super) fn open_session(&mut self, path: &Path) -> Result<bool, String> {
        let name = path.display().to_string();
        let session = Session::load(path).map_err(|e| e.to_string())?;
        if session.furthest.max(session.at).tick > loading::REPLAY_AT_ONCE {
            self.loading = Some(loading::Loading::start(path.to_path_buf(), session));
            return Ok(false);
        }
        let debugger = session.restore(&name).map_err(|e| e.to_string())?;
        self.install_session(path, &session, debugger);
        Ok(true)
    }

    /// A built-in lesson session: opened like a session file, but with no file behind it (a
    /// save asks where).
    pub(super) fn open_lesson(&mut self, name: &str, text: &str) {
        let opened = Session::from_ron(text, name).and_then(|s| Ok((s.restore(name)?, s)));
        match opened {
            Ok((debugger, session)) => {
                self.install_session(Path::new(name), &session, debugger);
                self.session_path = None;
                self.mark_saved();
            }
            Err(e) => self.notice = Some(e.to_string()),
        }
    }

    pub(super) fn install_session(&mut self, path: &Path, session: &Session, debugger: Debugger) {
        let changed = session.changed_on_disk(&self.prefs.include_folders());
        self.debugger = debugger;
        self.path = session.program_path.clone();
        self.file_text = Some(file_texts(&self.debugger));
        // A file that changed on disk differs from the session's copy in the window: it is
        // unsaved, so its tab says so and Save program writes the copy back.
        if let Some(saved) = self.file_text.as_mut() {
            for (k, f) in self.debugger.project().files.iter().enumerate() {
                if changed.contains(&f.name)
                    && let Some(text) = saved.get_mut(k)
                {
                    text.clear();
                    text.push('\u{0}');
                }
            }
        }
        self.session_path = Some(path.to_path_buf());
        self.fresh_views();
        self.apply_view_settings(&session.view);
        if let Some(window) = &session.window {
            super::window_state::restore(self.ctx.as_ref(), window, &mut self.layout);
            // The tabs come back as they were left, not with the dialect's best in front.
            self.focus_panel_pending = false;
        }
        // After the dialect's panels are in place, so the lesson's tab is the one in front.
        self.set_lesson(
            session
                .lesson
                .clone()
                .map(|l| lesson::LessonView::new(l, Some(session.clone()))),
        );
        if !session.warnings.is_empty() {
            self.notice = Some(format!(
                "Opened {}, but {}",
                path.display(),
                session.warnings.join("; ")
            ));
        }
        if !changed.is_empty() {
            let said = self
                .notice
                .take()
                .map_or(String::new(), |n| format!("{n}. "));
            self.notice = Some(format!(
                "{said}{} changed on disk since the session was saved: the session's copies are shown and run (Save program writes them back)",
                changed.join(", ")
            ));
        }
    }

    /// Open (or close, with `None`) a lesson: its panel comes forward beside the bits, where
    /// the registers stay in view.
    pub(super) fn set_lesson(&mut self, lesson: Option<lesson::LessonView>) {
        let open = lesson.is_some();
        // The lesson's inputs meet every program the student assembles while it is open.
        let scripted = lesson
            .as_ref()
            .and_then(|l| l.start.as_ref())
            .map(|s| {
                s.events
                    .iter()
                    .map(|e| servoscope_core::debugger::ScriptedEvent {
                        at: e.at,
                        location: e.location.clone(),
                        change: e.change,
                    })
                    .collect()
            })
            .unwrap_or_default();
        self.debugger.set_scripted_events(scripted);
        self.lesson = lesson;
        if open {
            self.layout
                .add_beside(layout::Pane::Lesson, &layout::Pane::Bits);
            self.layout.focus(&layout::Pane::Lesson);
            // The steps are what a student reads first: two thirds of the column, so a small
            // window shows more than three lines of them.
            self.layout.give_share(&layout::Pane::Lesson, 0.65);
        } else if self.layout.contains(&layout::Pane::Lesson) {
            self.layout.set_shown(&layout::Pane::Lesson, false);
        }
    }

    /// Reset lesson: the lesson's program, position and edits as it opened, its steps kept as
    /// they are now (a teacher's edits are not thrown away), at the step shown.
    pub(super) fn reset_lesson(&mut self) {
        let Some(start) = self.lesson.as_ref().and_then(|l| l.start.clone()) else {
            return;
        };
        let name = start.program_name.clone();
        match start.restore(&name) {
            Ok(debugger) => {
                let kept = self.lesson.take();
                let session_path = self.session_path.clone();
                self.install_session(Path::new(&name), &start, debugger);
                self.session_path = session_path;
                if let Some(mut kept) = kept {
                    kept.checked = None;
                    self.set_lesson(Some(kept));
                }
            }
            Err(e) => self.notice = Some(format!("Cannot reset the lesson: {e}")),
        }
    }

    /// Whether the program text differs from what was opened or last saved as a program.
    pub fn program_modified(&self) -> bool {
        self.file_text.as_ref() != Some(&file_texts(&self.debugger))
    }

    /// Write the program text to `path` (atomically; the dialect's extension is added to a
    /// name without one). The program then belongs to that file.
    pub fn save_program_to(&mut self, path: PathBuf) {
        let path = if path.extension().is_none() {
            path.with_extension(self.debugger.dialect().extensions[0])
        } else {
            path
        };
        if is_session_path(&path) {
            let message = format!(
                "{} would be read as a session; give the program its dialect's extension (.{})",
                path.display(),
                self.debugger.dialect().extensions[0]
            );
            self.file_failed(files::Purpose::SaveProgram, message);
            return;
        }
        let path = std::path::absolute(&path).unwrap_or(path);
        let texts = file_texts(&self.debugger);
        // The included files sit relative to the top file: each that changed is written
        // beside it (all of them when the top file moves to another folder).
        let same_folder = self.path.as_ref().and_then(|p| p.parent()) == path.parent();
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let saved = self.file_text.clone().unwrap_or_default();
        let mut written = Vec::new();
        let mut texts = texts;
        let mut outside = Vec::new();
        let folders = self.prefs.include_folders();
        for (k, f) in self.debugger.project().files.iter().enumerate() {
            // Never written outside the top file's folder (and the folders the user allowed),
            // links followed: a session file names the files, and a crafted one must not make
            // Save program overwrite anything elsewhere. Such a file stays unsaved.
            let inside = if k == 0 {
                Some(path.clone())
            } else {
                folders.path_of(&dir, &f.name)
            };
            let target = inside.clone().unwrap_or_else(|| dir.join(&f.name));
            if inside.is_none() {
                if saved.get(k) != Some(&f.text) {
                    outside.push(f.name.clone());
                    if let (Some(t), Some(old)) = (texts.get_mut(k), saved.get(k)) {
                        t.clone_from(old);
                    }
                }
                continue;
            }
            // At the same place, only what changed is written (a new place gets every file).
            let unchanged = saved.get(k) == Some(&f.text);
            let same_place = if k == 0 {
                self.path.as_ref() == Some(&path)
            } else {
                same_folder
            };
            if unchanged && same_place && target.exists() {
                continue;
            }
            if let Some(folder) = target.parent() {
                let _ = std::fs::create_dir_all(folder);
            }
            if let Err(e) = servoscope_core::atomic::write_atomically(&target, |w| {
                w.write_all(f.text.as_bytes())
            }) {
                self.file_failed(
                    files::Purpose::SaveProgram,
                    format!("Cannot write {}: {e}", target.display()),
                );
                return;
            }
            written.push(target.display().to_string());
        }
        self.debugger.rename(files::file_name(&path));
        self.path = Some(path.clone());
        self.file_text = Some(texts);
        self.remember(&path);
        self.files.save_program.close();
        let mut notice = match written.len() {
            0 => "No file changed since it was last saved".to_string(),
            1 => format!("Program saved to {}", written[0]),
            _ => format!("Program saved: {}", written.join(", ")),
        };
        if !outside.is_empty() {
            notice.push_str(&format!(
                ". Not written, being outside the program's folder: {} (open it on its own to save it)",
                outside.join(", ")
            ));
        }
        self.notice = Some(notice);
    }

    /// Save the session to `path` (atomically). Errors leave the old file and are reported; a
    /// file that is not a session is replaced only after the user confirms.
    pub fn save_session_to(&mut self, path: PathBuf) {
        self.save_session(path, false);
    }

    pub(super) fn save_session(&mut self, path: PathBuf, replace: bool) {
        // A session saved as "lesson" is "lesson.ron", so it opens as a session later; Recent
        // keeps where it really is, not a path relative to wherever servoscope started.
        let path = if path.extension().is_none() {
            path.with_extension("ron")
        } else {
            path
        };
        let path = std::path::absolute(&path).unwrap_or(path);
        // Never over the program's own files, whatever the user confirms.
        if let Some(top) = &self.path {
            let inputs = servoscope_core::output::program_inputs(top, self.debugger.project());
            let kind = servoscope_core::output::Output::Session;
            if let Err(e) = servoscope_core::output::may_write(&path, kind, &inputs, true) {
                self.confirm_replace = None;
                self.file_failed(
                    files::Purpose::SaveSession,
                    format!("{e}: choose another name"),
                );
                return;
            }
        }
        let session = self.session();
        let saved = if replace {
            session.save_over(&path)
        } else {
            session.save(&path)
        };
        if let Err(SessionError::WouldReplace { reason, .. }) = &saved {
            self.confirm_replace = Some((path, reason.clone()));
            return;
        }
        match saved {
            Ok(()) => {
                self.session_path = Some(path.clone());
                self.remember(&path);
                self.files.save.close();
                self.mark_saved();
                self.notice = Some(format!("Session saved to {}", path.display()));
                // Saved: whatever waited behind "unsaved changes" can go on.
                if let Some(action) = self.pending.take() {
                    self.perform(action);
                }
            }
            Err(e) => self.file_failed(files::Purpose::SaveSession, e.to_string()),
        }
    }

    /// Run `action` now, or ask first when there are unsaved changes.
    pub(super) fn guarded(&mut self, action: Pending) {
        if self.is_dirty() {
            self.pending = Some(action);
        } else {
            self.perform(action);
        }
    }

    pub(super) fn perform(&mut self, action: Pending) {
        match action {
            Pending::Open(path) => self.open_path(path),
            Pending::ExampleProject(i) => {
                if let Some((dialect, _, project)) = registry::example_projects().nth(i) {
                    self.set_lesson(None);
                    self.debugger.load_project(dialect, project);
                    self.file_text = Some(file_texts(&self.debugger));
                    self.path = None;
                    self.session_path = None;
                    self.fresh_views();
                    self.mark_saved();
                }
            }
            Pending::Example(i) => {
                if let Some((dialect, name, text)) = registry::examples().nth(i) {
                    self.load_program_as(dialect, name, text);
                }
            }
            Pending::Lesson(i) => {
                if let Some((_, name, text)) = registry::lessons().nth(i) {
                    self.open_lesson(name, text);
                }
            }
            Pending::New(name) => {
                if let Some(dialect) = registry::by_name(name) {
                    let file = format!("new.{}", dialect.extensions[0]);
                    self.load_program_as(dialect, &file, dialect.new_program);
                }
            }
            Pending::Quit => self.allow_close = true,
        }
    }
}

/// Each file's text, the top file first.
pub(super) fn file_texts(debugger: &Debugger) -> Vec<String> {
    debugger
        .project()
        .files
        .iter()
        .map(|f| f.text.clone())
        .collect()
}
