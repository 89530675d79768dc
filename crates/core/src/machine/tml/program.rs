//! An assembled TML program: statements with their operands resolved (spec §5).

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Ty {
    Int,
    /// Predefined 16-bit registers shown unsigned (SRL, MER, …); read signed by instructions.
    Uint,
    Long,
    Fixed,
}

impl Ty {
    pub fn bits(self) -> u8 {
        match self {
            Ty::Int | Ty::Uint => 16,
            Ty::Long | Ty::Fixed => 32,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Ty::Int => "int",
            Ty::Uint => "uint",
            Ty::Long => "long",
            Ty::Fixed => "fixed",
        }
    }
}

/// Where a datum lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Data {
    /// Index into [`super::PREDEFINED`].
    Pre(u8),
    /// Index into the program's variables.
    Var(u16),
}

/// A readable (or writable) operand: a datum, or the high/low half of a 32-bit one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Operand {
    pub data: Data,
    /// `Some(true)` for `X(H)`, `Some(false)` for `X(L)`.
    pub half: Option<bool>,
    /// The datum's type (a half is an `Int`).
    pub ty: Ty,
}

impl Operand {
    pub fn bits(&self) -> u8 {
        if self.half.is_some() {
            16
        } else {
            self.ty.bits()
        }
    }
    pub fn is_fixed(&self) -> bool {
        self.half.is_none() && self.ty == Ty::Fixed
    }
}

/// An operand or an immediate already reduced to what the statement uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Value {
    Imm(i64),
    Var(Operand),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cond {
    Eq,
    Neq,
    Lt,
    Leq,
    Gt,
    Geq,
}

impl Cond {
    pub fn parse(word: &str) -> Option<Cond> {
        Some(match word.to_ascii_uppercase().as_str() {
            "EQ" => Cond::Eq,
            "NEQ" => Cond::Neq,
            "LT" => Cond::Lt,
            "LEQ" => Cond::Leq,
            "GT" => Cond::Gt,
            "GEQ" => Cond::Geq,
            _ => return None,
        })
    }
    pub fn holds(self, v: i64) -> bool {
        match self {
            Cond::Eq => v == 0,
            Cond::Neq => v != 0,
            Cond::Lt => v < 0,
            Cond::Leq => v <= 0,
            Cond::Gt => v > 0,
            Cond::Geq => v >= 0,
        }
    }
    pub fn symbol(self) -> &'static str {
        match self {
            Cond::Eq => "= 0",
            Cond::Neq => "≠ 0",
            Cond::Lt => "< 0",
            Cond::Leq => "≤ 0",
            Cond::Gt => "> 0",
            Cond::Geq => "≥ 0",
        }
    }
}

/// How `+=`/`-=` reads its right operand (spec §5.2), decided at assembly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AddKind {
    /// The value as read (16-bit wrap for a 16-bit left side, raw bits for 32-bit data).
    Plain,
    /// A 16-bit datum into a fixed: its value × 65536 (the integer part).
    IntegerPart,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventSpec {
    MotionComplete,
    Time(Value),
    Input(u8, bool),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Assign(Operand, Value),
    Negate(Operand, Operand),
    AssignShift {
        dst: Operand,
        src: Operand,
        left: bool,
        n: u8,
    },
    Add {
        dst: Operand,
        src: Value,
        kind: AddKind,
        subtract: bool,
    },
    Multiply {
        a: Operand,
        b: Value,
        left: bool,
        n: u8,
    },
    Divide(Operand, Operand),
    Shift {
        dst: Operand,
        left: bool,
        n: u8,
    },
    ShiftProduct {
        left: bool,
        n: u8,
    },
    Srb {
        dst: Operand,
        and: u16,
        or: u16,
    },
    Jump {
        target: u32,
        call: bool,
        cond: Option<(Operand, Cond)>,
    },
    /// `GOTO V16;` / `CALL V16, X, C;`: to the program address the variable holds (§5.7).
    JumpVia {
        via: Operand,
        call: bool,
        cond: Option<(Operand, Cond)>,
    },
    Ret,
    End,
    ModePp,
    Relative(bool),
    Tum(bool),
    Upd,
    Stop,
    Sap(Value),
    Axis(bool),
    Nop,
    SetEvent(EventSpec),
    Wait(Option<u16>),
}

/// One statement and where it is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stmt {
    pub op: Op,
    pub line: usize,
    pub col: usize,
    /// The statement's text, for explanations.
    pub text: String,
    /// Its size in program memory, in 16-bit words (spec §5.11).
    pub words: u8,
}

