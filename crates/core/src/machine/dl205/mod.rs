//! AutomationDirect DL205 (spec `dl205.md`): a scanned PLC whose math runs through a 32-bit
//! accumulator and an 8-level accumulator stack, mostly in BCD, with the boolean stack of its
//! rungs and the SP flags.
//!
//! Decided where the spec is silent (also noted where implemented):
//! - The debugger may write V words, X inputs (seen from the next scan: the scan start copies
//!   the switches into the image), Y and C; SP relays are the machine's.
//! - SP53 and SP75 remember the line of the instruction that last set them, for the views.

pub mod assembler;
pub mod dialect;
pub mod explain;
pub mod fast;
pub mod ladder;
pub mod program;
pub mod syntax;
pub mod view;

use std::sync::Arc;

use crate::machine::plc::{CounterInputs, Edges, TimeBase, accumulate};
pub use assembler::assemble;
use program::{
    Bit, Cmp, CounterKind, D, Edge, Kind, Math, Op, Preset, Program, ShiftKind, Src, Test,
    TimerKind, W, sp,
};

pub const V_WORDS: usize = 0o40000;
/// Z0 = 1, Z1…Z7 = 0: the master-line zones at each scan, SG, ISG and SBR.
const ZONES_AT_START: [bool; 8] = [true, false, false, false, false, false, false, false];
pub const LEVELS: usize = 8;

/// Where execution goes after an instruction.
enum Flow {
    Next,
    To(u32),
    EndScan,
}

/// What the last instruction did to the accumulator stack, for the panel and explanations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StackMove {
    #[default]
    None,
    /// A value entered L1; the one that fell off L8, when all eight levels were in use (a
    /// level below the depth holds no value, so nothing is lost from it).
    Push { entered: u32, lost: Option<u32> },
    /// L1 rose into ACC or was consumed.
    Pop { value: u32 },
    /// L1 was overwritten (DIVS, DIVBS).
    Overwrite { value: u32 },
}

/// A FOR loop in progress: where its FOR is and the turns left, this one included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Loop {
    pub for_at: u32,
    pub left: u32,
}

/// A subroutine call in progress: where to return and the caller's rung and block state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    pub ret: u32,
    pub bstack: Vec<bool>,
    pub rung_has_output: bool,
    pub level: u8,
    pub zones: [bool; 8],
    pub stage_power: bool,
    pub loop_state: Option<Loop>,
}

/// Which instruction last changed a stage bit, and the position just after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StageChange {
    pub stage: u32,
    pub line: usize,
    pub at: crate::machine::Pos,
}

/// Calls may nest 8 deep (checked at assembly: spec §2).
pub const CALL_DEPTH: usize = 8;

#[derive(Clone, Debug, PartialEq)]
pub struct Dl205 {
    pub program: Arc<Program>,
    pub v: Vec<u16>,
    pub x: Vec<bool>,
    pub x_image: Vec<bool>,
    pub y: Vec<bool>,
    pub c: Vec<bool>,
    pub s: Vec<bool>,
    pub t: Vec<bool>,
    pub ct: Vec<bool>,
    pub sp: [bool; program::SPECIAL.len()],
    /// Each timer's time toward its next unit (`Tn.ms`).
    pub t_ms: Vec<u32>,
    /// The scan each timer last counted, plus one (0: none since its last reset).
    pub t_counted: Vec<u64>,
    /// Each counter's inputs at its last execution (`CTn.in`).
    pub ct_in: Vec<CounterInputs>,
    pub edges: Edges,
    /// Whether the last edge contact evaluated fired (for its explanation).
    pub edge_fired: bool,
    /// The edge contacts that fired in this scan, by instruction index (the code view marks
    /// them).
    pub fired_this_scan: Vec<u32>,
    /// Whether the last instruction raised SP53 or SP75 (what it wrote, for the Log).
    pub raised_error: bool,
    /// A timer's or counter's current value before the last instruction ran it.
    pub box_before: u32,
    /// OROUT targets already written in this scan.
    pub orout_marks: Vec<bool>,
    pub time: TimeBase,
    /// Master-line level ℓ and zone powers Z0…Z7 (spec §6.8).
    pub level: u8,
    pub zones: [bool; 8],
    /// Stage power G, fixed at each SG/ISG.
    pub stage_power: bool,
    /// G ∧ Z_ℓ: what every output's rung power is ANDed with.
    pub block_power: bool,
    pub loop_state: Option<Loop>,
    pub calls: Vec<Frame>,
    /// Each stage's clean-up mark: it ran since it last turned off (spec §6.10).
    pub stage_marks: Vec<bool>,
    /// The last change of each stage bit the program changed.
    pub stage_changes: Vec<StageChange>,
    pub acc: u32,
    pub stack: [u32; LEVELS],
    pub depth: u8,
    pub load_pending: bool,
    pub bstack: Vec<bool>,
    pub rung_has_output: bool,
    pub pc: u32,
    pub tick: u64,
    pub step: u32,
    pub steps: u64,
    pub last: Option<u32>,
    /// ACC and L1 before the last instruction, and what it did to the stack.
    pub before: (u32, u32),
    pub moved: StackMove,
    /// Whether the last instruction ran (its rung was powered), or met non-BCD data / ÷0.
    pub last_ran: bool,
    pub sp53_line: Option<usize>,
    pub sp75_line: Option<usize>,
    /// The rung power after each instruction of this scan (None: not reached yet).
    pub power: Vec<Option<bool>>,
    /// Bits the user forced (last: the run loops' fields keep their places).
    pub forces: crate::machine::plc::Forces,
}

