//! The assembled form of a SilverLode program: commands with every name resolved, so the
//! executor only matches on small enums.

use std::sync::Arc;

/// Declares an operation enum together with its source names, so the assembler, the executor
/// and the explanations can never disagree on spelling.
macro_rules! named_ops {
    ($(#[$meta:meta])* $name:ident { $($variant:ident = $text:literal),* $(,)? }) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum $name { $($variant),* }

        impl $name {
            pub const ALL: &'static [$name] = &[$($name::$variant),*];
            pub const NAMES: &'static [&'static str] = &[$($text),*];

            pub fn name(self) -> &'static str {
                match self { $($name::$variant => $text),* }
            }

            /// Case-insensitive lookup.
            pub fn parse(text: &str) -> Option<Self> {
                Self::ALL.iter().copied().find(|op| op.name().eq_ignore_ascii_case(text))
            }
        }
    };
}

named_ops! {
    /// CLC operations: the accumulator (R10) against one register.
    ClcOp {
        Clear = "CLEAR", Copy = "COPY", Save = "SAVE", CopyRef = "COPY_REF", SaveRef = "SAVE_REF",
        Abs = "ABS", Neg = "NEG", Inc = "INC", Dec = "DEC", Add = "ADD", AddHi = "ADD_HI",
        AddLo = "ADD_LO", Sub = "SUB", SubRev = "SUB_REV", MultS = "MULT_S", MultU = "MULT_U",
        Div = "DIV", Mod = "MOD", Max = "MAX", Min = "MIN", And = "AND", Or = "OR", Xor = "XOR",
        Shl = "SHL", ShrS = "SHR_S", ShrU = "SHR_U", CopyWordHiAcc = "COPY_WORD_HI_ACC",
        CopyWordHiReg = "COPY_WORD_HI_REG", CopyWordLoReg = "COPY_WORD_LO_REG",
        SextHi = "SEXT_HI", SextLo = "SEXT_LO", SubTarget = "SUB_TARGET",
    }
}

named_ops! {
    /// CLD / CLX operations: `res = f(reg1, d)`, plus the queue operations.
    ExtOp {
        Copy = "COPY", Abs = "ABS", Neg = "NEG", Add = "ADD", Sub = "SUB", SubRev = "SUB_REV",
        AddHi = "ADD_HI", AddLo = "ADD_LO", And = "AND", Or = "OR", Xor = "XOR", Max = "MAX",
        Min = "MIN", SextHi = "SEXT_HI", SextLo = "SEXT_LO", PackLoLo = "PACK_LO_LO",
        PackHiLo = "PACK_HI_LO", PackHiHi = "PACK_HI_HI", MultS = "MULT_S", MultU = "MULT_U",
        MultS64Shr16 = "MULT_S64_SHR16", MultU64 = "MULT_U64", Div = "DIV", DivRev = "DIV_REV",
        DivU64 = "DIV_U64", Mod = "MOD", ModRev = "MOD_REV",
        QInit = "Q_INIT", QPushHead = "Q_PUSH_HEAD", QPopHead = "Q_POP_HEAD",
        QPushTail = "Q_PUSH_TAIL", QPopTail = "Q_POP_TAIL", QRead = "Q_READ",
        QPushHeadErr = "Q_PUSH_HEAD_ERR", QPopHeadErr = "Q_POP_HEAD_ERR",
        QPushTailErr = "Q_PUSH_TAIL_ERR", QPopTailErr = "Q_POP_TAIL_ERR",
    }
}

impl ExtOp {
    pub fn is_queue(self) -> bool {
        use ExtOp::*;
        matches!(
            self,
            QInit
                | QPushHead
                | QPopHead
                | QPushTail
                | QPopTail
                | QRead
                | QPushHeadErr
                | QPopHeadErr
                | QPushTailErr
                | QPopTailErr
        )
    }
}

