//! Technosoft TML (spec `tml.md`): the language of iPOS/IDM drives. 16-bit `int`, 32-bit
//! `long`, 16.16 `fixed`, a 48-bit product register, 10 statements per 1 ms tick, events and
//! `WAIT!`, and an integer trapezoidal profile that lands exactly.
//!
//! Decided where the spec is silent (each also noted where it is implemented):
//! - Positions are `(tick, step)`: `step` counts the statements completed in the tick. A tick
//!   completes as soon as its instruction phase ends (10 statements, a `WAIT!` that must wait,
//!   `END`, a fault): the motion phases run at once, so `(t, 10)` is never a position.
//! - A breakpoint is checked when a statement starts, not when a waiting `WAIT!` is retried.
//! - User edits: the rw data of §2, user variables, PREG and the inputs may be written from the
//!   debugger; the data the drive computes (TPOS, APOS, SRL, …) may not. Writing CPOS etc. takes
//!   effect at the next `UPD`, as a TML assignment would.
//! - The plot's profile end is the `motion.end` of the runner (P of the last accepted UPD).

pub mod arith;
pub mod assembler;
pub mod dialect;
mod exec;
mod explain;
mod motion;
pub mod program;
pub mod syntax;
pub mod view;

use std::sync::Arc;

pub use assembler::assemble;
pub use program::{Program, Stmt, Ty};

/// Statements per tick (spec §3).
pub const STATEMENTS_PER_TICK: u32 = 10;
/// Return points the TML stack holds (spec §5.7).
pub const STACK_DEPTH: usize = 11;
pub const TICK_MICROS: u32 = 1000;
pub const INPUTS: usize = 16;

/// The predefined data of spec §2 (tables A and B), in the order views and the runner list them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Predefined {
    pub name: &'static str,
    pub alias: Option<&'static str>,
    pub ty: Ty,
    pub writable: bool,
    /// The word address in the drive's data memory (spec §2.1, §2.2).
    pub address: u16,
    /// Table B: in the runner's registers only when the program names it (spec §9).
    pub table_b: bool,
    /// What the datum means; for table B also whether it has a behaviour or is storage only.
    pub description: &'static str,
}

