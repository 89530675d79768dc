//! One instruction's execution: the scan's start, the bit logic on the block and branch
//! stacks with SOTU/SOTD, MOV, the typed arithmetic with REP, INC/DEC, and the rest
//! through `act`.

use super::program::{Arith, Op, Word};
use super::{Cycle, M8003, M8120, M8121, M8122, M8123, M8125, Mark, OpenNet, STACK_DEPTH};

impl OpenNet {
    /// The scan's start (spec §3 step 1): inputs, the clocks sampled at t = tick × scan_ms.
    pub(super) fn refresh(&mut self) {
        self.input_image.clone_from(&self.inputs);
        self.special[M8120] = self.tick == 0;
        // The clocks are on in the first half of each period: one division for the three
        // (each period divides the next), as this runs every scan.
        let phase = self.time.phase(self.tick, 1000) as u32;
        self.special[M8121] = phase < 500;
        self.special[M8122] = phase % 100 < 50;
        self.special[M8123] = phase % 10 < 5;
        self.special[M8125] = true;
        self.rlo = false;
        self.mc = true;
        self.blocks.clear();
        self.branches.clear();
        // Only an MCS that was off or a taken jump marks anything.
        if self.program.marks_code {
            self.marks.fill(Mark::NotReached);
        }
    }

    /// LOD's effect on the stacks and RLO, for a contact that reads `x`.
    #[inline(always)]
    pub(super) fn load_contact(&mut self, index: usize, x: bool) {
        if self.program.opens.get(index).copied().unwrap_or(true) {
            self.blocks.clear();
            self.branches.clear();
        } else {
            Self::push(&mut self.blocks, self.rlo);
        }
        self.rlo = x;
    }

    #[inline(always)]
    pub(super) fn sotu(&mut self, m: u32) {
        self.rlo = self.edges.rose(m as usize, self.rlo && self.mc);
        self.note_pulse(m);
    }

    /// Remember the scan an edge instruction pulsed in (rare: only when it does).
    #[inline(always)]
    fn note_pulse(&mut self, m: u32) {
        if self.rlo
            && let Some(s) = self.edge_scans.get_mut(m as usize)
        {
            *s = self.tick + 1;
        }
    }

    /// SOTD: with MC = 0 it gives 0 and forgets (no falling edge is seen, spec §5.12).
    #[inline(always)]
    pub(super) fn sotd(&mut self, m: u32) {
        if self.mc {
            self.rlo = self.edges.fell(m as usize, self.rlo);
            self.note_pulse(m);
        } else {
            self.edges.rose(m as usize, false);
            self.rlo = false;
        }
    }

    #[inline]
    pub(super) fn push(stack: &mut Vec<bool>, v: bool) {
        if stack.len() < STACK_DEPTH {
            stack.push(v);
        }
    }

