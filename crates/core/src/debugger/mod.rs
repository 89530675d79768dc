//! Run control over a machine of any dialect: the program text and its assembly, breakpoints,
//! stepping forward and back, running at a chosen speed in bounded slices, pausing, resetting,
//! going to any position, and user edits that become part of the replayable timeline.
//!
//! The debugger holds the machine behind [`Engine`] (dynamic dispatch once per action or frame
//! slice); the loops inside run on the concrete machine type.
//!
//! No egui here: everything the GUI can do is a method a unit test can call. The GUI calls
//! [`Debugger::advance`] once per frame with a time budget, so a run never blocks a frame; a run
//! at unlimited speed goes on between frames on a worker thread ([`Debugger::hand_off`]).

pub mod action;
mod breakpoint_list;
pub mod breakpoints;
mod channels;
pub mod dialect;
mod edits;
pub mod engine;
pub mod expr;
pub mod history;
mod lines;
pub mod log;
mod program;
mod run;
#[cfg(test)]
mod tests;
pub mod trace;
mod watch;
mod worker;

use std::cell::RefCell;
use std::collections::BTreeSet;

pub use action::Action;
pub use breakpoints::{BreakError, BreakKind, Breakpoint, DataTrigger, LogMessage};
pub use channels::ChannelChoice;
pub use edits::EditError;
pub use engine::{Engine, StopWhen, engine};
pub use lines::remap_lines;
pub use run::{BACK_TICKS_AT_ONCE, Event, Goal, Speed};
pub use watch::Watch;

use crate::machine::project::{Project, SourceFile};
pub use dialect::{Dialect, OpenResult};

use crate::machine::dialect::Settings;
use crate::machine::{Diagnostic, Loc, MachineView, Pos, StopReason};
use breakpoints::Checker;
use history::{Change, Mark, MarkKind, UserEvent};
use trace::{Channel, Trace};

/// Ticks run between two looks at the clock while running unlimited, at most. A run's first
/// chunk is [`FIRST_CHUNK_TICKS`] and each next one doubles while a chunk fits in the frame's
/// budget: a scan of a large PLC program can cost 100 µs, so 20,000 of them before the first
/// look would freeze the window for seconds.
pub(crate) const CHUNK_TICKS: u64 = 20_000;
pub const FIRST_CHUNK_TICKS: u64 = 16;
/// Ticks a single step may take before it continues over later frames (a long DLY or move).
pub(crate) const STEP_TICKS_AT_ONCE: u64 = 16_384;
/// Ticks replayed between two progress reports when a session loads.
pub const REPLAY_SLICE: u64 = 1 << 20;

pub struct Debugger {
    dialect: &'static Dialect,
    name: String,
    /// The program's files, the top file first (one for most programs).
    project: Project,
    /// The files the current program was assembled from.
    assembled: Project,
    diagnostics: Vec<Diagnostic>,
    settings: Settings,
    engine: Box<dyn Engine>,
    /// The plot channels by location name (resolved against each assembled program).
    channel_names: Vec<ChannelChoice>,
    breaks: Vec<Breakpoint>,
    /// `breaks` compiled against the current program, with hit counts and the log.
    checker: RefCell<Checker>,
    watches: Vec<Watch>,
    /// Counts new timelines (restart, assembly, another program): views that cache what they
    /// computed from the history compare it.
    generation: u64,
    /// The last "who wrote this?" answer: asking again at it goes further back.
    last_writer: Option<(Loc, Pos)>,
    goal: Option<Goal>,
    /// Skip the breakpoint on the current line once (resuming from it).
    resume_past_breakpoint: bool,
    /// Stop a run when the machine's error lamp turns on (OpenNet's M8004).
    break_on_error: bool,
    lamp_was_on: bool,
    speed: Speed,
    /// Commands owed at slow speeds (fractions carry over between frames).
    credit: f64,
    event: Option<Event>,
    /// The simulation thread, started by the first [`Debugger::hand_off`].
    worker: Option<worker::Worker>,
    /// The run is with the worker; `engine` is then the stand-in.
    lent: bool,
    /// What stands in for the engine while the worker has it (kept to be used again).
    spare: Option<Box<dyn Engine>>,
    rate: run::RateMeter,
    /// Ticks of the next chunk a frame runs (see [`CHUNK_TICKS`]), and the shortest time a
    /// chunk of this run took.
    chunk_ticks: u64,
    chunk_floor: Option<std::time::Duration>,
    /// The search back in progress while the goal is [`Goal::Back`].
    back: Option<run::Back>,
    /// Edits every new timeline starts with (a lesson's inputs), by location name, so a
    /// student's edited and re-assembled program meets the same inputs as the lesson's.
    scripted: Vec<ScriptedEvent>,
}

