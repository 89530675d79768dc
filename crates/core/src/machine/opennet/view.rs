//! OpenNet's face for the debugger and the runner (spec §2, §9).

use std::any::Any;

use serde_json::json;

use crate::machine::JsonMap;
use std::fmt::Write;

use crate::machine::PlcView;

use super::program::{Area, BOXES, Bit, Op, SPECIAL, Value, Word, point_name};
use super::{M8003, M8004, Mark, OpenNet};
use crate::machine::{
    Format, Loc, LocInfo, MachineView, Pos, RunState, SpaceInfo, SpaceKind, WriteError,
};

pub use super::memory::*;
use super::memory::{SPECIAL_DESCRIPTIONS, area_of};

/// Each location a word operand covers in `words` words at `offset`: registers, points, or
/// (as a destination) timer and counter presets.
fn word_locs(w: &Word, words: u32, offset: u32, f: &mut dyn FnMut(Loc)) {
    match *w {
        Word::Reg { n, .. } => (n + offset..n + offset + words).for_each(|r| f(Loc::new(D, r))),
        Word::Bits { area, index, .. } => {
            let start = index + offset * 16;
            (start..start + words * 16).for_each(|b| f(Loc::new(area_space(area), b)));
        }
        Word::Timer { n, .. } => {
            (n + offset..n + offset + words).for_each(|t| f(Loc::new(T_PRESET, t)))
        }
        Word::Counter { n, .. } => {
            (n + offset..n + offset + words).for_each(|c| f(Loc::new(C_PRESET, c)))
        }
        Word::Const(_) => {}
    }
}

/// Every REP cycle's block of a destination operand.
fn rep_locs(w: &Word, block: u32, rep: u8, f: &mut dyn FnMut(Loc)) {
    for c in 0..u32::from(rep) {
        word_locs(w, block, if w.repeats() { c * block } else { 0 }, f);
    }
}

/// Every location `op` may write when it runs (a superset of one execution's writes).
pub fn static_writes(op: &Op, f: &mut dyn FnMut(Loc)) {
    use super::program::Arith;
    match *op {
        Op::Out(b, _) | Op::Set(b) | Op::Rst(b) => f(bit_loc(b)),
        Op::Mov { ty, dst, rep, .. } => rep_locs(&dst, ty.words(), rep, f),
        Op::Arith {
            op, ty, dst, rep, ..
        } => {
            let block = match op {
                Arith::Add | Arith::Sub => ty.words(),
                Arith::Mul => 2,
                Arith::Div => 2 * ty.words(),
            };
            rep_locs(&dst, block, rep, f);
            f(Loc::new(SPECIAL_SPACE, M8003 as u32));
            f(Loc::new(SPECIAL_SPACE, M8004 as u32));
        }
        Op::Step { ty, reg, .. } => (reg..reg + ty.words()).for_each(|r| f(Loc::new(D, r))),
        Op::Timer { n, preset, .. } => {
            f(Loc::new(T_CURRENT, n));
            f(Loc::new(T, n));
            if let Value::Reg(_) = preset {
                f(Loc::new(T_PRESET, n));
            }
        }
        Op::Counter { n, preset, .. } => {
            f(Loc::new(C_CURRENT, n));
            f(Loc::new(C, n));
            if let Value::Reg(_) = preset {
                f(Loc::new(C_PRESET, n));
            }
        }
        Op::ShiftRegister { first, len, .. } => {
            (first..first + len).for_each(|i| f(Loc::new(R, i)))
        }
        Op::WordCompare {
            dst: (area, at),
            dst_repeat,
            rep,
            ..
        } => {
            let span = if dst_repeat { u32::from(rep) } else { 1 };
            (at..at + span).for_each(|i| f(Loc::new(area_space(area), i)));
        }
        Op::WordLogic { ty, dst, rep, .. } => rep_locs(&dst, ty.words(), rep, f),
        Op::Convert { ty, dst, rep, .. } => {
            rep_locs(&dst, ty.words(), rep, f);
            f(Loc::new(SPECIAL_SPACE, M8004 as u32));
        }
        Op::Shift { ty, word, .. } => {
            word_locs(&word, ty.words(), 0, f);
            f(Loc::new(SPECIAL_SPACE, M8003 as u32));
        }
        Op::Mcs(_) | Op::Mcr => f(Loc::new(LOGIC, 1)),
        _ => {}
    }
}

