//! OpenNet's fast loop: each instruction pre-decoded once into a [`Flat`] op that runs with
//! one dispatch, and whole scans run without the per-instruction record the views read (the
//! last instruction, its REP cycles, the step counters). Timers, counters, comparisons, MCS
//! and jumps run the executor's own code ([`OpenNet::act`]) without its record. The scan's
//! last instruction always runs in the full executor, so a machine leaves the fast loop
//! exactly as the executor would leave it at the scan's end.

use std::sync::Arc;

use super::program::{Arith, Bit, Instr, Op, Ty, Word};
use super::view::static_writes;
use super::{M8003, OpenNet};
use crate::machine::WriteSet;

/// A word operand the fast loop reads without looking at bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operand {
    Reg(u32),
    Const(u32),
}

/// An instruction with its operands resolved: bit logic as is, the advanced instructions on
/// registers and constants by kind, and `Full` for the rest (bit-area words, END).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flat {
    /// LOD that opens a rung: the stacks start empty.
    Open(Bit, bool),
    /// LOD inside a rung: the result so far goes on the block stack.
    Lod(Bit, bool),
    And(Bit, bool),
    Or(Bit, bool),
    AndLod,
    OrLod,
    Bps,
    Brd,
    Bpp,
    Sotu(u32),
    Sotd(u32),
    Out(Bit, bool),
    Set(Bit),
    Rst(Bit),
    /// `steps` advance the operands a, b and dst by REP cycle (0 when not repeated).
    Mov {
        words: u8,
        src: Operand,
        dst: u32,
        rep: u8,
        steps: [u8; 2],
    },
    Arith {
        op: Arith,
        ty: Ty,
        a: Operand,
        b: Operand,
        dst: u32,
        rep: u8,
        steps: [u8; 3],
    },
    Step {
        up: bool,
        words: u8,
        reg: u32,
    },
    /// The PLC's control instructions: [`OpenNet::act`] on the program's op.
    Act,
    Full,
}

fn operand(w: Word) -> Option<Operand> {
    match w {
        Word::Const(v) => Some(Operand::Const(v)),
        Word::Reg { n, .. } => Some(Operand::Reg(n)),
        Word::Bits { .. } | Word::Timer { .. } | Word::Counter { .. } => None,
    }
}

fn register(w: Word) -> Option<u32> {
    match w {
        Word::Reg { n, .. } => Some(n),
        _ => None,
    }
}

/// What an operand advances by per REP cycle, for a block of `block` words.
fn step(w: Word, block: u32) -> u8 {
    if w.repeats() { block as u8 } else { 0 }
}

/// The registers written by `Arith` cycles: a result of `dst_block` words.
fn dst_block(op: Arith, ty: Ty) -> u32 {
    match op {
        Arith::Add | Arith::Sub => ty.words(),
        Arith::Mul => 2,
        Arith::Div => 2 * ty.words(),
    }
}

/// The fast form of each instruction.
pub fn flatten(instrs: &[Instr], opens: &[bool]) -> Vec<Flat> {
    instrs
        .iter()
        .zip(opens)
        .map(|(instr, &opens)| flat_op(instr.op, opens))
        .collect()
}

