//! The accumulator and its 8-level stack: loads and outputs, BCD and binary math, the
//! tables of MOV/SETBIT/RSTBIT, comparisons, and the SP flags they set.

use super::program::{self, Bit, Kind, Math, Op, ShiftKind, Src, sp};
use super::{Dl205, LEVELS, StackMove, V_WORDS, bcd_value, to_bcd};

impl Dl205 {
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

    pub(super) fn load(&mut self, v: u32) {
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

    pub(super) fn non_bcd(&mut self) {
        self.raised_error = true;
        self.sp[sp::SP75] = true;
        self.sp75_line = Some(self.line());
    }

    fn divide_by_zero(&mut self) {
        self.raised_error = true;
        self.sp[sp::SP53] = true;
        self.sp53_line = Some(self.line());
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
                    self.sp[sp::SP66] = if is_double {
                        lx + ly >= 10_000
                    } else {
                        s >= 10_000
                    };
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

    /// An output instruction on a powered rung.
    pub(super) fn output(&mut self, op: Op) {
        match op {
            Op::Rst(a, b) if matches!(a.kind, Kind::T | Kind::Ct) => {
                for n in a.n..=b.n {
                    self.reset_box(Bit { kind: a.kind, n });
                }
            }
            Op::Set(a, b) | Op::Rst(a, b) => {
                let on = matches!(op, Op::Set(..));
                for n in a.n..=b.n {
                    self.set_bit(Bit { kind: a.kind, n }, on);
                }
            }
            Op::Table(kind, operand) => self.table(kind, operand),
            Op::Inv => {
                self.acc = !self.acc;
                self.zn();
            }
            Op::Cmp(w) => {
                let w = self.w(w);
                self.compare(self.acc & 0xFFFF, w);
            }
            Op::CmpD(d) => {
                let d = self.d(d);
                self.compare(self.acc, d);
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
                    let b = Bit {
                        kind: e.kind,
                        n: e.n + i,
                    };
                    acc | (u32::from(self.bit(b)) << i)
                });
                self.load(v);
            }
            Op::OutV(a) => {
                self.set_word(a, self.acc as u16);
                self.load_pending = false;
            }
            Op::OutD(a) => {
                self.set_word(a, self.acc as u16);
                self.set_word(a + 1, (self.acc >> 16) as u16);
                self.load_pending = false;
            }
            Op::OutF(e, n) => {
                for i in 0..u32::from(n) {
                    self.set_bit(
                        Bit {
                            kind: e.kind,
                            n: e.n + i,
                        },
                        self.acc >> i & 1 == 1,
                    );
                }
                self.load_pending = false;
            }
            Op::Pop => self.acc = self.pop(),
            Op::Bcd(m, s) => self.bcd_math(m, s),
            Op::Binary(m, s) => self.binary_math(m, s),
            Op::IncB(a) | Op::DecB(a) => {
                let was = self.word(a);
                let now = if matches!(op, Op::IncB(_)) {
                    was.wrapping_add(1)
                } else {
                    was.wrapping_sub(1)
                };
                self.set_word(a, now);
                self.sp[sp::SP63] = now == 0;
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
                let w = u32::from(self.word(a));
                self.acc = l.apply(self.acc & 0xFFFF, w);
                self.sp[sp::SP63] = self.acc == 0;
            }
            Op::LogicD(l, d) => {
                let v = self.d(d);
                self.acc = l.apply(self.acc, v);
                self.zn();
            }
            Op::LogicS(l) => {
                let v = self.stack[0];
                self.acc = l.apply(self.acc, v);
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

    /// The table of MOV/SETBIT/RSTBIT: its start (low word of ACC) and BCD count (L1), or
    /// None for a non-BCD count.
    pub(in crate::machine) fn table_span(&self) -> Option<(u32, u32)> {
        let count = bcd_value(self.stack[0] & 0xFFFF, 4)?;
        Some((self.acc & 0xFFFF, count as u32))
    }

    /// MOV, SETBIT, RSTBIT (spec §6.6, §9.25): ACC and the stack stay as they are.
    fn table(&mut self, kind: program::Table, operand: u32) {
        let Some((start, count)) = self.table_span() else {
            self.non_bcd();
            return;
        };
        let last = V_WORDS as u32 - 1;
        match kind {
            program::Table::Mov => {
                if count > 0 && (start + count - 1 > last || operand + count - 1 > last) {
                    self.out_of_range();
                    return;
                }
                for i in 0..count {
                    let w = self.word(start + i);
                    self.set_word(operand + i, w);
                }
            }
            program::Table::SetBit | program::Table::RstBit => {
                let word = start + operand / 16;
                if operand >= 16 * count || word > last {
                    self.out_of_range();
                    return;
                }
                let bit = 1u16 << (operand % 16);
                let w = self.word(word);
                let w = if kind == program::Table::SetBit {
                    w | bit
                } else {
                    w & !bit
                };
                self.set_word(word, w);
            }
        }
        self.sp[sp::SP53] = false;
        self.sp[sp::SP75] = false;
    }

    /// A table past V37777: SP53 = 1, SP75 = 0, nothing else (spec §6.6).
    fn out_of_range(&mut self) {
        self.divide_by_zero();
        self.sp[sp::SP75] = false;
    }

    /// CMP/CMPD: SP60 less, SP61 equal, SP62 greater (unsigned).
    fn compare(&mut self, a: u32, b: u32) {
        self.sp[sp::SP60] = a < b;
        self.sp[sp::SP61] = a == b;
        self.sp[sp::SP62] = a > b;
    }
}