/// An edit at a position, by location name, that every restart applies again (a lesson's input
/// switched on at scan 10). A name the program does not have is skipped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScriptedEvent {
    pub at: Pos,
    pub location: String,
    pub change: Change,
}

/// `project` with every file's line endings and byte-order mark normalized.
fn normalized(mut project: Project) -> Project {
    for f in &mut project.files {
        if let std::borrow::Cow::Owned(text) = crate::text::normalize(&f.text) {
            f.text = text;
        }
    }
    project
}

/// A number no other timeline of this process has had.
fn next_generation() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// An empty program of `dialect`, for the moments before anything assembles.
fn empty_engine(dialect: &Dialect, settings: &Settings) -> Box<dyn Engine> {
    match dialect.open_text(dialect.empty_program, settings) {
        Ok(engine) => engine,
        // A constant of the dialect's own, not the user's: every dialect's test asserts it.
        Err(d) => unreachable!("{} refuses its own empty program: {d:?}", dialect.name),
    }
}

/// At the furthest position of a rebuilt timeline whose run stopped there (a fault leaves the
/// position where the faulting instruction began, so a replay to it stops just before): run
/// that instruction, so the engine holds the stop. True when the machine is stopped.
/// An instruction that does not stop the run (an error-lamp mark) is not run: the
/// furthest position stays.
fn run_into_stop(engine: &mut dyn Engine) -> bool {
    engine.run_into_stop()
}

impl Debugger {
    /// A debugger on `source` in `dialect`. If it does not assemble, the diagnostics are kept
    /// and nothing runs until the text is fixed.
    pub fn with_dialect(
        dialect: &'static Dialect,
        name: impl Into<String>,
        source: impl Into<String>,
    ) -> Self {
        let name = name.into();
        let project = Project::single(
            name.clone(),
            crate::text::normalize(&source.into()).into_owned(),
        );
        Debugger::on_project(dialect, name, project)
    }

    /// A debugger on a program of several files (the top file first).
    pub fn with_project(dialect: &'static Dialect, project: Project) -> Self {
        let name = project.top_name().to_string();
        Debugger::on_project(dialect, name, normalized(project))
    }

    fn on_project(dialect: &'static Dialect, name: String, project: Project) -> Self {
        let settings = dialect.default_settings();
        let engine = empty_engine(dialect, &settings);
        let checker = RefCell::new(Checker::new(&[], engine.machine(), &[]));
        let mut d = Debugger {
            dialect,
            name,
            project,
            assembled: Project::default(),
            diagnostics: Vec::new(),
            engine,
            settings,
            channel_names: ChannelChoice::defaults(dialect),
            breaks: Vec::new(),
            checker,
            watches: Vec::new(),
            generation: 0,
            last_writer: None,
            goal: None,
            resume_past_breakpoint: false,
            break_on_error: false,
            lamp_was_on: false,
            speed: Speed::PerSecond(10.0),
            credit: 0.0,
            event: None,
            worker: None,
            lent: false,
            spare: None,
            rate: run::RateMeter::default(),
            chunk_ticks: FIRST_CHUNK_TICKS,
            chunk_floor: None,
            back: None,
            scripted: Vec::new(),
        };
        d.assemble();
        d.channels_for_program();
        d
    }

    /// A new program's plot starts on what it uses ([`ChannelChoice::for_program`]).
    fn channels_for_program(&mut self) {
        let chosen = ChannelChoice::for_program(self.dialect, self.engine.machine());
        if chosen != self.channel_names {
            self.set_channels(chosen);
        }
    }

