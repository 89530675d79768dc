//! IDEC OpenNet (spec `opennet.md`): a scanned PLC with bit logic on two stacks, typed
//! arithmetic (W, I, D, L) with the vendor's signed-overflow rule, REP, the carry relay M8003
//! and the latched execution-error relay M8004.
//!
//! Decided where the spec is silent (each also noted where it is implemented):
//! - Inputs: a switch flipped in the debugger mid-scan is seen by the program from the next
//!   scan (the refresh copies the switches into the input image). Views show the switches; the
//!   runner's `bits` and the program read the image.
//! - Break on error stops before the instruction after the one that turned M8004 on.

pub mod assembler;
pub mod dialect;
pub mod explain;
pub mod fast;
#[cfg(feature = "gui")]
pub mod panels;
pub mod program;
pub mod syntax;
pub mod view;

use std::sync::Arc;

pub use assembler::assemble;
use program::{Area, Arith, Bit, Op, Program, Ty, Word};


pub const REGISTERS: usize = 8000;
pub const STACK_DEPTH: usize = 8;
/// Virtual scan time (spec §3).
pub const SCAN_MICROS: u32 = 10_000;
pub const M8003: usize = 0;
pub const M8004: usize = 1;

/// An execution error (spec §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExecError {
    pub kind: &'static str,
    pub line: usize,
    pub tick: u64,
}

/// One REP cycle of the last advanced instruction, for the explanation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cycle {
    pub a: i64,
    pub b: i64,
    /// Exact result (the quotient for DIV).
    pub exact: i64,
    pub stored: u32,
    pub remainder: i64,
    pub out_of_range: bool,
    pub error: Option<&'static str>,
    pub a_at: u32,
    pub b_at: u32,
    pub dst_at: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub struct OpenNet {
    pub program: Arc<Program>,
    pub d: Vec<u16>,
    /// The input switches, and the image the program reads (taken at scan start).
    pub inputs: Vec<bool>,
    pub input_image: Vec<bool>,
    pub q: Vec<bool>,
    pub m: Vec<bool>,
    /// M8003, M8004, M8120, M8121, M8122.
    pub special: [bool; 5],
    pub rlo: bool,
    pub blocks: Vec<bool>,
    pub branches: Vec<bool>,
    pub edges: Vec<bool>,
    pub pc: u32,
    pub tick: u64,
    pub step: u32,
    pub steps: u64,
    pub error_count: u64,
    pub last_error: Option<ExecError>,
    /// The last executed instruction, whether it acted, and its REP cycles.
    pub last: Option<u32>,
    pub last_acted: bool,
    pub last_cycles: Vec<Cycle>,
}

impl OpenNet {
    pub fn new(program: Arc<Program>) -> Self {
        let edges = vec![false; program.edges as usize];
        OpenNet {
            program,
            d: vec![0; REGISTERS],
            inputs: vec![false; Area::I.points() as usize],
            input_image: vec![false; Area::I.points() as usize],
            q: vec![false; Area::Q.points() as usize],
            m: vec![false; Area::M.points() as usize],
            special: [false; 5],
            rlo: false,
            blocks: Vec::new(),
            branches: Vec::new(),
            edges,
            pc: 0,
            tick: 0,
            step: 0,
            steps: 0,
            error_count: 0,
            last_error: None,
            last: None,
            last_acted: false,
            last_cycles: Vec::new(),
        }
    }

    fn area(&self, area: Area) -> &[bool] {
        match area {
            Area::I => &self.input_image,
            Area::Q => &self.q,
            Area::M => &self.m,
        }
    }

    fn area_mut(&mut self, area: Area) -> &mut [bool] {
        match area {
            Area::I => &mut self.input_image,
            Area::Q => &mut self.q,
            Area::M => &mut self.m,
        }
    }

    pub fn bit(&self, b: Bit) -> bool {
        match b {
            Bit::Point(area, i) => self.area(area).get(i as usize).copied().unwrap_or(false),
            Bit::Special(s) => self.special[s as usize],
        }
    }

    fn set_bit(&mut self, b: Bit, v: bool) {
        match b {
            Bit::Point(area, i) => {
                if let Some(x) = self.area_mut(area).get_mut(i as usize) {
                    *x = v;
                }
            }
            Bit::Special(s) => self.special[s as usize] = v,
        }
    }

