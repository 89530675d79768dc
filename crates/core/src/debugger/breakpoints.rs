//! Breakpoints with more than a line: conditions, hit counts, log points and data breakpoints,
//! as the user sets them ([`Breakpoint`], saved in sessions) and compiled against the current
//! program ([`Checker`], asked at every instruction boundary of a run).
//!
//! Decisions where a professional debugger leaves room:
//! - A line breakpoint stops *before* its line runs; a data breakpoint stops right *after* the
//!   instruction that wrote its location, so the explanation shows that write. Both forward
//!   (Run) and backward (reverse-continue) land on the same positions.
//! - Data breakpoints look at every instruction boundary. A value the machine changes inside a
//!   long instruction (a position during a SilverLode move) is seen when that instruction
//!   completes. "Written" counts writes of the same value; "changed" compares with the value at
//!   the previous boundary; "equals V" fires when the value becomes V (not while it stays V).
//! - Hits are counted as a forward run passes a breakpoint whose condition holds, from the start
//!   of the timeline; Reset and a new assembly clear them; going back in time does not uncount
//!   them. A hit count N lets the first N - 1 hits pass and stops on the Nth and every later one.
//!   Reverse-continue ignores hit counts and log points (it looks for the last stop, not a count).
//! - A log point never stops: it adds its message, with `{EXPR}` holes filled, to the log. A
//!   position logged twice (after going back and running again) is logged once.

use super::expr::{Expr, ExprError, Message};
use crate::machine::{Loc, MachineView, Pos, value};

/// What makes a data breakpoint fire.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum DataTrigger {
    /// Any instruction writes the location (even the value it already held).
    Write,
    /// Its value differs from the value at the previous instruction boundary.
    Change,
    /// Its value becomes this number (as the location reads: signed ones sign-extended).
    Equal(i64),
}

impl DataTrigger {
    /// "written", "changed", "becomes 12": the value as `location` reads in `m` (a DL205 V
    /// word's BCD digits).
    pub fn describe(self, m: &dyn MachineView, location: &str) -> String {
        match self {
            DataTrigger::Write => "written".to_string(),
            DataTrigger::Change => "changed".to_string(),
            DataTrigger::Equal(v) => match m.find(location) {
                Some(loc) => format!(
                    "becomes {}",
                    crate::machine::show_in_reading(m, loc, v as u64)
                ),
                None => format!("becomes {v}"),
            },
        }
    }
}

/// Where a breakpoint is.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BreakKind {
    /// Before the instruction on this 1-based line runs.
    Line(usize),
    /// After an instruction touches this location (by name, so it survives edits).
    Data {
        location: String,
        trigger: DataTrigger,
    },
}

/// A breakpoint as the user set it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Breakpoint {
    pub kind: BreakKind,
    /// Stop only when this expression holds ("" = always).
    pub condition: String,
    /// Stop on the Nth hit and later (0 and 1: every hit).
    pub hit_count: u64,
    /// A log point's message ("" = a breakpoint that stops).
    pub log: String,
    pub enabled: bool,
}

impl Default for Breakpoint {
    fn default() -> Self {
        Breakpoint::line(0)
    }
}

impl Breakpoint {
    pub fn line(line: usize) -> Self {
        Breakpoint {
            kind: BreakKind::Line(line),
            condition: String::new(),
            hit_count: 0,
            log: String::new(),
            enabled: true,
        }
    }

    pub fn data(location: impl Into<String>, trigger: DataTrigger) -> Self {
        Breakpoint {
            kind: BreakKind::Data {
                location: location.into(),
                trigger,
            },
            ..Breakpoint::line(0)
        }
    }

    pub fn with_condition(mut self, condition: impl Into<String>) -> Self {
        self.condition = condition.into();
        self
    }

    pub fn with_hit_count(mut self, n: u64) -> Self {
        self.hit_count = n;
        self
    }

    pub fn with_log(mut self, message: impl Into<String>) -> Self {
        self.log = message.into();
        self
    }

    pub fn line_number(&self) -> Option<usize> {
        match self.kind {
            BreakKind::Line(l) => Some(l),
            BreakKind::Data { .. } => None,
        }
    }

