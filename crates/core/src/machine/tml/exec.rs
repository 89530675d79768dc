//! Running TML: one statement at a time inside a tick's instruction phase, then the motion,
//! time and event phases of spec §3.

use super::program::{AddKind, Data, EventSpec, Flat, Op, Operand, Slot, Value};
use super::{
    Event, Fault, LastMultiply, PREG_MASK, STACK_DEPTH, STATEMENTS_PER_TICK, Tml, d, der, mer, srl,
    upd_ignored,
};
use crate::machine::{MachineView, Pos, Quiet, Span, StopReason, WriteSet};

/// What one statement did.
enum Outcome {
    Done,
    /// `WAIT!` must wait: the instruction phase is over.
    Wait,
    Fault(Fault),
}

fn sx16(v: u32) -> i64 {
    i64::from(v as u16 as i16)
}
fn sx32(v: u32) -> i64 {
    i64::from(v as i32)
}

impl Tml {
    /// The signed value an instruction reads from `op` (PROD/PRODH from PREG).
    pub fn read_operand(&self, op: &Operand) -> i64 {
        let raw = self.raw(op.data);
        match op.half {
            Some(true) => sx16(raw >> 16),
            Some(false) => sx16(raw),
            None if op.ty.bits() == 16 => sx16(raw),
            None => sx32(raw),
        }
    }

    /// The raw bits of a datum (16-bit data in the low half).
    pub fn raw(&self, data: Data) -> u32 {
        match data {
            Data::Pre(d::PROD) => self.preg as u32,
            Data::Pre(d::PRODH) => (self.preg >> 16) as u32,
            // Both follow other state (spec §2.2), so they are read from it.
            Data::Pre(d::RTIME) => self.data[d::ATIME as usize].wrapping_sub(self.time0),
            Data::Pre(d::MCR) => self.mcr(),
            Data::Pre(i) => self.data[i as usize],
            Data::Var(v) => self.vars[v as usize],
        }
    }

    fn set_raw(&mut self, data: Data, raw: u32) {
        match data {
            Data::Pre(i) => self.data[i as usize] = raw,
            Data::Var(v) => self.vars[v as usize] = raw,
        }
    }

    /// Store the low bits of `value` in `op` (two's complement wrap).
    pub fn store(&mut self, op: &Operand, value: i64) {
        let old = self.raw(op.data);
        let raw = match op.half {
            Some(true) => (old & 0xFFFF) | ((value as u32 & 0xFFFF) << 16),
            Some(false) => (old & 0xFFFF_0000) | (value as u32 & 0xFFFF),
            None if op.ty.bits() == 16 => value as u32 & 0xFFFF,
            None => value as u32,
        };
        self.set_raw(op.data, raw);
    }

    fn value(&self, v: &Value) -> i64 {
        match v {
            Value::Imm(i) => *i,
            Value::Var(op) => self.read_operand(op),
        }
    }

    fn srl_set(&mut self, bits: u32, on: bool) {
        let srl = &mut self.data[d::SRL as usize];
        if on {
            *srl |= bits;
        } else {
            *srl &= !bits;
        }
    }

    /// Shifted as spec §5.5 on `bits` bits: left zero-fills, right sign-extends.
    fn shifted(value: i64, left: bool, n: u8) -> i64 {
        if left { value << n } else { value >> n }
    }