named_ops! {
    /// The ISW bits a condition can test.
    CondBit {
        Zero = "ZERO", Positive = "POSITIVE", Negative = "NEGATIVE", Index = "INDEX",
        Io1 = "IO1", Io2 = "IO2", Io3 = "IO3", MovingError = "MOVING_ERROR",
        HoldingError = "HOLDING_ERROR", InputFound = "INPUT_FOUND", DelayDone = "DELAY_DONE",
    }
}

impl CondBit {
    pub fn isw_bit(self) -> u8 {
        match self {
            CondBit::Index => 0,
            CondBit::Zero => 1,
            CondBit::Positive => 2,
            CondBit::Negative => 3,
            CondBit::Io1 => 4,
            CondBit::Io2 => 5,
            CondBit::Io3 => 6,
            CondBit::MovingError => 8,
            CondBit::HoldingError => 9,
            CondBit::InputFound => 11,
            CondBit::DelayDone => 12,
        }
    }
}

/// `COND` or `!COND`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Cond {
    pub bit: CondBit,
    /// True for `!COND`: holds while the bit is clear.
    pub negated: bool,
}

impl Cond {
    #[inline(always)]
    pub fn holds(self, isw: u16) -> bool {
        (isw >> self.bit.isw_bit() & 1 == 1) != self.negated
    }
}

impl std::fmt::Display for Cond {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let bang = if self.negated { "!" } else { "" };
        write!(f, "{bang}{}", self.bit.name())
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MoveKind {
    /// Absolute, literal position.
    Mav,
    /// Relative to the target, literal distance.
    Mrv,
    /// Absolute, position in a register.
    Rav,
    /// Relative, distance in a register.
    Rrv,
}

impl MoveKind {
    pub fn name(self) -> &'static str {
        match self {
            MoveKind::Mav => "MAV",
            MoveKind::Mrv => "MRV",
            MoveKind::Rav => "RAV",
            MoveKind::Rrv => "RRV",
        }
    }
    pub fn is_relative(self) -> bool {
        matches!(self, MoveKind::Mrv | MoveKind::Rrv)
    }
    pub fn takes_register(self) -> bool {
        matches!(self, MoveKind::Rav | MoveKind::Rrv)
    }
}

/// One assembled command. Register operands are already checked to be 0..=199; jump targets are
/// command indices (`== len` means "past the last line", which ends the program).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Instr {
    Clc {
        op: ClcOp,
        reg: u8,
    },
    Cld {
        op: ExtOp,
        res: u8,
        reg1: u8,
        data: i32,
    },
    Clx {
        op: ExtOp,
        res: u8,
        reg1: u8,
        reg2: u8,
    },
    Wrp {
        reg: u8,
        value: i32,
    },
    Jmp {
        target: u32,
        cond: Option<Cond>,
    },
    Call {
        target: u32,
    },
    Ret,
    Dly {
        ticks: u32,
    },
    Wbs {
        cond: Cond,
    },
    Cer {
        target: Option<u32>,
    },
    End,
    Move {
        kind: MoveKind,
        /// Literal position/distance, or the register number for RAV/RRV.
        pos: i32,
        accel: i32,
        vel: i32,
        cond: Option<Cond>,
    },
    Ztp,
    Ttp,
}

/// A register's dedicated name (spec §1), the one table the assembler and the views read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Alias {
    pub register: u8,
    pub name: &'static str,
    pub description: &'static str,
}

pub const ALIASES: &[Alias] = &[
    Alias {
        register: 0,
        name: "TARGET",
        description: "target position (counts)",
    },
    Alias {
        register: 1,
        name: "ACTUAL",
        description: "actual position (counts)",
    },
    Alias {
        register: 2,
        name: "LAST_INDEX",
        description: "last index position",
    },
    Alias {
        register: 4,
        name: "LAST_TRIG",
        description: "actual position when the last move stopped on its input",
    },
    Alias {
        register: 6,
        name: "POS_ERROR",
        description: "position error R0 − R1",
    },
    Alias {
        register: 7,
        name: "VELOCITY",
        description: "actual velocity (counts/tick × 2^26)",
    },
    Alias {
        register: 10,
        name: "ACC",
        description: "accumulator of CLC",
    },
];

