//! The executor: one tick of the machine, every command, queues, moves and the motion model
//! (spec §3–§6). Faults are raised before a command changes anything.

mod effects;
mod fast;
mod moves;

use super::program::{ClcOp, ExtOp, Instr};
use super::{Fault, FaultKind, LastExec, Outcome, REGISTERS, STACK_DEPTH, SilverLode, isw, psw};
use crate::machine::{RunState, WaitReason};
use effects::{Effect, clc_effect, ext_effect};

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
}
