//! The debugger window. Each panel draws from the [`Debugger`] and its own view settings and
//! returns what the user asked for as [`Command`]s; [`ServoscopeApp::apply`] carries them out.
//! No run logic lives here: it is all in `debugger` and `machine`.

pub mod bitrows;
pub mod breakpoints;
pub mod code;
pub mod code_rows;
pub mod controls;
pub mod dialects;
pub mod files;
pub mod frames;
pub mod help;
pub mod layout;
pub mod lesson;
pub mod loading;
pub mod log;
pub mod panels;
pub mod plot;
pub mod registers;
pub mod settings;
pub mod status;
pub mod theme;
pub mod timeline;
pub mod watches;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

pub use frames::{
    FramePacer, FrameStats, MAX_LEAD, MAX_RUN_SLICE, MIN_RUN_SLICE, TARGET_FRAME, run_slice,
};
use panels::DialectPanel;
use servoscope_core::debugger::{Breakpoint, ChannelChoice, Debugger, Speed, Watch};
use servoscope_core::machine::Pos;
use servoscope_core::machine::{Format, Loc};
use servoscope_core::registry::{self, Dialect, Settings};
use servoscope_core::session::{Session, SessionError, ViewSettings, is_session_path};

/// What a user asked for, from a panel, the menu or a key.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// One instruction, into a call (F11).
    StepCommand,
    /// One instruction, over a call (F10).
    StepOver,
    /// Until the subroutine on hand returns (Shift+F11).
    StepOut,
    StepTick,
    Run,
    Pause,
    Reset,
    RunToLine(usize),
    ToggleBreakpoint(usize),
    Assemble,
    EditSource(String),
    /// Show each statement's program-memory address in the code view's gutter.
    ShowAddresses(bool),
    /// The text of file `.0` of the program (0 is the top file) was edited.
    EditFile(usize, String),
    SetSpeed(Speed),
    SetInput(Loc, bool),
    SetValue(Loc, u64),
    ToggleBit(Loc, u8),
    SetBit(Loc, u8, bool),
    SetChannels(Vec<ChannelChoice>),
    /// One instruction back, into a call that just returned (Ctrl+Shift+F10).
    StepBackCommand,
    /// One instruction back, over a call that just returned (Shift+F10).
    StepBackOver,
    /// Back to the CALL that entered the subroutine on hand (Ctrl+Shift+F11).
    StepBackOut,
    StepBackTick,
    ReverseContinue,
    GoToTick(u64),
    OpenDialog,
    /// Open a program or a session (asks first when there are unsaved changes).
    OpenPath(PathBuf),
    /// Ctrl+S: save to the current session file, or ask where.
    SaveSession,
    SaveSessionDialog,
    SaveSessionTo(PathBuf),
    /// Save the program text to its file, or ask where.
    SaveProgram,
    SaveProgramDialog,
    SaveProgramTo(PathBuf),
    /// Save over a file that is not a session, after the user confirmed.
    SaveSessionOver(PathBuf),
    /// Go on with the action waiting behind "unsaved changes".
    DiscardAndContinue,
    CancelPending,
    ExportDialog,
    ExportCsv(PathBuf),
    /// An example of any dialect, by its index in [`registry::examples`].
    LoadExample(usize),
    /// An example of several files, by its index in [`registry::example_projects`].
    LoadExampleProject(usize),
    /// A lesson session of any dialect, by its index in [`registry::lessons`].
    LoadLesson(usize),
    /// File -> New: an empty program in the dialect with this name.
    NewProgram(&'static str),
    SetDark(bool),
    OpenSettings,
    SetSettings(Settings),
    /// Stop a run when the machine's error lamp turns on.
    SetBreakOnError(bool),
    /// Close (false) or reopen (true) a panel.
    ShowPane(layout::Pane, bool),
    ResetLayout,
    AddBreakpoint(Breakpoint),
    UpdateBreakpoint(usize, Breakpoint),
    RemoveBreakpoint(usize),
    /// Go back to the write of this location (again: the write before).
    WhoWrote(Loc),
    AddWatch(String),
    UpdateWatch(usize, Watch),
    RemoveWatch(usize),
    PlotWatch(usize),
    /// Go to a position of the recorded run (a log entry).
    GoTo(Pos),
    /// Scroll the program to a line and put the caret there.
    ShowLine(usize),
    ExportLogDialog,
    ExportLog(PathBuf),
    /// Force a bit ON/OFF (Some) or release it (None).
    Force(Loc, Option<bool>),
    ReleaseAllForces,
    /// Show a location in the register view.
    SelectLocation(Loc),
    /// Bring a panel's tab to the front.
    FocusPane(layout::Pane),
    ExportLadderDialog,
    ExportLadder(PathBuf),
    /// F1 / Help → Reference: the Help panel at this mnemonic's entry (the whole reference
    /// without one).
    OpenHelp(Option<String>),
    /// Show this step of the open lesson (from 0).
    LessonStep(usize),
    /// Evaluate the shown step's checks on the present state.
    LessonCheck,
    /// Back to the lesson's program and position.
    LessonReset,
    /// File → Save as lesson: this session becomes a lesson to write, then to save.
    SaveAsLesson,
}