    /// A plain line breakpoint: no condition, count or message (sessions list these by line).
    pub fn is_plain(&self) -> bool {
        matches!(self.kind, BreakKind::Line(_))
            && self.enabled
            && self.condition.trim().is_empty()
            && self.hit_count <= 1
            && self.log.is_empty()
    }

    /// "line 7", "R4 changed", "V1000 becomes 12" (values as the location reads in `m`).
    pub fn describe(&self, m: &dyn MachineView) -> String {
        match &self.kind {
            BreakKind::Line(l) => format!("line {l}"),
            BreakKind::Data { location, trigger } => {
                format!("{location} {}", trigger.describe(m, location))
            }
        }
    }
}

/// What is wrong with a breakpoint in the current program.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BreakError {
    #[error("condition, {0}")]
    Condition(ExprError),
    #[error("message, {0}")]
    Message(ExprError),
    #[error("there is no location named '{0}'")]
    Location(String),
    #[error("line {line} is past the last line of its file ({last})")]
    PastEnd { line: usize, last: usize },
}

/// A message a log point wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LogMessage {
    pub at: Pos,
    pub line: usize,
    pub text: String,
}

/// What stopped a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Hit {
    /// Index into the debugger's breakpoint list.
    pub index: usize,
    /// For a data breakpoint: the value at the previous boundary and now.
    pub values: Option<(i64, i64)>,
}

/// Log messages kept at most; past it the oldest quarter goes.
pub const MAX_LOG: usize = 100_000;

struct Compiled {
    condition: Option<Expr>,
    message: Option<Message>,
    hit_count: u64,
}

struct DataCheck {
    index: usize,
    loc: Loc,
    width: u8,
    signed: bool,
    trigger: DataTrigger,
    /// The value at the previous boundary.
    prev: i64,
}

/// The enabled breakpoints compiled against a program, with their hit counters.
#[derive(Default)]
pub struct Checker {
    compiled: Vec<Option<Compiled>>,
    /// Line breakpoints by line (index = line): indices into `compiled`.
    /// Breakpoint indexes by program line (a map: a project's lines are sparse, see
    /// [`crate::machine::project`]).
    by_line: LineTable,
    data: Vec<DataCheck>,
    hits: Vec<u64>,
    /// Going back: no counts, no log points.
    backward: bool,
    pub log: Vec<LogMessage>,
    /// (position, line) of every message in `log`, so a replayed stretch logs once.
    logged: std::collections::HashSet<(Pos, usize)>,
    pub hit: Option<Hit>,
    /// The problems found compiling, by breakpoint index.
    pub errors: Vec<Option<BreakError>>,
}

/// Breakpoint indexes by program line: a table indexed by line for the top file (the one every
/// program has, looked up at each instruction; sized by the program, as a line past the file's
/// end never gets here) and a map for the lines of included files, which are sparse
/// ([`crate::machine::project`]).
#[derive(Debug, Default)]
struct LineTable {
    top: Vec<Vec<usize>>,
    others: std::collections::BTreeMap<usize, Vec<usize>>,
}

impl LineTable {
    fn push(&mut self, line: usize, index: usize) {
        if line < crate::machine::project::FILE_LINES {
            if self.top.len() <= line {
                self.top.resize_with(line + 1, Vec::new);
            }
            self.top[line].push(index);
        } else {
            self.others.entry(line).or_default().push(index);
        }
    }

    #[inline]
    fn get(&self, line: usize) -> &[usize] {
        match self.top.get(line) {
            Some(at) => at,
            None if line < crate::machine::project::FILE_LINES => &[],
            None => self.others.get(&line).map_or(&[], Vec::as_slice),
        }
    }

    fn is_empty(&self) -> bool {
        self.top.is_empty() && self.others.is_empty()
    }

    /// The lines with a breakpoint, in order.
    fn lines(&self) -> Vec<usize> {
        (0..self.top.len())
            .filter(|&l| !self.top[l].is_empty())
            .chain(self.others.keys().copied())
            .collect()
    }
}

