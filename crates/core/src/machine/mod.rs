//! The interpreter core: one folder per dialect, and the dialect-neutral face of a machine that
//! the debugger, the window and the headless runner use.
//!
//! Nothing here does I/O or knows about the layers above. A dialect provides an assembler (text
//! → program + diagnostics), a machine implementing [`Machine`] and its description
//! ([`dialect::DialectInfo`]); the layers above talk only to [`MachineView`] (dynamic, for
//! reading and editing) and to [`Machine`] (generic, for the run loops, so the hot loop is
//! monomorphised).
//!
//! ## Positions: (tick, step)
//! Time is a [`Pos`]: the tick counter and the number of instructions already executed inside
//! that tick. A SilverLode command fills a whole tick, so its positions are always `(t, 0)`; a
//! scanned PLC (one tick = one scan) executes many instructions per tick, and a user steps,
//! steps back and edits between them: `(t, 3)` is "scan t, after its third instruction".

pub mod bits;
pub mod diagnostics;
pub mod dialect;
pub mod plc;
pub mod project;
pub mod reference;
pub mod value;

// The dialects: each a folder whose `dialect::DIALECT` describes it and `dialect::open`
// assembles its programs; `crate::registry` lists them.
pub mod dl205;
pub mod opennet;
pub mod silverlode;
pub mod tml;

use std::any::Any;

pub use diagnostics::{Diagnostic, Severity};
pub use value::Format;

/// A JSON object whose keys keep the order they were inserted in (the runner's reports).
pub type JsonMap = serde_json::Map<String, serde_json::Value>;

/// A moment of a run: the tick counter and the instructions executed so far inside that tick.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    serde::Serialize,
    serde::Deserialize,
)]
pub struct Pos {
    pub tick: u64,
    #[serde(default)]
    pub step: u32,
}

impl Pos {
    pub const fn at_tick(tick: u64) -> Self {
        Pos { tick, step: 0 }
    }
}

impl std::fmt::Display for Pos {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.step == 0 {
            write!(f, "{}", self.tick)
        } else {
            write!(f, "{}.{}", self.tick, self.step)
        }
    }
}

/// What a machine is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum RunState {
    /// Ready to execute the instruction at the program counter.
    Running,
    /// In the middle of an instruction that spans ticks.
    Waiting(WaitReason),
    /// The program ended (END, or ran past its last line).
    Ended,
    /// A fault stopped the program; the state is as it was before that instruction.
    Faulted,
}

impl RunState {
    /// True while ticking can change anything.
    pub fn is_live(self) -> bool {
        matches!(self, RunState::Running | RunState::Waiting(_))
    }

    /// The word a user reads in a status bar and the runner prints.
    pub fn label(self) -> &'static str {
        match self {
            RunState::Running => "running",
            RunState::Waiting(WaitReason::Delay) => "waiting for delay",
            RunState::Waiting(WaitReason::Move) => "waiting for move",
            RunState::Waiting(WaitReason::Condition) => "waiting for input",
            RunState::Ended => "ended",
            RunState::Faulted => "faulted",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum WaitReason {
    Delay,
    Move,
    /// A status condition (WBS, WAIT!): in practice an input.
    Condition,
}

/// One storage location: a space of the machine and an index inside it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Loc {
    pub space: u8,
    pub index: u32,
}

impl Loc {
    pub const fn new(space: u8, index: u32) -> Self {
        Loc { space, index }
    }
}

/// How a view presents a storage space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpaceKind {
    /// Data words in a table (R0–R199, V-memory, D registers, TML data).
    Registers,
    /// Status words with named bits, or single flag relays (ISW/PSW, SP63, M8003).
    Flags,
    /// Input switches a user flips (IO1–IO3, X0…, I0…).
    Inputs,
    /// Output and internal bits (Y, C, Q, M).
    Bits,
}

/// A named storage space of a machine.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpaceInfo {
    pub name: &'static str,
    pub title: &'static str,
    pub kind: SpaceKind,
    /// Locations `0..len`.
    pub len: u32,
}

