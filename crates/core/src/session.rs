//! Debug sessions saved to files: everything needed to rebuild a debugging moment exactly, and
//! nothing that can be recomputed. RON via serde, pretty-printed, with an explicit format
//! version.
//!
//! A session holds the program text (and where it came from), its dialect and the dialect's
//! settings, breakpoints, plot channels, the timeline of user events (each a location by name
//! and a change, at a (tick, step) position), the position the user was at and the furthest
//! one reached, the timeline marks, and the view settings. Loading replays the program
//! deterministically to the furthest position and goes back to the saved one, so every
//! location, the trace and the history are exactly what they were.
//!
//! Compatibility: format 1 (SilverLode only: events as `Input`/`Register`/`StatusBit`, the
//! servo model in `servo`, formats by register index) still loads, converted to format 2. Every
//! field has a default, so files missing fields load; a file from a newer format is refused
//! with a clear message. Saving writes a temporary file and renames it over the target.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::debugger::history::{Change, MarkKind, UserEvent};
use crate::debugger::{ChannelChoice, Debugger, Speed};
use crate::machine::project::{Project, SourceFile};
use crate::machine::{Format, MachineView, Pos};
use crate::registry::{self, Dialect, Settings};

/// The newest session format this build reads and writes. Format 3 adds the files of a program
/// of several files (`files`, `file_breakpoints`); a one-file program is still written as
/// format 2, which older builds read.
pub const FORMAT_VERSION: u32 = 3;
/// Format 1 was SilverLode's only: its files name no other dialect.
const FORMAT_1_DIALECT: &str = "silverlode";
/// The format of a session whose program is one file.
pub const SINGLE_FILE_FORMAT: u32 = 2;
/// The furthest tick a session may ask to replay to: 10^9 ticks (33 hours of servo time,
/// seconds to a minute of replay). Beyond it a damaged or hostile file could freeze the window.
pub const MAX_REPLAY_TICKS: u64 = 1_000_000_000;

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Session {
    /// Session format version; 0 means the field was missing (not a session).
    pub format: u32,
    pub dialect: String,
    /// The program's file name, for titles.
    pub program_name: String,
    /// Where the program was loaded from, if from a file.
    pub program_path: Option<PathBuf>,
    /// The program text itself, so a session opens anywhere (the top file's, for a program of
    /// several files).
    pub program: String,
    /// Format 3: the files the top file includes, in order of first inclusion, each with its
    /// name relative to the top file's directory and its text.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<SourceFile>,
    /// Format 3: plain line breakpoints in the included files, by file name and line
    /// (`breakpoints` holds the top file's). In `breakpoint_list`, a line of an included file
    /// is its program line: file k of `[top] + files` has lines k × 1048576 + line.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub file_breakpoints: Vec<(String, usize)>,
    /// The lines of plain line breakpoints (what every format-2 reader understands).
    pub breakpoints: Vec<usize>,
    /// Every breakpoint in the list's order, with conditions, hit counts, log points, data
    /// breakpoints and disabled ones. When present it is the whole truth and `breakpoints` is
    /// only for older readers; files from before it have only `breakpoints`.
    pub breakpoint_list: Vec<crate::debugger::Breakpoint>,
    pub watches: Vec<crate::debugger::Watch>,
    /// Stop a run when the dialect's error flags come on.
    pub break_on_error: bool,
    /// The dialect's settings (SilverLode: the servo model).
    pub settings: Settings,
    /// The plot channels; `None` means the dialect's defaults.
    pub channels: Option<Vec<ChannelChoice>>,
    /// Input switches and edits, each at its position (may lie after `at`).
    pub events: Vec<SessionEvent>,
    /// The position the user was at.
    pub at: Pos,
    /// The furthest position reached (the timeline is rebuilt up to here).
    pub furthest: Pos,
    pub marks: Vec<SessionMark>,
    pub view: ViewSettings,
    /// The run had ended or faulted at `furthest`: restoring runs the instruction there again,
    /// so the stop (its fault, flags and message) is restored too. Files from before this
    /// field say so with a fault mark at `furthest`.
    pub stopped: bool,
    /// A lesson's title and steps (see [`crate::lesson`]); `None` for an ordinary session.
    /// Format-2 readers before it ignore the field and open the lesson as a session.
    pub lesson: Option<crate::lesson::Lesson>,
    /// What reading the file dropped and why (breakpoints past the program's last line, marks
    /// past the furthest position): shown to the user, never saved.
    #[serde(skip)]
    pub warnings: Vec<String>,
}