    /// The pattern of `words` words at `w`, advanced by `offset` words.
    pub fn read_word(&self, w: &Word, words: u32, offset: u32) -> u32 {
        match *w {
            Word::Const(v) => v,
            Word::Reg { n, .. } => {
                let at = (n + offset) as usize;
                let hi = u32::from(self.d.get(at).copied().unwrap_or(0));
                if words == 1 {
                    hi
                } else {
                    // The upper word is in the lower-numbered register.
                    (hi << 16) | u32::from(self.d.get(at + 1).copied().unwrap_or(0))
                }
            }
            Word::Bits { area, index, .. } => {
                let start = (index + offset * 16) as usize;
                let bits = self.area(area);
                (0..words * 16).fold(0, |acc, i| {
                    acc | (u32::from(bits.get(start + i as usize).copied().unwrap_or(false)) << i)
                })
            }
        }
    }

    pub fn write_word(&mut self, w: &Word, words: u32, offset: u32, value: u32) {
        match *w {
            Word::Const(_) => {}
            Word::Reg { n, .. } => {
                let at = (n + offset) as usize;
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
            Word::Bits { area, index, .. } => {
                let start = (index + offset * 16) as usize;
                let bits = self.area_mut(area);
                for i in 0..(words * 16) as usize {
                    if let Some(b) = bits.get_mut(start + i) {
                        *b = value >> i & 1 == 1;
                    }
                }
            }
        }
    }

    /// The offset of a word operand in REP cycle `c`: `(R)` operands advance by their block.
    fn offset(w: &Word, block: u32, c: u32) -> u32 {
        if w.repeats() { c * block } else { 0 }
    }

    /// Spec §5.4: what ADD/SUB store, and whether the result was out of range.
    pub fn store_add(ty: Ty, r: i64) -> (u32, bool) {
        let in_range = r >= ty.min() && r <= ty.max();
        let pattern = match ty {
            Ty::W => r.rem_euclid(1 << 16) as u32,
            Ty::D => r.rem_euclid(1 << 32) as u32,
            Ty::I if in_range => r as u16 as u32,
            Ty::L if in_range => r as u32,
            // Out of range: the sign of r, then r mod 2^15 / 2^31 (not two's complement).
            Ty::I => (u32::from(r < 0) << 15) | r.rem_euclid(1 << 15) as u32,
            Ty::L => (u32::from(r < 0) << 31) | r.rem_euclid(1 << 31) as u32,
        };
        (pattern, !in_range)
    }

    /// MUL's 32-bit result pattern, or None when D or L cannot hold the product.
    #[inline]
    fn product(ty: Ty, x: i64, y: i64) -> Option<u32> {
        let p = i128::from(x) * i128::from(y);
        let fits = match ty {
            Ty::D => p <= i128::from(u32::MAX),
            Ty::L => (i128::from(i32::MIN)..=i128::from(i32::MAX)).contains(&p),
            _ => true,
        };
        fits.then_some(p as u32)
    }

    /// DIV's quotient and remainder (truncated toward zero; the remainder has the dividend's
    /// sign), or the error it raises.
    #[inline]
    fn quotient(ty: Ty, x: i64, y: i64) -> Result<(i64, i64), &'static str> {
        if y == 0 {
            Err("divide_by_zero")
        } else if ty.signed() && x == ty.min() && y == -1 {
            Err("divide_overflow")
        } else {
            Ok((x / y, x % y))
        }
    }

    fn record_error(&mut self, kind: &'static str) {
        self.record_error_at(self.pc as usize, kind);
    }

    fn record_error_at(&mut self, index: usize, kind: &'static str) {
        let line = self.program.instrs.get(index).map_or(0, |i| i.line);
        self.special[M8004] = true;
        self.error_count += 1;
        self.last_error = Some(ExecError {
            kind,
            line,
            tick: self.tick,
        });
    }

    fn refresh(&mut self) {
        self.input_image.clone_from(&self.inputs);
        self.special[2] = self.tick == 0;
        self.special[3] = self.tick % 100 < 50;
        self.special[4] = self.tick % 10 < 5;
        self.rlo = false;
        self.blocks.clear();
        self.branches.clear();
    }

    fn push(stack: &mut Vec<bool>, v: bool) {
        if stack.len() < STACK_DEPTH {
            stack.push(v);
        }
    }

