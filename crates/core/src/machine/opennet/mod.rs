//! IDEC OpenNet (spec `opennet.md`): a scanned PLC with bit logic on two stacks, typed
//! arithmetic (W, I, D, L) with the vendor's signed-overflow rule, REP, the carry relay M8003
//! and the latched execution-error relay M8004.
//!
//! Decided where the spec is silent (each also noted where it is implemented):
//! - Inputs: a switch flipped in the debugger mid-scan is seen by the program from the next
//!   scan (the refresh copies the switches into the input image). Views show the switches; the
//!   runner's `bits` and the program read the image.
//! - Break on error stops before the instruction after the one that turned M8004 on.

pub mod assembler;
pub mod dialect;
pub mod explain;
pub mod fast;
pub mod ladder;
pub mod program;
pub mod syntax;
pub mod view;

use std::sync::Arc;

pub use assembler::assemble;
use program::{Area, Arith, BOXES, Bit, CounterKind, Op, Program, Ty, Value, Word};

use crate::machine::plc::{Edges, TimeBase, accumulate};

pub const REGISTERS: usize = 8000;
pub const STACK_DEPTH: usize = 8;
pub const M8003: usize = 0;
pub const M8004: usize = 1;
pub const M8120: usize = 2;
pub const M8121: usize = 3;
pub const M8122: usize = 4;
pub const M8123: usize = 5;
pub const M8125: usize = 6;

/// A timer (spec §5.8): it counts down from its preset while its input is on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TimerState {
    pub preset: u16,
    pub current: u16,
    pub output: bool,
    /// Timing since an earlier powered execution: the next one counts time.
    pub running: bool,
    /// Controller time toward the next increment, ms (0 ≤ e < increment).
    pub elapsed_ms: u32,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CounterState {
    pub preset: u16,
    pub current: u16,
    pub output: bool,
}

/// What switched an instruction off in this scan, for the code view (spec §5.12's dimming):
/// set by the MCS or JMP that decides it, so the fast loop marks nothing per instruction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u8)]
pub enum Mark {
    #[default]
    NotReached,
    /// Runs with MC = 0 (after an MCS that is off, up to its MCR): every output's input is off.
    MasterOff,
    /// Skipped by a taken JMP.
    Jumped,
}

/// An execution error (spec §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExecError {
    pub kind: &'static str,
    pub line: usize,
    pub tick: u64,
}

/// One REP cycle of the last advanced instruction, for the explanation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cycle {
    pub a: i64,
    pub b: i64,
    /// Exact result (the quotient for DIV).
    pub exact: i64,
    pub stored: u32,
    pub remainder: i64,
    pub out_of_range: bool,
    pub error: Option<&'static str>,
    pub a_at: u32,
    pub b_at: u32,
    pub dst_at: u32,
}

