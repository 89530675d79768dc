//! DL205's fast loop: each instruction pre-decoded once into a [`Flat`] op that runs with one
//! dispatch, and whole scans run without the per-instruction record the views read (the last
//! instruction, ACC and L1 before it, what it did to the stack, the step counters). The rung
//! power after each instruction is kept, as the ladder view shows it. END, the last
//! instruction of every program, runs in the full executor, so a machine leaves the fast loop
//! exactly as the executor leaves it at a scan's end.

use std::sync::Arc;

use super::program::{Bit, D, Instr, Kind, Op, Test, W, box_shape, current_word};
use super::view::{ACC, SP, V, bit_loc, kind_space, word_writes};
use super::{Dl205, LEVELS};
use crate::machine::{Loc, WriteSet};

/// An instruction with its operands resolved; `Output` is an output instruction the fast loop
/// hands to the executor's output step (the math, whose own work outweighs a dispatch).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flat {
    Str(Test),
    And(Test),
    Or(Test),
    AndStr,
    OrStr,
    Coil(Bit),
    Nop,
    /// LD K, LDD K, LDA.
    LoadConst(u32),
    /// LD V.
    LoadWord(u32),
    /// LDD V.
    LoadPair(u32),
    OutWord(u32),
    OutPair(u32),
    Pop,
    Not,
    /// An output that runs on an unpowered rung too (PD, OROUT, the boxes).
    Always(Op),
    Output(Op),
    /// END and program control (jumps, loops, calls, stages, master lines): the executor
    /// runs it and says where to go on.
    Full,
}

/// The fast form of each instruction.
pub fn flatten(instrs: &[Instr]) -> Vec<Flat> {
    instrs
        .iter()
        .map(|instr| match instr.op {
            Op::Str(t) => Flat::Str(t),
            Op::And(t) => Flat::And(t),
            Op::Or(t) => Flat::Or(t),
            Op::AndStr => Flat::AndStr,
            Op::OrStr => Flat::OrStr,
            Op::Coil(b) => Flat::Coil(b),
            Op::Nop => Flat::Nop,
            Op::Ld(W::K(k)) => Flat::LoadConst(u32::from(k)),
            Op::Ldd(D::K(k)) | Op::Lda(k) => Flat::LoadConst(k),
            Op::Ld(W::V(a)) => Flat::LoadWord(a),
            Op::Ldd(D::V(a)) => Flat::LoadPair(a),
            Op::OutV(a) => Flat::OutWord(a),
            Op::OutD(a) => Flat::OutPair(a),
            Op::Pop => Flat::Pop,
            Op::Not => Flat::Not,
            op if op.is_control() => Flat::Full,
            op if op.always_runs() => Flat::Always(op),
            op => Flat::Output(op),
        })
        .collect()
}

/// What a timer or counter box may write: its current value word(s), its status bit, SP75.
pub fn box_writes(op: &Op) -> Vec<Loc> {
    let (kind, n) = match *op {
        Op::Timer(_, n, _) => (Kind::T, n),
        Op::Counter(_, n, _) => (Kind::Ct, n),
        _ => return Vec::new(),
    };
    let words = box_shape(op).map_or(1, |(w, _)| w);
    let word = current_word(kind, n);
    let mut out: Vec<Loc> = (word..word + words).map(|w| Loc::new(V, w)).collect();
    out.push(bit_loc(Bit { kind, n }));
    out.push(Loc::new(SP, super::program::sp::SP75 as u32));
    out
}

