//! The executor: one tick of the machine, every command, queues, moves and the motion model
//! (spec §3–§6). Faults are raised before a command changes anything.

use super::motion::FRAC;
use super::program::{ClcOp, Cond, ExtOp, Instr, MoveKind, Op};
use super::{
    Fault, FaultKind, LastExec, Outcome, REGISTERS, RawQueue, STACK_DEPTH, SilverLode, hi, isw, lo,
    psw, sx16,
};
use crate::machine::{RunState, StopReason, WaitReason};

/// A fault raised by a command before it changed anything.
struct Raise(FaultKind, String);

type Exec = Result<(), Raise>;

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

/// `dividend / LO(word)` (`%` when `modulo`), the divisor sign-extended from 16 bits (spec §3);
/// `what` names the divisor in the fault of a 0 (or of −1 under i32::MIN).
#[inline]
fn divide(
    dividend: i32,
    word: i32,
    modulo: bool,
    what: impl FnOnce() -> String,
) -> Result<i32, Raise> {
    let divisor = sx16(lo(word));
    if divisor == 0 {
        return Err(Raise(
            FaultKind::DivideByZero,
            format!("divide by zero: the divisor {} is 0", what()),
        ));
    }
    if dividend == i32::MIN && divisor == -1 {
        return Err(Raise(
            FaultKind::DivideOverflow,
            format!("{dividend} / -1 does not fit in 32 bits"),
        ));
    }
    Ok(if modulo {
        dividend % divisor
    } else {
        dividend / divisor
    })
}

/// What a register-only command did: the values its explanation shows, whether it succeeded
/// (a flag-variant queue operation may not), and the flag bits it leaves.
struct Effect {
    vals: [i32; 4],
    outcome: Outcome,
    flags: u16,
}

impl Effect {
    #[inline(always)]
    fn value(vals: [i32; 4], v: i32) -> Effect {
        Effect {
            vals,
            outcome: Outcome::Done,
            flags: flag_bits(v),
        }
    }
}

/// A CLC command but SUB_TARGET, on the registers alone: the full executor and the fast loop
/// both run this. A fault leaves the registers untouched.
#[inline]
fn clc_effect(regs: &mut [i32; REGISTERS], op: ClcOp, reg: usize) -> Result<Effect, Raise> {
    let acc = regs[10];
    let x = regs[reg];
    // (register written, value)
    let (dst, v) = match op {
        ClcOp::Clear => (reg, 0),
        ClcOp::Copy => (10, x),
        ClcOp::Save => (reg, acc),
        ClcOp::CopyRef | ClcOp::SaveRef => {
            if !(0..REGISTERS as i32).contains(&x) {
                return Err(Raise(
                    FaultKind::BadRegister,
                    format!("R{reg} = {x} does not name a register (0 ..= 199)"),
                ));
            }
            if op == ClcOp::CopyRef {
                (10, regs[x as usize])
            } else {
                (x as usize, acc)
            }
        }
        ClcOp::Abs => (reg, x.wrapping_abs()),
        ClcOp::Neg => (reg, x.wrapping_neg()),
        ClcOp::Inc => (reg, x.wrapping_add(1)),
        ClcOp::Dec => (reg, x.wrapping_sub(1)),
        ClcOp::Add => (10, acc.wrapping_add(x)),
        ClcOp::AddHi => (10, acc.wrapping_add(sx16(hi(x)))),
        ClcOp::AddLo => (10, acc.wrapping_add(sx16(lo(x)))),
        ClcOp::Sub => (10, acc.wrapping_sub(x)),
        ClcOp::SubRev => (10, x.wrapping_sub(acc)),
        ClcOp::MultS | ClcOp::MultU => (10, acc.wrapping_mul(x)),
        ClcOp::Div | ClcOp::Mod => (
            10,
            divide(acc, x, op == ClcOp::Mod, || {
                format!("LO(R{reg}) of 0x{:08X}", x as u32)
            })?,
        ),
        ClcOp::Max => (10, acc.max(x)),
        ClcOp::Min => (10, acc.min(x)),
        ClcOp::And => (10, acc & x),
        ClcOp::Or => (10, acc | x),
        ClcOp::Xor => (10, acc ^ x),
        ClcOp::Shl => (reg, x.wrapping_shl(1)),
        ClcOp::ShrS => (reg, x >> 1),
        ClcOp::ShrU => (reg, (x as u32 >> 1) as i32),
        ClcOp::CopyWordHiAcc => (10, lo(x) << 16 | lo(acc)),
        ClcOp::CopyWordHiReg => (reg, lo(acc) << 16 | lo(x)),
        ClcOp::CopyWordLoReg => (reg, (x as u32 & 0xFFFF_0000) as i32 | lo(acc)),
        ClcOp::SextHi => (10, sx16(hi(x))),
        ClcOp::SextLo => (10, sx16(lo(x))),
        // Moves the zero point: the executor's own (`SilverLode::clc`).
        ClcOp::SubTarget => {
            return Err(Raise(
                FaultKind::BadRegister,
                "SUB_TARGET moves the motion model".to_string(),
            ));
        }
    };
    regs[dst] = v;
    Ok(Effect::value([acc, x, v, 0], v))
}

