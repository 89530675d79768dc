//! Debug sessions saved to files: everything needed to rebuild a debugging moment exactly, and
//! nothing that can be recomputed. RON via serde, pretty-printed, with an explicit format
//! version.
//!
//! A session holds the program text (and where it came from), the dialect, breakpoints, servo
//! settings, the timeline of user events (input switches, register and bit edits, each with its
//! tick), the tick the user was at and the furthest tick reached, the timeline marks, and the
//! view settings. Loading replays the program deterministically to the furthest tick and goes
//! back to the saved one, so registers, flags, queues, the trace and the history are exactly
//! what they were.
//!
//! Compatibility: every field has a default, so files from older formats still load; a file
//! from a newer format is refused with a clear message. Saving writes a temporary file and
//! renames it over the target.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::debugger::format::Format;
use crate::debugger::history::{MarkKind, UserEvent};
use crate::debugger::{Debugger, Speed};
use crate::machine::Machine;
use crate::machine::silverlode::ServoSettings;

/// The session format this build writes. Version 1 is the first.
pub const FORMAT_VERSION: u32 = 1;
pub const DIALECT: &str = "silverlode";
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
    /// The program text itself, so a session opens anywhere.
    pub program: String,
    pub breakpoints: Vec<usize>,
    pub servo: ServoSettings,
    /// Input switches and edits, each with its tick (may lie after `tick`).
    pub events: Vec<UserEvent>,
    /// The tick the user was at.
    pub tick: u64,
    /// The furthest tick reached (the timeline is rebuilt up to here).
    pub furthest: u64,
    pub marks: Vec<SessionMark>,
    pub view: ViewSettings,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SessionMark {
    pub tick: u64,
    pub fault: bool,
    pub line: usize,
}

/// How the panels were set up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ViewSettings {
    pub register_format: Format,
    /// Formats chosen for single registers.
    pub register_formats: Vec<(usize, Format)>,
    pub only_used_registers: bool,
    pub selected_register: Option<usize>,
    pub plot_velocity: bool,
    pub speed: Speed,
}

impl Default for ViewSettings {
    fn default() -> Self {
        ViewSettings {
            register_format: Format::Signed,
            register_formats: Vec::new(),
            only_used_registers: true,
            selected_register: None,
            plot_velocity: false,
            speed: Speed::PerSecond(10.0),
        }
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
    #[error("{path}: the program in the session does not assemble: {first} ({count} error(s))")]
    Program {
        path: String,
        first: String,
        count: usize,
    },
    #[error("{path} asks to replay {ticks} ticks; servoscope replays at most {MAX_REPLAY_TICKS}")]
    TooLong { path: String, ticks: u64 },
    #[error("cannot encode the session: {0}")]
    Encode(String),
}

/// The fields read before the rest, so a newer or foreign file is recognised as such.
#[derive(Deserialize, Default)]
#[serde(default)]
struct Header {
    format: u32,
    dialect: String,
}

impl Session {
    /// The debugging moment as a session.
    pub fn capture(debugger: &Debugger, program_path: Option<PathBuf>, view: ViewSettings) -> Self {
        Session {
            format: FORMAT_VERSION,
            dialect: DIALECT.to_string(),
            program_name: debugger.name().to_string(),
            program_path,
            program: debugger.source().to_string(),
            breakpoints: debugger.breakpoints().iter().copied().collect(),
            servo: debugger.settings(),
            events: debugger.events().to_vec(),
            tick: debugger.machine().ticks(),
            furthest: debugger.furthest_tick(),
            marks: debugger
                .marks()
                .iter()
                .map(|m| SessionMark {
                    tick: m.tick,
                    fault: m.kind == MarkKind::Fault,
                    line: m.line,
                })
                .collect(),
            view,
        }
    }

    pub fn to_ron(&self) -> Result<String, SessionError> {
        let config = ron::ser::PrettyConfig::new()
            .depth_limit(6)
            .struct_names(false)
            .indentor("  ");
        ron::ser::to_string_pretty(self, config).map_err(|e| SessionError::Encode(e.to_string()))
    }

    /// Parse a session; `path` names the file in messages.
    pub fn from_ron(text: &str, path: &str) -> Result<Session, SessionError> {
        let malformed = |e: ron::error::SpannedError| SessionError::Malformed {
            path: path.to_string(),
            line: e.span.start.line,
            col: e.span.start.col,
            message: e.code.to_string(),
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
        if header.dialect != DIALECT {
            return Err(SessionError::Foreign {
                path: path.to_string(),
                reason: format!("its dialect is '{}', not '{DIALECT}'", header.dialect),
            });
        }
        ron::from_str(text).map_err(malformed)
    }

    pub fn load(path: &Path) -> Result<Session, SessionError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SessionError::Read {
            path: name.clone(),
            source,
        })?;
        Session::from_ron(&text, &name)
    }

    /// Write atomically: the old file stays intact if anything fails.
    pub fn save(&self, path: &Path) -> Result<(), SessionError> {
        let text = self.to_ron()?;
        crate::atomic::write_atomically(path, |w| w.write_all(text.as_bytes())).map_err(|source| {
            SessionError::Write {
                path: path.display().to_string(),
                source,
            }
        })
    }

    /// Rebuild the debugger: replay to the furthest tick, then go back to the saved one.
    pub fn restore(&self, path: &str) -> Result<Debugger, SessionError> {
        let furthest = self.furthest.max(self.tick);
        if furthest > MAX_REPLAY_TICKS {
            return Err(SessionError::TooLong {
                path: path.to_string(),
                ticks: furthest,
            });
        }
        let mut debugger = Debugger::restore(
            self.program_name.clone(),
            self.program.clone(),
            self.servo,
            self.breakpoints.iter().copied(),
            self.events.clone(),
            furthest,
        )
        .map_err(|diags| SessionError::Program {
            path: path.to_string(),
            first: diags.first().map(ToString::to_string).unwrap_or_default(),
            count: diags.len(),
        })?;
        debugger.restore_marks(self.marks.iter().map(|m| {
            let kind = if m.fault {
                MarkKind::Fault
            } else {
                MarkKind::Breakpoint
            };
            (m.tick, kind, m.line)
        }));
        if self.tick < debugger.machine().ticks() {
            debugger.goto_tick(self.tick);
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
        let other = Session::from_ron("(format: 1, dialect: \"tml\")", "s.ron");
        assert!(matches!(other, Err(SessionError::Foreign { .. })));
        let broken = Session::from_ron("(format: 1, dialect: \"silverlode\", tick: ", "s.ron");
        match broken {
            Err(SessionError::Malformed { line, .. }) => assert_eq!(line, 1),
            other => panic!("{other:?}"),
        }
        assert!(Session::from_ron("not ron at all {", "s.ron").is_err());
    }

    #[test]
    fn an_absurd_tick_is_refused_instead_of_replayed_forever() {
        let text = "(format: 1, dialect: \"silverlode\", program: \"l: JMP l\", tick: 18446744073709551615)";
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
        assert_eq!(s.tick, 0);
        assert_eq!(s.view, ViewSettings::default());
        let d = s.restore("old.ron").expect("restores");
        assert_eq!(d.machine().ticks(), 0);
    }
}