    fn execute(&mut self) -> Outcome {
        let index = self.pc as usize;
        let op = self.program.stmts[index].op;
        let mut next = self.pc + 1;
        let mut vals = [0i64; 3];
        match op {
            Op::Assign(dst, src) => {
                let v = self.value(&src);
                self.store(&dst, v);
                vals = [v, 0, self.read_operand(&dst)];
            }
            Op::Negate(dst, src) => {
                let v = self.read_operand(&src);
                self.store(&dst, v.wrapping_neg());
                vals = [v, 0, self.read_operand(&dst)];
            }
            Op::AssignShift { dst, src, left, n } => {
                let v = self.read_operand(&src);
                self.store(&dst, Self::shifted(v, left, n));
                vals = [v, i64::from(n), self.read_operand(&dst)];
            }
            Op::Add {
                dst,
                src,
                kind,
                subtract,
            } => {
                let old = self.read_operand(&dst);
                let mut delta = self.value(&src);
                if kind == AddKind::IntegerPart {
                    delta *= 65536;
                }
                let result = if subtract {
                    old.wrapping_sub(delta)
                } else {
                    old.wrapping_add(delta)
                };
                self.store(&dst, result);
                vals = [old, delta, self.read_operand(&dst)];
            }
            Op::Multiply { a, b, left, n } => {
                let (va, vb) = (self.read_operand(&a), self.value(&b));
                let product = i128::from(va) * i128::from(vb);
                let shifted = if left { product << n } else { product >> n };
                self.preg = (shifted as u64) & PREG_MASK;
                self.last_multiply = Some(LastMultiply {
                    line: self.program.stmts[index].line,
                    a: va,
                    b: vb,
                    left,
                    shift: n,
                    product,
                });
                vals = [va, vb, self.preg_signed()];
            }
            Op::Divide(dst, divisor) => {
                let old = self.read_operand(&dst);
                let dv = self.read_operand(&divisor);
                let q = quotient(old, dv, dst.is_fixed());
                self.store(&dst, q);
                vals = [old, dv, q];
            }
            Op::Shift { dst, left, n } => {
                let old = self.read_operand(&dst);
                self.store(&dst, Self::shifted(old, left, n));
                vals = [old, i64::from(n), self.read_operand(&dst)];
            }
            Op::ShiftProduct { left, n } => {
                let old = self.preg_signed();
                self.preg = (Self::shifted(old, left, n) as u64) & PREG_MASK;
                vals = [old, i64::from(n), self.preg_signed()];
            }
            Op::Srb { dst, and, or } => {
                let old = self.read_operand(&dst);
                let raw = (old as u16 & and) | or;
                self.store(&dst, i64::from(raw));
                vals = [old, 0, self.read_operand(&dst)];
            }
            Op::Jump { target, call, cond } => {
                let taken = self.jump_taken(cond, &mut vals);
                if taken {
                    if let Err(fault) = self.push_return(call) {
                        return Outcome::Fault(fault);
                    }
                    next = target;
                }
            }
            Op::JumpVia { via, call, cond } => {
                let taken = self.jump_taken(cond, &mut vals);
                let address = self.read_operand(&via) as u16;
                vals[2] = i64::from(address);
                if taken {
                    // The address comes before CALL's stack check (spec §5.7).
                    let Some(to) = self.program.statement_at(u32::from(address)) else {
                        return Outcome::Fault(Fault::BadAddress { address, call });
                    };
                    if let Err(fault) = self.push_return(call) {
                        return Outcome::Fault(fault);
                    }
                    next = to as u32;
                }
            }
            Op::Ret => match self.stack.pop() {
                Some(back) => next = back,
                None => {
                    self.data[d::MER as usize] |= mer::COMMAND_ERROR;
                    self.data[d::DER as usize] |= der::STACK_UNDERFLOW;
                    return Outcome::Fault(Fault::StackUnderflow);
                }
            },
            Op::End => {
                self.ended = true;
            }
            Op::ModePp => {
                self.mode_pp = true;
                self.tum1 = false;
            }
            Op::Relative(relative) => self.relative = relative,
            Op::Tum(one) => self.tum1 = one,
            Op::Upd => vals = [i64::from(self.update()), 0, 0],
            Op::Stop => {
                if self.profile.active {
                    self.profile.stopping = true;
                    self.profile.decel = sx32(self.data[d::CACC as usize]);
                }
            }
            Op::Sap(v) => {
                let value = self.value(&v);
                let apos = sx32(self.data[d::APOS as usize]);
                let delta = value - apos;
                self.data[d::APOS as usize] = value as u32;
                self.profile.x += i128::from(delta) * 65536;
                self.data[d::TPOS as usize] = self.profile.position() as u32;
                if self.profile.active && !self.profile.stopping {
                    self.profile.end = (i64::from(self.profile.end) + delta) as i32;
                }
                vals = [value, delta, 0];
            }
            Op::Axis(on) => {
                self.srl_set(srl::AXIS_ON, on);
                if !on {
                    self.profile.active = false;
                    self.profile.stopping = false;
                    self.profile.v = 0;
                    self.profile.x = i128::from(sx32(self.data[d::APOS as usize])) * 65536;
                }
            }
            Op::Nop => {}
            Op::SetEvent(spec) => {
                self.event = Some(match spec {
                    EventSpec::MotionComplete => Event::MotionComplete,
                    EventSpec::Time(v) => {
                        self.time0 = self.data[d::ATIME as usize];
                        Event::Time {
                            after: self.value(&v),
                            time0: sx32(self.time0),
                        }
                    }
                    EventSpec::Input(input, level) => Event::Input { input, level },
                });
                self.srl_set(srl::EVENT, false);
            }
            Op::Wait(limit) => {
                let occurred = self.event.is_none() || self.data[d::SRL as usize] & srl::EVENT != 0;
                let t0 = *self.wait_since.get_or_insert(self.tick);
                let timed_out = limit.is_some_and(|t| self.tick - t0 >= u64::from(t));
                if !(occurred || timed_out) {
                    return Outcome::Wait;
                }
                vals = [i64::from(occurred), (self.tick - t0) as i64, 0];
                self.wait_since = None;
            }
        }
        self.last = Some(index as u32);
        self.last_vals = vals;
        self.pc = next;
        if self.pc as usize >= self.program.stmts.len() {
            self.ended = true;
        }
        Outcome::Done
    }