pub use crate::machine::plc::{bcd_value, to_bcd};

impl Dl205 {
    pub fn new(program: Arc<Program>) -> Self {
        Self::with_time(program, TimeBase::default())
    }

    pub fn with_time(program: Arc<Program>, time: TimeBase) -> Self {
        let n = program.instrs.len();
        let timers = Kind::T.count() as usize;
        let edges = Edges::new(program.edges as usize);
        let orout_marks = vec![false; program.orout_bits.len()];
        let mut m = Dl205 {
            program,
            v: vec![0; V_WORDS],
            x: vec![false; Kind::X.count() as usize],
            x_image: vec![false; Kind::X.count() as usize],
            y: vec![false; Kind::Y.count() as usize],
            c: vec![false; Kind::C.count() as usize],
            s: vec![false; Kind::S.count() as usize],
            t: vec![false; timers],
            ct: vec![false; timers],
            sp: [false; program::SPECIAL.len()],
            t_ms: vec![0; timers],
            t_counted: vec![0; timers],
            ct_in: vec![CounterInputs::default(); timers],
            edges,
            edge_fired: false,
            fired_this_scan: Vec::new(),
            raised_error: false,
            box_before: 0,
            orout_marks,
            time,
            level: 0,
            zones: ZONES_AT_START,
            stage_power: true,
            block_power: true,
            loop_state: None,
            calls: Vec::new(),
            stage_marks: vec![false; Kind::S.count() as usize],
            forces: Default::default(),
            stage_changes: Vec::new(),
            acc: 0,
            stack: [0; LEVELS],
            depth: 0,
            load_pending: false,
            bstack: Vec::new(),
            rung_has_output: false,
            pc: 0,
            tick: 0,
            step: 0,
            steps: 0,
            last: None,
            before: (0, 0),
            moved: StackMove::None,
            last_ran: false,
            sp53_line: None,
            sp75_line: None,
            power: vec![None; n],
        };
        m.sp[sp::SP1] = true;
        // ISG stages are on before scan 0.
        let initial: Vec<u32> = m
            .program
            .instrs
            .iter()
            .filter_map(|i| match i.op {
                Op::Sg {
                    stage,
                    initial: true,
                    ..
                } => Some(stage),
                _ => None,
            })
            .collect();
        for stage in initial {
            m.s[stage as usize] = true;
        }
        m
    }

    pub fn bit(&self, b: Bit) -> bool {
        let i = b.n as usize;
        match b.kind {
            Kind::X => self.x_image.get(i).copied().unwrap_or(false),
            Kind::Y => self.y.get(i).copied().unwrap_or(false),
            Kind::C => self.c.get(i).copied().unwrap_or(false),
            Kind::Sp => self.sp.get(i).copied().unwrap_or(false),
            Kind::S => self.s.get(i).copied().unwrap_or(false),
            Kind::T => self.t.get(i).copied().unwrap_or(false),
            Kind::Ct => self.ct.get(i).copied().unwrap_or(false),
        }
    }

    fn set_bit(&mut self, b: Bit, on: bool) {
        let i = b.n as usize;
        let slot = match b.kind {
            Kind::Y => self.y.get_mut(i),
            Kind::C => self.c.get_mut(i),
            Kind::S => {
                if self.s.get(i).is_some_and(|&was| was != on) {
                    self.note_stage_change(b.n);
                }
                self.s.get_mut(i)
            }
            // RST of a timer or counter clears its box (see `reset_box`).
            Kind::T => self.t.get_mut(i),
            Kind::Ct => self.ct.get_mut(i),
            // The assembler never lets a program write X or SP.
            Kind::X | Kind::Sp => None,
        };
        if let Some(s) = slot {
            *s = on;
        }
    }

    /// V word `a`: a data word, or a bit-mapped word (V40400–V41237) read from its bits.
    #[inline(always)]
    pub fn word(&self, a: u32) -> u16 {
        match self.v.get(a as usize) {
            Some(&w) => w,
            None => self.mapped_word(a),
        }
    }

    #[inline(always)]
    pub(super) fn set_word(&mut self, a: u32, value: u16) {
        match self.v.get_mut(a as usize) {
            Some(w) => *w = value,
            None => self.set_mapped_word(a, value),
        }
    }

    fn mapped_word(&self, a: u32) -> u16 {
        let Some((kind, first)) = program::mapped(a) else {
            return 0;
        };
        (0..16).fold(0u16, |word, i| {
            let n = first + i;
            let on = match kind {
                // Unmodelled special relays read 0.
                Kind::Sp => program::SPECIAL
                    .iter()
                    .position(|&s| s == n)
                    .is_some_and(|i| self.sp[i]),
                _ => self.bit(Bit { kind, n }),
            };
            word | (u16::from(on) << i)
        })
    }