fn flat_op(op: Op, opens_rung: bool) -> Flat {
    match op {
        Op::Lod(b, neg) if opens_rung => Flat::Open(b, neg),
        Op::Lod(b, neg) => Flat::Lod(b, neg),
        Op::And(b, neg) => Flat::And(b, neg),
        Op::Or(b, neg) => Flat::Or(b, neg),
        Op::AndLod => Flat::AndLod,
        Op::OrLod => Flat::OrLod,
        Op::Bps => Flat::Bps,
        Op::Brd => Flat::Brd,
        Op::Bpp => Flat::Bpp,
        Op::Sotu(m) => Flat::Sotu(m),
        Op::Sotd(m) => Flat::Sotd(m),
        Op::Out(b, neg) => Flat::Out(b, neg),
        Op::Set(b) => Flat::Set(b),
        Op::Rst(b) => Flat::Rst(b),
        Op::Mov { ty, src, dst, rep } => {
            let w = ty.words();
            match (operand(src), register(dst)) {
                (Some(s), Some(d)) => Flat::Mov {
                    words: w as u8,
                    src: s,
                    dst: d,
                    rep,
                    steps: [step(src, w), step(dst, w)],
                },
                _ => Flat::Full,
            }
        }
        Op::Arith {
            op,
            ty,
            a,
            b,
            dst,
            rep,
        } => {
            let w = ty.words();
            match (operand(a), operand(b), register(dst)) {
                (Some(x), Some(y), Some(d)) => Flat::Arith {
                    op,
                    ty,
                    a: x,
                    b: y,
                    dst: d,
                    rep,
                    steps: [step(a, w), step(b, w), step(dst, dst_block(op, ty))],
                },
                _ => Flat::Full,
            }
        }
        Op::Step { up, ty, reg } => Flat::Step {
            up,
            words: ty.words() as u8,
            reg,
        },
        Op::End => Flat::Full,
        _ => Flat::Act,
    }
}

/// Every location a pass over `instrs` may write, as `note_writes` notes them one at a time.
pub fn scan_writes(instrs: &[Instr]) -> WriteSet {
    let mut set = WriteSet::default();
    for instr in instrs {
        static_writes(&instr.op, &mut |loc| set.insert(loc));
    }
    set
}

impl OpenNet {
    #[inline(always)]
    fn load(&self, o: Operand, words: u8, at: u32) -> u32 {
        match o {
            Operand::Const(v) => v,
            Operand::Reg(n) => {
                let at = (n + at) as usize;
                let hi = u32::from(self.d.get(at).copied().unwrap_or(0));
                if words == 1 {
                    hi
                } else {
                    (hi << 16) | u32::from(self.d.get(at + 1).copied().unwrap_or(0))
                }
            }
        }
    }

    #[inline(always)]
    fn store(&mut self, reg: u32, words: u8, value: u32) {
        let at = reg as usize;
        if words == 1 {
            if let Some(r) = self.d.get_mut(at) {
                *r = value as u16;
            }
        } else {
            if let Some(r) = self.d.get_mut(at) {
                *r = (value >> 16) as u16;
            }
            if let Some(r) = self.d.get_mut(at + 1) {
                *r = value as u16;
            }
        }
    }

    /// One instruction of the fast loop; `index` is where it is, for an error's line. Returns
    /// where a taken jump continues.
    #[inline(always)]
    fn run_flat(&mut self, index: usize, op: Flat) -> Option<usize> {
        match op {
            Flat::Open(b, neg) => {
                self.blocks.clear();
                self.branches.clear();
                self.rlo = self.bit(b) != neg;
            }
            Flat::Lod(b, neg) => {
                Self::push(&mut self.blocks, self.rlo);
                self.rlo = self.bit(b) != neg;
            }
            Flat::And(b, neg) => self.rlo &= self.bit(b) != neg,
            Flat::Or(b, neg) => self.rlo |= self.bit(b) != neg,
            Flat::AndLod => self.rlo &= self.blocks.pop().unwrap_or(false),
            Flat::OrLod => self.rlo |= self.blocks.pop().unwrap_or(false),
            Flat::Bps => Self::push(&mut self.branches, self.rlo),
            Flat::Brd => self.rlo = self.branches.last().copied().unwrap_or(false),
            Flat::Bpp => self.rlo = self.branches.pop().unwrap_or(false),
            Flat::Sotu(m) => self.sotu(m),
            Flat::Sotd(m) => self.sotd(m),
            Flat::Out(b, neg) => self.set_bit(b, (self.rlo && self.mc) != neg),
            Flat::Set(b) if self.rlo && self.mc => self.set_bit(b, true),
            Flat::Rst(b) if self.rlo && self.mc => self.set_bit(b, false),
            Flat::Set(_) | Flat::Rst(_) => {}
            Flat::Mov {
                words,
                src,
                dst,
                rep,
                steps: [s, d],
            } if self.rlo && self.mc => {
                for c in 0..u32::from(rep) {
                    let v = self.load(src, words, c * u32::from(s));
                    self.store(dst + c * u32::from(d), words, v);
                }
            }
            Flat::Arith {
                op,
                ty,
                a,
                b,
                dst,
                rep,
                steps,
            } if self.rlo && self.mc => self.arith_flat(index, op, ty, [a, b], dst, rep, steps),
            Flat::Step { up, words, reg } if self.rlo && self.mc => {
                let v = self.load(Operand::Reg(reg), words, 0);
                let next = if up {
                    v.wrapping_add(1)
                } else {
                    v.wrapping_sub(1)
                };
                self.store(reg, words, if words == 1 { next & 0xFFFF } else { next });
            }
            Flat::Mov { .. } | Flat::Arith { .. } | Flat::Step { .. } => {}
            Flat::Act => return self.act_outlined(index),
            Flat::Full => {
                self.pc = index as u32;
                self.execute();
                return (self.pc as usize != index + 1).then_some(self.pc as usize);
            }
        }
        None
    }