/// Bounds on what a session file may ask for, far above anything servoscope writes: a number
/// in a damaged or hostile file is checked against these before anything is sized by it.
pub mod limits {
    /// Breakpoints (either list), watches and view formats, each.
    pub const LIST: usize = 10_000;
    /// User edits and timeline marks, each.
    pub const EVENTS: usize = 1_000_000;
    /// Characters of one condition, message, watch, channel, location or program name.
    pub const TEXT: usize = 4_096;
    /// Characters of one lesson step's text.
    pub const STEP_TEXT: usize = 65_536;
}

/// One user edit, by location name.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SessionEvent {
    pub at: Pos,
    pub location: String,
    pub change: Change,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SessionMark {
    pub at: Pos,
    pub fault: bool,
    pub line: usize,
}

/// How the panels were set up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ViewSettings {
    /// For readers before `every_location_as`; there `Signed` meant each location in its own
    /// reading.
    pub register_format: Format,
    /// The format chosen for every location; `None`: each in its dialect's reading. Files from
    /// before it have only `register_format`, read by [`ViewSettings::column`].
    pub every_location_as: Option<Format>,
    /// Formats chosen for single locations, by name.
    pub formats: Vec<(String, Format)>,
    pub only_used_registers: bool,
    /// The location selected in the register view, by name.
    pub selected: Option<String>,
    pub speed: Speed,
}

impl Default for ViewSettings {
    fn default() -> Self {
        ViewSettings {
            register_format: Format::Signed,
            every_location_as: None,
            formats: Vec::new(),
            only_used_registers: true,
            selected: None,
            speed: Speed::PerSecond(10.0),
        }
    }
}

impl ViewSettings {
    /// Settings that show every location in `column` (`None`: each in its own reading), in a
    /// form older readers understand too.
    pub fn with_column(mut self, column: Option<Format>) -> Self {
        self.every_location_as = column;
        self.register_format = column.unwrap_or(Format::Signed);
        self
    }

    /// The format chosen for every location, if one was. Older files say it only in
    /// `register_format`, where `Signed` (the default) meant each location in its own reading.
    pub fn column(&self) -> Option<Format> {
        self.every_location_as.or(match self.register_format {
            Format::Signed => None,
            f => Some(f),
        })
    }
}

#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    #[error("cannot read {path}: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    #[error("cannot write {path}: {source}")]
    Write {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}:{line}:{col}: not a readable session file: {message}")]
    Malformed {
        path: String,
        line: usize,
        col: usize,
        message: String,
    },
    #[error("{path} is not a servoscope session: {reason}")]
    Foreign { path: String, reason: String },
    #[error(
        "{path} was saved by a newer servoscope (session format {found}); this one reads formats up to {FORMAT_VERSION}"
    )]
    Newer { path: String, found: u32 },
    #[error("{path}: its program {program} does not assemble: {first} ({count} error(s))")]
    Program {
        path: String,
        /// The program's own name, with which `first` gives the program's line and column.
        program: String,
        first: String,
        count: usize,
    },
    #[error("{path}: an edit names '{location}', which this {dialect} program does not have")]
    UnknownLocation {
        path: String,
        location: String,
        dialect: &'static str,
    },
    #[error("{path}: edit {index} ({location} at {at}) cannot be made: {reason}")]
    BadEvent {
        path: String,
        index: usize,
        location: String,
        at: Pos,
        reason: String,
    },
    #[error("{path} cannot be honoured: {reason}")]
    Unreasonable { path: String, reason: String },
    #[error("{path} asks to replay {ticks} ticks; servoscope replays at most {MAX_REPLAY_TICKS}")]
    TooLong { path: String, ticks: u64 },
    #[error("cannot encode the session: {0}")]
    Encode(String),
    #[error("opening {path} was cancelled")]
    Cancelled { path: String },
    #[error("{path} exists and is not a session, so it was not replaced ({reason})")]
    WouldReplace { path: String, reason: String },
}

/// The fields read before the rest, so a newer or foreign file is recognised as such.
#[derive(Deserialize, Default)]
#[serde(default)]
struct Header {
    format: u32,
    dialect: String,
}

/// Format 1, as written by servoscope before dialects: SilverLode only.
mod v1 {
    use serde::Deserialize;

    #[derive(Deserialize, Default)]
    #[serde(default)]
    pub struct Session {
        pub program_name: String,
        pub program_path: Option<std::path::PathBuf>,
        pub program: String,
        pub breakpoints: Vec<usize>,
        pub servo: Servo,
        pub events: Vec<Event>,
        pub tick: u64,
        pub furthest: u64,
        pub marks: Vec<Mark>,
        pub view: View,
    }

