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
pub mod breakpoints;
pub mod dialect;
pub mod engine;
pub mod expr;
pub mod history;
mod lines;
pub mod log;
mod run;
pub mod trace;
mod watch;
mod worker;

use std::cell::RefCell;
use std::collections::BTreeSet;

pub use action::Action;
pub use breakpoints::{BreakError, BreakKind, Breakpoint, DataTrigger, LogMessage};
pub use engine::{Engine, StopWhen, engine};
pub use lines::remap_lines;
pub use run::{BACK_TICKS_AT_ONCE, Event, Goal, Speed};
pub use watch::Watch;

use crate::machine::project::{Project, SourceFile};
pub use dialect::{Dialect, OpenResult};

use crate::machine::dialect::Settings;
use crate::machine::{Diagnostic, Format, Loc, MachineView, Pos, StopReason, value};
use breakpoints::Checker;
use history::{Change, Mark, MarkKind, UserEvent};
use trace::{Channel, MAX_CHANNELS, Trace};

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

/// A plot channel as the user chose it: a location name, a legend and a plot group.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ChannelChoice {
    pub location: String,
    #[serde(default)]
    pub label: String,
    #[serde(default)]
    pub group: u8,
}

impl ChannelChoice {
    pub fn defaults(dialect: &Dialect) -> Vec<ChannelChoice> {
        dialect
            .default_channels
            .iter()
            .map(|c| ChannelChoice {
                location: c.location.to_string(),
                label: c.label.to_string(),
                group: c.group,
            })
            .collect()
    }
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
fn run_into_stop(engine: &mut dyn Engine) -> bool {
    let m = engine.machine();
    if !m.run_state().is_live() {
        return true;
    }
    let at = m.pos();
    if at != engine.furthest() {
        return false;
    }
    let next = Pos {
        tick: at.tick,
        step: at.step.saturating_add(1),
    };
    engine.forward(next, &StopWhen::default());
    if engine.machine().run_state().is_live() {
        // It did not stop there after all (an older file's error-lamp mark): back.
        engine.goto(at);
        return false;
    }
    true
}

/// Why a typed value was not stored.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EditError {
    #[error("there is no location named '{0}'")]
    Unknown(String),
    #[error(transparent)]
    Value(#[from] crate::machine::value::ValueError),
    #[error(transparent)]
    Refused(#[from] crate::machine::WriteError),
    #[error("fix the program's errors first: edits apply to a running program")]
    NotAssembled,
    #[error("{name} has {width} bit(s): there is no bit {bit}")]
    NoSuchBit { name: String, bit: u8, width: u8 },
    #[error("the program has {0}: step back or reset to change its state")]
    Stopped(&'static str),
}

impl Change {
    /// Whether this change can be made to the location `info` describes: it is writable, a
    /// value fits its width, a bit is one of its bits. Checked before any edit is recorded, so
    /// the timeline only ever holds edits that apply.
    pub fn check(self, info: &crate::machine::LocInfo) -> Result<(), EditError> {
        if !info.editable {
            return Err(crate::machine::WriteError::ReadOnly(info.name.clone()).into());
        }
        match self {
            Change::Set(value) if info.width < 64 && value >> info.width != 0 => {
                Err(crate::machine::WriteError::TooWide {
                    name: info.name.clone(),
                    value,
                    width: info.width,
                }
                .into())
            }
            Change::Bit { bit, .. } if bit >= info.width => Err(EditError::NoSuchBit {
                name: info.name.clone(),
                bit,
                width: info.width,
            }),
            Change::Force(_) if info.width != 1 => {
                Err(crate::machine::WriteError::NotForceable(info.name.clone()).into())
            }
            _ => Ok(()),
        }
    }
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
        d
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
    pub fn add_new_includes(&mut self, dir: &std::path::Path) -> usize {
        match self.dialect.includes {
            Some(includes) => {
                crate::machine::project::add_new_includes(&mut self.project, dir, includes)
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

    fn resolve_channels(&self, m: &dyn MachineView) -> Vec<Channel> {
        self.channel_names
            .iter()
            .filter_map(|c| {
                let label = |name: &str| {
                    if c.label.is_empty() {
                        name.to_string()
                    } else {
                        c.label.clone()
                    }
                };
                if let Some(loc) = m.find(&c.location) {
                    let info = m.info(loc)?;
                    let reading = info.reading();
                    return Some(Channel {
                        loc,
                        label: label(&info.name),
                        name: info.name,
                        width: info.width,
                        // A word its dialect reads as signed (an OpenNet D of type I) plots so.
                        signed: info.signed || reading == Format::Signed,
                        reading,
                        group: c.group,
                        expr: None,
                    });
                }
                // Not a location: a watch expression plotted as a channel.
                let expr = expr::Expr::compile(&c.location, m).ok()?;
                Some(Channel {
                    loc: Loc::new(0, 0),
                    label: label(expr.text()),
                    name: expr.text().to_string(),
                    width: 64,
                    signed: true,
                    reading: Format::Signed,
                    group: c.group,
                    expr: Some(expr),
                })
            })
            .take(MAX_CHANNELS)
            .collect()
    }

    /// Choose the plot channels. The trace is rebuilt by replaying the recorded history.
    pub fn set_channels(&mut self, channels: Vec<ChannelChoice>) {
        self.channel_names = channels;
        self.channel_names.truncate(MAX_CHANNELS);
        for c in &mut self.channel_names {
            c.group = c.group.min(trace::PLOT_GROUPS - 1);
        }
        let here = self.pos();
        let furthest = self.furthest();
        let resolved = self.resolve_channels(self.engine.machine());
        let marks: Vec<Mark> = self.marks().to_vec();
        let stopped = self.engine.stopped();
        let mut engine = self.engine.restarted(self.events().to_vec(), resolved);
        engine.forward(furthest, &StopWhen::default());
        if stopped {
            run_into_stop(engine.as_mut());
        }
        for m in marks {
            engine.mark_at(m.at, m.kind, m.line);
        }
        engine.goto(here);
        self.engine = engine;
    }

    // ---- program ---------------------------------------------------------------------------

    /// Replace the whole program (File -> Open). Breakpoints are cleared.
    pub fn load(&mut self, name: impl Into<String>, source: impl Into<String>) {
        let dialect = self.dialect;
        self.load_as(dialect, name, source);
    }

    /// Replace the whole program with one of several files (File -> Open of a top file).
    pub fn load_project(&mut self, dialect: &'static Dialect, project: Project) {
        let name = project.top_name().to_string();
        self.load_as(dialect, name, "");
        self.project = normalized(project);
        self.assemble();
        self.assembled = self.project.clone();
    }

    /// Replace the whole program with one in `dialect`. Breakpoints are cleared; the settings
    /// and plot channels become the dialect's defaults when the dialect changes.
    pub fn load_as(
        &mut self,
        dialect: &'static Dialect,
        name: impl Into<String>,
        source: impl Into<String>,
    ) {
        if dialect != self.dialect {
            self.dialect = dialect;
            self.settings = dialect.default_settings();
            self.channel_names = ChannelChoice::defaults(dialect);
        }
        // Nothing of the previous program stays: not its state, its history, nor its inputs
        // (a new program starts with every input low, as the runner does).
        self.engine = empty_engine(dialect, &self.settings);
        self.name = name.into();
        self.project = Project::single(
            self.name.clone(),
            crate::text::normalize(&source.into()).into_owned(),
        );
        self.assembled = Project::default();
        // Breakpoints and watches belong to their program: a new one starts clean.
        self.breaks.clear();
        self.watches.clear();
        self.assemble();
        // The text is as loaded, not edited, even when it does not assemble.
        self.assembled = self.project.clone();
    }

    /// A new timeline at the start of the current program: every input low, as in the runner
    /// (a run's input switches are part of its recorded timeline, not of the next run).
    fn restart(&mut self) {
        let channels = self.resolve_channels(self.engine.machine());
        let m = self.engine.machine();
        let events = self
            .scripted
            .iter()
            .filter_map(|e| {
                let loc = m.find(&e.location)?;
                // An edit this program's location cannot take is left out, like an unknown name.
                e.change.check(&m.info(loc)?).ok()?;
                Some(UserEvent {
                    at: e.at,
                    loc,
                    change: e.change,
                })
            })
            .collect();
        self.engine = self.engine.restarted(events, channels);
        self.goal = None;
        self.chunk_ticks = FIRST_CHUNK_TICKS;
        self.chunk_floor = None;
        self.last_writer = None;
        self.generation = next_generation();
        self.rebuild_checker(false);
    }

    /// Assemble the current text. On success the machine restarts on the new program and
    /// breakpoints follow the lines they were on; on failure the diagnostics are kept and the
    /// old state stays on screen, but nothing runs.
    pub fn assemble(&mut self) -> bool {
        self.goal = None;
        match self.dialect.open_program(&self.project, &self.settings) {
            Ok(engine) => {
                // Each file's breakpoints follow their lines in that file's edit.
                let movers: Vec<_> = (0..self.project.files.len())
                    .map(|f| {
                        let old = self.assembled.files.get(f).map_or("", |x| x.text.as_str());
                        lines::line_mover(old, &self.project.files[f].text)
                    })
                    .collect();
                self.breaks.retain_mut(|b| match &mut b.kind {
                    BreakKind::Line(l) => {
                        let (file, local) = Project::split(*l);
                        movers
                            .get(file)
                            .and_then(|moved| moved(local))
                            .map(|to| *l = Project::line(file, to))
                            .is_some()
                    }
                    BreakKind::Data { .. } => true,
                });
                self.engine = engine;
                self.restart();
                self.assembled = self.project.clone();
                // What is left are warnings: they are shown, the program runs.
                self.diagnostics = self.engine.machine().warnings();
                self.diagnostics.sort_by_key(|d| (d.line, d.col));
                self.event = Some(Event::Assembled);
                true
            }
            Err(mut diagnostics) => {
                // Views find a line's diagnostics by binary search.
                diagnostics.sort_by_key(|d| (d.line, d.col));
                self.event = Some(Event::NotAssembled(diagnostics.len()));
                self.diagnostics = diagnostics;
                false
            }
        }
    }

    /// Assemble first if the text changed. False when the program cannot run.
    fn ready(&mut self) -> bool {
        if self.is_edited() || self.has_errors() {
            return self.assemble();
        }
        true
    }

    // ---- breakpoints -----------------------------------------------------------------------

    /// Toggle a plain breakpoint on a 1-based line: removes every breakpoint of the line when
    /// there is one. Returns whether the line now has one.
    pub fn toggle_breakpoint(&mut self, line: usize) -> bool {
        if line == 0 {
            return false;
        }
        let before = self.breaks.len();
        self.breaks.retain(|b| b.line_number() != Some(line));
        let set = self.breaks.len() == before;
        if set {
            self.breaks.push(Breakpoint::line(line));
        }
        self.rebuild_checker(true);
        set
    }

    /// Plain breakpoints on these lines, replacing every breakpoint.
    pub fn set_breakpoints(&mut self, lines: impl IntoIterator<Item = usize>) {
        let lines: BTreeSet<usize> = lines.into_iter().filter(|&l| l > 0).collect();
        self.set_breakpoint_list(lines.into_iter().map(Breakpoint::line).collect());
    }

    /// Every breakpoint, in the order of the list panel.
    pub fn breakpoint_list(&self) -> &[Breakpoint] {
        &self.breaks
    }

    /// Replace every breakpoint (a session loading); hit counts start at 0.
    pub fn set_breakpoint_list(&mut self, list: Vec<Breakpoint>) {
        self.breaks = list
            .into_iter()
            .filter(|b| b.line_number() != Some(0))
            .collect();
        self.rebuild_checker(false);
    }

    /// Add a breakpoint; returns its index in the list. The problem with its condition,
    /// message or location, if any, is [`Debugger::breakpoint_error`].
    pub fn add_breakpoint(&mut self, b: Breakpoint) -> usize {
        self.breaks.push(b);
        self.rebuild_checker(true);
        self.breaks.len() - 1
    }

    /// Change a breakpoint (its hit count so far stays).
    pub fn update_breakpoint(&mut self, index: usize, b: Breakpoint) {
        if let Some(slot) = self.breaks.get_mut(index) {
            *slot = b;
            self.rebuild_checker(true);
        }
    }

    pub fn remove_breakpoint(&mut self, index: usize) {
        if index < self.breaks.len() {
            self.breaks.remove(index);
            let old =
                self.checker
                    .replace(Checker::new(&self.breaks, self.machine(), &self.lines()));
            let mut hits: Vec<u64> = (0..=self.breaks.len()).map(|i| old.hits(i)).collect();
            hits.remove(index);
            let new = self.checker.get_mut();
            new.set_hits(&hits);
            new.log = old.log;
            new.rebuild_logged();
        }
    }

    /// Source lines of each file of the program that runs (breakpoints past them can never
    /// stop).
    fn lines(&self) -> Vec<usize> {
        self.assembled
            .files
            .iter()
            .map(|f| f.text.lines().count())
            .collect()
    }

    /// Why a breakpoint cannot work in the current program (a condition that does not parse,
    /// a location that does not exist); it is inactive until fixed.
    pub fn breakpoint_error(&self, index: usize) -> Option<BreakError> {
        self.checker.borrow().errors.get(index).cloned().flatten()
    }

    /// How many times a forward run passed the breakpoint with its condition holding.
    pub fn breakpoint_hits(&self, index: usize) -> u64 {
        self.checker.borrow().hits(index)
    }

    /// The messages log points wrote, oldest first.
    pub fn log_messages(&self) -> std::cell::Ref<'_, [LogMessage]> {
        std::cell::Ref::map(self.checker.borrow(), |c| c.log.as_slice())
    }

    /// Compile the breakpoints against the current program, keeping the hit counts and log
    /// (`keep`) or starting both afresh.
    fn rebuild_checker(&mut self, keep: bool) {
        let mut new = Checker::new(&self.breaks, self.engine.machine(), &self.lines());
        if keep {
            let old = self.checker.borrow();
            new.keep_hits(&old);
            new.log = old.log.clone();
        }
        new.rebuild_logged();
        self.checker = RefCell::new(new);
    }

    // ---- edits -----------------------------------------------------------------------------

    /// Change a location now; the edit becomes part of the timeline. A refused edit changes
    /// nothing.
    pub fn edit(&mut self, loc: Loc, change: Change) -> Result<(), EditError> {
        if self.has_errors() {
            return Err(EditError::NotAssembled);
        }
        // A stopped run has no future for an edit to change, and an edit recorded at the
        // stop's position would replay before the instruction that stopped it: refused.
        let state = self.machine().run_state();
        if !state.is_live() {
            return Err(EditError::Stopped(state.label()));
        }
        let info = self
            .machine()
            .info(loc)
            .ok_or(crate::machine::WriteError::NoSuchLocation)?;
        change.check(&info)?;
        let now = self.machine().read(loc);
        let unchanged = match change {
            Change::Set(v) => v == now,
            Change::Bit { bit, on } => (now >> bit & 1 == 1) == on,
            Change::Force(level) => self.machine().forced(loc) == level,
        };
        if unchanged {
            // Writing what is already there changes nothing: no event, the future stays.
            return Ok(());
        }
        let at = self.pos();
        if self.engine.edit(loc, change)? {
            self.event = Some(Event::FutureDiscarded(at.tick));
            self.checker.borrow_mut().forget_log_after(at);
        }
        Ok(())
    }

    /// Store a raw value in a location.
    pub fn set_value(&mut self, loc: Loc, value: u64) -> Result<(), EditError> {
        self.edit(loc, Change::Set(value))
    }

    /// Parse what the user typed for the location named `name` and store it. On error nothing
    /// changes.
    pub fn set_text(&mut self, name: &str, text: &str) -> Result<u64, EditError> {
        let loc = self
            .find(name)
            .ok_or_else(|| EditError::Unknown(name.to_string()))?;
        self.set_loc_text(loc, text)
    }

    /// Parse what the user typed for `loc` (at its width) and store it.
    pub fn set_loc_text(&mut self, loc: Loc, text: &str) -> Result<u64, EditError> {
        let info = self
            .machine()
            .info(loc)
            .ok_or_else(|| EditError::Unknown(format!("{loc:?}")))?;
        let value = value::parse_value(text, info.width).map_err(EditError::Value)?;
        self.set_value(loc, value)?;
        Ok(value)
    }

    /// Flip one bit of a location.
    pub fn toggle_bit(&mut self, loc: Loc, bit: u8) -> Result<(), EditError> {
        // A bit past 63 reads as clear; `edit` refuses it (and any past the width).
        let on = self
            .machine()
            .read(loc)
            .checked_shr(u32::from(bit))
            .unwrap_or(0)
            & 1
            == 0;
        self.edit(loc, Change::Bit { bit, on })
    }

    /// Set one bit of a location.
    pub fn set_bit(&mut self, loc: Loc, bit: u8, on: bool) -> Result<(), EditError> {
        self.edit(loc, Change::Bit { bit, on })
    }

    /// Switch an input (any 1-bit location) high or low; nothing is recorded when it already
    /// is.
    pub fn set_input(&mut self, loc: Loc, high: bool) -> Result<(), EditError> {
        if (self.machine().read(loc) != 0) == high {
            return Ok(());
        }
        self.set_value(loc, u64::from(high))
    }

    /// Force a bit ON or OFF (`Some`) or release it (`None`) from now on: a user event like an
    /// edit, so time travel replays it and sessions keep it.
    pub fn force(&mut self, loc: Loc, level: Option<bool>) -> Result<(), EditError> {
        self.edit(loc, Change::Force(level))
    }

    /// Release every force now.
    pub fn release_all_forces(&mut self) -> Result<(), EditError> {
        for (loc, _) in self.machine().forces() {
            self.force(loc, None)?;
        }
        Ok(())
    }

    /// The dialect's settings; applying them restarts the program.
    pub fn set_settings(&mut self, settings: &Settings) {
        self.settings = self.dialect.settings_from(settings);
        self.assembled = Project::default();
        self.assemble();
    }
}

#[cfg(test)]
mod tests {
    use std::time::{Duration, Instant};

    use super::*;

    fn reg(d: &Debugger, r: u32) -> i32 {
        d.machine().read(Loc::new(0, r)) as u32 as i32
    }

    const LOOP: &str = "WRP 11, 3\nloop: CLC INC, 12\nCLC DEC, 11\nJMP loop, !ZERO\nEND\n";

    #[test]
    fn run_stops_at_a_breakpoint_and_resumes_past_it() {
        let mut d = Debugger::new("loop", LOOP);
        d.set_speed(Speed::Unlimited);
        d.toggle_breakpoint(2);
        d.run();
        assert!(!d.advance(0.016, Duration::from_millis(50)));
        assert_eq!(d.event(), Some(&Event::Breakpoint(2)));
        assert_eq!(reg(&d, 12), 0, "stopped before line 2 ran");
        d.run();
        d.advance(0.016, Duration::from_millis(50));
        assert_eq!(d.event(), Some(&Event::Breakpoint(2)));
        assert_eq!(reg(&d, 12), 1, "one round later");
        d.toggle_breakpoint(2);
        d.run();
        d.advance(0.016, Duration::from_millis(50));
        assert_eq!(d.event(), Some(&Event::Ended));
        assert_eq!(reg(&d, 12), 3);
    }

    #[test]
    fn slow_speed_runs_the_commands_the_time_allows() {
        let mut d = Debugger::new("loop", LOOP);
        d.set_speed(Speed::PerSecond(10.0));
        d.run();
        // 0.25 s at 10 commands/s: 2.5 commands, so 2 now and the half carries over.
        d.advance(0.25, Duration::from_millis(50));
        assert_eq!(d.machine().steps(), 2);
        d.advance(0.05, Duration::from_millis(50));
        assert_eq!(d.machine().steps(), 3);
        assert!(d.is_running());
        d.pause();
        assert!(!d.is_running());
        assert_eq!(
            d.event(),
            Some(&Event::Paused(Some(4))),
            "three commands ran"
        );
    }

    #[test]
    fn run_to_line_and_reset() {
        let mut d = Debugger::new("loop", LOOP);
        d.set_speed(Speed::Unlimited);
        d.run_to_line(5);
        d.advance(0.0, Duration::from_millis(50));
        assert_eq!(d.event(), Some(&Event::ReachedLine(5)));
        assert_eq!(d.machine().pc_line(), Some(5));
        let io2 = d.find("IO2").expect("SilverLode has IO2");
        d.set_input(io2, true).expect("inputs can be switched");
        d.reset();
        assert_eq!(d.machine().ticks(), 0);
        assert_eq!(
            d.machine().read(io2),
            0,
            "a new run starts with its inputs low, as the runner's does"
        );
        assert!(
            d.events().is_empty(),
            "nothing carried into the new timeline"
        );
        d.set_input(io2, true).expect("inputs can be switched");
        *d.source_mut() = "WRP 11, 2\nEND\n".to_string();
        d.assemble();
        assert_eq!(d.machine().read(io2), 0, "nor into a re-assembled program");
    }

    #[test]
    fn unlimited_runs_in_bounded_slices() {
        let mut d = Debugger::new("forever", "loop: CLC INC, 11\nJMP loop");
        d.set_speed(Speed::Unlimited);
        d.run();
        let started = Instant::now();
        assert!(d.advance(0.016, Duration::from_millis(5)), "still running");
        assert!(
            // A guard against a blocking loop, not a speed claim.
            started.elapsed() < Duration::from_secs(3),
            "returned after its budget"
        );
        assert!(d.machine().ticks() > 0);
        d.pause();
        assert!(!d.advance(0.016, Duration::from_millis(5)));
    }

    #[test]
    fn real_time_speed_advances_the_ticks_the_time_is_worth() {
        // An endless wait: only time passes.
        let mut d = Debugger::new("wait", "WBS IO1\nEND");
        d.set_speed(Speed::RealTime(1.0));
        d.run();
        // 12 ms of real time at ×1 is 100 ticks of 120 µs.
        assert!(d.advance(0.012, Duration::from_millis(50)));
        assert_eq!(d.machine().ticks(), 100);
        d.set_speed(Speed::RealTime(0.1));
        d.advance(0.012, Duration::from_millis(50));
        assert_eq!(d.machine().ticks(), 110, "×0.1: ten ticks");
        // A switch flipped between frames lands on the tick on screen.
        let io1 = d.find("IO1").expect("an input");
        d.set_input(io1, true).expect("switched");
        assert_eq!(d.events()[0].at.tick, 110);
        d.advance(0.012, Duration::from_millis(50));
        assert_eq!(d.event(), Some(&Event::Ended));
        assert_eq!(
            d.machine().ticks(),
            112,
            "WBS saw it in tick 111, END took 112"
        );
    }

    #[test]
    fn a_long_step_continues_over_frames() {
        let mut d = Debugger::new("delay", "DLY 1000000\nEND");
        d.step_command();
        assert_eq!(d.goal(), Some(Goal::FinishStep));
        while d.advance(0.016, Duration::from_millis(50)) {}
        assert_eq!(d.machine().pc_line(), Some(2));
        assert_eq!(d.event(), Some(&Event::Stepped));
    }

    #[test]
    fn errors_block_running_until_fixed() {
        let mut d = Debugger::new("bad", "WRP 11, 1\nBOGUS 3");
        assert_eq!(d.diagnostics().len(), 1);
        d.step_command();
        d.run();
        assert!(!d.is_running());
        assert_eq!(d.machine().ticks(), 0);
        assert_eq!(d.event(), Some(&Event::NotAssembled(1)));
        *d.source_mut() = "WRP 11, 1\nEND".to_string();
        d.step_command();
        assert_eq!(reg(&d, 11), 1, "edits assemble on the next step");
        assert!(d.diagnostics().is_empty());
    }

    #[test]
    fn register_edits_parse_or_change_nothing() {
        let mut d = Debugger::new("p", "END");
        assert_eq!(d.set_text("R20", "0x10"), Ok(16));
        assert!(d.set_text("R20", "banana").is_err());
        assert_eq!(reg(&d, 20), 16);
        let r20 = d.find("r20").expect("R20 exists");
        d.toggle_bit(r20, 0).expect("a register bit flips");
        assert_eq!(reg(&d, 20), 17);
        assert!(matches!(
            d.set_text("R200", "1"),
            Err(EditError::Unknown(_))
        ));
        assert!(
            d.set_text("R20", "0x1_0000_0000").is_err(),
            "wider than 32 bits"
        );
        assert_eq!(reg(&d, 20), 17, "refused edits change nothing");
    }
}
