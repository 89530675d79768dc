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
        if self.half.is_some() { 16 } else { self.ty.bits() }
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
}

/// A user variable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Var {
    pub name: String,
    pub ty: Ty,
    pub line: usize,
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Program {
    pub stmts: Vec<Stmt>,
    pub vars: Vec<Var>,
    pub labels: Vec<(String, u32)>,
    /// Predefined data the text mentions (indices into [`super::PREDEFINED`]).
    pub used: Vec<u8>,
    pub uses_preg: bool,
    /// Inputs the text mentions.
    pub used_inputs: Vec<u8>,
}
