//! An assembled DL205 program (spec §1, §6).

/// Bit element kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    X,
    Y,
    C,
    Sp,
}

impl Kind {
    pub fn letter(self) -> &'static str {
        match self {
            Kind::X => "X",
            Kind::Y => "Y",
            Kind::C => "C",
            Kind::Sp => "SP",
        }
    }
    /// Elements 0..count (octal numbering: the index is the octal number's value).
    pub fn count(self) -> u32 {
        match self {
            Kind::X | Kind::Y => 0o2000,
            Kind::C => 0o4000,
            Kind::Sp => 0o1000,
        }
    }
}

/// The special relays modelled (spec §4), by octal number.
pub const SPECIAL: [u32; 11] = [0, 1, 0o53, 0o63, 0o64, 0o65, 0o66, 0o67, 0o70, 0o73, 0o75];

pub mod sp {
    pub const SP0: usize = 0;
    pub const SP1: usize = 1;
    pub const SP53: usize = 2;
    pub const SP63: usize = 3;
    pub const SP64: usize = 4;
    pub const SP65: usize = 5;
    pub const SP66: usize = 6;
    pub const SP67: usize = 7;
    pub const SP70: usize = 8;
    pub const SP73: usize = 9;
    pub const SP75: usize = 10;
}

/// A bit element: its kind and index (for SP: the index into [`SPECIAL`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Bit {
    pub kind: Kind,
    pub n: u32,
}

pub fn bit_name(b: Bit) -> String {
    match b.kind {
        Kind::Sp => format!("SP{:o}", SPECIAL[b.n as usize]),
        k => format!("{}{:o}", k.letter(), b.n),
    }
}

/// A 16-bit source: a V word or a K constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum W {
    V(u32),
    K(u16),
}

/// A 32-bit source: a V pair or a K constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum D {
    V(u32),
    K(u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cmp {
    Eq,
    Ne,
    Ge,
    Lt,
}

/// What a contact tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Test {
    Bit(Bit, bool),
    Compare(u32, W, Cmp),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Math {
    Add,
    Sub,
    Mul,
    Div,
}

/// The operand of a math instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Src {
    Word(W),
    Double(D),
    Stack,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Logic {
    And,
    Or,
    Xor,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShiftKind {
    Shfl,
    Shfr,
    Rotl,
    Rotr,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Str(Test),
    And(Test),
    Or(Test),
    AndStr,
    OrStr,
    Coil(Bit),
    Set(Bit, Bit),
    Rst(Bit, Bit),
    End,
    Nop,
    Ld(W),
    Ldd(D),
    Lda(u32),
    Ldf(Bit, u8),
    OutV(u32),
    OutD(u32),
    OutF(Bit, u8),
    Pop,
    Bcd(Math, Src),
    Binary(Math, Src),
    IncB(u32),
    DecB(u32),
    ToBin,
    ToBcd,
    LogicV(Logic, u32),
    LogicD(Logic, D),
    LogicS(Logic),
    Shift(ShiftKind, W),
}

impl Op {
    pub fn is_contact(&self) -> bool {
        matches!(self, Op::Str(_) | Op::And(_) | Op::Or(_) | Op::AndStr | Op::OrStr)
    }
    pub fn is_output(&self) -> bool {
        !self.is_contact() && !matches!(self, Op::End | Op::Nop)
    }
}

/// Where each rung starts (spec §2): a STR-family contact when there is no rung yet or the
/// current rung already has an output.
pub fn rung_starts(instrs: &[Instr]) -> Vec<usize> {
    let mut starts = Vec::new();
    let mut has_output = true;
    for (i, ins) in instrs.iter().enumerate() {
        if matches!(ins.op, Op::Str(_)) && has_output {
            starts.push(i);
            has_output = false;
        } else if ins.op.is_output() {
            has_output = true;
        }
    }
    starts
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Instr {
    pub op: Op,
    pub line: usize,
    pub text: String,
    pub mnemonic: String,
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Program {
    pub instrs: Vec<Instr>,
    pub used_v: Vec<u32>,
    pub used_bits: Vec<Bit>,
    /// The fast loop's form of `instrs` ([`super::fast`]).
    pub flat: Vec<super::fast::Flat>,
    /// Every location a scan may write.
    pub scan_writes: crate::machine::WriteSet,
}