    /// SilverLode's servo model as format 1 stored it; each field is the setting of that key.
    #[derive(Deserialize, Default)]
    #[serde(default)]
    pub struct Servo {
        pub natural_frequency_hz: Option<f64>,
        pub damping: Option<f64>,
        pub moving_error_limit: Option<u32>,
        pub holding_error_limit: Option<u32>,
    }

    impl Servo {
        pub fn settings(&self) -> crate::registry::Settings {
            [
                ("natural_frequency_hz", self.natural_frequency_hz),
                ("damping", self.damping),
                ("moving_error_limit", self.moving_error_limit.map(f64::from)),
                (
                    "holding_error_limit",
                    self.holding_error_limit.map(f64::from),
                ),
            ]
            .into_iter()
            .filter_map(|(key, value)| Some((key.to_string(), value?)))
            .collect()
        }
    }

    #[derive(Deserialize)]
    pub struct Event {
        pub tick: u64,
        pub edit: Edit,
    }

    #[derive(Deserialize)]
    pub enum Edit {
        Input { input: usize, high: bool },
        Register { register: usize, value: u32 },
        StatusBit { word: String, bit: u8, on: bool },
    }

    #[derive(Deserialize)]
    pub struct Mark {
        pub tick: u64,
        pub fault: bool,
        pub line: usize,
    }

    #[derive(Deserialize)]
    #[serde(default)]
    pub struct View {
        pub register_format: crate::machine::Format,
        pub register_formats: Vec<(usize, crate::machine::Format)>,
        pub only_used_registers: bool,
        pub selected_register: Option<usize>,
        #[allow(dead_code)]
        pub plot_velocity: bool,
        pub speed: crate::debugger::Speed,
    }

    impl Default for View {
        fn default() -> Self {
            View {
                register_format: crate::machine::Format::Signed,
                register_formats: Vec::new(),
                only_used_registers: true,
                selected_register: None,
                plot_velocity: false,
                speed: crate::debugger::Speed::PerSecond(10.0),
            }
        }
    }
}

impl From<v1::Session> for Session {
    fn from(old: v1::Session) -> Session {
        let event = |e: v1::Event| {
            let (location, change) = match e.edit {
                v1::Edit::Input { input, high } => {
                    // Wide enough for any number a file gives: IO18446744073709551616 is then
                    // refused by name, as an input the program does not have.
                    let number = input as u128 + 1;
                    (format!("IO{number}"), Change::Set(u64::from(high)))
                }
                v1::Edit::Register { register, value } => {
                    (format!("R{register}"), Change::Set(u64::from(value)))
                }
                v1::Edit::StatusBit { word, bit, on } => (word, Change::Bit { bit, on }),
            };
            SessionEvent {
                at: Pos::at_tick(e.tick),
                location,
                change,
            }
        };
        Session {
            format: FORMAT_VERSION,
            dialect: FORMAT_1_DIALECT.to_string(),
            program_name: old.program_name,
            program_path: old.program_path,
            program: old.program,
            breakpoints: old.breakpoints,
            // Clamped and completed as the dialect's settings are when the session restores.
            settings: registry::by_name(FORMAT_1_DIALECT).map_or_else(
                || old.servo.settings(),
                |d| d.settings_from(&old.servo.settings()),
            ),
            channels: None,
            events: old.events.into_iter().map(event).collect(),
            at: Pos::at_tick(old.tick),
            furthest: Pos::at_tick(old.furthest),
            marks: old
                .marks
                .into_iter()
                .map(|m| SessionMark {
                    at: Pos::at_tick(m.tick),
                    fault: m.fault,
                    line: m.line,
                })
                .collect(),
            view: ViewSettings {
                register_format: old.view.register_format,
                formats: old
                    .view
                    .register_formats
                    .into_iter()
                    .map(|(r, f)| (format!("R{r}"), f))
                    .collect(),
                only_used_registers: old.view.only_used_registers,
                selected: old.view.selected_register.map(|r| format!("R{r}")),
                speed: old.view.speed,
                every_location_as: None,
            },
            ..Session::default()
        }
    }
}

/// Why the existing file at `path` is not a session, if there is one that is not. Missing and
/// empty files, and sessions of any format, are fine to replace.
fn not_a_session(path: &Path) -> Option<String> {
    let path = crate::atomic::resolve(path).ok()?;
    let meta = std::fs::metadata(&path).ok()?;
    if meta.len() == 0 {
        return None;
    }
    let text = match crate::text::read(&path) {
        Ok(text) => text,
        Err(e) => return Some(e.to_string()),
    };
    match Session::from_ron(&text, &path.display().to_string()) {
        Ok(_) | Err(SessionError::Newer { .. } | SessionError::Program { .. }) => None,
        Err(e) => Some(e.to_string()),
    }
}