    /// Whether a GOTO/CALL with `cond` jumps; notes the tested value and the outcome in
    /// `vals` for the explanation.
    fn jump_taken(
        &self,
        cond: Option<(Operand, super::program::Cond)>,
        vals: &mut [i64; 3],
    ) -> bool {
        let taken = match cond {
            Some((x, c)) => {
                let v = self.read_operand(&x);
                vals[0] = v;
                c.holds(v)
            }
            None => true,
        };
        vals[1] = i64::from(taken);
        taken
    }

    /// A taken CALL pushes its return point; on a full stack it faults (spec §5.7).
    fn push_return(&mut self, call: bool) -> Result<(), Fault> {
        if !call {
            return Ok(());
        }
        if self.stack.len() >= STACK_DEPTH {
            self.data[d::MER as usize] |= mer::COMMAND_ERROR;
            self.data[d::DER as usize] |= der::STACK_OVERFLOW;
            return Err(Fault::StackOverflow);
        }
        self.stack.push(self.pc + 1);
        Ok(())
    }

    /// `UPD` (spec §5.8): start or retarget the profile, or ignore it with the error bits set.
    /// Returns why it was ignored ([`upd_ignored`] bits; 0 when it was not).
    fn update(&mut self) -> u8 {
        let (cspd, cacc) = (
            sx32(self.data[d::CSPD as usize]),
            sx32(self.data[d::CACC as usize]),
        );
        let axis_on = self.data[d::SRL as usize] & srl::AXIS_ON != 0;
        let why = [
            (!self.mode_pp, upd_ignored::NO_MODE_PP),
            (!axis_on, upd_ignored::AXIS_OFF),
            (cspd <= 0, upd_ignored::CSPD),
            (cacc <= 0, upd_ignored::CACC),
        ]
        .into_iter()
        .filter(|(bad, _)| *bad)
        .fold(0, |all, (_, bit)| all | bit);
        if why != 0 {
            self.data[d::MER as usize] |= mer::COMMAND_ERROR;
            self.data[d::DER as usize] |= der::UPD_IGNORED;
            return why;
        }
        let p = &mut self.profile;
        if !self.tum1 {
            p.x = i128::from(sx32(self.data[d::APOS as usize])) * 65536;
            p.v = sx32(self.data[d::ASPD as usize]);
        }
        let cpos = sx32(self.data[d::CPOS as usize]);
        p.end = if self.relative {
            (p.position_unwrapped() + cpos) as i32
        } else {
            cpos as i32
        };
        p.speed = cspd;
        p.accel = cacc;
        p.active = true;
        p.stopping = false;
        self.srl_set(srl::MOTION_COMPLETE, false);
        0
    }