    /// Only VY, VC and VS words are written (the assembler refuses the others).
    fn set_mapped_word(&mut self, a: u32, value: u16) {
        if let Some((kind @ (Kind::Y | Kind::C | Kind::S), first)) = program::mapped(a) {
            for i in 0..16 {
                self.set_bit(Bit { kind, n: first + i }, value >> i & 1 == 1);
            }
        }
    }

    fn w(&self, w: W) -> u32 {
        match w {
            W::V(a) => u32::from(self.word(a)),
            W::K(k) => u32::from(k),
        }
    }

    /// A pair: Vn low word, Vn+1 high word.
    pub fn pair(&self, a: u32) -> u32 {
        u32::from(self.word(a)) | (u32::from(self.word(a + 1)) << 16)
    }

    fn d(&self, d: D) -> u32 {
        match d {
            D::V(a) => self.pair(a),
            D::K(k) => k,
        }
    }

    pub fn push(&mut self, v: u32) {
        let lost = (usize::from(self.depth) == LEVELS).then_some(self.stack[LEVELS - 1]);
        self.stack.copy_within(0..LEVELS - 1, 1);
        self.stack[0] = v;
        self.depth = (self.depth + 1).min(LEVELS as u8);
        self.moved = StackMove::Push { entered: v, lost };
    }

    pub fn pop(&mut self) -> u32 {
        let v = self.stack[0];
        self.stack.copy_within(1..LEVELS, 0);
        self.stack[LEVELS - 1] = 0;
        self.depth = self.depth.saturating_sub(1);
        self.moved = StackMove::Pop { value: v };
        v
    }

    fn load(&mut self, v: u32) {
        if self.load_pending {
            let acc = self.acc;
            self.push(acc);
        }
        self.acc = v;
        self.load_pending = true;
    }

    fn zn(&mut self) {
        self.sp[sp::SP63] = self.acc == 0;
        self.sp[sp::SP70] = self.acc >> 31 == 1;
    }

    fn line(&self) -> usize {
        self.program.instrs[self.pc as usize].line
    }

    fn non_bcd(&mut self) {
        self.raised_error = true;
        self.sp[sp::SP75] = true;
        self.sp75_line = Some(self.line());
    }

    fn divide_by_zero(&mut self) {
        self.raised_error = true;
        self.sp[sp::SP53] = true;
        self.sp53_line = Some(self.line());
    }

    /// A contact's value; an edge contact also updates its memory.
    #[inline(always)]
    fn test(&mut self, t: Test) -> bool {
        match t {
            Test::Bit(b, neg) => self.bit(b) != neg,
            Test::Edge(b, edge, i) => {
                let now = self.bit(b);
                self.edge_fired = match edge {
                    Edge::Rising => self.edges.rose(i as usize, now),
                    Edge::Falling => self.edges.fell(i as usize, now),
                };
                if self.edge_fired {
                    self.fired_this_scan.push(self.pc);
                }
                self.edge_fired
            }
            Test::Compare(a, b, kind) => {
                let (x, y) = (u32::from(self.word(a)), self.w(b));
                match kind {
                    Cmp::Eq => x == y,
                    Cmp::Ne => x != y,
                    Cmp::Ge => x >= y,
                    Cmp::Lt => x < y,
                }
            }
        }
    }

    /// BCD math (spec §6.3).
    fn bcd_math(&mut self, op: Math, src: Src) {
        let a = self.acc;
        // The digits each row reads; a non-BCD one skips everything but SP75.
        let (a_digits, operand, o_digits) = match (op, src) {
            (Math::Add | Math::Sub, Src::Word(w)) => (4, self.w(w), 4),
            (Math::Add | Math::Sub, Src::Double(d)) => (8, self.d(d), 8),
            (Math::Add | Math::Sub, Src::Stack) => (8, self.stack[0], 8),
            (Math::Mul, Src::Word(w)) => (4, self.w(w), 4),
            (Math::Mul, Src::Stack) => (4, self.stack[0], 4),
            (Math::Mul, Src::Double(d)) => (8, self.d(d), 8),
            (Math::Div, Src::Word(w)) => (8, self.w(w), 4),
            (Math::Div, Src::Double(d)) => (8, self.d(d), 8),
            (Math::Div, Src::Stack) => (8, self.stack[0], 4),
        };
        let (Some(x), Some(y)) = (bcd_value(a, a_digits), bcd_value(operand, o_digits)) else {
            self.non_bcd();
            return;
        };
        let is_double = !matches!(src, Src::Word(_));
        match op {
            Math::Add | Math::Sub => {
                let modulus: i64 = if is_double { 100_000_000 } else { 10_000 };
                let s = if op == Math::Add {
                    x as i64 + y as i64
                } else {
                    x as i64 - y as i64
                };
                self.acc = to_bcd(s.rem_euclid(modulus) as u64);
                let (lx, ly) = (x % 10_000, y % 10_000);
                if op == Math::Add {
                    self.sp[sp::SP66] = if is_double {
                        lx + ly >= 10_000
                    } else {
                        s >= 10_000
                    };
                    self.sp[sp::SP67] = is_double && s >= 100_000_000;
                } else {
                    self.sp[sp::SP64] = if is_double { lx < ly } else { s < 0 };
                    self.sp[sp::SP65] = is_double && s < 0;
                }
                if src == Src::Stack {
                    self.pop();
                }
            }
            Math::Mul => {
                let p = x * y;
                self.acc = to_bcd(p % 100_000_000);
                match src {
                    Src::Stack => {
                        self.pop();
                    }
                    Src::Double(_) => self.push(to_bcd(p / 100_000_000)),
                    Src::Word(_) => {}
                }
            }
            Math::Div => {
                if y == 0 {
                    self.divide_by_zero();
                    return;
                }
                self.acc = to_bcd(x / y);
                let r = to_bcd(x % y);
                if src == Src::Stack {
                    self.stack[0] = r;
                    self.moved = StackMove::Overwrite { value: r };
                } else {
                    self.push(r);
                }
                self.sp[sp::SP53] = false;
            }
        }
        self.sp[sp::SP75] = false;
        self.zn();
    }

