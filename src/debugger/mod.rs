//! Run control over a machine of any dialect: the program text and its assembly, breakpoints,
//! stepping forward and back, running at a chosen speed in bounded slices, pausing, resetting,
//! going to any position, and user edits that become part of the replayable timeline.
//!
//! The debugger holds the machine behind [`Engine`] (dynamic dispatch once per action or frame
//! slice); the loops inside run on the concrete machine type.
//!
//! No egui here: everything the GUI can do is a method a unit test can call. The GUI calls
//! [`Debugger::advance`] once per frame with a time budget, so a run never blocks a frame.

pub mod engine;
pub mod history;
pub mod trace;

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

pub use engine::{Engine, StopWhen, engine};

use crate::machine::registry::{self, Dialect, Settings};
use crate::machine::{Diagnostic, Loc, MachineView, Pos, RunState, SpaceKind, StopReason, value};
use history::{Change, Mark, MarkKind, UserEvent};
use trace::{Channel, MAX_CHANNELS, Trace};

/// Ticks run between two looks at the clock while running unlimited.
const CHUNK_TICKS: u64 = 20_000;
/// Ticks a single step may take before it continues over later frames (a long DLY or move).
const STEP_TICKS_AT_ONCE: u64 = 200_000;

/// How fast Run goes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Speed {
    /// Commands per second (a step that waits, like DLY, counts as one command).
    PerSecond(f64),
    /// As fast as the machine goes, in slices that leave every frame its time.
    Unlimited,
}

impl Speed {
    pub const PRESETS: [Speed; 9] = [
        Speed::PerSecond(1.0),
        Speed::PerSecond(2.0),
        Speed::PerSecond(5.0),
        Speed::PerSecond(10.0),
        Speed::PerSecond(100.0),
        Speed::PerSecond(1_000.0),
        Speed::PerSecond(10_000.0),
        Speed::PerSecond(100_000.0),
        Speed::Unlimited,
    ];

    /// `10 commands/s`, in the dialect's word for a step.
    pub fn label(self, steps: &str) -> String {
        match self {
            Speed::Unlimited => "unlimited".to_string(),
            Speed::PerSecond(n) if n >= 1000.0 => format!("{}k {steps}/s", n / 1000.0),
            Speed::PerSecond(n) => format!("{n} {steps}/s"),
        }
    }
}

/// What the debugger is doing over frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Goal {
    /// Until a breakpoint, the end or a fault.
    Continue,
    /// Until the current command completes (a long DLY or move).
    FinishStep,
    /// Until the command on this line is about to run (or a breakpoint).
    ToLine(usize),
    /// Until this tick (beyond the furthest one reached so far).
    ToTick(u64),
}

/// Why the debugger last stopped, for the status bar.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Event {
    Breakpoint(usize),
    ReachedLine(usize),
    ReachedTick(u64),
    Paused(Option<usize>),
    Stepped,
    SteppedBack,
    /// Reverse-continue found no earlier breakpoint: back at the start.
    NoEarlierBreakpoint,
    Ended,
    Faulted,
    Reset,
    /// The text has errors: nothing runs until they are fixed.
    NotAssembled(usize),
    Assembled,
    /// An edit in the past rewrote history from this tick on.
    FutureDiscarded(u64),
}

impl Event {
    pub fn describe(&self) -> String {
        match self {
            Event::Breakpoint(l) => format!("Breakpoint hit at line {l}"),
            Event::ReachedLine(l) => format!("Reached line {l}"),
            Event::ReachedTick(t) => format!("At tick {t}"),
            Event::Paused(Some(l)) => format!("Paused at line {l}"),
            Event::Paused(None) => "Paused".to_string(),
            Event::Stepped => "Stepped".to_string(),
            Event::SteppedBack => "Stepped back".to_string(),
            Event::NoEarlierBreakpoint => "No earlier breakpoint: back at the start".to_string(),
            Event::Ended => "Program ended".to_string(),
            Event::Faulted => "Stopped on a fault".to_string(),
            Event::Reset => "Reset to the start".to_string(),
            Event::NotAssembled(n) => format!("{n} error(s) in the program: fix them to run"),
            Event::Assembled => "Program assembled".to_string(),
            Event::FutureDiscarded(t) => {
                format!("Edited at tick {t}: the recorded future after it was discarded")
            }
        }
    }
}