    /// Phases 3–6 of a tick.
    #[inline]
    fn finish_tick(&mut self) {
        // 3. motion
        self.profile.advance();
        let tpos = self.profile.position();
        self.data[d::TPOS as usize] = tpos as u32;
        let tspd = self.profile.v as u32;
        self.data[d::TACC as usize] = tspd.wrapping_sub(self.data[d::TSPD as usize]);
        self.data[d::TSPD as usize] = tspd;
        let apos = self.data[d::APOS as usize] as i32;
        if self.data[d::SRL as usize] & srl::AXIS_ON != 0 {
            let r = i64::from(tpos.wrapping_sub(apos));
            let m = r - r / 2;
            self.data[d::APOS as usize] = apos.wrapping_add(m as i32) as u32;
            self.data[d::ASPD as usize] = (m * 65536) as u32;
        } else {
            self.data[d::ASPD as usize] = 0;
        }
        let err = tpos.wrapping_sub(self.data[d::APOS as usize] as i32);
        self.data[d::POSERR as usize] = err.clamp(-32768, 32767) as u32 & 0xFFFF;
        // The in-position count and motion complete (spec §6.1; `motion_complete` spelled out
        // here, where every tick pays for it).
        let active = self.profile.active;
        let band = self.data[d::POSOKLIM as usize] & 0xFFFF;
        self.in_position = if !active && err.unsigned_abs() <= band {
            self.in_position.saturating_add(1)
        } else {
            0
        };
        let complete = !active
            && (self.data[d::UPGRADE as usize] & super::UPGRADE_IN_POSITION == 0
                || self.in_position >= (self.data[d::TONPOSOK as usize] as u16).max(1));
        self.srl_set(srl::MOTION_COMPLETE, complete);
        // 4. time
        self.data[d::ATIME as usize] = self.data[d::ATIME as usize].wrapping_add(1);
        // 5. the programmed event
        if let Some(event) = self.event
            && self.data[d::SRL as usize] & srl::EVENT == 0
        {
            let occurred = match event {
                Event::MotionComplete => complete,
                Event::Time { after, time0 } => sx32(self.data[d::ATIME as usize]) - time0 >= after,
                Event::Input { input, level } => self.input(input.into()) == level,
            };
            if occurred {
                self.srl_set(srl::EVENT, true);
            }
        }
        // 6. complete
        self.tick += 1;
        self.step = 0;
    }

    pub fn is_live(&self) -> bool {
        !self.ended && self.fault.is_none()
    }