/// Preferences kept between runs by eframe's storage (never the program state).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    pub dark: bool,
    pub recent: Vec<PathBuf>,
    pub speed: Speed,
    /// The register view's format per dialect, where the user chose one for every location.
    pub register_formats: BTreeMap<String, Format>,
    pub only_used_registers: bool,
    /// The panel layout as the user left it; `None` for the default.
    #[serde(with = "layout::as_text")]
    pub layout: Option<layout::Layout>,
    /// The titles of the panels the build had when `layout` was saved: a panel added since
    /// then joins a saved layout once, while one the user closed stays closed. Plain text, so
    /// a damaged entry costs nothing.
    #[serde(default = "layout::panes_before_debugger_panels")]
    pub known_panes: Vec<String>,
}

impl Default for Prefs {
    fn default() -> Self {
        Prefs {
            dark: true,
            recent: Vec::new(),
            speed: Speed::PerSecond(10.0),
            register_formats: BTreeMap::new(),
            only_used_registers: true,
            layout: None,
            known_panes: layout::Pane::common_titles(),
        }
    }
}

pub const PREFS_KEY: &str = "servoscope-prefs";
const MAX_RECENT: usize = 10;

/// Something that would replace the current session, waiting for the user to confirm that
/// unsaved changes may go.
#[derive(Clone, Debug, PartialEq)]
pub enum Pending {
    Open(PathBuf),
    Example(usize),
    /// An example of several files, by its index in [`registry::example_projects`].
    ExampleProject(usize),
    Lesson(usize),
    New(&'static str),
    Quit,
}

pub struct ServoscopeApp {
    pub debugger: Debugger,
    pub frame_stats: Option<FrameStats>,
    /// The program file, if the program came from one.
    pub path: Option<PathBuf>,
    /// The session file this state was loaded from or saved to.
    pub session_path: Option<PathBuf>,
    /// The session as last saved or loaded: differences are unsaved changes.
    saved: Session,
    saved_program: String,
    /// The text the program file holds (as loaded or last saved), when there is a file.
    /// Each file's text as opened or last saved as a program (the top file first).
    file_text: Option<Vec<String>>,
    pub prefs: Prefs,
    pub code: code::CodeView,
    pub registers: registers::RegisterView,
    pub plot: plot::PlotView,
    pub timeline: timeline::TimelineView,
    pub breakpoints: breakpoints::BreakpointsView,
    pub watches: watches::WatchesView,
    pub log: log::LogView,
    pub settings: settings::SettingsView,
    pub files: files::Files,
    /// The open lesson, if the session is one.
    pub lesson: Option<lesson::LessonView>,
    /// The lesson as last saved or loaded: differences are unsaved changes.
    saved_lesson: Option<servoscope_core::lesson::Lesson>,
    pub help: help::HelpView,
    pub layout: layout::Layout,
    /// The current dialect's own panels, and the dialect they were made for.
    panels: Vec<Box<dyn DialectPanel>>,
    /// A program was just opened: bring its best panel to the front next frame.
    focus_panel_pending: bool,
    panels_for: &'static str,
    /// Inputs of a large input space the user asked to see as switches.
    pub extra_inputs: Vec<Loc>,
    pub new_input: String,
    /// An action waiting for "discard unsaved changes?".
    pub pending: Option<Pending>,
    /// A session opening in the background.
    pub loading: Option<loading::Loading>,
    /// A save waiting for "replace this file that is not a session?".
    pub confirm_replace: Option<(PathBuf, String)>,
    allow_close: bool,
    /// A message for the user that is not a program diagnostic (a file that could not be read).
    pub notice: Option<String>,
    title: String,
    last_frame: Option<Instant>,
    /// When to ask for the next frame while running unlimited.
    pacer: FramePacer,
    /// Smoothed frame time not spent simulating (drawing, presenting, waiting).
    overhead: Duration,
    last_slice: Duration,
    theme_applied: Option<bool>,
    fonts_installed: bool,
}

impl ServoscopeApp {
    /// The app on the first built-in example.
    pub fn new(prefs: Prefs) -> Self {
        let dialect = registry::default_dialect();
        let (name, text) = dialect
            .examples
            .first()
            .copied()
            .unwrap_or(("new", dialect.new_program));
        let mut debugger = Debugger::with_dialect(dialect, name, text);
        debugger.set_speed(prefs.speed);
        // Leftovers of saves killed last time, in the folders the user works in.
        for folder in prefs.recent.iter().filter_map(|p| p.parent()) {
            servoscope_core::atomic::remove_stale_temporaries(folder);
        }
        let registers = registers::RegisterView::new(&prefs);
        let panels = dialects::panels(dialect);
        let titles: Vec<&str> = panels.iter().map(|p| p.title()).collect();
        let mut layout = prefs
            .layout
            .clone()
            .and_then(layout::Layout::checked)
            .unwrap_or_else(|| layout::Layout::standard(&titles));
        layout.sync_dialect_panels(&titles);
        for pane in layout::Pane::COMMON {
            if !prefs.known_panes.iter().any(|t| t == pane.title()) {
                layout.add_beside(pane, &layout::Pane::Bits);
            }
        }
        let mut app = ServoscopeApp {
            debugger,
            path: None,
            session_path: None,
            saved: Session::default(),
            saved_program: String::new(),
            file_text: None,
            prefs,
            code: code::CodeView::default(),
            registers,
            plot: plot::PlotView::default(),
            timeline: timeline::TimelineView::default(),
            breakpoints: breakpoints::BreakpointsView::default(),
            watches: watches::WatchesView::default(),
            log: log::LogView::default(),
            settings: settings::SettingsView::default(),
            files: files::Files::default(),
            lesson: None,
            saved_lesson: None,
            help: help::HelpView::default(),
            layout,
            panels,
            focus_panel_pending: true,
            panels_for: dialect.name,
            extra_inputs: Vec::new(),
            new_input: String::new(),
            pending: None,
            confirm_replace: None,
            loading: None,
            allow_close: false,
            notice: None,
            frame_stats: None,
            title: String::new(),
            last_frame: None,
            pacer: FramePacer::default(),
            overhead: Duration::from_millis(8),
            last_slice: Duration::ZERO,
            theme_applied: None,
            fonts_installed: false,
        };
        app.mark_saved();
        app
    }

