//! An assembled DL205 program (spec §1, §6).

/// Bit element kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    X,
    Y,
    C,
    Sp,
    /// Stage bits.
    S,
    /// Timer status bits.
    T,
    /// Counter status bits.
    Ct,
}

impl Kind {
    pub fn letter(self) -> &'static str {
        match self {
            Kind::X => "X",
            Kind::Y => "Y",
            Kind::C => "C",
            Kind::Sp => "SP",
            Kind::S => "S",
            Kind::T => "T",
            Kind::Ct => "CT",
        }
    }
    /// Elements 0..count (octal numbering: the index is the octal number's value).
    pub fn count(self) -> u32 {
        match self {
            Kind::X | Kind::Y | Kind::S => 0o2000,
            Kind::C => 0o4000,
            Kind::Sp => 0o1000,
            Kind::T | Kind::Ct => 0o400,
        }
    }
}

/// The special relays modelled (spec §4), by octal number, ascending: a range of them (LDF
/// SP0 K8) is a range of indices.
pub const SPECIAL: [u32; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 0o53, 0o60, 0o61, 0o62, 0o63, 0o64, 0o65, 0o66, 0o67, 0o70, 0o73, 0o75,
];

pub mod sp {
    pub const SP0: usize = 0;
    pub const SP1: usize = 1;
    pub const SP2: usize = 2;
    pub const SP3: usize = 3;
    pub const SP4: usize = 4;
    pub const SP5: usize = 5;
    pub const SP6: usize = 6;
    pub const SP7: usize = 7;
    pub const SP53: usize = 8;
    pub const SP60: usize = 9;
    pub const SP61: usize = 10;
    pub const SP62: usize = 11;
    pub const SP63: usize = 12;
    pub const SP64: usize = 13;
    pub const SP65: usize = 14;
    pub const SP66: usize = 15;
    pub const SP67: usize = 16;
    pub const SP70: usize = 17;
    pub const SP73: usize = 18;
    pub const SP75: usize = 19;
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
    /// An edge contact (STRPD: rising, STRND: falling) with the index of its edge memory.
    Edge(Bit, Edge, u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    Rising,
    Falling,
}

/// A preset or other box operand: a K constant, a V word, or a V pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    K(u32),
    Word(u32),
    Pair(u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Table {
    /// Copy the table to the one at this V address.
    Mov,
    /// Set / clear bit n (the operand) of the table.
    SetBit,
    RstBit,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimerKind {
    Tmr,
    Tmrf,
    Tmra,
    Tmraf,
}

impl TimerKind {
    pub fn unit_ms(self) -> u32 {
        match self {
            TimerKind::Tmr | TimerKind::Tmra => 100,
            TimerKind::Tmrf | TimerKind::Tmraf => 10,
        }
    }
    /// TMRA/TMRAF: an enable and a reset leg, two words, kept while disabled.
    pub fn accumulating(self) -> bool {
        matches!(self, TimerKind::Tmra | TimerKind::Tmraf)
    }
    pub fn mnemonic(self) -> &'static str {
        match self {
            TimerKind::Tmr => "TMR",
            TimerKind::Tmrf => "TMRF",
            TimerKind::Tmra => "TMRA",
            TimerKind::Tmraf => "TMRAF",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CounterKind {
    /// Count and reset legs.
    Cnt,
    /// Stage counter: one count leg, cleared only by RST.
    Sgcnt,
    /// Up, down and reset legs; two words.
    Udc,
}

impl CounterKind {
    pub fn mnemonic(self) -> &'static str {
        match self {
            CounterKind::Cnt => "CNT",
            CounterKind::Sgcnt => "SGCNT",
            CounterKind::Udc => "UDC",
        }
    }
}

/// Words a box's current value takes (1, or 2 for TMRA/TMRAF/UDC) and the legs it reads.
pub fn box_shape(op: &Op) -> Option<(u32, usize)> {
    match op {
        Op::Timer(k, ..) if k.accumulating() => Some((2, 2)),
        Op::Timer(..) => Some((1, 1)),
        Op::Counter(CounterKind::Cnt, ..) => Some((1, 2)),
        Op::Counter(CounterKind::Sgcnt, ..) => Some((1, 1)),
        Op::Counter(CounterKind::Udc, ..) => Some((2, 3)),
        _ => None,
    }
}

/// The bit-mapped words (spec §1, DL260 memory map): each region's first V address, the
/// element kind, and the name DirectSOFT gives its words.
pub const MAPPED: [(u32, u32, Kind, &str); 7] = [
    (0o40400, 0o40477, Kind::X, "VX"),
    (0o40500, 0o40577, Kind::Y, "VY"),
    (0o40600, 0o40777, Kind::C, "VC"),
    (0o41000, 0o41077, Kind::S, "VS"),
    (0o41100, 0o41117, Kind::T, "VT"),
    (0o41140, 0o41157, Kind::Ct, "VCT"),
    (0o41200, 0o41237, Kind::Sp, "VSP"),
];

/// The last V address that exists (VSP's last word).
pub const LAST_MAPPED: u32 = 0o41237;

/// The element kind and first element (its octal number's value; SP numbers for VSP) of a
/// bit-mapped word; None for a data word or an address that does not exist.
pub fn mapped(a: u32) -> Option<(Kind, u32)> {
    MAPPED
        .iter()
        .find(|(first, last, ..)| (*first..=*last).contains(&a))
        .map(|&(first, _, kind, _)| (kind, (a - first) * 16))
}

/// Whether a program may write this bit-mapped word (VY, VC, VS); data words always.
pub fn writable_word(a: u32) -> bool {
    !matches!(
        mapped(a),
        Some((Kind::X | Kind::T | Kind::Ct | Kind::Sp, _))
    )
}

/// The V address of timer or counter `n`'s current value (TAn = Vn, CTAn = V1000 + n).
pub fn current_word(kind: Kind, n: u32) -> u32 {
    if kind == Kind::Ct { 0o1000 + n } else { n }
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

pub use crate::machine::plc::Logic;

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
    /// Invert the top of the boolean stack.
    Not,
    /// One-shot coil with the index of its edge memory.
    Pd(Bit, u32),
    /// OR-ing coil with the index of its per-scan "written" mark.
    OrOut(Bit, u32),
    Inv,
    Cmp(W),
    CmpD(D),
    Timer(TimerKind, u32, Preset),
    Counter(CounterKind, u32, Preset),
    /// MOV, SETBIT, RSTBIT (spec §6.6): count from L1, start address from ACC.
    Table(Table, u32),
    // Program control (spec §6.8, §6.10). Targets are instruction indices, resolved by the
    // assembler once every label, subroutine and stage is known.
    /// Continue at the LBL with this index.
    Goto(u32),
    Lbl(u16),
    /// The loop count and the index of the loop's NEXT.
    For(W, u32),
    /// The index of the loop's FOR.
    Next(u32),
    /// Call the SBR at this index.
    Gts(u32),
    Sbr(u16),
    Rt,
    Rtc,
    Mls(u8),
    Mlr(u8),
    /// A stage: its number, whether it is an ISG, and the index of the next SG, ISG or END
    /// (where an inactive stage skips to).
    Sg {
        stage: u32,
        initial: bool,
        next: u32,
    },
    /// Turn the enclosing stage `own` off and stage `to` on.
    Jmp {
        to: u32,
        own: u32,
    },
    Njmp {
        to: u32,
        own: u32,
    },
}

impl Op {
    pub fn is_contact(&self) -> bool {
        matches!(
            self,
            Op::Str(_) | Op::And(_) | Op::Or(_) | Op::AndStr | Op::OrStr | Op::Not
        )
    }
    /// Outputs that run whatever their rung's power (spec §5): they act on an unpowered rung
    /// too (a coil turns off, a timer resets).
    pub fn always_runs(&self) -> bool {
        matches!(
            self,
            Op::Coil(_)
                | Op::Pd(..)
                | Op::OrOut(..)
                | Op::Timer(..)
                | Op::Counter(..)
                | Op::Mls(_)
                | Op::Njmp { .. }
        )
    }
    /// Instructions that change where execution goes, or the block's power: the fast loop
    /// hands them to the executor.
    pub fn is_control(&self) -> bool {
        matches!(
            self,
            Op::End
                | Op::Goto(_)
                | Op::Lbl(_)
                | Op::For(..)
                | Op::Next(_)
                | Op::Gts(_)
                | Op::Sbr(_)
                | Op::Rt
                | Op::Rtc
                | Op::Mls(_)
                | Op::Mlr(_)
                | Op::Sg { .. }
                | Op::Jmp { .. }
                | Op::Njmp { .. }
        )
    }
    /// Instructions that take no rung condition and end the current rung (spec §2).
    pub fn is_standalone(&self) -> bool {
        matches!(
            self,
            Op::End
                | Op::Nop
                | Op::Lbl(_)
                | Op::Next(_)
                | Op::Sbr(_)
                | Op::Rt
                | Op::Sg { .. }
                | Op::Mlr(_)
        )
    }
    pub fn is_output(&self) -> bool {
        !self.is_contact() && !self.is_standalone()
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
    /// Edge memories (edge contacts and PD coils), one per instruction.
    pub edges: u32,
    /// Distinct OROUT targets; each has a per-scan mark.
    pub orout_bits: Vec<Bit>,
    /// Every timer and counter box, in program order.
    pub boxes: Vec<BoxDecl>,
    /// The program as a ladder diagram, wired but not laid out.
    pub ladder: std::sync::Arc<crate::machine::plc::ladder::Ladder>,
    /// The same laid out, once something draws it (a long rung costs nothing until then).
    pub diagram: crate::machine::plc::ladder::LaidOut,
    /// DirectSOFT's element documentation from a `#BEGIN ELEMENT_DOC` block.
    pub docs: Vec<ElementDoc>,
}

/// One record of a DirectSOFT `#BEGIN ELEMENT_DOC` block: `"X0","START_PB","wiring","Start
/// push button"` (element, nickname, wiring info, description; `""` for a quote).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ElementDoc {
    /// The element as written (`X0`, `V2000`), upper case.
    pub element: String,
    pub nickname: String,
    pub description: String,
}

/// A timer or counter box of the program: for the Timers & counters panel, RST and the
/// one-box-per-number check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoxDecl {
    /// `T` or `CT` and the box's number.
    pub status: Bit,
    /// Words of its current value (2: it also takes number n + 1).
    pub words: u32,
    pub preset: Preset,
    /// Index of its instruction.
    pub instr: usize,
}

impl Program {
    /// Words of the current value of the box with this status bit (1 when there is none).
    pub fn box_words(&self, status: Bit) -> u32 {
        self.boxes
            .iter()
            .find(|b| b.status == status)
            .map_or(1, |b| b.words)
    }
}
