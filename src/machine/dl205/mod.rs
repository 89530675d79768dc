//! AutomationDirect DL205 (spec `dl205.md`): a scanned PLC whose math runs through a 32-bit
//! accumulator and an 8-level accumulator stack, mostly in BCD, with the boolean stack of its
//! rungs and the SP flags.
//!
//! Decided where the spec is silent (also noted where implemented):
//! - The debugger may write V words, X inputs (seen from the next scan: the scan start copies
//!   the switches into the image), Y and C; SP relays are the machine's.
//! - SP53 and SP75 remember the line of the instruction that last set them, for the views.

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
use program::{Bit, Cmp, D, Kind, Logic, Math, Op, Program, ShiftKind, Src, Test, W, sp};


pub const V_WORDS: usize = 0o40000;
pub const LEVELS: usize = 8;

/// What the last instruction did to the accumulator stack, for the panel and explanations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StackMove {
    #[default]
    None,
    /// A value entered L1; the one that fell off L8, when all eight levels were in use (a
    /// level below the depth holds no value, so nothing is lost from it).
    Push { entered: u32, lost: Option<u32> },
    /// L1 rose into ACC or was consumed.
    Pop { value: u32 },
    /// L1 was overwritten (DIVS, DIVBS).
    Overwrite { value: u32 },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Dl205 {
    pub program: Arc<Program>,
    pub v: Vec<u16>,
    pub x: Vec<bool>,
    pub x_image: Vec<bool>,
    pub y: Vec<bool>,
    pub c: Vec<bool>,
    pub sp: [bool; 11],
    pub acc: u32,
    pub stack: [u32; LEVELS],
    pub depth: u8,
    pub load_pending: bool,
    pub bstack: Vec<bool>,
    pub rung_has_output: bool,
    pub pc: u32,
    pub tick: u64,
    pub step: u32,
    pub steps: u64,
    pub last: Option<u32>,
    /// ACC and L1 before the last instruction, and what it did to the stack.
    pub before: (u32, u32),
    pub moved: StackMove,
    /// Whether the last instruction ran (its rung was powered), or met non-BCD data / ÷0.
    pub last_ran: bool,
    pub sp53_line: Option<usize>,
    pub sp75_line: Option<usize>,
    /// The rung power after each instruction of this scan (None: not reached yet).
    pub power: Vec<Option<bool>>,
}

/// The value of the low `n` BCD digits of `x`, or None if one is not a decimal digit.
pub fn bcd_value(x: u32, n: u32) -> Option<u64> {
    let mut v = 0u64;
    for i in (0..n).rev() {
        let d = x >> (4 * i) & 0xF;
        if d > 9 {
            return None;
        }
        v = v * 10 + u64::from(d);
    }
    Some(v)
}

/// The BCD pattern of the low 8 decimal digits of `v`.
pub fn to_bcd(v: u64) -> u32 {
    let mut v = v % 100_000_000;
    let mut out = 0u32;
    for i in 0..8 {
        out |= ((v % 10) as u32) << (4 * i);
        v /= 10;
    }
    out
}

impl Dl205 {
    pub fn new(program: Arc<Program>) -> Self {
        let n = program.instrs.len();
        let mut m = Dl205 {
            program,
            v: vec![0; V_WORDS],
            x: vec![false; Kind::X.count() as usize],
            x_image: vec![false; Kind::X.count() as usize],
            y: vec![false; Kind::Y.count() as usize],
            c: vec![false; Kind::C.count() as usize],
            sp: [false; 11],
            acc: 0,
            stack: [0; LEVELS],
            depth: 0,
            load_pending: false,
            bstack: Vec::new(),
            rung_has_output: false,
            pc: 0,
            tick: 0,
            step: 0,
            steps: 0,
            last: None,
            before: (0, 0),
            moved: StackMove::None,
            last_ran: false,
            sp53_line: None,
            sp75_line: None,
            power: vec![None; n],
        };
        m.sp[sp::SP1] = true;
        m
    }

    pub fn bit(&self, b: Bit) -> bool {
        let i = b.n as usize;
        match b.kind {
            Kind::X => self.x_image.get(i).copied().unwrap_or(false),
            Kind::Y => self.y.get(i).copied().unwrap_or(false),
            Kind::C => self.c.get(i).copied().unwrap_or(false),
            Kind::Sp => self.sp.get(i).copied().unwrap_or(false),
        }
    }

