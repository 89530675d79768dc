//! The SilverLode dialect (spec `silverlode.md`): assembler, executor and motion model.
//!
//! Decided where the spec is silent (each also noted where it is implemented):
//! - A fault without a `CER` handler stops the machine *at the start* of the faulting tick: the
//!   tick counter, the motion model and every register are as before the command; only PSW
//!   bit 12 is set. With a handler the tick is spent (the command error and the jump take it).
//! - Stop conditions of moves are level-triggered, checked every tick of the move from its
//!   first tick: a condition already true when the move starts stops it at once.
//! - A move whose end is the current target, or whose velocity is 0, completes in its one tick
//!   without moving. A relative move whose end does not fit 32 bits faults `bad_motion`.
//! - Moves and `WBS` complete in the tick where their trajectory ends / condition holds.
//! - `Q_READ` accepts 0 ..< len from the head and -1 ..= -len from the tail.
//! - When a command's result register is also one it updates otherwise (a queue header, a
//!   `MULT_U64` pair), the result register is written last and wins.
//! - ISW bit 11 / PSW bit 11 are cleared when a move starts; ISW bit 12 when a DLY starts.
//! - The index input is not simulated: ISW bit 0 and R2 change only when a program writes them.
//! - The holding-error limit defaults to 2000 counts, like the moving-error limit.

pub mod arith;
pub mod assembler;
pub mod dialect;
mod exec;
mod explain;
pub mod jit;
pub mod motion;
pub mod program;
pub mod syntax;
pub mod view;

use std::sync::Arc;

pub use assembler::assemble;
pub use motion::ServoSettings;
pub use program::{ClcOp, Cond, CondBit, ExtOp, Instr, MoveKind, Program};

use crate::machine::{BitInfo, RunState};
use motion::Motion;
pub use view::{QueueAccess, QueueHeader, QueueView};

pub const REGISTERS: usize = 200;
pub const STACK_DEPTH: usize = 8;
pub const TICK_MICROS: u32 = 120;

pub mod isw {
    pub const INDEX_FOUND: u16 = 1 << 0;
    pub const ZERO: u16 = 1 << 1;
    pub const POSITIVE: u16 = 1 << 2;
    pub const NEGATIVE: u16 = 1 << 3;
    pub const IO1: u16 = 1 << 4;
    pub const DRIVER_ENABLED: u16 = 1 << 7;
    pub const MOVING_ERROR: u16 = 1 << 8;
    pub const HOLDING_ERROR: u16 = 1 << 9;
    pub const INPUT_FOUND: u16 = 1 << 11;
    pub const DELAY_DONE: u16 = 1 << 12;
    pub const FLAGS: u16 = ZERO | POSITIVE | NEGATIVE;
}

pub mod psw {
    pub const INPUT_FOUND: u16 = 1 << 11;
    pub const COMMAND_ERROR: u16 = 1 << 12;
    pub const PROGRAM_DONE: u16 = 1 << 13;
}

pub static ISW_BITS: &[BitInfo] = &[
    BitInfo {
        bit: 0,
        name: "INDEX",
        description: "index found",
    },
    BitInfo {
        bit: 1,
        name: "ZERO",
        description: "last calculation zero (queue: success)",
    },
    BitInfo {
        bit: 2,
        name: "POSITIVE",
        description: "last calculation positive",
    },
    BitInfo {
        bit: 3,
        name: "NEGATIVE",
        description: "last calculation negative (queue: failure)",
    },
    BitInfo {
        bit: 4,
        name: "IO1",
        description: "input 1 high",
    },
    BitInfo {
        bit: 5,
        name: "IO2",
        description: "input 2 high",
    },
    BitInfo {
        bit: 6,
        name: "IO3",
        description: "input 3 high",
    },
    BitInfo {
        bit: 7,
        name: "DRIVER",
        description: "driver enabled (always on)",
    },
    BitInfo {
        bit: 8,
        name: "MOVING_ERROR",
        description: "|position error| over the moving limit during a move",
    },
    BitInfo {
        bit: 9,
        name: "HOLDING_ERROR",
        description: "|position error| over the holding limit while holding",
    },
    BitInfo {
        bit: 11,
        name: "INPUT_FOUND",
        description: "last move stopped on its input condition",
    },
    BitInfo {
        bit: 12,
        name: "DELAY_DONE",
        description: "the last DLY has finished",
    },
];