impl Checker {
    /// Compile `breakpoints` against `m`'s program, whose files have `lines[f]` source lines. A
    /// breakpoint whose condition, message or location does not compile, or whose line is
    /// past its file's last one, is inactive and its error is kept.
    pub fn new(breakpoints: &[Breakpoint], m: &dyn MachineView, lines: &[usize]) -> Checker {
        let mut c = Checker {
            compiled: Vec::new(),
            by_line: Default::default(),
            data: Vec::new(),
            hits: vec![0; breakpoints.len()],
            backward: false,
            log: Vec::new(),
            logged: Default::default(),
            hit: None,
            errors: Vec::new(),
        };
        for (index, b) in breakpoints.iter().enumerate() {
            let compiled = match b.kind {
                BreakKind::Line(line) => {
                    let (file, local) = crate::machine::project::Project::split(line);
                    match lines.get(file) {
                        Some(&last) if local > last => {
                            Err(BreakError::PastEnd { line: local, last })
                        }
                        Some(_) => compile(b, m),
                        // No such file: past the end of the program's last line.
                        None => Err(BreakError::PastEnd {
                            line,
                            last: lines.first().copied().unwrap_or(0),
                        }),
                    }
                }
                _ => compile(b, m),
            };
            let (compiled, error) = match compiled {
                Ok(x) => (Some(x), None),
                Err(e) => (None, Some(e)),
            };
            c.errors.push(error);
            if b.enabled && compiled.is_some() {
                match &b.kind {
                    BreakKind::Line(l) => c.by_line.push(*l, index),
                    BreakKind::Data { location, trigger } => {
                        if let Some(loc) = m.find(location)
                            && let Some(info) = m.info(loc)
                        {
                            let mut check = DataCheck {
                                index,
                                loc,
                                width: info.width,
                                signed: info.signed,
                                trigger: *trigger,
                                prev: 0,
                            };
                            check.prev = check.read(m);
                            c.data.push(check);
                        }
                    }
                }
            }
            c.compiled.push(compiled);
        }
        c
    }

    /// A checker for going back: the same breakpoints, ignoring hit counts and log points.
    pub fn backward(breakpoints: &[Breakpoint], m: &dyn MachineView, lines: &[usize]) -> Checker {
        let mut c = Checker::new(breakpoints, m, lines);
        c.backward = true;
        c
    }

    /// Where it needs asking: before its lines, and after an instruction that wrote one of its
    /// data breakpoints' locations (until one is written, a data breakpoint cannot fire: its
    /// value and "written" stay as they were).
    pub fn quiet_plan(&self) -> (Vec<usize>, Vec<Loc>) {
        let lines = self.by_line.lines();
        (lines, self.data.iter().map(|d| d.loc).collect())
    }

    pub fn is_empty(&self) -> bool {
        self.by_line.is_empty() && self.data.is_empty()
    }

    pub fn hits(&self, index: usize) -> u64 {
        self.hits.get(index).copied().unwrap_or(0)
    }

    pub fn reset_hits(&mut self) {
        self.hits.iter_mut().for_each(|h| *h = 0);
    }

    /// Take over the hit counts of an earlier checker (the breakpoints were edited, not the
    /// program): counts stay with breakpoints at the same index.
    pub fn keep_hits(&mut self, old: &Checker) {
        for (new, old) in self.hits.iter_mut().zip(&old.hits) {
            *new = *old;
        }
    }

    /// Data breakpoints compare with `m`'s values from here on (a run starting, a search from
    /// a checkpoint, after a user edit).
    pub fn prime<M: MachineView + ?Sized>(&mut self, m: &M) {
        for d in &mut self.data {
            d.prev = d.read(m);
        }
    }

    /// Hit counts by index (a breakpoint removed from the list).
    pub fn set_hits(&mut self, hits: &[u64]) {
        for (new, old) in self.hits.iter_mut().zip(hits) {
            *new = *old;
        }
    }

    /// After `log` was replaced: the index of what it holds.
    pub fn rebuild_logged(&mut self) {
        self.logged = self.log.iter().map(|l| (l.at, l.line)).collect();
    }