/// One named bit of a word.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BitInfo {
    pub bit: u8,
    pub name: &'static str,
    pub description: &'static str,
}

/// Static description of one location.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LocInfo {
    /// Canonical name, e.g. `R26`, `V1400`, `ISW`, `IO1`.
    pub name: String,
    /// The dedicated name, e.g. `ACTUAL` for R1.
    pub alias: Option<&'static str>,
    /// A one-line description for tooltips.
    pub description: &'static str,
    /// Width in bits, 1 ..= 64.
    pub width: u8,
    /// Read as a two's-complement number by default (plots, "signed" readings).
    pub signed: bool,
    /// The reading a view starts with for this location (a TML `fixed` as Q16.16).
    pub format: Option<Format>,
    /// Named bits, for words that are bit fields.
    pub bits: &'static [BitInfo],
    /// A user may write it (false for a relay the machine alone drives).
    pub editable: bool,
}

impl LocInfo {
    /// The format the dialect reads this location in: its own (`format`), else signed or
    /// unsigned decimal by `signed`.
    pub fn reading(&self) -> Format {
        self.format.unwrap_or(if self.signed {
            Format::Signed
        } else {
            Format::Unsigned
        })
    }

    /// A plain data word.
    pub fn word(name: String, width: u8, signed: bool) -> Self {
        LocInfo {
            name,
            alias: None,
            description: "",
            width,
            signed,
            format: None,
            bits: &[],
            editable: true,
        }
    }
}

/// The rung power after an instruction, as the code view shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinePower {
    On,
    Off,
    /// An output on an unpowered rung: it did nothing this scan.
    Skipped,
    /// Not executed in this scan at all: jumped over, an inactive stage, a subroutine not
    /// called.
    NotRun,
    /// Executed with every output's input forced off (OpenNet's MCS area with MC = 0).
    MasterOff,
}

/// A fault as a user reads it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct FaultInfo {
    /// Stable machine-readable kind, e.g. `divide_by_zero`.
    pub kind: &'static str,
    pub message: String,
    /// 1-based source line of the faulting instruction.
    pub line: usize,
}

/// Why a run loop returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The machine ended or faulted.
    Stopped,
    /// The position limit was reached first.
    TickLimit,
    /// The caller's predicate asked to stop (breakpoint, watchpoint, ...).
    Predicate,
}

/// Why a user edit was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum WriteError {
    #[error("there is no such location")]
    NoSuchLocation,
    #[error("{0} is set by the machine and cannot be written")]
    ReadOnly(String),
    #[error("{value} does not fit in {name} ({width} bits)")]
    TooWide { name: String, value: u64, width: u8 },
    #[error("{name} is forced {}: release the force first", if *on { "ON" } else { "OFF" })]
    Forced { name: String, on: bool },
    #[error("{0} cannot be forced (only inputs, outputs and relays can)")]
    NotForceable(String),
}