    /// The app on a program or session file; if it cannot be read, on the built-in example
    /// with a notice. `dialect` overrides the program's extension.
    pub fn with_file(prefs: Prefs, path: PathBuf, dialect: Option<&str>) -> Self {
        let mut app = ServoscopeApp::new(prefs);
        app.open_path_as(path, dialect.and_then(registry::by_name));
        app
    }

    /// The view settings a session keeps.
    pub fn view_settings(&self) -> ViewSettings {
        let m = self.debugger.machine();
        let name = |loc: Loc| m.info(loc).map(|i| i.name);
        ViewSettings {
            formats: self
                .registers
                .overrides
                .iter()
                .filter_map(|(&loc, &f)| Some((name(loc)?, f)))
                .collect(),
            only_used_registers: self.registers.only_used,
            selected: self.registers.selected.and_then(name),
            speed: self.debugger.speed(),
            ..ViewSettings::default()
        }
        .with_column(self.registers.column())
    }

    fn apply_view_settings(&mut self, view: &ViewSettings) {
        let m = self.debugger.machine();
        self.registers.dialect = self.debugger.dialect().name;
        self.registers.set_column(view.column());
        self.registers.overrides = view
            .formats
            .iter()
            .filter_map(|(n, f)| Some((m.find(n)?, *f)))
            .collect();
        self.registers.only_used = view.only_used_registers;
        self.registers.selected = view.selected.as_deref().and_then(|n| m.find(n));
        self.debugger.set_speed(view.speed);
    }

    /// The titles of the current dialect's own panels.
    pub fn panel_titles(&self) -> Vec<&'static str> {
        self.panels.iter().map(|p| p.title()).collect()
    }

    /// Make the dialect panels match the debugger's dialect.
    fn sync_panels(&mut self) {
        let dialect = self.debugger.dialect();
        if self.panels_for != dialect.name {
            self.panels = dialects::panels(dialect);
            self.panels_for = dialect.name;
            self.registers.dialect = dialect.name;
            let titles: Vec<&str> = self.panels.iter().map(|p| p.title()).collect();
            self.layout.sync_dialect_panels(&titles);
            self.extra_inputs.clear();
            self.settings = settings::SettingsView::default();
        }
    }

