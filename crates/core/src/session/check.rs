//! What a session file may give: every number and list bounded by what it refers to before
//! anything is sized by it, and the breakpoints, channels and marks that no longer fit
//! dropped with a warning.

use super::{Session, SessionError, limits};
use crate::machine::project::Project;

impl Session {
    /// Bound every number and list the file gives by what it refers to, before anything is
    /// sized by it: refuse what cannot be honoured, drop (with a warning) breakpoints past the
    /// program's last line and marks past the furthest position.
    pub(super) fn check(&mut self, path: &str) -> Result<(), SessionError> {
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
            (
                "breakpoint hit counts",
                self.breakpoint_hits.len(),
                limits::LIST,
            ),
            (
                "characters of window state",
                self.window.as_ref().map_or(0, String::len),
                limits::STEP_TEXT,
            ),
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
            .chain(self.event.iter().flat_map(event_texts))
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
}

/// The texts a saved status-bar event carries.
fn event_texts(event: &crate::debugger::Event) -> Vec<&str> {
    use crate::debugger::Event;
    match event {
        Event::Watchpoint {
            location, old, new, ..
        } => vec![location, old, new],
        Event::WrittenBy {
            location,
            explanation,
            ..
        } => vec![location, explanation],
        Event::NeverWritten(name) => vec![name],
        _ => Vec::new(),
    }
}