    fn set_bit(&mut self, b: Bit, on: bool) {
        let i = b.n as usize;
        let slot = match b.kind {
            Kind::Y => self.y.get_mut(i),
            Kind::C => self.c.get_mut(i),
            // The assembler never lets a program write X or SP.
            Kind::X | Kind::Sp => None,
        };
        if let Some(s) = slot {
            *s = on;
        }
    }

    fn w(&self, w: W) -> u32 {
        match w {
            W::V(a) => u32::from(self.v[a as usize]),
            W::K(k) => u32::from(k),
        }
    }

    /// A pair: Vn low word, Vn+1 high word.
    pub fn pair(&self, a: u32) -> u32 {
        u32::from(self.v[a as usize]) | (u32::from(self.v[a as usize + 1]) << 16)
    }

    fn d(&self, d: D) -> u32 {
        match d {
            D::V(a) => self.pair(a),
            D::K(k) => k,
        }
    }

    pub fn push(&mut self, v: u32) {
        let lost = (usize::from(self.depth) == LEVELS).then_some(self.stack[LEVELS - 1]);
        self.stack.copy_within(0..LEVELS - 1, 1);
        self.stack[0] = v;
        self.depth = (self.depth + 1).min(LEVELS as u8);
        self.moved = StackMove::Push { entered: v, lost };
    }

    pub fn pop(&mut self) -> u32 {
        let v = self.stack[0];
        self.stack.copy_within(1..LEVELS, 0);
        self.stack[LEVELS - 1] = 0;
        self.depth = self.depth.saturating_sub(1);
        self.moved = StackMove::Pop { value: v };
        v
    }

    fn load(&mut self, v: u32) {
        if self.load_pending {
            let acc = self.acc;
            self.push(acc);
        }
        self.acc = v;
        self.load_pending = true;
    }

    fn zn(&mut self) {
        self.sp[sp::SP63] = self.acc == 0;
        self.sp[sp::SP70] = self.acc >> 31 == 1;
    }

    fn line(&self) -> usize {
        self.program.instrs[self.pc as usize].line
    }

    fn non_bcd(&mut self) {
        self.sp[sp::SP75] = true;
        self.sp75_line = Some(self.line());
    }

    fn divide_by_zero(&mut self) {
        self.sp[sp::SP53] = true;
        self.sp53_line = Some(self.line());
    }

    fn test(&self, t: Test) -> bool {
        match t {
            Test::Bit(b, neg) => self.bit(b) != neg,
            Test::Compare(a, b, kind) => {
                let (x, y) = (u32::from(self.v[a as usize]), self.w(b));
                match kind {
                    Cmp::Eq => x == y,
                    Cmp::Ne => x != y,
                    Cmp::Ge => x >= y,
                    Cmp::Lt => x < y,
                }
            }
        }
    }

    /// BCD math (spec §6.3).
    fn bcd_math(&mut self, op: Math, src: Src) {
        let a = self.acc;
        // The digits each row reads; a non-BCD one skips everything but SP75.
        let (a_digits, operand, o_digits) = match (op, src) {
            (Math::Add | Math::Sub, Src::Word(w)) => (4, self.w(w), 4),
            (Math::Add | Math::Sub, Src::Double(d)) => (8, self.d(d), 8),
            (Math::Add | Math::Sub, Src::Stack) => (8, self.stack[0], 8),
            (Math::Mul, Src::Word(w)) => (4, self.w(w), 4),
            (Math::Mul, Src::Stack) => (4, self.stack[0], 4),
            (Math::Mul, Src::Double(d)) => (8, self.d(d), 8),
            (Math::Div, Src::Word(w)) => (8, self.w(w), 4),
            (Math::Div, Src::Double(d)) => (8, self.d(d), 8),
            (Math::Div, Src::Stack) => (8, self.stack[0], 4),
        };
        let (Some(x), Some(y)) = (bcd_value(a, a_digits), bcd_value(operand, o_digits)) else {
            self.non_bcd();
            return;
        };
        let is_double = !matches!(src, Src::Word(_));
        match op {
            Math::Add | Math::Sub => {
                let modulus: i64 = if is_double { 100_000_000 } else { 10_000 };
                let s = if op == Math::Add {
                    x as i64 + y as i64
                } else {
                    x as i64 - y as i64
                };
                self.acc = to_bcd(s.rem_euclid(modulus) as u64);
                let (lx, ly) = (x % 10_000, y % 10_000);
                if op == Math::Add {
                    self.sp[sp::SP66] = if is_double { lx + ly >= 10_000 } else { s >= 10_000 };
                    self.sp[sp::SP67] = is_double && s >= 100_000_000;
                } else {
                    self.sp[sp::SP64] = if is_double { lx < ly } else { s < 0 };
                    self.sp[sp::SP65] = is_double && s < 0;
                }
                if src == Src::Stack {
                    self.pop();
                }
            }
            Math::Mul => {
                let p = x * y;
                self.acc = to_bcd(p % 100_000_000);
                match src {
                    Src::Stack => {
                        self.pop();
                    }
                    Src::Double(_) => self.push(to_bcd(p / 100_000_000)),
                    Src::Word(_) => {}
                }
            }
            Math::Div => {
                if y == 0 {
                    self.divide_by_zero();
                    return;
                }
                self.acc = to_bcd(x / y);
                let r = to_bcd(x % y);
                if src == Src::Stack {
                    self.stack[0] = r;
                    self.moved = StackMove::Overwrite { value: r };
                } else {
                    self.push(r);
                }
                self.sp[sp::SP53] = false;
            }
        }
        self.sp[sp::SP75] = false;
        self.zn();
    }

