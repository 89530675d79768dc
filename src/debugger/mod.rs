//! Run control over a machine: the program text and its assembly, breakpoints, stepping
//! forward and back, running at a chosen speed in bounded slices, pausing, resetting, going to
//! any tick, and user edits that become part of the replayable timeline.
//!
//! No egui here: everything the GUI can do is a method a unit test can call. The GUI calls
//! [`Debugger::advance`] once per frame with a time budget, so a run never blocks a frame.

pub mod format;
pub mod history;
pub mod trace;

use std::collections::BTreeSet;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::machine::silverlode::{ServoSettings, SilverLode, assemble};
use crate::machine::{Diagnostic, Machine, RunState, StopReason};
use history::{Edit, Mark, MarkKind, Timeline, UserEvent};
use trace::Trace;

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

    pub fn label(self) -> String {
        match self {
            Speed::Unlimited => "unlimited".to_string(),
            Speed::PerSecond(n) if n >= 1000.0 => format!("{}k commands/s", n / 1000.0),
            Speed::PerSecond(n) => format!("{n} commands/s"),
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
    name: String,
    source: String,
    /// The text the current program was assembled from.
    assembled_source: String,
    diagnostics: Vec<Diagnostic>,
    settings: ServoSettings,
    initial: SilverLode,
    timeline: Timeline,
    breakpoints: BTreeSet<usize>,
    goal: Option<Goal>,
    /// Skip the breakpoint on the current line once (resuming from it).
    resume_past_breakpoint: bool,
    speed: Speed,
    /// Commands owed at slow speeds (fractions carry over between frames).
    credit: f64,
    event: Option<Event>,
}

impl Debugger {
    /// A debugger on `source`. If it does not assemble, the diagnostics are kept and nothing
    /// runs until the text is fixed.
    pub fn new(name: impl Into<String>, source: impl Into<String>) -> Self {
        let empty = SilverLode::new(crate::machine::silverlode::Program::empty());
        let mut d = Debugger {
            name: name.into(),
            source: source.into(),
            assembled_source: String::new(),
            diagnostics: Vec::new(),
            settings: ServoSettings::default(),
            initial: empty.clone(),
            timeline: Timeline::new(empty, Vec::new()),
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

    /// A debugger restored to `tick` of a recorded run: the program, its settings, its
    /// breakpoints and its timeline of user events (some may lie after `tick`).
    pub fn restore(
        name: impl Into<String>,
        source: impl Into<String>,
        settings: ServoSettings,
        breakpoints: impl IntoIterator<Item = usize>,
        events: Vec<UserEvent>,
        tick: u64,
    ) -> Result<Debugger, Vec<Diagnostic>> {
        let source = source.into();
        let program = assemble(&source)?;
        let settings = settings.clamped();
        let initial = SilverLode::with_settings(Arc::new(program), settings);
        let mut timeline = Timeline::new(initial.clone(), events);
        timeline.forward(tick, |_| false);
        let mut d = Debugger::new(name, "");
        d.assembled_source = source.clone();
        d.source = source;
        d.settings = settings;
        d.initial = initial;
        d.timeline = timeline;
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
    pub fn machine(&self) -> &SilverLode {
        &self.timeline.machine
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
    pub fn settings(&self) -> ServoSettings {
        self.settings
    }
    /// Registers the program's text mentions.
    pub fn used_registers(&self) -> &[u8] {
        &self.machine().program().used_registers
    }
    /// The motion trace since the last reset.
    pub fn trace(&self) -> &Trace {
        &self.timeline.trace
    }
    /// The furthest tick reached: the timeline spans 0 ..= this.
    pub fn furthest_tick(&self) -> u64 {
        self.timeline.furthest()
    }
    /// Every input switch and edit, with its tick.
    pub fn events(&self) -> &[UserEvent] {
        self.timeline.events()
    }
    /// Breakpoint hits and faults on the timeline.
    pub fn marks(&self) -> &[Mark] {
        self.timeline.marks()
    }
    /// Put back the marks of a saved session.
    pub fn restore_marks(&mut self, marks: impl IntoIterator<Item = (u64, MarkKind, usize)>) {
        for (tick, kind, line) in marks {
            self.timeline.mark_at(tick, kind, line);
        }
    }

    /// Bytes the history holds (checkpoints, events, trace).
    pub fn history_bytes(&self) -> usize {
        self.timeline.memory_bytes()
    }

    /// Write the trace as CSV (one row per tick where a value changed), atomically.
    /// Returns the number of rows.
    pub fn export_trace_csv(&self, path: &std::path::Path) -> std::io::Result<usize> {
        let micros = self.machine().tick_micros();
        let trace = &self.timeline.trace;
        crate::atomic::write_atomically(path, |w| trace.write_csv(w, micros))?;
        Ok(trace.len())
    }

    // ---- program ---------------------------------------------------------------------------

    /// Replace the whole program (File → Open). Breakpoints are cleared.
    pub fn load(&mut self, name: impl Into<String>, source: impl Into<String>) {
        self.name = name.into();
        self.source = source.into();
        self.assembled_source.clear();
        self.breakpoints.clear();
        self.assemble();
    }

    /// A new timeline at tick 0 on `initial`, with the inputs at their current levels.
    fn restart(&mut self) {
        let events = (0..3)
            .filter(|&i| self.machine().input(i))
            .map(|input| UserEvent {
                tick: 0,
                edit: Edit::Input { input, high: true },
            })
            .collect();
        self.timeline = Timeline::new(self.initial.clone(), events);
        self.goal = None;
    }

    /// Assemble the current text. On success the machine restarts on the new program and
    /// breakpoints follow the lines they were on; on failure the diagnostics are kept and the
    /// old state stays on screen, but nothing runs.
    pub fn assemble(&mut self) -> bool {
        self.goal = None;
        match assemble(&self.source) {
            Ok(program) => {
                let moved = remap_lines(&self.assembled_source, &self.source, &self.breakpoints);
                self.breakpoints = moved;
                self.initial = SilverLode::with_settings(Arc::new(program), self.settings);
                self.restart();
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

    /// Execute one command (F10). A command that waits long continues over later frames.
    pub fn step_command(&mut self) {
        if !self.ready() || !self.live() {
            return;
        }
        self.goal = None;
        let start = self.machine().ticks();
        let reason = self
            .timeline
            .forward(start.saturating_add(STEP_TICKS_AT_ONCE), |m| {
                m.ticks() > start
            });
        if reason == StopReason::TickLimit {
            self.goal = Some(Goal::FinishStep);
        } else {
            self.after_stop(Event::Stepped);
        }
    }

    /// Advance one tick (F11).
    pub fn step_tick(&mut self) {
        if !self.ready() || !self.live() {
            return;
        }
        self.goal = None;
        let now = self.machine().ticks();
        self.timeline.forward(now + 1, |_| false);
        self.after_stop(Event::Stepped);
    }

    /// Run until a breakpoint, the end or a fault (F5).
    pub fn run(&mut self) {
        self.start(Goal::Continue);
    }

    /// Run until the command on `line` is about to execute (Ctrl+F10).
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
            self.restart();
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
                self.timeline.mark(MarkKind::Fault, line);
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
        let bps = self.breakpoint_table();
        while commands > 0 {
            let skip = std::mem::take(&mut self.resume_past_breakpoint);
            let now = self.machine().ticks();
            let reason = match goal {
                // Mid-command, the next command boundary ends the step; at one, it is over.
                Goal::FinishStep if self.machine().run_state() == RunState::Running => {
                    StopReason::Predicate
                }
                Goal::FinishStep => self.timeline.forward(now + CHUNK_TICKS, |_| true),
                Goal::ToTick(t) => match self.timeline.forward(t.min(now + CHUNK_TICKS), |_| false)
                {
                    StopReason::TickLimit if self.machine().ticks() >= t => StopReason::Predicate,
                    other => other,
                },
                _ if commands == u64::MAX => {
                    let mut first = skip;
                    self.timeline.forward(now + CHUNK_TICKS, |m| {
                        let stop = !first && stops_at(&bps, goal, m.pc_line());
                        first = false;
                        stop
                    })
                }
                _ => {
                    if !skip && stops_at(&bps, goal, self.machine().pc_line()) {
                        StopReason::Predicate
                    } else {
                        commands -= 1;
                        match self
                            .timeline
                            .forward(now + STEP_TICKS_AT_ONCE, |m| m.ticks() > now)
                        {
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
                            self.timeline.mark(MarkKind::Breakpoint, line);
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

    /// Go to any tick. Within the recorded timeline this is a replay from the nearest
    /// checkpoint; beyond it the program runs there over the next frames.
    pub fn goto_tick(&mut self, tick: u64) {
        self.goal = None;
        if self.has_errors() || self.is_edited() {
            return;
        }
        if tick <= self.furthest_tick() {
            self.timeline.goto(tick);
            self.event = Some(Event::ReachedTick(self.machine().ticks()));
        } else if self.machine().run_state().is_live()
            || self.machine().ticks() < self.furthest_tick()
        {
            self.timeline.goto(self.furthest_tick());
            self.goal = Some(Goal::ToTick(tick));
        }
    }

    /// Back one tick (Shift+F11).
    pub fn step_back_tick(&mut self) {
        let now = self.machine().ticks();
        if now > 0 && !self.is_edited() {
            self.goal = None;
            self.timeline.goto(now - 1);
            self.event = Some(Event::SteppedBack);
        }
    }

    /// Back to where the last command started (Shift+F10).
    pub fn step_back_command(&mut self) {
        let now = self.machine().ticks();
        if now == 0 || self.is_edited() {
            return;
        }
        self.goal = None;
        let start = self.timeline.find_back(now, |_| true).unwrap_or(0);
        self.timeline.goto(start);
        self.event = Some(Event::SteppedBack);
    }

    /// Back to the last time a breakpoint was about to run, or the start (Shift+F5).
    pub fn reverse_continue(&mut self) {
        let now = self.machine().ticks();
        if now == 0 || self.is_edited() {
            return;
        }
        self.goal = None;
        let bps = self.breakpoint_table();
        let hit = self
            .timeline
            .find_back(now, |m| stops_at(&bps, Goal::Continue, m.pc_line()));
        self.timeline.goto(hit.unwrap_or(0));
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

    fn edit(&mut self, edit: Edit) {
        let tick = self.machine().ticks();
        if self.timeline.edit(edit) {
            self.event = Some(Event::FutureDiscarded(tick));
        }
    }

    pub fn set_register(&mut self, index: usize, value: u32) {
        if index < self.machine().register_count() {
            self.edit(Edit::Register {
                register: index,
                value,
            });
        }
    }

    /// Parse what the user typed and store it. On error nothing changes.
    pub fn set_register_text(&mut self, index: usize, text: &str) -> Result<u32, String> {
        if index >= self.machine().register_count() {
            return Err(format!("there is no register R{index}"));
        }
        let value = format::parse_value(text)?;
        self.set_register(index, value);
        Ok(value)
    }

    pub fn toggle_register_bit(&mut self, index: usize, bit: u8) {
        if bit < 32 {
            let value = self.machine().register(index) ^ (1 << bit);
            self.set_register(index, value);
        }
    }

    /// Set a status bit by hand; false (and nothing recorded) when that bit is not editable.
    pub fn set_status_bit(&mut self, word: &str, bit: u8, on: bool) -> bool {
        let mut probe = self.machine().clone();
        if !probe.set_status_bit(word, bit, on) {
            return false;
        }
        self.edit(Edit::StatusBit {
            word: word.to_string(),
            bit,
            on,
        });
        true
    }

    pub fn set_input(&mut self, index: usize, high: bool) {
        if index < self.machine().input_count() && self.machine().input(index) != high {
            self.edit(Edit::Input { input: index, high });
        }
    }

    pub fn set_settings(&mut self, settings: ServoSettings) {
        self.settings = settings.clamped();
        self.assembled_source.clear();
        self.assemble();
    }
}

fn stops_at(breakpoints: &[bool], goal: Goal, line: Option<usize>) -> bool {
    let Some(line) = line else {
        return false;
    };
    breakpoints.get(line).copied().unwrap_or(false) || goal == Goal::ToLine(line)
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
        assert_eq!(d.machine().reg(12), 0, "stopped before line 2 ran");
        d.run();
        d.advance(0.016, Duration::from_millis(50));
        assert_eq!(d.event(), Some(&Event::Breakpoint(2)));
        assert_eq!(d.machine().reg(12), 1, "one round later");
        d.toggle_breakpoint(2);
        d.run();
        d.advance(0.016, Duration::from_millis(50));
        assert_eq!(d.event(), Some(&Event::Ended));
        assert_eq!(d.machine().reg(12), 3);
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
        d.set_input(1, true);
        d.reset();
        assert_eq!(d.machine().ticks(), 0);
        assert!(
            d.machine().input(1),
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
        assert_eq!(d.machine().reg(11), 1, "edits assemble on the next step");
        assert!(d.diagnostics().is_empty());
    }

    #[test]
    fn register_edits_parse_or_change_nothing() {
        let mut d = Debugger::new("p", "END");
        assert_eq!(d.set_register_text(20, "0x10"), Ok(16));
        assert!(d.set_register_text(20, "banana").is_err());
        assert_eq!(d.machine().reg(20), 16);
        d.toggle_register_bit(20, 0);
        assert_eq!(d.machine().reg(20), 17);
        assert!(d.set_register_text(200, "1").is_err());
    }
}
