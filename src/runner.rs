//! The headless runner (`servoscope run`): run a program of any dialect to its end, a fault or
//! a tick limit, with an input timeline and initial values, and report the final state as text
//! or as one JSON object: a common header (`dialect`, `status`, `ticks`, `steps`, `fault`)
//! followed by the fields the dialect's spec defines.

use std::fmt::Write as _;

use crate::debugger::Engine;
use crate::debugger::history::{self, Change, UserEvent};
use crate::machine::registry::{AtLimit, Dialect};
use crate::machine::{Loc, Machine, MachineView, Pos, RunState, SpaceKind, value};

/// An input toggle: `input` flips when the tick counter equals `tick`, before that tick runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct InputToggle {
    pub tick: u64,
    pub input: Loc,
}

/// Why the arguments cannot be used.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ArgError {
    #[error("--input '{spec}': expected NAME=T1,T2,... with an input name such as {example}")]
    InputShape { spec: String, example: String },
    #[error(
        "--input '{spec}': '{name}' is not an input of this {dialect} program (inputs: {inputs})"
    )]
    NotAnInput {
        spec: String,
        name: String,
        dialect: &'static str,
        inputs: String,
    },
    #[error("--input '{spec}': '{tick}' is not a tick number")]
    BadTick { spec: String, tick: String },
    #[error("--set '{spec}': expected NAME=VALUE, e.g. R26=-5")]
    SetShape { spec: String },
    #[error("--set '{spec}': there is no location '{name}' in this {dialect} program")]
    UnknownLocation {
        spec: String,
        name: String,
        dialect: &'static str,
    },
    #[error("--set '{spec}': {source}")]
    BadValue {
        spec: String,
        source: value::ValueError,
    },
}

/// The names of a machine's inputs, shortened for messages.
fn input_names(m: &dyn MachineView) -> Vec<String> {
    m.spaces()
        .iter()
        .enumerate()
        .filter(|(_, s)| s.kind == SpaceKind::Inputs)
        .flat_map(|(i, s)| (0..s.len.min(4)).map(move |index| Loc::new(i as u8, index)))
        .filter_map(|loc| m.info(loc).map(|info| info.name))
        .collect()
}

fn is_input(m: &dyn MachineView, loc: Loc) -> bool {
    m.spaces()
        .get(usize::from(loc.space))
        .is_some_and(|s| s.kind == SpaceKind::Inputs)
}

/// Parse `NAME=T1,T2,...` into toggles of that input of `m`.
pub fn parse_input_spec(m: &dyn MachineView, spec: &str) -> Result<Vec<InputToggle>, ArgError> {
    let names = input_names(m);
    let (name, ticks) = spec.split_once('=').ok_or_else(|| ArgError::InputShape {
        spec: spec.to_string(),
        example: names.first().cloned().unwrap_or_default(),
    })?;
    let input = m
        .find(name)
        .filter(|&loc| is_input(m, loc))
        .ok_or_else(|| ArgError::NotAnInput {
            spec: spec.to_string(),
            name: name.trim().to_string(),
            dialect: m.dialect(),
            inputs: format!("{}, ...", names.join(", ")),
        })?;
    ticks
        .split(',')
        .map(|t| {
            let t = t.trim().replace('_', "");
            t.parse::<u64>()
                .map(|tick| InputToggle { tick, input })
                .map_err(|_| ArgError::BadTick {
                    spec: spec.to_string(),
                    tick: t.clone(),
                })
        })
        .collect()
}

/// Parse `NAME=VALUE` into an edit of that location at the start.
pub fn parse_set_spec(m: &dyn MachineView, spec: &str) -> Result<UserEvent, ArgError> {
    let (name, text) = spec.split_once('=').ok_or_else(|| ArgError::SetShape {
        spec: spec.to_string(),
    })?;
    let loc = m.find(name).ok_or_else(|| ArgError::UnknownLocation {
        spec: spec.to_string(),
        name: name.trim().to_string(),
        dialect: m.dialect(),
    })?;
    let width = m.info(loc).map_or(64, |i| i.width);
    let v = value::parse_value(text, width).map_err(|source| ArgError::BadValue {
        spec: spec.to_string(),
        source,
    })?;
    Ok(UserEvent {
        at: Pos::default(),
        loc,
        change: Change::Set(v),
    })
}

