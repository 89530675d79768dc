//! The headless runner (`servoscope run`): run a program of any dialect to its end, a fault or
//! a tick limit, with an input timeline and initial values, and report the final state as text
//! or as one JSON object: a common header (`dialect`, `status`, `ticks`, `steps`, `fault`)
//! followed by the fields the dialect's spec defines.

use std::fmt::Write as _;

use serde_json::{Value, json};

use crate::debugger::Engine;
use crate::debugger::expr::Expr;
use crate::debugger::history::{self, Change, UserEvent};
use crate::machine::project::Project;
use crate::machine::{
    Diagnostic, JsonMap, Loc, Machine, MachineView, Pos, RunState, Severity, SpaceKind, StopReason,
    value,
};
use crate::registry::{AtLimit, Dialect};

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
    #[error(
        "--set '{spec}': {name} is the {kind}'s bit (0 or 1); its current value is {name}.current (--set {name}.current={value})"
    )]
    BitOfBox {
        spec: String,
        name: String,
        kind: &'static str,
        value: String,
    },
    #[error("--set '{spec}': {source}")]
    BadValue {
        spec: String,
        source: value::ValueError,
    },
    #[error("--force '{spec}': expected NAME=1|0[@SCAN], e.g. Y0=1@100")]
    ForceShape { spec: String },
    #[error("--force '{spec}': {reason}")]
    CannotForce { spec: String, reason: String },
}

/// Parse `NAME=1|0[@SCAN]` into a force of that bit from that scan (from the start without
/// `@SCAN`). ON/OFF are taken for 1/0.
pub fn parse_force_spec(m: &dyn MachineView, spec: &str) -> Result<UserEvent, ArgError> {
    let shape = || ArgError::ForceShape {
        spec: spec.to_string(),
    };
    let (name, rest) = spec.split_once('=').ok_or_else(shape)?;
    let (level, at) = match rest.split_once('@') {
        Some((l, t)) => (l, Some(t)),
        None => (rest, None),
    };
    let on = match level.trim().to_ascii_uppercase().as_str() {
        "1" | "ON" => true,
        "0" | "OFF" => false,
        _ => return Err(shape()),
    };
    let tick = match at {
        Some(t) => t.trim().parse::<u64>().map_err(|_| shape())?,
        None => 0,
    };
    let cannot = |reason: String| ArgError::CannotForce {
        spec: spec.to_string(),
        reason,
    };
    let loc = m.find(name).ok_or_else(|| {
        cannot(format!(
            "there is no location '{}' in this {} program",
            name.trim(),
            m.dialect()
        ))
    })?;
    if !m.can_force(loc) {
        let name = m
            .info(loc)
            .map_or_else(|| name.trim().to_string(), |i| i.name);
        return Err(cannot(format!(
            "{name} cannot be forced (inputs, outputs and relays can)"
        )));
    }
    Ok(UserEvent {
        at: Pos::at_tick(tick),
        loc,
        change: Change::Force(Some(on)),
    })
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
    let info = m.info(loc);
    let width = info.as_ref().map_or(64, |i| i.width);
    // OpenNet's `C0` and `T0` are the box's bit; a number is meant for its current value.
    let trimmed = name.trim();
    if width == 1
        && value::parse_value(text, 1).is_err()
        && m.find(&format!("{trimmed}.current")).is_some()
    {
        let kind = if trimmed.to_ascii_uppercase().starts_with('T') {
            "timer"
        } else {
            "counter"
        };
        return Err(ArgError::BitOfBox {
            spec: spec.to_string(),
            name: trimmed.to_string(),
            kind,
            value: text.trim().to_string(),
        });
    }
    let bad = |source| ArgError::BadValue {
        spec: spec.to_string(),
        source,
    };
    // A location read as unsigned (DL205 V words: 0–65535) takes no negative value.
    if let Some(info) = &info
        && !info.signed
        && info.reading() != value::Format::Signed
        && text.trim_start().starts_with('-')
        && width < 64
    {
        return Err(bad(value::ValueError::TooWide {
            text: text.trim().to_string(),
            width,
            min: 0,
            max: (1i128 << width) - 1,
        }));
    }
    // A fixed-point location takes a decimal number as TML writes it (`10.`, `2.5`).
    let is_decimal = text.contains('.') && !text.contains('(');
    let v = match &info {
        Some(info) if info.reading() == value::Format::Q16 && is_decimal => {
            value::parse_value(&format!("q16({})", text.trim()), width)
        }
        _ => value::parse_value(text, width),
    }
    .map_err(bad)?;
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

/// Run `machine` until it stops or reaches `max_ticks`, toggling inputs on the way.
pub fn run_with_inputs<M: Machine>(machine: &mut M, toggles: &[InputToggle], max_ticks: u64) {
    history::run_events_bare(machine, &toggles_to_events(toggles), max_ticks);
}

/// Where `--break` stopped a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BreakHit {
    pub expr: String,
    pub at: Pos,
    /// The line about to run.
    pub line: Option<usize>,
}