    /// Run plain statements ([`Flat`]: user variables, immediates, the product register and
    /// jumps) exactly as `execute` and `run_loop` would, at most `max` of them, finishing each
    /// tick as its instruction phase fills. Stops before a statement the full executor must
    /// run. Returns how many ran.
    ///
    /// `tick_done` is asked after each tick and ends the run when it says so; `span` widens to
    /// the statements it may have run.
    fn run_plain<T: FnMut(&Self) -> bool>(
        &mut self,
        max: u64,
        halts: &[bool],
        span: &mut Span,
        mut tick_done: T,
    ) -> u64 {
        if !self.is_live() || self.wait_since.is_some() {
            return 0;
        }
        let entry = self.pc as usize;
        let len = self.program.flat.len();
        let mut n = 0;
        while n < max {
            let index = self.pc as usize;
            let Some(&op) = self.program.flat.get(index) else {
                break;
            };
            if halts.get(index) == Some(&true) {
                break;
            }
            let vars = &mut self.vars[..];
            let read = |vars: &[u32], s: Slot| -> i64 {
                i64::from(
                    ((vars.get(s.var as usize).copied().unwrap_or(0) << s.shift) as i32) >> s.shift,
                )
            };
            let store = |vars: &mut [u32], s: Slot, v: i64| {
                if let Some(slot) = vars.get_mut(s.var as usize) {
                    *slot = v as u32 & (u32::MAX >> s.shift);
                }
            };
            let mut next = self.pc + 1;
            let vals = match op {
                Flat::SetImm { dst, v } => {
                    store(vars, dst, v);
                    [v, 0, read(vars, dst)]
                }
                Flat::Copy { dst, src } => {
                    let v = read(vars, src);
                    store(vars, dst, v);
                    [v, 0, read(vars, dst)]
                }
                Flat::AddImm { .. } | Flat::Add { .. } => {
                    let (dst, delta, subtract) = match op {
                        Flat::Add {
                            dst,
                            src,
                            scale,
                            subtract,
                        } => (dst, read(vars, src) * scale, subtract),
                        Flat::AddImm {
                            dst,
                            delta,
                            subtract,
                        } => (dst, delta, subtract),
                        _ => break,
                    };
                    let old = read(vars, dst);
                    let result = if subtract {
                        old.wrapping_sub(delta)
                    } else {
                        old.wrapping_add(delta)
                    };
                    store(vars, dst, result);
                    [old, delta, read(vars, dst)]
                }
                Flat::Shift { dst, left, n } => {
                    let old = read(vars, dst);
                    store(vars, dst, Self::shifted(old, left, n));
                    [old, i64::from(n), read(vars, dst)]
                }
                Flat::CopyProduct { dst, high } => {
                    let raw = if high { self.preg >> 16 } else { self.preg };
                    let v = i64::from(raw as u32 as i32);
                    store(vars, dst, v);
                    [v, 0, read(vars, dst)]
                }
                Flat::Div {
                    dst,
                    divisor,
                    fixed,
                } => {
                    let (old, dv) = (read(vars, dst), read(vars, divisor));
                    let q = quotient(old, dv, fixed);
                    store(vars, dst, q);
                    [old, dv, q]
                }
                Flat::MulImm { a, b, left, n } => {
                    let va = read(vars, a);
                    self.multiply(index, va, b, left, n)
                }
                Flat::Mul { a, b, left, n } => {
                    let (va, vb) = (read(vars, a), read(vars, b));
                    self.multiply(index, va, vb, left, n)
                }
                Flat::Negate { dst, src } => {
                    let v = read(vars, src);
                    store(vars, dst, v.wrapping_neg());
                    [v, 0, read(vars, dst)]
                }
                Flat::AssignShift { dst, src, left, n } => {
                    let v = read(vars, src);
                    store(vars, dst, Self::shifted(v, left, n));
                    [v, i64::from(n), read(vars, dst)]
                }
                Flat::Srb { dst, and, or } => {
                    let old = read(vars, dst);
                    store(vars, dst, i64::from((old as u16 & and) | or));
                    [old, 0, read(vars, dst)]
                }
                Flat::ShiftProduct { left, n } => {
                    let old = self.preg_signed();
                    self.preg = (Self::shifted(old, left, n) as u64) & PREG_MASK;
                    [old, i64::from(n), self.preg_signed()]
                }
                Flat::Nop => [0; 3],
                Flat::Goto { target } => {
                    span.jump(index, target as usize);
                    next = target;
                    [0, 1, 0]
                }
                Flat::GotoIf { target, x, cond } => {
                    let v = read(vars, x);
                    let taken = cond.holds(v);
                    if !taken && index + 1 == len {
                        // Falling off the last statement ends the program: the full executor's.
                        break;
                    }
                    if taken {
                        span.jump(index, target as usize);
                        next = target;
                    }
                    [v, i64::from(taken), 0]
                }
                Flat::Full => break,
            };
            self.last = Some(index as u32);
            self.last_vals = vals;
            self.pc = next;
            self.steps += 1;
            self.step += 1;
            n += 1;
            let tick_over = self.step >= STATEMENTS_PER_TICK;
            if tick_over {
                self.finish_tick();
            }
            if tick_over && tick_done(self) {
                break;
            }
        }
        if n > 0 {
            span.jump(self.pc as usize, entry);
        }
        n
    }