/// A file is a session when its extension is `.ron`.
pub fn is_session_path(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ron"))
}

/// User events by location name, for sessions.
pub fn named_events(m: &dyn MachineView, events: &[UserEvent]) -> Vec<SessionEvent> {
    events
        .iter()
        .map(|e| SessionEvent {
            at: e.at,
            location: m.info(e.loc).map_or_else(String::new, |i| i.name),
            change: e.change,
        })
        .collect()
}

/// What every session holds: the program, its dialect and settings, and the recorded edits.
pub struct Recorded<'a> {
    pub dialect: &'a Dialect,
    pub program_name: &'a str,
    pub program_path: Option<PathBuf>,
    pub program: &'a str,
    /// The included files of a program of several files (empty for one file).
    pub files: &'a [SourceFile],
    pub settings: &'a Settings,
    pub machine: &'a dyn MachineView,
    pub events: &'a [UserEvent],
}

impl Session {
    /// A session of a recorded run, at the machine's position (the runner's `--save-session`).
    pub fn of_run(run: Recorded<'_>) -> Self {
        Session {
            format: if run.files.is_empty() {
                SINGLE_FILE_FORMAT
            } else {
                FORMAT_VERSION
            },
            dialect: run.dialect.name.to_string(),
            program_name: run.program_name.to_string(),
            program_path: run.program_path,
            program: run.program.to_string(),
            files: run.files.to_vec(),
            settings: run.settings.clone(),
            events: named_events(run.machine, run.events),
            at: run.machine.pos(),
            furthest: run.machine.pos(),
            stopped: !run.machine.run_state().is_live(),
            ..Session::default()
        }
    }

    /// The debugging moment as a session.
    pub fn capture(debugger: &Debugger, program_path: Option<PathBuf>, view: ViewSettings) -> Self {
        Session::capture_parts(debugger, program_path, view, debugger.source())
    }

    /// The moment without the program text, for a cheap comparison every frame (the text is
    /// compared on its own, without copying it).
    pub fn capture_without_program(
        debugger: &Debugger,
        program_path: Option<PathBuf>,
        view: ViewSettings,
    ) -> Self {
        Session::capture_parts(debugger, program_path, view, "")
    }

    fn capture_parts(
        debugger: &Debugger,
        program_path: Option<PathBuf>,
        view: ViewSettings,
        program: &str,
    ) -> Self {
        let defaults = ChannelChoice::defaults(debugger.dialect());
        let channels = debugger.channel_choices();
        let included = debugger.project().files.get(1..).unwrap_or_default();
        let run = Session::of_run(Recorded {
            dialect: debugger.dialect(),
            program_name: debugger.name(),
            program_path,
            program,
            files: included,
            settings: debugger.settings(),
            machine: debugger.machine(),
            events: debugger.events(),
        });
        let list = debugger.breakpoint_list();
        let all_plain = list.iter().all(crate::debugger::Breakpoint::is_plain);
        let plain = list
            .iter()
            .filter(|b| b.is_plain())
            .filter_map(crate::debugger::Breakpoint::line_number);
        let project = debugger.project();
        Session {
            breakpoints: plain
                .clone()
                .filter(|&l| Project::split(l).0 == 0)
                .collect(),
            file_breakpoints: plain
                .filter_map(|l| {
                    let (file, local) = Project::split(l);
                    (file > 0).then(|| (project.file_of(l).to_string(), local))
                })
                .collect(),
            breakpoint_list: if all_plain { Vec::new() } else { list.to_vec() },
            watches: debugger.watches().to_vec(),
            break_on_error: debugger.break_on_error(),
            channels: (channels != defaults.as_slice()).then(|| channels.to_vec()),
            furthest: debugger.furthest(),
            stopped: debugger.stopped_at_furthest(),
            marks: debugger
                .marks()
                .iter()
                .map(|m| SessionMark {
                    at: m.at,
                    fault: m.kind == MarkKind::Fault,
                    line: m.line,
                })
                .collect(),
            view,
            ..run
        }
    }

    pub fn to_ron(&self) -> Result<String, SessionError> {
        let config = ron::ser::PrettyConfig::new()
            .depth_limit(6)
            .struct_names(false)
            .indentor("  ");
        ron::ser::to_string_pretty(self, config).map_err(|e| SessionError::Encode(e.to_string()))
    }