pub static PSW_BITS: &[BitInfo] = &[
    BitInfo {
        bit: 11,
        name: "INPUT_FOUND",
        description: "last move stopped on its input condition",
    },
    BitInfo {
        bit: 12,
        name: "COMMAND_ERROR",
        description: "a command faulted",
    },
    BitInfo {
        bit: 13,
        name: "PROGRAM_DONE",
        description: "the program ended",
    },
];

/// Fault kinds of spec §5.6.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FaultKind {
    DivideByZero,
    DivideOverflow,
    QueueFull,
    QueueEmpty,
    BadQueue,
    BadRegister,
    BadMotion,
    StackOverflow,
    StackUnderflow,
}

impl FaultKind {
    pub fn code(self) -> &'static str {
        match self {
            FaultKind::DivideByZero => "divide_by_zero",
            FaultKind::DivideOverflow => "divide_overflow",
            FaultKind::QueueFull => "queue_full",
            FaultKind::QueueEmpty => "queue_empty",
            FaultKind::BadQueue => "bad_queue",
            FaultKind::BadRegister => "bad_register",
            FaultKind::BadMotion => "bad_motion",
            FaultKind::StackOverflow => "stack_overflow",
            FaultKind::StackUnderflow => "stack_underflow",
        }
    }
}

/// A fault that stopped the machine.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Fault {
    pub kind: FaultKind,
    /// Command index of the faulting command.
    pub pc: u32,
    pub message: String,
}

/// What the last executed command did, kept small so the hot path only stores a few words.
/// The explanation and the written-register list are built from it on demand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LastExec {
    /// Command index, `u32::MAX` before the first command.
    pub pc: u32,
    /// Operand values read before the command wrote anything, and results (meaning per command).
    pub vals: [i32; 4],
    pub outcome: Outcome,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Outcome {
    Done,
    /// A flag-variant queue operation failed (nothing changed, NEGATIVE set).
    Failed,
    Faulted,
}

/// Everything that changes while a program runs. Plain data, cheap to clone and compare.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct State {
    pub regs: [i32; REGISTERS],
    pub isw: u16,
    pub psw: u16,
    /// Index of the next command.
    pub pc: u32,
    pub stack: [u32; STACK_DEPTH],
    pub sp: u8,
    pub ticks: u64,
    pub steps: u64,
    pub run: RunState,
    pub delay_left: u32,
    pub wait_cond: Option<Cond>,
    pub cer: Option<u32>,
    pub inputs: u8,
    pub fault: Option<Fault>,
    pub motion: Motion,
    /// The motion model changed R0/R1/R6/R7 in the last tick.
    pub motion_ticked: bool,
    /// Bases of every successful `Q_INIT`, in order of first initialisation.
    pub queue_bases: Vec<u8>,
    pub last: LastExec,
}

impl State {
    fn new() -> Self {
        State {
            regs: [0; REGISTERS],
            isw: isw::DRIVER_ENABLED,
            psw: 0,
            pc: 0,
            stack: [0; STACK_DEPTH],
            sp: 0,
            ticks: 0,
            steps: 0,
            run: RunState::Running,
            delay_left: 0,
            wait_cond: None,
            cer: None,
            inputs: 0,
            fault: None,
            motion: Motion::at_rest(),
            motion_ticked: false,
            queue_bases: Vec::new(),
            last: LastExec {
                pc: u32::MAX,
                vals: [0; 4],
                outcome: Outcome::Done,
            },
        }
    }
}