    /// Binary math (spec §6.4).
    fn binary_math(&mut self, op: Math, src: Src) {
        let a = self.acc;
        let y = match src {
            Src::Word(w) => self.w(w),
            Src::Double(d) => self.d(d),
            Src::Stack => self.stack[0],
        };
        match op {
            Math::Add => {
                let r = a.wrapping_add(y);
                self.sp[sp::SP66] = (a & 0xFFFF) + (y & 0xFFFF) > 0xFFFF;
                self.sp[sp::SP67] = u64::from(a) + u64::from(y) > u64::from(u32::MAX);
                self.sp[sp::SP73] = (a >> 31 == y >> 31) && (r >> 31 != a >> 31);
                self.acc = r;
            }
            Math::Sub => {
                self.sp[sp::SP64] = (a & 0xFFFF) < (y & 0xFFFF);
                self.sp[sp::SP65] = a < y;
                self.acc = a.wrapping_sub(y);
            }
            Math::Mul => {
                self.acc = if src == Src::Stack {
                    (a & 0xFFFF) * (y & 0xFFFF)
                } else {
                    a.wrapping_mul(y)
                };
            }
            Math::Div => {
                let divisor = if src == Src::Stack { y & 0xFFFF } else { y };
                if divisor == 0 {
                    self.divide_by_zero();
                    return;
                }
                self.acc = a / divisor;
                let r = a % divisor;
                if src == Src::Stack {
                    self.stack[0] = r;
                    self.moved = StackMove::Overwrite { value: r };
                } else {
                    self.push(r);
                }
                self.sp[sp::SP53] = false;
            }
        }
        if src == Src::Stack && matches!(op, Math::Add | Math::Sub | Math::Mul) {
            self.pop();
        }
        self.zn();
    }

    /// STR: a new level on the boolean stack (a rung's first clears it).
    #[inline(always)]
    fn contact_str(&mut self, t: Test) {
        if self.bstack.is_empty() || self.rung_has_output {
            self.bstack.clear();
            self.rung_has_output = false;
        }
        let v = self.test(t);
        if self.bstack.len() < LEVELS {
            self.bstack.push(v);
        }
    }

    #[inline(always)]
    fn contact_and(&mut self, t: Test) {
        let v = self.test(t);
        if let Some(top) = self.bstack.last_mut() {
            *top &= v;
        }
    }

    #[inline(always)]
    fn contact_or(&mut self, t: Test) {
        let v = self.test(t);
        if let Some(top) = self.bstack.last_mut() {
            *top |= v;
        }
    }

    /// ANDSTR (`and`) / ORSTR: the top two levels become one.
    #[inline(always)]
    fn join_top(&mut self, and: bool) {
        if self.bstack.len() >= 2 {
            let b = self.bstack.pop().unwrap_or(false);
            let a = self.bstack.pop().unwrap_or(false);
            self.bstack.push(if and { a && b } else { a || b });
        }
    }