/// The dialect-neutral face of a machine for views, edits, sessions and the runner. Values are
/// raw bit patterns of the location's width (at most 64 bits): a view reads them in any format.
/// Dynamic dispatch is fine here: these calls happen per frame or per user action.
pub trait MachineView: Send + 'static {
    /// Dialect identifier, e.g. `silverlode`.
    fn dialect(&self) -> &'static str;
    /// Time of one tick in microseconds (a scan's nominal time for PLCs).
    fn tick_micros(&self) -> u32;

    /// The storage spaces, in the order views list them.
    fn spaces(&self) -> Vec<SpaceInfo>;
    /// Description of one location; `None` when it does not exist.
    fn info(&self, loc: Loc) -> Option<LocInfo>;
    /// The raw bits of a location (0 for one that does not exist).
    fn read(&self, loc: Loc) -> u64;
    /// A user edit: store `value` (masked to the location's width by the caller's parse).
    fn write(&mut self, loc: Loc, value: u64) -> Result<(), WriteError>;
    /// A location by any of its names (canonical, alias, case-insensitive).
    fn find(&self, name: &str) -> Option<Loc> {
        find_by_name(self, name)
    }
    /// Locations the program text mentions, for "used by the program" filters.
    fn used(&self) -> Vec<Loc>;
    /// What the program's documentation says of a location: a DirectSOFT nickname and
    /// description (`START_PB — Start push button`). `None` where it says nothing.
    fn location_doc(&self, _loc: Loc) -> Option<String> {
        None
    }
    /// Names the program itself gives to locations (SilverLode DEFs, TML variables).
    fn program_names(&self) -> Vec<(String, Loc)> {
        Vec::new()
    }
    /// Constants the program names (a SilverLode `DEF gain = q16(0.0254)`), with their values:
    /// watches and conditions may use them, hovering one shows its value.
    fn program_constants(&self) -> Vec<(String, i64)> {
        Vec::new()
    }

    /// 1-based source line of the instruction the program counter points at.
    fn pc_line(&self) -> Option<usize>;
    /// Return addresses as 1-based source lines, outermost first.
    fn call_stack_lines(&self) -> Vec<usize> {
        Vec::new()
    }
    /// Subroutine calls in progress (step over and step out run until it drops back).
    fn call_depth(&self) -> usize {
        self.call_stack_lines().len()
    }
    fn run_state(&self) -> RunState;
    fn fault(&self) -> Option<FaultInfo> {
        None
    }
    /// Where the machine is: the tick counter and the instructions run inside this tick.
    fn pos(&self) -> Pos;
    fn ticks(&self) -> u64 {
        self.pos().tick
    }
    /// Instructions (commands) executed since the start.
    fn steps(&self) -> u64;

    /// Locations the last executed instruction wrote (plus those the machine itself drives,
    /// such as motion registers while the motor moves).
    fn last_written(&self) -> Vec<Loc> {
        let mut out = Vec::new();
        self.for_each_written(&mut |loc| {
            if !out.contains(&loc) {
                out.push(loc);
            }
        });
        out
    }
    /// What the last instruction itself wrote, flags included, and nothing the machine drove
    /// on its own in the same tick (a servo's motion registers): what the Log and the
    /// runner's trace credit to the instruction.
    fn instruction_written(&self) -> Vec<Loc> {
        self.last_written()
    }
    /// Each location the last executed instruction wrote (one may come twice): the one
    /// description of writes, asked at every instruction boundary while recording, so it
    /// builds no list.
    fn for_each_written(&self, f: &mut dyn FnMut(Loc));
    /// Add the locations the last executed instruction wrote to `set` (asked at every new
    /// boundary while the timeline records: dialects answer without a closure per location).
    fn note_writes(&self, set: &mut WriteSet) {
        self.for_each_written(&mut |loc| set.insert(loc));
    }
    /// Whether the last executed instruction wrote `loc` (data breakpoints and "who wrote
    /// this?").
    fn wrote(&self, loc: Loc) -> bool {
        let mut hit = false;
        self.for_each_written(&mut |l| hit |= l == loc);
        hit
    }
    /// The last executed instruction in words, with its operand values. Built on demand.
    fn explain_last(&self) -> Option<String>;
    /// The text of the statement the last step executed, where a line may hold several (TML's
    /// `a = 1; UPD;`); `None` where the line's text is the instruction.
    fn last_statement_text(&self) -> Option<&str> {
        None
    }
    /// 1-based line of the last executed instruction.
    fn last_line(&self) -> Option<usize>;

    /// Add the dialect's fields to the runner's JSON object, after the common header
    /// (`registers`, flags, …), in the order the runner prints them.
    fn report_json(&self, out: &mut JsonMap);
    /// The dialect's lines of the runner's text report.
    fn report_text(&self) -> String;

    /// Short notes the code view shows at the end of lines now (DL205: a FOR loop's turn, the
    /// call a subroutine runs in, an edge contact that fired this scan).
    fn line_notes(&self) -> Vec<(usize, String)> {
        Vec::new()
    }

    /// Each line on which a statement starts, with that statement's program-memory address
    /// (TML, spec tml.md §5.11), sorted by line: the code view's gutter can show them.
    fn line_addresses(&self) -> Vec<(usize, u32)> {
        Vec::new()
    }

    /// Warnings about the program that do not stop it (OpenNet: a MICRO3 relay read but never
    /// written): the window lists them with the problems, the runner prints them on stderr.
    fn warnings(&self) -> Vec<Diagnostic> {
        Vec::new()
    }

    /// The controller's error lamp (OpenNet's M8004): "break on error" stops when it turns on.
    fn error_lamp(&self) -> bool {
        false
    }

    /// The scanned PLC's face (ladder, rung power, forcing), for a machine that is one.
    fn as_plc(&self) -> Option<&dyn PlcView> {
        None
    }
    fn as_plc_mut(&mut self) -> Option<&mut dyn PlcView> {
        None
    }
    /// The motion face (what the plot draws besides the channels), for a drive that has one.
    fn as_motion(&self) -> Option<&dyn MotionView> {
        None
    }

    /// For a dialect's own panels, which know the concrete type.
    fn as_any(&self) -> &dyn Any;
}

