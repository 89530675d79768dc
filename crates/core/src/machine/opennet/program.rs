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

/// Bit areas: I, Q and M in IDEC numbering (the last digit is octal), R decimal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Area {
    I,
    Q,
    M,
    /// Shift-register bits R0–R255.
    R,
}

impl Area {
    pub fn points(self) -> u32 {
        match self {
            Area::I | Area::Q => 480,
            Area::M => 2048,
            Area::R => 256,
        }
    }
    pub fn letter(self) -> char {
        match self {
            Area::I => 'I',
            Area::Q => 'Q',
            Area::M => 'M',
            Area::R => 'R',
        }
    }
    /// Whether the last digit of a point's number is octal.
    pub fn octal(self) -> bool {
        self != Area::R
    }
}

/// IDEC's name of point `index` of an area: I0–I7, I10–I17, …; R0–R255.
pub fn point_name(area: Area, index: u32) -> String {
    if area.octal() {
        format!("{}{}", area.letter(), index / 8 * 10 + index % 8)
    } else {
        format!("{}{index}", area.letter())
    }
}

/// The special relays modelled (spec §2).
pub const SPECIAL: [u16; 7] = [8003, 8004, 8120, 8121, 8122, 8123, 8125];
/// Timers T0–T255 and counters C0–C255.
pub const BOXES: u32 = 256;

/// A bit operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Bit {
    Point(Area, u32),
    /// Index into [`SPECIAL`].
    Special(u8),
    /// A timer's or counter's output.
    Timer(u32),
    Counter(u32),
}

/// A word operand of an advanced instruction. A timer or counter word reads its current value
/// and takes a write as its preset (spec §4.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Word {
    Const(u32),
    Reg {
        n: u32,
        repeat: bool,
    },
    Bits {
        area: Area,
        index: u32,
        repeat: bool,
    },
    Timer {
        n: u32,
        repeat: bool,
    },
    Counter {
        n: u32,
        repeat: bool,
    },
}

impl Word {
    pub fn repeats(&self) -> bool {
        match self {
            Word::Const(_) => false,
            Word::Reg { repeat, .. }
            | Word::Bits { repeat, .. }
            | Word::Timer { repeat, .. }
            | Word::Counter { repeat, .. } => *repeat,
        }
    }
}

/// A preset or compared value: a constant or a data register read when used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Value {
    Const(u16),
    Reg(u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimerKind {
    Tml,
    Tim,
    Tmh,
    Tms,
}

impl TimerKind {
    pub fn increment_ms(self) -> u32 {
        match self {
            TimerKind::Tml => 1000,
            TimerKind::Tim => 100,
            TimerKind::Tmh => 10,
            TimerKind::Tms => 1,
        }
    }
    pub fn mnemonic(self) -> &'static str {
        match self {
            TimerKind::Tml => "TML",
            TimerKind::Tim => "TIM",
            TimerKind::Tmh => "TMH",
            TimerKind::Tms => "TMS",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CounterKind {
    /// Adding counter: reset, pulse.
    Cnt,
    /// Dual-pulse reversible counter: preset input, up pulse, down pulse.
    Cdp,
    /// Up/down selection reversible counter: preset input, pulse, up/down selection.
    Cud,
}

impl CounterKind {
    pub fn mnemonic(self) -> &'static str {
        match self {
            CounterKind::Cnt => "CNT",
            CounterKind::Cdp => "CDP",
            CounterKind::Cud => "CUD",
        }
    }
    /// Its inputs, one LOD block each.
    pub fn inputs(self) -> u32 {
        match self {
            CounterKind::Cnt => 2,
            CounterKind::Cdp | CounterKind::Cud => 3,
        }
    }
}

/// The relation of a CMP instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rel {
    Eq,
    Ne,
    Lt,
    Gt,
    Le,
    Ge,
    /// ICMP>=: a ≥ b ≥ c.
    Between,
}

impl Rel {
    pub fn holds(self, a: i64, b: i64, c: i64) -> bool {
        match self {
            Rel::Eq => a == b,
            Rel::Ne => a != b,
            Rel::Lt => a < b,
            Rel::Gt => a > b,
            Rel::Le => a <= b,
            Rel::Ge => a >= b,
            Rel::Between => a >= b && b >= c,
        }
    }
    pub fn symbol(self) -> &'static str {
        match self {
            Rel::Eq => "=",
            Rel::Ne => "≠",
            Rel::Lt => "<",
            Rel::Gt => ">",
            Rel::Le => "≤",
            Rel::Ge | Rel::Between => "≥",
        }
    }
}