/// An assembled program: commands, where each came from, and the names the source used.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Program {
    pub instrs: Vec<Instr>,
    /// 1-based source line of each command.
    pub lines: Vec<u32>,
    /// Labels with the command index they name, in source order.
    pub labels: Vec<(String, u32)>,
    /// Registers the source mentions (for "registers this program uses" filters).
    pub used_registers: Vec<u8>,
    /// DEF names that name registers, in source order.
    pub register_names: Vec<(String, u8)>,
    /// DEFs of numbers, in source order.
    pub constants: Vec<(String, i64)>,
    /// `instrs` pre-decoded for the fast loop, one [`Op`] per command plus an end marker.
    pub flat: Vec<Op>,
    /// Every register a command of `flat` other than `Full` may write.
    pub flat_writes: crate::machine::WriteSet,
    /// The loops of `flat` the fast loop may run compiled.
    pub loops: super::jit::Loops,
}

/// A command as the fast loop dispatches on it: one match, operands resolved. Every command
/// that only reads and writes registers (and the call stack), sets the flags and takes one tick
/// has a form of its own; moves, waits, the end, CER, SUB_TARGET/ZTP/TTP and writes of R0/R1
/// (the motion model's inputs) are [`Op::Full`] and run through the full executor, and so does
/// any command whose operands would fault this time (the loop hands it over before it runs).
/// The commonest calculations have arms of their own; the rest go through the executor's own
/// arithmetic (`Clc`, `ExtI`, `ExtR`), so the two can never disagree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `res = a + d` and the others: `d` an immediate.
    AddI {
        res: u8,
        a: u8,
        d: i32,
    },
    SubI {
        res: u8,
        a: u8,
        d: i32,
    },
    AndI {
        res: u8,
        a: u8,
        d: i32,
    },
    OrI {
        res: u8,
        a: u8,
        d: i32,
    },
    XorI {
        res: u8,
        a: u8,
        d: i32,
    },
    MulI {
        res: u8,
        a: u8,
        d: i32,
    },
    MulShr16I {
        res: u8,
        a: u8,
        d: i32,
    },
    /// `res = a + b` and the others: `b` a register.
    AddR {
        res: u8,
        a: u8,
        b: u8,
    },
    SubR {
        res: u8,
        a: u8,
        b: u8,
    },
    AndR {
        res: u8,
        a: u8,
        b: u8,
    },
    OrR {
        res: u8,
        a: u8,
        b: u8,
    },
    XorR {
        res: u8,
        a: u8,
        b: u8,
    },
    MulR {
        res: u8,
        a: u8,
        b: u8,
    },
    MulShr16R {
        res: u8,
        a: u8,
        b: u8,
    },
    /// CLC: the accumulator (R10) with register `r`.
    AccAdd {
        r: u8,
    },
    AccSub {
        r: u8,
    },
    AccMul {
        r: u8,
    },
    AccAnd {
        r: u8,
    },
    AccOr {
        r: u8,
    },
    AccXor {
        r: u8,
    },
    /// CLC COPY (R10 = r) and SAVE (r = R10).
    AccCopy {
        r: u8,
    },
    AccSave {
        r: u8,
    },
    Inc {
        r: u8,
    },
    Dec {
        r: u8,
    },
    /// Any other CLC operation but SUB_TARGET.
    Clc {
        op: ClcOp,
        r: u8,
    },
    /// Any other CLD operation (queues and 64-bit ones included) but Q_INIT.
    ExtI {
        op: ExtOp,
        res: u8,
        a: u8,
        d: i32,
    },
    /// Any other CLX operation but Q_INIT.
    ExtR {
        op: ExtOp,
        res: u8,
        a: u8,
        b: u8,
    },
    Wrp {
        r: u8,
        value: i32,
    },
    Call {
        target: u32,
    },
    Ret,
    Jmp {
        target: u32,
    },
    /// Taken when ISW bit `bit` is `want`.
    JmpIf {
        target: u32,
        bit: u8,
        want: u8,
    },
    Full,
}