    fn execute(&mut self) {
        let index = self.pc as usize;
        let op = self.program.instrs[index].op;
        self.before = (self.acc, self.stack[0]);
        self.moved = StackMove::None;
        self.raised_error = false;
        let rung = self.bstack.last().copied().unwrap_or(false);
        // Effective power: the rung's, inside a powered stage and master-line zone.
        let power = rung && self.block_power;
        self.last_ran = true;
        let mut next = self.pc + 1;
        let mut end_scan = false;
        match op {
            Op::Str(t) => self.contact_str(t),
            Op::And(t) => self.contact_and(t),
            Op::Or(t) => self.contact_or(t),
            Op::AndStr => self.join_top(true),
            Op::OrStr => self.join_top(false),
            Op::Not => self.invert_top(),
            Op::End => end_scan = true,
            Op::Nop => {}
            op if op.is_standalone() => {
                // A standalone instruction ends the rung: the next STR starts one.
                self.rung_has_output = true;
                match self.standalone(op) {
                    Flow::Next => {}
                    Flow::To(i) => next = i,
                    Flow::EndScan => end_scan = true,
                }
            }
            Op::Mls(n) => {
                self.rung_has_output = true;
                let n = usize::from(n.min(7));
                self.zones[n] = n > 0 && self.zones[n - 1] && rung;
                self.level = n as u8;
                self.update_block_power();
            }
            Op::Njmp { to, own } => {
                self.rung_has_output = true;
                if self.block_power && !rung {
                    self.jump_stage(own, to);
                }
            }
            op if op.always_runs() => {
                self.rung_has_output = true;
                self.always(op, power);
            }
            // An unpowered FOR continues after its NEXT.
            Op::For(_, next_at) if !power => {
                self.rung_has_output = true;
                self.last_ran = false;
                next = next_at + 1;
            }
            _ if !power => {
                self.rung_has_output = true;
                self.last_ran = false;
            }
            Op::Goto(to) => {
                self.rung_has_output = true;
                next = to;
            }
            Op::For(count, next_at) => {
                self.rung_has_output = true;
                let turns = match count {
                    W::K(k) => bcd_value(u32::from(k), 4),
                    W::V(a) => bcd_value(u32::from(self.word(a)), 4),
                };
                let turns = turns.unwrap_or_else(|| {
                    self.non_bcd();
                    0
                });
                if turns == 0 {
                    next = next_at + 1;
                } else {
                    self.loop_state = Some(Loop {
                        for_at: self.pc,
                        left: turns as u32,
                    });
                }
            }
            Op::Gts(to) => {
                self.rung_has_output = true;
                self.calls.push(Frame {
                    ret: self.pc + 1,
                    bstack: std::mem::take(&mut self.bstack),
                    rung_has_output: true,
                    level: self.level,
                    zones: self.zones,
                    stage_power: self.stage_power,
                    loop_state: self.loop_state.take(),
                });
                next = to;
            }
            Op::Rtc => {
                self.rung_has_output = true;
                match self.return_from_call() {
                    Some(ret) => next = ret,
                    None => end_scan = true,
                }
            }
            Op::Jmp { to, own } => {
                self.rung_has_output = true;
                self.jump_stage(own, to);
            }
            _ => {
                self.rung_has_output = true;
                self.output(op);
            }
        }
        // Contacts: the rung's power after them; outputs: the power they acted on.
        self.power[index] = Some(if op.is_output() {
            power
        } else {
            self.bstack.last().copied().unwrap_or(false)
        });
        self.last = Some(index as u32);
        self.steps += 1;
        self.step += 1;
        self.pc = next;
        if end_scan || self.pc as usize >= self.program.instrs.len() {
            self.pc = 0;
            self.step = 0;
            self.tick += 1;
        }
    }

    /// A standalone instruction (spec §6.8, §6.10): where execution goes next.
    fn standalone(&mut self, op: Op) -> Flow {
        match op {
            Op::Next(for_at) => match self.loop_state {
                Some(Loop { left, .. }) if left > 1 => {
                    self.loop_state = Some(Loop {
                        for_at,
                        left: left - 1,
                    });
                    Flow::To(for_at + 1)
                }
                _ => {
                    self.loop_state = None;
                    Flow::Next
                }
            },
            Op::Sbr(_) => {
                self.bstack.clear();
                self.level = 0;
                self.zones = ZONES_AT_START;
                self.stage_power = true;
                self.loop_state = None;
                self.update_block_power();
                Flow::Next
            }
            Op::Rt => match self.return_from_call() {
                Some(ret) => Flow::To(ret),
                // Only a call reaches a subroutine (checked at assembly): end the scan.
                None => Flow::EndScan,
            },
            Op::Mlr(n) => {
                self.level = n.min(7);
                self.update_block_power();
                Flow::Next
            }
            Op::Sg { stage, next, .. } => {
                self.level = 0;
                self.zones = ZONES_AT_START;
                let i = stage as usize;
                let on = self.s.get(i).copied().unwrap_or(false);
                let marked = self.stage_marks.get(i).copied().unwrap_or(false);
                let flow = if on {
                    self.stage_power = true;
                    self.stage_marks[i] = true;
                    Flow::Next
                } else if marked {
                    // One clean-up pass: outputs see no power, timers reset.
                    self.stage_power = false;
                    self.stage_marks[i] = false;
                    Flow::Next
                } else {
                    Flow::To(next)
                };
                self.update_block_power();
                flow
            }
            _ => Flow::Next,
        }
    }

    /// RT/RTC: the caller's state back; where to continue (None: no call in progress).
    fn return_from_call(&mut self) -> Option<u32> {
        let frame = self.calls.pop()?;
        self.bstack = frame.bstack;
        self.rung_has_output = frame.rung_has_output;
        self.level = frame.level;
        self.zones = frame.zones;
        self.stage_power = frame.stage_power;
        self.loop_state = frame.loop_state;
        self.update_block_power();
        Some(frame.ret)
    }

