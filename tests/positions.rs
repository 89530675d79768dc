//! (tick, step) positions for a scanned machine: a tick is a whole scan of many instructions;
//! the debugger steps, steps back, breaks and edits *inside* a scan, and replay reproduces it
//! exactly. SilverLode fills a tick with one command, so these run on a small scanned machine
//! written here against the same traits every dialect implements.

use std::any::Any;
use std::sync::Arc;
use std::time::Duration;

use servoscope::debugger::history::{Change, UserEvent};
use servoscope::debugger::{Debugger, Event, Speed, engine};
use servoscope::machine::registry::{
    AtLimit, Dialect, OpenResult, Settings, TokenClass, Vocabulary,
};
use servoscope::machine::{
    Diagnostic, FaultInfo, Loc, LocInfo, Machine, MachineView, Pos, RunState, SpaceInfo, SpaceKind,
    StopReason, WriteError,
};

/// `ADD v k` (V[v] += k), `COPY a b` (V[b] = V[a]), `IN v` (V[v] = the input), then END.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Add(usize, u16),
    Copy(usize, usize),
    In(usize),
    End,
}

/// A scanned PLC in miniature: every scan runs each instruction once, END closes the scan.
#[derive(Clone, Debug, PartialEq)]
struct Scanned {
    program: Arc<Vec<Op>>,
    v: [u16; 8],
    input: bool,
    tick: u64,
    /// Instructions already run in this scan (= index of the next one).
    step: u32,
    steps: u64,
    last: Option<usize>,
}

const V: u8 = 0;
const IN: u8 = 1;

fn v(i: u32) -> Loc {
    Loc::new(V, i)
}

impl Scanned {
    fn execute(&mut self) {
        let at = self.step as usize;
        match self.program[at] {
            Op::Add(r, k) => self.v[r] = self.v[r].wrapping_add(k),
            Op::Copy(a, b) => self.v[b] = self.v[a],
            Op::In(r) => self.v[r] = u16::from(self.input),
            Op::End => {}
        }
        self.last = Some(at);
        self.steps += 1;
        self.step += 1;
        if self.step as usize == self.program.len() {
            self.step = 0;
            self.tick += 1;
        }
    }
}

impl MachineView for Scanned {
    fn dialect(&self) -> &'static str {
        "scanned"
    }
    fn tick_micros(&self) -> u32 {
        10_000
    }
    fn spaces(&self) -> Vec<SpaceInfo> {
        vec![
            SpaceInfo {
                name: "V",
                title: "Words",
                kind: SpaceKind::Registers,
                len: 8,
            },
            SpaceInfo {
                name: "X",
                title: "Inputs",
                kind: SpaceKind::Inputs,
                len: 1,
            },
        ]
    }
    fn info(&self, loc: Loc) -> Option<LocInfo> {
        match (loc.space, loc.index) {
            (V, i @ 0..8) => Some(LocInfo::word(format!("V{i}"), 16, false)),
            (IN, 0) => Some(LocInfo::word("X0".to_string(), 1, false)),
            _ => None,
        }
    }
    fn read(&self, loc: Loc) -> u64 {
        match (loc.space, loc.index) {
            (V, i @ 0..8) => u64::from(self.v[i as usize]),
            (IN, 0) => u64::from(self.input),
            _ => 0,
        }
    }
    fn write(&mut self, loc: Loc, value: u64) -> Result<(), WriteError> {
        match (loc.space, loc.index) {
            (V, i @ 0..8) => self.v[i as usize] = value as u16,
            (IN, 0) => self.input = value != 0,
            _ => return Err(WriteError::NoSuchLocation),
        }
        Ok(())
    }
    fn used(&self) -> Vec<Loc> {
        Vec::new()
    }
    fn program_names(&self) -> Vec<(String, Loc)> {
        Vec::new()
    }
    fn pc_line(&self) -> Option<usize> {
        Some(self.step as usize + 1)
    }
    fn call_stack_lines(&self) -> Vec<usize> {
        Vec::new()
    }
    fn run_state(&self) -> RunState {
        RunState::Running
    }
    fn fault(&self) -> Option<FaultInfo> {
        None
    }
    fn pos(&self) -> Pos {
        Pos {
            tick: self.tick,
            step: self.step,
        }
    }
    fn steps(&self) -> u64 {
        self.steps
    }
    fn last_written(&self) -> Vec<Loc> {
        Vec::new()
    }
    fn explain_last(&self) -> Option<String> {
        None
    }
    fn last_line(&self) -> Option<usize> {
        self.last.map(|i| i + 1)
    }
    fn report_json(&self) -> String {
        String::new()
    }
    fn report_text(&self) -> String {
        String::new()
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

impl Machine for Scanned {
    fn run_observed<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        limit: Pos,
        mut stop: F,
        mut observe: O,
    ) -> StopReason {
        loop {
            if self.pos() >= limit {
                return StopReason::TickLimit;
            }
            if stop(self) {
                return StopReason::Predicate;
            }
            let tick = self.tick;
            self.execute();
            if self.tick > tick {
                observe(self);
            }
        }
    }
}