    /// A debugger restored to `at` of a recorded run: the program, its settings, breakpoints,
    /// plot channels and timeline of user events (some may lie after `at`), replayed to
    /// `furthest` so the history is there to go back to.
    #[allow(clippy::too_many_arguments)]
    pub fn restore(
        dialect: &'static Dialect,
        name: impl Into<String>,
        project: impl Into<Project>,
        settings: &Settings,
        breakpoints: impl IntoIterator<Item = usize>,
        channels: Option<Vec<ChannelChoice>>,
        events: Vec<UserEvent>,
        furthest: Pos,
    ) -> Result<Debugger, Vec<Diagnostic>> {
        let name = name.into();
        let mut project = normalized(project.into());
        if !project.is_multi()
            && let Some(top) = project.files.first_mut()
        {
            top.name = name.clone();
        }
        let settings = dialect.settings_from(settings);
        let engine = dialect.open_program(&project, &settings)?;
        let mut d = Debugger::with_dialect(dialect, name, dialect.empty_program);
        d.assembled = project.clone();
        d.project = project;
        d.settings = settings;
        if let Some(channels) = channels {
            d.channel_names = channels;
        }
        let channels = d.resolve_channels(engine.machine());
        d.engine = engine.restarted(events, channels);
        d.generation = next_generation();
        d.set_breakpoints(breakpoints);
        d.event = None;
        d.replay_to(furthest, &mut |_| true);
        Ok(d)
    }

    /// Run the recorded timeline forward to `furthest`, in slices of [`REPLAY_SLICE`] ticks,
    /// asking `go_on` with the tick reached between slices. Returns false when `go_on` said
    /// stop (the debugger is then part-way and should be dropped).
    pub fn replay_to(&mut self, furthest: Pos, go_on: &mut dyn FnMut(u64) -> bool) -> bool {
        loop {
            let now = self.pos();
            let next = Pos::at_tick(now.tick.saturating_add(REPLAY_SLICE)).min(furthest);
            if now >= furthest
                || !self.machine().run_state().is_live()
                || self.engine.forward(next, &StopWhen::default()) != StopReason::TickLimit
            {
                return true;
            }
            if !go_on(self.pos().tick) {
                return false;
            }
        }
    }

    /// A restored run that had ended or faulted at its furthest position: run the instruction
    /// there again, so the state is the stop itself (run state, fault, flags, the status bar's
    /// word for it), as the runner reports it. Does nothing elsewhere or when the run goes on
    /// from there.
    pub fn replay_stop(&mut self) {
        if run_into_stop(self.engine.as_mut()) {
            self.after_stop(Event::Stepped);
        }
    }

    // ---- reading ---------------------------------------------------------------------------

