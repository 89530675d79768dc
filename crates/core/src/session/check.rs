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
        // What a user types (a condition, a watch, a lesson's text) is cut to the limit with a
        // warning, so a file an older build saved past it still opens; names, which come from
        // the program and cannot be cut without changing what they name, are refused.
        let cut = self.cut_long_texts();
        self.warnings.extend(cut);
        if let Some(lesson) = &mut self.lesson
            && let Some(ticks) = lesson.max_ticks
            && ticks > crate::lesson::MAX_LESSON_TICKS
        {
            lesson.max_ticks = Some(crate::lesson::MAX_LESSON_TICKS);
            self.warnings.push(format!(
                "the lesson asks to run {ticks} ticks; it is graded over {}, the most servoscope grades",
                crate::lesson::MAX_LESSON_TICKS
            ));
        }
        let texts = std::iter::once(self.program_name.as_str())
            .chain(self.files.iter().map(|f| f.name.as_str()))
            .chain(self.file_breakpoints.iter().map(|(f, _)| f.as_str()))
            .chain(self.breakpoint_list.iter().map(|b| match &b.kind {
                crate::debugger::BreakKind::Data { location, .. } => location.as_str(),
                crate::debugger::BreakKind::Line(_) => "",
            }))
            .chain(self.channels.iter().flatten().map(|c| c.location.as_str()))
            .chain(self.events.iter().map(|e| e.location.as_str()))
            .chain(self.view.formats.iter().map(|(name, _)| name.as_str()))
            .chain(self.view.selected.as_deref());
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

impl Session {
    /// Cut every text a user types (breakpoint conditions and log messages, watches, plot
    /// labels, the lesson's title, checks and step texts, the status bar's saved event) to
    /// the characters a session keeps: one limit for what is saved and what is read. Says what
    /// was cut.
    pub fn cut_long_texts(&mut self) -> Vec<String> {
        let mut said = Vec::new();
        let mut cut = |what: &str, text: &mut String, most: usize| {
            if let Some((end, _)) = text.char_indices().nth(most) {
                let chars = text.chars().count();
                let start: String = text.chars().take(24).collect();
                said.push(format!(
                    "{what} of {chars} characters (\"{start}…\") was cut to the {most} a session keeps"
                ));
                text.truncate(end);
            }
        };
        for b in &mut self.breakpoint_list {
            cut("a breakpoint condition", &mut b.condition, limits::TEXT);
            cut("a breakpoint's log message", &mut b.log, limits::TEXT);
        }
        for w in &mut self.watches {
            cut("a watch", &mut w.expr, limits::TEXT);
        }
        for c in self.channels.iter_mut().flatten() {
            cut("a plot label", &mut c.label, limits::TEXT);
        }
        if let Some(event) = &mut self.event {
            for text in event_texts(event) {
                cut("the status bar's event", text, limits::TEXT);
            }
        }
        if let Some(lesson) = &mut self.lesson {
            cut("the lesson's title", &mut lesson.title, limits::TEXT);
            for step in &mut lesson.steps {
                cut("a lesson step", &mut step.text, limits::STEP_TEXT);
                for check in &mut step.checks {
                    cut("a lesson check", check, limits::TEXT);
                }
            }
        }
        said
    }
}

/// The texts a saved status-bar event carries.
fn event_texts(event: &mut crate::debugger::Event) -> Vec<&mut String> {
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