/// Every location a pass over `instrs` may write, as `note_writes` notes them one at a time.
pub fn scan_writes(instrs: &[Instr]) -> WriteSet {
    let mut set = WriteSet::default();
    let mut accumulator = false;
    for instr in instrs {
        match instr.op {
            Op::Coil(b) | Op::Pd(b, _) | Op::OrOut(b, _) => set.insert(bit_loc(b)),
            Op::Timer(..) | Op::Counter(..) => {
                for loc in box_writes(&instr.op) {
                    set.insert(loc);
                }
            }
            Op::Jmp { to, own } | Op::Njmp { to, own } => {
                set.insert(Loc::new(super::view::S, own));
                set.insert(Loc::new(super::view::S, to));
            }
            Op::For(..) => set.insert(Loc::new(SP, super::program::sp::SP75 as u32)),
            Op::Rst(a, b) if matches!(a.kind, Kind::T | Kind::Ct) => {
                for n in a.n..=b.n {
                    let status = Bit { kind: a.kind, n };
                    set.insert(bit_loc(status));
                    let word = current_word(a.kind, n);
                    (word..word + 2).for_each(|w| set.insert(Loc::new(V, w)));
                }
            }
            Op::Set(a, b) | Op::Rst(a, b) => {
                (a.n..=b.n).for_each(|n| set.insert(Loc::new(kind_space(a.kind), n)));
            }
            Op::OutF(e, n) => {
                (e.n..e.n + u32::from(n)).for_each(|i| set.insert(Loc::new(kind_space(e.kind), i)));
            }
            Op::OutV(a) | Op::IncB(a) | Op::DecB(a) => word_writes(a, &mut |l| set.insert(l)),
            Op::OutD(a) => {
                word_writes(a, &mut |l| set.insert(l));
                word_writes(a + 1, &mut |l| set.insert(l));
            }
            // A table's words come from ACC and L1 at run time: any V word (256 consecutive
            // indices fill the Bloom set's bits for the space), and its error flags.
            Op::Table(..) => {
                (0..256).for_each(|i| set.insert(Loc::new(V, i)));
                set.insert(Loc::new(SP, super::program::sp::SP53 as u32));
                set.insert(Loc::new(SP, super::program::sp::SP75 as u32));
            }
            op if op.is_output() => accumulator = true,
            _ => {}
        }
    }
    if accumulator {
        (0..=LEVELS as u32).for_each(|i| set.insert(Loc::new(ACC, i)));
    }
    set
}

impl Dl205 {
    /// One instruction of the fast loop at `index`.
    #[inline(always)]
    fn run_flat(&mut self, index: usize, op: Flat) {
        let power = self.bstack.last().copied().unwrap_or(false) && self.block_power;
        match op {
            Flat::Str(t) => self.contact_str(t),
            Flat::And(t) => self.contact_and(t),
            Flat::Or(t) => self.contact_or(t),
            Flat::AndStr => self.join_top(true),
            Flat::OrStr => self.join_top(false),
            Flat::Nop => {}
            Flat::Not => self.invert_top(),
            Flat::Always(op) => {
                self.rung_has_output = true;
                self.always(op, power);
            }
            Flat::Coil(b) => {
                self.rung_has_output = true;
                self.set_bit(b, power);
            }
            // Handled by the scan loop.
            Flat::Full => return,
            _ if !power => self.rung_has_output = true,
            Flat::LoadConst(k) => {
                self.rung_has_output = true;
                self.load(k);
            }
            Flat::LoadWord(a) => {
                self.rung_has_output = true;
                let v = u32::from(self.word(a));
                self.load(v);
            }
            Flat::LoadPair(a) => {
                self.rung_has_output = true;
                let v = self.pair(a);
                self.load(v);
            }
            Flat::OutWord(a) => {
                self.rung_has_output = true;
                self.set_word(a, self.acc as u16);
                self.load_pending = false;
            }
            Flat::OutPair(a) => {
                self.rung_has_output = true;
                self.set_word(a, self.acc as u16);
                self.set_word(a + 1, (self.acc >> 16) as u16);
                self.load_pending = false;
            }
            Flat::Pop => {
                self.rung_has_output = true;
                self.acc = self.pop();
            }
            Flat::Output(op) => {
                self.rung_has_output = true;
                self.output(op);
            }
        }
        // As the executor: contacts leave the rung's power, outputs the power they acted on.
        let contact = matches!(
            op,
            Flat::Str(_)
                | Flat::And(_)
                | Flat::Or(_)
                | Flat::AndStr
                | Flat::OrStr
                | Flat::Not
                | Flat::Nop
        );
        let after = if contact {
            self.bstack.last().copied().unwrap_or(false)
        } else {
            power
        };
        if let Some(p) = self.power.get_mut(index) {
            *p = Some(after);
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
        let start = self.steps;
        let tick = self.tick;
        self.scan_start();
        let mut index = 0usize;
        let mut executed = 0u64;
        while let Some(&op) = flat.get(index) {
            if op == Flat::Full {
                // Program control and END in the executor, with the counters it keeps.
                self.pc = index as u32;
                self.step = executed as u32;
                self.steps = start + executed;
                self.execute();
                executed += 1;
                if self.tick != tick {
                    return true;
                }
                index = self.pc as usize;
            } else {
                // Where the executor would be: error flags and stage changes remember it.
                self.pc = index as u32;
                self.step = executed as u32;
                self.run_flat(index, op);
                executed += 1;
                index += 1;
            }
        }
        // The last instruction is END (checked at assembly); past it the executor's rule.
        self.pc = 0;
        self.step = 0;
        self.steps = start + executed;
        self.tick += 1;
        true
    }
}