    /// JMP: the enclosing stage off, the target on.
    fn jump_stage(&mut self, own: u32, to: u32) {
        self.set_bit(
            Bit {
                kind: Kind::S,
                n: own,
            },
            false,
        );
        self.set_bit(
            Bit {
                kind: Kind::S,
                n: to,
            },
            true,
        );
    }

    /// Remember which instruction last changed stage bit `n`, and when (the Stages panel).
    fn note_stage_change(&mut self, n: u32) {
        let change = StageChange {
            stage: n,
            line: self.pc_line_now(),
            at: crate::machine::Pos {
                tick: self.tick,
                step: self.step + 1,
            },
        };
        match self.stage_changes.iter_mut().find(|c| c.stage == n) {
            Some(c) => *c = change,
            None => self.stage_changes.push(change),
        }
    }

    fn update_block_power(&mut self) {
        self.block_power = self.stage_power && self.zones[usize::from(self.level.min(7))];
    }

    /// NOT: the top of the boolean stack inverted.
    #[inline(always)]
    fn invert_top(&mut self) {
        if let Some(top) = self.bstack.last_mut() {
            *top = !*top;
        }
    }

    /// An output that runs whatever its rung's power `p` (spec §5).
    pub(super) fn always(&mut self, op: Op, p: bool) {
        match op {
            Op::Coil(b) => self.set_bit(b, p),
            Op::Pd(b, edge) => {
                let fired = self.edges.rose(edge as usize, p);
                self.set_bit(b, fired);
            }
            Op::OrOut(b, mark) => {
                let first = self
                    .orout_marks
                    .get_mut(mark as usize)
                    .is_some_and(|m| !std::mem::replace(m, true));
                let on = if first { p } else { self.bit(b) || p };
                self.set_bit(b, on);
            }
            Op::Timer(kind, n, preset) => {
                let (enable, reset) = if kind.accumulating() {
                    (self.leg(0), self.leg(1))
                } else {
                    (p, !p)
                };
                self.timer(kind, n, preset, enable, reset);
            }
            Op::Counter(kind, n, preset) => {
                let (up, down, reset) = match kind {
                    CounterKind::Cnt => (self.leg(0), false, self.leg(1)),
                    CounterKind::Sgcnt => (p, false, false),
                    CounterKind::Udc => (self.leg(0), self.leg(1), self.leg(2)),
                };
                self.counter(kind, n, preset, up, down, reset);
            }
            _ => {}
        }
    }

    /// Leg `i` of a multi-input box: the rung's i-th level, first STR first, inside the
    /// block's power.
    fn leg(&self, i: usize) -> bool {
        self.block_power && self.bstack.get(i).copied().unwrap_or(false)
    }

    /// A box's current value: one word, or a pair (low word first).
    fn box_value(&self, addr: u32, words: u32) -> u32 {
        if words == 2 {
            self.pair(addr)
        } else {
            u32::from(self.word(addr))
        }
    }

    fn set_box_value(&mut self, addr: u32, words: u32, value: u32) {
        self.set_word(addr, value as u16);
        if words == 2 {
            self.set_word(addr + 1, (value >> 16) as u16);
        }
    }

    fn preset(&self, preset: Preset) -> u32 {
        match preset {
            Preset::K(k) => k,
            Preset::Word(a) => u32::from(self.word(a)),
            Preset::Pair(a) => self.pair(a),
        }
    }

    /// The status bit of a box: current value ≥ preset as raw patterns (spec §9.15); a
    /// non-BCD preset also sets SP75 (§9.16).
    fn box_done(&mut self, value: u32, preset: Preset, words: u32) -> bool {
        let preset = self.preset(preset);
        if bcd_value(preset, 4 * words).is_none() {
            self.non_bcd();
        }
        value >= preset
    }

    /// A timer's execution (spec §6.9): reset, count this scan once, status.
    fn timer(&mut self, kind: TimerKind, n: u32, preset: Preset, enable: bool, reset: bool) {
        let words = if kind.accumulating() { 2 } else { 1 };
        let i = n as usize;
        self.box_before = self.box_value(n, words);
        if reset {
            self.set_box_value(n, words, 0);
            self.t_ms[i] = 0;
            self.t_counted[i] = 0;
            self.t[i] = false;
            return;
        }
        let max: u64 = if words == 2 { 99_999_999 } else { 9_999 };
        if enable && self.t_counted[i] != self.tick + 1 {
            self.t_counted[i] = self.tick + 1;
            match bcd_value(self.box_value(n, words), 4 * words) {
                None => self.non_bcd(),
                Some(value) if value < max => {
                    let (units, left) = accumulate(self.t_ms[i], self.time.scan_ms, kind.unit_ms());
                    let value = (value + units).min(max);
                    self.t_ms[i] = if value == max { 0 } else { left };
                    self.set_box_value(n, words, to_bcd(value));
                }
                Some(_) => self.t_ms[i] = 0,
            }
        }
        let value = self.box_value(n, words);
        self.t[i] = self.box_done(value, preset, words);
    }