    /// The current debugging moment as a session.
    pub fn session(&self) -> Session {
        Session {
            lesson: self.lesson.as_ref().map(|l| l.lesson.clone()),
            ..Session::capture(&self.debugger, self.path.clone(), self.view_settings())
        }
    }

    fn mark_saved(&mut self) {
        self.saved = Session::capture_without_program(
            &self.debugger,
            self.path.clone(),
            self.view_settings(),
        );
        self.saved_program = self.debugger.source().to_string();
        self.saved_lesson = self.lesson.as_ref().map(|l| l.lesson.clone());
    }

    /// Changes since the session was last saved or loaded (edits, breakpoints, the tick, ...).
    /// Asked every frame (the title's ●): compares without copying the program text.
    pub fn is_dirty(&self) -> bool {
        // The session holds the text as typed, assembled or not: compare that.
        self.debugger.source() != self.saved_program
            || self.lesson.as_ref().map(|l| &l.lesson) != self.saved_lesson.as_ref()
            || Session::capture_without_program(
                &self.debugger,
                self.path.clone(),
                self.view_settings(),
            ) != self.saved
    }

    pub fn window_title(&self) -> String {
        let dirty = if self.is_dirty() { " ●" } else { "" };
        let session = self
            .session_path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| format!(" [{}]", n.to_string_lossy()))
            .unwrap_or_default();
        let star = if self.program_modified() { "*" } else { "" };
        format!(
            "servoscope — {}{star}{session}{dirty}",
            self.debugger.name()
        )
    }

    /// Put `path` first in File → Open recent, as an absolute path: a relative one would name
    /// another file once servoscope starts in another folder.
    fn remember(&mut self, path: &Path) {
        let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        self.prefs.recent.retain(|p| *p != path);
        self.prefs.recent.insert(0, path);
        self.prefs.recent.truncate(MAX_RECENT);
    }

    fn fresh_views(&mut self) {
        self.code.reset_view();
        self.plot.reset();
        self.registers.selected = None;
        self.registers.overrides.clear();
        self.notice = None;
        self.sync_panels();
        self.focus_panel_pending = true;
    }

    /// Open a program (dialect by extension) or a session (`.ron`). On failure the current
    /// session stays and the user is told why.
    pub fn open_path(&mut self, path: PathBuf) {
        self.open_path_as(path, None);
    }

    fn open_path_as(&mut self, path: PathBuf, dialect: Option<&'static Dialect>) {
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

    fn opened(&mut self, path: &Path) {
        self.remember(path);
        self.files.open.close();
        self.mark_saved();
    }

    fn open_failed(&mut self, message: String) {
        self.file_failed(files::Purpose::OpenProgram, message);
    }

    /// A file could not be opened or written: said in its dialog and in the notice banner.
    /// File → Export ladder…: the diagram at the current position, as SVG.
    fn export_ladder(&mut self, path: &std::path::Path) {
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

    fn file_failed(&mut self, purpose: files::Purpose, message: String) {
        self.files.request(purpose).error = Some(message.clone());
        self.notice = Some(message);
    }

    /// Finish (or give up) a background open.
    fn poll_loading(&mut self, ctx: &egui::Context) {
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

    fn open_program(
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
            .load(path)
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
    fn open_session(&mut self, path: &Path) -> Result<bool, String> {
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
    fn open_lesson(&mut self, name: &str, text: &str) {
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

    fn install_session(&mut self, path: &Path, session: &Session, debugger: Debugger) {
        let changed = session.changed_on_disk();
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
    fn set_lesson(&mut self, lesson: Option<lesson::LessonView>) {
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
        } else if self.layout.contains(&layout::Pane::Lesson) {
            self.layout.set_shown(&layout::Pane::Lesson, false);
        }
    }

    /// Reset lesson: the lesson's program, position and edits as it opened, its steps kept as
    /// they are now (a teacher's edits are not thrown away), at the step shown.
    fn reset_lesson(&mut self) {
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
        for (k, f) in self.debugger.project().files.iter().enumerate() {
            let target = if k == 0 {
                path.clone()
            } else {
                dir.join(&f.name)
            };
            // Never written outside the top file's folder: a session file names the files, and
            // a crafted one must not make Save program overwrite anything elsewhere. Such a
            // file stays unsaved.
            let escapes = Path::new(&f.name).is_absolute()
                || Path::new(&f.name)
                    .components()
                    .any(|c| matches!(c, std::path::Component::ParentDir));
            if k > 0 && escapes {
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

    fn save_session(&mut self, path: PathBuf, replace: bool) {
        // A session saved as "lesson" is "lesson.ron", so it opens as a session later; Recent
        // keeps where it really is, not a path relative to wherever servoscope started.
        let path = if path.extension().is_none() {
            path.with_extension("ron")
        } else {
            path
        };
        let path = std::path::absolute(&path).unwrap_or(path);
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
    fn guarded(&mut self, action: Pending) {
        if self.is_dirty() {
            self.pending = Some(action);
        } else {
            self.perform(action);
        }
    }

    fn perform(&mut self, action: Pending) {
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

    pub fn apply(&mut self, ctx: &egui::Context, command: Command) {
        let d = &mut self.debugger;
        match command {
            Command::StepCommand => d.step_command(),
            Command::StepOver => d.step_over(),
            Command::StepOut => d.step_out(),
            Command::StepTick => d.step_tick(),
            Command::StepBackCommand => d.step_back_command(),
            Command::StepBackOver => d.step_back_over(),
            Command::StepBackOut => d.step_back_out(),
            Command::StepBackTick => d.step_back_tick(),
            Command::ReverseContinue => d.reverse_continue(),
            Command::GoToTick(tick) => d.goto_tick(tick),
            Command::Run => d.run(),
            Command::Pause => d.pause(),
            Command::Reset => d.reset(),
            Command::RunToLine(line) => d.run_to_line(line),
            Command::ToggleBreakpoint(line) => {
                d.toggle_breakpoint(line);
            }
            Command::Assemble => {
                d.assemble();
            }
            Command::EditSource(text) => *d.source_mut() = text,
            Command::EditFile(file, text) => {
                *d.file_text_mut(file) = text;
                // An `#include` typed in: its file is read from beside the top file.
                if let Some(dir) = self.path.as_ref().and_then(|p| p.parent()) {
                    d.add_new_includes(dir);
                }
            }
            Command::ShowAddresses(shown) => self.code.addresses = shown,
            Command::SetSpeed(speed) => {
                d.set_speed(speed);
                self.prefs.speed = speed;
            }
            Command::SetInput(loc, high) => {
                let result = d.set_input(loc, high);
                self.report(result);
            }
            Command::SetValue(loc, v) => {
                let result = d.set_value(loc, v);
                self.report(result);
            }
            Command::ToggleBit(loc, bit) => {
                let result = d.toggle_bit(loc, bit);
                self.report(result);
            }
            Command::SetBit(loc, bit, on) => {
                let result = d.set_bit(loc, bit, on);
                self.report(result);
            }
            Command::SetChannels(channels) => {
                d.set_channels(channels);
                self.plot.reset();
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
            Command::SetBreakOnError(on) => self.debugger.set_break_on_error(on),
            Command::ResetLayout => {
                let titles: Vec<&str> = self.panels.iter().map(|p| p.title()).collect();
                self.layout = layout::Layout::standard(&titles);
            }
            Command::AddBreakpoint(b) => {
                self.debugger.add_breakpoint(b);
                self.layout.set_shown(&layout::Pane::Breakpoints, true);
                self.layout.focus(&layout::Pane::Breakpoints);
            }
            Command::UpdateBreakpoint(i, b) => self.debugger.update_breakpoint(i, b),
            Command::RemoveBreakpoint(i) => self.debugger.remove_breakpoint(i),
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
            Command::UpdateWatch(i, w) => self.debugger.update_watch(i, w),
            Command::RemoveWatch(i) => self.debugger.remove_watch(i),
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
            Command::GoTo(pos) => self.debugger.goto(pos),
            Command::ShowLine(line) => self.code.show_line(line),
            Command::Force(loc, level) => {
                let result = self.debugger.force(loc, level);
                self.report(result);
            }
            Command::ReleaseAllForces => {
                let result = self.debugger.release_all_forces();
                self.report(result);
            }
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
                        },
                        Some(start),
                    );
                    view.editing = true;
                    self.set_lesson(Some(view));
                }
                self.files.save.start(ctx);
            }
            Command::ExportLogDialog => self.files.export_log.start(ctx),
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
            Command::SetSettings(settings) => {
                self.debugger.set_settings(&settings);
                self.settings.draft = None;
            }
        }
    }

    /// A refused edit is said in the notice banner; nothing changed.
    fn report(&mut self, result: Result<(), servoscope_core::debugger::EditError>) {
        if let Err(e) = result {
            self.notice = Some(format!("Not changed: {e}"));
        }
    }

    /// One frame: keys, the run slice, then every panel. Usable without eframe (tests).
    pub fn show(&mut self, ui: &mut egui::Ui) {
        if !self.fonts_installed {
            // Fonts change from the next pass on: this one is thrown away unseen.
            theme::install_fonts(ui.ctx());
            self.fonts_installed = true;
            ui.ctx().request_discard("the fonts were installed");
            ui.ctx().request_repaint();
            return;
        }
        let ctx = ui.ctx().clone();
        // Which files differ from what was opened or saved: their tabs carry a •.
        let saved = self.file_text.as_deref().unwrap_or_default();
        self.code.unsaved = self
            .debugger
            .project()
            .files
            .iter()
            .enumerate()
            .map(|(k, f)| saved.get(k) != Some(&f.text))
            .collect();
        if self.theme_applied != Some(self.prefs.dark) {
            theme::apply(&ctx, self.prefs.dark);
            self.theme_applied = Some(self.prefs.dark);
        }

        // Closing with unsaved changes asks first.
        if ctx.input(|i| i.viewport().close_requested()) && !self.allow_close && self.is_dirty() {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.pending = Some(Pending::Quit);
        }
        if self.allow_close && self.pending.is_none() && self.frame_stats.is_none() {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }

        self.poll_loading(&ctx);
        let mut commands = Vec::new();
        // Keys are taken now (before a widget sees them) but acted on at the end of the frame,
        // after the editor's text of this same frame: Ctrl+Enter right after a keystroke
        // assembles the text on screen.
        let mut keyed = Vec::new();
        controls::shortcuts(&ctx, &self.debugger, &self.code, &mut keyed);
        files::dropped_files(&ctx, &mut commands);
        self.files.poll(&mut commands);
        if self.loading.is_some() {
            commands.clear();
        }
        for c in commands.drain(..) {
            self.apply(&ctx, c);
        }

        let now = Instant::now();
        let interval = self.last_frame.map(|t| now.duration_since(t));
        self.last_frame = Some(now);
        if let Some(interval) = interval
            && self.debugger.is_running()
        {
            let overhead = interval.saturating_sub(self.last_slice);
            self.overhead = (self.overhead * 7 + overhead) / 8;
        }
        let slice = run_slice(self.overhead);
        let dt = interval.map_or(0.0, |d| d.as_secs_f64());
        let sim_start = Instant::now();
        self.debugger.advance(dt, slice);
        self.last_slice = sim_start.elapsed();

        // The window is cleared to the panels' colour (`clear_color`), so the panels paint no
        // fill: without a GPU every filled pixel is shaded in software, and the central panel's
        // fill alone was more than all the rest of a frame's drawing together.
        let bar = egui::Frame::side_top_panel(ui.style()).fill(egui::Color32::TRANSPARENT);
        let central = egui::Frame::central_panel(ui.style()).fill(egui::Color32::TRANSPARENT);
        egui::Panel::top("menu").frame(bar).show(ui, |ui| {
            controls::menu_bar(ui, self, &mut commands);
            controls::toolbar(
                ui,
                &self.debugger,
                &mut self.extra_inputs,
                &mut self.new_input,
                &mut commands,
            );
        });
        egui::Panel::bottom("status_bar").frame(bar).show(ui, |ui| {
            status::status_bar(ui, &self.debugger);
        });
        egui::CentralPanel::default().frame(central).show(ui, |ui| {
            if let Some(notice) = self.notice.clone()
                && status::notice_banner(ui, &notice)
            {
                self.notice = None;
            }
            status::fault_banner(ui, &self.debugger);
            for panel in &self.panels {
                let pane = layout::Pane::Dialect(panel.title().to_string());
                self.layout
                    .show_when(&pane, panel.has_content(&self.debugger));
            }
            // A program just opened: bring forward the panel that suits it best (the last
            // registered that asks).
            // An open lesson keeps its tab in front: it is what the student reads first.
            if std::mem::take(&mut self.focus_panel_pending)
                && self.lesson.is_none()
                && let Some(panel) = self
                    .panels
                    .iter()
                    .rev()
                    .find(|p| p.wants_focus(&self.debugger))
            {
                self.layout
                    .focus(&layout::Pane::Dialect(panel.title().to_string()));
            }
            if self.layout.is_shown(&layout::Pane::Log) {
                self.log.refresh(&mut self.debugger);
            }
            self.layout.fit_timeline(timeline::height(ui.style()));
            let current_places = self.layout.current_places();
            let mut panes = layout::Panes {
                debugger: &self.debugger,
                code: &mut self.code,
                registers: &mut self.registers,
                plot: &mut self.plot,
                timeline: &mut self.timeline,
                breakpoints: &mut self.breakpoints,
                watches: &mut self.watches,
                log: &mut self.log,
                lesson: self.lesson.as_mut(),
                help: &mut self.help,
                dialect_panels: &mut self.panels,
                out: &mut commands,
                places: &mut self.layout.places,
                current_places: &current_places,
            };
            self.layout.tree.ui(&mut panes, ui);
        });
        self.files.windows(&ctx, &self.prefs, &mut commands);
        settings::window(&ctx, &self.debugger, &mut self.settings, &mut commands);
        if self.pending.is_some() {
            unsaved_prompt(&ctx, self.pending.as_ref(), &mut commands);
        }
        if let Some((path, reason)) = &self.confirm_replace
            && let Some(answer) = replace_prompt(&ctx, path, reason)
        {
            if answer {
                commands.push(Command::SaveSessionOver(path.clone()));
            } else {
                self.confirm_replace = None;
            }
        }

        if self.loading.is_some() {
            // The session being opened replaces this one: nothing more happens to it meanwhile.
            commands.clear();
            keyed.clear();
        }
        if !keyed.is_empty() {
            // The frame drew the state before the keys: the next one shows what they did.
            ctx.request_repaint();
        }
        for c in commands.into_iter().chain(keyed) {
            self.apply(&ctx, c);
        }
        self.prefs
            .register_formats
            .clone_from(&self.registers.every);
        self.prefs.only_used_registers = self.registers.only_used;

        let title = self.window_title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        let paced = self.debugger.is_running()
            && self.debugger.speed() == servoscope_core::debugger::Speed::Unlimited;
        if (self.debugger.is_running() && !paced) || self.files.is_waiting() {
            ctx.request_repaint();
        }
    }
}

/// A menu button whose popup holds fields (a text field, a combo box): it stays open while the
/// user clicks inside it, and closes on a click outside, Escape or its button (a plain menu
/// closes on any click, so its fields could not be used).
pub fn form_menu_button<R>(
    ui: &mut egui::Ui,
    title: &str,
    content: impl FnOnce(&mut egui::Ui) -> R,
) -> egui::Response {
    egui::containers::menu::MenuButton::new(title)
        .config(
            egui::containers::menu::MenuConfig::new()
                .close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside),
        )
        .ui(ui, content)
        .0
}

/// A small dialog in the middle of the window.
pub fn dialog(title: &str) -> egui::Window<'static> {
    egui::Window::new(title)
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
}

/// "Replace a file that is not a session?": true to replace, false to cancel, None meanwhile.
fn replace_prompt(ctx: &egui::Context, path: &Path, reason: &str) -> Option<bool> {
    let mut answer = None;
    dialog("Replace file?").show(ctx, |ui| {
        ui.label(format!(
            "{} exists and is not a servoscope session ({reason}). Saving replaces it.",
            path.display()
        ));
        ui.horizontal(|ui| {
            if ui.button("Replace it").clicked() {
                answer = Some(true);
            }
            if ui.button("Keep it").clicked() {
                answer = Some(false);
            }
        });
    });
    answer
}

/// "Unsaved changes": save the session first, discard the changes, or cancel.
fn unsaved_prompt(ctx: &egui::Context, pending: Option<&Pending>, out: &mut Vec<Command>) {
    let what = match pending {
        Some(Pending::Open(path)) => format!("opening {}", path.display()),
        Some(Pending::Example(_) | Pending::ExampleProject(_)) => "opening the example".to_string(),
        Some(Pending::Lesson(_)) => "opening the lesson".to_string(),
        Some(Pending::New(_)) => "starting a new program".to_string(),
        Some(Pending::Quit) | None => "closing servoscope".to_string(),
    };
    dialog("Unsaved changes").show(ctx, |ui| {
        ui.label(format!(
            "This debugging session has changes that are not saved. They are lost by {what}."
        ));
        ui.horizontal(|ui| {
            if ui.button("Save session").clicked() {
                out.push(Command::SaveSession);
            }
            if ui.button("Discard changes").clicked() {
                out.push(Command::DiscardAndContinue);
            }
            if ui.button("Cancel").clicked() {
                out.push(Command::CancelPending);
            }
        });
    });
}

impl ServoscopeApp {
    /// A frame of the window: [`ServoscopeApp::show`], then the run in progress goes to the
    /// worker thread until the next frame, asked for so that frames come a frame's time apart
    /// ([`FramePacer`]).
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let started = Instant::now();
        self.show(ui);
        self.record_frame_stats(ui.ctx(), started);
        self.debugger.hand_off();
        if self.debugger.is_running()
            && self.debugger.speed() == servoscope_core::debugger::Speed::Unlimited
        {
            let wait = self.pacer.wait(started, Instant::now());
            ui.ctx().request_repaint_after(wait);
        }
    }

    fn record_frame_stats(&mut self, ctx: &egui::Context, started: Instant) {
        if let Some(stats) = &mut self.frame_stats {
            let m = self.debugger.machine();
            if let Some(report) = stats.record(started, Instant::now(), m.ticks(), m.tick_micros())
            {
                eprintln!("{report}");
                // A measurement run is not work to keep: close without "unsaved changes".
                self.allow_close = true;
                self.pending = None;
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                self.frame_stats = None;
            } else if !self.debugger.is_running() {
                // A program that ended still counts its frames to the last.
                ctx.request_repaint();
            }
        }
    }
}

/// Each file's text, the top file first.
fn file_texts(debugger: &Debugger) -> Vec<String> {
    debugger
        .project()
        .files
        .iter()
        .map(|f| f.text.clone())
        .collect()
}

impl eframe::App for ServoscopeApp {
    /// The panels' own colour, so that they need not fill themselves (see `frame`).
    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        visuals.panel_fill.to_normalized_gamma_f32()
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        self.prefs.layout = Some(self.layout.clone());
        self.prefs.known_panes = layout::Pane::common_titles();
        eframe::set_value(storage, PREFS_KEY, &self.prefs);
    }
}

/// Keep freed memory at the top of the heap instead of giving it back to the system at once.
/// Without a GPU, Mesa allocates a vertex and an index buffer for each mesh of every frame and
/// frees them at the next; glibc returned that memory each time (its trim threshold is 128 KiB)
/// and took it back on the next frame, zeroed page by page: about 850 page faults a frame, a
/// quarter of the window thread's time (`perf stat -e page-faults --per-thread` on
/// `servoscope --frame-stats 100000 benches/common/idiom.qsl` under Xvfb: 18 000–54 000 faults/s
/// before, none after; the window thread 256–353 → 202–244 ms of CPU a second). 32 MiB is the
/// most a quiet heap keeps.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_heap() {
    // SAFETY: mallopt changes a parameter of the allocator and is safe to call at any time.
    unsafe {
        libc::mallopt(libc::M_TRIM_THRESHOLD, 32 << 20);
    }
}

/// Start the window. `file`: a program to open instead of the built-in example, in `dialect`
/// when given. `frame_stats`: run it unlimited and report frame times over that many frames,
/// then close.
pub fn run_gui(
    file: Option<PathBuf>,
    dialect: Option<String>,
    frame_stats: Option<usize>,
) -> eframe::Result {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    keep_freed_heap();
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("servoscope")
            .with_inner_size([1280.0, 800.0])
            .with_min_inner_size([800.0, 500.0])
            .with_drag_and_drop(true),
        // Dithering hides banding in gradients, of which the window has none; without a GPU it
        // is shader work on every pixel of every frame.
        dithering: false,
        ..Default::default()
    };
    eframe::run_native(
        "servoscope",
        options,
        Box::new(move |cc| {
            // egui keeps scroll animations in its saved memory with times of the last session;
            // reloaded, one mid-flight never ends (the clock starts again at 0) and asks for a
            // frame at once, every frame, for as long as the app runs. Scroll positions are
            // not worth keeping.
            cc.egui_ctx
                .memory_mut(|m| m.data.remove_by_type::<egui::scroll_area::State>());
            let prefs: Prefs = cc
                .storage
                .and_then(|s| eframe::get_value(s, PREFS_KEY))
                .unwrap_or_default();
            let mut app = match file {
                Some(path) => ServoscopeApp::with_file(prefs, path, dialect.as_deref()),
                None => ServoscopeApp::new(prefs),
            };
            if let Some(frames) = frame_stats {
                app.frame_stats = Some(FrameStats::new(frames));
                app.debugger.set_speed(Speed::Unlimited);
                app.debugger.run();
            }
            Ok(Box::new(app))
        }),
    )
}