fn parse(source: &str) -> Result<Scanned, Vec<Diagnostic>> {
    let mut program = Vec::new();
    let mut errors = Vec::new();
    for (i, line) in source.lines().enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let num = |k: usize| words.get(k).and_then(|w| w.parse::<u16>().ok());
        let op = match (words.first().copied(), num(1), num(2)) {
            (None, ..) => continue,
            (Some("ADD"), Some(r), Some(k)) if r < 8 => Op::Add(r.into(), k),
            (Some("COPY"), Some(a), Some(b)) if a < 8 && b < 8 => Op::Copy(a.into(), b.into()),
            (Some("IN"), Some(r), None) if r < 8 => Op::In(r.into()),
            (Some("END"), None, None) => Op::End,
            _ => {
                errors.push(Diagnostic::error(i + 1, 1, line.len(), "bad instruction"));
                continue;
            }
        };
        program.push(op);
    }
    if program.last() != Some(&Op::End) {
        program.push(Op::End);
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(Scanned {
        program: Arc::new(program),
        v: [0; 8],
        input: false,
        tick: 0,
        step: 0,
        steps: 0,
        last: None,
    })
}

fn open(source: &str, _: &Settings) -> OpenResult {
    parse(source).map(engine)
}

fn plain(line: &str) -> Vec<TokenClass> {
    vec![TokenClass::Plain; line.chars().count()]
}

#[cfg(feature = "gui")]
fn no_panels() -> Vec<Box<dyn servoscope::ui::panels::DialectPanel>> {
    Vec::new()
}

static SCANNED: Dialect = Dialect {
    name: "scanned",
    display_name: "A scanned test machine",
    extensions: &["scan"],
    vocabulary: Vocabulary {
        tick: "scan",
        ticks: "scans",
        step: "instruction",
        steps: "instructions",
    },
    examples: &[],
    lessons: &[],
    settings: &[],
    default_channels: &[],
    default_max_ticks: 1,
    at_limit: AtLimit::Ended,
    new_program: "END\n",
    open,
    classify: plain,
    #[cfg(feature = "gui")]
    panels: no_panels,
};

/// Line 1 adds 1 to V0, line 2 copies V0 to V1, line 3 reads the input into V2, line 4 adds
/// 10 to V3, line 5 is END: a scan is five steps.
const PROGRAM: &str = "ADD 0 1\nCOPY 0 1\nIN 2\nADD 3 10\nEND";

fn scanned(d: &Debugger) -> &Scanned {
    d.machine_as::<Scanned>().expect("the scanned machine")
}

fn at(tick: u64, step: u32) -> Pos {
    Pos { tick, step }
}

#[test]
fn steps_walk_through_a_scan_and_back() {
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    assert!(d.diagnostics().is_empty());
    let mut seen = vec![d.pos()];
    for _ in 0..7 {
        d.step_command();
        seen.push(d.pos());
    }
    assert_eq!(
        seen,
        [
            at(0, 0),
            at(0, 1),
            at(0, 2),
            at(0, 3),
            at(0, 4),
            at(1, 0),
            at(1, 1),
            at(1, 2)
        ],
        "one instruction per step; END closes the scan"
    );
    assert_eq!(d.machine().pc_line(), Some(3), "about to read the input");
    assert_eq!(
        scanned(&d).v[..2],
        [2, 2],
        "scan 1 ran its ADD and its COPY"
    );

    d.step_back_command();
    assert_eq!(d.pos(), at(1, 1), "back one instruction inside the scan");
    d.step_back_command();
    d.step_back_command();
    assert_eq!(d.pos(), at(0, 4), "back across the scan boundary to END");
    d.step_tick();
    assert_eq!(d.pos(), at(1, 0), "the rest of the scan");
    d.step_command();
    d.step_tick();
    assert_eq!(d.pos(), at(2, 0));
    d.step_back_tick();
    assert_eq!(d.pos(), at(1, 0), "to the start of the previous scan");
    d.goto(at(1, 3));
    assert_eq!(d.pos(), at(1, 3));
    d.step_back_tick();
    assert_eq!(d.pos(), at(1, 0), "to the start of this scan");
}