/// Questions any view may ask of any machine, answered through its faces: a machine that is no
/// PLC forces nothing.
impl dyn MachineView {
    /// Whether this is a scanned PLC (ladder, forcing, scans).
    pub fn is_plc(&self) -> bool {
        self.as_plc().is_some()
    }
    /// Whether `loc` is a bit a user can force.
    pub fn can_force(&self, loc: Loc) -> bool {
        self.as_plc().is_some_and(|p| p.can_force(loc))
    }
    /// The level `loc` is forced to, if it is forced.
    pub fn forced(&self, loc: Loc) -> Option<bool> {
        self.as_plc()?.forced(loc)
    }
    /// The forced bits and their levels, in the order they were forced.
    pub fn forces(&self) -> Vec<(Loc, bool)> {
        self.as_plc().map_or_else(Vec::new, PlcView::forces)
    }
}

/// What a scanned PLC shows and allows besides the common face: the program as a ladder with
/// its power flow, and forcing. Reached by [`MachineView::as_plc`].
pub trait PlcView {
    /// The program as a ladder diagram, laid out the first time it is asked for.
    fn ladder(&self) -> std::sync::Arc<plc::ladder::Ladder>;
    /// The rungs and their elements, wired but not laid out: for what reads operands and
    /// comments without drawing (the I/O board), so it never pays for a layout.
    fn wiring(&self) -> std::sync::Arc<plc::ladder::Ladder>;
    /// Whether the contact-like element of instruction `index` conducts now: a normally-open
    /// contact whose bit is on, a normally-closed one whose bit is off, a compare that holds, an
    /// edge that fired in this scan.
    fn ladder_conducts(&self, index: usize) -> bool;
    /// The timers, counters and other boxes of the program, as the Timers & counters panel
    /// lists them.
    fn boxes(&self) -> Vec<plc::BoxRow>;
    /// Rung power per source line at this point of the scan: shown in the code view's gutter,
    /// outputs skipped on an unpowered rung greyed.
    fn line_power(&self) -> Vec<(usize, LinePower)>;
    /// Status relays the PLC itself drives at the start of every scan (DL205's SP0 first scan
    /// and SP1 always on). Before the first scan starts the window draws them as not driven
    /// yet, as the vendor's tool shows a PLC that is not running; the state itself keeps the
    /// spec's initial values (the runner's `--max-ticks 0` reports SP1 = 1).
    fn driven_by_scan(&self, _loc: Loc) -> bool {
        false
    }
    /// Force a bit to a level (`Some`) or release it (`None`): a forced bit keeps its level
    /// whatever the program writes (DL205 override, WindLDR set/reset forced).
    fn force(&mut self, loc: Loc, level: Option<bool>) -> Result<(), WriteError>;
    /// Whether `loc` is a bit a user can force.
    fn can_force(&self, loc: Loc) -> bool;
    /// The forced bits and their levels, in the order they were forced.
    fn forces(&self) -> Vec<(Loc, bool)>;
    /// The level `loc` is forced to, if it is forced.
    fn forced(&self, loc: Loc) -> Option<bool>;
}