    /// Binary math (spec §6.4).
    fn binary_math(&mut self, op: Math, src: Src) {
        let a = self.acc;
        let y = match src {
            Src::Word(w) => self.w(w),
            Src::Double(d) => self.d(d),
            Src::Stack => self.stack[0],
        };
        match op {
            Math::Add => {
                let r = a.wrapping_add(y);
                self.sp[sp::SP66] = (a & 0xFFFF) + (y & 0xFFFF) > 0xFFFF;
                self.sp[sp::SP67] = u64::from(a) + u64::from(y) > u64::from(u32::MAX);
                self.sp[sp::SP73] = (a >> 31 == y >> 31) && (r >> 31 != a >> 31);
                self.acc = r;
            }
            Math::Sub => {
                self.sp[sp::SP64] = (a & 0xFFFF) < (y & 0xFFFF);
                self.sp[sp::SP65] = a < y;
                self.acc = a.wrapping_sub(y);
            }
            Math::Mul => {
                self.acc = if src == Src::Stack {
                    (a & 0xFFFF) * (y & 0xFFFF)
                } else {
                    a.wrapping_mul(y)
                };
            }
            Math::Div => {
                let divisor = if src == Src::Stack { y & 0xFFFF } else { y };
                if divisor == 0 {
                    self.divide_by_zero();
                    return;
                }
                self.acc = a / divisor;
                let r = a % divisor;
                if src == Src::Stack {
                    self.stack[0] = r;
                    self.moved = StackMove::Overwrite { value: r };
                } else {
                    self.push(r);
                }
                self.sp[sp::SP53] = false;
            }
        }
        if src == Src::Stack && matches!(op, Math::Add | Math::Sub | Math::Mul) {
            self.pop();
        }
        self.zn();
    }

