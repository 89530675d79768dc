//! What the debugger last did or met, in words for the status bar.

/// Why the debugger last stopped, for the status bar (sessions keep it).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Event {
    Breakpoint(usize),
    /// "Break on error": the error lamp turned on; the line is the next instruction's.
    ErrorLamp(usize),
    ReachedLine(usize),
    ReachedTick(u64),
    Paused(Option<usize>),
    Stepped,
    SteppedBack,
    /// Reverse-continue found no earlier breakpoint: back at the start.
    NoEarlierBreakpoint,
    Ended,
    Faulted,
    Reset,
    /// The text has errors: nothing runs until they are fixed.
    NotAssembled(usize),
    Assembled,
    /// An edit in the past rewrote history from this tick on.
    FutureDiscarded(u64),
    /// A data breakpoint: `location` changed from `old` to `new` by the instruction on `line`.
    Watchpoint {
        location: String,
        line: usize,
        /// The values as the location reads (a DL205 V word's BCD digits).
        old: String,
        new: String,
    },
    /// "Who wrote this?" went to the write of `location` at `at`: by the instruction on
    /// `line`, or by the user's edit (no line).
    WrittenBy {
        location: String,
        at: crate::machine::Pos,
        line: Option<usize>,
        explanation: String,
    },
    /// "Who wrote this?" found no write: the location holds its value from the start.
    NeverWritten(String),
}

impl Event {
    /// The event in words; `tick` is the dialect's word for a tick ("tick" or "scan").
    pub fn describe(&self, tick: &str) -> String {
        self.describe_with(tick, &|l| format!("line {l}"))
    }

    /// [`Event::describe`] with lines in the words `at_line` gives them ("line 12", or
    /// "main.tml:12" in a program of several files).
    pub fn describe_with(&self, tick: &str, at_line: &dyn Fn(usize) -> String) -> String {
        match self {
            Event::Breakpoint(l) => format!("Breakpoint hit at {}", at_line(*l)),
            Event::ErrorLamp(l) => format!("Execution error: stopped before {}", at_line(*l)),
            Event::ReachedLine(l) => format!("Reached {}", at_line(*l)),
            Event::ReachedTick(t) => format!("At {tick} {t}"),
            Event::Paused(Some(l)) => format!("Paused at {}", at_line(*l)),
            Event::Paused(None) => "Paused".to_string(),
            Event::Stepped => "Stepped".to_string(),
            Event::SteppedBack => "Stepped back".to_string(),
            Event::NoEarlierBreakpoint => "No earlier breakpoint: back at the start".to_string(),
            Event::Ended => "Program ended".to_string(),
            Event::Faulted => "Stopped on a fault".to_string(),
            Event::Reset => "Reset to the start".to_string(),
            Event::NotAssembled(n) => format!("{n} error(s) in the program: fix them to run"),
            Event::Assembled => "Program assembled".to_string(),
            Event::FutureDiscarded(t) => {
                format!("Edited at {tick} {t}: the recorded future after it was discarded")
            }
            Event::Watchpoint {
                location,
                line,
                old,
                new,
            } => format!("{location} written at {}: {old} -> {new}", at_line(*line)),
            Event::WrittenBy {
                location,
                at,
                line: Some(l),
                explanation,
            } => format!(
                "{location} was written at {}, {}: {explanation}",
                position(tick, *at),
                at_line(*l)
            ),
            Event::WrittenBy {
                location,
                at,
                line: None,
                explanation,
            } => format!(
                "{location} was set at {} by {explanation}",
                position(tick, *at)
            ),
            Event::NeverWritten(name) => {
                format!("Nothing wrote {name} before here: it holds its value from the start")
            }
        }
    }
}

/// A position in words: "scan 1186, instruction 2" (the second instruction of that scan ran
/// just before it), or "tick 40" at a tick's start. `1186.2` read as a fraction of a scan.
fn position(tick: &str, at: crate::machine::Pos) -> String {
    if at.step == 0 {
        format!("{tick} {}", at.tick)
    } else {
        format!("{tick} {}, instruction {}", at.tick, at.step)
    }
}