    /// Parse a session of any known format; `path` names the file in messages.
    pub fn from_ron(text: &str, path: &str) -> Result<Session, SessionError> {
        let text = &crate::text::normalize(text);
        let malformed = |e: ron::error::SpannedError| SessionError::Malformed {
            path: path.to_string(),
            line: e.span.start.line,
            col: e.span.start.col,
            message: match e.code {
                // ron's own advice (raise its recursion limit) is for programmers.
                ron::Error::ExceededRecursionLimit => {
                    "nested far deeper than any session; the file is damaged".to_string()
                }
                code => code.to_string(),
            },
        };
        let header: Header = ron::from_str(text).map_err(malformed)?;
        if header.format == 0 {
            return Err(SessionError::Foreign {
                path: path.to_string(),
                reason: "it has no session format number".to_string(),
            });
        }
        if header.format > FORMAT_VERSION {
            return Err(SessionError::Newer {
                path: path.to_string(),
                found: header.format,
            });
        }
        let known = if header.format == 1 {
            header.dialect == FORMAT_1_DIALECT
        } else {
            registry::by_name(&header.dialect).is_some()
        };
        if !known {
            return Err(SessionError::Foreign {
                path: path.to_string(),
                reason: format!(
                    "its dialect '{}' is not one servoscope knows ({})",
                    header.dialect,
                    registry::list()
                ),
            });
        }
        let mut session: Session = if header.format == 1 {
            let old: v1::Session = ron::from_str(text).map_err(malformed)?;
            old.into()
        } else {
            ron::from_str(text).map_err(malformed)?
        };
        session.check(path)?;
        Ok(session)
    }

    /// Bound every number and list the file gives by what it refers to, before anything is
    /// sized by it: refuse what cannot be honoured, drop (with a warning) breakpoints past the
    /// program's last line and marks past the furthest position.
    fn check(&mut self, path: &str) -> Result<(), SessionError> {
        let refuse = |reason: String| SessionError::Unreasonable {
            path: path.to_string(),
            reason,
        };
        if self.program.len() > crate::text::MAX_FILE_BYTES
            || self
                .files
                .iter()
                .any(|f| f.text.len() > crate::text::MAX_FILE_BYTES)
        {
            return Err(refuse(format!(
                "a file of its program has more than {} bytes, the most servoscope opens",
                crate::text::MAX_FILE_BYTES
            )));
        }
        if self.files.len() >= crate::machine::project::MAX_FILES {
            return Err(refuse(format!(
                "its program has {} files; servoscope opens programs of at most {}",
                self.files.len() + 1,
                crate::machine::project::MAX_FILES
            )));
        }
        let counts = [
            ("breakpoints", self.breakpoints.len(), limits::LIST),
            ("breakpoints", self.breakpoint_list.len(), limits::LIST),
            ("breakpoints", self.file_breakpoints.len(), limits::LIST),
            ("watches", self.watches.len(), limits::LIST),
            ("register formats", self.view.formats.len(), limits::LIST),
            ("edits", self.events.len(), limits::EVENTS),
            ("marks", self.marks.len(), limits::EVENTS),
            (
                "lesson steps",
                self.lesson.as_ref().map_or(0, |l| l.steps.len()),
                limits::LIST,
            ),
            (
                "lesson checks",
                self.lesson
                    .as_ref()
                    .map_or(0, |l| l.steps.iter().map(|s| s.checks.len()).sum()),
                limits::LIST,
            ),
            (
                "plot channels",
                self.channels.as_ref().map_or(0, Vec::len),
                crate::debugger::trace::MAX_CHANNELS,
            ),
        ];
        for (what, count, most) in counts {
            if count > most {
                return Err(refuse(format!(
                    "it has {count} {what}; at most {most} are kept"
                )));
            }
        }
        let texts = std::iter::once(self.program_name.as_str())
            .chain(self.files.iter().map(|f| f.name.as_str()))
            .chain(self.file_breakpoints.iter().map(|(f, _)| f.as_str()))
            .chain(self.breakpoint_list.iter().flat_map(|b| {
                let location = match &b.kind {
                    crate::debugger::BreakKind::Data { location, .. } => location.as_str(),
                    crate::debugger::BreakKind::Line(_) => "",
                };
                [b.condition.as_str(), b.log.as_str(), location]
            }))
            .chain(self.watches.iter().map(|w| w.expr.as_str()))
            .chain(
                self.channels
                    .iter()
                    .flatten()
                    .flat_map(|c| [c.location.as_str(), c.label.as_str()]),
            )
            .chain(self.events.iter().map(|e| e.location.as_str()))
            .chain(self.view.formats.iter().map(|(name, _)| name.as_str()))
            .chain(self.view.selected.as_deref())
            .chain(self.lesson.iter().flat_map(|l| {
                std::iter::once(l.title.as_str()).chain(
                    l.steps
                        .iter()
                        .flat_map(|s| s.checks.iter().map(String::as_str)),
                )
            }));
        let step_texts = self.lesson.iter().flat_map(|l| &l.steps).map(|s| &s.text);
        for text in step_texts {
            let chars = text.chars().count();
            if chars > limits::STEP_TEXT {
                return Err(refuse(format!(
                    "a lesson step of {chars} characters; at most {} are kept",
                    limits::STEP_TEXT
                )));
            }
        }
        for text in texts {
            let chars = text.chars().count();
            if chars > limits::TEXT {
                let start: String = text.chars().take(24).collect();
                return Err(refuse(format!(
                    "a text of {chars} characters (\"{start}…\"); at most {} are kept",
                    limits::TEXT
                )));
            }
        }
        let project = self.project();
        let counts: Vec<usize> = project
            .files
            .iter()
            .map(|f| f.text.lines().count())
            .collect();
        let past = |line: usize| {
            let (file, local) = Project::split(line);
            local > counts.get(file).copied().unwrap_or(0)
        };
        let mut dropped: Vec<usize> = self
            .breakpoints
            .iter()
            .copied()
            .filter(|&l| past(l))
            .collect();
        self.breakpoints.retain(|&l| !past(l));
        self.breakpoint_list.retain(|b| match b.line_number() {
            Some(l) if past(l) => {
                dropped.push(l);
                false
            }
            _ => true,
        });
        let mut unknown = Vec::new();
        self.file_breakpoints.retain(|(name, line)| {
            match project.index_of(name).filter(|&f| f > 0) {
                Some(f) if !past(Project::line(f, *line)) => true,
                Some(f) => {
                    dropped.push(Project::line(f, *line));
                    false
                }
                None => {
                    unknown.push(format!("{name}:{line}"));
                    false
                }
            }
        });
        dropped.sort_unstable();
        dropped.dedup();
        for line in dropped {
            let (file, _) = Project::split(line);
            self.warnings
                .push(if project.is_multi() && file < counts.len() {
                    format!(
                        "the breakpoint on line {} was dropped: {} has {} lines",
                        project.describe(line),
                        project.file_of(line),
                        counts[file]
                    )
                } else {
                    format!(
                        "the breakpoint on line {line} was dropped: the program has {} lines",
                        counts.first().copied().unwrap_or(0)
                    )
                });
        }
        for at in unknown {
            self.warnings.push(format!(
                "the breakpoint at {at} was dropped: the program has no such file"
            ));
        }
        let last_plot = crate::debugger::trace::PLOT_GROUPS - 1;
        for c in self.channels.iter_mut().flatten() {
            if c.group > last_plot {
                self.warnings.push(format!(
                    "the channel {} was on plot {}, which does not exist: it is on plot {} now",
                    c.location,
                    u16::from(c.group) + 1,
                    last_plot + 1
                ));
                c.group = last_plot;
            }
        }
        let furthest = self.furthest.max(self.at);
        let marks = self.marks.len();
        self.marks.retain(|m| m.at <= furthest);
        if self.marks.len() < marks {
            self.warnings.push(format!(
                "{} timeline mark(s) after the furthest position {furthest} were dropped",
                marks - self.marks.len()
            ));
        }
        Ok(())
    }