impl Op {
    /// Every register a command may write when the fast loop runs it, `f` called for each:
    /// exactly, or every register it could reach when that depends on the data (a SAVE_REF, a
    /// queue's slots). Jumps, calls and `Full` write none the fast loop knows of.
    #[inline]
    pub fn each_write(self, mut f: impl FnMut(u8)) {
        use Op::*;
        let every_from =
            |f: &mut dyn FnMut(u8), from: u8| (from..super::REGISTERS as u8).for_each(f);
        match self {
            AddI { res, .. }
            | SubI { res, .. }
            | AndI { res, .. }
            | OrI { res, .. }
            | XorI { res, .. }
            | MulI { res, .. }
            | MulShr16I { res, .. }
            | AddR { res, .. }
            | SubR { res, .. }
            | AndR { res, .. }
            | OrR { res, .. }
            | XorR { res, .. }
            | MulR { res, .. }
            | MulShr16R { res, .. } => f(res),
            AccAdd { .. }
            | AccSub { .. }
            | AccMul { .. }
            | AccAnd { .. }
            | AccOr { .. }
            | AccXor { .. }
            | AccCopy { .. } => f(10),
            AccSave { r } | Inc { r } | Dec { r } | Wrp { r, .. } => f(r),
            Clc { op, r } => match op.writes() {
                ClcWrites::Acc => f(10),
                ClcWrites::Reg => f(r),
                // Never R0/R1: the fast loop hands such a SAVE_REF over.
                ClcWrites::Named => every_from(&mut f, 2),
                ClcWrites::Positions => {}
            },
            ExtI { op, res, a, .. } | ExtR { op, res, a, .. } => {
                f(res);
                if op == ExtOp::MultU64 {
                    f(res + 1);
                } else if op.is_queue() {
                    // The header and every slot a queue there could have.
                    every_from(&mut f, a);
                }
            }
            Call { .. } | Ret | Jmp { .. } | JmpIf { .. } | Full => {}
        }
    }
}

/// Where a CLC operation puts its result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClcWrites {
    /// The accumulator, R10.
    Acc,
    /// Its own register.
    Reg,
    /// The register its register names (SAVE_REF).
    Named,
    /// R0 and R1 (SUB_TARGET).
    Positions,
}

impl ClcOp {
    pub fn writes(self) -> ClcWrites {
        use ClcOp::*;
        match self {
            Clear | Save | Abs | Neg | Inc | Dec | Shl | ShrS | ShrU | CopyWordHiReg
            | CopyWordLoReg => ClcWrites::Reg,
            SaveRef => ClcWrites::Named,
            SubTarget => ClcWrites::Positions,
            Copy | CopyRef | Add | AddHi | AddLo | Sub | SubRev | MultS | MultU | Div | Mod
            | Max | Min | And | Or | Xor | CopyWordHiAcc | SextHi | SextLo => ClcWrites::Acc,
        }
    }
}

/// The fast loop's form of `instrs`: see [`Op`]. The last command of a program is `Full` unless
/// it is a jump (running past it ends the program), and one `Full` follows the end.
pub fn flatten(instrs: &[Instr]) -> Vec<Op> {
    let len = instrs.len() as u32;
    let mut flat: Vec<Op> = instrs
        .iter()
        .enumerate()
        .map(|(pc, &instr)| {
            let op = flat_op(instr, len);
            // A conditional jump there falls through to the end: the fast loop hands that
            // case over when it comes.
            let last = pc + 1 == instrs.len();
            let mut writes_motion = false;
            op.each_write(|r| writes_motion |= r <= 1);
            if (last && !matches!(op, Op::Jmp { .. } | Op::JmpIf { .. })) || writes_motion {
                Op::Full
            } else {
                op
            }
        })
        .collect();
    flat.push(Op::Full);
    flat
}