impl OpenNet {
    /// Each location the last executed instruction wrote (one may come twice).
    #[inline]
    fn each_written<F: FnMut(Loc)>(&self, mut f: F) {
        use super::program::Arith;
        let Some(instr) = self.last.and_then(|i| self.program.instrs.get(i as usize)) else {
            return;
        };
        match instr.op {
            Op::Mov { ty, dst, .. } if self.last_acted => {
                for c in &self.last_cycles {
                    word_locs(&dst, ty.words(), c.dst_at, &mut f);
                }
            }
            Op::Arith { op, ty, dst, .. } if self.last_acted => {
                let block = match op {
                    Arith::Add | Arith::Sub => ty.words(),
                    Arith::Mul => 2,
                    Arith::Div => 2 * ty.words(),
                };
                for c in self.last_cycles.iter().filter(|c| c.error.is_none()) {
                    word_locs(&dst, block, c.dst_at, &mut f);
                }
                if matches!(op, Arith::Add | Arith::Sub) {
                    f(Loc::new(SPECIAL_SPACE, M8003 as u32));
                }
                if self.last_cycles.iter().any(|c| c.error.is_some()) {
                    f(Loc::new(SPECIAL_SPACE, M8004 as u32));
                }
            }
            Op::Convert { ty, dst, .. } if self.last_acted => {
                for c in &self.last_cycles {
                    if c.error.is_none() {
                        word_locs(&dst, ty.words(), c.dst_at, &mut f);
                    }
                }
                if self.last_cycles.iter().any(|c| c.error.is_some()) {
                    f(Loc::new(SPECIAL_SPACE, M8004 as u32));
                }
            }
            // Timers, counters and shift registers run whatever their input; the rest act
            // only when it is on.
            Op::Out(..)
            | Op::Set(_)
            | Op::Rst(_)
            | Op::Timer { .. }
            | Op::Counter { .. }
            | Op::ShiftRegister { .. }
            | Op::Mcs(_)
            | Op::Mcr => static_writes(&instr.op, &mut f),
            op if self.last_acted => static_writes(&op, &mut f),
            _ => {}
        }
    }

    /// Timers the program names, with their instruction (if it has one).
    pub fn timer_rows(&self) -> Vec<crate::machine::plc::BoxRow> {
        use crate::machine::plc::BoxRow;
        let mut rows = Vec::new();
        let scan_ms = self.time.scan_ms;
        for instr in &self.program.instrs {
            match instr.op {
                Op::Timer { kind, n, preset } => {
                    let t = self.timers[n as usize];
                    let inc = kind.increment_ms();
                    rows.push(BoxRow {
                        title: format!("{} T{n}", kind.mnemonic()),
                        status: format!("T{n}"),
                        preset_from: preset_text(preset),
                        preset: Some(u64::from(t.preset)),
                        value_at: format!("T{n}.current"),
                        value: Some(u64::from(t.current)),
                        raw: u64::from(t.current),
                        max: 65535,
                        unit_ms: Some(inc),
                        done: t.output,
                        line: instr.line,
                        countdown: Some(crate::machine::plc::Countdown {
                            running: t.running,
                            elapsed_ms: t.elapsed_ms,
                            scan_ms,
                        }),
                    });
                }
                Op::Counter {
                    kind, n, preset, ..
                } => {
                    let c = self.counters[n as usize];
                    rows.push(BoxRow {
                        title: format!("{} C{n}", kind.mnemonic()),
                        status: format!("C{n}"),
                        preset_from: preset_text(preset),
                        preset: Some(u64::from(c.preset)),
                        value_at: format!("C{n}.current"),
                        value: Some(u64::from(c.current)),
                        raw: u64::from(c.current),
                        max: 65535,
                        unit_ms: None,
                        done: c.output,
                        line: instr.line,
                        countdown: None,
                    });
                }
                _ => {}
            }
        }
        rows
    }
}

fn preset_text(v: Value) -> String {
    match v {
        Value::Const(c) => c.to_string(),
        Value::Reg(n) => format!("D{n}"),
    }
}