/// A CLD/CLX command but Q_INIT, on the registers alone: the full executor and the fast loop
/// both run this. A fault leaves the registers untouched.
#[inline]
fn ext_effect(
    regs: &mut [i32; REGISTERS],
    op: ExtOp,
    res: usize,
    reg1: usize,
    d: i32,
) -> Result<Effect, Raise> {
    let a = regs[reg1];
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
        ExtOp::Div | ExtOp::Mod => divide(a, d, op == ExtOp::Mod, || {
            format!("LO(data) of 0x{:08X}", d as u32)
        })?,
        ExtOp::DivRev | ExtOp::ModRev => divide(d, a, op == ExtOp::ModRev, || {
            format!("LO(R{reg1}) of 0x{:08X}", a as u32)
        })?,
        ExtOp::MultU64 => {
            if res >= REGISTERS - 1 {
                return Err(Raise(
                    FaultKind::BadRegister,
                    "MULT_U64 needs two result registers; R199 has no R200 after it".to_string(),
                ));
            }
            let p = u64::from(a as u32) * u64::from(d as u32);
            regs[res + 1] = p as i32;
            regs[res] = (p >> 32) as i32;
            return Ok(Effect {
                vals: [a, d, (p >> 32) as i32, p as i32],
                outcome: Outcome::Done,
                flags: if p == 0 { isw::ZERO } else { isw::POSITIVE },
            });
        }
        ExtOp::DivU64 => {
            if reg1 >= REGISTERS - 1 {
                return Err(Raise(
                    FaultKind::BadRegister,
                    "DIV_U64 reads a register pair; R199 has no R200 after it".to_string(),
                ));
            }
            let low = regs[reg1 + 1];
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
            regs[res] = q as i32;
            return Ok(Effect {
                vals: [a, low, d, q as i32],
                outcome: Outcome::Done,
                flags: if q == 0 { isw::ZERO } else { isw::POSITIVE },
            });
        }
        _ => return queue_effect(regs, op, res, reg1, d),
    };
    regs[res] = v;
    Ok(Effect::value([a, d, v, 0], v))
}

/// A queue operation but Q_INIT (spec §4).
fn queue_effect(
    regs: &mut [i32; REGISTERS],
    op: ExtOp,
    res: usize,
    base: usize,
    d: i32,
) -> Result<Effect, Raise> {
    let before = [regs[base], regs.get(base + 1).copied().unwrap_or(0)];
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
            regs[slot0 + q.head as usize] = d;
            q.head = (q.head + 1) % q.size;
            q.len += 1;
            Some((q.size - q.len) as i32)
        }
        ExtOp::QPushTail | ExtOp::QPushTailErr => {
            q.tail = (q.tail + q.size - 1) % q.size;
            regs[slot0 + q.tail as usize] = d;
            q.len += 1;
            Some((q.size - q.len) as i32)
        }
        ExtOp::QPopHead | ExtOp::QPopHeadErr => {
            q.head = (q.head + q.size - 1) % q.size;
            q.len -= 1;
            Some(regs[slot0 + q.head as usize])
        }
        ExtOp::QPopTail | ExtOp::QPopTailErr => {
            let v = regs[slot0 + q.tail as usize];
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
            slot.map(|s| regs[slot0 + s as usize])
        }
    };
    Ok(match result {
        Some(value) => {
            if op != ExtOp::QRead {
                let (h0, h1) = q.encode();
                regs[base] = h0;
                regs[base + 1] = h1;
            }
            regs[res] = value;
            Effect {
                vals: [before[0], before[1], d, value],
                outcome: Outcome::Done,
                flags: isw::ZERO,
            }
        }
        None => Effect {
            vals: [before[0], before[1], d, 0],
            outcome: Outcome::Failed,
            flags: isw::NEGATIVE,
        },
    })
}

