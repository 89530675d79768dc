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

mod capture;
mod check;
mod format1;
mod restore;
#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::debugger::history::Change;
use crate::debugger::{ChannelChoice, Speed};
use crate::machine::project::{Project, SourceFile};
use crate::machine::{Format, Pos};
use crate::registry::{self, Dialect, Settings};

pub use capture::{Recorded, named_events};
use format1::v1;

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
    /// Each breakpoint's hits so far, in `breakpoint_list`'s order (a session with hits
    /// writes that list even when every breakpoint is plain), so a "from hit N" breakpoint
    /// stops where it would have without the reopen.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub breakpoint_hits: Vec<u64>,
    /// What the status bar said the debugger last did (a breakpoint hit, who wrote a value).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub event: Option<crate::debugger::Event>,
    /// The window's own state (panel tabs, scroll positions) as text the window writes and
    /// reads; the core keeps it as it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub window: Option<String>,
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
    /// so the stop (its fault, flags and message) is restored too. Written as a plain bool;
    /// `None` for a file from before this field, whose fault mark at `furthest` says so
    /// (today's error-lamp stops leave such a mark on a run that goes on).
    #[serde(with = "known_bool")]
    pub stopped: Option<bool>,
    /// `at` is the furthest position of a run that stopped there, and the debugger was paused
    /// just before the stopping instruction (stepped up to a SilverLode fault, which leaves the
    /// position where the instruction began), not at the stop.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub before_stop: bool,
    /// A lesson's title and steps (see [`crate::lesson`]); `None` for an ordinary session.
    /// Format-2 readers before it ignore the field and open the lesson as a session.
    pub lesson: Option<crate::lesson::Lesson>,
    /// What reading the file dropped and why (breakpoints past the program's last line, marks
    /// past the furthest position): shown to the user, never saved.
    #[serde(skip)]
    pub warnings: Vec<String>,
}

/// A bool in the file, `None` when the file does not have the field.
mod known_bool {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(value: &Option<bool>, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bool(value.unwrap_or(false))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<bool>, D::Error> {
        bool::deserialize(d).map(Some)
    }
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
    /// Characters of one lesson step's text, and of the window's state.
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

/// Why the existing file at `path` is not a session, if there is one that is not. Missing and
/// empty files, and sessions of any format, are fine to replace.
pub(crate) fn not_a_session(path: &Path) -> Option<String> {
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

impl Session {
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
    /// `program_path` (or are missing there): the session's copies are the ones used. A file
    /// the session names outside the program's folder (and outside the folders `folders`
    /// allows) is not read: a crafted session must not make servoscope read, or later write,
    /// a file elsewhere; it counts as changed.
    pub fn changed_on_disk(
        &self,
        folders: &crate::machine::project::IncludeFolders,
    ) -> Vec<String> {
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
                    Some(top.clone())
                } else {
                    folders.path_of(&dir, &f.name)
                };
                path.is_none_or(|path| {
                    crate::text::read(&path)
                        .map_or(true, |disk| disk != crate::text::normalize(&f.text))
                })
            })
            .map(|(_, f)| f.name.clone())
            .collect()
    }

    /// The session's dialect (checked when the file was read).
    pub fn dialect(&self) -> &'static Dialect {
        registry::by_name(&self.dialect).unwrap_or_else(registry::default_dialect)
    }
}