    /// [`OpenNet::act`] kept out of the loop's body: inlined, its size crowded the simple
    /// instructions' registers (small scans ran 30 % slower).
    #[inline(never)]
    fn act_outlined(&mut self, index: usize) -> Option<usize> {
        let op = self.program.instrs[index].op;
        self.act(index, op, false).map(|to| to as usize)
    }

    /// The advanced arithmetic of [`OpenNet::execute`] without its record of the cycles.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn arith_flat(
        &mut self,
        index: usize,
        op: Arith,
        ty: Ty,
        [a, b]: [Operand; 2],
        dst: u32,
        rep: u8,
        [sa, sb, sd]: [u8; 3],
    ) {
        let w = ty.words() as u8;
        let mut carry = false;
        for c in 0..u32::from(rep) {
            let x = ty.value(self.load(a, w, c * u32::from(sa)));
            let y = ty.value(self.load(b, w, c * u32::from(sb)));
            let at = dst + c * u32::from(sd);
            match op {
                Arith::Add | Arith::Sub => {
                    let r = if op == Arith::Add { x + y } else { x - y };
                    let (stored, out) = Self::store_add(ty, r);
                    carry |= out;
                    self.store(at, w, stored);
                }
                Arith::Mul => match Self::product(ty, x, y) {
                    Some(p) => self.store(at, 2, p),
                    None => self.record_error_at(index, "mul_range"),
                },
                Arith::Div => match Self::quotient(ty, x, y) {
                    Ok((q, r)) => {
                        self.store(at, w, q as u32);
                        self.store(at + u32::from(w), w, r as u32);
                    }
                    Err(kind) => self.record_error_at(index, kind),
                },
            }
        }
        if matches!(op, Arith::Add | Arith::Sub) {
            self.special[M8003] = carry;
        }
    }

    /// [`crate::machine::plc::ScannedPlc::scan_fast`].
    pub(super) fn scan_fast(&mut self) -> bool {
        let program = Arc::clone(&self.program);
        let flat = &program.flat;
        let len = program.instrs.len();
        if self.step != 0 || len == 0 || flat.len() != len {
            return false;
        }
        let last = len - 1;
        let start = self.steps;
        self.refresh();
        // A plain walk over the ops (the next one loads while this one runs); a taken jump
        // skips to its JEND.
        let mut skip_to = 0;
        let mut executed = 0u32;
        for (i, &op) in flat[..last].iter().enumerate() {
            if i < skip_to {
                continue;
            }
            if let Some(to) = self.run_flat(i, op) {
                skip_to = to;
            }
            executed += 1;
        }
        // The last instruction in the executor: it ends the scan with the full record.
        self.pc = last as u32;
        self.step = executed;
        self.steps = start + u64::from(executed);
        self.execute();
        true
    }
}
