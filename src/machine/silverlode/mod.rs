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

pub mod assembler;
pub mod dialect;
mod explain;
pub mod motion;
pub mod program;
/// The one file of this folder that draws (egui), built only with the window.
#[cfg(feature = "gui")]
pub mod queues_panel;
pub mod syntax;
pub mod view;

use std::sync::Arc;

pub use assembler::assemble;
pub use motion::ServoSettings;
pub use program::{ClcOp, Cond, CondBit, ExtOp, Instr, MoveKind, Program};

use crate::machine::{BitInfo, RunState, StopReason, WaitReason};
pub use view::{QueueAccess, QueueHeader, QueueView};
use motion::{FRAC, Motion};

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

/// A fault raised by a command before it changed anything.
struct Raise(FaultKind, String);

type Exec = Result<(), Raise>;

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
#[inline(always)]
fn flag_bits(v: i32) -> u16 {
    if v == 0 {
        isw::ZERO
    } else if v > 0 {
        isw::POSITIVE
    } else {
        isw::NEGATIVE
    }
}

fn check_divisor(dividend: i32, divisor: i32, what: &str) -> Result<(), Raise> {
    if divisor == 0 {
        return Err(Raise(
            FaultKind::DivideByZero,
            format!("divide by zero: the divisor {what} is 0"),
        ));
    }
    if dividend == i32::MIN && divisor == -1 {
        return Err(Raise(
            FaultKind::DivideOverflow,
            "-2147483648 / -1 does not fit in 32 bits".to_string(),
        ));
    }
    Ok(())
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
    // ---- execution -------------------------------------------------------------------------

    fn end_if_past_last_line(&mut self) {
        if self.s.pc as usize >= self.program.instrs.len() && self.s.run == RunState::Running {
            self.s.run = RunState::Ended;
            self.s.psw |= psw::PROGRAM_DONE;
        }
    }

    /// The current command finished: count it and move on.
    #[inline(always)]
    fn complete(&mut self, next_pc: u32) {
        self.s.steps += 1;
        self.s.pc = next_pc;
        self.s.run = RunState::Running;
        if next_pc as usize >= self.program.instrs.len() {
            self.s.run = RunState::Ended;
            self.s.psw |= psw::PROGRAM_DONE;
        }
    }

    #[inline(always)]
    fn set_flags(&mut self, v: i32) {
        self.s.isw = (self.s.isw & !isw::FLAGS) | flag_bits(v);
    }

    #[inline(always)]
    fn record(&mut self, vals: [i32; 4], outcome: Outcome) {
        self.s.last = LastExec {
            pc: self.s.pc,
            vals,
            outcome,
        };
    }

    /// One tick. Returns false when the machine was not live (nothing happened).
    #[inline]
    pub fn tick(&mut self) -> bool {
        match self.s.run {
            RunState::Running => {
                if !self.execute() {
                    return true;
                }
            }
            RunState::Waiting(WaitReason::Delay) => {
                self.s.delay_left -= 1;
                if self.s.delay_left == 0 {
                    self.s.isw |= isw::DELAY_DONE;
                    self.complete(self.s.pc + 1);
                }
            }
            RunState::Waiting(WaitReason::Condition) => {
                if self.s.wait_cond.is_none_or(|c| c.holds(self.s.isw)) {
                    self.complete(self.s.pc + 1);
                }
            }
            RunState::Waiting(WaitReason::Move) => {}
            RunState::Ended | RunState::Faulted => return false,
        }
        self.motion_tick();
        if self.s.run == RunState::Waiting(WaitReason::Move) && !self.s.motion.active {
            self.complete(self.s.pc + 1);
        }
        self.s.ticks += 1;
        true
    }

    /// Execute the command at pc. Returns false when it faulted without a handler (the tick
    /// is then not spent).
    #[inline(always)]
    fn execute(&mut self) -> bool {
        let pc = self.s.pc;
        let Some(&instr) = self.program.instrs.get(pc as usize) else {
            self.end_if_past_last_line();
            return false;
        };
        let result = match instr {
            Instr::Clc { op, reg } => self.clc(op, reg as usize),
            Instr::Cld {
                op,
                res,
                reg1,
                data,
            } => self.ext(op, res as usize, reg1 as usize, data),
            Instr::Clx {
                op,
                res,
                reg1,
                reg2,
            } => {
                let d = self.s.regs[reg2 as usize];
                self.ext(op, res as usize, reg1 as usize, d)
            }
            // Jumps close every loop: keep them out of the rarely used `flow`.
            Instr::Jmp { target, cond } => {
                let taken = cond.is_none_or(|c| c.holds(self.s.isw));
                self.record([i32::from(taken), 0, 0, 0], Outcome::Done);
                self.complete(if taken { target } else { pc + 1 });
                Ok(())
            }
            _ => self.flow(instr),
        };
        match result {
            Ok(()) => true,
            Err(Raise(kind, message)) => self.raise(kind, message),
        }
    }

    fn raise(&mut self, kind: FaultKind, message: String) -> bool {
        self.s.psw |= psw::COMMAND_ERROR;
        self.record([0; 4], Outcome::Faulted);
        let line = self
            .program
            .lines
            .get(self.s.pc as usize)
            .copied()
            .unwrap_or(0);
        if let Some(handler) = self.s.cer {
            // The handled error spends the tick; the faulting command is not counted as a step.
            self.s.fault = Some(Fault {
                kind,
                pc: self.s.pc,
                message: format!("{message} (line {line}, handled by CER)"),
            });
            self.s.pc = handler;
            self.end_if_past_last_line();
            true
        } else {
            self.s.fault = Some(Fault {
                kind,
                pc: self.s.pc,
                message,
            });
            self.s.run = RunState::Faulted;
            false
        }
    }

    #[inline(always)]
    fn clc(&mut self, op: ClcOp, reg: usize) -> Exec {
        let acc = self.s.regs[10];
        let x = self.s.regs[reg];
        // (register written, value)
        let (dst, v, extra) = match op {
            ClcOp::Clear => (reg, 0, 0),
            ClcOp::Copy => (10, x, 0),
            ClcOp::Save => (reg, acc, 0),
            ClcOp::CopyRef | ClcOp::SaveRef => {
                if !(0..REGISTERS as i32).contains(&x) {
                    return Err(Raise(
                        FaultKind::BadRegister,
                        format!("R{reg} = {x} does not name a register (0 ..= 199)"),
                    ));
                }
                if op == ClcOp::CopyRef {
                    (10, self.s.regs[x as usize], 0)
                } else {
                    (x as usize, acc, 0)
                }
            }
            ClcOp::Abs => (reg, x.wrapping_abs(), 0),
            ClcOp::Neg => (reg, x.wrapping_neg(), 0),
            ClcOp::Inc => (reg, x.wrapping_add(1), 0),
            ClcOp::Dec => (reg, x.wrapping_sub(1), 0),
            ClcOp::Add => (10, acc.wrapping_add(x), 0),
            ClcOp::AddHi => (10, acc.wrapping_add(sx16(hi(x))), 0),
            ClcOp::AddLo => (10, acc.wrapping_add(sx16(lo(x))), 0),
            ClcOp::Sub => (10, acc.wrapping_sub(x), 0),
            ClcOp::SubRev => (10, x.wrapping_sub(acc), 0),
            ClcOp::MultS | ClcOp::MultU => (10, acc.wrapping_mul(x), 0),
            ClcOp::Div | ClcOp::Mod => {
                let divisor = sx16(lo(x));
                check_divisor(acc, divisor, &format!("LO(R{reg}) of 0x{:08X}", x as u32))?;
                if op == ClcOp::Div {
                    (10, acc / divisor, 0)
                } else {
                    (10, acc % divisor, 0)
                }
            }
            ClcOp::Max => (10, acc.max(x), 0),
            ClcOp::Min => (10, acc.min(x), 0),
            ClcOp::And => (10, acc & x, 0),
            ClcOp::Or => (10, acc | x, 0),
            ClcOp::Xor => (10, acc ^ x, 0),
            ClcOp::Shl => (reg, x.wrapping_shl(1), 0),
            ClcOp::ShrS => (reg, x >> 1, 0),
            ClcOp::ShrU => (reg, (x as u32 >> 1) as i32, 0),
            ClcOp::CopyWordHiAcc => (10, lo(x) << 16 | lo(acc), 0),
            ClcOp::CopyWordHiReg => (reg, lo(acc) << 16 | lo(x), 0),
            ClcOp::CopyWordLoReg => (reg, (x as u32 & 0xFFFF_0000) as i32 | lo(acc), 0),
            ClcOp::SextHi => (10, sx16(hi(x)), 0),
            ClcOp::SextLo => (10, sx16(lo(x)), 0),
            ClcOp::SubTarget => {
                let (r0, r1) = (self.s.regs[0], self.s.regs[1]);
                self.record([r0, x, r0.wrapping_sub(x), r1], Outcome::Done);
                self.shift_positions(i64::from(x), i64::from(x));
                self.set_flags(self.s.regs[0]);
                self.complete(self.s.pc + 1);
                return Ok(());
            }
        };
        self.record([acc, x, v, extra], Outcome::Done);
        self.s.regs[dst] = v;
        self.set_flags(v);
        self.complete(self.s.pc + 1);
        Ok(())
    }

    #[inline(always)]
    fn ext(&mut self, op: ExtOp, res: usize, reg1: usize, d: i32) -> Exec {
        let a = self.s.regs[reg1];
        let v = match op {
            ExtOp::Copy => a,
            ExtOp::Abs => a.wrapping_abs(),
            ExtOp::Neg => a.wrapping_neg(),
            ExtOp::Add => a.wrapping_add(d),
            ExtOp::Sub => a.wrapping_sub(d),
            ExtOp::SubRev => d.wrapping_sub(a),
            ExtOp::AddHi => sx16(hi(a)).wrapping_add(d),
            ExtOp::AddLo => sx16(lo(a)).wrapping_add(d),
            ExtOp::And => a & d,
            ExtOp::Or => a | d,
            ExtOp::Xor => a ^ d,
            ExtOp::Max => a.max(d),
            ExtOp::Min => a.min(d),
            ExtOp::SextHi => sx16(hi(a)),
            ExtOp::SextLo => sx16(lo(a)),
            ExtOp::PackLoLo => lo(a) << 16 | lo(d),
            ExtOp::PackHiLo => hi(a) << 16 | lo(d),
            ExtOp::PackHiHi => hi(a) << 16 | hi(d),
            ExtOp::MultS | ExtOp::MultU => a.wrapping_mul(d),
            ExtOp::MultS64Shr16 => ((i64::from(a) * i64::from(d)) >> 16) as i32,
            ExtOp::Div | ExtOp::Mod => {
                let divisor = sx16(lo(d));
                check_divisor(a, divisor, &format!("LO(data) of 0x{:08X}", d as u32))?;
                if op == ExtOp::Div {
                    a / divisor
                } else {
                    a % divisor
                }
            }
            ExtOp::DivRev | ExtOp::ModRev => {
                let divisor = sx16(lo(a));
                check_divisor(d, divisor, &format!("LO(R{reg1}) of 0x{:08X}", a as u32))?;
                if op == ExtOp::DivRev {
                    d / divisor
                } else {
                    d % divisor
                }
            }
            ExtOp::MultU64 => {
                if res >= REGISTERS - 1 {
                    return Err(Raise(
                        FaultKind::BadRegister,
                        "MULT_U64 needs two result registers; R199 has no R200 after it"
                            .to_string(),
                    ));
                }
                let p = u64::from(a as u32) * u64::from(d as u32);
                self.record([a, d, (p >> 32) as i32, p as i32], Outcome::Done);
                self.s.regs[res + 1] = p as i32;
                self.s.regs[res] = (p >> 32) as i32;
                self.s.isw =
                    (self.s.isw & !isw::FLAGS) | if p == 0 { isw::ZERO } else { isw::POSITIVE };
                self.complete(self.s.pc + 1);
                return Ok(());
            }
            ExtOp::DivU64 => {
                if reg1 >= REGISTERS - 1 {
                    return Err(Raise(
                        FaultKind::BadRegister,
                        "DIV_U64 reads a register pair; R199 has no R200 after it".to_string(),
                    ));
                }
                let low = self.s.regs[reg1 + 1];
                let n = u64::from(a as u32) << 32 | u64::from(low as u32);
                let divisor = u64::from(d as u32);
                if divisor == 0 {
                    return Err(Raise(
                        FaultKind::DivideByZero,
                        "divide by zero: the 32-bit divisor is 0".to_string(),
                    ));
                }
                let q = n / divisor;
                if q > u64::from(u32::MAX) {
                    return Err(Raise(
                        FaultKind::DivideOverflow,
                        format!("{n} / {divisor} = {q} does not fit in 32 bits"),
                    ));
                }
                self.record([a, low, d, q as i32], Outcome::Done);
                self.s.regs[res] = q as i32;
                self.s.isw =
                    (self.s.isw & !isw::FLAGS) | if q == 0 { isw::ZERO } else { isw::POSITIVE };
                self.complete(self.s.pc + 1);
                return Ok(());
            }
            _ => return self.queue(op, res, reg1, d),
        };
        self.record([a, d, v, 0], Outcome::Done);
        self.s.regs[res] = v;
        self.set_flags(v);
        self.complete(self.s.pc + 1);
        Ok(())
    }

    fn queue(&mut self, op: ExtOp, res: usize, base: usize, d: i32) -> Exec {
        let regs = &self.s.regs;
        let before = [regs[base], regs.get(base + 1).copied().unwrap_or(0)];
        if op == ExtOp::QInit {
            if d < 1 || base + 1 + d as usize > REGISTERS - 1 {
                return Err(Raise(
                    FaultKind::BadQueue,
                    format!(
                        "a queue of {d} slots at R{base} does not fit: it needs size ≥ 1 and R{base} ..= R{} ≤ R199",
                        i64::from(d) + base as i64 + 1
                    ),
                ));
            }
            self.record([before[0], before[1], d, d], Outcome::Done);
            self.s.regs[base] = d << 16;
            self.s.regs[base + 1] = 0;
            self.s.regs[res] = d;
            if !self.s.queue_bases.contains(&(base as u8)) {
                self.s.queue_bases.push(base as u8);
            }
            return self.queue_done(true);
        }
        let Some(mut q) = RawQueue::decode(regs, base) else {
            return Err(Raise(
                FaultKind::BadQueue,
                format!(
                    "R{base} does not hold a valid queue header (size|len = 0x{:08X}, head|tail = 0x{:08X})",
                    before[0] as u32, before[1] as u32
                ),
            ));
        };
        let slot0 = base + 2;
        let full = q.len == q.size;
        let empty = q.len == 0;
        let fail = |kind: FaultKind, what: &str| {
            Err(Raise(
                kind,
                format!(
                    "queue at R{base} is {what} ({} of {} slots used)",
                    q.len, q.size
                ),
            ))
        };
        let result = match op {
            ExtOp::QPushHeadErr if full => return fail(FaultKind::QueueFull, "full"),
            ExtOp::QPushTailErr if full => return fail(FaultKind::QueueFull, "full"),
            ExtOp::QPopHeadErr | ExtOp::QPopTailErr if empty => {
                return fail(FaultKind::QueueEmpty, "empty");
            }
            ExtOp::QPushHead | ExtOp::QPushTail if full => None,
            ExtOp::QPopHead | ExtOp::QPopTail if empty => None,
            ExtOp::QPushHead | ExtOp::QPushHeadErr => {
                self.s.regs[slot0 + q.head as usize] = d;
                q.head = (q.head + 1) % q.size;
                q.len += 1;
                Some((q.size - q.len) as i32)
            }
            ExtOp::QPushTail | ExtOp::QPushTailErr => {
                q.tail = (q.tail + q.size - 1) % q.size;
                self.s.regs[slot0 + q.tail as usize] = d;
                q.len += 1;
                Some((q.size - q.len) as i32)
            }
            ExtOp::QPopHead | ExtOp::QPopHeadErr => {
                q.head = (q.head + q.size - 1) % q.size;
                q.len -= 1;
                Some(self.s.regs[slot0 + q.head as usize])
            }
            ExtOp::QPopTail | ExtOp::QPopTailErr => {
                let v = self.s.regs[slot0 + q.tail as usize];
                q.tail = (q.tail + 1) % q.size;
                q.len -= 1;
                Some(v)
            }
            _ => {
                // Q_READ: 0 ..< len from the head (0 = newest), -1 ..= -len from the tail.
                let n = i64::from(d);
                let (size, len) = (i64::from(q.size), i64::from(q.len));
                let slot = if n >= 0 && n < len {
                    Some((i64::from(q.head) - 1 - n).rem_euclid(size))
                } else if n < 0 && -n <= len {
                    Some((i64::from(q.tail) - 1 - n).rem_euclid(size))
                } else {
                    None
                };
                slot.map(|s| self.s.regs[slot0 + s as usize])
            }
        };
        match result {
            Some(value) => {
                self.record([before[0], before[1], d, value], Outcome::Done);
                if op != ExtOp::QRead {
                    let (h0, h1) = q.encode();
                    self.s.regs[base] = h0;
                    self.s.regs[base + 1] = h1;
                }
                self.s.regs[res] = value;
                self.queue_done(true)
            }
            None => {
                self.record([before[0], before[1], d, 0], Outcome::Failed);
                self.queue_done(false)
            }
        }
    }

    fn queue_done(&mut self, ok: bool) -> Exec {
        let flag = if ok { isw::ZERO } else { isw::NEGATIVE };
        self.s.isw = (self.s.isw & !isw::FLAGS) | flag;
        self.complete(self.s.pc + 1);
        Ok(())
    }

    #[inline(never)]
    fn flow(&mut self, instr: Instr) -> Exec {
        let next = self.s.pc + 1;
        match instr {
            Instr::Wrp { reg, value } => {
                self.record([self.s.regs[reg as usize], value, value, 0], Outcome::Done);
                self.s.regs[reg as usize] = value;
                self.complete(next);
            }
            Instr::Call { target } => {
                if self.s.sp as usize >= STACK_DEPTH {
                    return Err(Raise(
                        FaultKind::StackOverflow,
                        format!("CALL nested deeper than {STACK_DEPTH} levels"),
                    ));
                }
                self.record([self.s.sp as i32, 0, 0, 0], Outcome::Done);
                self.s.stack[self.s.sp as usize] = next;
                self.s.sp += 1;
                self.complete(target);
            }
            Instr::Ret => {
                if self.s.sp == 0 {
                    return Err(Raise(
                        FaultKind::StackUnderflow,
                        "RET with no CALL to return to".to_string(),
                    ));
                }
                self.record([self.s.sp as i32, 0, 0, 0], Outcome::Done);
                self.s.sp -= 1;
                let back = self.s.stack[self.s.sp as usize];
                self.complete(back);
            }
            Instr::Dly { ticks } => {
                self.record([ticks as i32, 0, 0, 0], Outcome::Done);
                self.s.isw &= !isw::DELAY_DONE;
                if ticks <= 1 {
                    self.s.isw |= isw::DELAY_DONE;
                    self.complete(next);
                } else {
                    self.s.delay_left = ticks - 1;
                    self.s.run = RunState::Waiting(WaitReason::Delay);
                }
            }
            Instr::Wbs { cond } => {
                let holds = cond.holds(self.s.isw);
                self.record([i32::from(holds), 0, 0, 0], Outcome::Done);
                if holds {
                    self.complete(next);
                } else {
                    self.s.wait_cond = Some(cond);
                    self.s.run = RunState::Waiting(WaitReason::Condition);
                }
            }
            Instr::Cer { target } => {
                self.record([0; 4], Outcome::Done);
                self.s.cer = target;
                self.complete(next);
            }
            Instr::End => {
                self.record([0; 4], Outcome::Done);
                self.s.steps += 1;
                self.s.run = RunState::Ended;
                self.s.psw |= psw::PROGRAM_DONE;
            }
            Instr::Move {
                kind,
                pos,
                accel,
                vel,
                cond,
            } => self.start_move(kind, pos, accel, vel, cond)?,
            Instr::Ztp => {
                let (r0, r1) = (self.s.regs[0], self.s.regs[1]);
                self.record([r0, r1, 0, 0], Outcome::Done);
                self.shift_positions(i64::from(r0), i64::from(r1));
                self.complete(next);
            }
            Instr::Ttp => {
                let (r0, r1) = (self.s.regs[0], self.s.regs[1]);
                self.record([r0, r1, 0, 0], Outcome::Done);
                self.s.regs[0] = r1;
                self.s.motion.settled = false;
                self.complete(next);
            }
            // Calculations and jumps run in `execute`, the hot path.
            Instr::Clc { .. } | Instr::Cld { .. } | Instr::Clx { .. } | Instr::Jmp { .. } => {}
        }
        Ok(())
    }

    fn start_move(
        &mut self,
        kind: MoveKind,
        pos: i32,
        accel: i32,
        vel: i32,
        cond: Option<Cond>,
    ) -> Exec {
        let (accel, vel) = (accel as u32, vel as u32);
        if !(1..=1 << 30).contains(&accel) {
            return Err(Raise(
                FaultKind::BadMotion,
                format!("acceleration {accel} is outside 1 ..= 1073741824 (native units)"),
            ));
        }
        if vel > 1 << 31 {
            return Err(Raise(
                FaultKind::BadMotion,
                format!("velocity {vel} is outside 0 ..= 2147483648 (native units)"),
            ));
        }
        let start = self.s.regs[0];
        let operand = if kind.takes_register() {
            self.s.regs[pos as usize]
        } else {
            pos
        };
        let end = if kind.is_relative() {
            let end = i64::from(start) + i64::from(operand);
            i32::try_from(end).map_err(|_| {
                Raise(
                    FaultKind::BadMotion,
                    format!("target {start} + {operand} = {end} does not fit in 32 bits"),
                )
            })?
        } else {
            operand
        };
        self.record([start, end, operand, 0], Outcome::Done);
        self.s.isw &= !isw::INPUT_FOUND;
        self.s.psw &= !psw::INPUT_FOUND;
        let m = &mut self.s.motion;
        if m.settled {
            // Wake the follower exactly where the registers say the motor is.
            m.x = i64::from(self.s.regs[1]) << FRAC;
            m.v = 0;
        }
        m.start(start, end, accel, vel, cond);
        m.settled = false;
        self.s.run = RunState::Waiting(WaitReason::Move);
        Ok(())
    }

    /// SUB_TARGET / ZTP: move the zero point; the motor does not move.
    fn shift_positions(&mut self, target_by: i64, actual_by: i64) {
        let regs = &mut self.s.regs;
        regs[0] = regs[0].wrapping_sub(target_by as i32);
        regs[1] = regs[1].wrapping_sub(actual_by as i32);
        regs[6] = regs[0].wrapping_sub(regs[1]);
        let m = &mut self.s.motion;
        m.shift(target_by, actual_by);
        m.seen_r0 = regs[0];
        m.seen_r1 = regs[1];
    }

    /// The motion phase of a tick. Costs a few compares while the motor is at rest.
    #[inline(always)]
    fn motion_tick(&mut self) {
        let m = &self.s.motion;
        // `settled` implies no trajectory; R0 and R1 unchanged since the model last wrote them.
        let idle = m.settled && (m.seen_r0, m.seen_r1) == (self.s.regs[0], self.s.regs[1]);
        if idle {
            self.s.motion_ticked = false;
        } else {
            self.s.motion_ticked = true;
            self.motion_step();
        }
    }

    fn motion_step(&mut self) {
        let regs = &mut self.s.regs;
        let m = &mut self.s.motion;
        if regs[1] != m.seen_r1 {
            // A program or the user wrote the actual position: the motor is now there.
            m.x = i64::from(regs[1]) << FRAC;
            m.v = 0;
        }
        if m.active && !m.stopping && m.stop_cond.is_some_and(|c| c.holds(self.s.isw)) {
            m.stopping = true;
            regs[4] = regs[1];
            self.s.isw |= isw::INPUT_FOUND;
            self.s.psw |= psw::INPUT_FOUND;
        }
        let moving = m.active;
        let reference = if m.active {
            regs[0] = m.advance_trajectory();
            m.pos
        } else {
            i64::from(regs[0]) << FRAC
        };
        m.settled = false;
        regs[1] = m.advance_follower(reference, self.k1, self.k2);
        regs[6] = regs[0].wrapping_sub(regs[1]);
        regs[7] = m.v.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32;
        m.seen_r0 = regs[0];
        m.seen_r1 = regs[1];
        let err = regs[6].unsigned_abs();
        let mut bits = self.s.isw & !(isw::MOVING_ERROR | isw::HOLDING_ERROR);
        if moving && err > self.settings.moving_error_limit {
            bits |= isw::MOVING_ERROR;
        }
        if !moving && err > self.settings.holding_error_limit {
            bits |= isw::HOLDING_ERROR;
        }
        self.s.isw = bits;
    }

    /// Run at full speed; see [`crate::machine::Machine::run_observed`].
    #[inline]
    pub fn run_fast<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        tick_limit: u64,
        mut stop: F,
        mut observe: O,
    ) -> StopReason {
        loop {
            match self.s.run {
                RunState::Ended | RunState::Faulted => return StopReason::Stopped,
                RunState::Running => {
                    if self.s.ticks >= tick_limit {
                        return StopReason::TickLimit;
                    }
                    if stop(self) {
                        return StopReason::Predicate;
                    }
                }
                RunState::Waiting(_) => {
                    if self.s.ticks >= tick_limit {
                        return StopReason::TickLimit;
                    }
                }
            }
            if self.tick() {
                observe(self);
            }
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

    /// The queue the last command used, derived from the command and its record.
    pub fn last_queue_access(&self) -> Option<QueueAccess> {
        let last = self.s.last;
        let (op, base) = match *self.program.instrs.get(last.pc as usize)? {
            Instr::Cld { op, reg1, .. } | Instr::Clx { op, reg1, .. } if op.is_queue() => {
                (op, reg1 as usize)
            }
            _ => return None,
        };
        let [h0, h1, d, _] = last.vals;
        let q = RawQueue::from_words(h0, h1);
        let size = i64::from(q.size.max(1));
        let (head, tail) = (i64::from(q.head), i64::from(q.tail));
        let (action, slot) = match op {
            ExtOp::QInit => ("init".to_string(), None),
            ExtOp::QPushHead | ExtOp::QPushHeadErr => ("push head".to_string(), Some(head)),
            ExtOp::QPopHead | ExtOp::QPopHeadErr => ("pop head".to_string(), Some(head - 1)),
            ExtOp::QPushTail | ExtOp::QPushTailErr => ("push tail".to_string(), Some(tail - 1)),
            ExtOp::QPopTail | ExtOp::QPopTailErr => ("pop tail".to_string(), Some(tail)),
            _ => {
                let n = i64::from(d);
                let slot = if n >= 0 { head - 1 - n } else { tail - 1 - n };
                (format!("read {n}"), Some(slot))
            }
        };
        let ok = last.outcome == Outcome::Done;
        let failure = (!ok).then(|| match (op, self.s.fault.as_ref().map(|f| f.kind)) {
            (_, Some(FaultKind::BadQueue)) if last.outcome == Outcome::Faulted => {
                "not a valid queue"
            }
            (
                ExtOp::QPushHead | ExtOp::QPushTail | ExtOp::QPushHeadErr | ExtOp::QPushTailErr,
                _,
            ) => "full",
            (ExtOp::QRead, _) => "no such element",
            _ => "empty",
        });
        Some(QueueAccess {
            base,
            action,
            slot: slot.filter(|_| ok).map(|s| s.rem_euclid(size) as usize),
            ok,
            failure,
        })
    }

    /// Registers the last command wrote, derived from the command and its record.
    pub fn written_by_last(&self) -> Vec<usize> {
        let last = self.s.last;
        let mut out = Vec::new();
        if last.outcome != Outcome::Done {
            return out;
        }
        let Some(&instr) = self.program.instrs.get(last.pc as usize) else {
            return out;
        };
        match instr {
            Instr::Clc { op, reg } => match op {
                ClcOp::Clear
                | ClcOp::Save
                | ClcOp::Abs
                | ClcOp::Neg
                | ClcOp::Inc
                | ClcOp::Dec
                | ClcOp::Shl
                | ClcOp::ShrS
                | ClcOp::ShrU
                | ClcOp::CopyWordHiReg
                | ClcOp::CopyWordLoReg => out.push(reg as usize),
                ClcOp::SaveRef => out.push(last.vals[1] as usize),
                ClcOp::SubTarget => out.extend([0, 1, 6]),
                _ => out.push(10),
            },
            Instr::Cld { op, res, reg1, .. } | Instr::Clx { op, res, reg1, .. } => {
                let (res, base) = (res as usize, reg1 as usize);
                match op {
                    ExtOp::MultU64 => out.extend([res, res + 1]),
                    ExtOp::QInit => out.extend([base, base + 1, res]),
                    ExtOp::QRead => out.push(res),
                    ExtOp::QPushHead | ExtOp::QPushHeadErr => {
                        let head = RawQueue::from_words(last.vals[0], last.vals[1]).head as usize;
                        out.extend([base + 2 + head, base, base + 1, res]);
                    }
                    ExtOp::QPushTail | ExtOp::QPushTailErr => {
                        let q = RawQueue::decode(&self.s.regs, base);
                        if let Some(q) = q {
                            out.push(base + 2 + q.tail as usize);
                        }
                        out.extend([base, base + 1, res]);
                    }
                    _ if op.is_queue() => out.extend([base, base + 1, res]),
                    _ => out.push(res),
                }
            }
            Instr::Wrp { reg, .. } => out.push(reg as usize),
            Instr::Ztp => out.extend([0, 1, 6]),
            Instr::Ttp => out.push(0),
            _ => {}
        }
        if self.s.motion_ticked {
            out.extend([0, 1, 6, 7]);
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