pub struct Debugger {
    dialect: &'static Dialect,
    name: String,
    source: String,
    /// The text the current program was assembled from.
    assembled_source: String,
    diagnostics: Vec<Diagnostic>,
    settings: Settings,
    engine: Box<dyn Engine>,
    /// The plot channels by location name (resolved against each assembled program).
    channel_names: Vec<ChannelChoice>,
    breakpoints: BTreeSet<usize>,
    goal: Option<Goal>,
    /// Skip the breakpoint on the current line once (resuming from it).
    resume_past_breakpoint: bool,
    speed: Speed,
    /// Commands owed at slow speeds (fractions carry over between frames).
    credit: f64,
    event: Option<Event>,
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

/// An empty program of `dialect`, for the moments before anything assembles.
fn empty_engine(dialect: &Dialect, settings: &Settings) -> Box<dyn Engine> {
    match (dialect.open)("", settings) {
        Ok(engine) => engine,
        // Every dialect accepts the empty program; fall back to the default one's if not.
        Err(_) => (registry::default_dialect().open)("", settings)
            .unwrap_or_else(|_| unreachable!("the default dialect accepts an empty program")),
    }
}

/// Why a typed value was not stored.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EditError {
    #[error("there is no location named '{0}'")]
    Unknown(String),
    #[error("{0}")]
    Value(String),
    #[error(transparent)]
    Refused(#[from] crate::machine::WriteError),
    #[error("fix the program's errors first: edits apply to a running program")]
    NotAssembled,
}

impl Debugger {
    /// A debugger on `source` in the default dialect (SilverLode).
    pub fn new(name: impl Into<String>, source: impl Into<String>) -> Self {
        Debugger::with_dialect(registry::default_dialect(), name, source)
    }

    /// A debugger on `source` in `dialect`. If it does not assemble, the diagnostics are kept
    /// and nothing runs until the text is fixed.
    pub fn with_dialect(
        dialect: &'static Dialect,
        name: impl Into<String>,
        source: impl Into<String>,
    ) -> Self {
        let settings = dialect.default_settings();
        let mut d = Debugger {
            dialect,
            name: name.into(),
            source: source.into(),
            assembled_source: String::new(),
            diagnostics: Vec::new(),
            engine: empty_engine(dialect, &settings),
            settings,
            channel_names: ChannelChoice::defaults(dialect),
            breakpoints: BTreeSet::new(),
            goal: None,
            resume_past_breakpoint: false,
            speed: Speed::PerSecond(10.0),
            credit: 0.0,
            event: None,
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
        source: impl Into<String>,
        settings: &Settings,
        breakpoints: impl IntoIterator<Item = usize>,
        channels: Option<Vec<ChannelChoice>>,
        events: Vec<UserEvent>,
        furthest: Pos,
    ) -> Result<Debugger, Vec<Diagnostic>> {
        let source = source.into();
        let settings = dialect.settings_from(settings);
        let engine = (dialect.open)(&source, &settings)?;
        let mut d = Debugger::with_dialect(dialect, name, "");
        d.assembled_source = source.clone();
        d.source = source;
        d.settings = settings;
        if let Some(channels) = channels {
            d.channel_names = channels;
        }
        let channels = d.resolve_channels(engine.machine());
        d.engine = engine.restarted(events, channels);
        d.engine.forward(furthest, &StopWhen::default());
        d.set_breakpoints(breakpoints);
        d.event = None;
        Ok(d)
    }

    // ---- reading ---------------------------------------------------------------------------

    pub fn name(&self) -> &str {
        &self.name
    }
    pub fn source(&self) -> &str {
        &self.source
    }
    /// The editable text. Edits take effect at the next assemble, step or run.
    pub fn source_mut(&mut self) -> &mut String {
        &mut self.source
    }
    pub fn is_edited(&self) -> bool {
        self.source != self.assembled_source
    }
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.diagnostics
    }
    pub fn has_errors(&self) -> bool {
        !self.diagnostics.is_empty()
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
    pub fn breakpoints(&self) -> &BTreeSet<usize> {
        &self.breakpoints
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

    /// Bytes the history holds (checkpoints, events, trace).
    pub fn history_bytes(&self) -> usize {
        self.engine.memory_bytes()
    }

    /// Write the trace as CSV (one row per tick where a value changed), atomically.
    /// Returns the number of rows.
    pub fn export_trace_csv(&self, path: &std::path::Path) -> std::io::Result<usize> {
        let micros = self.machine().tick_micros();
        let trace = self.engine.trace();
        let names: Vec<String> = self.channels().iter().map(|c| c.label.clone()).collect();
        crate::atomic::write_atomically(path, |w| trace.write_csv(w, micros, &names))?;
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
                let loc = m.find(&c.location)?;
                let info = m.info(loc)?;
                Some(Channel {
                    loc,
                    label: if c.label.is_empty() {
                        info.name.clone()
                    } else {
                        c.label.clone()
                    },
                    name: info.name,
                    width: info.width,
                    signed: info.signed,
                    group: c.group,
                })
            })
            .take(MAX_CHANNELS)
            .collect()
    }

