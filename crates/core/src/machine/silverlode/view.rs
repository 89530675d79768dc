//! SilverLode as the debugger, the views and the runner see it: its storage spaces (R0–R199,
//! the status words, the three inputs), its queues decoded, and its runner report (spec §8).

use std::any::Any;

use serde_json::{Value, json};

use crate::machine::JsonMap;
use std::fmt::Write as _;
use std::sync::Arc;

use super::motion::FRAC;
use super::program::{ALIASES, ClcOp, ExtOp, Instr};
use super::{FaultKind, ISW_BITS, Outcome, PSW_BITS, REGISTERS, RawQueue, SilverLode, TICK_MICROS};
use crate::machine::{
    FaultInfo, Loc, LocInfo, Machine, MachineView, Pos, RunState, SpaceInfo, SpaceKind, StopReason,
    WriteError,
};

/// Storage spaces, in the order [`MachineView::spaces`] lists them.
pub const REGS: u8 = 0;
pub const STATUS: u8 = 1;
pub const INPUTS: u8 = 2;
pub const ISW: Loc = Loc::new(STATUS, 0);
pub const PSW: Loc = Loc::new(STATUS, 1);

/// The register at `index`.
pub const fn reg(index: u32) -> Loc {
    Loc::new(REGS, index)
}

/// Input IO(n+1).
pub const fn io(index: u32) -> Loc {
    Loc::new(INPUTS, index)
}

/// ISW bits a user cannot set: the inputs (switched with IO1–IO3) and the always-on driver.
const ISW_FIXED: u16 = 0b1111 << 4;
const INPUT_NAMES: [&str; 3] = ["IO1", "IO2", "IO3"];

/// Native velocity units per count per tick (counts/tick × 2^26).
pub const VELOCITY_ONE: i64 = 1 << FRAC;

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

impl SilverLode {
    /// Every queue the program initialised, decoded from its registers as they are now.
    pub fn queues(&self) -> Vec<QueueView> {
        let regs = self.regs();
        self.state()
            .queue_bases
            .iter()
            .map(|&base| {
                let base = base as usize;
                let raw = [
                    regs[base] as u32,
                    regs.get(base + 1).map_or(0, |&v| v as u32),
                ];
                let header = RawQueue::decode(regs, base).map(|q| {
                    let first = base + 2;
                    let slots: Vec<i32> = regs[first..first + q.size as usize].to_vec();
                    let items = (0..q.len)
                        .map(|i| slots[((q.tail + i) % q.size) as usize])
                        .collect();
                    QueueHeader {
                        size: q.size as usize,
                        len: q.len as usize,
                        head: q.head as usize,
                        tail: q.tail as usize,
                        first_slot_register: first,
                        slots,
                        items,
                    }
                });
                QueueView { base, header, raw }
            })
            .collect()
    }
}

impl SilverLode {
    /// The queue the last command used, derived from the command and its record.
    pub fn last_queue_access(&self) -> Option<QueueAccess> {
        let last = self.s.last;
        let (op, base) = match *self.program.instrs.get(last.pc as usize)? {
            Instr::Cld { op, reg1, .. } | Instr::Clx { op, reg1, .. } if op.is_queue() => {
                (op, reg1 as usize)
            }
            _ => return None,
        };
        let [h0, h1, d, _] = last.vals;
        let q = RawQueue::from_words(h0, h1);
        let size = i64::from(q.size.max(1));
        let (head, tail) = (i64::from(q.head), i64::from(q.tail));
        let (action, slot) = match op {
            ExtOp::QInit => ("init".to_string(), None),
            ExtOp::QPushHead | ExtOp::QPushHeadErr => ("push head".to_string(), Some(head)),
            ExtOp::QPopHead | ExtOp::QPopHeadErr => ("pop head".to_string(), Some(head - 1)),
            ExtOp::QPushTail | ExtOp::QPushTailErr => ("push tail".to_string(), Some(tail - 1)),
            ExtOp::QPopTail | ExtOp::QPopTailErr => ("pop tail".to_string(), Some(tail)),
            _ => {
                let n = i64::from(d);
                let slot = if n >= 0 { head - 1 - n } else { tail - 1 - n };
                (format!("read {n}"), Some(slot))
            }
        };
        let ok = last.outcome == Outcome::Done;
        let failure = (!ok).then(|| match (op, self.s.fault.as_ref().map(|f| f.kind)) {
            (_, Some(FaultKind::BadQueue)) if last.outcome == Outcome::Faulted => {
                "not a valid queue"
            }
            (
                ExtOp::QPushHead | ExtOp::QPushTail | ExtOp::QPushHeadErr | ExtOp::QPushTailErr,
                _,
            ) => "full",
            (ExtOp::QRead, _) => "no such element",
            _ => "empty",
        });
        Some(QueueAccess {
            base,
            action,
            slot: slot.filter(|_| ok).map(|s| s.rem_euclid(size) as usize),
            ok,
            failure,
        })
    }

