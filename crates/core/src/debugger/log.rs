//! The execution log and "who wrote this?", both computed on demand by replaying the recorded
//! timeline (nothing is stored per executed instruction).
//!
//! The log lists the instructions executed up to the current position, newest last: each with
//! the position after it (where going shows it as the last executed instruction), its line, its
//! explanation and the locations it wrote. A filter keeps one line's executions or the writes of
//! one location. It is built in two passes over stretches of history going back from the
//! current position: a cheap pass finds the matching positions, a second builds the rows of
//! the newest ones only.

use std::collections::VecDeque;
use std::fmt::Write as _;

use super::{Debugger, Event};
use crate::machine::{Loc, MachineView, Pos, shown_value};

/// Which executed instructions the log shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LogFilter {
    #[default]
    All,
    /// Those on this 1-based line.
    Line(usize),
    /// Those that wrote this location.
    Writes(Loc),
}

impl LogFilter {
    fn keeps(self, m: &dyn MachineView) -> bool {
        match self {
            LogFilter::All => true,
            LogFilter::Line(l) => m.last_line() == Some(l),
            LogFilter::Writes(loc) => m.wrote(loc),
        }
    }
}

/// One executed instruction.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LogRow {
    /// The position right after it.
    pub at: Pos,
    /// Instructions executed since the start, this one included.
    pub step: u64,
    pub line: usize,
    pub explanation: String,
    /// The locations it wrote, by name, with their values after it.
    /// The values as each location reads (a DL205 V word's BCD digits).
    pub written: Vec<(String, String)>,
}

/// A stretch of the execution log.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ExecutionLog {
    /// Oldest first; the last is the instruction that ran just before the current position.
    pub rows: Vec<LogRow>,
    /// The search went back to here (the start when `complete`).
    pub searched_from: Pos,
    /// Nothing older matches: the log reaches the start of the run.
    pub complete: bool,
}

/// Ticks of the first stretch searched back; each next one is twice as long.
const FIRST_STRETCH: u64 = 256;

fn row_of(m: &dyn MachineView) -> LogRow {
    LogRow {
        at: m.pos(),
        step: m.steps(),
        line: m.last_line().unwrap_or(0),
        explanation: m.explain_last().unwrap_or_default(),
        written: m
            .instruction_written()
            .into_iter()
            .filter_map(|loc| Some((m.info(loc)?.name, shown_value(m, loc))))
            .collect(),
    }
}

/// A search of the execution log that goes on over several calls, a bounded stretch of
/// history each ([`Debugger::search_log`]): the window runs it over frames, so a filter that
/// matches rarely on a long, heavy history never holds up a frame.
#[derive(Clone, Debug)]
pub struct LogSearch {
    filter: LogFilter,
    max_rows: usize,
    max_ticks: u64,
    /// Where the log ends (the position it was started at).
    now: Pos,
    /// The rows found so far, oldest first.
    kept: VecDeque<LogRow>,
    /// Searched back to here.
    to: Pos,
    stretch: u64,
    complete: bool,
    done: bool,
}

impl LogSearch {
    /// The last `max_rows` instructions up to `now` that `filter` keeps, searching back at most
    /// `max_ticks` ticks.
    pub fn new(filter: LogFilter, max_rows: usize, max_ticks: u64, now: Pos) -> Self {
        LogSearch {
            filter,
            max_rows,
            max_ticks,
            now,
            kept: VecDeque::new(),
            to: now,
            stretch: FIRST_STRETCH,
            complete: false,
            done: max_rows == 0,
        }
    }
    pub fn is_done(&self) -> bool {
        self.done
    }
    /// How far back it has searched.
    pub fn searched_from(&self) -> Pos {
        self.to
    }
}

impl Debugger {
    /// The last `max_rows` instructions up to the current position that `filter` keeps,
    /// searching back at most `max_ticks` ticks (a bound on the work: a filter that matches
    /// rarely on a long history stops there, and `searched_from` says where).
    pub fn execution_log(
        &mut self,
        filter: LogFilter,
        max_rows: usize,
        max_ticks: u64,
    ) -> ExecutionLog {
        let mut search = LogSearch::new(filter, max_rows, max_ticks, self.pos());
        while !search.is_done() {
            self.search_log(&mut search);
        }
        self.log_found(&search)
    }