pub const PREDEFINED: &[Predefined] = &[
    pre(
        "CPOS",
        None,
        Ty::Long,
        true,
        0x029E,
        "command position (relative or absolute)",
    ),
    pre(
        "CSPD",
        None,
        Ty::Fixed,
        true,
        0x02A0,
        "command (slew) speed, counts/tick",
    ),
    pre(
        "CACC",
        None,
        Ty::Fixed,
        true,
        0x02A2,
        "command acceleration, counts/tick²",
    ),
    pre(
        "TPOS",
        None,
        Ty::Long,
        false,
        0x02B2,
        "target position from the profile",
    ),
    pre("TSPD", None, Ty::Fixed, false, 0x02B4, "target speed"),
    pre(
        "APOS",
        Some("APOS_LD"),
        Ty::Long,
        false,
        0x0228,
        "actual position",
    ),
    pre(
        "ASPD",
        Some("ASPD_MT"),
        Ty::Fixed,
        false,
        0x022C,
        "actual speed",
    ),
    pre(
        "POSERR",
        None,
        Ty::Int,
        false,
        0x022A,
        "TPOS − APOS, clamped to 16 bits",
    ),
    pre(
        "ATIME",
        None,
        Ty::Long,
        false,
        0x02C0,
        "absolute time: ticks completed",
    ),
    pre("SRL", None, Ty::Uint, false, 0x090E, "status register low"),
    pre(
        "SRH",
        None,
        Ty::Uint,
        false,
        0x090F,
        "status register high (always 0 here)",
    ),
    pre(
        "MER",
        None,
        Ty::Uint,
        false,
        0x08FC,
        "motion error register",
    ),
    pre("DER", None, Ty::Uint, false, 0x03AD, "drive error register"),
    pre(
        "UPGRADE",
        None,
        Ty::Int,
        true,
        0x0857,
        "bit 11 selects the in-position rule for motion complete; other bits stored only",
    ),
    pre(
        "FLAGUV",
        None,
        Ty::Int,
        false,
        0x02FB,
        "under-voltage flag, always 0",
    ),
    pre(
        "PROD",
        None,
        Ty::Long,
        false,
        0x030E,
        "bits 31..0 of the product register",
    ),
    pre(
        "PRODH",
        None,
        Ty::Long,
        false,
        0x030F,
        "bits 47..16 of the product register",
    ),
    // Table B.
    b(
        "TACC",
        Ty::Fixed,
        false,
        0x02B6,
        "behaviour: the change of TSPD in the last tick",
    ),
    b(
        "RTIME",
        Ty::Long,
        false,
        0x02C2,
        "behaviour: ATIME − TIME0 (TIME0 set by the last !RT, else 0)",
    ),
    b(
        "MCR",
        Ty::Uint,
        false,
        0x0309,
        "behaviour: motion command register, written by MODE PP, CPA/CPR, TUM0/TUM1",
    ),
    b(
        "POSOKLIM",
        Ty::Uint,
        true,
        0x036A,
        "behaviour: in-position band in counts (with UPGRADE bit 11)",
    ),
    b(
        "TONPOSOK",
        Ty::Uint,
        true,
        0x036B,
        "behaviour: in-position time in ticks (with UPGRADE bit 11)",
    ),
    b(
        "VAR_I1",
        Ty::Int,
        true,
        0x0366,
        "storage only (scratch of generated code)",
    ),
    b(
        "VAR_I2",
        Ty::Int,
        true,
        0x0367,
        "storage only (scratch of generated code)",
    ),
    b(
        "VAR_I3",
        Ty::Int,
        true,
        0x0979,
        "storage only (scratch of generated code)",
    ),
    b(
        "VAR_LF",
        Ty::Long,
        true,
        0x0368,
        "storage only (scratch of generated code)",
    ),
    b(
        "DoTMLInitializations",
        Ty::Int,
        true,
        0x09C0,
        "storage only (0: EasyMotion's setup goes on to ENDINIT)",
    ),
    b(
        "ExecuteMain",
        Ty::Uint,
        true,
        0x09BF,
        "storage only: a label address for the firmware",
    ),
    b(
        "ExecuteAutotuning",
        Ty::Uint,
        true,
        0x0998,
        "storage only: a label address for the firmware",
    ),
    b(
        "HOMINGTABLE_POINTER",
        Ty::Uint,
        true,
        0x09C1,
        "storage only: the homing table's address",
    ),
    b(
        "FUNCTIONTABLE_POINTER",
        Ty::Uint,
        true,
        0x09C9,
        "storage only: the function table's address",
    ),
];

/// Aliases beyond the one each datum shows (spec §2.1: APOS is also APOS_MT, ASPD also
/// ASPD_LD), with the name they stand for.
pub const MORE_ALIASES: &[(&str, &str)] = &[("APOS_MT", "APOS"), ("ASPD_LD", "ASPD")];

/// `name` with an alias of [`MORE_ALIASES`] replaced by the datum's name (any case).
pub fn canonical_name(name: &str) -> &str {
    MORE_ALIASES
        .iter()
        .find(|(alias, _)| alias.eq_ignore_ascii_case(name.trim()))
        .map_or(name, |&(_, to)| to)
}

const fn pre(
    name: &'static str,
    alias: Option<&'static str>,
    ty: Ty,
    writable: bool,
    address: u16,
    description: &'static str,
) -> Predefined {
    Predefined {
        name,
        alias,
        ty,
        writable,
        address,
        table_b: false,
        description,
    }
}

const fn b(
    name: &'static str,
    ty: Ty,
    writable: bool,
    address: u16,
    description: &'static str,
) -> Predefined {
    Predefined {
        table_b: true,
        ..pre(name, None, ty, writable, address, description)
    }
}

