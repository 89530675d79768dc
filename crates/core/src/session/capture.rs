//! Capturing a debugging moment, or a run of the headless runner, as a session.

use std::path::PathBuf;

use super::{FORMAT_VERSION, SINGLE_FILE_FORMAT, Session, SessionEvent, SessionMark, ViewSettings};
use crate::debugger::history::{MarkKind, UserEvent};
use crate::debugger::{ChannelChoice, Debugger};
use crate::machine::MachineView;
use crate::machine::project::{Project, SourceFile};
use crate::registry::{Dialect, Settings};

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
            stopped: Some(!run.machine.run_state().is_live()),
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
        let hits: Vec<u64> = (0..list.len())
            .map(|i| debugger.breakpoint_hits(i))
            .collect();
        let any_hits = hits.iter().any(|&h| h > 0);
        let all_plain = list.iter().all(crate::debugger::Breakpoint::is_plain) && !any_hits;
        let plain = list
            .iter()
            .filter(|b| b.is_plain())
            .filter_map(crate::debugger::Breakpoint::line_number);
        let project = debugger.project();
        let mut session = Session {
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
            breakpoint_hits: if any_hits { hits } else { Vec::new() },
            event: debugger.event().cloned(),
            watches: debugger.watches().to_vec(),
            break_on_error: debugger.break_on_error(),
            channels: (channels != defaults.as_slice()).then(|| channels.to_vec()),
            furthest: debugger.furthest(),
            stopped: Some(debugger.stopped_at_furthest()),
            before_stop: debugger.stopped_at_furthest()
                && debugger.pos() == debugger.furthest()
                && debugger.machine().run_state().is_live(),
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
        };
        // The window's fields take no more than this; a text that came another way is cut
        // here, so what is saved always reads back.
        session.cut_long_texts();
        session
    }
}