    /// [`crate::machine::Machine::run_quiet`]: whole ticks in the fast loop, each compared at
    /// its end with the watched values the run began with; the run stops after the first tick
    /// that changed one (the timeline samples it), before a statement the fast loop cannot
    /// run, or at the last tick boundary before `limit`.
    pub fn run_quiet_to(&mut self, limit: Pos, quiet: &mut Quiet) -> StopReason {
        let limit = Pos::at_tick(limit.tick);
        if self.step != 0 {
            return StopReason::TickLimit;
        }
        quiet.held.clear();
        quiet
            .held
            .extend(quiet.watched.iter().map(|&loc| self.read(loc)));
        let program = std::sync::Arc::clone(&self.program);
        quiet.halts_for(program.stmts.len(), |i| {
            program.stmts.get(i).map_or(0, |s| s.line)
        });
        // What the timeline notes at the first boundary; the motion data while the profile
        // moves (no plain statement starts a move).
        let mut written = WriteSet::default();
        self.note_writes(&mut written);
        self.note_motion(&mut written);
        let start = self.steps;
        let mut span = Span::default();
        let (halts, watched, held) = (&quiet.halts, &quiet.watched, &quiet.held);
        let mut changed = false;
        let reason = loop {
            if !self.is_live() {
                break StopReason::Stopped;
            }
            let now = self.pos();
            if now >= limit || changed {
                break StopReason::TickLimit;
            }
            let left = (limit.tick - now.tick).saturating_mul(u64::from(STATEMENTS_PER_TICK));
            let ran = self.run_plain(left, halts, &mut span, |m| {
                changed = watched
                    .iter()
                    .zip(held)
                    .any(|(&loc, &was)| m.read(loc) != was);
                changed
            });
            // A run that ends inside a tick (a statement the fast loop hands over) is finished
            // by the timeline, observed.
            if ran == 0 || self.step != 0 {
                break StopReason::TickLimit;
            }
        };
        let ran = self.steps - start;
        if ran > 0 {
            // The destinations of the statements it may have run: those of its span, or of the
            // whole program when the span is most of it.
            match span.narrow(program.flat.len(), ran) {
                Some(range) => program.flat[range]
                    .iter()
                    .for_each(|&op| note_flat_writes(op, &mut written)),
                None => written.union(program.flat_writes),
            }
            quiet.written.union(written);
        }
        reason
    }

    fn multiply(&mut self, index: usize, va: i64, vb: i64, left: bool, n: u8) -> [i64; 3] {
        let product = i128::from(va) * i128::from(vb);
        let shifted = if left { product << n } else { product >> n };
        self.preg = (shifted as u64) & PREG_MASK;
        self.last_multiply = Some(LastMultiply {
            line: self.program.stmts.get(index).map_or(0, |s| s.line),
            a: va,
            b: vb,
            left,
            shift: n,
            product,
        });
        [va, vb, self.preg_signed()]
    }