    /// Registers the last command wrote, derived from the command and its record.
    pub fn written_by_last(&self) -> Vec<usize> {
        let mut out = Vec::new();
        self.each_written_register(|r| out.push(r));
        out.sort_unstable();
        out.dedup();
        out
    }

    /// [`SilverLode::written_by_last`] without a list (a register may come twice).
    #[inline]
    fn each_written_register<F: FnMut(usize)>(&self, mut f: F) {
        self.each_register_the_command_wrote(&mut f);
        if self.s.motion_ticked {
            [0, 1, 6, 7].into_iter().for_each(f);
        }
    }

    /// The registers the last command wrote, without the motion model's.
    #[inline]
    fn each_register_the_command_wrote<F: FnMut(usize)>(&self, mut f: F) {
        let last = self.s.last;
        if last.outcome != Outcome::Done {
            return;
        }
        let Some(&instr) = self.program.instrs.get(last.pc as usize) else {
            return;
        };
        match instr {
            Instr::Clc { op, reg } => match op {
                ClcOp::Clear
                | ClcOp::Save
                | ClcOp::Abs
                | ClcOp::Neg
                | ClcOp::Inc
                | ClcOp::Dec
                | ClcOp::Shl
                | ClcOp::ShrS
                | ClcOp::ShrU
                | ClcOp::CopyWordHiReg
                | ClcOp::CopyWordLoReg => f(reg as usize),
                ClcOp::SaveRef => f(last.vals[1] as usize),
                ClcOp::SubTarget => [0, 1, 6].into_iter().for_each(&mut f),
                _ => f(10),
            },
            Instr::Cld { op, res, reg1, .. } | Instr::Clx { op, res, reg1, .. } => {
                let (res, base) = (res as usize, reg1 as usize);
                match op {
                    ExtOp::MultU64 => [res, res + 1].into_iter().for_each(&mut f),
                    ExtOp::QInit => [base, base + 1, res].into_iter().for_each(&mut f),
                    ExtOp::QRead => f(res),
                    ExtOp::QPushHead | ExtOp::QPushHeadErr => {
                        let head = RawQueue::from_words(last.vals[0], last.vals[1]).head as usize;
                        [base + 2 + head, base, base + 1, res]
                            .into_iter()
                            .for_each(&mut f);
                    }
                    ExtOp::QPushTail | ExtOp::QPushTailErr => {
                        let q = RawQueue::decode(&self.s.regs, base);
                        if let Some(q) = q {
                            f(base + 2 + q.tail as usize);
                        }
                        [base, base + 1, res].into_iter().for_each(&mut f);
                    }
                    _ if op.is_queue() => [base, base + 1, res].into_iter().for_each(&mut f),
                    _ => f(res),
                }
            }
            Instr::Wrp { reg, .. } => f(reg as usize),
            Instr::Ztp => [0, 1, 6].into_iter().for_each(&mut f),
            Instr::Ttp => f(0),
            _ => {}
        }
    }
}