/// [`Program::flat_writes`].
pub fn flat_writes(flat: &[Op]) -> crate::machine::WriteSet {
    let mut set = crate::machine::WriteSet::default();
    for op in flat {
        op.each_write(|r| set.insert(super::view::reg(u32::from(r))));
    }
    set
}

/// Whether a CLD/CLX operation has a form in the fast loop with these registers: Q_INIT notes the
/// queue for the panels (outside the registers), and a register pair or queue header that runs
/// past R199 faults every time.
fn fits(op: ExtOp, res: u8, a: u8) -> bool {
    let last = super::REGISTERS as u8 - 1;
    match op {
        ExtOp::QInit => false,
        ExtOp::MultU64 => res < last,
        ExtOp::DivU64 => a < last,
        _ if op.is_queue() => a + 2 <= last,
        _ => true,
    }
}

fn flat_op(instr: Instr, len: u32) -> Op {
    use Op::*;
    match instr {
        Instr::Cld {
            op,
            res,
            reg1: a,
            data: d,
        } => match op {
            ExtOp::Add => AddI { res, a, d },
            ExtOp::Sub => SubI { res, a, d },
            ExtOp::And => AndI { res, a, d },
            ExtOp::Or => OrI { res, a, d },
            ExtOp::Xor => XorI { res, a, d },
            ExtOp::MultS | ExtOp::MultU => MulI { res, a, d },
            ExtOp::MultS64Shr16 => MulShr16I { res, a, d },
            _ if !fits(op, res, a) => Full,
            _ => ExtI { op, res, a, d },
        },
        Instr::Clx {
            op,
            res,
            reg1: a,
            reg2: b,
        } => match op {
            ExtOp::Add => AddR { res, a, b },
            ExtOp::Sub => SubR { res, a, b },
            ExtOp::And => AndR { res, a, b },
            ExtOp::Or => OrR { res, a, b },
            ExtOp::Xor => XorR { res, a, b },
            ExtOp::MultS | ExtOp::MultU => MulR { res, a, b },
            ExtOp::MultS64Shr16 => MulShr16R { res, a, b },
            _ if !fits(op, res, a) => Full,
            _ => ExtR { op, res, a, b },
        },
        Instr::Clc { op, reg: r } => match op {
            ClcOp::Add => AccAdd { r },
            ClcOp::Sub => AccSub { r },
            ClcOp::MultS | ClcOp::MultU => AccMul { r },
            ClcOp::And => AccAnd { r },
            ClcOp::Or => AccOr { r },
            ClcOp::Xor => AccXor { r },
            ClcOp::Copy => AccCopy { r },
            ClcOp::Save => AccSave { r },
            ClcOp::Inc => Inc { r },
            ClcOp::Dec => Dec { r },
            ClcOp::SubTarget => Full,
            _ => Clc { op, r },
        },
        Instr::Wrp { reg, value } => Wrp { r: reg, value },
        // A jump (or call) past the last command ends the program: the full executor does that.
        Instr::Jmp { target, .. } | Instr::Call { target } if target >= len => Full,
        Instr::Call { target } => Call { target },
        Instr::Ret => Ret,
        Instr::Jmp { target, cond: None } => Jmp { target },
        Instr::Jmp {
            target,
            cond: Some(c),
        } => JmpIf {
            target,
            bit: c.bit.isw_bit(),
            want: u8::from(!c.negated),
        },
        _ => Full,
    }
}

impl Program {
    pub fn empty() -> Arc<Program> {
        Arc::new(Program {
            instrs: Vec::new(),
            lines: Vec::new(),
            labels: Vec::new(),
            used_registers: Vec::new(),
            register_names: Vec::new(),
            constants: Vec::new(),
            flat: vec![Op::Full],
            flat_writes: crate::machine::WriteSet::default(),
            loops: super::jit::Loops::default(),
        })
    }

    /// The label naming command `index`, for explanations.
    pub fn label_at(&self, index: u32) -> Option<&str> {
        self.labels
            .iter()
            .find(|(_, at)| *at == index)
            .map(|(name, _)| name.as_str())
    }
}
