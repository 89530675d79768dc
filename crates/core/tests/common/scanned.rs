//! A scanned PLC in miniature, written against the same traits every dialect implements: a tick
//! is a whole scan of many instructions. Tests of (tick, step) positions and of the window's
//! dialect-neutral views use it.

#![allow(dead_code)]

use std::any::Any;
use std::sync::Arc;

use servoscope_core::debugger::engine;
use servoscope_core::machine::project::Project;
use servoscope_core::machine::{
    Diagnostic, FaultInfo, Loc, LocInfo, Machine, MachineView, Pos, RunState, SpaceInfo, SpaceKind,
    StopReason, WriteError,
};
use servoscope_core::registry::{
    AtLimit, Dialect, DialectInfo, OpenResult, Settings, TokenClass, Vocabulary,
};

/// `ADD v k` (V[v] += k), `COPY a b` (V[b] = V[a]), `IN v` (V[v] = the input), then END.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Add(usize, u16),
    Copy(usize, usize),
    In(usize),
    End,
}

/// A scanned PLC in miniature: every scan runs each instruction once, END closes the scan.
#[derive(Clone, Debug, PartialEq)]
pub struct Scanned {
    program: Arc<Vec<Op>>,
    pub v: [u16; 8],
    input: bool,
    /// The last ADD gave 0 (a flag a user may flip).
    zero: bool,
    tick: u64,
    /// Instructions already run in this scan (= index of the next one).
    step: u32,
    steps: u64,
    last: Option<usize>,
}

pub const V: u8 = 0;
pub const IN: u8 = 1;
pub const FLAGS: u8 = 2;

pub fn v(i: u32) -> Loc {
    Loc::new(V, i)
}

impl Scanned {
    fn execute(&mut self) {
        let at = self.step as usize;
        match self.program[at] {
            Op::Add(r, k) => {
                self.v[r] = self.v[r].wrapping_add(k);
                self.zero = self.v[r] == 0;
            }
            Op::Copy(a, b) => self.v[b] = self.v[a],
            Op::In(r) => self.v[r] = u16::from(self.input),
            Op::End => {}
        }
        self.last = Some(at);
        self.steps += 1;
        self.step += 1;
        if self.step as usize == self.program.len() {
            self.step = 0;
            self.tick += 1;
        }
    }
}

impl MachineView for Scanned {
    fn dialect(&self) -> &'static str {
        "scanned"
    }
    fn tick_micros(&self) -> u32 {
        10_000
    }
    fn spaces(&self) -> Vec<SpaceInfo> {
        vec![
            SpaceInfo {
                name: "V",
                title: "Words",
                kind: SpaceKind::Registers,
                len: 8,
            },
            SpaceInfo {
                name: "X",
                title: "Inputs",
                kind: SpaceKind::Inputs,
                len: 1,
            },
            SpaceInfo {
                name: "SP",
                title: "Relays",
                kind: SpaceKind::Flags,
                len: 2,
            },
        ]
    }
    fn info(&self, loc: Loc) -> Option<LocInfo> {
        match (loc.space, loc.index) {
            (V, i @ 0..8) => Some(LocInfo::word(format!("V{i}"), 16, false)),
            (IN, 0) => Some(LocInfo::word("X0".to_string(), 1, false)),
            (FLAGS, 0) => Some(LocInfo {
                description: "the last ADD gave 0",
                ..LocInfo::word("ZERO".to_string(), 1, false)
            }),
            (FLAGS, 1) => Some(LocInfo {
                description: "on during the first scan",
                editable: false,
                ..LocInfo::word("FIRST".to_string(), 1, false)
            }),
            _ => None,
        }
    }
    fn read(&self, loc: Loc) -> u64 {
        match (loc.space, loc.index) {
            (V, i @ 0..8) => u64::from(self.v[i as usize]),
            (IN, 0) => u64::from(self.input),
            (FLAGS, 0) => u64::from(self.zero),
            (FLAGS, 1) => u64::from(self.tick == 0),
            _ => 0,
        }
    }
    fn write(&mut self, loc: Loc, value: u64) -> Result<(), WriteError> {
        match (loc.space, loc.index) {
            (V, i @ 0..8) => self.v[i as usize] = value as u16,
            (IN, 0) => self.input = value != 0,
            (FLAGS, 0) => self.zero = value != 0,
            (FLAGS, 1) => return Err(WriteError::ReadOnly("FIRST".to_string())),
            _ => return Err(WriteError::NoSuchLocation),
        }
        Ok(())
    }
    fn used(&self) -> Vec<Loc> {
        let mut used: Vec<Loc> = self
            .program
            .iter()
            .flat_map(|op| match *op {
                Op::Add(r, _) | Op::In(r) => vec![r],
                Op::Copy(a, b) => vec![a, b],
                Op::End => vec![],
            })
            .map(|r| v(r as u32))
            .collect();
        used.sort_unstable();
        used.dedup();
        used
    }
    fn program_names(&self) -> Vec<(String, Loc)> {
        Vec::new()
    }
    fn pc_line(&self) -> Option<usize> {
        Some(self.step as usize + 1)
    }
    fn call_stack_lines(&self) -> Vec<usize> {
        Vec::new()
    }
    fn run_state(&self) -> RunState {
        RunState::Running
    }
    fn fault(&self) -> Option<FaultInfo> {
        None
    }
    fn pos(&self) -> Pos {
        Pos {
            tick: self.tick,
            step: self.step,
        }
    }
    fn steps(&self) -> u64 {
        self.steps
    }
    fn for_each_written(&self, _: &mut dyn FnMut(Loc)) {}
    fn explain_last(&self) -> Option<String> {
        None
    }
    fn last_line(&self) -> Option<usize> {
        self.last.map(|i| i + 1)
    }
    fn report_json(&self, _: &mut servoscope_core::machine::JsonMap) {}
    fn report_text(&self) -> String {
        String::new()
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

impl Machine for Scanned {
    fn run_observed<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        limit: Pos,
        mut stop: F,
        mut observe: O,
    ) -> StopReason {
        loop {
            if self.pos() >= limit {
                return StopReason::TickLimit;
            }
            if stop(self) {
                return StopReason::Predicate;
            }
            let tick = self.tick;
            self.execute();
            if self.tick > tick {
                observe(self);
            }
        }
    }
}