    fn execute(&mut self) {
        let index = self.pc as usize;
        let op = self.program.instrs[index].op;
        let previous_output = index > 0 && is_output(&self.program.instrs[index - 1].op);
        self.last_acted = false;
        self.last_cycles.clear();
        match op {
            Op::Lod(b, neg) => {
                if index == 0 || previous_output {
                    self.blocks.clear();
                    self.branches.clear();
                } else {
                    Self::push(&mut self.blocks, self.rlo);
                }
                self.rlo = self.bit(b) != neg;
            }
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
            Op::Sotu(m) => {
                let mem = &mut self.edges[m as usize];
                let old = self.rlo;
                self.rlo = old && !*mem;
                *mem = old;
            }
            Op::Sotd(m) => {
                let mem = &mut self.edges[m as usize];
                let old = self.rlo;
                self.rlo = !old && *mem;
                *mem = old;
            }
            Op::Out(b, neg) => self.set_bit(b, self.rlo != neg),
            Op::Set(b) => {
                if self.rlo {
                    self.set_bit(b, true);
                }
            }
            Op::Rst(b) => {
                if self.rlo {
                    self.set_bit(b, false);
                }
            }
            Op::End => {}
            Op::Mov { ty, src, dst, rep } if self.rlo => {
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
            } if self.rlo => {
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
            Op::Step { up, ty, reg } if self.rlo => {
                self.last_acted = true;
                let word = Word::Reg {
                    n: reg,
                    repeat: false,
                };
                let w = ty.words();
                let v = self.read_word(&word, w, 0);
                let next = if up { v.wrapping_add(1) } else { v.wrapping_sub(1) };
                let next = if w == 1 { next & 0xFFFF } else { next };
                self.write_word(&word, w, 0, next);
            }
            Op::Mov { .. } | Op::Arith { .. } | Op::Step { .. } => {}
        }
        self.last = Some(index as u32);
        self.steps += 1;
        self.step += 1;
        self.pc += 1;
        if op == Op::End || self.pc as usize >= self.program.instrs.len() {
            self.pc = 0;
            self.step = 0;
            self.tick += 1;
        }
    }
}

impl crate::machine::ScanSteps for OpenNet {
    fn has_instructions(&self) -> bool {
        !self.program.instrs.is_empty()
    }
    fn start_scan(&mut self) {
        self.refresh();
    }
    fn run_instruction(&mut self) {
        self.execute();
    }
    fn complete_empty_scan(&mut self) {
        self.tick += 1;
    }
    fn instruction_line(&self, index: usize) -> usize {
        self.program.instrs.get(index).map_or(0, |i| i.line)
    }
    fn instruction_count(&self) -> usize {
        self.program.instrs.len()
    }
    fn fast_scan(&mut self) -> bool {
        self.scan_fast()
    }
    fn scan_writes(&self) -> crate::machine::WriteSet {
        self.program.scan_writes
    }
}

pub fn is_output(op: &Op) -> bool {
    matches!(
        op,
        Op::Out(..) | Op::Set(_) | Op::Rst(_) | Op::Mov { .. } | Op::Arith { .. } | Op::Step { .. }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row of the vendor's storage table (spec §5.4).
    #[test]
    fn the_vendors_storage_table() {
        let rows: &[(Ty, i64, u32, bool)] = &[
            (Ty::W, 0, 0x0000, false),
            (Ty::W, 65535, 0xFFFF, false),
            (Ty::W, 131071, 0xFFFF, true),
            (Ty::W, -1, 0xFFFF, true),
            (Ty::W, -65535, 0x0001, true),
            (Ty::W, -65536, 0x0000, true),
            (Ty::I, 65534, 0x7FFE, true),
            (Ty::I, 32768, 0x0000, true),
            (Ty::I, 32767, 0x7FFF, false),
            (Ty::I, 0, 0x0000, false),
            (Ty::I, -1, 0xFFFF, false),
            (Ty::I, -32767, 0x8001, false),
            (Ty::I, -32768, 0x8000, false),
            (Ty::I, -32769, 0xFFFF, true),
            (Ty::I, -65535, 0x8001, true),
            (Ty::D, 0, 0, false),
            (Ty::D, 4294967295, 0xFFFF_FFFF, false),
            (Ty::D, 8589934591, 0xFFFF_FFFF, true),
            (Ty::D, -1, 0xFFFF_FFFF, true),
            (Ty::D, -4294967295, 0x0000_0001, true),
            (Ty::D, -4294967296, 0x0000_0000, true),
            (Ty::L, 4294967294, 0x7FFF_FFFE, true),
            (Ty::L, 2147483648, 0x0000_0000, true),
            (Ty::L, 2147483647, 0x7FFF_FFFF, false),
            (Ty::L, 0, 0, false),
            (Ty::L, -1, 0xFFFF_FFFF, false),
            (Ty::L, -2147483647, 0x8000_0001, false),
            (Ty::L, -2147483648, 0x8000_0000, false),
            (Ty::L, -2147483649, 0xFFFF_FFFF, true),
            (Ty::L, -4294967295, 0x8000_0001, true),
        ];
        for &(ty, r, stored, carry) in rows {
            assert_eq!(OpenNet::store_add(ty, r), (stored, carry), "{ty:?} {r}");
        }
    }
}