    /// Run to `limit` with nothing asked and nothing observed: plain statements in the fast
    /// loop, the rest one at a time.
    pub fn run_bare_to(&mut self, limit: Pos) -> StopReason {
        loop {
            if !self.is_live() {
                return StopReason::Stopped;
            }
            let now = self.pos();
            if now >= limit {
                return StopReason::TickLimit;
            }
            // Every tick has its full instruction phase while only plain statements run.
            let left = (limit.tick - now.tick)
                .saturating_mul(u64::from(STATEMENTS_PER_TICK))
                .saturating_add(u64::from(limit.step))
                .saturating_sub(u64::from(now.step));
            if self.run_plain(left, &[], &mut Span::default(), |_| false) == 0 {
                let next = self.steps + 1;
                self.run_loop(limit, |m| m.steps >= next, |_| {});
            }
        }
    }

    /// Run until `limit`, a stop, or `stop` asks before a statement starts.
    pub fn run_loop<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        limit: Pos,
        mut stop: F,
        mut observe: O,
    ) -> StopReason {
        loop {
            if !self.is_live() {
                return StopReason::Stopped;
            }
            if self.pos() >= limit {
                return StopReason::TickLimit;
            }
            // A retried WAIT! is the middle of a statement, not a start.
            if self.wait_since.is_none() && stop(self) {
                return StopReason::Predicate;
            }
            let phase_over = match self.execute() {
                Outcome::Done => {
                    self.steps += 1;
                    self.step += 1;
                    self.ended || self.step >= STATEMENTS_PER_TICK
                }
                Outcome::Wait => true,
                Outcome::Fault(f) => {
                    let line = self.program.stmts[self.pc as usize].line;
                    self.fault = Some((f, line));
                    true
                }
            };
            if phase_over {
                self.finish_tick();
                observe(self);
            }
        }
    }
}

impl super::Profile {
    /// ⌊x / 65536⌋ without wrapping, as the relative end of UPD needs it.
    pub fn position_unwrapped(&self) -> i64 {
        (self.x >> 16) as i64
    }
}

/// The locations a plain statement writes.
/// Every location a statement of `flat` other than `Full` may write.
pub fn flat_writes(flat: &[Flat]) -> WriteSet {
    let mut set = WriteSet::default();
    for &op in flat {
        note_flat_writes(op, &mut set);
    }
    set
}

fn note_flat_writes(op: Flat, set: &mut WriteSet) {
    use super::view::{DATA, PREG_INDEX, VARS, data_loc};
    use crate::machine::Loc;
    match op {
        Flat::SetImm { dst, .. }
        | Flat::Copy { dst, .. }
        | Flat::AddImm { dst, .. }
        | Flat::Add { dst, .. }
        | Flat::Shift { dst, .. }
        | Flat::CopyProduct { dst, .. }
        | Flat::Div { dst, .. }
        | Flat::Negate { dst, .. }
        | Flat::AssignShift { dst, .. }
        | Flat::Srb { dst, .. } => set.insert(Loc::new(VARS, u32::from(dst.var))),
        Flat::MulImm { .. } | Flat::Mul { .. } | Flat::ShiftProduct { .. } => {
            set.insert(Loc::new(DATA, PREG_INDEX));
            set.insert(data_loc(d::PROD));
            set.insert(data_loc(d::PRODH));
        }
        Flat::Goto { .. } | Flat::GotoIf { .. } | Flat::Nop | Flat::Full => {}
    }
}

/// `dst /= divisor` (spec §5.4): a fixed dividend as is, an integer one as its value × 65536;
/// the quotient saturates to 32 bits, and a zero divisor gives the saturated value of the
/// dividend's sign.
fn quotient(old: i64, divisor: i64, fixed: bool) -> i64 {
    let n = if fixed {
        i128::from(old)
    } else {
        i128::from(old) * 65536
    };
    let q = if divisor == 0 {
        if n >= 0 {
            i128::from(i32::MAX)
        } else {
            i128::from(i32::MIN)
        }
    } else {
        (n / i128::from(divisor)).clamp(i128::from(i32::MIN), i128::from(i32::MAX))
    };
    q as i64
}