    pub(super) fn execute(&mut self) {
        let index = self.pc as usize;
        let op = self.program.instrs[index].op;
        self.last_acted = false;
        self.last_cycles.clear();
        // The record is of this instruction alone (the fast loop keeps none).
        self.box_before = (0, false);
        self.legs = [false; 3];
        let mc = self.mc;
        let input = self.rlo && mc;
        let mut next = self.pc + 1;
        match op {
            Op::Lod(b, neg) => self.load_contact(index, self.bit(b) != neg),
            Op::And(b, neg) => self.rlo &= self.bit(b) != neg,
            Op::Or(b, neg) => self.rlo |= self.bit(b) != neg,
            Op::AndLod => {
                let top = self.blocks.pop().unwrap_or(false);
                self.rlo &= top;
            }
            Op::OrLod => {
                let top = self.blocks.pop().unwrap_or(false);
                self.rlo |= top;
            }
            Op::Bps => Self::push(&mut self.branches, self.rlo),
            Op::Brd => self.rlo = self.branches.last().copied().unwrap_or(false),
            Op::Bpp => self.rlo = self.branches.pop().unwrap_or(false),
            Op::Sotu(m) => self.sotu(m),
            Op::Sotd(m) => self.sotd(m),
            Op::Out(b, neg) => self.set_bit(b, input != neg),
            Op::Set(b) => {
                if input {
                    self.set_bit(b, true);
                }
            }
            Op::Rst(b) => {
                if input {
                    self.set_bit(b, false);
                }
            }
            Op::End => {}
            Op::Mov { ty, src, dst, rep } if input => {
                self.last_acted = true;
                let w = ty.words();
                for c in 0..u32::from(rep) {
                    let (so, dof) = (Self::offset(&src, w, c), Self::offset(&dst, w, c));
                    let v = self.read_word(&src, w, so);
                    self.write_word(&dst, w, dof, v);
                    self.last_cycles.push(Cycle {
                        a: ty.value(v),
                        b: 0,
                        exact: ty.value(v),
                        stored: v,
                        remainder: 0,
                        out_of_range: false,
                        error: None,
                        a_at: so,
                        b_at: 0,
                        dst_at: dof,
                    });
                }
            }
            Op::Arith {
                op,
                ty,
                a,
                b,
                dst,
                rep,
            } if input => {
                self.last_acted = true;
                let w = ty.words();
                let dst_block = match op {
                    Arith::Add | Arith::Sub => w,
                    Arith::Mul => 2,
                    Arith::Div => 2 * w,
                };
                let mut carry = false;
                for c in 0..u32::from(rep) {
                    let (ao, bo, dof) = (
                        Self::offset(&a, w, c),
                        Self::offset(&b, w, c),
                        Self::offset(&dst, dst_block, c),
                    );
                    let x = ty.value(self.read_word(&a, w, ao));
                    let y = ty.value(self.read_word(&b, w, bo));
                    let mut cycle = Cycle {
                        a: x,
                        b: y,
                        exact: 0,
                        stored: 0,
                        remainder: 0,
                        out_of_range: false,
                        error: None,
                        a_at: ao,
                        b_at: bo,
                        dst_at: dof,
                    };
                    match op {
                        Arith::Add | Arith::Sub => {
                            let r = if op == Arith::Add { x + y } else { x - y };
                            let (stored, out) = Self::store_add(ty, r);
                            carry |= out;
                            self.write_word(&dst, w, dof, stored);
                            cycle.exact = r;
                            cycle.stored = stored;
                            cycle.out_of_range = out;
                        }
                        Arith::Mul => {
                            cycle.exact = (i128::from(x) * i128::from(y)) as i64;
                            match Self::product(ty, x, y) {
                                Some(p) => {
                                    self.write_word(&dst, 2, dof, p);
                                    cycle.stored = p;
                                }
                                None => cycle.error = Some("mul_range"),
                            }
                        }
                        Arith::Div => match Self::quotient(ty, x, y) {
                            Ok((q, r)) => {
                                self.write_word(&dst, w, dof, q as u32);
                                self.write_word(&dst, w, dof + w, r as u32);
                                cycle.exact = q;
                                cycle.stored = q as u32 & if w == 1 { 0xFFFF } else { u32::MAX };
                                cycle.remainder = r;
                            }
                            Err(kind) => cycle.error = Some(kind),
                        },
                    }
                    if let Some(kind) = cycle.error {
                        self.record_error(kind);
                    }
                    self.last_cycles.push(cycle);
                }
                if matches!(op, Arith::Add | Arith::Sub) {
                    self.special[M8003] = carry;
                }
            }
            Op::Step { up, ty, reg } if input => {
                self.last_acted = true;
                let word = Word::Reg {
                    n: reg,
                    repeat: false,
                };
                let w = ty.words();
                let v = self.read_word(&word, w, 0);
                let next = if up {
                    v.wrapping_add(1)
                } else {
                    v.wrapping_sub(1)
                };
                let next = if w == 1 { next & 0xFFFF } else { next };
                self.write_word(&word, w, 0, next);
            }
            Op::Mov { .. } | Op::Arith { .. } | Op::Step { .. } => {}
            _ => {
                self.last_acted = input;
                if let Some(to) = self.act(index, op, true) {
                    next = to;
                }
            }
        }
        self.last = Some(index as u32);
        self.steps += 1;
        self.step += 1;
        self.pc = next;
        if matches!(op, Op::End) || self.pc as usize >= self.program.instrs.len() {
            self.pc = 0;
            self.step = 0;
            self.tick += 1;
        }
    }
}