/// A user variable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Var {
    pub name: String,
    pub ty: Ty,
    pub line: usize,
}

/// A user variable as the fast loop reads it: `((raw << shift) as i32 >> shift)` is the signed
/// value of a 16-bit variable (`shift` 16) or a 32-bit one (`shift` 0), and a store keeps the
/// low `32 − shift` bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Slot {
    pub var: u16,
    pub shift: u8,
}

impl Slot {
    /// A whole user variable (not a half, not predefined data).
    fn of(op: &Operand) -> Option<Slot> {
        match (op.data, op.half) {
            (Data::Var(var), None) => Some(Slot {
                var,
                shift: 32 - op.ty.bits(),
            }),
            _ => None,
        }
    }
}

/// A statement as the fast loop dispatches on it: one match, operands resolved to user
/// variables and immediates. Everything that touches predefined data, halves, the product
/// register's halves (but `v = PROD`/`PRODH`), the stack (it can overflow), motion, events,
/// waits or the end is [`Flat::Full`] and runs through the full executor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flat {
    SetImm {
        dst: Slot,
        v: i64,
    },
    Copy {
        dst: Slot,
        src: Slot,
    },
    /// `dst ± delta` (`delta` already scaled for an integer part).
    AddImm {
        dst: Slot,
        delta: i64,
        subtract: bool,
    },
    Add {
        dst: Slot,
        src: Slot,
        scale: i64,
        subtract: bool,
    },
    Shift {
        dst: Slot,
        left: bool,
        n: u8,
    },
    /// `dst = PROD` (`high` false) or `dst = PRODH`.
    CopyProduct {
        dst: Slot,
        high: bool,
    },
    /// `dst /= divisor`; `fixed` when `dst` is a fixed (no scaling of the dividend).
    Div {
        dst: Slot,
        divisor: Slot,
        fixed: bool,
    },
    MulImm {
        a: Slot,
        b: i64,
        left: bool,
        n: u8,
    },
    Mul {
        a: Slot,
        b: Slot,
        left: bool,
        n: u8,
    },
    /// `dst = -src`.
    Negate {
        dst: Slot,
        src: Slot,
    },
    /// `dst = src << n` or `src >> n`.
    AssignShift {
        dst: Slot,
        src: Slot,
        left: bool,
        n: u8,
    },
    /// The product register shifted in place.
    ShiftProduct {
        left: bool,
        n: u8,
    },
    /// `SRB dst, and, or`.
    Srb {
        dst: Slot,
        and: u16,
        or: u16,
    },
    /// `NOP`, `BEGIN`, `ENDINIT`.
    Nop,
    Goto {
        target: u32,
    },
    GotoIf {
        target: u32,
        x: Slot,
        cond: Cond,
    },
    Full,
}

/// The fast loop's form of `stmts`, one [`Flat`] each: a jump to or past the end, and the last
/// statement unless it jumps, are `Full` (the full executor ends the program).
pub fn flatten(stmts: &[Stmt]) -> Vec<Flat> {
    let len = stmts.len() as u32;
    stmts
        .iter()
        .enumerate()
        .map(|(i, stmt)| {
            let flat = flat_stmt(&stmt.op, len);
            let last = i + 1 == stmts.len();
            if last && !matches!(flat, Flat::Goto { .. } | Flat::GotoIf { .. }) {
                Flat::Full
            } else {
                flat
            }
        })
        .collect()
}