fn parse(source: &str) -> Result<Scanned, Vec<Diagnostic>> {
    let mut program = Vec::new();
    let mut errors = Vec::new();
    for (i, line) in source.lines().enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let num = |k: usize| words.get(k).and_then(|w| w.parse::<u16>().ok());
        let op = match (words.first().copied(), num(1), num(2)) {
            (None, ..) => continue,
            (Some("ADD"), Some(r), Some(k)) if r < 8 => Op::Add(r.into(), k),
            (Some("COPY"), Some(a), Some(b)) if a < 8 && b < 8 => Op::Copy(a.into(), b.into()),
            (Some("IN"), Some(r), None) if r < 8 => Op::In(r.into()),
            (Some("END"), None, None) => Op::End,
            _ => {
                errors.push(Diagnostic::error(i + 1, 1, line.len(), "bad instruction"));
                continue;
            }
        };
        program.push(op);
    }
    if program.last() != Some(&Op::End) {
        program.push(Op::End);
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(Scanned {
        program: Arc::new(program),
        v: [0; 8],
        input: false,
        zero: false,
        tick: 0,
        step: 0,
        steps: 0,
        last: None,
    })
}

fn open(project: &Project, _: &Settings) -> OpenResult {
    parse(project.top_text()).map(engine)
}

fn plain(line: &str) -> Vec<TokenClass> {
    vec![TokenClass::Plain; line.chars().count()]
}

pub static SCANNED: Dialect = Dialect {
    info: &SCANNED_INFO,
    open,
};

static SCANNED_INFO: DialectInfo = DialectInfo {
    name: "scanned",
    display_name: "A scanned test machine",
    extensions: &["scan"],
    vocabulary: Vocabulary {
        tick: "scan",
        ticks: "scans",
        step: "instruction",
        steps: "instructions",
        location_hint: "",
        watch_hint: "",
        condition_hint: "",
    },
    examples: &[],
    projects: &[],
    lessons: &[],
    reference: "",
    mnemonics: &[],
    settings: &[],
    default_channels: &[],
    default_max_ticks: 1,
    at_limit: AtLimit::Ended,
    new_program: "END\n",
    empty_program: "",
    error_flags: "none",
    decimal_literals_are_fixed: false,
    includes: None,
    classify: plain,
};

/// Line 1 adds 1 to V0, line 2 copies V0 to V1, line 3 reads the input into V2, line 4 adds
/// 10 to V3, line 5 is END: a scan is five steps.
pub const PROGRAM: &str = "ADD 0 1\nCOPY 0 1\nIN 2\nADD 3 10\nEND";