/// A SilverLode servo running one program.
#[derive(Clone, Debug, PartialEq)]
pub struct SilverLode {
    program: Arc<Program>,
    settings: ServoSettings,
    k1: i64,
    k2: i64,
    s: State,
}

#[inline(always)]
pub(super) fn hi(v: i32) -> i32 {
    (v as u32 >> 16) as i32
}
#[inline(always)]
pub(super) fn lo(v: i32) -> i32 {
    v & 0xFFFF
}
#[inline(always)]
pub(super) fn sx16(word: i32) -> i32 {
    i32::from(word as u16 as i16)
}

/// A queue header read from its two registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RawQueue {
    pub size: u32,
    pub len: u32,
    pub head: u32,
    pub tail: u32,
}

impl RawQueue {
    /// The header fields of two header words, valid or not.
    pub fn from_words(h0: i32, h1: i32) -> RawQueue {
        let (h0, h1) = (h0 as u32, h1 as u32);
        RawQueue {
            size: h0 >> 16,
            len: h0 & 0xFFFF,
            head: h1 >> 16,
            tail: h1 & 0xFFFF,
        }
    }

    /// The queue whose header is at `base`, if it is a valid one.
    pub fn decode(regs: &[i32; REGISTERS], base: usize) -> Option<RawQueue> {
        if base + 1 >= REGISTERS {
            return None;
        }
        let q = RawQueue::from_words(regs[base], regs[base + 1]);
        let valid = q.size >= 1
            && q.len <= q.size
            && q.head < q.size
            && q.tail < q.size
            && base + 1 + (q.size as usize) < REGISTERS;
        valid.then_some(q)
    }

    fn encode(self) -> (i32, i32) {
        (
            (self.size << 16 | self.len) as i32,
            (self.head << 16 | self.tail) as i32,
        )
    }
}

impl SilverLode {
    pub fn new(program: Arc<Program>) -> Self {
        Self::with_settings(program, ServoSettings::default())
    }

    pub fn with_settings(program: Arc<Program>, settings: ServoSettings) -> Self {
        let settings = settings.clamped();
        let (k1, k2) = settings.coefficients();
        let mut m = SilverLode {
            program,
            settings,
            k1,
            k2,
            s: State::new(),
        };
        m.end_if_past_last_line();
        m
    }

    pub fn program(&self) -> &Arc<Program> {
        &self.program
    }
    pub fn settings(&self) -> ServoSettings {
        self.settings
    }
    pub fn state(&self) -> &State {
        &self.s
    }
    pub fn regs(&self) -> &[i32; REGISTERS] {
        &self.s.regs
    }
    pub fn reg(&self, r: usize) -> i32 {
        self.s.regs[r]
    }
    pub fn isw(&self) -> u16 {
        self.s.isw
    }
    pub fn psw(&self) -> u16 {
        self.s.psw
    }
    /// Index of the next command (== program length once it ran past the end).
    pub fn pc(&self) -> u32 {
        self.s.pc
    }
    /// A user edit of a register (out-of-range indices are ignored).
    pub fn set_reg(&mut self, r: usize, value: i32) {
        if let Some(slot) = self.s.regs.get_mut(r) {
            *slot = value;
        }
    }
    /// A user edit of a whole status word (`isw` or PSW); callers check which bits may change.
    pub(crate) fn set_status_word(&mut self, isw: bool, value: u16) {
        if isw {
            self.s.isw = value;
        } else {
            self.s.psw = value;
        }
    }
    /// Toggle-free input set, as the CLI and the input timeline use it.
    pub fn set_io(&mut self, index: usize, high: bool) {
        if index >= 3 {
            return;
        }
        let bit = 1u8 << index;
        if high {
            self.s.inputs |= bit;
            self.s.isw |= isw::IO1 << index;
        } else {
            self.s.inputs &= !bit;
            self.s.isw &= !(isw::IO1 << index);
        }
    }

    pub fn line_of(&self, pc: u32) -> Option<usize> {
        self.program.lines.get(pc as usize).map(|&l| l as usize)
    }
}