    pub fn load(path: &Path) -> Result<Session, SessionError> {
        let name = path.display().to_string();
        let text = crate::text::read(path).map_err(|e| match e {
            crate::text::TextError::Read { path, source } => SessionError::Read { path, source },
            other => SessionError::Foreign {
                path: name.clone(),
                reason: other.to_string(),
            },
        })?;
        Session::from_ron(&text, &name)
    }

    /// Write atomically: the old file stays intact if anything fails. A file at `path` that is
    /// not a session (a program, say) is not replaced: [`Session::save_over`] does that once
    /// the user confirmed.
    pub fn save(&self, path: &Path) -> Result<(), SessionError> {
        if let Some(reason) = not_a_session(path) {
            return Err(SessionError::WouldReplace {
                path: path.display().to_string(),
                reason,
            });
        }
        self.save_over(path)
    }

    /// Write atomically, replacing whatever regular file is at `path`.
    pub fn save_over(&self, path: &Path) -> Result<(), SessionError> {
        let text = self.to_ron()?;
        crate::atomic::write_atomically(path, |w| w.write_all(text.as_bytes())).map_err(|source| {
            SessionError::Write {
                path: path.display().to_string(),
                source,
            }
        })
    }

    /// The program's files: the top file (`program_name`, `program`), then `files`.
    pub fn project(&self) -> Project {
        let mut project = Project::single(self.program_name.clone(), self.program.clone());
        project.files.extend(self.files.iter().cloned());
        project
    }