/// Input toggles as timeline events that set each input's level (inputs start low).
pub fn toggles_to_events(toggles: &[InputToggle]) -> Vec<UserEvent> {
    let mut toggles = toggles.to_vec();
    toggles.sort();
    let mut levels: std::collections::HashMap<Loc, bool> = Default::default();
    toggles
        .iter()
        .map(|t| {
            let level = levels.entry(t.input).or_insert(false);
            *level = !*level;
            UserEvent {
                at: Pos::at_tick(t.tick),
                loc: t.input,
                change: Change::Set(u64::from(*level)),
            }
        })
        .collect()
}

/// Run `machine` until it stops or reaches `max_ticks`, applying each event when the machine
/// reaches its position; events before the current position count as already applied. This is
/// the timeline's own replay, so a run and a session agree.
pub fn run_events<M: Machine>(machine: &mut M, events: &[UserEvent], max_ticks: u64) {
    let mut events = events.to_vec();
    events.sort_by_key(|e| e.at);
    let mut next = events.partition_point(|e| e.at < machine.pos());
    history::replay(
        machine,
        &events,
        &mut next,
        Pos::at_tick(max_ticks),
        |_| false,
        |_, _| {},
    );
}

/// Run `machine` until it stops or reaches `max_ticks`, toggling inputs on the way.
pub fn run_with_inputs<M: Machine>(machine: &mut M, toggles: &[InputToggle], max_ticks: u64) {
    run_events(machine, &toggles_to_events(toggles), max_ticks);
}

/// The final state of a run, as the runner prints it.
pub struct Report<'a> {
    pub dialect: &'a Dialect,
    pub machine: &'a dyn MachineView,
}

impl Report<'_> {
    pub fn status(&self) -> &'static str {
        match self.machine.run_state() {
            RunState::Ended => "ended",
            RunState::Faulted => "faulted",
            _ => match self.dialect.at_limit {
                AtLimit::Limit => "limit",
                AtLimit::Ended => "ended",
            },
        }
    }

    /// 0 ended, 1 faulted, 3 tick limit (2 is for files and arguments).
    pub fn exit_code(&self) -> u8 {
        match self.status() {
            "ended" => 0,
            "faulted" => 1,
            _ => 3,
        }
    }

    /// One JSON object: the common header, then the dialect's fields.
    pub fn to_json(&self) -> String {
        let m = self.machine;
        let fault = serde_json::to_string(&m.fault()).unwrap_or_else(|_| "null".to_string());
        let fields = m.report_json();
        let mut out = format!(
            "{{\"dialect\":\"{}\",\"status\":\"{}\",\"ticks\":{},\"steps\":{},\"fault\":{fault}",
            m.dialect(),
            self.status(),
            m.ticks(),
            m.steps()
        );
        if !fields.is_empty() {
            out.push(',');
            out.push_str(&fields);
        }
        out.push('}');
        out
    }

    /// A summary for people: status, counters, fault, then the dialect's lines.
    pub fn to_text(&self) -> String {
        let m = self.machine;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "status: {}  {}: {} ({:.3} ms)  steps: {}",
            self.status(),
            self.dialect.vocabulary.ticks,
            m.ticks(),
            m.ticks() as f64 * f64::from(m.tick_micros()) / 1000.0,
            m.steps()
        );
        if let Some(f) = m.fault() {
            let _ = writeln!(out, "fault: {} at line {}: {}", f.kind, f.line, f.message);
        }
        out.push_str(&m.report_text());
        out
    }
}

/// Run `engine`'s program from its start with `events` up to `max_ticks`, leaving the final
/// state in the returned engine.
pub fn run_engine(engine: &dyn Engine, events: &[UserEvent], max_ticks: u64) -> Box<dyn Engine> {
    let mut run = engine.restarted(Vec::new(), Vec::new());
    run.run_headless(events, max_ticks);
    run
}
