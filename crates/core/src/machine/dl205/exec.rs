//! One instruction's execution: the contacts on the boolean stack of the rung, what each
//! instruction does with the rung's power, and the start of each scan.

use super::program::{Cmp, Edge, Op, Test, W, sp};
use super::{Dl205, Flow, Frame, LEVELS, Loop, StackMove, ZONES_AT_START, bcd_value};

impl Dl205 {
    /// A contact's value; an edge contact also updates its memory.
    #[inline(always)]
    fn test(&mut self, t: Test) -> bool {
        match t {
            Test::Bit(b, neg) => self.bit(b) != neg,
            Test::Edge(b, edge, i) => {
                let now = self.bit(b);
                self.edge_fired = match edge {
                    Edge::Rising => self.edges.rose(i as usize, now),
                    Edge::Falling => self.edges.fell(i as usize, now),
                };
                if self.edge_fired {
                    self.fired_this_scan.push(self.pc);
                }
                self.edge_fired
            }
            Test::Compare(a, b, kind) => {
                let (x, y) = (u32::from(self.word(a)), self.w(b));
                match kind {
                    Cmp::Eq => x == y,
                    Cmp::Ne => x != y,
                    Cmp::Ge => x >= y,
                    Cmp::Lt => x < y,
                }
            }
        }
    }

    /// STR: a new level on the boolean stack (a rung's first clears it).
    #[inline(always)]
    pub(super) fn contact_str(&mut self, t: Test) {
        if self.bstack.is_empty() || self.rung_has_output {
            self.bstack.clear();
            self.rung_has_output = false;
        }
        let v = self.test(t);
        if self.bstack.len() < LEVELS {
            self.bstack.push(v);
        }
    }

    #[inline(always)]
    pub(super) fn contact_and(&mut self, t: Test) {
        let v = self.test(t);
        if let Some(top) = self.bstack.last_mut() {
            *top &= v;
        }
    }

    #[inline(always)]
    pub(super) fn contact_or(&mut self, t: Test) {
        let v = self.test(t);
        if let Some(top) = self.bstack.last_mut() {
            *top |= v;
        }
    }

    /// ANDSTR (`and`) / ORSTR: the top two levels become one.
    #[inline(always)]
    pub(super) fn join_top(&mut self, and: bool) {
        if self.bstack.len() >= 2 {
            let b = self.bstack.pop().unwrap_or(false);
            let a = self.bstack.pop().unwrap_or(false);
            self.bstack.push(if and { a && b } else { a || b });
        }
    }

    pub(super) fn execute(&mut self) {
        let index = self.pc as usize;
        let op = self.program.instrs[index].op;
        self.before = (self.acc, self.stack[0]);
        self.moved = StackMove::None;
        self.raised_error = false;
        let rung = self.bstack.last().copied().unwrap_or(false);
        // Effective power: the rung's, inside a powered stage and master-line zone.
        let power = rung && self.block_power;
        self.last_ran = true;
        let mut next = self.pc + 1;
        let mut end_scan = false;
        match op {
            Op::Str(t) => self.contact_str(t),
            Op::And(t) => self.contact_and(t),
            Op::Or(t) => self.contact_or(t),
            Op::AndStr => self.join_top(true),
            Op::OrStr => self.join_top(false),
            Op::Not => self.invert_top(),
            Op::End => end_scan = true,
            Op::Nop => {}
            op if op.is_standalone() => {
                // A standalone instruction ends the rung: the next STR starts one.
                self.rung_has_output = true;
                match self.standalone(op) {
                    Flow::Next => {}
                    Flow::To(i) => next = i,
                    Flow::EndScan => end_scan = true,
                }
            }
            Op::Mls(n) => {
                self.rung_has_output = true;
                let n = usize::from(n.min(7));
                self.zones[n] = n > 0 && self.zones[n - 1] && rung;
                self.level = n as u8;
                self.update_block_power();
            }
            Op::Njmp { to, own } => {
                self.rung_has_output = true;
                if self.block_power && !rung {
                    self.jump_stage(own, to);
                }
            }
            op if op.always_runs() => {
                self.rung_has_output = true;
                self.always(op, power);
            }
            // An unpowered FOR continues after its NEXT.
            Op::For(_, next_at) if !power => {
                self.rung_has_output = true;
                self.last_ran = false;
                next = next_at + 1;
            }
            _ if !power => {
                self.rung_has_output = true;
                self.last_ran = false;
            }
            Op::Goto(to) => {
                self.rung_has_output = true;
                next = to;
            }
            Op::For(count, next_at) => {
                self.rung_has_output = true;
                let turns = match count {
                    W::K(k) => bcd_value(u32::from(k), 4),
                    W::V(a) => bcd_value(u32::from(self.word(a)), 4),
                };
                let turns = turns.unwrap_or_else(|| {
                    self.non_bcd();
                    0
                });
                if turns == 0 {
                    next = next_at + 1;
                } else {
                    self.loop_state = Some(Loop {
                        for_at: self.pc,
                        left: turns as u32,
                    });
                }
            }
            Op::Gts(to) => {
                self.rung_has_output = true;
                self.calls.push(Frame {
                    ret: self.pc + 1,
                    bstack: std::mem::take(&mut self.bstack),
                    rung_has_output: true,
                    level: self.level,
                    zones: self.zones,
                    stage_power: self.stage_power,
                    loop_state: self.loop_state.take(),
                });
                next = to;
            }
            Op::Rtc => {
                self.rung_has_output = true;
                match self.return_from_call() {
                    Some(ret) => next = ret,
                    None => end_scan = true,
                }
            }
            Op::Jmp { to, own } => {
                self.rung_has_output = true;
                self.jump_stage(own, to);
            }
            _ => {
                self.rung_has_output = true;
                self.output(op);
            }
        }
        // Contacts: the rung's power after them; outputs: the power they acted on.
        self.power[index] = Some(if op.is_output() {
            power
        } else {
            self.bstack.last().copied().unwrap_or(false)
        });
        self.last = Some(index as u32);
        self.steps += 1;
        self.step += 1;
        self.pc = next;
        if end_scan || self.pc as usize >= self.program.instrs.len() {
            self.pc = 0;
            self.step = 0;
            self.tick += 1;
        }
    }

    /// NOT: the top of the boolean stack inverted.
    #[inline(always)]
    pub(super) fn invert_top(&mut self) {
        if let Some(top) = self.bstack.last_mut() {
            *top = !*top;
        }
    }

    pub(super) fn scan_start(&mut self) {
        self.x_image.clone_from(&self.x);
        let t = self.tick;
        self.sp[sp::SP0] = t == 0;
        self.sp[sp::SP1] = true;
        self.sp[sp::SP2] = false;
        for (relay, period) in [
            (sp::SP3, 60_000),
            (sp::SP4, 1_000),
            (sp::SP5, 100),
            (sp::SP6, 50),
        ] {
            self.sp[relay] = self.time.late_half(t, period);
        }
        self.sp[sp::SP7] = t % 2 == 1;
        self.orout_marks.iter_mut().for_each(|m| *m = false);
        self.fired_this_scan.clear();
        self.level = 0;
        self.zones = ZONES_AT_START;
        self.stage_power = true;
        self.block_power = true;
        self.loop_state = None;
        self.calls.clear();
        self.acc = 0;
        self.stack = [0; LEVELS];
        self.depth = 0;
        self.load_pending = false;
        self.bstack.clear();
        self.rung_has_output = false;
        self.power.iter_mut().for_each(|p| *p = None);
    }
}
