//! Rebuilding the debugger from a session: its events resolved against the program, the
//! run replayed to the furthest position, then back to the saved one.

use super::{MAX_REPLAY_TICKS, Session, SessionError};
use crate::debugger::Debugger;
use crate::debugger::history::{MarkKind, UserEvent};
use crate::machine::project::Project;
use crate::machine::{MachineView, Pos};

impl Session {
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
        let fault_mark_at_end =
            self.stopped.is_none() && self.marks.iter().any(|m| m.fault && m.at == furthest);
        if self.stopped == Some(true)
            || fault_mark_at_end
            || !debugger.machine().run_state().is_live()
        {
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
        } else if self.before_stop && !debugger.machine().run_state().is_live() {
            debugger.goto_live(self.at);
        }
        debugger.set_breakpoint_hits(&self.breakpoint_hits);
        if let Some(event) = &self.event {
            debugger.set_event(event.clone());
        }
        debugger.set_speed(self.view.speed);
        Ok(debugger)
    }
}