impl MachineView for OpenNet {
    fn dialect(&self) -> &'static str {
        "opennet"
    }
    fn tick_micros(&self) -> u32 {
        self.time.micros()
    }
    fn spaces(&self) -> Vec<SpaceInfo> {
        let space = |name, title, kind, len| SpaceInfo {
            name,
            title,
            kind,
            len,
        };
        vec![
            space(
                "D",
                "Data registers",
                SpaceKind::Registers,
                super::REGISTERS as u32,
            ),
            space("I", "Inputs", SpaceKind::Inputs, Area::I.points()),
            space("Q", "Outputs", SpaceKind::Bits, Area::Q.points()),
            space("M", "Internal relays", SpaceKind::Bits, Area::M.points()),
            space(
                "special",
                "Special relays",
                SpaceKind::Flags,
                SPECIAL.len() as u32,
            ),
            space(
                "R",
                "Shift-register bits",
                SpaceKind::Bits,
                Area::R.points(),
            ),
            space("T", "Timer outputs", SpaceKind::Bits, BOXES),
            space(
                "T.current",
                "Timer current values",
                SpaceKind::Registers,
                BOXES,
            ),
            space("T.preset", "Timer presets", SpaceKind::Registers, BOXES),
            space("C", "Counter outputs", SpaceKind::Bits, BOXES),
            space(
                "C.current",
                "Counter current values",
                SpaceKind::Registers,
                BOXES,
            ),
            space("C.preset", "Counter presets", SpaceKind::Registers, BOXES),
            space("logic", "Logic state", SpaceKind::Flags, 2),
        ]
    }
    fn info(&self, loc: Loc) -> Option<LocInfo> {
        let i = loc.index;
        let bit = |name: String, description: &'static str, editable: bool| LocInfo {
            name,
            alias: None,
            description,
            width: 1,
            signed: false,
            format: None,
            bits: &[],
            editable,
        };
        let word = |name: String, description: &'static str| LocInfo {
            description,
            format: Some(Format::Unsigned),
            ..LocInfo::word(name, 16, false)
        };
        match loc.space {
            D if (i as usize) < super::REGISTERS => {
                let signed = self.program.signed_regs.binary_search(&i).is_ok();
                Some(LocInfo {
                    description: if signed {
                        "data register (16 bits), read as signed (type I or L)"
                    } else {
                        "data register (16 bits)"
                    },
                    // The stored pattern stays unsigned for the trace, the log and conditions
                    // (spec §2); only the view's reading follows the type.
                    format: Some(if signed {
                        Format::Signed
                    } else {
                        Format::Unsigned
                    }),
                    ..LocInfo::word(format!("D{i}"), 16, false)
                })
            }
            SPECIAL_SPACE => SPECIAL
                .get(i as usize)
                .map(|&n| bit(format!("M{n}"), SPECIAL_DESCRIPTIONS[i as usize], i < 2)),
            // The instructions own the outputs; presets and current values may be edited.
            T if i < BOXES => Some(bit(
                format!("T{i}"),
                "timer output (on when the current value reaches 0)",
                false,
            )),
            C if i < BOXES => Some(bit(format!("C{i}"), "counter output", false)),
            T_CURRENT if i < BOXES => Some(word(
                format!("T{i}.current"),
                "timer current value: counts down from the preset",
            )),
            T_PRESET if i < BOXES => Some(word(
                format!("T{i}.preset"),
                "timer preset, in the timer's increments",
            )),
            C_CURRENT if i < BOXES => Some(word(format!("C{i}.current"), "counter current value")),
            C_PRESET if i < BOXES => Some(word(format!("C{i}.preset"), "counter preset")),
            LOGIC => match i {
                0 => Some(bit("RLO".into(), "result of logic operation", false)),
                1 => Some(bit(
                    "MC".into(),
                    "master control: outputs take RLO AND MC (MCS/MCR)",
                    false,
                )),
                _ => None,
            },
            s => {
                let area = area_of(s)?;
                (i < area.points()).then(|| {
                    bit(
                        point_name(area, i),
                        match area {
                            Area::I => "input",
                            Area::Q => "output",
                            Area::M => "internal relay",
                            Area::R => "shift-register bit",
                        },
                        true,
                    )
                })
            }
        }
    }
    fn read(&self, loc: Loc) -> u64 {
        let i = loc.index as usize;
        let timer = self.timers.get(i);
        let counter = self.counters.get(i);
        match loc.space {
            D => self.d.get(i).map_or(0, |&v| u64::from(v)),
            // A forced input reads as what the program sees.
            I => u64::from(
                self.forces
                    .get(loc)
                    .unwrap_or_else(|| self.inputs.get(i).copied().unwrap_or(false)),
            ),
            Q => u64::from(self.q.get(i).copied().unwrap_or(false)),
            M => u64::from(self.m.get(i).copied().unwrap_or(false)),
            R => u64::from(self.r.get(i).copied().unwrap_or(false)),
            SPECIAL_SPACE => u64::from(self.special.get(i).copied().unwrap_or(false)),
            T => timer.map_or(0, |t| u64::from(t.output)),
            T_CURRENT => timer.map_or(0, |t| u64::from(t.current)),
            T_PRESET => timer.map_or(0, |t| u64::from(t.preset)),
            C => counter.map_or(0, |c| u64::from(c.output)),
            C_CURRENT => counter.map_or(0, |c| u64::from(c.current)),
            C_PRESET => counter.map_or(0, |c| u64::from(c.preset)),
            LOGIC if i == 0 => u64::from(self.rlo),
            LOGIC => u64::from(self.mc),
            _ => 0,
        }
    }
    fn write(&mut self, loc: Loc, value: u64) -> Result<(), WriteError> {
        let info = crate::machine::check_write(self, loc, value)?;
        self.forces.check_write(loc, || info.name)?;
        let i = loc.index as usize;
        let on = value != 0;
        match loc.space {
            D => self.d[i] = value as u16,
            I => self.inputs[i] = on,
            Q => self.q[i] = on,
            M => self.m[i] = on,
            R => self.r[i] = on,
            SPECIAL_SPACE => self.special[i] = on,
            T_CURRENT => self.timers[i].current = value as u16,
            T_PRESET => self.timers[i].preset = value as u16,
            C_CURRENT => self.counters[i].current = value as u16,
            C_PRESET => self.counters[i].preset = value as u16,
            _ => return Err(WriteError::NoSuchLocation),
        }
        Ok(())
    }

    fn find(&self, name: &str) -> Option<Loc> {
        parse_name(name)
    }
    fn used(&self) -> Vec<Loc> {
        let p = &self.program;
        let mut out: Vec<Loc> = p.used_regs.iter().map(|&n| Loc::new(D, n)).collect();
        out.extend(
            p.used_bits
                .iter()
                .map(|&(area, i)| Loc::new(area_space(area), i)),
        );
        out.extend((0..SPECIAL.len() as u32).map(|i| Loc::new(SPECIAL_SPACE, i)));
        for &n in &p.used_timers {
            out.extend([T, T_CURRENT, T_PRESET].map(|s| Loc::new(s, n)));
        }
        for &n in &p.used_counters {
            out.extend([C, C_CURRENT, C_PRESET].map(|s| Loc::new(s, n)));
        }
        out.extend([Loc::new(LOGIC, 0), Loc::new(LOGIC, 1)]);
        out
    }
    fn warnings(&self) -> Vec<crate::machine::Diagnostic> {
        let mut warnings = self.program.warnings.clone();
        warnings.extend(crate::machine::plc::ladder::duplicate_coils(
            &self.program.ladder,
        ));
        warnings
    }
    fn line_notes(&self) -> Vec<(usize, String)> {
        let instrs = &self.program.instrs;
        let mut notes = Vec::new();
        for (i, ins) in instrs.iter().enumerate() {
            let mark = self.marks.get(i).copied().unwrap_or_default();
            let ran = mark != Mark::Jumped && (self.tick > 0 || i < self.step as usize);
            match ins.op {
                Op::Jmp(to) => {
                    let Some(target) = instrs.get(to as usize) else {
                        continue;
                    };
                    // A jump straight onto its JEND skips nothing: it shows as not taken.
                    let taken = self.marks.get(i + 1).is_some_and(|m| *m == Mark::Jumped);
                    let state = match mark {
                        Mark::Jumped => String::new(),
                        _ if taken => " (taken)".into(),
                        _ if ran => " (not taken)".into(),
                        _ => String::new(),
                    };
                    notes.push((ins.line, format!("→ JEND line {}{state}", target.line)));
                }
                Op::Jend => {
                    let from: Vec<String> = instrs
                        .iter()
                        .filter(|j| j.op == Op::Jmp(i as u32))
                        .map(|j| j.line.to_string())
                        .collect();
                    if !from.is_empty() {
                        notes.push((ins.line, format!("← JMP line {}", from.join(", "))));
                    }
                }
                // An area whose MC is off this scan: its code is marked from the MCS on.
                Op::Mcs(end) => {
                    let end = instrs.get(end as usize).map_or(0, |j| j.line);
                    if self.marks.get(i + 1) == Some(&Mark::MasterOff) {
                        notes.push((ins.line, format!("MC off: outputs off to MCR line {end}")));
                    }
                }
                Op::Timer { n, .. } if ran => {
                    let t = self.timers[n as usize];
                    notes.push((ins.line, format!("T{n}.current = {}", t.current)));
                }
                Op::Counter { n, .. } if ran => {
                    let c = self.counters[n as usize];
                    notes.push((ins.line, format!("C{n}.current = {}", c.current)));
                }
                _ => {}
            }
        }
        notes
    }
    fn pc_line(&self) -> Option<usize> {
        self.program.instrs.get(self.pc as usize).map(|i| i.line)
    }
    fn run_state(&self) -> RunState {
        RunState::Running
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
    fn for_each_written(&self, f: &mut dyn FnMut(Loc)) {
        self.each_written(f);
    }
    fn note_writes(&self, set: &mut crate::machine::WriteSet) {
        self.each_written(|loc| set.insert(loc));
    }
    fn explain_last(&self) -> Option<String> {
        super::explain::explain(self)
    }
    fn last_line(&self) -> Option<usize> {
        self.last
            .and_then(|i| self.program.instrs.get(i as usize))
            .map(|i| i.line)
    }
    fn error_lamp(&self) -> bool {
        self.special[M8004]
    }
    fn report_json(&self, out: &mut JsonMap) {
        let registers: JsonMap = (self.d.iter().enumerate())
            .filter(|(_, v)| **v != 0)
            .map(|(i, v)| (format!("D{i}"), json!(v)))
            .collect();
        // The five relays always; M8123 and M8125 when the program names them. The clocks as
        // the last scan saw them; nothing before a scan has run.
        let named = |i: usize| {
            self.program.instrs.iter().any(|ins| match ins.op {
                Op::Lod(b, _) | Op::And(b, _) | Op::Or(b, _) => b == Bit::Special(i as u8),
                _ => false,
            })
        };
        let flags: JsonMap = (SPECIAL.iter().enumerate())
            .filter(|&(i, _)| i < 5 || named(i))
            .map(|(i, n)| {
                let on = self.special[i] && (i < 2 || self.tick > 0);
                (format!("M{n}"), json!(u8::from(on)))
            })
            .collect();
        let mut bits = JsonMap::new();
        for (area, values) in [
            (Area::I, &self.input_image),
            (Area::Q, &self.q),
            (Area::M, &self.m),
            (Area::R, &self.r),
        ] {
            for (i, _) in values.iter().enumerate().filter(|(_, b)| **b) {
                bits.insert(point_name(area, i as u32), json!(1));
            }
        }
        let boxes = |list: &[u32], letter: char, get: &dyn Fn(usize) -> (u16, u16, bool)| {
            (list.iter())
                .map(|&n| {
                    let (preset, current, output) = get(n as usize);
                    let state =
                        json!({"preset": preset, "current": current, "output": u8::from(output)});
                    (format!("{letter}{n}"), state)
                })
                .collect::<JsonMap>()
        };
        let timers = boxes(&self.program.used_timers, 'T', &|n| {
            let t = self.timers[n];
            (t.preset, t.current, t.output)
        });
        let counters = boxes(&self.program.used_counters, 'C', &|n| {
            let c = self.counters[n];
            (c.preset, c.current, c.output)
        });
        let last = self.last_error.map_or(
            serde_json::Value::Null,
            |e| json!({"kind": e.kind.to_string(), "line": e.line, "tick": e.tick}),
        );
        out.insert("registers".into(), registers.into());
        out.insert("flags".into(), flags.into());
        out.insert("bits".into(), bits.into());
        out.insert("timers".into(), timers.into());
        out.insert("counters".into(), counters.into());
        out.insert("settings".into(), json!({"scan_ms": self.time.scan_ms}));
        out.insert("error_count".into(), json!(self.error_count));
        out.insert("last_error".into(), last);
    }
    fn report_text(&self) -> String {
        let mut out = String::new();
        let regs: Vec<String> = self
            .d
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0)
            .map(|(i, v)| format!("D{i}={v}"))
            .collect();
        let _ = writeln!(out, "registers (non-zero): {}", regs.join(" "));
        let _ = writeln!(
            out,
            "M8003={} M8004={} errors: {}",
            u8::from(self.special[0]),
            u8::from(self.special[1]),
            self.error_count
        );
        if let Some(e) = self.last_error {
            let _ = writeln!(
                out,
                "last error: {} on line {} in scan {}",
                e.kind, e.line, e.tick
            );
        }
        for row in self.timer_rows() {
            let _ = writeln!(
                out,
                "{}: preset {}, current {}, output {}",
                row.title,
                row.preset.unwrap_or(0),
                row.raw,
                u8::from(row.done)
            );
        }
        out
    }
    fn as_plc(&self) -> Option<&dyn PlcView> {
        Some(self)
    }
    fn as_plc_mut(&mut self) -> Option<&mut dyn PlcView> {
        Some(self)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}
