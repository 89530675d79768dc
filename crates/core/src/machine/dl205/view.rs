//! DL205's face for the debugger and the runner (spec §3, §8).

use std::any::Any;

use serde_json::json;

use crate::machine::JsonMap;
use std::fmt::Write;

use crate::machine::PlcView;
use crate::machine::plc::ScannedPlc;

use super::program::{Bit, Kind, SPECIAL, bit_name, mapped};
use super::{Dl205, LEVELS, V_WORDS, bcd_value};
use crate::machine::{
    Format, Loc, LocInfo, MachineView, Pos, RunState, SpaceInfo, SpaceKind, WriteError,
};

pub use super::memory::*;
use super::memory::{MAPPED_WORDS, NO_BITS};

impl Dl205 {
    /// The special relays an instruction that ran wrote, set or cleared (spec §6.3, §6.4): a
    /// math instruction that met a non-BCD digit or a zero divisor wrote only SP75 or SP53.
    pub fn flags_written(&self, op: super::program::Op, line: usize) -> &'static [usize] {
        use super::program::{Math, Op, sp::*};
        let stopped_by = |flag: usize, at: Option<usize>| self.sp[flag] && at == Some(line);
        let untouched = self.acc == self.before.0 && self.moved == super::StackMove::None;
        match op {
            Op::Bcd(..) | Op::ToBin if untouched && stopped_by(SP75, self.sp75_line) => &[SP75],
            Op::Bcd(..) | Op::Binary(..) if untouched && stopped_by(SP53, self.sp53_line) => {
                &[SP53]
            }
            Op::Bcd(Math::Add, _) => &[SP63, SP66, SP67, SP70, SP75],
            Op::Bcd(Math::Sub, _) => &[SP63, SP64, SP65, SP70, SP75],
            Op::Bcd(Math::Mul, _) => &[SP63, SP70, SP75],
            Op::Bcd(Math::Div, _) => &[SP53, SP63, SP70, SP75],
            Op::Binary(Math::Add, _) => &[SP63, SP66, SP67, SP70, SP73],
            Op::Binary(Math::Sub, _) => &[SP63, SP64, SP65, SP70],
            Op::Binary(Math::Mul, _) => &[SP63, SP70],
            Op::Binary(Math::Div, _) => &[SP53, SP63, SP70],
            Op::ToBin => &[SP63, SP70, SP75],
            Op::ToBcd | Op::LogicD(..) | Op::LogicS(..) => &[SP63, SP70],
            Op::IncB(_) | Op::DecB(_) | Op::LogicV(..) => &[SP63],
            Op::Inv => &[SP63, SP70],
            Op::Table(..) if self.raised_error && self.sp[SP75] => &[SP75],
            Op::Table(..) => &[SP53, SP75],
            Op::Cmp(_) | Op::CmpD(_) => &[SP60, SP61, SP62],
            // Boxes only ever set SP75 (spec §6.9).
            Op::Timer(..) | Op::Counter(..) if self.raised_error => &[SP75],
            _ => &[],
        }
    }

    /// The V words the last MOV/SETBIT/RSTBIT wrote (none when it met an error).
    fn table_writes(&self, f: &mut impl FnMut(Loc)) {
        use super::program::{Op, Table};
        let Some(ins) = self.last.and_then(|i| self.program.instrs.get(i as usize)) else {
            return;
        };
        let (Op::Table(kind, operand), Some((start, count))) = (ins.op, self.table_span()) else {
            return;
        };
        if self.raised_error {
            return;
        }
        match kind {
            Table::Mov => (operand..operand + count).for_each(|a| f(v_loc(a))),
            Table::SetBit | Table::RstBit => f(v_loc(start + operand / 16)),
        }
    }

    /// Each location the last executed instruction wrote (one may come twice).
    #[inline]
    fn each_written<F: FnMut(Loc)>(&self, mut f: F) {
        use super::program::Op;
        let Some(ins) = self.last.and_then(|i| self.program.instrs.get(i as usize)) else {
            return;
        };
        if self.acc != self.before.0 {
            f(Loc::new(ACC, 0));
        }
        // The levels a push or pop shifted (those holding values), or the one overwritten.
        let levels = match self.moved {
            super::StackMove::None => 0,
            super::StackMove::Push { .. } => u32::from(self.depth),
            super::StackMove::Pop { .. } => u32::from(self.depth) + 1,
            super::StackMove::Overwrite { .. } => 1,
        };
        (1..=levels.min(LEVELS as u32)).for_each(|i| f(Loc::new(ACC, i)));
        if self.last_ran || ins.op.always_runs() {
            for &flag in self.flags_written(ins.op, ins.line) {
                f(Loc::new(SP, flag as u32));
            }
        }
        match ins.op {
            Op::OutV(a) | Op::IncB(a) | Op::DecB(a) if self.last_ran => word_writes(a, &mut f),
            Op::OutD(a) if self.last_ran => {
                word_writes(a, &mut f);
                word_writes(a + 1, &mut f);
            }
            Op::Table(..) if self.last_ran => self.table_writes(&mut f),
            Op::Coil(b) | Op::Pd(b, _) | Op::OrOut(b, _) => f(bit_loc(b)),
            Op::Timer(..) | Op::Counter(..) => {
                // Value word(s) and status; SP75 came with the flags above.
                let writes = super::fast::box_writes(&ins.op);
                writes[..writes.len() - 1].iter().for_each(|&loc| f(loc));
            }
            Op::Rst(a, b) if self.last_ran && matches!(a.kind, Kind::T | Kind::Ct) => {
                for n in a.n..=b.n {
                    let status = Bit { kind: a.kind, n };
                    let word = super::program::current_word(a.kind, n);
                    let words = self.program.box_words(status);
                    (word..word + words).for_each(|w| f(Loc::new(V, w)));
                    f(bit_loc(status));
                }
            }
            Op::Set(a, b) | Op::Rst(a, b) if self.last_ran => {
                (a.n..=b.n).for_each(|n| f(Loc::new(kind_space(a.kind), n)));
            }
            Op::Jmp { to, own } if self.last_ran => {
                f(Loc::new(S, own));
                f(Loc::new(S, to));
            }
            Op::Njmp { to, own } if self.s.get(to as usize) == Some(&true) => {
                let rung = self
                    .power
                    .get(self.last.unwrap_or(0) as usize)
                    .copied()
                    .flatten();
                if rung == Some(false) && self.block_power {
                    f(Loc::new(S, own));
                    f(Loc::new(S, to));
                }
            }
            Op::For(..) if self.raised_error => f(Loc::new(SP, super::program::sp::SP75 as u32)),
            Op::OutF(e, n) if self.last_ran => {
                (e.n..e.n + u32::from(n)).for_each(|i| f(Loc::new(kind_space(e.kind), i)));
            }
            _ => {}
        }
    }
}