    /// A counter's execution (spec §6.9): count rises, reset, status.
    fn counter(
        &mut self,
        kind: CounterKind,
        n: u32,
        preset: Preset,
        up: bool,
        down: bool,
        reset: bool,
    ) {
        let words = if kind == CounterKind::Udc { 2 } else { 1 };
        let i = n as usize;
        let addr = program::current_word(Kind::Ct, n);
        self.box_before = self.box_value(addr, words);
        let (rose_up, rose_down) = self.ct_in[i].rises(up, down);
        if reset {
            self.set_box_value(addr, words, 0);
            self.ct[i] = false;
            return;
        }
        if rose_up != rose_down {
            let max: u64 = if words == 2 { 99_999_999 } else { 9_999 };
            match bcd_value(self.box_value(addr, words), 4 * words) {
                None => self.non_bcd(),
                Some(v) => {
                    let v = if rose_up {
                        (v + 1).min(max)
                    } else {
                        v.saturating_sub(1)
                    };
                    self.set_box_value(addr, words, to_bcd(v));
                }
            }
        }
        let value = self.box_value(addr, words);
        self.ct[i] = self.box_done(value, preset, words);
    }

    /// RST of a timer or counter bit: its box starts over (value word(s), time, status).
    fn reset_box(&mut self, b: Bit) {
        let i = b.n as usize;
        let words = self.program.box_words(b);
        let addr = program::current_word(b.kind, b.n);
        if (addr + words) as usize <= self.v.len() {
            self.set_box_value(addr, words, 0);
        }
        if b.kind == Kind::T {
            self.t_ms[i] = 0;
            self.t_counted[i] = 0;
        }
        self.set_bit(b, false);
    }

    /// An output instruction on a powered rung.
    fn output(&mut self, op: Op) {
        match op {
            Op::Rst(a, b) if matches!(a.kind, Kind::T | Kind::Ct) => {
                for n in a.n..=b.n {
                    self.reset_box(Bit { kind: a.kind, n });
                }
            }
            Op::Set(a, b) | Op::Rst(a, b) => {
                let on = matches!(op, Op::Set(..));
                for n in a.n..=b.n {
                    self.set_bit(Bit { kind: a.kind, n }, on);
                }
            }
            Op::Table(kind, operand) => self.table(kind, operand),
            Op::Inv => {
                self.acc = !self.acc;
                self.zn();
            }
            Op::Cmp(w) => {
                let w = self.w(w);
                self.compare(self.acc & 0xFFFF, w);
            }
            Op::CmpD(d) => {
                let d = self.d(d);
                self.compare(self.acc, d);
            }
            Op::Ld(w) => {
                let v = self.w(w);
                self.load(v);
            }
            Op::Ldd(d) => {
                let v = self.d(d);
                self.load(v);
            }
            Op::Lda(n) => self.load(n),
            Op::Ldf(e, n) => {
                let v = (0..u32::from(n)).fold(0u32, |acc, i| {
                    let b = Bit {
                        kind: e.kind,
                        n: e.n + i,
                    };
                    acc | (u32::from(self.bit(b)) << i)
                });
                self.load(v);
            }
            Op::OutV(a) => {
                self.set_word(a, self.acc as u16);
                self.load_pending = false;
            }
            Op::OutD(a) => {
                self.set_word(a, self.acc as u16);
                self.set_word(a + 1, (self.acc >> 16) as u16);
                self.load_pending = false;
            }
            Op::OutF(e, n) => {
                for i in 0..u32::from(n) {
                    self.set_bit(
                        Bit {
                            kind: e.kind,
                            n: e.n + i,
                        },
                        self.acc >> i & 1 == 1,
                    );
                }
                self.load_pending = false;
            }
            Op::Pop => self.acc = self.pop(),
            Op::Bcd(m, s) => self.bcd_math(m, s),
            Op::Binary(m, s) => self.binary_math(m, s),
            Op::IncB(a) | Op::DecB(a) => {
                let was = self.word(a);
                let now = if matches!(op, Op::IncB(_)) {
                    was.wrapping_add(1)
                } else {
                    was.wrapping_sub(1)
                };
                self.set_word(a, now);
                self.sp[sp::SP63] = now == 0;
            }
            Op::ToBin => match bcd_value(self.acc, 8) {
                Some(v) => {
                    self.acc = v as u32;
                    self.sp[sp::SP75] = false;
                    self.zn();
                }
                None => self.non_bcd(),
            },
            Op::ToBcd => {
                self.acc = to_bcd(u64::from(self.acc));
                self.zn();
            }
            Op::LogicV(l, a) => {
                let w = u32::from(self.word(a));
                self.acc = l.apply(self.acc & 0xFFFF, w);
                self.sp[sp::SP63] = self.acc == 0;
            }
            Op::LogicD(l, d) => {
                let v = self.d(d);
                self.acc = l.apply(self.acc, v);
                self.zn();
            }
            Op::LogicS(l) => {
                let v = self.stack[0];
                self.acc = l.apply(self.acc, v);
                self.pop();
                self.zn();
            }
            Op::Shift(kind, n) => {
                let n = self.w(n);
                self.acc = match kind {
                    ShiftKind::Shfl => self.acc.checked_shl(n).unwrap_or(0),
                    ShiftKind::Shfr => self.acc.checked_shr(n).unwrap_or(0),
                    ShiftKind::Rotl => self.acc.rotate_left(n % 32),
                    ShiftKind::Rotr => self.acc.rotate_right(n % 32),
                };
            }
            _ => {}
        }
    }

