//! The fast loop: plain commands run many at a time while the motor rests (with loops of plain
//! arithmetic compiled), and the runs to a tick limit built on it.

use super::effects::{clc_effect, ext_effect};
use super::flag_bits;
use crate::machine::silverlode::program::{ClcOp, Op};
use crate::machine::silverlode::{LastExec, Outcome, STACK_DEPTH, SilverLode, isw};
use crate::machine::{RunState, StopReason};

impl SilverLode {
    /// Run plain commands ([`Op`]: registers and flags only, one tick each) while the machine
    /// runs and the motor rests, exactly as `tick` would, with the bookkeeping done once at the
    /// end. Stops after `max` commands, before a command the full executor must run, and, when
    /// `STOPS`, before a command `stops` marks (but not the first when it was `asked`). With
    /// `SPAN`, widens `span` to the commands it may have run. Returns how many commands ran.
    /// Where a jump lands on a loop of plain arithmetic ([`jit`](crate::machine::silverlode::jit))
    /// with room for whole rounds and nothing to stop before in them, the rounds run compiled.
    pub(in crate::machine::silverlode) fn run_plain<const STOPS: bool, const SPAN: bool>(
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
