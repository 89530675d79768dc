//! The debugger window. Each panel draws from the [`Debugger`] and its own view settings and
//! returns what the user asked for as [`Command`]s; [`ServoscopeApp::apply`] carries them out.
//! No run logic lives here: it is all in `debugger` and `machine`.

mod apply;
pub mod bitrows;
pub mod breakpoints;
pub mod code;
pub mod code_rows;
mod command;
pub mod controls;
pub mod dialects;
mod file_actions;
pub mod files;
pub mod frames;
pub mod help;
pub mod include_folders;
pub mod layout;
pub mod lesson;
pub mod loading;
pub mod log;
pub mod panels;
pub mod plot;
mod prefs;
pub mod push_buttons;
pub mod registers;
pub mod settings;
mod show;
pub mod status;
pub mod theme;
pub mod timeline;
pub mod watches;
pub mod window_state;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

pub use command::Command;
pub use frames::{
    FramePacer, FrameStats, MAX_LEAD, MAX_RUN_SLICE, MIN_RUN_SLICE, TARGET_FRAME, run_slice,
};
use panels::DialectPanel;
use prefs::MAX_RECENT;
pub use prefs::{PREFS_KEY, Prefs};
use servoscope_core::debugger::{Action, Breakpoint, Debugger, Speed};
use servoscope_core::machine::{Format, Loc};
use servoscope_core::registry::{self, Dialect, Settings};
use servoscope_core::session::{Session, SessionError, ViewSettings, is_session_path};
pub use show::{dialog, form_menu_button};

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
    pub include_folders: include_folders::IncludeFoldersView,
    pub files: files::Files,
    /// The open lesson, if the session is one.
    pub lesson: Option<lesson::LessonView>,
    /// The lesson as last saved or loaded: differences are unsaved changes.
    saved_lesson: Option<servoscope_core::lesson::Lesson>,
    pub help: help::HelpView,
    pub layout: layout::Layout,
    /// The window's egui context, from the first frame on: a session saves the window's
    /// scroll positions from it.
    ctx: Option<egui::Context>,
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
        debugger.set_speed(prefs.speed_for(dialect.name));
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
            include_folders: include_folders::IncludeFoldersView::default(),
            files: files::Files::default(),
            lesson: None,
            saved_lesson: None,
            help: help::HelpView::default(),
            layout,
            ctx: None,
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

    pub(super) fn apply_view_settings(&mut self, view: &ViewSettings) {
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
    pub(super) fn sync_panels(&mut self) {
        let dialect = self.debugger.dialect();
        if self.panels_for != dialect.name {
            self.panels = dialects::panels(dialect);
            self.panels_for = dialect.name;
            self.registers.dialect = dialect.name;
            self.debugger.set_speed(self.prefs.speed_for(dialect.name));
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
            window: (self.ctx.as_ref()).map(|ctx| window_state::capture(ctx, &self.layout)),
            ..Session::capture(&self.debugger, self.path.clone(), self.view_settings())
        }
    }

    pub(super) fn mark_saved(&mut self) {
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
    pub(super) fn remember(&mut self, path: &Path) {
        let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        self.prefs.recent.retain(|p| *p != path);
        self.prefs.recent.insert(0, path);
        self.prefs.recent.truncate(MAX_RECENT);
    }

    pub(super) fn fresh_views(&mut self) {
        self.code.reset_view();
        self.plot.reset();
        self.registers.selected = None;
        self.registers.overrides.clear();
        self.notice = None;
        self.sync_panels();
        self.focus_panel_pending = true;
    }
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
/// and took it back on the next frame, zeroed page by page: page faults took a large share of
/// the window thread's time (docs/figures.md). 32 MiB is the most a quiet heap keeps.
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