    /// The files of the session's program that differ from the files on disk next to
    /// `program_path` (or are missing there): the session's copies are the ones used.
    pub fn changed_on_disk(&self) -> Vec<String> {
        let Some(top) = &self.program_path else {
            return Vec::new();
        };
        if self.files.is_empty() {
            return Vec::new();
        }
        let dir = top.parent().map(Path::to_path_buf).unwrap_or_default();
        self.project()
            .files
            .iter()
            .enumerate()
            .filter(|(k, f)| {
                let path = if *k == 0 {
                    top.clone()
                } else {
                    dir.join(&f.name)
                };
                crate::text::read(&path)
                    .map_or(true, |disk| disk != crate::text::normalize(&f.text))
            })
            .map(|(_, f)| f.name.clone())
            .collect()
    }

    /// The session's dialect (checked when the file was read).
    pub fn dialect(&self) -> &'static Dialect {
        registry::by_name(&self.dialect).unwrap_or_else(registry::default_dialect)
    }

    /// The events with their locations resolved against the session's program.
    pub fn user_events(
        &self,
        m: &dyn MachineView,
        path: &str,
    ) -> Result<Vec<UserEvent>, SessionError> {
        self.events
            .iter()
            .enumerate()
            .map(|(index, e)| {
                let loc = m
                    .find(&e.location)
                    .ok_or_else(|| SessionError::UnknownLocation {
                        path: path.to_string(),
                        location: e.location.clone(),
                        dialect: m.dialect(),
                    })?;
                let refused = |reason: String| SessionError::BadEvent {
                    path: path.to_string(),
                    index: index + 1,
                    location: e.location.clone(),
                    at: e.at,
                    reason,
                };
                let info = m
                    .info(loc)
                    .ok_or_else(|| refused("no such location".to_string()))?;
                e.change
                    .check(&info)
                    .map_err(|why| refused(why.to_string()))?;
                Ok(UserEvent {
                    at: e.at,
                    loc,
                    change: e.change,
                })
            })
            .collect()
    }

    /// Rebuild the debugger: replay to the furthest position, then go back to the saved one.
    pub fn restore(&self, path: &str) -> Result<Debugger, SessionError> {
        self.restore_with(path, &mut |_| true)
    }

    /// [`Session::restore`], reporting the tick reached while it replays; `go_on` returning
    /// false cancels (the window's Cancel button) with [`SessionError::Cancelled`].
    pub fn restore_with(
        &self,
        path: &str,
        go_on: &mut dyn FnMut(u64) -> bool,
    ) -> Result<Debugger, SessionError> {
        let furthest = self.furthest.max(self.at);
        if furthest.tick > MAX_REPLAY_TICKS {
            return Err(SessionError::TooLong {
                path: path.to_string(),
                ticks: furthest.tick,
            });
        }
        let dialect = self.dialect();
        let program = if self.program_name.is_empty() {
            "(unnamed)"
        } else {
            self.program_name.as_str()
        };
        let program_error = |diags: Vec<crate::machine::Diagnostic>| SessionError::Program {
            path: path.to_string(),
            program: program.to_string(),
            first: diags
                .first()
                .map(|d| d.with_file(program).to_string())
                .unwrap_or_default(),
            count: diags.len(),
        };
        let project = self.project();
        let probe = dialect
            .open_program(&project, &dialect.settings_from(&self.settings))
            .map_err(program_error)?;
        let events = self.user_events(probe.machine(), path)?;
        let breakpoints: Vec<usize> =
            self.breakpoints
                .iter()
                .copied()
                .chain(self.file_breakpoints.iter().filter_map(|(name, line)| {
                    project.index_of(name).map(|f| Project::line(f, *line))
                }))
                .collect();
        let mut debugger = Debugger::restore(
            dialect,
            self.program_name.clone(),
            project,
            &self.settings,
            breakpoints,
            self.channels.clone(),
            events,
            Pos::default(),
        )
        .map_err(program_error)?;
        if !self.breakpoint_list.is_empty() {
            debugger.set_breakpoint_list(self.breakpoint_list.clone());
        }
        debugger.set_watches(self.watches.clone());
        debugger.set_break_on_error(self.break_on_error);
        if !debugger.replay_to(furthest, go_on) {
            return Err(SessionError::Cancelled {
                path: path.to_string(),
            });
        }
        let fault_mark_at_end = self.marks.iter().any(|m| m.fault && m.at == furthest);
        if self.stopped || fault_mark_at_end || !debugger.machine().run_state().is_live() {
            debugger.replay_stop();
        }
        debugger.restore_marks(self.marks.iter().map(|m| {
            let kind = if m.fault {
                MarkKind::Fault
            } else {
                MarkKind::Breakpoint
            };
            (m.at, kind, m.line)
        }));
        if self.at < debugger.pos() {
            debugger.goto(self.at);
        }
        debugger.set_speed(self.view.speed);
        Ok(debugger)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newer_foreign_and_broken_files_are_refused_clearly() {
        let newer = Session::from_ron("(format: 99, dialect: \"silverlode\")", "s.ron");
        assert!(matches!(newer, Err(SessionError::Newer { found: 99, .. })));
        let foreign = Session::from_ron("(name: \"x\")", "s.ron");
        assert!(matches!(foreign, Err(SessionError::Foreign { .. })));
        let other = Session::from_ron("(format: 2, dialect: \"cobol\")", "s.ron");
        assert!(matches!(other, Err(SessionError::Foreign { .. })));
        let v1_other = Session::from_ron("(format: 1, dialect: \"tml\")", "s.ron");
        assert!(
            matches!(v1_other, Err(SessionError::Foreign { .. })),
            "format 1 was SilverLode only"
        );
        let broken = Session::from_ron("(format: 2, dialect: \"silverlode\", at: ", "s.ron");
        match broken {
            Err(SessionError::Malformed { line, .. }) => assert_eq!(line, 1),
            other => panic!("{other:?}"),
        }
        assert!(Session::from_ron("not ron at all {", "s.ron").is_err());
    }

    #[test]
    fn sessions_from_other_editors_and_damaged_ones() {
        let lf =
            "(format: 2, dialect: \"silverlode\", program: \"WRP 11, 1\\nEND\", at: (tick: 1))";
        let want = Session::from_ron(lf, "s.ron").expect("loads");
        let bom = format!("\u{feff}{}", lf.replace('\n', "\r\n"));
        assert_eq!(
            Session::from_ron(&bom, "s.ron").expect("a BOM is skipped"),
            want
        );
        let cr =
            "(format: 2,\rdialect: \"silverlode\",\rprogram: \"WRP 11, 1\\nEND\",\rat: (tick: 1))";
        assert_eq!(Session::from_ron(cr, "s.ron").expect("CR line ends"), want);
        let deep = format!(
            "(format: 2, dialect: \"silverlode\", view: {}",
            "(".repeat(10_000)
        );
        match Session::from_ron(&deep, "deep.ron") {
            Err(SessionError::Malformed { message, .. }) => {
                assert!(!message.contains("recursion_limit"), "{message}");
                assert!(message.contains("damaged"), "{message}");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn an_absurd_tick_is_refused_instead_of_replayed_forever() {
        let text = "(format: 1, dialect: \"silverlode\", program: \"l: JMP l\", tick: 18446744073709551615)";
        let s = Session::from_ron(text, "huge.ron").expect("parses");
        assert!(matches!(
            s.restore("huge.ron"),
            Err(SessionError::TooLong { .. })
        ));
        let text =
            "(format: 2, dialect: \"silverlode\", program: \"l: JMP l\", at: (tick: 2000000000))";
        let s = Session::from_ron(text, "huge.ron").expect("parses");
        assert!(matches!(
            s.restore("huge.ron"),
            Err(SessionError::TooLong { .. })
        ));
    }

    #[test]
    fn an_older_file_with_missing_fields_still_loads() {
        let s = Session::from_ron(
            "(format: 1, dialect: \"silverlode\", program: \"WRP 11, 1\\nEND\")",
            "old.ron",
        )
        .expect("loads");
        assert_eq!(s.at, Pos::default());
        assert_eq!(s.view, ViewSettings::default());
        let d = s.restore("old.ron").expect("restores");
        assert_eq!(d.machine().ticks(), 0);
    }

    #[test]
    fn a_format_1_input_number_at_the_edge_of_its_type_is_refused_by_name() {
        let text = "(format: 1, dialect: \"silverlode\", program: \"END\", \
                    events: [(tick: 0, edit: Input(input: 18446744073709551615, high: true))])";
        let s = Session::from_ron(text, "old.ron").expect("parses");
        match s.restore("old.ron") {
            Err(SessionError::UnknownLocation { location, .. }) => {
                assert_eq!(location, "IO18446744073709551616")
            }
            other => panic!("{:?}", other.map(|_| ())),
        }
    }

    #[test]
    fn an_edit_of_a_location_the_program_lacks_is_refused() {
        let text = "(format: 2, dialect: \"silverlode\", program: \"END\", \
                    events: [(at: (tick: 0), location: \"V1400\", change: Set(1))])";
        let s = Session::from_ron(text, "s.ron").expect("parses");
        match s.restore("s.ron") {
            Err(SessionError::UnknownLocation { location, .. }) => assert_eq!(location, "V1400"),
            other => panic!("{:?}", other.map(|_| ())),
        }
    }
}