    /// An edit rewrote the history after `at`: its messages go with it.
    pub fn forget_log_after(&mut self, at: Pos) {
        self.log.retain(|l| l.at <= at);
        self.rebuild_logged();
    }

    /// Forget the log (a new timeline).
    pub fn clear_log(&mut self) {
        self.log.clear();
        self.logged.clear();
    }

    /// Whether a line breakpoint could stop on `line` (the gutter, quick tests).
    pub fn watches_line(&self, line: usize) -> bool {
        !self.by_line.get(line).is_empty()
    }

    /// Asked at every instruction boundary: whether to stop here. Counts hits, writes log
    /// messages and says in `hit` which breakpoint stopped.
    #[inline]
    pub fn check<M: MachineView + ?Sized>(&mut self, m: &M) -> bool {
        if !self.data.is_empty() && self.check_data(m) {
            return true;
        }
        if self.by_line.is_empty() {
            return false;
        }
        let Some(line) = m.pc_line() else {
            return false;
        };
        let count = self.by_line.get(line).len();
        for k in 0..count {
            let index = self.by_line.get(line)[k];
            if self.fire(index, m, line, None) {
                return true;
            }
        }
        false
    }

    #[inline]
    fn check_data<M: MachineView + ?Sized>(&mut self, m: &M) -> bool {
        let mut fired = None;
        for d in &mut self.data {
            let now = d.read(m);
            let prev = std::mem::replace(&mut d.prev, now);
            if fired.is_some() {
                continue;
            }
            let touched = match d.trigger {
                DataTrigger::Write => m.wrote(d.loc),
                DataTrigger::Change => now != prev,
                DataTrigger::Equal(v) => now == v && prev != v,
            };
            if touched {
                fired = Some((d.index, prev, now));
            }
        }
        let Some((index, prev, now)) = fired else {
            return false;
        };
        let line = m.last_line().unwrap_or(0);
        self.fire(index, m, line, Some((prev, now)))
    }

    /// A breakpoint's place was reached: its condition, count and message decide.
    fn fire<M: MachineView + ?Sized>(
        &mut self,
        index: usize,
        m: &M,
        line: usize,
        values: Option<(i64, i64)>,
    ) -> bool {
        let Some(Some(c)) = self.compiled.get(index) else {
            return false;
        };
        if c.condition.as_ref().is_some_and(|e| !e.holds(m)) {
            return false;
        }
        if self.backward {
            if c.message.is_some() {
                return false;
            }
            self.hit = Some(Hit { index, values });
            return true;
        }
        self.hits[index] += 1;
        if self.hits[index] < c.hit_count {
            return false;
        }
        if let Some(message) = &c.message {
            let at = m.pos();
            if self.logged.insert((at, line)) {
                if self.log.len() >= MAX_LOG {
                    let dropped: Vec<LogMessage> = self.log.drain(..MAX_LOG / 4).collect();
                    for l in dropped {
                        self.logged.remove(&(l.at, l.line));
                    }
                }
                self.log.push(LogMessage {
                    at,
                    line,
                    text: message.render(m),
                });
            }
            return false;
        }
        self.hit = Some(Hit { index, values });
        true
    }
}

impl DataCheck {
    #[inline]
    fn read<M: MachineView + ?Sized>(&self, m: &M) -> i64 {
        let raw = m.read(self.loc);
        if self.signed {
            value::sign_extend(raw, self.width)
        } else {
            (raw & value::mask(self.width)) as i64
        }
    }
}

fn compile(b: &Breakpoint, m: &dyn MachineView) -> Result<Compiled, BreakError> {
    let condition = match b.condition.trim() {
        "" => None,
        text => Some(Expr::compile(text, m).map_err(BreakError::Condition)?),
    };
    let message = match b.log.as_str() {
        "" => None,
        text => Some(Message::compile(text, m).map_err(BreakError::Message)?),
    };
    if let BreakKind::Data { location, .. } = &b.kind
        && m.find(location).is_none()
    {
        return Err(BreakError::Location(location.clone()));
    }
    Ok(Compiled {
        condition,
        message,
        hit_count: b.hit_count,
    })
}
