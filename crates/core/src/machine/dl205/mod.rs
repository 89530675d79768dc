//! AutomationDirect DL205 (spec `dl205.md`): a scanned PLC whose math runs through a 32-bit
//! accumulator and an 8-level accumulator stack, mostly in BCD, with the boolean stack of its
//! rungs and the SP flags.
//!
//! Decided where the spec is silent (also noted where implemented):
//! - The debugger may write V words, X inputs (seen from the next scan: the scan start copies
//!   the switches into the image), Y and C; SP relays are the machine's.
//! - SP53 and SP75 remember the line of the instruction that last set them, for the views.

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

mod boxes;
mod exec;
mod flow;
mod math;

use std::sync::Arc;

use crate::machine::plc::{CounterInputs, Edges, TimeBase};
pub use assembler::assemble;
use program::{Bit, D, Kind, Op, Program, W, sp};

pub const V_WORDS: usize = 0o40000;
/// Z0 = 1, Z1…Z7 = 0: the master-line zones at each scan, SG, ISG and SBR.
const ZONES_AT_START: [bool; 8] = [true, false, false, false, false, false, false, false];
pub const LEVELS: usize = 8;

/// Where execution goes after an instruction.
enum Flow {
    Next,
    To(u32),
    EndScan,
}

/// What the last instruction did to the accumulator stack, for the panel and explanations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StackMove {
    #[default]
    None,
    /// A value entered L1; the one that fell off L8, when all eight levels were in use (a
    /// level below the depth holds no value, so nothing is lost from it).
    Push { entered: u32, lost: Option<u32> },
    /// L1 rose into ACC or was consumed.
    Pop { value: u32 },
    /// L1 was overwritten (DIVS, DIVBS).
    Overwrite { value: u32 },
}

/// A FOR loop in progress: where its FOR is and the turns left, this one included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Loop {
    pub for_at: u32,
    pub left: u32,
}

/// A subroutine call in progress: where to return and the caller's rung and block state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    pub ret: u32,
    pub bstack: Vec<bool>,
    pub rung_has_output: bool,
    pub level: u8,
    pub zones: [bool; 8],
    pub stage_power: bool,
    pub loop_state: Option<Loop>,
}

/// Which instruction last changed a stage bit, and the position just after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StageChange {
    pub stage: u32,
    pub line: usize,
    pub at: crate::machine::Pos,
}

/// Calls may nest 8 deep (checked at assembly: spec §2).
pub const CALL_DEPTH: usize = 8;

#[derive(Clone, Debug, PartialEq)]
pub struct Dl205 {
    pub program: Arc<Program>,
    pub v: Vec<u16>,
    pub x: Vec<bool>,
    pub x_image: Vec<bool>,
    pub y: Vec<bool>,
    pub c: Vec<bool>,
    pub s: Vec<bool>,
    pub t: Vec<bool>,
    pub ct: Vec<bool>,
    pub sp: [bool; program::SPECIAL.len()],
    /// Each timer's time toward its next unit (`Tn.ms`).
    pub t_ms: Vec<u32>,
    /// The scan each timer last counted, plus one (0: none since its last reset).
    pub t_counted: Vec<u64>,
    /// Each counter's inputs at its last execution (`CTn.in`).
    pub ct_in: Vec<CounterInputs>,
    pub edges: Edges,
    /// Whether the last edge contact evaluated fired (for its explanation).
    pub edge_fired: bool,
    /// The edge contacts that fired in this scan, by instruction index (the code view marks
    /// them).
    pub fired_this_scan: Vec<u32>,
    /// Whether the last instruction raised SP53 or SP75 (what it wrote, for the Log).
    pub raised_error: bool,
    /// A timer's or counter's current value before the last instruction ran it.
    pub box_before: u32,
    /// OROUT targets already written in this scan.
    pub orout_marks: Vec<bool>,
    pub time: TimeBase,
    /// Master-line level ℓ and zone powers Z0…Z7 (spec §6.8).
    pub level: u8,
    pub zones: [bool; 8],
    /// Stage power G, fixed at each SG/ISG.
    pub stage_power: bool,
    /// G ∧ Z_ℓ: what every output's rung power is ANDed with.
    pub block_power: bool,
    pub loop_state: Option<Loop>,
    pub calls: Vec<Frame>,
    /// Each stage's clean-up mark: it ran since it last turned off (spec §6.10).
    pub stage_marks: Vec<bool>,
    /// The last change of each stage bit the program changed.
    pub stage_changes: Vec<StageChange>,
    pub acc: u32,
    pub stack: [u32; LEVELS],
    pub depth: u8,
    pub load_pending: bool,
    pub bstack: Vec<bool>,
    pub rung_has_output: bool,
    pub pc: u32,
    pub tick: u64,
    pub step: u32,
    pub steps: u64,
    pub last: Option<u32>,
    /// ACC and L1 before the last instruction, and what it did to the stack.
    pub before: (u32, u32),
    pub moved: StackMove,
    /// Whether the last instruction ran (its rung was powered), or met non-BCD data / ÷0.
    pub last_ran: bool,
    pub sp53_line: Option<usize>,
    pub sp75_line: Option<usize>,
    /// The rung power after each instruction of this scan (None: not reached yet).
    pub power: Vec<Option<bool>>,
    /// Bits the user forced (last: the run loops' fields keep their places).
    pub forces: crate::machine::plc::Forces,
}

pub use crate::machine::plc::{bcd_value, to_bcd};

impl Dl205 {
    pub fn new(program: Arc<Program>) -> Self {
        Self::with_time(program, TimeBase::default())
    }