/// Indices into [`PREDEFINED`] (and [`Tml::data`]).
pub mod d {
    pub const CPOS: u8 = 0;
    pub const CSPD: u8 = 1;
    pub const CACC: u8 = 2;
    pub const TPOS: u8 = 3;
    pub const TSPD: u8 = 4;
    pub const APOS: u8 = 5;
    pub const ASPD: u8 = 6;
    pub const POSERR: u8 = 7;
    pub const ATIME: u8 = 8;
    pub const SRL: u8 = 9;
    pub const SRH: u8 = 10;
    pub const MER: u8 = 11;
    pub const DER: u8 = 12;
    pub const UPGRADE: u8 = 13;
    pub const FLAGUV: u8 = 14;
    pub const PROD: u8 = 15;
    pub const PRODH: u8 = 16;
    pub const TACC: u8 = 17;
    pub const RTIME: u8 = 18;
    pub const MCR: u8 = 19;
    pub const POSOKLIM: u8 = 20;
    pub const TONPOSOK: u8 = 21;
    pub const VAR_I1: u8 = 22;
    pub const VAR_I2: u8 = 23;
    pub const VAR_I3: u8 = 24;
    pub const VAR_LF: u8 = 25;
    pub const DO_TML_INITIALIZATIONS: u8 = 26;
    pub const EXECUTE_MAIN: u8 = 27;
    pub const EXECUTE_AUTOTUNING: u8 = 28;
    pub const HOMINGTABLE_POINTER: u8 = 29;
    pub const FUNCTIONTABLE_POINTER: u8 = 30;
    pub const COUNT: usize = 31;
}

pub mod srl {
    pub const MOTION_COMPLETE: u32 = 1 << 10;
    pub const EVENT: u32 = 1 << 14;
    pub const AXIS_ON: u32 = 1 << 15;
}
/// UPGRADE bit 11: motion complete waits for the in-position rule (spec §6.1).
pub const UPGRADE_IN_POSITION: u32 = 1 << 11;

/// MCR as spec §2.2 builds it.
pub mod mcr {
    pub const MODE_PP: u32 = 0x8701;
    pub const ABSOLUTE: u32 = 0x2000;
    pub const TUM1: u32 = 0x4000;
}

/// Where the program is loaded in the drive's program memory (spec §5.11).
pub const PROGRAM_BASE: u32 = 0x4000;

pub mod mer {
    pub const COMMAND_ERROR: u32 = 1 << 14;
}
pub mod der {
    pub const STACK_OVERFLOW: u32 = 1 << 0;
    pub const STACK_UNDERFLOW: u32 = 1 << 1;
    pub const UPD_IGNORED: u32 = 1 << 4;
}
/// Why an `UPD` was ignored (the last statement's first value; several may hold at once).
pub mod upd_ignored {
    pub const NO_MODE_PP: u8 = 1 << 0;
    pub const AXIS_OFF: u8 = 1 << 1;
    pub const CSPD: u8 = 1 << 2;
    pub const CACC: u8 = 1 << 3;
}

/// PREG's 48 bits.
pub const PREG_MASK: u64 = (1 << 48) - 1;

/// The programmed event (spec §5.9).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    MotionComplete,
    /// `!RT t`: t ticks after `time0`.
    Time {
        after: i64,
        time0: i64,
    },
    Input {
        input: u8,
        level: bool,
    },
}

/// The trapezoidal profile generator (spec §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Profile {
    /// Reference position × 65536 (never wrapped).
    pub x: i128,
    /// Reference speed, raw 16.16.
    pub v: i64,
    pub active: bool,
    pub stopping: bool,
    /// End position P, speed V and acceleration A of the last accepted UPD.
    pub end: i32,
    pub speed: i64,
    pub accel: i64,
    /// Deceleration while stopping.
    pub decel: i64,
}

/// The last multiplication, for the product register panel and the explanation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LastMultiply {
    pub line: usize,
    pub a: i64,
    pub b: i64,
    pub left: bool,
    pub shift: u8,
    /// The exact product before the shift.
    pub product: i128,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    StackOverflow,
    StackUnderflow,
    /// A jump through a variable to an address where no statement starts (spec §5.7).
    BadAddress {
        address: u16,
        call: bool,
    },
}