impl SilverLode {
    pub(super) fn end_if_past_last_line(&mut self) {
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
    #[inline(always)]
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
        if op == ClcOp::SubTarget {
            let (r0, r1, x) = (self.s.regs[0], self.s.regs[1], self.s.regs[reg]);
            self.record([r0, x, r0.wrapping_sub(x), r1], Outcome::Done);
            self.shift_positions(i64::from(x), i64::from(x));
            self.set_flags(self.s.regs[0]);
            self.complete(self.s.pc + 1);
            return Ok(());
        }
        let effect = clc_effect(&mut self.s.regs, op, reg)?;
        self.apply(effect);
        Ok(())
    }

    #[inline(always)]
    fn ext(&mut self, op: ExtOp, res: usize, reg1: usize, d: i32) -> Exec {
        if op == ExtOp::QInit {
            return self.queue_init(res, reg1, d);
        }
        let effect = ext_effect(&mut self.s.regs, op, res, reg1, d)?;
        self.apply(effect);
        Ok(())
    }

    /// A register-only command ran: explain it, set its flags, move on.
    #[inline(always)]
    fn apply(&mut self, effect: Effect) {
        self.record(effect.vals, effect.outcome);
        self.s.isw = (self.s.isw & !isw::FLAGS) | effect.flags;
        self.complete(self.s.pc + 1);
    }