/// What a drive's plot draws besides its channels. Reached by [`MachineView::as_motion`].
pub trait MotionView {
    /// Values the plot marks with a horizontal line on its first plot (TML: the profile's end
    /// position), with their labels.
    fn plot_markers(&self) -> Vec<(String, i64)> {
        Vec::new()
    }

    /// A band the plot draws around a channel: the channel's location name, the half width
    /// and a label (TML with UPGRADE bit 11: TPOS ± POSOKLIM, the in-position window).
    fn plot_band(&self) -> Option<(&'static str, i64, String)> {
        None
    }
}

/// The location named `name`: canonical names and aliases of every space, then the program's
/// own names. Linear in the machine's size; dialects with large spaces override
/// [`MachineView::find`] with a parser.
pub fn find_by_name<M: MachineView + ?Sized>(m: &M, name: &str) -> Option<Loc> {
    let name = name.trim();
    for (s, space) in m.spaces().iter().enumerate() {
        for index in 0..space.len {
            let loc = Loc::new(s as u8, index);
            if let Some(info) = m.info(loc)
                && (info.name.eq_ignore_ascii_case(name)
                    || info.alias.is_some_and(|a| a.eq_ignore_ascii_case(name)))
            {
                return Some(loc);
            }
        }
    }
    m.program_names()
        .into_iter()
        .find(|(n, _)| n == name)
        .map(|(_, loc)| loc)
}

/// The checks every user edit passes: the location exists, may be written, and `value` fits
/// its width. Returns its description.
pub fn check_write<M: MachineView + ?Sized>(
    m: &M,
    loc: Loc,
    value: u64,
) -> Result<LocInfo, WriteError> {
    let info = m.info(loc).ok_or(WriteError::NoSuchLocation)?;
    if !info.editable {
        return Err(WriteError::ReadOnly(info.name));
    }
    if info.width < 64 && value >> info.width != 0 {
        return Err(WriteError::TooWide {
            name: info.name,
            value,
            width: info.width,
        });
    }
    Ok(info)
}

/// Every location of every space, for views and reports that list them all.
pub fn all_locations(m: &dyn MachineView) -> Vec<Loc> {
    m.spaces()
        .iter()
        .enumerate()
        .flat_map(|(s, space)| (0..space.len).map(move |i| Loc::new(s as u8, i)))
        .collect()
}

/// The value of `loc` as a number: sign-extended from its width when the location is signed.
/// `raw`, a bit pattern of `loc`, as the location reads: BCD digits for a DL205 V word
/// (0x0039 → `39`), Q16.16 for a TML fixed, signed or unsigned decimal otherwise. Every text
/// that shows a location's value (status bar, Log, "who wrote this?", check output) uses it.
pub fn show_in_reading(m: &dyn MachineView, loc: Loc, raw: u64) -> String {
    match m.info(loc) {
        Some(info) => info.reading().show(raw, info.width),
        None => raw.to_string(),
    }
}

/// The present value of `loc` as the location reads ([`show_in_reading`]).
pub fn shown_value(m: &dyn MachineView, loc: Loc) -> String {
    show_in_reading(m, loc, m.read(loc))
}

/// The present value of `loc` as a JSON number in the location's reading (a BCD word's
/// digits, a Q16.16's fraction); a BCD word holding a nibble over 9 is the text
/// `"1A (not BCD)"`. For `--trace`, whose readers compare with what the views show.
pub fn json_in_reading(m: &dyn MachineView, loc: Loc) -> serde_json::Value {
    let raw = m.read(loc);
    let Some(info) = m.info(loc) else {
        return serde_json::json!(raw);
    };
    let raw = raw & value::mask(info.width);
    match info.reading() {
        value::Format::Bcd => {
            let digits = value::bcd(raw);
            digits
                .parse::<u64>()
                .map_or_else(|_| serde_json::json!(digits), |n| serde_json::json!(n))
        }
        value::Format::Q16 => {
            serde_json::json!(value::sign_extend(raw, info.width) as f64 / 65536.0)
        }
        value::Format::Signed => serde_json::json!(value::sign_extend(raw, info.width)),
        _ => serde_json::json!(raw),
    }
}