    /// The line of the instruction about to run (0 past the end).
    pub fn pc_line_now(&self) -> usize {
        self.program
            .instrs
            .get(self.pc as usize)
            .map_or(0, |i| i.line)
    }

    /// Every timer and counter box for the Timers & counters panel, in program order.
    pub fn boxes(&self) -> Vec<crate::machine::plc::BoxRow> {
        self.program
            .boxes
            .iter()
            .filter_map(|b| {
                let ins = self.program.instrs.get(b.instr)?;
                let (mnemonic, unit_ms) = match ins.op {
                    Op::Timer(k, ..) => (k.mnemonic(), Some(k.unit_ms())),
                    Op::Counter(k, ..) => (k.mnemonic(), None),
                    _ => return None,
                };
                let status = program::bit_name(b.status);
                let raw = self.box_value(program::current_word(b.status.kind, b.status.n), b.words);
                let digits = 4 * b.words;
                Some(crate::machine::plc::BoxRow {
                    title: format!("{mnemonic} {status}"),
                    preset_from: ins.text.split_whitespace().nth(2).unwrap_or("").to_string(),
                    preset: bcd_value(self.preset(b.preset), digits),
                    value_at: format!("{}A{:o}", b.status.kind.letter(), b.status.n),
                    value: bcd_value(raw, digits),
                    raw: u64::from(raw),
                    max: if b.words == 2 { 99_999_999 } else { 9_999 },
                    unit_ms,
                    done: self.bit(b.status),
                    line: ins.line,
                    countdown: None,
                    status,
                })
            })
            .collect()
    }

    /// The table of MOV/SETBIT/RSTBIT: its start (low word of ACC) and BCD count (L1), or
    /// None for a non-BCD count.
    pub(super) fn table_span(&self) -> Option<(u32, u32)> {
        let count = bcd_value(self.stack[0] & 0xFFFF, 4)?;
        Some((self.acc & 0xFFFF, count as u32))
    }

    /// MOV, SETBIT, RSTBIT (spec §6.6, §9.25): ACC and the stack stay as they are.
    fn table(&mut self, kind: program::Table, operand: u32) {
        let Some((start, count)) = self.table_span() else {
            self.non_bcd();
            return;
        };
        let last = V_WORDS as u32 - 1;
        match kind {
            program::Table::Mov => {
                if count > 0 && (start + count - 1 > last || operand + count - 1 > last) {
                    self.out_of_range();
                    return;
                }
                for i in 0..count {
                    let w = self.word(start + i);
                    self.set_word(operand + i, w);
                }
            }
            program::Table::SetBit | program::Table::RstBit => {
                let word = start + operand / 16;
                if operand >= 16 * count || word > last {
                    self.out_of_range();
                    return;
                }
                let bit = 1u16 << (operand % 16);
                let w = self.word(word);
                let w = if kind == program::Table::SetBit {
                    w | bit
                } else {
                    w & !bit
                };
                self.set_word(word, w);
            }
        }
        self.sp[sp::SP53] = false;
        self.sp[sp::SP75] = false;
    }

    /// A table past V37777: SP53 = 1, SP75 = 0, nothing else (spec §6.6).
    fn out_of_range(&mut self) {
        self.divide_by_zero();
        self.sp[sp::SP75] = false;
    }

    /// CMP/CMPD: SP60 less, SP61 equal, SP62 greater (unsigned).
    fn compare(&mut self, a: u32, b: u32) {
        self.sp[sp::SP60] = a < b;
        self.sp[sp::SP61] = a == b;
        self.sp[sp::SP62] = a > b;
    }

    fn scan_start(&mut self) {
        self.x_image.clone_from(&self.x);
        let t = self.tick;
        self.sp[sp::SP0] = t == 0;
        self.sp[sp::SP1] = true;
        self.sp[sp::SP2] = false;
        for (relay, period) in [
            (sp::SP3, 60_000),
            (sp::SP4, 1_000),
            (sp::SP5, 100),
            (sp::SP6, 50),
        ] {
            self.sp[relay] = self.time.late_half(t, period);
        }
        self.sp[sp::SP7] = t % 2 == 1;
        self.orout_marks.iter_mut().for_each(|m| *m = false);
        self.fired_this_scan.clear();
        self.level = 0;
        self.zones = ZONES_AT_START;
        self.stage_power = true;
        self.block_power = true;
        self.loop_state = None;
        self.calls.clear();
        self.acc = 0;
        self.stack = [0; LEVELS];
        self.depth = 0;
        self.load_pending = false;
        self.bstack.clear();
        self.rung_has_output = false;
        self.power.iter_mut().for_each(|p| *p = None);
    }
}
