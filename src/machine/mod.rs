//! The interpreter core: one module per dialect, and the dialect-neutral view of a machine that
//! the debugger, the GUI and the headless runner use.
//!
//! Nothing here does I/O or knows about egui. A dialect provides an assembler (text → program +
//! diagnostics) and a machine implementing [`Machine`]; the layers above only talk to that trait,
//! so a new dialect plugs in without changing them.

pub mod diagnostics;
pub mod silverlode;

pub use diagnostics::{Diagnostic, Severity};

/// What a machine is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum RunState {
    /// Ready to execute the command at the program counter on the next tick.
    Running,
    /// In the middle of a command that spans ticks.
    Waiting(WaitReason),
    /// The program ended (END, or ran past its last line).
    Ended,
    /// A command error stopped the program; the state is as it was before that command.
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
    /// A status-word condition (WBS): in practice an input.
    Condition,
}

/// Static description of one register.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RegisterInfo {
    /// Canonical name, e.g. `R26`.
    pub name: String,
    /// The dedicated name, e.g. `ACTUAL` for R1.
    pub alias: Option<&'static str>,
    /// A one-line description for tooltips.
    pub description: &'static str,
    /// Width in bits.
    pub width: u8,
}

/// One named bit of a status word.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BitInfo {
    pub bit: u8,
    pub name: &'static str,
    pub description: &'static str,
}

/// A status word with its value and the meaning of its bits.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StatusWordView {
    pub name: &'static str,
    pub width: u8,
    pub value: u32,
    pub bits: &'static [BitInfo],
}

impl StatusWordView {
    pub fn is_set(&self, bit: u8) -> bool {
        self.value >> bit & 1 == 1
    }
}

/// A fault as a user reads it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct FaultInfo {
    /// Stable machine-readable kind, e.g. `divide_by_zero`.
    pub kind: &'static str,
    pub message: String,
    /// 1-based source line of the faulting command.
    pub line: usize,
}

/// A queue decoded from its header registers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct QueueView {
    pub base: usize,
    /// Decoded header; `None` when the registers no longer hold a valid queue header.
    pub header: Option<QueueHeader>,
    /// Raw header words as stored (`R[base]`, `R[base+1]`).
    pub raw: [u32; 2],
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct QueueHeader {
    pub size: usize,
    pub len: usize,
    pub head: usize,
    pub tail: usize,
    /// Register index of slot 0.
    pub first_slot_register: usize,
    /// Every slot's current register value, slot 0 first (occupied or stale).
    pub slots: Vec<i32>,
    /// Occupied values from the tail (oldest) to the head (newest).
    pub items: Vec<i32>,
}

impl QueueHeader {
    /// Whether slot `index` currently holds a queued value.
    pub fn is_occupied(&self, index: usize) -> bool {
        if self.size == 0 || index >= self.size {
            return false;
        }
        (index + self.size - self.tail) % self.size < self.len
    }
}

/// What the last command did to a queue, for views that highlight it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct QueueAccess {
    pub base: usize,
    /// `init`, `push head`, `pop head`, `push tail`, `pop tail`, `read 0`, `read -1`, ...
    pub action: String,
    /// The slot written or read; `None` for init and for failed operations.
    pub slot: Option<usize>,
    /// False when the queue was full or empty (flag variant) or the command faulted.
    pub ok: bool,
    /// Why it failed, e.g. `full` or `empty`.
    pub failure: Option<&'static str>,
}

/// Motion state in the units the registers use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct MotionView {
    pub target: i32,
    pub actual: i32,
    pub error: i32,
    /// Actual velocity, native units (counts/tick × 2^26).
    pub velocity: i32,
    /// A trajectory is running.
    pub moving: bool,
}

/// Why `run_until` returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The machine ended or faulted.
    Stopped,
    /// The tick limit was reached first.
    TickLimit,
    /// The caller's predicate asked to stop (breakpoint, watchpoint, ...).
    Predicate,
}

/// The dialect-neutral face of a machine. Values are raw bit patterns (`u32`) so that a view can
/// show any register in any format; `register_info` tells the width.
pub trait Machine: Clone + PartialEq {
    /// Dialect identifier, e.g. `silverlode`.
    fn dialect(&self) -> &'static str;
    /// Time of one tick in microseconds.
    fn tick_micros(&self) -> u32;

    fn register_count(&self) -> usize;
    fn register_info(&self, index: usize) -> RegisterInfo;
    fn register(&self, index: usize) -> u32;
    /// A user edit. Out-of-range indices are ignored (the views never offer them).
    fn set_register(&mut self, index: usize, value: u32);

    fn status_words(&self) -> Vec<StatusWordView>;
    /// A user edit of one status bit. Returns false when that bit cannot be set by hand.
    fn set_status_bit(&mut self, word: &str, bit: u8, on: bool) -> bool;

    fn input_count(&self) -> usize;
    fn input(&self, index: usize) -> bool;
    fn set_input(&mut self, index: usize, high: bool);

    /// 1-based source line of the command the program counter points at.
    fn pc_line(&self) -> Option<usize>;
    /// Return addresses as 1-based source lines, outermost first.
    fn call_stack_lines(&self) -> Vec<usize>;
    fn run_state(&self) -> RunState;
    fn fault(&self) -> Option<FaultInfo>;
    fn ticks(&self) -> u64;
    fn steps(&self) -> u64;

    fn queues(&self) -> Vec<QueueView>;
    fn motion(&self) -> MotionView;

    /// Registers the last executed command wrote (plus the motion registers while the motor moves).
    fn last_written(&self) -> Vec<usize>;
    /// The last executed command in words, with its operand values. Built on demand.
    fn explain_last(&self) -> Option<String>;
    /// 1-based line of the last executed command.
    fn last_line(&self) -> Option<usize>;
    /// The queue the last command used, if it was a queue operation.
    fn last_queue_access(&self) -> Option<QueueAccess>;

    /// Advance one tick.
    fn step_tick(&mut self);
    /// Advance until the current command completes (or the machine stops), at most `max_ticks`.
    fn step_command(&mut self, max_ticks: u64) -> StopReason;
    /// Run until the tick counter reaches `tick_limit`, the machine stops, or `stop` returns true.
    /// `stop` is asked before every command starts, never in the middle of one.
    fn run_until<F: FnMut(&Self) -> bool>(&mut self, tick_limit: u64, stop: F) -> StopReason {
        self.run_observed(tick_limit, stop, |_| {})
    }
    /// `run_until`, calling `observe` after every tick (traces record through it).
    fn run_observed<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        tick_limit: u64,
        stop: F,
        observe: O,
    ) -> StopReason;
}