impl Fault {
    pub fn kind(self) -> &'static str {
        match self {
            Fault::StackOverflow => "stack_overflow",
            Fault::StackUnderflow => "stack_underflow",
            Fault::BadAddress { .. } => "bad_address",
        }
    }
    pub fn message(self) -> String {
        match self {
            Fault::StackOverflow => "CALL with 11 return points already on the TML stack".into(),
            Fault::StackUnderflow => "RET with no CALL to return to".into(),
            Fault::BadAddress { address, call } => format!(
                "{} through a variable to 0x{address:04X}, where no statement starts",
                if call { "CALL" } else { "GOTO" }
            ),
        }
    }
}

/// A TML drive running one program.
#[derive(Clone, Debug, PartialEq)]
pub struct Tml {
    pub program: Arc<Program>,
    /// Predefined data, raw low bits of each datum's width (PROD/PRODH are read from PREG).
    pub data: [u32; d::COUNT],
    /// User variables, raw, in declaration order.
    pub vars: Vec<u32>,
    /// The 48-bit product register, raw.
    pub preg: u64,
    pub inputs: u16,
    pub stack: Vec<u32>,
    pub pc: u32,
    pub tick: u64,
    pub step: u32,
    pub steps: u64,
    pub ended: bool,
    pub fault: Option<(Fault, usize)>,
    pub event: Option<Event>,
    /// The tick in which a waiting `WAIT!` was first reached.
    pub wait_since: Option<u64>,
    pub mode_pp: bool,
    pub relative: bool,
    pub tum1: bool,
    pub profile: Profile,
    /// Index of the last completed statement, and the values it read and wrote.
    pub last: Option<u32>,
    pub last_vals: [i64; 3],
    pub last_multiply: Option<LastMultiply>,
    /// ATIME when the last `!RT` was set (TIME0 of spec §5.9), raw; RTIME counts from it.
    pub time0: u32,
    /// The in-position count n of spec §6.1.
    pub in_position: u16,
}

impl Tml {
    pub fn new(program: Arc<Program>) -> Self {
        let vars = vec![0; program.vars.len()];
        let mut data = [0; d::COUNT];
        data[d::SRL as usize] = srl::AXIS_ON | srl::MOTION_COMPLETE;
        let ended = program.stmts.is_empty();
        Tml {
            program,
            data,
            vars,
            preg: 0,
            inputs: 0,
            stack: Vec::new(),
            pc: 0,
            tick: 0,
            step: 0,
            steps: 0,
            ended,
            fault: None,
            event: None,
            wait_since: None,
            mode_pp: false,
            relative: true,
            tum1: false,
            profile: Profile::default(),
            last: None,
            last_vals: [0; 3],
            last_multiply: None,
            time0: 0,
            in_position: u16::MAX,
        }
    }

    /// PREG as a signed 48-bit number.
    pub fn preg_signed(&self) -> i64 {
        ((self.preg << 16) as i64) >> 16
    }

    pub fn input(&self, n: usize) -> bool {
        self.inputs & (1 << n) != 0
    }

    /// Whether `WAIT!` is waiting now, and for how many ticks already.
    pub fn waiting(&self) -> Option<u64> {
        self.wait_since.map(|t0| self.tick.saturating_sub(t0))
    }

    /// MCR (spec §2.2): written by MODE PP, CPA/CPR and TUM0/TUM1, so read from their state.
    pub fn mcr(&self) -> u32 {
        let mut v = 0;
        if self.mode_pp {
            v |= mcr::MODE_PP;
        }
        if !self.relative {
            v |= mcr::ABSOLUTE;
        }
        if self.tum1 {
            v |= mcr::TUM1;
        }
        v
    }

    /// Whether UPGRADE bit 11 makes motion complete wait for the in-position rule (§6.1).
    pub fn in_position_rule(&self) -> bool {
        self.data[d::UPGRADE as usize] & UPGRADE_IN_POSITION != 0
    }

    /// Motion complete by spec §6.1: no profile active and, under UPGRADE bit 11, the
    /// in-position count has reached TONPOSOK (at least 1).
    pub fn motion_complete(&self) -> bool {
        if self.profile.active {
            return false;
        }
        if !self.in_position_rule() {
            return true;
        }
        let needed = (self.data[d::TONPOSOK as usize] as u16).max(1);
        self.in_position >= needed
    }
}
