//! An assembled OpenNet program (spec §1, §4, §5).

/// The data types of advanced instructions (spec §4.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Ty {
    W,
    I,
    D,
    L,
}

impl Ty {
    pub fn parse(c: &str) -> Option<Ty> {
        Some(match c.to_ascii_uppercase().as_str() {
            "W" => Ty::W,
            "I" => Ty::I,
            "D" => Ty::D,
            "L" => Ty::L,
            _ => return None,
        })
    }
    pub fn words(self) -> u32 {
        match self {
            Ty::W | Ty::I => 1,
            Ty::D | Ty::L => 2,
        }
    }
    pub fn bits(self) -> u32 {
        self.words() * 16
    }
    pub fn signed(self) -> bool {
        matches!(self, Ty::I | Ty::L)
    }
    pub fn letter(self) -> char {
        match self {
            Ty::W => 'W',
            Ty::I => 'I',
            Ty::D => 'D',
            Ty::L => 'L',
        }
    }
    /// The pattern as a number of this type.
    pub fn value(self, pattern: u32) -> i64 {
        match self {
            Ty::W => i64::from(pattern as u16),
            Ty::I => i64::from(pattern as u16 as i16),
            Ty::D => i64::from(pattern),
            Ty::L => i64::from(pattern as i32),
        }
    }
    pub fn min(self) -> i64 {
        match self {
            Ty::W | Ty::D => 0,
            Ty::I => -32768,
            Ty::L => i64::from(i32::MIN),
        }
    }
    pub fn max(self) -> i64 {
        match self {
            Ty::W => 65535,
            Ty::I => 32767,
            Ty::D => i64::from(u32::MAX),
            Ty::L => i64::from(i32::MAX),
        }
    }
}

/// Bit areas (IDEC numbering: the last digit is octal).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Area {
    I,
    Q,
    M,
}

impl Area {
    pub fn points(self) -> u32 {
        match self {
            Area::I | Area::Q => 480,
            Area::M => 2048,
        }
    }
    pub fn letter(self) -> char {
        match self {
            Area::I => 'I',
            Area::Q => 'Q',
            Area::M => 'M',
        }
    }
}

/// IDEC's name of point `index` of an area: I0–I7, I10–I17, …
pub fn point_name(area: Area, index: u32) -> String {
    format!("{}{}", area.letter(), index / 8 * 10 + index % 8)
}

/// The special relays modelled (spec §2).
pub const SPECIAL: [u16; 5] = [8003, 8004, 8120, 8121, 8122];

/// A bit operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Bit {
    Point(Area, u32),
    /// Index into [`SPECIAL`].
    Special(u8),
}

/// A word operand of an advanced instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Word {
    Const(u32),
    Reg { n: u32, repeat: bool },
    Bits { area: Area, index: u32, repeat: bool },
}

impl Word {
    pub fn repeats(&self) -> bool {
        match self {
            Word::Const(_) => false,
            Word::Reg { repeat, .. } | Word::Bits { repeat, .. } => *repeat,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arith {
    Add,
    Sub,
    Mul,
    Div,
}

impl Arith {
    pub fn name(self) -> &'static str {
        match self {
            Arith::Add => "ADD",
            Arith::Sub => "SUB",
            Arith::Mul => "MUL",
            Arith::Div => "DIV",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Lod(Bit, bool),
    And(Bit, bool),
    Or(Bit, bool),
    AndLod,
    OrLod,
    Bps,
    Brd,
    Bpp,
    /// Edge memory index.
    Sotu(u32),
    Sotd(u32),
    Out(Bit, bool),
    Set(Bit),
    Rst(Bit),
    End,
    Mov {
        ty: Ty,
        src: Word,
        dst: Word,
        rep: u8,
    },
    Arith {
        op: Arith,
        ty: Ty,
        a: Word,
        b: Word,
        dst: Word,
        rep: u8,
    },
    /// INC (true) or DEC (false) of a register (W) or pair (D).
    Step {
        up: bool,
        ty: Ty,
        reg: u32,
    },
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Instr {
    pub op: Op,
    pub line: usize,
    pub text: String,
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Program {
    pub instrs: Vec<Instr>,
    /// Number of SOTU/SOTD edge memories.
    pub edges: u32,
    pub used_regs: Vec<u32>,
    /// Registers the program reads as signed (data type I, or the upper word of an L pair):
    /// the register view shows them signed, the others unsigned (spec §3).
    pub signed_regs: Vec<u32>,
    pub used_bits: Vec<(Area, u32)>,
    /// The fast loop's form of `instrs` ([`super::fast`]).
    pub flat: Vec<super::fast::Flat>,
    /// Every location a scan may write.
    pub scan_writes: crate::machine::WriteSet,
}