    /// Search one more stretch of history back (at most [`super::history::CHECKPOINT_EVERY`]
    /// ticks, replayed from the checkpoint before it). Returns the ticks searched.
    pub fn search_log(&mut self, search: &mut LogSearch) -> u64 {
        if search.done {
            return 0;
        }
        let to = search.to;
        let from_tick = to.tick.saturating_sub(search.stretch);
        let from = if from_tick == 0 {
            // Positions start at 0: "after" something before it includes the first step.
            None
        } else {
            Some(Pos::at_tick(from_tick))
        };
        let mut found: Vec<Pos> = Vec::new();
        let filter = search.filter;
        self.engine
            .visit(from.unwrap_or_default(), to, &mut |m: &dyn MachineView| {
                if filter.keeps(m) {
                    found.push(m.pos());
                }
                true
            });
        // The newest matches this stretch adds, and their rows from a second look at it.
        let room = search.max_rows - search.kept.len();
        let wanted: Vec<Pos> = found.split_off(found.len().saturating_sub(room));
        if !wanted.is_empty() {
            let mut rows = Vec::with_capacity(wanted.len());
            self.engine.visit(from.unwrap_or_default(), to, &mut |m| {
                if wanted.get(rows.len()) == Some(&m.pos()) {
                    rows.push(row_of(m));
                }
                rows.len() < wanted.len()
            });
            for row in rows.into_iter().rev() {
                search.kept.push_front(row);
            }
        }
        let searched = to.tick - from_tick;
        match from {
            None => {
                search.complete = search.kept.len() < search.max_rows;
                search.to = Pos::default();
                search.done = true;
            }
            Some(f) => search.to = f,
        }
        if search.kept.len() >= search.max_rows || search.now.tick - from_tick >= search.max_ticks {
            search.done = true;
        }
        search.stretch = search
            .stretch
            .saturating_mul(2)
            .min(super::history::CHECKPOINT_EVERY);
        searched
    }

    /// The rows `search` found (all of them once it is done).
    pub fn log_found(&self, search: &LogSearch) -> ExecutionLog {
        ExecutionLog {
            rows: search.kept.iter().cloned().collect(),
            searched_from: if search.complete {
                Pos::default()
            } else {
                search.to
            },
            complete: search.complete,
        }
    }

    /// Go back to the instruction that last wrote `loc` before the current position (or the
    /// user's edit that did), landing right after it so its explanation shows. Asked again
    /// where the last answer landed, it goes to the write before. Returns where it went.
    pub fn who_wrote(&mut self, loc: Loc) -> Option<Pos> {
        self.goal = None;
        if self.has_errors() || self.is_edited() {
            return None;
        }
        let name = self
            .machine()
            .info(loc)
            .map_or_else(|| format!("{loc:?}"), |i| i.name);
        let now = self.pos();
        let again = self.last_writer == Some((loc, now));
        // A forced bit holds the force's level whatever the program wrote since: the force is
        // the answer.
        if !again && let Some(on) = self.machine().forced(loc) {
            let forced_at = self
                .events()
                .iter()
                .filter(|e| e.loc == loc && e.at <= now)
                .filter(|e| matches!(e.change, super::history::Change::Force(Some(_))))
                .map(|e| e.at)
                .next_back();
            if let Some(at) = forced_at {
                self.engine.goto(at);
                self.last_writer = Some((loc, at));
                self.event = Some(Event::WrittenBy {
                    location: name.clone(),
                    at,
                    line: None,
                    explanation: format!(
                        "your force: {name} forced {} (it holds whatever the program writes)",
                        if on { "ON" } else { "OFF" }
                    ),
                });
                return Some(at);
            }
        }
        let by_program = if !again && self.machine().wrote(loc) {
            Some(now)
        } else {
            self.engine.find_write_back(now, loc)
        };
        let limit = if again {
            now
        } else {
            Pos {
                step: now.step + 1,
                ..now
            }
        };
        let by_user = self
            .events()
            .iter()
            .filter(|e| e.loc == loc && e.at < limit)
            .map(|e| e.at)
            .next_back();
        let (at, user) = match (by_program, by_user) {
            (Some(p), Some(u)) if u >= p => (u, true),
            (Some(p), _) => (p, false),
            (None, Some(u)) => (u, true),
            (None, None) => {
                self.last_writer = None;
                self.event = Some(Event::NeverWritten(name));
                return None;
            }
        };
        self.engine.goto(at);
        self.last_writer = Some((loc, at));
        let m = self.machine();
        let forced = self.events().iter().any(|e| {
            e.loc == loc && e.at == at && matches!(e.change, super::history::Change::Force(_))
        });
        let mut explanation = if user && forced {
            String::from("your force or its release")
        } else if user {
            String::from("your edit")
        } else {
            m.explain_last().unwrap_or_default()
        };
        if explanation.is_empty() {
            explanation.push_str("the machine");
        }
        let value = shown_value(m, loc);
        let _ = write!(explanation, " ({name} = {value})");
        self.event = Some(Event::WrittenBy {
            location: name,
            at,
            line: if user { None } else { m.last_line() },
            explanation,
        });
        Some(at)
    }
}