    /// Choose the plot channels. The trace is rebuilt by replaying the recorded history.
    pub fn set_channels(&mut self, channels: Vec<ChannelChoice>) {
        self.channel_names = channels;
        self.channel_names.truncate(MAX_CHANNELS);
        let here = self.pos();
        let furthest = self.furthest();
        let resolved = self.resolve_channels(self.engine.machine());
        let marks: Vec<Mark> = self.marks().to_vec();
        let mut engine = self.engine.restarted(self.events().to_vec(), resolved);
        engine.forward(furthest, &StopWhen::default());
        for m in marks {
            engine.mark_at(m.at, m.kind, m.line);
        }
        engine.goto(here);
        self.engine = engine;
    }

    // ---- program ---------------------------------------------------------------------------

    /// Replace the whole program (File → Open). Breakpoints are cleared.
    pub fn load(&mut self, name: impl Into<String>, source: impl Into<String>) {
        let dialect = self.dialect;
        self.load_as(dialect, name, source);
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
            self.engine = empty_engine(dialect, &self.settings);
        }
        self.name = name.into();
        self.source = source.into();
        self.assembled_source.clear();
        self.breakpoints.clear();
        self.assemble();
    }

    /// Every input location and its level now.
    fn input_levels(m: &dyn MachineView) -> Vec<(Loc, u64)> {
        m.spaces()
            .iter()
            .enumerate()
            .filter(|(_, s)| s.kind == SpaceKind::Inputs)
            .flat_map(|(i, s)| (0..s.len).map(move |index| Loc::new(i as u8, index)))
            .map(|loc| (loc, m.read(loc)))
            .filter(|&(_, v)| v != 0)
            .collect()
    }

    /// A new timeline at the start of the current program, with the inputs at these levels.
    fn restart_with_inputs(&mut self, inputs: Vec<(Loc, u64)>) {
        let events = inputs
            .into_iter()
            .filter(|(loc, _)| self.engine.machine().info(*loc).is_some())
            .map(|(loc, v)| UserEvent {
                at: Pos::default(),
                loc,
                change: Change::Set(v),
            })
            .collect();
        let channels = self.resolve_channels(self.engine.machine());
        self.engine = self.engine.restarted(events, channels);
        self.goal = None;
    }