pub fn value_of(m: &dyn MachineView, loc: Loc) -> i64 {
    let raw = m.read(loc);
    match m.info(loc) {
        Some(info) if info.signed => value::sign_extend(raw, info.width),
        _ => raw as i64,
    }
}

/// A machine the debugger can run: the view plus the run loops, generic so that each dialect's
/// hot loop is compiled for it (no dynamic dispatch per executed instruction).
pub trait Machine: MachineView + Clone + PartialEq {
    /// Bytes a clone of this machine holds, its vectors included: what a checkpoint of the
    /// timeline costs (the program is shared, not copied).
    fn snapshot_bytes(&self) -> usize {
        std::mem::size_of_val(self)
    }

    /// Run until the position reaches `limit`, the machine stops, or `stop` returns true.
    /// `stop` is asked before every instruction starts, never in the middle of one; `observe`
    /// is called after every completed tick (traces and checkpoints record through it).
    fn run_observed<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        limit: Pos,
        stop: F,
        observe: O,
    ) -> StopReason;

    /// `run_observed` without an observer, up to a tick.
    fn run_until<F: FnMut(&Self) -> bool>(&mut self, tick_limit: u64, stop: F) -> StopReason {
        self.run_observed(Pos::at_tick(tick_limit), stop, |_| {})
    }

    /// `run_observed` with nothing asked and nothing observed: as fast as the dialect runs
    /// (the headless runner's loop).
    fn run_bare(&mut self, limit: Pos) -> StopReason {
        self.run_observed(limit, |_| false, |_| {})
    }

    /// Run towards `limit` while no location of `quiet.watched` changes, except in the last
    /// tick run, adding the locations written to `quiet.written`: how a timeline records a
    /// stretch in which its trace holds still, without a look at every tick (it samples the
    /// end). May stop short of `limit` (with `TickLimit`) where a tick needs looking at; `None`
    /// when the dialect has no such loop for these locations, and every tick is then observed.
    ///
    /// Before an instruction on a line of `quiet.lines` the run either returns (`TickLimit`) for
    /// the timeline to ask, or asks `stop` itself and returns `Predicate` when it holds; never
    /// both for one boundary. An instruction that would write a location of `quiet.guarded` is
    /// either left to the timeline or is the last one the run runs.
    fn run_quiet(
        &mut self,
        _limit: Pos,
        _quiet: &mut Quiet,
        _stop: &mut dyn FnMut(&Self) -> bool,
    ) -> Option<StopReason> {
        None
    }

    /// Advance to the end of the current tick (one tick; one scan for a PLC).
    fn step_tick(&mut self) {
        let next = Pos::at_tick(self.ticks() + 1);
        self.run_observed(next, |_| false, |_| {});
    }

    /// Advance until the current instruction completes (or the machine stops), at most
    /// `max_ticks`.
    fn step_command(&mut self, max_ticks: u64) -> StopReason {
        let start = self.pos();
        let limit = Pos::at_tick(start.tick.saturating_add(max_ticks));
        self.run_observed(limit, |m| m.pos() > start, |_| {})
    }
}

/// What [`Machine::run_quiet`] keeps still and what it reports.
#[derive(Clone, Debug, Default)]
pub struct Quiet {
    /// Stop before any of these would change.
    pub watched: Vec<Loc>,
    /// Stop before an instruction on one of these lines (breakpoints).
    pub lines: Vec<usize>,
    /// Stop before an instruction that would write one of these (data breakpoints); a machine
    /// that cannot see a write coming has no quiet loop while this holds any.
    pub guarded: Vec<Loc>,
    /// The locations the run wrote.
    pub written: WriteSet,
    /// The machine's own table of where to halt, made from `lines` at its first call.
    pub halts: Vec<bool>,
    /// How many instructions `halts` marks.
    pub halting: usize,
    /// The machine's room for the watched values a run began with.
    pub held: Vec<u64>,
    /// The machine's own table of where its loop hands over, made at its first call.
    pub stops: Vec<bool>,
    /// How many instructions `stops` marks.
    pub stopping: usize,
}

