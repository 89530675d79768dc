//! IDEC OpenNet (spec `opennet.md`): a scanned PLC with bit logic on two stacks, typed
//! arithmetic (W, I, D, L) with the vendor's signed-overflow rule, REP, the carry relay M8003
//! and the latched execution-error relay M8004.
//!
//! Decided where the spec is silent (each also noted where it is implemented):
//! - Inputs: a switch flipped in the debugger mid-scan is seen by the program from the next
//!   scan (the refresh copies the switches into the input image). Views show the switches; the
//!   runner's `bits` and the program read the image.
//! - Break on error stops before the instruction after the one that turned M8004 on.

pub mod assembler;
pub mod dialect;
pub mod explain;
pub mod fast;
pub mod ladder;
pub mod memory;
pub mod program;
mod scanned;
pub mod syntax;
pub mod view;

mod act;
mod arith;
mod exec;
mod words;

use std::sync::Arc;

pub use assembler::assemble;
use program::{Area, BOXES, Bit, Program};

use crate::machine::plc::{Edges, TimeBase};

pub const REGISTERS: usize = 8000;
pub const STACK_DEPTH: usize = 8;
pub const M8003: usize = 0;
pub const M8004: usize = 1;
pub const M8120: usize = 2;
pub const M8121: usize = 3;
pub const M8122: usize = 4;
pub const M8123: usize = 5;
pub const M8125: usize = 6;

/// A timer (spec §5.8): it counts down from its preset while its input is on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TimerState {
    pub preset: u16,
    pub current: u16,
    pub output: bool,
    /// Timing since an earlier powered execution: the next one counts time.
    pub running: bool,
    /// Controller time toward the next increment, ms (0 ≤ e < increment).
    pub elapsed_ms: u32,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CounterState {
    pub preset: u16,
    pub current: u16,
    pub output: bool,
}

/// What switched an instruction off in this scan, for the code view (spec §5.12's dimming):
/// set by the MCS or JMP that decides it, so the fast loop marks nothing per instruction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u8)]
pub enum Mark {
    #[default]
    NotReached,
    /// Runs with MC = 0 (after an MCS that is off, up to its MCR): every output's input is off.
    MasterOff,
    /// Skipped by a taken JMP.
    Jumped,
}

/// An execution error (spec §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExecError {
    pub kind: &'static str,
    pub line: usize,
    pub tick: u64,
}

/// One REP cycle of the last advanced instruction, for the explanation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cycle {
    pub a: i64,
    pub b: i64,
    /// Exact result (the quotient for DIV).
    pub exact: i64,
    pub stored: u32,
    pub remainder: i64,
    pub out_of_range: bool,
    pub error: Option<&'static str>,
    pub a_at: u32,
    pub b_at: u32,
    pub dst_at: u32,
}