    /// STR: a new level on the boolean stack (a rung's first clears it).
    #[inline(always)]
    fn contact_str(&mut self, t: Test) {
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
    fn contact_and(&mut self, t: Test) {
        let v = self.test(t);
        if let Some(top) = self.bstack.last_mut() {
            *top &= v;
        }
    }

    #[inline(always)]
    fn contact_or(&mut self, t: Test) {
        let v = self.test(t);
        if let Some(top) = self.bstack.last_mut() {
            *top |= v;
        }
    }

    /// ANDSTR (`and`) / ORSTR: the top two levels become one.
    #[inline(always)]
    fn join_top(&mut self, and: bool) {
        if self.bstack.len() >= 2 {
            let b = self.bstack.pop().unwrap_or(false);
            let a = self.bstack.pop().unwrap_or(false);
            self.bstack.push(if and { a && b } else { a || b });
        }
    }

    fn execute(&mut self) {
        let index = self.pc as usize;
        let op = self.program.instrs[index].op;
        self.before = (self.acc, self.stack[0]);
        self.moved = StackMove::None;
        let power = self.bstack.last().copied().unwrap_or(false);
        self.last_ran = true;
        match op {
            Op::Str(t) => self.contact_str(t),
            Op::And(t) => self.contact_and(t),
            Op::Or(t) => self.contact_or(t),
            Op::AndStr => self.join_top(true),
            Op::OrStr => self.join_top(false),
            Op::End | Op::Nop => {}
            Op::Coil(b) => {
                self.rung_has_output = true;
                self.set_bit(b, power);
            }
            _ if !power => {
                self.rung_has_output = true;
                self.last_ran = false;
            }
            _ => {
                self.rung_has_output = true;
                self.output(op);
            }
        }
        self.power[index] = Some(self.bstack.last().copied().unwrap_or(false));
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

    /// An output instruction on a powered rung.
    fn output(&mut self, op: Op) {
        match op {
            Op::Set(a, b) | Op::Rst(a, b) => {
                let on = matches!(op, Op::Set(..));
                for n in a.n..=b.n {
                    self.set_bit(Bit { kind: a.kind, n }, on);
                }
            }
            Op::Ld(w) => {
                let v = self.w(w);
                self.load(v);
            }
            Op::Ldd(d) => {
                let v = self.d(d);
                self.load(v);
            }
            Op::Lda(n) => self.load(n),
            Op::Ldf(e, n) => {
                let v = (0..u32::from(n)).fold(0u32, |acc, i| {
                    let b = Bit { kind: e.kind, n: e.n + i };
                    acc | (u32::from(self.bit(b)) << i)
                });
                self.load(v);
            }
            Op::OutV(a) => {
                self.v[a as usize] = self.acc as u16;
                self.load_pending = false;
            }
            Op::OutD(a) => {
                self.v[a as usize] = self.acc as u16;
                self.v[a as usize + 1] = (self.acc >> 16) as u16;
                self.load_pending = false;
            }
            Op::OutF(e, n) => {
                for i in 0..u32::from(n) {
                    self.set_bit(Bit { kind: e.kind, n: e.n + i }, self.acc >> i & 1 == 1);
                }
                self.load_pending = false;
            }
            Op::Pop => self.acc = self.pop(),
            Op::Bcd(m, s) => self.bcd_math(m, s),
            Op::Binary(m, s) => self.binary_math(m, s),
            Op::IncB(a) | Op::DecB(a) => {
                let v = &mut self.v[a as usize];
                *v = if matches!(op, Op::IncB(_)) {
                    v.wrapping_add(1)
                } else {
                    v.wrapping_sub(1)
                };
                self.sp[sp::SP63] = *v == 0;
            }
            Op::ToBin => match bcd_value(self.acc, 8) {
                Some(v) => {
                    self.acc = v as u32;
                    self.sp[sp::SP75] = false;
                    self.zn();
                }
                None => self.non_bcd(),
            },
            Op::ToBcd => {
                self.acc = to_bcd(u64::from(self.acc));
                self.zn();
            }
            Op::LogicV(l, a) => {
                let w = u32::from(self.v[a as usize]);
                self.acc = apply(l, self.acc & 0xFFFF, w);
                self.sp[sp::SP63] = self.acc == 0;
            }
            Op::LogicD(l, d) => {
                let v = self.d(d);
                self.acc = apply(l, self.acc, v);
                self.zn();
            }
            Op::LogicS(l) => {
                let v = self.stack[0];
                self.acc = apply(l, self.acc, v);
                self.pop();
                self.zn();
            }
            Op::Shift(kind, n) => {
                let n = self.w(n);
                self.acc = match kind {
                    ShiftKind::Shfl => self.acc.checked_shl(n).unwrap_or(0),
                    ShiftKind::Shfr => self.acc.checked_shr(n).unwrap_or(0),
                    ShiftKind::Rotl => self.acc.rotate_left(n % 32),
                    ShiftKind::Rotr => self.acc.rotate_right(n % 32),
                };
            }
            _ => {}
        }
    }

    fn scan_start(&mut self) {
        self.x_image.clone_from(&self.x);
        self.sp[sp::SP0] = self.tick == 0;
        self.sp[sp::SP1] = true;
        self.acc = 0;
        self.stack = [0; LEVELS];
        self.depth = 0;
        self.load_pending = false;
        self.bstack.clear();
        self.rung_has_output = false;
        self.power.iter_mut().for_each(|p| *p = None);
    }
}

impl crate::machine::ScanSteps for Dl205 {
    fn has_instructions(&self) -> bool {
        !self.program.instrs.is_empty()
    }
    fn start_scan(&mut self) {
        self.scan_start();
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

fn apply(l: Logic, a: u32, b: u32) -> u32 {
    match l {
        Logic::And => a & b,
        Logic::Or => a | b,
        Logic::Xor => a ^ b,
    }
}