impl Quiet {
    /// `halts` for a program whose instruction `i` is on line `line_of(i)`.
    pub fn halts_for(&mut self, count: usize, line_of: impl Fn(usize) -> usize) -> &[bool] {
        if self.lines.is_empty() {
            self.halts.clear();
            self.halting = 0;
        } else if self.halts.len() != count {
            self.halts = (0..count)
                .map(|i| self.lines.contains(&line_of(i)))
                .collect();
            self.halting = self.halts.iter().filter(|&&h| h).count();
        }
        &self.halts
    }
}

/// Where a fast loop may have been: every instruction it entered at (where it began, each jump's
/// target) up to every one it left from (each jump, where it ended), as one range. A loop that
/// ran in a corner of a program notes only that corner's writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    lo: usize,
    hi: usize,
}

impl Default for Span {
    fn default() -> Self {
        Span {
            lo: usize::MAX,
            hi: 0,
        }
    }
}

impl Span {
    /// A run from `from` (left there) to `to` (entered there).
    #[inline(always)]
    pub fn jump(&mut self, from: usize, to: usize) {
        self.lo = self.lo.min(to);
        self.hi = self.hi.max(from);
    }

    /// The instructions of a program of `len` the loop may have run, while that is a small
    /// part of it for `ran` instructions run (else None: count the whole program).
    pub fn narrow(&self, len: usize, ran: u64) -> Option<std::ops::Range<usize>> {
        let hi = self.hi.min(len.saturating_sub(1));
        let width = hi.checked_sub(self.lo)? as u64 + 1;
        (width <= ran.saturating_mul(4).saturating_add(64)).then_some(self.lo..hi + 1)
    }
}

/// A 256-bit Bloom set of locations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WriteSet([u64; 4]);

impl WriteSet {
    /// Exact for indexes below 256 in one space; spaces and larger indexes share bits.
    #[inline]
    fn bit(loc: Loc) -> (usize, u64) {
        let b = (loc.index ^ u32::from(loc.space).wrapping_mul(0x9E37_79B9)) as usize & 255;
        (b >> 6, 1 << (b & 63))
    }

    #[inline]
    pub fn insert(&mut self, loc: Loc) {
        let (word, bit) = WriteSet::bit(loc);
        self.0[word] |= bit;
    }

    pub fn may_hold(&self, loc: Loc) -> bool {
        let (word, bit) = WriteSet::bit(loc);
        self.0[word] & bit != 0
    }

    pub fn union(&mut self, other: WriteSet) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a |= b;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Span;

    #[test]
    fn a_span_covers_each_stretch_from_its_entry_to_its_exit() {
        // Began at 0, ran to the jump at 4, looped 2..=4 many times, ended at 3.
        let mut span = Span::default();
        span.jump(4, 2);
        span.jump(4, 2);
        span.jump(3, 0);
        assert_eq!(span.narrow(1_000, 20), Some(0..5));
        // A loop at the end of a long program: only its corner.
        let mut late = Span::default();
        late.jump(905, 900);
        late.jump(903, 900);
        assert_eq!(late.narrow(1_000, 100), Some(900..906));
        // Nothing run, or most of a program for few instructions run: no narrowing.
        assert_eq!(Span::default().narrow(1_000, 0), None);
        let mut wide = Span::default();
        wide.jump(990, 3);
        assert_eq!(wide.narrow(1_000, 10), None);
        // The end past the program is cut to it.
        let mut past = Span::default();
        past.jump(12, 8);
        assert_eq!(past.narrow(10, 5), Some(8..10));
    }
}