impl MachineView for Dl205 {
    fn dialect(&self) -> &'static str {
        "dl205"
    }
    fn tick_micros(&self) -> u32 {
        self.time.micros()
    }
    fn spaces(&self) -> Vec<SpaceInfo> {
        vec![
            SpaceInfo {
                name: "acc",
                title: "Accumulator and stack",
                kind: SpaceKind::Registers,
                len: 1 + LEVELS as u32,
            },
            SpaceInfo {
                name: "V",
                title: "V-memory",
                kind: SpaceKind::Registers,
                len: V_WORDS as u32,
            },
            SpaceInfo {
                name: "X",
                title: "Inputs",
                kind: SpaceKind::Inputs,
                len: Kind::X.count(),
            },
            SpaceInfo {
                name: "Y",
                title: "Outputs",
                kind: SpaceKind::Bits,
                len: Kind::Y.count(),
            },
            SpaceInfo {
                name: "C",
                title: "Control relays",
                kind: SpaceKind::Bits,
                len: Kind::C.count(),
            },
            SpaceInfo {
                name: "SP",
                title: "Special relays",
                kind: SpaceKind::Flags,
                len: SPECIAL.len() as u32,
            },
            SpaceInfo {
                name: "S",
                title: "Stage bits",
                kind: SpaceKind::Bits,
                len: Kind::S.count(),
            },
            SpaceInfo {
                name: "T",
                title: "Timer status bits",
                kind: SpaceKind::Bits,
                len: Kind::T.count(),
            },
            SpaceInfo {
                name: "CT",
                title: "Counter status bits",
                kind: SpaceKind::Bits,
                len: Kind::Ct.count(),
            },
            SpaceInfo {
                name: "VM",
                title: "Bit-mapped words",
                kind: SpaceKind::Registers,
                len: MAPPED_WORDS,
            },
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
            bits: NO_BITS,
            editable,
        };
        match loc.space {
            ACC if i == 0 => Some(LocInfo {
                description: "accumulator",
                format: Some(Format::Bcd),
                editable: false,
                ..LocInfo::word("ACC".into(), 32, false)
            }),
            ACC if (i as usize) <= LEVELS => Some(LocInfo {
                description: "accumulator stack level",
                format: Some(Format::Bcd),
                editable: false,
                ..LocInfo::word(format!("L{i}"), 32, false)
            }),
            V if (i as usize) < V_WORDS => Some(LocInfo {
                description: "V-memory word",
                format: Some(Format::Bcd),
                ..LocInfo::word(format!("V{i:o}"), 16, false)
            }),
            // A bit-mapped word reads as its 16 elements: binary.
            VM => mapped_address(i)
                .and_then(|a| Some((a, mapped(a)?)))
                .map(|(a, (kind, _))| LocInfo {
                    description: match kind {
                        Kind::X => "bit-mapped inputs (VX, read-only)",
                        Kind::Y => "bit-mapped outputs (VY)",
                        Kind::C => "bit-mapped control relays (VC)",
                        Kind::S => "bit-mapped stage bits (VS)",
                        Kind::T => "bit-mapped timer status (VT, read-only)",
                        Kind::Ct => "bit-mapped counter status (VCT, read-only)",
                        Kind::Sp => "bit-mapped special relays (VSP, read-only)",
                    },
                    format: Some(Format::Binary),
                    editable: super::program::writable_word(a),
                    ..LocInfo::word(format!("V{a:o}"), 16, false)
                }),
            X if i < Kind::X.count() => Some(bit(format!("X{i:o}"), "input", true)),
            Y if i < Kind::Y.count() => Some(bit(format!("Y{i:o}"), "output", true)),
            C if i < Kind::C.count() => Some(bit(format!("C{i:o}"), "control relay", true)),
            S if i < Kind::S.count() => Some(bit(format!("S{i:o}"), "stage bit", true)),
            // The boxes own their status bits: RST in the program clears them.
            T if i < Kind::T.count() => Some(bit(format!("T{i:o}"), "timer status", false)),
            CT if i < Kind::Ct.count() => Some(bit(format!("CT{i:o}"), "counter status", false)),
            SP => SPECIAL
                .get(i as usize)
                .map(|&n| bit(format!("SP{n:o}"), SP_DESCRIPTIONS[i as usize], false)),
            _ => None,
        }
    }
    fn read(&self, loc: Loc) -> u64 {
        let i = loc.index as usize;
        match loc.space {
            ACC if i == 0 => u64::from(self.acc),
            ACC => self.stack.get(i - 1).map_or(0, |&v| u64::from(v)),
            V => u64::from(self.word(i as u32)),
            VM => mapped_address(i as u32).map_or(0, |a| u64::from(self.word(a))),
            // A forced input reads as what the program sees.
            X => u64::from(
                self.forces
                    .get(loc)
                    .unwrap_or_else(|| self.x.get(i).copied().unwrap_or(false)),
            ),
            Y => u64::from(self.y.get(i).copied().unwrap_or(false)),
            C => u64::from(self.c.get(i).copied().unwrap_or(false)),
            SP => u64::from(self.sp.get(i).copied().unwrap_or(false)),
            S => u64::from(self.s.get(i).copied().unwrap_or(false)),
            T => u64::from(self.t.get(i).copied().unwrap_or(false)),
            CT => u64::from(self.ct.get(i).copied().unwrap_or(false)),
            _ => 0,
        }
    }
    fn write(&mut self, loc: Loc, value: u64) -> Result<(), WriteError> {
        let info = crate::machine::check_write(self, loc, value)?;
        self.forces.check_write(loc, || info.name)?;
        let i = loc.index as usize;
        let on = value != 0;
        match loc.space {
            V => self.set_word(i as u32, value as u16),
            VM => match mapped_address(i as u32) {
                Some(a) => self.set_word(a, value as u16),
                None => return Err(WriteError::NoSuchLocation),
            },
            X => self.x[i] = on,
            Y => self.y[i] = on,
            C => self.c[i] = on,
            S => self.s[i] = on,
            _ => return Err(WriteError::NoSuchLocation),
        }
        // A word edit over forced bits (VY) leaves them as forced.
        crate::machine::plc::hold_forces(self);
        Ok(())
    }
    fn find(&self, name: &str) -> Option<Loc> {
        parse_name(name).or_else(|| {
            // An ELEMENT_DOC nickname, as DirectSOFT lets one be used for its element.
            let doc = (self.program.docs.iter())
                .find(|d| !d.nickname.is_empty() && d.nickname.eq_ignore_ascii_case(name.trim()))?;
            parse_name(&doc.element)
        })
    }
    fn used(&self) -> Vec<Loc> {
        let mut out: Vec<Loc> = (0..=LEVELS as u32).map(|i| Loc::new(ACC, i)).collect();
        out.extend(self.program.used_v.iter().map(|&n| v_loc(n)));
        out.extend(self.program.used_bits.iter().map(|&b| bit_loc(b)));
        out.extend((0..SPECIAL.len() as u32).map(|i| Loc::new(SP, i)));
        out
    }
    fn line_notes(&self) -> Vec<(usize, String)> {
        use super::program::Op;
        let line = |i: u32| ScannedPlc::instruction_line(self, i as usize);
        let mut notes = Vec::new();
        // The loop running now, and those the calls in progress were made from.
        let loops = self
            .calls
            .iter()
            .filter_map(|f| f.loop_state)
            .chain(self.loop_state);
        for l in loops {
            let Some(Op::For(count, _)) = self.program.instrs.get(l.for_at as usize).map(|i| i.op)
            else {
                continue;
            };
            let total = match count {
                super::program::W::K(k) => bcd_value(u32::from(k), 4),
                super::program::W::V(a) => bcd_value(u32::from(self.word(a)), 4),
            };
            if let Some(total) = total {
                let turn = total.saturating_sub(u64::from(l.left)) + 1;
                notes.push((line(l.for_at), format!("turn {turn} of {total}")));
            }
        }
        // The subroutine now running, and where each call came from.
        for (depth, frame) in self.calls.iter().enumerate() {
            let sbr = match self
                .program
                .instrs
                .get(frame.ret as usize - 1)
                .map(|i| i.op)
            {
                Some(Op::Gts(to)) => to,
                _ => continue,
            };
            notes.push((
                line(sbr),
                format!(
                    "called from line {} (depth {})",
                    line(frame.ret - 1),
                    depth + 1
                ),
            ));
        }
        for &i in &self.fired_this_scan {
            notes.push((line(i), "fired".into()));
        }
        notes
    }
    fn call_stack_lines(&self) -> Vec<usize> {
        self.calls
            .iter()
            .map(|f| ScannedPlc::instruction_line(self, f.ret as usize))
            .collect()
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
    /// ELEMENT_DOC nicknames (DirectSOFT's names for elements) name their locations in
    /// views, watches and conditions.
    fn program_names(&self) -> Vec<(String, Loc)> {
        (self.program.docs.iter())
            .filter(|d| !d.nickname.is_empty())
            .filter_map(|d| Some((d.nickname.clone(), parse_name(&d.element)?)))
            .collect()
    }
    fn location_doc(&self, loc: Loc) -> Option<String> {
        let name = self.info(loc)?.name;
        let doc = (self.program.docs.iter())
            .find(|d| parse_name(&d.element) == Some(loc) || d.element == name)?;
        let text = match (doc.nickname.as_str(), doc.description.as_str()) {
            ("", "") => return None,
            (nick, "") => nick.to_string(),
            ("", description) => description.to_string(),
            (nick, description) => format!("{nick} — {description}"),
        };
        Some(text)
    }
    fn warnings(&self) -> Vec<crate::machine::Diagnostic> {
        crate::machine::plc::ladder::duplicate_coils(&self.program.ladder)
    }
    fn explain_last(&self) -> Option<String> {
        super::explain::explain(self)
    }
    fn last_line(&self) -> Option<usize> {
        self.last
            .and_then(|i| self.program.instrs.get(i as usize))
            .map(|i| i.line)
    }
    /// SP53 (divide by zero) or SP75 (a non-BCD digit): the DL205's own error flags.
    fn error_lamp(&self) -> bool {
        self.sp[super::program::sp::SP53] || self.sp[super::program::sp::SP75]
    }
    fn report_json(&self, out: &mut JsonMap) {
        let mut registers = JsonMap::new();
        registers.insert("ACC".into(), json!(self.acc));
        for (i, v) in self.stack.iter().enumerate() {
            registers.insert(format!("L{}", i + 1), json!(v));
        }
        for (i, v) in self.v.iter().enumerate().filter(|(_, v)| **v != 0) {
            registers.insert(format!("V{i:o}"), json!(v));
        }
        let flags: JsonMap = (SPECIAL.iter().enumerate())
            .map(|(i, n)| (format!("SP{n:o}"), json!(u8::from(self.sp[i]))))
            .collect();
        let mut bits = JsonMap::new();
        for (kind, values) in [
            (Kind::X, &self.x_image),
            (Kind::Y, &self.y),
            (Kind::C, &self.c),
            (Kind::S, &self.s),
            (Kind::T, &self.t),
            (Kind::Ct, &self.ct),
        ] {
            for (i, _) in values.iter().enumerate().filter(|(_, b)| **b) {
                bits.insert(bit_name(Bit { kind, n: i as u32 }), json!(1));
            }
        }
        out.insert("scan_ms".into(), json!(self.time.scan_ms));
        out.insert("time_ms".into(), json!(self.time.time_ms(self.tick)));
        out.insert("registers".into(), registers.into());
        out.insert("flags".into(), flags.into());
        out.insert("bits".into(), bits.into());
        out.insert("stack_depth".into(), json!(self.depth));
    }
    fn report_text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "ACC: {:08X}  stack ({}): {}",
            self.acc,
            self.depth,
            self.stack
                .iter()
                .map(|v| format!("{v:08X}"))
                .collect::<Vec<_>>()
                .join(" ")
        );
        let v: Vec<String> = self
            .v
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0)
            .map(|(i, v)| format!("V{i:o}={v:04X}"))
            .collect();
        let _ = writeln!(out, "V-memory (non-zero, hex): {}", v.join(" "));
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