impl MachineView for SilverLode {
    fn dialect(&self) -> &'static str {
        "silverlode"
    }
    fn tick_micros(&self) -> u32 {
        TICK_MICROS
    }
    fn spaces(&self) -> Vec<SpaceInfo> {
        vec![
            SpaceInfo {
                name: "R",
                title: "Registers",
                kind: SpaceKind::Registers,
                len: REGISTERS as u32,
            },
            SpaceInfo {
                name: "status",
                title: "Status words",
                kind: SpaceKind::Flags,
                len: 2,
            },
            SpaceInfo {
                name: "IO",
                title: "Inputs",
                kind: SpaceKind::Inputs,
                len: 3,
            },
        ]
    }
    fn info(&self, loc: Loc) -> Option<LocInfo> {
        match (loc.space, loc.index) {
            (REGS, r) if (r as usize) < REGISTERS => {
                let alias = ALIASES.iter().find(|a| u32::from(a.register) == r);
                Some(LocInfo {
                    alias: alias.map(|a| a.name),
                    description: alias.map_or("user register", |a| a.description),
                    ..LocInfo::word(format!("R{r}"), 32, true)
                })
            }
            (STATUS, w @ 0..=1) => Some(LocInfo {
                description: if w == 0 {
                    "input status word"
                } else {
                    "program status word"
                },
                bits: if w == 0 { ISW_BITS } else { PSW_BITS },
                format: Some(crate::machine::Format::Binary),
                ..LocInfo::word(if w == 0 { "ISW" } else { "PSW" }.to_string(), 16, false)
            }),
            (INPUTS, i @ 0..=2) => Some(LocInfo {
                description: "digital input (ISW bits 4–6)",
                ..LocInfo::word(INPUT_NAMES[i as usize].to_string(), 1, false)
            }),
            _ => None,
        }
    }
    fn read(&self, loc: Loc) -> u64 {
        match (loc.space, loc.index) {
            (REGS, r) => self
                .regs()
                .get(r as usize)
                .map_or(0, |&v| u64::from(v as u32)),
            (STATUS, 0) => u64::from(self.isw()),
            (STATUS, 1) => u64::from(self.psw()),
            (INPUTS, i @ 0..=2) => u64::from(self.state().inputs >> i & 1),
            _ => 0,
        }
    }
    fn write(&mut self, loc: Loc, value: u64) -> Result<(), WriteError> {
        let info = self.info(loc).ok_or(WriteError::NoSuchLocation)?;
        if value > crate::machine::value::mask(info.width) {
            return Err(WriteError::TooWide {
                name: info.name,
                value,
                width: info.width,
            });
        }
        match (loc.space, loc.index) {
            (REGS, r) => self.set_reg(r as usize, value as u32 as i32),
            (STATUS, w) => {
                let (current, named) = if w == 0 {
                    (self.isw(), ISW_BITS)
                } else {
                    (self.psw(), PSW_BITS)
                };
                let allowed = named.iter().fold(0u16, |m, b| m | 1 << b.bit)
                    & if w == 0 { !ISW_FIXED } else { u16::MAX };
                let changed = current ^ value as u16;
                if changed & !allowed != 0 {
                    let bit = changed & !allowed;
                    return Err(WriteError::ReadOnly(format!(
                        "{} bit {}",
                        info.name,
                        bit.trailing_zeros()
                    )));
                }
                self.set_status_word(w == 0, value as u16);
            }
            (INPUTS, i) => self.set_io(i as usize, value != 0),
            _ => return Err(WriteError::NoSuchLocation),
        }
        Ok(())
    }
    fn find(&self, name: &str) -> Option<Loc> {
        let name = name.trim();
        let upper = name.to_ascii_uppercase();
        if let Some(n) = upper.strip_prefix('R')
            && !n.is_empty()
            && n.chars().all(|c| c.is_ascii_digit())
        {
            return n
                .parse::<u32>()
                .ok()
                .filter(|&r| (r as usize) < REGISTERS)
                .map(reg);
        }
        crate::machine::find_by_name(self, name)
    }
    fn used(&self) -> Vec<Loc> {
        self.program()
            .used_registers
            .iter()
            .map(|&r| reg(u32::from(r)))
            .collect()
    }
    fn program_names(&self) -> Vec<(String, Loc)> {
        self.program()
            .register_names
            .iter()
            .map(|(n, r)| (n.clone(), reg(u32::from(*r))))
            .collect()
    }
    fn program_constants(&self) -> Vec<(String, i64)> {
        self.program().constants.clone()
    }
    fn pc_line(&self) -> Option<usize> {
        self.line_of(self.pc())
    }
    fn call_depth(&self) -> usize {
        self.state().sp as usize
    }
    fn call_stack_lines(&self) -> Vec<usize> {
        let s = self.state();
        s.stack[..s.sp as usize]
            .iter()
            .map(|&pc| self.line_of(pc).unwrap_or(0))
            .collect()
    }
    fn run_state(&self) -> RunState {
        self.state().run
    }
    fn fault(&self) -> Option<FaultInfo> {
        let s = self.state();
        if s.run != RunState::Faulted {
            return None;
        }
        s.fault.as_ref().map(|f| FaultInfo {
            kind: f.kind.code(),
            message: f.message.clone(),
            line: self.line_of(f.pc).unwrap_or(0),
        })
    }
    fn pos(&self) -> Pos {
        Pos::at_tick(self.state().ticks)
    }
    fn ticks(&self) -> u64 {
        self.state().ticks
    }
    fn steps(&self) -> u64 {
        self.state().steps
    }
    fn last_written(&self) -> Vec<Loc> {
        self.written_by_last()
            .into_iter()
            .map(|r| reg(r as u32))
            .collect()
    }
    fn for_each_written(&self, f: &mut dyn FnMut(Loc)) {
        self.each_written_register(|r| f(reg(r as u32)));
    }
    fn instruction_written(&self) -> Vec<Loc> {
        let mut regs = Vec::new();
        self.each_register_the_command_wrote(|r| regs.push(r));
        regs.sort_unstable();
        regs.dedup();
        let mut out: Vec<Loc> = regs.into_iter().map(|r| reg(r as u32)).collect();
        // Every calculation and queue command sets the ISW flags (spec §4); DLY its DELAY_DONE;
        // a failed flag-variant queue command its NEGATIVE flag.
        let last = self.s.last;
        let sets_isw = matches!(last.outcome, Outcome::Done | Outcome::Failed)
            && matches!(
                self.program.instrs.get(last.pc as usize),
                Some(Instr::Clc { .. } | Instr::Cld { .. } | Instr::Clx { .. } | Instr::Dly { .. })
            );
        if sets_isw {
            out.push(Loc::new(1, 0));
        }
        // END sets PSW bit 13 (program done).
        if last.outcome == Outcome::Done
            && matches!(self.program.instrs.get(last.pc as usize), Some(Instr::End))
        {
            out.push(Loc::new(1, 1));
        }
        out
    }
    fn note_writes(&self, set: &mut crate::machine::WriteSet) {
        self.each_written_register(|r| set.insert(reg(r as u32)));
    }
    fn explain_last(&self) -> Option<String> {
        super::explain::explain(self)
    }
    fn last_line(&self) -> Option<usize> {
        self.line_of(self.state().last.pc)
    }
    /// PSW bit 12: a command error (also when a CER handler caught it and the program goes on).
    fn error_lamp(&self) -> bool {
        self.psw() >> 12 & 1 == 1
    }
    fn report_json(&self, out: &mut JsonMap) {
        let registers: JsonMap = (self.regs().iter().enumerate())
            .map(|(i, v)| (i.to_string(), json!(v)))
            .collect();
        out.insert("registers".into(), registers.into());
        out.insert("isw".into(), json!(self.isw()));
        out.insert("psw".into(), json!(self.psw()));
        // A header the program overwrote is not a queue any more; the runner lists only queues
        // it can decode.
        let queues: Vec<Value> = (self.queues().into_iter())
            .filter_map(|q| {
                let h = q.header?;
                Some(json!({
                    "base": q.base,
                    "size": h.size,
                    "len": h.len,
                    "head": h.head,
                    "tail": h.tail,
                    "items": h.items,
                }))
            })
            .collect();
        out.insert("queues".into(), queues.into());
    }
    fn report_text(&self) -> String {
        let mut out = String::new();
        let (isw, psw) = (self.isw(), self.psw());
        let _ = writeln!(
            out,
            "ISW: 0x{isw:04X} ({isw:016b})  PSW: 0x{psw:04X} ({psw:016b})"
        );
        let nonzero: Vec<String> = self
            .regs()
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0)
            .map(|(i, v)| format!("R{i}={v}"))
            .collect();
        if nonzero.is_empty() {
            let _ = writeln!(out, "registers: all zero");
        } else {
            let _ = writeln!(out, "registers (non-zero): {}", nonzero.join(" "));
        }
        for q in self.queues() {
            if let Some(h) = q.header {
                let _ = writeln!(
                    out,
                    "queue R{}: {}/{} head {} tail {} items (oldest first) {:?}",
                    q.base, h.len, h.size, h.head, h.tail, h.items
                );
            }
        }
        out
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