    pub fn with_time(program: Arc<Program>, time: TimeBase) -> Self {
        let n = program.instrs.len();
        let timers = Kind::T.count() as usize;
        let edges = Edges::new(program.edges as usize);
        let orout_marks = vec![false; program.orout_bits.len()];
        let mut m = Dl205 {
            program,
            v: vec![0; V_WORDS],
            x: vec![false; Kind::X.count() as usize],
            x_image: vec![false; Kind::X.count() as usize],
            y: vec![false; Kind::Y.count() as usize],
            c: vec![false; Kind::C.count() as usize],
            s: vec![false; Kind::S.count() as usize],
            t: vec![false; timers],
            ct: vec![false; timers],
            sp: [false; program::SPECIAL.len()],
            t_ms: vec![0; timers],
            t_counted: vec![0; timers],
            ct_in: vec![CounterInputs::default(); timers],
            edges,
            edge_fired: false,
            fired_this_scan: Vec::new(),
            raised_error: false,
            box_before: 0,
            orout_marks,
            time,
            level: 0,
            zones: ZONES_AT_START,
            stage_power: true,
            block_power: true,
            loop_state: None,
            calls: Vec::new(),
            stage_marks: vec![false; Kind::S.count() as usize],
            forces: Default::default(),
            stage_changes: Vec::new(),
            acc: 0,
            stack: [0; LEVELS],
            depth: 0,
            load_pending: false,
            bstack: Vec::new(),
            rung_has_output: false,
            pc: 0,
            tick: 0,
            step: 0,
            steps: 0,
            last: None,
            before: (0, 0),
            moved: StackMove::None,
            last_ran: false,
            sp53_line: None,
            sp75_line: None,
            power: vec![None; n],
        };
        m.sp[sp::SP1] = true;
        // ISG stages are on before scan 0.
        let initial: Vec<u32> = m
            .program
            .instrs
            .iter()
            .filter_map(|i| match i.op {
                Op::Sg {
                    stage,
                    initial: true,
                    ..
                } => Some(stage),
                _ => None,
            })
            .collect();
        for stage in initial {
            m.s[stage as usize] = true;
        }
        m
    }

    pub fn bit(&self, b: Bit) -> bool {
        let i = b.n as usize;
        match b.kind {
            Kind::X => self.x_image.get(i).copied().unwrap_or(false),
            Kind::Y => self.y.get(i).copied().unwrap_or(false),
            Kind::C => self.c.get(i).copied().unwrap_or(false),
            Kind::Sp => self.sp.get(i).copied().unwrap_or(false),
            Kind::S => self.s.get(i).copied().unwrap_or(false),
            Kind::T => self.t.get(i).copied().unwrap_or(false),
            Kind::Ct => self.ct.get(i).copied().unwrap_or(false),
        }
    }

    fn set_bit(&mut self, b: Bit, on: bool) {
        let i = b.n as usize;
        let slot = match b.kind {
            Kind::Y => self.y.get_mut(i),
            Kind::C => self.c.get_mut(i),
            Kind::S => {
                if self.s.get(i).is_some_and(|&was| was != on) {
                    self.note_stage_change(b.n);
                }
                self.s.get_mut(i)
            }
            // RST of a timer or counter clears its box (see `reset_box`).
            Kind::T => self.t.get_mut(i),
            Kind::Ct => self.ct.get_mut(i),
            // The assembler never lets a program write X or SP.
            Kind::X | Kind::Sp => None,
        };
        if let Some(s) = slot {
            *s = on;
        }
    }

    /// V word `a`: a data word, or a bit-mapped word (V40400–V41237) read from its bits.
    #[inline(always)]
    pub fn word(&self, a: u32) -> u16 {
        match self.v.get(a as usize) {
            Some(&w) => w,
            None => self.mapped_word(a),
        }
    }

    #[inline(always)]
    pub(super) fn set_word(&mut self, a: u32, value: u16) {
        match self.v.get_mut(a as usize) {
            Some(w) => *w = value,
            None => self.set_mapped_word(a, value),
        }
    }

    fn mapped_word(&self, a: u32) -> u16 {
        let Some((kind, first)) = program::mapped(a) else {
            return 0;
        };
        (0..16).fold(0u16, |word, i| {
            let n = first + i;
            let on = match kind {
                // Unmodelled special relays read 0.
                Kind::Sp => program::SPECIAL
                    .iter()
                    .position(|&s| s == n)
                    .is_some_and(|i| self.sp[i]),
                _ => self.bit(Bit { kind, n }),
            };
            word | (u16::from(on) << i)
        })
    }

    /// Only VY, VC and VS words are written (the assembler refuses the others).
    fn set_mapped_word(&mut self, a: u32, value: u16) {
        if let Some((kind @ (Kind::Y | Kind::C | Kind::S), first)) = program::mapped(a) {
            for i in 0..16 {
                self.set_bit(Bit { kind, n: first + i }, value >> i & 1 == 1);
            }
        }
    }

    fn w(&self, w: W) -> u32 {
        match w {
            W::V(a) => u32::from(self.word(a)),
            W::K(k) => u32::from(k),
        }
    }

    /// A pair: Vn low word, Vn+1 high word.
    pub fn pair(&self, a: u32) -> u32 {
        u32::from(self.word(a)) | (u32::from(self.word(a + 1)) << 16)
    }

    fn d(&self, d: D) -> u32 {
        match d {
            D::V(a) => self.pair(a),
            D::K(k) => k,
        }
    }

    /// The line of the instruction about to run (0 past the end).
    pub fn pc_line_now(&self) -> usize {
        self.program
            .instrs
            .get(self.pc as usize)
            .map_or(0, |i| i.line)
    }
}