    fn queue_init(&mut self, res: usize, base: usize, d: i32) -> Exec {
        let regs = &self.s.regs;
        let before = [regs[base], regs.get(base + 1).copied().unwrap_or(0)];
        if d < 1 || base + 1 + d as usize > REGISTERS - 1 {
            return Err(Raise(
                FaultKind::BadQueue,
                format!(
                    "a queue of {d} slots at R{base} does not fit: it needs size ≥ 1 and R{base}–R{} within R0–R199",
                    i64::from(d) + base as i64 + 1
                ),
            ));
        }
        self.s.regs[base] = d << 16;
        self.s.regs[base + 1] = 0;
        self.s.regs[res] = d;
        if !self.s.queue_bases.contains(&(base as u8)) {
            self.s.queue_bases.push(base as u8);
        }
        self.apply(Effect {
            vals: [before[0], before[1], d, d],
            outcome: Outcome::Done,
            flags: isw::ZERO,
        });
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

    /// Whether the motion model has nothing to do this tick (see `motion_tick`).
    #[inline(always)]
    pub(super) fn motion_idle(&self) -> bool {
        let m = &self.s.motion;
        m.settled && (m.seen_r0, m.seen_r1) == (self.s.regs[0], self.s.regs[1])
    }

    /// Run plain commands ([`Op`]: registers and flags only, one tick each) while the machine
    /// runs and the motor rests, exactly as `tick` would, with the bookkeeping done once at the
    /// end. Stops after `max` commands, before a command the full executor must run, and, when
    /// `STOPS`, before a command `stops` marks (but not the first when it was `asked`). With
    /// `SPAN`, widens `span` to the commands it may have run. Returns how many commands ran.
    /// Where a jump lands on a loop of plain arithmetic ([`super::jit`]) with room for whole
    /// rounds and nothing to stop before in them, the rounds run compiled.
    pub(super) fn run_plain<const STOPS: bool, const SPAN: bool>(
        &mut self,
        max: u64,
        stops: &[bool],
        asked: bool,
        span: &mut crate::machine::Span,
    ) -> u64 {
        if self.s.run != RunState::Running || !self.motion_idle() {
            return 0;
        }
        let SilverLode { program, s, .. } = self;
        let flat = &program.flat[..];
        let len = program.instrs.len();
        let regs = &mut s.regs;
        let mut isw = s.isw;
        let mut pc = s.pc as usize;
        let mut last = s.last;
        let entry = pc;
        let mut n = 0u64;
        // Where the loop starts or a jump lands on a loop's head, its whole rounds may run
        // compiled (out of line, and not even looked up in a program without loops: the arms
        // stay as tight as without).
        let any_loop = !program.loops.is_empty();
        macro_rules! compiled_rounds {
            () => {
                if any_loop && let Some(looped) = program.loops.at(pc) {
                    let (done, flags) = looped.enter::<STOPS>(regs, isw, max - n, stops);
                    if done > 0 {
                        n += done;
                        isw = flags;
                        last = LastExec {
                            pc: looped.end as u32,
                            vals: [1, 0, 0, 0],
                            outcome: Outcome::Done,
                        };
                        if SPAN {
                            span.jump(looped.end, looped.head);
                        }
                    }
                }
            };
        }
        // A command run through the executor's own arithmetic; one that would fault is left
        // to the full executor, untouched.
        macro_rules! effect {
            ($effect:expr) => {{
                let Ok(effect) = $effect else {
                    break;
                };
                isw = (isw & !isw::FLAGS) | effect.flags;
                last = LastExec {
                    pc: pc as u32,
                    vals: effect.vals,
                    outcome: effect.outcome,
                };
                pc += 1;
                n += 1;
                continue;
            }};
        }
        compiled_rounds!();
        while n < max {
            let Some(&op) = flat.get(pc) else {
                break;
            };
            // (The first command's halt was asked already when `asked`.)
            if STOPS && stops.get(pc) == Some(&true) && !(asked && n == 0) {
                break;
            }
            // (register written, value, operands for the explanation)
            let (dst, v, x0, x1) = match op {
                Op::AddI { res, a, d } => {
                    let a = regs[a as usize];
                    (res, a.wrapping_add(d), a, d)
                }
                Op::SubI { res, a, d } => {
                    let a = regs[a as usize];
                    (res, a.wrapping_sub(d), a, d)
                }
                Op::AndI { res, a, d } => {
                    let a = regs[a as usize];
                    (res, a & d, a, d)
                }
                Op::OrI { res, a, d } => {
                    let a = regs[a as usize];
                    (res, a | d, a, d)
                }
                Op::XorI { res, a, d } => {
                    let a = regs[a as usize];
                    (res, a ^ d, a, d)
                }
                Op::MulI { res, a, d } => {
                    let a = regs[a as usize];
                    (res, a.wrapping_mul(d), a, d)
                }
                Op::MulShr16I { res, a, d } => {
                    let a = regs[a as usize];
                    (res, ((i64::from(a) * i64::from(d)) >> 16) as i32, a, d)
                }
                Op::AddR { res, a, b } => {
                    let (a, d) = (regs[a as usize], regs[b as usize]);
                    (res, a.wrapping_add(d), a, d)
                }
                Op::SubR { res, a, b } => {
                    let (a, d) = (regs[a as usize], regs[b as usize]);
                    (res, a.wrapping_sub(d), a, d)
                }
                Op::AndR { res, a, b } => {
                    let (a, d) = (regs[a as usize], regs[b as usize]);
                    (res, a & d, a, d)
                }
                Op::OrR { res, a, b } => {
                    let (a, d) = (regs[a as usize], regs[b as usize]);
                    (res, a | d, a, d)
                }
                Op::XorR { res, a, b } => {
                    let (a, d) = (regs[a as usize], regs[b as usize]);
                    (res, a ^ d, a, d)
                }
                Op::MulR { res, a, b } => {
                    let (a, d) = (regs[a as usize], regs[b as usize]);
                    (res, a.wrapping_mul(d), a, d)
                }
                Op::MulShr16R { res, a, b } => {
                    let (a, d) = (regs[a as usize], regs[b as usize]);
                    (res, ((i64::from(a) * i64::from(d)) >> 16) as i32, a, d)
                }
                Op::AccAdd { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (10, acc.wrapping_add(x), acc, x)
                }
                Op::AccSub { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (10, acc.wrapping_sub(x), acc, x)
                }
                Op::AccMul { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (10, acc.wrapping_mul(x), acc, x)
                }
                Op::AccAnd { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (10, acc & x, acc, x)
                }
                Op::AccOr { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (10, acc | x, acc, x)
                }
                Op::AccXor { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (10, acc ^ x, acc, x)
                }
                Op::AccCopy { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (10, x, acc, x)
                }
                Op::AccSave { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (r, acc, acc, x)
                }
                Op::Inc { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (r, x.wrapping_add(1), acc, x)
                }
                Op::Dec { r } => {
                    let (acc, x) = (regs[10], regs[r as usize]);
                    (r, x.wrapping_sub(1), acc, x)
                }
                Op::Wrp { r, value } => {
                    last = LastExec {
                        pc: pc as u32,
                        vals: [regs[r as usize], value, value, 0],
                        outcome: Outcome::Done,
                    };
                    regs[r as usize] = value;
                    pc += 1;
                    n += 1;
                    continue;
                }
                Op::Clc { op, r } => {
                    // A SAVE_REF into R0/R1 moves the motor: the full executor's.
                    if op == ClcOp::SaveRef && (regs[r as usize] as u32) < 2 {
                        break;
                    }
                    effect!(clc_effect(regs, op, r as usize))
                }
                Op::ExtI { op, res, a, d } => {
                    effect!(ext_effect(regs, op, res as usize, a as usize, d))
                }
                Op::ExtR { op, res, a, b } => {
                    let d = regs[b as usize];
                    effect!(ext_effect(regs, op, res as usize, a as usize, d))
                }
                Op::Call { target } => {
                    if s.sp as usize >= STACK_DEPTH {
                        break;
                    }
                    last = LastExec {
                        pc: pc as u32,
                        vals: [i32::from(s.sp), 0, 0, 0],
                        outcome: Outcome::Done,
                    };
                    s.stack[s.sp as usize] = pc as u32 + 1;
                    s.sp += 1;
                    if SPAN {
                        span.jump(pc, target as usize);
                    }
                    pc = target as usize;
                    n += 1;
                    continue;
                }
                Op::Ret => {
                    // Returning past the last command ends the program: the full executor's.
                    let Some(&back) =
                        s.sp.checked_sub(1)
                            .and_then(|top| s.stack.get(top as usize))
                    else {
                        break;
                    };
                    if back as usize >= len {
                        break;
                    }
                    last = LastExec {
                        pc: pc as u32,
                        vals: [i32::from(s.sp), 0, 0, 0],
                        outcome: Outcome::Done,
                    };
                    s.sp -= 1;
                    if SPAN {
                        span.jump(pc, back as usize);
                    }
                    pc = back as usize;
                    n += 1;
                    continue;
                }
                Op::Jmp { target } => {
                    if SPAN {
                        span.jump(pc, target as usize);
                    }
                    last = LastExec {
                        pc: pc as u32,
                        vals: [1, 0, 0, 0],
                        outcome: Outcome::Done,
                    };
                    pc = target as usize;
                    n += 1;
                    compiled_rounds!();
                    continue;
                }
                Op::JmpIf { target, bit, want } => {
                    let taken = (isw >> bit & 1) as u8 == want;
                    if !taken && pc + 2 == flat.len() {
                        // Falling off the last command ends the program: the full executor's.
                        break;
                    }
                    last = LastExec {
                        pc: pc as u32,
                        vals: [i32::from(taken), 0, 0, 0],
                        outcome: Outcome::Done,
                    };
                    if SPAN && taken {
                        span.jump(pc, target as usize);
                    }
                    // Without a branch on `taken` where the program has no loop to compile: a
                    // loop's exit is a jump mispredicted otherwise (call_ret.qsl 8 % slower).
                    pc = if taken { target as usize } else { pc + 1 };
                    n += 1;
                    if any_loop && taken {
                        compiled_rounds!();
                    }
                    continue;
                }
                Op::Full => break,
            };
            regs[dst as usize] = v;
            isw = (isw & !isw::FLAGS) | flag_bits(v);
            last = LastExec {
                pc: pc as u32,
                vals: [x0, x1, v, 0],
                outcome: Outcome::Done,
            };
            pc += 1;
            n += 1;
        }
        if n > 0 {
            if SPAN {
                span.jump(pc, entry);
            }
            s.isw = isw;
            s.pc = pc as u32;
            s.last = last;
            s.ticks += n;
            s.steps += n;
            s.motion_ticked = false;
        }
        n
    }

    /// Run to `tick_limit` with nothing asked and nothing observed: plain commands in the fast
    /// loop, the rest tick by tick.
    pub fn run_to_tick(&mut self, tick_limit: u64) -> StopReason {
        loop {
            if matches!(self.s.run, RunState::Ended | RunState::Faulted) {
                return StopReason::Stopped;
            }
            if self.s.ticks >= tick_limit {
                return StopReason::TickLimit;
            }
            let mut unused = crate::machine::Span::default();
            let left = tick_limit - self.s.ticks;
            if self.run_plain::<false, false>(left, &[], false, &mut unused) == 0 {
                self.tick();
            }
        }
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
}