/// The final state of a run, as the runner prints it.
pub struct Report<'a> {
    pub dialect: &'a Dialect,
    pub machine: &'a dyn MachineView,
    /// The program's files: positions in a program of several files name their file (spec
    /// tml.md §9); a one-file program reports lines alone, as it always did.
    pub project: Option<&'a Project>,
    /// The run stopped because `--break` came true.
    pub broke: Option<BreakHit>,
}

impl Report<'_> {
    pub fn status(&self) -> &'static str {
        if self.broke.is_some() {
            return "break";
        }
        match self.machine.run_state() {
            RunState::Ended => "ended",
            RunState::Faulted => "faulted",
            _ => match self.dialect.at_limit {
                AtLimit::Limit => "limit",
                AtLimit::Ended => "ended",
            },
        }
    }

    /// 0 ended, 1 faulted, 3 tick limit, 4 `--break` came true (2 is for files and
    /// arguments).
    pub fn exit_code(&self) -> u8 {
        match self.status() {
            "ended" => 0,
            "faulted" => 1,
            "break" => 4,
            _ => 3,
        }
    }

    /// The project when it has several files.
    fn files(&self) -> Option<&Project> {
        self.project.filter(|p| p.is_multi())
    }

    /// One JSON object: the common header, then the dialect's fields.
    pub fn to_json(&self) -> String {
        let m = self.machine;
        let fault = match (m.fault(), self.files()) {
            (Some(f), Some(p)) => json!({
                "kind": f.kind,
                "message": f.message,
                "line": Project::split(f.line).1,
                "file": p.file_of(f.line),
            }),
            (f, _) => serde_json::to_value(f).unwrap_or(Value::Null),
        };
        let mut out = JsonMap::new();
        out.insert("dialect".into(), json!(m.dialect()));
        out.insert("status".into(), json!(self.status().to_string()));
        out.insert("ticks".into(), json!(m.ticks()));
        out.insert("steps".into(), json!(m.steps()));
        out.insert("fault".into(), fault);
        if let Some(b) = &self.broke {
            let mut at = JsonMap::new();
            at.insert("expr".into(), json!(b.expr));
            at.insert("tick".into(), json!(b.at.tick));
            at.insert("step".into(), json!(b.at.step));
            at.insert("line".into(), json!(b.line.map(|l| Project::split(l).1)));
            insert_file(&mut at, self.files(), b.line);
            out.insert("break".into(), at.into());
        }
        m.report_json(&mut out);
        Value::Object(out).to_string()
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
        let describe = |line: usize| match self.files() {
            Some(p) => p.describe(line),
            None => line.to_string(),
        };
        if let Some(f) = m.fault() {
            let _ = writeln!(
                out,
                "fault: {} at line {}: {}",
                f.kind,
                describe(f.line),
                f.message
            );
        }
        if let Some(b) = &self.broke {
            let line = b
                .line
                .map_or_else(String::new, |l| format!(", before line {}", describe(l)));
            let _ = writeln!(out, "break: {} at {}{line}", b.expr, b.at);
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

/// [`run_engine`] within a wall-clock budget, for a grading loop that must always finish: the
/// clock is read every few thousand instruction boundaries (a scan that turns slow half-way,
/// or one long scan, cannot outrun it), and the run stops at the first boundary past
/// `deadline`. Returns the run and whether it got to `max_ticks` or the program stopped. One
/// run from the start, events applied as a straight run applies them: only pacing lives
/// here, never inside the machine.
pub fn run_engine_until(
    engine: &dyn Engine,
    events: &[UserEvent],
    max_ticks: u64,
    deadline: std::time::Instant,
) -> (Box<dyn Engine>, bool) {
    let mut run = engine.restarted(Vec::new(), Vec::new());
    let mut boundaries: u32 = 0;
    let reason = run.run_headless_observed(events, max_ticks, &mut |_| {
        boundaries = boundaries.wrapping_add(1);
        boundaries.is_multiple_of(CLOCK_EVERY) && std::time::Instant::now() >= deadline
    });
    (run, reason != StopReason::Predicate)
}

/// Instruction boundaries between two readings of the clock in [`run_engine_until`].
const CLOCK_EVERY: u32 = 4096;

/// The file of `line` as `"file"`, for a program of several files.
fn insert_file(out: &mut JsonMap, files: Option<&Project>, line: Option<usize>) {
    if let (Some(p), Some(l)) = (files, line) {
        out.insert("file".into(), json!(p.file_of(l)));
    }
}

/// What the runner watches while it runs: `--trace` and `--break`.
#[derive(Default)]
pub struct Probe<'a> {
    /// One JSON object per executed instruction goes here.
    pub trace: Option<&'a mut dyn std::io::Write>,
    /// Stop at the first instruction boundary where this holds.
    pub until: Option<Expr>,
}

/// The first word of a source line's statement: its mnemonic as written (after a label; for a
/// TML assignment, the name assigned).
pub fn mnemonic(line: &str) -> &str {
    let code = line.trim();
    let code = match code.split_once(':') {
        Some((label, rest))
            if !label.is_empty() && label.chars().all(|c| c.is_alphanumeric() || c == '_') =>
        {
            rest.trim_start()
        }
        _ => code,
    };
    let end = code
        .find(|c: char| c.is_whitespace() || c == ';' || c == ',')
        .unwrap_or(code.len());
    &code[..end]
}

/// One `--trace` line: the executed instruction's start position, its line and mnemonic, the
/// locations it wrote with their new values (what the instruction wrote, flags included, not
/// what a motion model drove in the same tick), and its explanation.
fn trace_line(
    m: &dyn MachineView,
    n: u64,
    started: Pos,
    source: &[Vec<&str>],
    files: Option<&Project>,
) -> String {
    let line = m.last_line();
    // A line of several statements (TML) names each by its own text.
    let word = m.last_statement_text().map_or_else(
        || {
            line.and_then(|l| {
                let (file, local) = Project::split(l);
                source.get(file)?.get(local.wrapping_sub(1))
            })
            .map_or("", |text| mnemonic(text))
        },
        mnemonic,
    );
    let mut out = JsonMap::new();
    out.insert("n".into(), json!(n));
    out.insert("tick".into(), json!(started.tick));
    out.insert("step".into(), json!(started.step));
    out.insert("line".into(), json!(line.map(|l| Project::split(l).1)));
    insert_file(&mut out, files, line);
    out.insert("mnemonic".into(), json!(word));
    let written: JsonMap = (m.instruction_written().into_iter())
        .filter_map(|loc| Some((m.info(loc)?.name, crate::machine::json_in_reading(m, loc))))
        .collect();
    out.insert("written".into(), written.into());
    // The status bar's words for the step, overflow and carry notes included.
    out.insert(
        "explain".into(),
        json!(m.explain_last().unwrap_or_default()),
    );
    let mut text = Value::Object(out).to_string();
    text.push('\n');
    text
}

/// Run `engine`'s program from its start like [`run_engine`], writing the `--trace` and
/// stopping at `--break`. Returns the final engine, where the break stopped, and the first
/// error writing the trace (the run stops there).
pub fn run_engine_probed(
    engine: &dyn Engine,
    events: &[UserEvent],
    max_ticks: u64,
    project: &Project,
    mut probe: Probe<'_>,
) -> (Box<dyn Engine>, Option<BreakHit>, Option<std::io::Error>) {
    let mut run = engine.restarted(Vec::new(), Vec::new());
    let lines: Vec<Vec<&str>> = project
        .files
        .iter()
        .map(|f| f.text.lines().collect())
        .collect();
    let files = project.is_multi().then_some(project);
    let mut seen = run.machine().steps();
    let mut started = run.machine().pos();
    let mut error = None;
    let mut broke = None;
    let mut emit = |m: &dyn MachineView,
                    seen: &mut u64,
                    started: &mut Pos,
                    out: &mut Option<&mut dyn std::io::Write>|
     -> bool {
        if m.steps() > *seen {
            if let Some(w) = out.as_mut()
                && let Err(e) =
                    w.write_all(trace_line(m, m.steps(), *started, &lines, files).as_bytes())
            {
                error = Some(e);
                return false;
            }
            *seen = m.steps();
        }
        *started = m.pos();
        true
    };
    let reason = run.run_headless_observed(events, max_ticks, &mut |m| {
        if !emit(m, &mut seen, &mut started, &mut probe.trace) {
            return true;
        }
        if let Some(e) = &probe.until
            && e.holds(m)
        {
            broke = Some(BreakHit {
                expr: e.text().to_string(),
                at: m.pos(),
                line: m.pc_line(),
            });
            return true;
        }
        false
    });
    if reason != StopReason::Predicate {
        // The last instruction (END, a fault) has no boundary after it.
        emit(run.machine(), &mut seen, &mut started, &mut probe.trace);
    }
    if let Some(w) = probe.trace.as_mut()
        && let Err(e) = w.flush()
    {
        error.get_or_insert(e);
    }
    (run, broke, error)
}

/// The runner's one JSON object for a program that did not assemble: its dialect, the status
/// `not assembled` and each diagnostic with its file (as the command line named it), line,
/// column, severity and message, so a script or a grading loop records why nothing ran.
pub fn not_assembled_json(
    dialect: &Dialect,
    project: &Project,
    top_path: &str,
    diagnostics: &[Diagnostic],
) -> Value {
    let diagnostics: Vec<Value> = (diagnostics.iter())
        .map(|d| {
            let (file, line) = Project::split(d.line);
            json!({
                "file": project.display_path(top_path, file),
                "line": line,
                "column": d.col,
                "severity": match d.severity {
                    Severity::Error => "error",
                    Severity::Warning => "warning",
                },
                "message": d.message,
            })
        })
        .collect();
    json!({
        "dialect": dialect.name,
        "status": NOT_ASSEMBLED,
        "diagnostics": diagnostics,
    })
}

/// The status of a program that did not assemble, in the runner's and `check`'s JSON.
pub const NOT_ASSEMBLED: &str = "not assembled";