fn flat_stmt(op: &Op, len: u32) -> Flat {
    let full = || Flat::Full;
    match *op {
        Op::Assign(dst, Value::Imm(v)) => {
            Slot::of(&dst).map_or_else(full, |dst| Flat::SetImm { dst, v })
        }
        Op::Assign(dst, Value::Var(src)) => match (Slot::of(&dst), Slot::of(&src), src.data) {
            (Some(dst), Some(src), _) => Flat::Copy { dst, src },
            (Some(dst), None, Data::Pre(p))
                if src.half.is_none()
                    && src.ty.bits() == 32
                    && (p == super::d::PROD || p == super::d::PRODH) =>
            {
                Flat::CopyProduct {
                    dst,
                    high: p == super::d::PRODH,
                }
            }
            _ => Flat::Full,
        },
        Op::Divide(dst, divisor) => match (Slot::of(&dst), Slot::of(&divisor)) {
            (Some(slot), Some(divisor)) => Flat::Div {
                dst: slot,
                divisor,
                fixed: dst.is_fixed(),
            },
            _ => Flat::Full,
        },
        Op::Add {
            dst,
            src,
            kind,
            subtract,
        } => {
            let scale = if kind == AddKind::IntegerPart {
                65536
            } else {
                1
            };
            match (Slot::of(&dst), src) {
                (Some(dst), Value::Imm(v)) => {
                    v.checked_mul(scale)
                        .map_or(Flat::Full, |delta| Flat::AddImm {
                            dst,
                            delta,
                            subtract,
                        })
                }
                (Some(dst), Value::Var(src)) => {
                    Slot::of(&src).map_or(Flat::Full, |src| Flat::Add {
                        dst,
                        src,
                        scale,
                        subtract,
                    })
                }
                _ => Flat::Full,
            }
        }
        Op::Shift { dst, left, n } if n < 64 => {
            Slot::of(&dst).map_or_else(full, |dst| Flat::Shift { dst, left, n })
        }
        Op::Multiply { a, b, left, n } if n < 64 => match (Slot::of(&a), b) {
            (Some(a), Value::Imm(b)) => Flat::MulImm { a, b, left, n },
            (Some(a), Value::Var(b)) => {
                Slot::of(&b).map_or(Flat::Full, |b| Flat::Mul { a, b, left, n })
            }
            _ => Flat::Full,
        },
        Op::Negate(dst, src) => match (Slot::of(&dst), Slot::of(&src)) {
            (Some(dst), Some(src)) => Flat::Negate { dst, src },
            _ => Flat::Full,
        },
        Op::AssignShift { dst, src, left, n } if n < 64 => match (Slot::of(&dst), Slot::of(&src)) {
            (Some(dst), Some(src)) => Flat::AssignShift { dst, src, left, n },
            _ => Flat::Full,
        },
        Op::ShiftProduct { left, n } if n < 64 => Flat::ShiftProduct { left, n },
        Op::Srb { dst, and, or } => {
            Slot::of(&dst).map_or_else(full, |dst| Flat::Srb { dst, and, or })
        }
        Op::Nop => Flat::Nop,
        Op::Jump {
            target,
            call: false,
            cond,
        } if target < len => match cond {
            None => Flat::Goto { target },
            Some((x, cond)) => {
                Slot::of(&x).map_or(Flat::Full, |x| Flat::GotoIf { target, x, cond })
            }
        },
        _ => Flat::Full,
    }
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Program {
    /// `stmts` pre-decoded for the fast loop.
    pub flat: Vec<Flat>,
    /// Every location a statement of `flat` other than `Full` may write.
    pub flat_writes: crate::machine::WriteSet,
    pub stmts: Vec<Stmt>,
    pub vars: Vec<Var>,
    pub labels: Vec<(String, u32)>,
    /// The names of the program's files when it has several (positions then name their file:
    /// line `l` is in `files[l / FILE_LINES]`); empty for one file.
    pub files: Vec<String>,
    /// The line of each label of `labels`, in the same order.
    pub label_lines: Vec<usize>,
    /// Each statement's program-memory address (spec §5.11), and the end address after them.
    pub addresses: Vec<u32>,
    pub end_address: u32,
    /// Predefined data the text mentions (indices into [`super::PREDEFINED`]).
    pub used: Vec<u8>,
    pub uses_preg: bool,
    /// Inputs the text mentions.
    pub used_inputs: Vec<u8>,
}

/// Where user variables start in the drive's data memory (spec §2.4).
pub const VARIABLES_BASE: u32 = 0x03B0;

impl Program {
    /// Each user variable's data address (spec §2.4): from 0x03B0 in declaration order, an
    /// int one word, a long or fixed two at an even address.
    pub fn var_addresses(&self) -> Vec<u32> {
        let mut next = VARIABLES_BASE;
        self.vars
            .iter()
            .map(|v| {
                if v.ty.bits() == 32 {
                    next += next % 2;
                }
                let at = next;
                next += u32::from(v.ty.bits() / 16);
                at
            })
            .collect()
    }

    /// The program-memory address of statement `index`, or the end address past the last.
    pub fn address_of(&self, index: usize) -> u32 {
        self.addresses
            .get(index)
            .copied()
            .unwrap_or(self.end_address)
    }

    /// The statement that starts at `address`, or `len` for the end address; `None` where no
    /// statement starts (a jump there is a `bad_address`).
    pub fn statement_at(&self, address: u32) -> Option<usize> {
        if address == self.end_address {
            return Some(self.stmts.len());
        }
        self.addresses.binary_search(&address).ok()
    }
}