impl Cycle {
    /// A cycle that read `a` and `b` from these offsets; the rest is filled in by its kind.
    fn read(a: i64, b: i64, a_at: u32, b_at: u32) -> Cycle {
        Cycle {
            a,
            b,
            exact: 0,
            stored: 0,
            remainder: 0,
            out_of_range: false,
            error: None,
            a_at,
            b_at,
            dst_at: 0,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct OpenNet {
    pub program: Arc<Program>,
    pub d: Vec<u16>,
    /// The input switches, and the image the program reads (taken at scan start).
    pub inputs: Vec<bool>,
    pub input_image: Vec<bool>,
    pub q: Vec<bool>,
    pub m: Vec<bool>,
    /// Shift-register bits R0–R255.
    pub r: Vec<bool>,
    /// M8003, M8004, M8120, M8121, M8122, M8123, M8125 ([`SPECIAL`]).
    pub special: [bool; 7],
    pub rlo: bool,
    /// The master-control bit: outputs take RLO AND MC (spec §5.12).
    pub mc: bool,
    pub blocks: Vec<bool>,
    pub branches: Vec<bool>,
    /// SOTU/SOTD memories, and the pulse memories of counters and shift registers.
    pub edges: Edges,
    pub pulses: Edges,
    /// Each SOTU/SOTD memory's last pulse: its scan plus one (the Ladder shows it conducting).
    pub edge_scans: Vec<u64>,
    /// Bits the user forced.
    pub forces: crate::machine::plc::Forces,
    pub timers: Vec<TimerState>,
    pub counters: Vec<CounterState>,
    pub time: TimeBase,
    /// What each instruction did in this scan so far.
    pub marks: Vec<Mark>,
    /// The last timer's or counter's state before it ran (current value, output) and the
    /// inputs of the last counter or shift register in program order, for the explanation.
    pub box_before: (u16, bool),
    pub legs: [bool; 3],
    pub pc: u32,
    pub tick: u64,
    pub step: u32,
    pub steps: u64,
    pub error_count: u64,
    pub last_error: Option<ExecError>,
    /// The last executed instruction, whether it acted, and its REP cycles.
    pub last: Option<u32>,
    pub last_acted: bool,
    pub last_cycles: Vec<Cycle>,
}

impl OpenNet {
    pub fn new(program: Arc<Program>) -> Self {
        Self::with_time(program, TimeBase::default())
    }

    pub fn with_time(program: Arc<Program>, time: TimeBase) -> Self {
        let mut timers = vec![TimerState::default(); BOXES as usize];
        for &(n, p) in &program.timer_presets {
            timers[n as usize].preset = p;
            timers[n as usize].current = p;
        }
        let mut counters = vec![CounterState::default(); BOXES as usize];
        for &(n, p) in &program.counter_presets {
            counters[n as usize].preset = p;
        }
        OpenNet {
            d: vec![0; REGISTERS],
            inputs: vec![false; Area::I.points() as usize],
            input_image: vec![false; Area::I.points() as usize],
            q: vec![false; Area::Q.points() as usize],
            m: vec![false; Area::M.points() as usize],
            r: vec![false; Area::R.points() as usize],
            special: [false; 7],
            rlo: false,
            mc: true,
            blocks: Vec::new(),
            branches: Vec::new(),
            edges: Edges::new(program.edges as usize),
            edge_scans: vec![0; program.edges as usize],
            forces: Default::default(),
            pulses: Edges::new(program.pulses as usize),
            timers,
            counters,
            time,
            marks: vec![Mark::NotReached; program.instrs.len()],
            box_before: (0, false),
            legs: [false; 3],
            program,
            pc: 0,
            tick: 0,
            step: 0,
            steps: 0,
            error_count: 0,
            last_error: None,
            last: None,
            last_acted: false,
            last_cycles: Vec::new(),
        }
    }

    fn area(&self, area: Area) -> &[bool] {
        match area {
            Area::I => &self.input_image,
            Area::Q => &self.q,
            Area::M => &self.m,
            Area::R => &self.r,
        }
    }

    fn area_mut(&mut self, area: Area) -> &mut [bool] {
        match area {
            Area::I => &mut self.input_image,
            Area::Q => &mut self.q,
            Area::M => &mut self.m,
            Area::R => &mut self.r,
        }
    }

    pub fn bit(&self, b: Bit) -> bool {
        match b {
            Bit::Point(area, i) => self.area(area).get(i as usize).copied().unwrap_or(false),
            Bit::Special(s) => self.special[s as usize],
            Bit::Timer(n) => self.timers.get(n as usize).is_some_and(|t| t.output),
            Bit::Counter(n) => self.counters.get(n as usize).is_some_and(|c| c.output),
        }
    }

    fn set_bit(&mut self, b: Bit, v: bool) {
        match b {
            Bit::Point(area, i) => {
                if let Some(x) = self.area_mut(area).get_mut(i as usize) {
                    *x = v;
                }
            }
            Bit::Special(s) => self.special[s as usize] = v,
            // The assembler never lets a bit instruction write a timer or counter.
            Bit::Timer(_) | Bit::Counter(_) => {}
        }
    }

    /// The pattern of `words` words at `w`, advanced by `offset` words.
    pub fn read_word(&self, w: &Word, words: u32, offset: u32) -> u32 {
        match *w {
            Word::Const(v) => v,
            Word::Reg { n, .. } => {
                let at = (n + offset) as usize;
                let hi = u32::from(self.d.get(at).copied().unwrap_or(0));
                if words == 1 {
                    hi
                } else {
                    // The upper word is in the lower-numbered register.
                    (hi << 16) | u32::from(self.d.get(at + 1).copied().unwrap_or(0))
                }
            }
            Word::Bits { area, index, .. } => {
                let start = (index + offset * 16) as usize;
                let bits = self.area(area);
                (0..words * 16).fold(0, |acc, i| {
                    acc | (u32::from(bits.get(start + i as usize).copied().unwrap_or(false)) << i)
                })
            }
            // A timer or counter as a source is its current value (spec §4.3).
            Word::Timer { n, .. } => self.box_words(words, (n + offset) as usize, |m, i| {
                m.timers.get(i).map_or(0, |t| t.current)
            }),
            Word::Counter { n, .. } => self.box_words(words, (n + offset) as usize, |m, i| {
                m.counters.get(i).map_or(0, |c| c.current)
            }),
        }
    }

    /// `words` consecutive timer or counter values from `at`, the first the upper word.
    fn box_words(&self, words: u32, at: usize, get: impl Fn(&Self, usize) -> u16) -> u32 {
        let hi = u32::from(get(self, at));
        if words == 1 {
            hi
        } else {
            (hi << 16) | u32::from(get(self, at + 1))
        }
    }

    pub fn write_word(&mut self, w: &Word, words: u32, offset: u32, value: u32) {
        match *w {
            Word::Const(_) => {}
            Word::Reg { n, .. } => {
                let at = (n + offset) as usize;
                if words == 1 {
                    if let Some(r) = self.d.get_mut(at) {
                        *r = value as u16;
                    }
                } else {
                    if let Some(r) = self.d.get_mut(at) {
                        *r = (value >> 16) as u16;
                    }
                    if let Some(r) = self.d.get_mut(at + 1) {
                        *r = value as u16;
                    }
                }
            }
            Word::Bits { area, index, .. } => {
                let start = (index + offset * 16) as usize;
                let bits = self.area_mut(area);
                for i in 0..(words * 16) as usize {
                    if let Some(b) = bits.get_mut(start + i) {
                        *b = value >> i & 1 == 1;
                    }
                }
            }
            // A timer or counter as a destination takes the value as its preset (spec §4.3); a
            // pair keeps its upper word in the lower number, as registers do.
            Word::Timer { n, .. } | Word::Counter { n, .. } => {
                let timer = matches!(w, Word::Timer { .. });
                let at = (n + offset) as usize;
                let parts: &[(usize, u16)] = if words == 1 {
                    &[(at, value as u16)]
                } else {
                    &[(at, (value >> 16) as u16), (at + 1, value as u16)]
                };
                for &(i, v) in parts {
                    if timer {
                        if let Some(t) = self.timers.get_mut(i) {
                            t.preset = v;
                        }
                    } else if let Some(c) = self.counters.get_mut(i) {
                        c.preset = v;
                    }
                }
            }
        }
    }

    /// The offset of a word operand in REP cycle `c`: `(R)` operands advance by their block.
    fn offset(w: &Word, block: u32, c: u32) -> u32 {
        if w.repeats() { c * block } else { 0 }
    }

    /// Spec §5.4: what ADD/SUB store, and whether the result was out of range.
    pub fn store_add(ty: Ty, r: i64) -> (u32, bool) {
        let in_range = r >= ty.min() && r <= ty.max();
        let pattern = match ty {
            Ty::W => r.rem_euclid(1 << 16) as u32,
            Ty::D => r.rem_euclid(1 << 32) as u32,
            Ty::I if in_range => r as u16 as u32,
            Ty::L if in_range => r as u32,
            // Out of range: the sign of r, then r mod 2^15 / 2^31 (not two's complement).
            Ty::I => (u32::from(r < 0) << 15) | r.rem_euclid(1 << 15) as u32,
            Ty::L => (u32::from(r < 0) << 31) | r.rem_euclid(1 << 31) as u32,
        };
        (pattern, !in_range)
    }

    /// MUL's 32-bit result pattern, or None when D or L cannot hold the product.
    #[inline]
    fn product(ty: Ty, x: i64, y: i64) -> Option<u32> {
        let p = i128::from(x) * i128::from(y);
        let fits = match ty {
            Ty::D => p <= i128::from(u32::MAX),
            Ty::L => (i128::from(i32::MIN)..=i128::from(i32::MAX)).contains(&p),
            _ => true,
        };
        fits.then_some(p as u32)
    }

    /// DIV's quotient and remainder (truncated toward zero; the remainder has the dividend's
    /// sign), or the error it raises.
    #[inline]
    fn quotient(ty: Ty, x: i64, y: i64) -> Result<(i64, i64), &'static str> {
        if y == 0 {
            Err("divide_by_zero")
        } else if ty.signed() && x == ty.min() && y == -1 {
            Err("divide_overflow")
        } else {
            Ok((x / y, x % y))
        }
    }

    fn record_error(&mut self, kind: &'static str) {
        self.record_error_at(self.pc as usize, kind);
    }

    fn record_error_at(&mut self, index: usize, kind: &'static str) {
        let line = self.program.instrs.get(index).map_or(0, |i| i.line);
        self.special[M8004] = true;
        self.error_count += 1;
        self.last_error = Some(ExecError {
            kind,
            line,
            tick: self.tick,
        });
    }

    /// The scan's start (spec §3 step 1): inputs, the clocks sampled at t = tick × scan_ms.
    fn refresh(&mut self) {
        self.input_image.clone_from(&self.inputs);
        self.special[M8120] = self.tick == 0;
        // The clocks are on in the first half of each period: one division for the three
        // (each period divides the next), as this runs every scan.
        let phase = self.time.phase(self.tick, 1000) as u32;
        self.special[M8121] = phase < 500;
        self.special[M8122] = phase % 100 < 50;
        self.special[M8123] = phase % 10 < 5;
        self.special[M8125] = true;
        self.rlo = false;
        self.mc = true;
        self.blocks.clear();
        self.branches.clear();
        // Only an MCS that was off or a taken jump marks anything.
        if self.program.marks_code {
            self.marks.fill(Mark::NotReached);
        }
    }

    /// A preset or compared value now.
    fn value(&self, v: Value) -> u16 {
        match v {
            Value::Const(c) => c,
            Value::Reg(n) => self.d.get(n as usize).copied().unwrap_or(0),
        }
    }

    /// LOD's effect on the stacks and RLO, for a contact that reads `x`.
    #[inline(always)]
    fn load_contact(&mut self, index: usize, x: bool) {
        if self.program.opens.get(index).copied().unwrap_or(true) {
            self.blocks.clear();
            self.branches.clear();
        } else {
            Self::push(&mut self.blocks, self.rlo);
        }
        self.rlo = x;
    }

    #[inline(always)]
    fn sotu(&mut self, m: u32) {
        self.rlo = self.edges.rose(m as usize, self.rlo && self.mc);
        self.note_pulse(m);
    }

    /// Remember the scan an edge instruction pulsed in (rare: only when it does).
    #[inline(always)]
    fn note_pulse(&mut self, m: u32) {
        if self.rlo
            && let Some(s) = self.edge_scans.get_mut(m as usize)
        {
            *s = self.tick + 1;
        }
    }

    /// SOTD: with MC = 0 it gives 0 and forgets (no falling edge is seen, spec §5.12).
    #[inline(always)]
    fn sotd(&mut self, m: u32) {
        if self.mc {
            self.rlo = self.edges.fell(m as usize, self.rlo);
            self.note_pulse(m);
        } else {
            self.edges.rose(m as usize, false);
            self.rlo = false;
        }
    }

    /// The instructions of the PLC's control: contacts that compare, timers, counters, shift
    /// registers, the comparisons and word instructions, MCS/MCR and JMP/JEND. The executor
    /// and the fast loop both run them here; `record` keeps the REP cycles and the box's
    /// state before for the explanation. Returns where a taken jump continues.
    #[inline(always)]
    pub(crate) fn act(&mut self, index: usize, op: Op, record: bool) -> Option<u32> {
        let input = self.rlo && self.mc;
        match op {
            Op::Compare {
                counter,
                n,
                value,
                at_least,
            } => {
                let x = if counter {
                    self.counters.get(n as usize).map_or(0, |c| c.current)
                } else {
                    self.d.get(n as usize).copied().unwrap_or(0)
                };
                let v = self.value(value);
                self.load_contact(index, if at_least { x >= v } else { x == v });
            }
            Op::Timer { kind, n, preset } => {
                let scan_ms = self.time.scan_ms;
                let preset_now = match preset {
                    Value::Reg(_) => Some(self.value(preset)),
                    Value::Const(_) => None,
                };
                let t = self.timers.get_mut(n as usize)?;
                if record {
                    self.box_before = (t.current, t.output);
                }
                if let Some(p) = preset_now {
                    t.preset = p;
                }
                if !input {
                    *t = TimerState {
                        preset: t.preset,
                        current: t.preset,
                        ..TimerState::default()
                    };
                } else {
                    if t.running {
                        let (units, left) = accumulate(t.elapsed_ms, scan_ms, kind.increment_ms());
                        t.current = u64::from(t.current).saturating_sub(units) as u16;
                        t.elapsed_ms = left;
                    } else {
                        // The first powered execution starts timing and counts no time.
                        t.running = true;
                        t.current = t.preset;
                        t.elapsed_ms = 0;
                    }
                    t.output = t.current == 0;
                }
            }
            Op::Counter {
                kind,
                n,
                preset,
                pulses,
            } => {
                // The inputs in program order: the last is RLO, the others come off the stack.
                let last = self.rlo;
                let second = self.blocks.pop().unwrap_or(false);
                let (a, b, c) = if kind == CounterKind::Cnt {
                    (second, last, false)
                } else {
                    (self.blocks.pop().unwrap_or(false), second, last)
                };
                let preset_now = match preset {
                    Value::Reg(_) => Some(self.value(preset)),
                    Value::Const(_) => None,
                };
                let p = pulses as usize;
                if record {
                    self.legs = [a, b, c];
                    if let Some(cn) = self.counters.get(n as usize) {
                        self.box_before = (cn.current, cn.output);
                    }
                }
                let mc = self.mc;
                let rises = if mc {
                    match kind {
                        CounterKind::Cnt | CounterKind::Cud => (self.pulses.rose(p, b), false),
                        CounterKind::Cdp => (self.pulses.rose(p, b), self.pulses.rose(p + 1, c)),
                    }
                } else {
                    // MC off: the memories forget, so a pulse on when MC returns counts.
                    self.pulses.rose(p, false);
                    if kind == CounterKind::Cdp {
                        self.pulses.rose(p + 1, false);
                    }
                    (false, false)
                };
                let cn = self.counters.get_mut(n as usize)?;
                if let Some(v) = preset_now {
                    cn.preset = v;
                }
                if !mc {
                    cn.output = false;
                    return None;
                }
                match kind {
                    CounterKind::Cnt => {
                        if a {
                            cn.current = 0;
                            cn.output = false;
                        } else {
                            if rises.0 && cn.current < cn.preset {
                                cn.current += 1;
                            }
                            cn.output = cn.current >= cn.preset;
                        }
                    }
                    CounterKind::Cdp | CounterKind::Cud => {
                        if a {
                            cn.current = cn.preset;
                        } else {
                            let (up, down) = if kind == CounterKind::Cdp {
                                rises
                            } else {
                                (rises.0 && c, rises.0 && !c)
                            };
                            if up && !down {
                                cn.current = cn.current.wrapping_add(1);
                            } else if down && !up {
                                cn.current = cn.current.wrapping_sub(1);
                            }
                        }
                        cn.output = cn.current == 0;
                    }
                }
            }
            Op::ShiftRegister {
                down,
                first,
                len,
                pulses,
            } => {
                let data = self.rlo;
                let pulse = self.blocks.pop().unwrap_or(false);
                let reset = self.blocks.pop().unwrap_or(false);
                if record {
                    self.legs = [reset, pulse, data];
                }
                if !self.mc {
                    self.pulses.rose(pulses as usize, false);
                    return None;
                }
                let rise = self.pulses.rose(pulses as usize, pulse);
                let (from, to) = (first as usize, (first + len) as usize);
                let bits = self.r.get_mut(from..to)?;
                if reset {
                    bits.fill(false);
                } else if rise {
                    let top = bits.len() - 1;
                    if down {
                        bits.copy_within(1.., 0);
                        bits[top] = data;
                    } else {
                        bits.copy_within(..top, 1);
                        bits[0] = data;
                    }
                }
            }
            Op::WordCompare {
                rel,
                ty,
                a,
                b,
                c,
                dst: (area, at),
                dst_repeat,
                rep,
            } if input => {
                let w = ty.words();
                for k in 0..u32::from(rep) {
                    let (ao, bo) = (Self::offset(&a, w, k), Self::offset(&b, w, k));
                    let x = ty.value(self.read_word(&a, w, ao));
                    let y = ty.value(self.read_word(&b, w, bo));
                    let z = ty.value(self.read_word(&c, w, Self::offset(&c, w, k)));
                    let on = rel.holds(x, y, z);
                    let point = at + if dst_repeat { k } else { 0 };
                    self.set_bit(Bit::Point(area, point), on);
                    if record {
                        self.last_cycles.push(Cycle {
                            exact: z,
                            stored: u32::from(on),
                            dst_at: point - at,
                            ..Cycle::read(x, y, ao, bo)
                        });
                    }
                }
            }
            Op::WordLogic {
                op: logic,
                ty,
                a,
                b,
                dst,
                rep,
            } if input => {
                let w = ty.words();
                for k in 0..u32::from(rep) {
                    let (ao, bo, dof) = (
                        Self::offset(&a, w, k),
                        Self::offset(&b, w, k),
                        Self::offset(&dst, w, k),
                    );
                    let x = self.read_word(&a, w, ao);
                    let y = self.read_word(&b, w, bo);
                    let v = logic.apply(x, y);
                    self.write_word(&dst, w, dof, v);
                    if record {
                        self.last_cycles.push(Cycle {
                            stored: v,
                            dst_at: dof,
                            ..Cycle::read(i64::from(x), i64::from(y), ao, bo)
                        });
                    }
                }
            }
            Op::Shift { left, ty, word, by } if input => {
                let w = ty.words();
                let bits = ty.bits();
                let by = u32::from(by);
                let old = self.read_word(&word, w, 0);
                let mask = if bits == 32 {
                    u32::MAX
                } else {
                    (1 << bits) - 1
                };
                let (new, out) = if left {
                    ((old << by) & mask, old >> (bits - by) & 1)
                } else {
                    (old >> by, old >> (by - 1) & 1)
                };
                self.write_word(&word, w, 0, new);
                self.special[M8003] = out == 1;
                if record {
                    self.last_cycles.push(Cycle {
                        stored: new,
                        ..Cycle::read(i64::from(old), i64::from(by), 0, 0)
                    });
                }
            }
            Op::Convert {
                to_bcd,
                ty,
                src,
                dst,
                rep,
            } if input => {
                let w = ty.words();
                for k in 0..u32::from(rep) {
                    let (so, dof) = (Self::offset(&src, w, k), Self::offset(&dst, w, k));
                    let v = self.read_word(&src, w, so);
                    let digits = 4 * w;
                    let result = if to_bcd {
                        (u64::from(v) < 10u64.pow(digits))
                            .then(|| crate::machine::plc::to_bcd(u64::from(v)))
                            .ok_or("bcd_range")
                    } else {
                        crate::machine::plc::bcd_value(v, digits)
                            .map(|x| x as u32)
                            .ok_or("bcd_digit")
                    };
                    match result {
                        Ok(out) => self.write_word(&dst, w, dof, out),
                        Err(kind) => self.record_error_at(index, kind),
                    }
                    if record {
                        self.last_cycles.push(Cycle {
                            stored: result.unwrap_or(0),
                            error: result.err(),
                            dst_at: dof,
                            ..Cycle::read(i64::from(v), 0, so, 0)
                        });
                    }
                }
            }
            Op::Mcs(end) => {
                self.mc = input;
                // Until its MCR every instruction runs with MC = 0 (no jump is taken then).
                if !input && (end as usize) < self.marks.len() {
                    self.marks[index + 1..end as usize].fill(Mark::MasterOff);
                }
            }
            Op::Mcr => self.mc = true,
            Op::Jmp(to) if input && (to as usize) < self.marks.len() => {
                self.marks[index + 1..to as usize].fill(Mark::Jumped);
                return Some(to);
            }
            _ => {}
        }
        None
    }

    fn push(stack: &mut Vec<bool>, v: bool) {
        if stack.len() < STACK_DEPTH {
            stack.push(v);
        }
    }

    fn execute(&mut self) {
        let index = self.pc as usize;
        let op = self.program.instrs[index].op;
        self.last_acted = false;
        self.last_cycles.clear();
        // The record is of this instruction alone (the fast loop keeps none).
        self.box_before = (0, false);
        self.legs = [false; 3];
        let mc = self.mc;
        let input = self.rlo && mc;
        let mut next = self.pc + 1;
        match op {
            Op::Lod(b, neg) => self.load_contact(index, self.bit(b) != neg),
            Op::And(b, neg) => self.rlo &= self.bit(b) != neg,
            Op::Or(b, neg) => self.rlo |= self.bit(b) != neg,
            Op::AndLod => {
                let top = self.blocks.pop().unwrap_or(false);
                self.rlo &= top;
            }
            Op::OrLod => {
                let top = self.blocks.pop().unwrap_or(false);
                self.rlo |= top;
            }
            Op::Bps => Self::push(&mut self.branches, self.rlo),
            Op::Brd => self.rlo = self.branches.last().copied().unwrap_or(false),
            Op::Bpp => self.rlo = self.branches.pop().unwrap_or(false),
            Op::Sotu(m) => self.sotu(m),
            Op::Sotd(m) => self.sotd(m),
            Op::Out(b, neg) => self.set_bit(b, input != neg),
            Op::Set(b) => {
                if input {
                    self.set_bit(b, true);
                }
            }
            Op::Rst(b) => {
                if input {
                    self.set_bit(b, false);
                }
            }
            Op::End => {}
            Op::Mov { ty, src, dst, rep } if input => {
                self.last_acted = true;
                let w = ty.words();
                for c in 0..u32::from(rep) {
                    let (so, dof) = (Self::offset(&src, w, c), Self::offset(&dst, w, c));
                    let v = self.read_word(&src, w, so);
                    self.write_word(&dst, w, dof, v);
                    self.last_cycles.push(Cycle {
                        a: ty.value(v),
                        b: 0,
                        exact: ty.value(v),
                        stored: v,
                        remainder: 0,
                        out_of_range: false,
                        error: None,
                        a_at: so,
                        b_at: 0,
                        dst_at: dof,
                    });
                }
            }
            Op::Arith {
                op,
                ty,
                a,
                b,
                dst,
                rep,
            } if input => {
                self.last_acted = true;
                let w = ty.words();
                let dst_block = match op {
                    Arith::Add | Arith::Sub => w,
                    Arith::Mul => 2,
                    Arith::Div => 2 * w,
                };
                let mut carry = false;
                for c in 0..u32::from(rep) {
                    let (ao, bo, dof) = (
                        Self::offset(&a, w, c),
                        Self::offset(&b, w, c),
                        Self::offset(&dst, dst_block, c),
                    );
                    let x = ty.value(self.read_word(&a, w, ao));
                    let y = ty.value(self.read_word(&b, w, bo));
                    let mut cycle = Cycle {
                        a: x,
                        b: y,
                        exact: 0,
                        stored: 0,
                        remainder: 0,
                        out_of_range: false,
                        error: None,
                        a_at: ao,
                        b_at: bo,
                        dst_at: dof,
                    };
                    match op {
                        Arith::Add | Arith::Sub => {
                            let r = if op == Arith::Add { x + y } else { x - y };
                            let (stored, out) = Self::store_add(ty, r);
                            carry |= out;
                            self.write_word(&dst, w, dof, stored);
                            cycle.exact = r;
                            cycle.stored = stored;
                            cycle.out_of_range = out;
                        }
                        Arith::Mul => {
                            cycle.exact = (i128::from(x) * i128::from(y)) as i64;
                            match Self::product(ty, x, y) {
                                Some(p) => {
                                    self.write_word(&dst, 2, dof, p);
                                    cycle.stored = p;
                                }
                                None => cycle.error = Some("mul_range"),
                            }
                        }
                        Arith::Div => match Self::quotient(ty, x, y) {
                            Ok((q, r)) => {
                                self.write_word(&dst, w, dof, q as u32);
                                self.write_word(&dst, w, dof + w, r as u32);
                                cycle.exact = q;
                                cycle.stored = q as u32 & if w == 1 { 0xFFFF } else { u32::MAX };
                                cycle.remainder = r;
                            }
                            Err(kind) => cycle.error = Some(kind),
                        },
                    }
                    if let Some(kind) = cycle.error {
                        self.record_error(kind);
                    }
                    self.last_cycles.push(cycle);
                }
                if matches!(op, Arith::Add | Arith::Sub) {
                    self.special[M8003] = carry;
                }
            }
            Op::Step { up, ty, reg } if input => {
                self.last_acted = true;
                let word = Word::Reg {
                    n: reg,
                    repeat: false,
                };
                let w = ty.words();
                let v = self.read_word(&word, w, 0);
                let next = if up {
                    v.wrapping_add(1)
                } else {
                    v.wrapping_sub(1)
                };
                let next = if w == 1 { next & 0xFFFF } else { next };
                self.write_word(&word, w, 0, next);
            }
            Op::Mov { .. } | Op::Arith { .. } | Op::Step { .. } => {}
            _ => {
                self.last_acted = input;
                if let Some(to) = self.act(index, op, true) {
                    next = to;
                }
            }
        }
        self.last = Some(index as u32);
        self.steps += 1;
        self.step += 1;
        self.pc = next;
        if matches!(op, Op::End) || self.pc as usize >= self.program.instrs.len() {
            self.pc = 0;
            self.step = 0;
            self.tick += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row of the vendor's storage table (spec §5.4).
    #[test]
    fn the_vendors_storage_table() {
        let rows: &[(Ty, i64, u32, bool)] = &[
            (Ty::W, 0, 0x0000, false),
            (Ty::W, 65535, 0xFFFF, false),
            (Ty::W, 131071, 0xFFFF, true),
            (Ty::W, -1, 0xFFFF, true),
            (Ty::W, -65535, 0x0001, true),
            (Ty::W, -65536, 0x0000, true),
            (Ty::I, 65534, 0x7FFE, true),
            (Ty::I, 32768, 0x0000, true),
            (Ty::I, 32767, 0x7FFF, false),
            (Ty::I, 0, 0x0000, false),
            (Ty::I, -1, 0xFFFF, false),
            (Ty::I, -32767, 0x8001, false),
            (Ty::I, -32768, 0x8000, false),
            (Ty::I, -32769, 0xFFFF, true),
            (Ty::I, -65535, 0x8001, true),
            (Ty::D, 0, 0, false),
            (Ty::D, 4294967295, 0xFFFF_FFFF, false),
            (Ty::D, 8589934591, 0xFFFF_FFFF, true),
            (Ty::D, -1, 0xFFFF_FFFF, true),
            (Ty::D, -4294967295, 0x0000_0001, true),
            (Ty::D, -4294967296, 0x0000_0000, true),
            (Ty::L, 4294967294, 0x7FFF_FFFE, true),
            (Ty::L, 2147483648, 0x0000_0000, true),
            (Ty::L, 2147483647, 0x7FFF_FFFF, false),
            (Ty::L, 0, 0, false),
            (Ty::L, -1, 0xFFFF_FFFF, false),
            (Ty::L, -2147483647, 0x8000_0001, false),
            (Ty::L, -2147483648, 0x8000_0000, false),
            (Ty::L, -2147483649, 0xFFFF_FFFF, true),
            (Ty::L, -4294967295, 0x8000_0001, true),
        ];
        for &(ty, r, stored, carry) in rows {
            assert_eq!(OpenNet::store_add(ty, r), (stored, carry), "{ty:?} {r}");
        }
    }
}