    /// Assemble the current text. On success the machine restarts on the new program and
    /// breakpoints follow the lines they were on; on failure the diagnostics are kept and the
    /// old state stays on screen, but nothing runs.
    pub fn assemble(&mut self) -> bool {
        self.goal = None;
        match (self.dialect.open)(&self.source, &self.settings) {
            Ok(engine) => {
                let moved = remap_lines(&self.assembled_source, &self.source, &self.breakpoints);
                self.breakpoints = moved;
                let inputs = Self::input_levels(self.engine.machine());
                self.engine = engine;
                self.restart_with_inputs(inputs);
                self.assembled_source = self.source.clone();
                self.diagnostics.clear();
                self.event = Some(Event::Assembled);
                true
            }
            Err(diagnostics) => {
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

    // ---- run control -----------------------------------------------------------------------

    /// Execute one instruction (F10). One that waits long continues over later frames.
    pub fn step_command(&mut self) {
        if !self.ready() || !self.live() {
            return;
        }
        self.goal = None;
        let start = self.pos();
        let limit = Pos::at_tick(start.tick.saturating_add(STEP_TICKS_AT_ONCE));
        let stop = StopWhen {
            after: Some(start),
            ..StopWhen::default()
        };
        if self.engine.forward(limit, &stop) == StopReason::TickLimit {
            self.goal = Some(Goal::FinishStep);
        } else {
            self.after_stop(Event::Stepped);
        }
    }

    /// Advance to the end of the current tick (F11): one tick, or the rest of the scan.
    pub fn step_tick(&mut self) {
        if !self.ready() || !self.live() {
            return;
        }
        self.goal = None;
        let next = Pos::at_tick(self.pos().tick + 1);
        self.engine.forward(next, &StopWhen::default());
        self.after_stop(Event::Stepped);
    }

    /// Run until a breakpoint, the end or a fault (F5).
    pub fn run(&mut self) {
        self.start(Goal::Continue);
    }

    /// Run until the instruction on `line` is about to execute (Ctrl+F10).
    pub fn run_to_line(&mut self, line: usize) {
        self.start(Goal::ToLine(line));
    }

    fn start(&mut self, goal: Goal) {
        if !self.ready() || !self.live() {
            return;
        }
        self.goal = Some(goal);
        self.credit = 0.0;
        self.resume_past_breakpoint = true;
        self.event = None;
    }

    /// Stop running (F6). Answers at once: the run only advances inside `advance`.
    pub fn pause(&mut self) {
        if self.goal.take().is_some() {
            self.event = Some(Event::Paused(self.machine().pc_line()));
        }
    }

    /// Back to the start of the program with a fresh timeline (Ctrl+Shift+F5), assembling edits
    /// first. Inputs keep their levels: they are switches on the bench, not program state.
    pub fn reset(&mut self) {
        self.goal = None;
        if self.is_edited() || self.has_errors() {
            self.assemble();
        } else {
            let inputs = Self::input_levels(self.machine());
            self.restart_with_inputs(inputs);
        }
        self.event = Some(Event::Reset);
    }

    pub fn set_speed(&mut self, speed: Speed) {
        self.speed = match speed {
            Speed::PerSecond(n) if !(n.is_finite() && n > 0.0) => Speed::PerSecond(1.0),
            s => s,
        };
        self.credit = 0.0;
    }

    fn live(&mut self) -> bool {
        let live = self.machine().run_state().is_live();
        if !live {
            self.after_stop(Event::Stepped);
        }
        live
    }

    fn after_stop(&mut self, otherwise: Event) {
        let state = self.machine().run_state();
        self.event = Some(match state {
            RunState::Ended => Event::Ended,
            RunState::Faulted => {
                let line = self.machine().fault().map_or(0, |f| f.line);
                self.engine.mark(MarkKind::Fault, line);
                Event::Faulted
            }
            _ => otherwise,
        });
        if !state.is_live() {
            self.goal = None;
        }
    }

    /// Run for this frame: `dt` seconds since the last frame (for slow speeds), `budget` the
    /// wall time it may take (for unlimited speed). Returns true while still running.
    pub fn advance(&mut self, dt: f64, budget: Duration) -> bool {
        let Some(goal) = self.goal else {
            return false;
        };
        if !self.machine().run_state().is_live() {
            self.after_stop(Event::Stepped);
            return false;
        }
        let started = Instant::now();
        let mut commands = match (goal, self.speed) {
            (Goal::FinishStep | Goal::ToTick(_), _) | (_, Speed::Unlimited) => u64::MAX,
            (_, Speed::PerSecond(n)) => {
                self.credit += n * dt.clamp(0.0, 0.25);
                let whole = self.credit.floor();
                self.credit -= whole;
                whole as u64
            }
        };
        let table = self.breakpoint_table();
        let line = match goal {
            Goal::ToLine(l) => Some(l),
            _ => None,
        };
        while commands > 0 {
            let skip = std::mem::take(&mut self.resume_past_breakpoint);
            let now = self.pos();
            let chunk = Pos::at_tick(now.tick.saturating_add(CHUNK_TICKS));
            let reason = match goal {
                // Mid-instruction, the next boundary ends the step; at one, it is over.
                Goal::FinishStep if self.machine().run_state() == RunState::Running => {
                    StopReason::Predicate
                }
                Goal::FinishStep => self.engine.forward(
                    chunk,
                    &StopWhen {
                        any: true,
                        ..StopWhen::default()
                    },
                ),
                Goal::ToTick(t) => {
                    match self
                        .engine
                        .forward(chunk.min(Pos::at_tick(t)), &StopWhen::default())
                    {
                        StopReason::TickLimit if self.pos().tick >= t => StopReason::Predicate,
                        other => other,
                    }
                }
                _ if commands == u64::MAX => self.engine.forward(
                    chunk,
                    &StopWhen {
                        breakpoints: &table,
                        line,
                        skip_first: skip,
                        ..StopWhen::default()
                    },
                ),
                _ => {
                    let at_stop = StopWhen {
                        breakpoints: &table,
                        line,
                        ..StopWhen::default()
                    };
                    if !skip && at_stop.holds(self.machine()) {
                        StopReason::Predicate
                    } else {
                        commands -= 1;
                        let one = StopWhen {
                            after: Some(now),
                            ..StopWhen::default()
                        };
                        let limit = Pos::at_tick(now.tick.saturating_add(STEP_TICKS_AT_ONCE));
                        match self.engine.forward(limit, &one) {
                            StopReason::Predicate => StopReason::TickLimit,
                            other => other,
                        }
                    }
                }
            };
            match reason {
                StopReason::Stopped => {
                    self.after_stop(Event::Stepped);
                    return false;
                }
                StopReason::Predicate => {
                    self.goal = None;
                    let line = self.machine().pc_line().unwrap_or(0);
                    self.event = Some(match goal {
                        Goal::FinishStep => Event::Stepped,
                        Goal::ToTick(t) => Event::ReachedTick(t),
                        Goal::ToLine(l) if l == line => Event::ReachedLine(line),
                        _ => {
                            self.engine.mark(MarkKind::Breakpoint, line);
                            Event::Breakpoint(line)
                        }
                    });
                    return false;
                }
                StopReason::TickLimit => {
                    if started.elapsed() >= budget {
                        break;
                    }
                }
            }
        }
        true
    }

    fn breakpoint_table(&self) -> Vec<bool> {
        let len = self.breakpoints.last().map_or(0, |&l| l + 1);
        let mut table = vec![false; len];
        for &l in &self.breakpoints {
            table[l] = true;
        }
        table
    }

    // ---- time travel -----------------------------------------------------------------------

    /// Go to any tick (its start). Within the recorded timeline this is a replay from the
    /// nearest checkpoint; beyond it the program runs there over the next frames.
    pub fn goto_tick(&mut self, tick: u64) {
        self.goto(Pos::at_tick(tick));
    }

    /// Go to any position, inside a tick too.
    pub fn goto(&mut self, pos: Pos) {
        self.goal = None;
        if self.has_errors() || self.is_edited() {
            return;
        }
        if pos <= self.furthest() {
            self.engine.goto(pos);
            self.event = Some(Event::ReachedTick(self.pos().tick));
        } else if self.machine().run_state().is_live() || self.pos() < self.furthest() {
            self.engine.goto(self.furthest());
            if pos.step == 0 {
                self.goal = Some(Goal::ToTick(pos.tick));
            } else {
                // Inside a tick beyond the history: short, so at once.
                self.engine.forward(pos, &StopWhen::default());
                self.event = Some(Event::ReachedTick(self.pos().tick));
            }
        }
    }

    /// Back to the start of the current tick, or of the previous one when already at a start
    /// (Shift+F11).
    pub fn step_back_tick(&mut self) {
        let now = self.pos();
        if now == Pos::default() || self.is_edited() {
            return;
        }
        self.goal = None;
        let to = if now.step > 0 {
            Pos::at_tick(now.tick)
        } else {
            Pos::at_tick(now.tick - 1)
        };
        self.engine.goto(to);
        self.event = Some(Event::SteppedBack);
    }

    /// Back to where the last instruction started (Shift+F10).
    pub fn step_back_command(&mut self) {
        let now = self.pos();
        if now == Pos::default() || self.is_edited() {
            return;
        }
        self.goal = None;
        let any = StopWhen {
            any: true,
            ..StopWhen::default()
        };
        let start = self.engine.find_back(now, &any).unwrap_or_default();
        self.engine.goto(start);
        self.event = Some(Event::SteppedBack);
    }

    /// Back to the last time a breakpoint was about to run, or the start (Shift+F5).
    pub fn reverse_continue(&mut self) {
        let now = self.pos();
        if now == Pos::default() || self.is_edited() {
            return;
        }
        self.goal = None;
        let table = self.breakpoint_table();
        let at_breakpoint = StopWhen {
            breakpoints: &table,
            ..StopWhen::default()
        };
        let hit = self.engine.find_back(now, &at_breakpoint);
        self.engine.goto(hit.unwrap_or_default());
        self.event = Some(match hit {
            Some(_) => Event::Breakpoint(self.machine().pc_line().unwrap_or(0)),
            None => Event::NoEarlierBreakpoint,
        });
    }

    // ---- breakpoints -----------------------------------------------------------------------

    /// Toggle a breakpoint on a 1-based line. Returns whether it is now set.
    pub fn toggle_breakpoint(&mut self, line: usize) -> bool {
        if line == 0 {
            return false;
        }
        if self.breakpoints.remove(&line) {
            false
        } else {
            self.breakpoints.insert(line);
            true
        }
    }

    pub fn set_breakpoints(&mut self, lines: impl IntoIterator<Item = usize>) {
        self.breakpoints = lines.into_iter().filter(|&l| l > 0).collect();
    }

    // ---- edits -----------------------------------------------------------------------------

    /// Change a location now; the edit becomes part of the timeline. A refused edit changes
    /// nothing.
    pub fn edit(&mut self, loc: Loc, change: Change) -> Result<(), EditError> {
        if self.has_errors() {
            return Err(EditError::NotAssembled);
        }
        let at = self.pos();
        if self.engine.edit(loc, change)? {
            self.event = Some(Event::FutureDiscarded(at.tick));
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
        let on = self.machine().read(loc) >> bit & 1 == 0;
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

    /// The dialect's settings; applying them restarts the program.
    pub fn set_settings(&mut self, settings: &Settings) {
        self.settings = self.dialect.settings_from(settings);
        self.assembled_source.clear();
        self.assemble();
    }
}

/// Move 1-based line numbers from `old` text to `new` text: lines in the unchanged head stay,
/// lines in the unchanged tail move with it, lines inside the changed middle stay where they
/// were (clamped to the new length).
pub fn remap_lines(old: &str, new: &str, lines: &BTreeSet<usize>) -> BTreeSet<usize> {
    if old.is_empty() {
        return lines.clone();
    }
    let old_lines: Vec<&str> = old.lines().collect();
    let new_lines: Vec<&str> = new.lines().collect();
    let head = old_lines
        .iter()
        .zip(&new_lines)
        .take_while(|(a, b)| a == b)
        .count();
    let max_tail = old_lines.len().min(new_lines.len()) - head;
    let tail = old_lines
        .iter()
        .rev()
        .zip(new_lines.iter().rev())
        .take(max_tail)
        .take_while(|(a, b)| a == b)
        .count();
    let old_tail_start = old_lines.len() - tail;
    let shift = new_lines.len() as i64 - old_lines.len() as i64;
    lines
        .iter()
        .filter_map(|&line| {
            let index = line - 1;
            let moved = if index < head {
                index as i64
            } else if index >= old_tail_start {
                index as i64 + shift
            } else {
                index.min(new_lines.len().saturating_sub(1)) as i64
            };
            (moved >= 0 && (moved as usize) < new_lines.len().max(1)).then_some(moved as usize + 1)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reg(d: &Debugger, r: u32) -> i32 {
        d.machine().read(Loc::new(0, r)) as u32 as i32
    }

    const LOOP: &str = "WRP 11, 3\nloop: CLC INC, 12\nCLC DEC, 11\nJMP loop, !ZERO\nEND\n";

    #[test]
    fn breakpoints_follow_inserted_and_deleted_lines() {
        let bps: BTreeSet<usize> = [1, 3, 5].into();
        let old = "a\nb\nc\nd\ne";
        assert_eq!(
            remap_lines(old, "a\nnew\nb\nc\nd\ne", &bps),
            [1, 4, 6].into()
        );
        assert_eq!(remap_lines(old, "a\nc\nd\ne", &bps), [1, 2, 4].into());
        assert_eq!(remap_lines(old, "a\nb\nC\nd\ne", &bps), [1, 3, 5].into());
    }

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
            1,
            "inputs keep their levels across a reset"
        );
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