/// A straight walk, one instruction at a time, with edits at positions inside scans; returns
/// the machine at every position.
fn straight(d: &mut Debugger, edits: &[(Pos, Loc, u64)], scans: u64) -> Vec<Scanned> {
    let mut states = vec![scanned(d).clone()];
    while d.pos() < at(scans, 0) {
        let now = d.pos();
        for &(_, loc, value) in edits.iter().filter(|e| e.0 == now) {
            d.set_value(loc, value).expect("an edit");
            *states.last_mut().expect("one state") = scanned(d).clone();
        }
        d.step_command();
        states.push(scanned(d).clone());
    }
    states
}

#[test]
fn edits_inside_a_scan_replay_exactly() {
    let edits = [
        (at(1, 2), v(0), 100),
        (at(2, 1), Loc::new(IN, 0), 1),
        (at(3, 4), v(3), 7),
        (at(5, 0), v(5), 9),
    ];
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    let reference = straight(&mut d, &edits, 8);
    assert_eq!(reference.len(), 8 * 5 + 1);
    // The edit at (1, 2) came after COPY of scan 1: V1 keeps 2, V0 jumps to 100.
    let after = &reference[5 + 2]; // scan 1, after its second instruction
    assert_eq!((after.v[0], after.v[1]), (100, 2));
    // X0 switched on at (2, 1) is read by IN at step 2 of that same scan.
    assert_eq!(reference[2 * 5 + 3].v[2], 1);

    // Every position, reached by going there, is the straight walk's state.
    for (i, want) in reference.iter().enumerate().rev() {
        let pos = at(i as u64 / 5, i as u32 % 5);
        d.goto(pos);
        assert_eq!(scanned(&d), want, "at {pos}");
    }

    // A debugger restored from the events (as a session does) walks the same states.
    let events: Vec<UserEvent> = d.events().to_vec();
    assert_eq!(events.len(), edits.len());
    let mut r = Debugger::restore(
        &SCANNED,
        "p.scan",
        PROGRAM,
        &Settings::new(),
        [],
        None,
        events,
        at(8, 0),
    )
    .expect("restores");
    assert_eq!(r.furthest(), at(8, 0));
    for (i, want) in reference.iter().enumerate() {
        r.goto(at(i as u64 / 5, i as u32 % 5));
        assert_eq!(scanned(&r), want, "restored, step {i}");
    }
}

#[test]
fn an_edit_in_the_past_inside_a_scan_discards_the_future() {
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    for _ in 0..12 {
        d.step_command();
    }
    assert_eq!(d.pos(), at(2, 2));
    d.goto(at(1, 3));
    d.set_value(v(7), 42).expect("an edit");
    assert_eq!(d.event(), Some(&Event::FutureDiscarded(1)));
    assert_eq!(d.furthest(), at(1, 3), "the recorded future is gone");
    assert_eq!(
        d.events()[0],
        UserEvent {
            at: at(1, 3),
            loc: v(7),
            change: Change::Set(42)
        }
    );
}

#[test]
fn breakpoints_stop_before_their_instruction_in_every_scan() {
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    d.set_speed(Speed::Unlimited);
    d.toggle_breakpoint(4);
    let mut stops = Vec::new();
    for _ in 0..3 {
        d.run();
        while d.advance(0.016, Duration::from_secs(5)) {}
        assert_eq!(d.event(), Some(&Event::Breakpoint(4)));
        stops.push(d.pos());
    }
    assert_eq!(stops, [at(0, 3), at(1, 3), at(2, 3)]);
    d.step_tick();
    d.reverse_continue();
    assert_eq!(d.pos(), at(2, 3), "the last hit before here");
    d.reverse_continue();
    assert_eq!(d.pos(), at(1, 3));
}

#[test]
fn stepping_a_scan_and_the_status_words() {
    let mut d = Debugger::with_dialect(&SCANNED, "p.scan", PROGRAM);
    assert_eq!(d.dialect().vocabulary.tick, "scan");
    d.step_tick();
    d.step_tick();
    assert_eq!(d.pos(), at(2, 0));
    assert_eq!(
        d.machine().steps(),
        10,
        "five instructions a scan, END included"
    );
    assert_eq!(scanned(&d).v[3], 20);
}