pub use crate::machine::plc::Logic;

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
    /// CC=/CC>= (counter current value) or DC=/DC>= (data register): a contact that starts a
    /// block like LOD.
    Compare {
        counter: bool,
        n: u32,
        value: Value,
        at_least: bool,
    },
    Timer {
        kind: TimerKind,
        n: u32,
        preset: Value,
    },
    /// `pulses`: the first of this counter's pulse memories (two for CDP, else one).
    Counter {
        kind: CounterKind,
        n: u32,
        preset: Value,
        pulses: u32,
    },
    /// SFR (up) or SFRN (down) over R`first` … R`first+len-1`.
    ShiftRegister {
        down: bool,
        first: u32,
        len: u32,
        pulses: u32,
    },
    /// CMP…/ICMP>=: one bit of `dst` per REP cycle (the next point each cycle when `dst_repeat`).
    WordCompare {
        rel: Rel,
        ty: Ty,
        a: Word,
        b: Word,
        c: Word,
        dst: (Area, u32),
        dst_repeat: bool,
        rep: u8,
    },
    WordLogic {
        op: Logic,
        ty: Ty,
        a: Word,
        b: Word,
        dst: Word,
        rep: u8,
    },
    /// SFTL (left) / SFTR by `by` bits, in place.
    Shift {
        left: bool,
        ty: Ty,
        word: Word,
        by: u8,
    },
    /// HTOB (to BCD) / BTOH (from BCD).
    Convert {
        to_bcd: bool,
        ty: Ty,
        src: Word,
        dst: Word,
        rep: u8,
    },
    /// The index of the MCR that closes its area.
    Mcs(u32),
    Mcr,
    /// The index of the JEND it continues at.
    Jmp(u32),
    Jend,
    Nop,
}

impl Op {
    /// An output instruction (spec §5.1): it takes RLO AND MC as its input and does not change
    /// RLO; the next LOD starts a rung.
    pub fn is_output(&self) -> bool {
        !matches!(
            self,
            Op::Lod(..)
                | Op::And(..)
                | Op::Or(..)
                | Op::AndLod
                | Op::OrLod
                | Op::Bps
                | Op::Brd
                | Op::Bpp
                | Op::Sotu(_)
                | Op::Sotd(_)
                | Op::Compare { .. }
                | Op::End
                | Op::Mcr
                | Op::Jend
                | Op::Nop
        )
    }
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
    /// Number of counter and shift-register pulse memories.
    pub pulses: u32,
    /// Whether each instruction's LOD (or compare contact) starts a rung: the stacks empty.
    pub opens: Vec<bool>,
    /// Whether the program has an MCS or a JMP, which mark the code they switch off.
    pub marks_code: bool,
    /// Timers and counters the program names anywhere, ascending.
    pub used_timers: Vec<u32>,
    pub used_counters: Vec<u32>,
    /// The start presets (spec §2): the constant of each timer / counter instruction.
    pub timer_presets: Vec<(u32, u16)>,
    pub counter_presets: Vec<(u32, u16)>,
    /// MICRO3 warnings (spec §1): they never stop a program.
    pub warnings: Vec<crate::machine::Diagnostic>,
    pub used_regs: Vec<u32>,
    /// Registers the program reads as signed (data type I, or the upper word of an L pair):
    /// the register view shows them signed, the others unsigned (spec §3).
    pub signed_regs: Vec<u32>,
    pub used_bits: Vec<(Area, u32)>,
    /// The fast loop's form of `instrs` ([`super::fast`]).
    pub flat: Vec<super::fast::Flat>,
    /// Every location a scan may write.
    pub scan_writes: crate::machine::WriteSet,
    /// The program as a ladder diagram, wired but not laid out.
    pub ladder: std::sync::Arc<crate::machine::plc::ladder::Ladder>,
    /// The same laid out, once something draws it (a long rung costs nothing until then).
    pub diagram: crate::machine::plc::ladder::LaidOut,
}