impl Machine for SilverLode {
    fn snapshot_bytes(&self) -> usize {
        std::mem::size_of_val(self) + std::mem::size_of_val(&self.s.queue_bases[..])
    }

    fn run_observed<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        limit: Pos,
        stop: F,
        observe: O,
    ) -> StopReason {
        // Every position of a SilverLode run is at a tick boundary: (t, s > 0) lies between
        // (t, 0) and (t + 1, 0), so reaching it means finishing tick t.
        let tick_limit = limit.tick.saturating_add(u64::from(limit.step > 0));
        self.run_fast(tick_limit, stop, observe)
    }

    fn run_bare(&mut self, limit: Pos) -> StopReason {
        SilverLode::run_to_tick(self, limit.tick.saturating_add(u64::from(limit.step > 0)))
    }

    /// Plain commands run in the fast loop until one would write a watched register; watching
    /// anything but registers (a status word changes with every calculation) is not supported.
    /// Asks `stop` itself before a breakpoint line whose command the fast loop runs, so a
    /// conditional breakpoint costs a question, not a hand-over.
    fn run_quiet(
        &mut self,
        limit: Pos,
        quiet: &mut crate::machine::Quiet,
        stop: &mut dyn FnMut(&Self) -> bool,
    ) -> Option<StopReason> {
        // Plotted registers and those of data breakpoints: a write to one ends the stretch.
        let mut guard = [false; REGISTERS];
        for loc in quiet.watched.iter().chain(&quiet.guarded) {
            if loc.space != REGS || loc.index as usize >= REGISTERS {
                return None;
            }
            guard[loc.index as usize] = true;
        }
        let tick_limit = limit.tick.saturating_add(u64::from(limit.step > 0));
        let program = Arc::clone(&self.program);
        quiet.halts_for(program.instrs.len(), |i| {
            program.lines.get(i).map_or(0, |&l| l as usize)
        });
        if quiet.halting * 4 > program.instrs.len() {
            // Breakpoints on most lines: a question at nearly every command, which the
            // timeline's own loop asks as cheaply.
            return None;
        }
        let guarded = |op: super::program::Op| {
            let mut hit = false;
            op.each_write(|r| hit |= guard[usize::from(r)]);
            hit
        };
        // One look per command in the loop: a breakpoint line, or a write to a plotted register.
        if quiet.stops.len() != program.flat.len() {
            quiet.stops = (program.flat.iter().enumerate())
                .map(|(i, &op)| quiet.halts.get(i) == Some(&true) || guarded(op))
                .collect();
            quiet.stopping = quiet.stops.iter().filter(|&&s| s).count();
        }
        let (halts, stops) = (&quiet.halts, &quiet.stops);
        let mut span = crate::machine::Span::default();
        let mut run = |m: &mut Self, max: u64, asked: bool| {
            // Nothing to stop before: the loop that looks at no table.
            if quiet.stopping == 0 {
                m.run_plain::<false, true>(max, &[], asked, &mut span)
            } else {
                m.run_plain::<true, true>(max, stops, asked, &mut span)
            }
        };
        let start = self.s.steps;
        let reason = loop {
            if matches!(self.s.run, RunState::Ended | RunState::Faulted) {
                break StopReason::Stopped;
            }
            if self.s.ticks >= tick_limit {
                break StopReason::TickLimit;
            }
            let left = tick_limit - self.s.ticks;
            if run(self, left, false) > 0 {
                continue;
            }
            // Halted before a breakpoint line while the loop could run on: ask here, once, and
            // run that command: in the loop if it can, else by the full executor (a tick that
            // may change anything, so the stretch ends with it).
            let pc = self.s.pc as usize;
            let running = self.s.run == RunState::Running && self.motion_idle();
            if !running || halts.get(pc) != Some(&true) {
                break StopReason::TickLimit;
            }
            if stop(self) {
                break StopReason::Predicate;
            }
            if run(self, 1, true) == 0 {
                self.tick();
                self.note_writes(&mut quiet.written);
                break StopReason::TickLimit;
            }
            if program.flat.get(pc).is_some_and(|&op| guarded(op)) {
                // It wrote a watched register: the last command of the stretch, and the
                // timeline asks the boundary after it.
                break StopReason::TickLimit;
            }
        };
        let ran = self.s.steps - start;
        if ran > 0 {
            // The registers the commands it may have run write: those of its span, or of the
            // whole program when the span is most of it.
            match span.narrow(program.flat.len(), ran) {
                Some(range) => (program.flat[range].iter())
                    .for_each(|op| op.each_write(|r| quiet.written.insert(reg(u32::from(r))))),
                None => quiet.written.union(program.flat_writes),
            }
        }
        Some(reason)
    }
}