    pub fn name(&self) -> &str {
        &self.name
    }
    /// The program's name changes (saved under another file name); nothing else does.
    pub fn rename(&mut self, name: impl Into<String>) {
        self.name = name.into();
        // Included files are named relative to the top file's folder, not its name.
        for project in [&mut self.project, &mut self.assembled] {
            if let Some(top) = project.files.first_mut() {
                top.name = self.name.clone();
            }
        }
    }
    /// The top file's text.
    pub fn source(&self) -> &str {
        self.project.top_text()
    }
    /// The top file's editable text. Edits take effect at the next assemble, step or run.
    pub fn source_mut(&mut self) -> &mut String {
        self.file_text_mut(0)
    }
    /// Every file of the program, the top file first.
    pub fn project(&self) -> &Project {
        &self.project
    }
    /// The files as the running program was assembled from them.
    pub fn assembled_project(&self) -> &Project {
        &self.assembled
    }
    /// File `file`'s editable text (the top file's when there is no such file).
    pub fn file_text_mut(&mut self, file: usize) -> &mut String {
        if self.project.files.is_empty() {
            self.project.files.push(SourceFile::default());
        }
        let file = file.min(self.project.files.len() - 1);
        &mut self.project.files[file].text
    }
    /// Read from disk, beside the top file in `dir`, the files the program's texts now include
    /// but it does not hold yet (an `#include` typed in): the next assembly has them.
    pub fn add_new_includes(
        &mut self,
        dir: &std::path::Path,
        folders: &crate::machine::project::IncludeFolders,
    ) -> usize {
        match self.dialect.includes {
            Some(includes) => {
                crate::machine::project::add_new_includes(&mut self.project, dir, includes, folders)
            }
            None => 0,
        }
    }
    /// Whether file `file`'s text differs from what was assembled.
    pub fn is_file_edited(&self, file: usize) -> bool {
        self.project.files.get(file).map(|f| &f.text)
            != self.assembled.files.get(file).map(|f| &f.text)
    }
    /// A program line as a user reads it: `12`, or `setup.tml:12` in a program of several
    /// files.
    pub fn describe_line(&self, line: usize) -> String {
        self.project.describe(line)
    }
    /// "line 12", or "setup.tml:12" in a program of several files.
    pub fn where_line(&self, line: usize) -> String {
        if self.project.is_multi() {
            self.project.describe(line)
        } else {
            format!("line {line}")
        }
    }
    /// Whether any file's text differs from what was assembled (or a file came or went).
    pub fn is_edited(&self) -> bool {
        self.project.files.len() != self.assembled.files.len()
            || (0..self.project.files.len()).any(|f| self.is_file_edited(f))
    }
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.diagnostics
    }
    /// Whether the program did not assemble (warnings alone leave it running).
    pub fn has_errors(&self) -> bool {
        self.error_count() > 0
    }
    pub fn error_count(&self) -> usize {
        self.diagnostics
            .iter()
            .filter(|d| d.severity == crate::machine::Severity::Error)
            .count()
    }
    pub fn machine(&self) -> &dyn MachineView {
        self.engine.machine()
    }
    /// The machine as its concrete type, for a dialect's own panels and tests.
    pub fn machine_as<T: 'static>(&self) -> Option<&T> {
        self.machine().as_any().downcast_ref()
    }
    pub fn dialect(&self) -> &'static Dialect {
        self.dialect
    }
    /// Where the machine is now.
    pub fn pos(&self) -> Pos {
        self.machine().pos()
    }
    /// The lines with an enabled line breakpoint.
    pub fn breakpoints(&self) -> BTreeSet<usize> {
        self.breaks
            .iter()
            .filter(|b| b.enabled)
            .filter_map(Breakpoint::line_number)
            .collect()
    }
    pub fn is_running(&self) -> bool {
        self.goal.is_some()
    }
    pub fn goal(&self) -> Option<Goal> {
        self.goal
    }
    pub fn speed(&self) -> Speed {
        self.speed
    }
    pub fn event(&self) -> Option<&Event> {
        self.event.as_ref()
    }

    /// Put back what the status bar said when a session was saved.
    pub fn set_event(&mut self, event: Event) {
        self.event = Some(event);
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }
    /// The trace of the plot channels since the last reset.
    pub fn trace(&self) -> &Trace {
        self.engine.trace()
    }
    /// The channels the trace records, resolved.
    pub fn channels(&self) -> &[Channel] {
        self.engine.channels()
    }
    /// The channels as chosen (names may not exist in the current program).
    pub fn channel_choices(&self) -> &[ChannelChoice] {
        &self.channel_names
    }
    /// The furthest position reached: the timeline spans the start ..= this.
    pub fn furthest(&self) -> Pos {
        self.engine.furthest()
    }
    /// Whether the run ended or faulted at the furthest position (sessions keep this).
    pub fn stopped_at_furthest(&self) -> bool {
        self.engine.stopped()
    }
    /// The furthest tick reached.
    pub fn furthest_tick(&self) -> u64 {
        self.furthest().tick
    }
    /// Every input switch and edit, with its position.
    pub fn events(&self) -> &[UserEvent] {
        self.engine.events()
    }
    /// Breakpoint hits and faults on the timeline.
    pub fn marks(&self) -> &[Mark] {
        self.engine.marks()
    }
    /// Put back the marks of a saved session.
    pub fn restore_marks(&mut self, marks: impl IntoIterator<Item = (Pos, MarkKind, usize)>) {
        for (at, kind, line) in marks {
            self.engine.mark_at(at, kind, line);
        }
    }

    /// Edits every restart applies again (a lesson's inputs); the current timeline is not
    /// changed until the next restart.
    pub fn set_scripted_events(&mut self, events: Vec<ScriptedEvent>) {
        self.scripted = events;
    }

    pub fn scripted_events(&self) -> &[ScriptedEvent] {
        &self.scripted
    }

    /// Which timeline this is: it changes whenever a new one starts (restart, assembly, another
    /// program, a session).
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Bytes the history holds (checkpoints, events, trace).
    pub fn history_bytes(&self) -> usize {
        self.engine.memory_bytes()
    }

    /// Write the trace as CSV (one row per tick where a value changed), atomically.
    /// Returns the number of rows.
    pub fn export_trace_csv(&self, path: &std::path::Path) -> std::io::Result<usize> {
        let micros = self.machine().tick_micros();
        let trace = self.engine.trace();
        let channels = self.channels();
        crate::atomic::write_atomically(path, |w| trace.write_csv(w, micros, channels))?;
        Ok(trace.len())
    }

    /// The location named `name` in the current machine.
    pub fn find(&self, name: &str) -> Option<Loc> {
        self.machine().find(name)
    }
}