impl Cycle {
    /// A cycle that read `a` and `b` from these offsets; the rest is filled in by its kind.
    fn read(a: i64, b: i64, a_at: u32, b_at: u32) -> Cycle {
        Cycle {
            a,
            b,
            exact: 0,
            stored: 0,
            remainder: 0,
            out_of_range: false,
            error: None,
            a_at,
            b_at,
            dst_at: 0,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct OpenNet {
    pub program: Arc<Program>,
    pub d: Vec<u16>,
    /// The input switches, and the image the program reads (taken at scan start).
    pub inputs: Vec<bool>,
    pub input_image: Vec<bool>,
    pub q: Vec<bool>,
    pub m: Vec<bool>,
    /// Shift-register bits R0–R255.
    pub r: Vec<bool>,
    /// M8003, M8004, M8120, M8121, M8122, M8123, M8125 ([`SPECIAL`]).
    pub special: [bool; 7],
    pub rlo: bool,
    /// The master-control bit: outputs take RLO AND MC (spec §5.12).
    pub mc: bool,
    pub blocks: Vec<bool>,
    pub branches: Vec<bool>,
    /// SOTU/SOTD memories, and the pulse memories of counters and shift registers.
    pub edges: Edges,
    pub pulses: Edges,
    /// Each SOTU/SOTD memory's last pulse: its scan plus one (the Ladder shows it conducting).
    pub edge_scans: Vec<u64>,
    /// Bits the user forced.
    pub forces: crate::machine::plc::Forces,
    pub timers: Vec<TimerState>,
    pub counters: Vec<CounterState>,
    pub time: TimeBase,
    /// What each instruction did in this scan so far.
    pub marks: Vec<Mark>,
    /// The last timer's or counter's state before it ran (current value, output) and the
    /// inputs of the last counter or shift register in program order, for the explanation.
    pub box_before: (u16, bool),
    pub legs: [bool; 3],
    pub pc: u32,
    pub tick: u64,
    pub step: u32,
    pub steps: u64,
    pub error_count: u64,
    pub last_error: Option<ExecError>,
    /// The last executed instruction, whether it acted, and its REP cycles.
    pub last: Option<u32>,
    pub last_acted: bool,
    pub last_cycles: Vec<Cycle>,
}

impl OpenNet {
    pub fn new(program: Arc<Program>) -> Self {
        Self::with_time(program, TimeBase::default())
    }

    pub fn with_time(program: Arc<Program>, time: TimeBase) -> Self {
        let mut timers = vec![TimerState::default(); BOXES as usize];
        for &(n, p) in &program.timer_presets {
            timers[n as usize].preset = p;
            timers[n as usize].current = p;
        }
        let mut counters = vec![CounterState::default(); BOXES as usize];
        for &(n, p) in &program.counter_presets {
            counters[n as usize].preset = p;
        }
        OpenNet {
            d: vec![0; REGISTERS],
            inputs: vec![false; Area::I.points() as usize],
            input_image: vec![false; Area::I.points() as usize],
            q: vec![false; Area::Q.points() as usize],
            m: vec![false; Area::M.points() as usize],
            r: vec![false; Area::R.points() as usize],
            special: [false; 7],
            rlo: false,
            mc: true,
            blocks: Vec::new(),
            branches: Vec::new(),
            edges: Edges::new(program.edges as usize),
            edge_scans: vec![0; program.edges as usize],
            forces: Default::default(),
            pulses: Edges::new(program.pulses as usize),
            timers,
            counters,
            time,
            marks: vec![Mark::NotReached; program.instrs.len()],
            box_before: (0, false),
            legs: [false; 3],
            program,
            pc: 0,
            tick: 0,
            step: 0,
            steps: 0,
            error_count: 0,
            last_error: None,
            last: None,
            last_acted: false,
            last_cycles: Vec::new(),
        }
    }

    fn area(&self, area: Area) -> &[bool] {
        match area {
            Area::I => &self.input_image,
            Area::Q => &self.q,
            Area::M => &self.m,
            Area::R => &self.r,
        }
    }

    fn area_mut(&mut self, area: Area) -> &mut [bool] {
        match area {
            Area::I => &mut self.input_image,
            Area::Q => &mut self.q,
            Area::M => &mut self.m,
            Area::R => &mut self.r,
        }
    }

    pub fn bit(&self, b: Bit) -> bool {
        match b {
            Bit::Point(area, i) => self.area(area).get(i as usize).copied().unwrap_or(false),
            Bit::Special(s) => self.special[s as usize],
            Bit::Timer(n) => self.timers.get(n as usize).is_some_and(|t| t.output),
            Bit::Counter(n) => self.counters.get(n as usize).is_some_and(|c| c.output),
        }
    }

    fn set_bit(&mut self, b: Bit, v: bool) {
        match b {
            Bit::Point(area, i) => {
                if let Some(x) = self.area_mut(area).get_mut(i as usize) {
                    *x = v;
                }
            }
            Bit::Special(s) => self.special[s as usize] = v,
            // The assembler never lets a bit instruction write a timer or counter.
            Bit::Timer(_) | Bit::Counter(_) => {}
        }
    }
}
