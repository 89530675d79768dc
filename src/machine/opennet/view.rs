//! OpenNet's face for the debugger and the runner (spec §2, §9).

use std::any::Any;
use std::fmt::Write;

use super::program::{Area, SPECIAL, point_name};
use super::{M8004, OpenNet};
use crate::machine::{
    Format, Loc, LocInfo, Machine, MachineView, Pos, RunState, SpaceInfo, SpaceKind,
    StopReason, WriteError,
};

pub const D: u8 = 0;
pub const I: u8 = 1;
pub const Q: u8 = 2;
pub const M: u8 = 3;
pub const SPECIAL_SPACE: u8 = 4;

const SPECIAL_DESCRIPTIONS: [&str; 5] = [
    "carry (ADD) or borrow (SUB)",
    "user program execution error (latched)",
    "initialize pulse: on in scan 0",
    "1-s clock",
    "100-ms clock",
];

fn area_of(space: u8) -> Option<Area> {
    match space {
        I => Some(Area::I),
        Q => Some(Area::Q),
        M => Some(Area::M),
        _ => None,
    }
}

pub fn area_space(area: Area) -> u8 {
    match area {
        Area::I => I,
        Area::Q => Q,
        Area::M => M,
    }
}

/// `D12`, `I17`, `M8003` → its location.
pub fn parse_name(name: &str) -> Option<Loc> {
    let name = name.trim();
    let mut chars = name.chars();
    let letter = chars.next()?.to_ascii_uppercase();
    let digits = chars.as_str();
    if digits.is_empty() || digits.len() > 6 || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let n: u32 = digits.parse().ok()?;
    match letter {
        'D' if n < super::REGISTERS as u32 => Some(Loc::new(D, n)),
        'M' if n >= 8000 => SPECIAL
            .iter()
            .position(|&s| u32::from(s) == n)
            .map(|i| Loc::new(SPECIAL_SPACE, i as u32)),
        'I' | 'Q' | 'M' => {
            let area = match letter {
                'I' => Area::I,
                'Q' => Area::Q,
                _ => Area::M,
            };
            if n % 10 >= 8 {
                return None;
            }
            let index = n / 10 * 8 + n % 10;
            (index < area.points()).then(|| Loc::new(area_space(area), index))
        }
        _ => None,
    }
}

impl OpenNet {
    /// Each location the last executed instruction wrote (one may come twice).
    #[inline]
    fn each_written<F: FnMut(Loc)>(&self, mut f: F) {
        use super::program::{Op, Word};
        let Some(instr) = self.last.and_then(|i| self.program.instrs.get(i as usize)) else {
            return;
        };
        let words = |w: &Word, block: u32, offset: u32, f: &mut dyn FnMut(Loc)| match *w {
            Word::Reg { n, .. } => {
                (n + offset..n + offset + block).for_each(|r| f(Loc::new(D, r)));
            }
            Word::Bits { area, index, .. } => {
                let start = index + offset * 16;
                (start..start + block * 16).for_each(|b| f(Loc::new(area_space(area), b)));
            }
            Word::Const(_) => {}
        };
        match instr.op {
            Op::Out(b, _) | Op::Set(b) | Op::Rst(b) => match b {
                super::program::Bit::Point(area, i) => f(Loc::new(area_space(area), i)),
                super::program::Bit::Special(s) => f(Loc::new(SPECIAL_SPACE, u32::from(s))),
            },
            Op::Mov { ty, dst, .. } if self.last_acted => {
                for c in &self.last_cycles {
                    words(&dst, ty.words(), c.dst_at, &mut f);
                }
            }
            Op::Arith { op, ty, dst, .. } if self.last_acted => {
                let block = match op {
                    super::program::Arith::Add | super::program::Arith::Sub => ty.words(),
                    super::program::Arith::Mul => 2,
                    super::program::Arith::Div => 2 * ty.words(),
                };
                for c in self.last_cycles.iter().filter(|c| c.error.is_none()) {
                    words(&dst, block, c.dst_at, &mut f);
                }
                f(Loc::new(SPECIAL_SPACE, 0));
                if self.last_cycles.iter().any(|c| c.error.is_some()) {
                    f(Loc::new(SPECIAL_SPACE, M8004 as u32));
                }
            }
            Op::Step { ty, reg, .. } if self.last_acted => {
                (reg..reg + ty.words()).for_each(|r| f(Loc::new(D, r)));
            }
            _ => {}
        }
    }
}

impl MachineView for OpenNet {
    fn dialect(&self) -> &'static str {
        "opennet"
    }
    fn tick_micros(&self) -> u32 {
        super::SCAN_MICROS
    }
    fn spaces(&self) -> Vec<SpaceInfo> {
        vec![
            SpaceInfo {
                name: "D",
                title: "Data registers",
                kind: SpaceKind::Registers,
                len: super::REGISTERS as u32,
            },
            SpaceInfo {
                name: "I",
                title: "Inputs",
                kind: SpaceKind::Inputs,
                len: Area::I.points(),
            },
            SpaceInfo {
                name: "Q",
                title: "Outputs",
                kind: SpaceKind::Bits,
                len: Area::Q.points(),
            },
            SpaceInfo {
                name: "M",
                title: "Internal relays",
                kind: SpaceKind::Bits,
                len: Area::M.points(),
            },
            SpaceInfo {
                name: "special",
                title: "Special relays",
                kind: SpaceKind::Flags,
                len: SPECIAL.len() as u32,
            },
        ]
    }
    fn info(&self, loc: Loc) -> Option<LocInfo> {
        let i = loc.index;
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
                    format: Some(if signed { Format::Signed } else { Format::Unsigned }),
                    ..LocInfo::word(format!("D{i}"), 16, false)
                })
            }
            SPECIAL_SPACE => SPECIAL.get(i as usize).map(|&n| LocInfo {
                name: format!("M{n}"),
                alias: None,
                description: SPECIAL_DESCRIPTIONS[i as usize],
                width: 1,
                signed: false,
                format: None,
                bits: &[],
                editable: i < 2,
            }),
            s => {
                let area = area_of(s)?;
                (i < area.points()).then(|| LocInfo {
                    name: point_name(area, i),
                    alias: None,
                    description: match area {
                        Area::I => "input",
                        Area::Q => "output",
                        Area::M => "internal relay",
                    },
                    width: 1,
                    signed: false,
                    format: None,
                    bits: &[],
                    editable: true,
                })
            }
        }
    }
    fn read(&self, loc: Loc) -> u64 {
        let i = loc.index as usize;
        match loc.space {
            D => self.d.get(i).map_or(0, |&v| u64::from(v)),
            I => u64::from(self.inputs.get(i).copied().unwrap_or(false)),
            Q => u64::from(self.q.get(i).copied().unwrap_or(false)),
            M => u64::from(self.m.get(i).copied().unwrap_or(false)),
            SPECIAL_SPACE => u64::from(self.special.get(i).copied().unwrap_or(false)),
            _ => 0,
        }
    }
    fn write(&mut self, loc: Loc, value: u64) -> Result<(), WriteError> {
        crate::machine::check_write(self, loc, value)?;
        let i = loc.index as usize;
        let on = value != 0;
        match loc.space {
            D => self.d[i] = value as u16,
            I => self.inputs[i] = on,
            Q => self.q[i] = on,
            M => self.m[i] = on,
            SPECIAL_SPACE => self.special[i] = on,
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
        out
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
    fn report_json(&self) -> String {
        let regs: Vec<String> = self
            .d
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0)
            .map(|(i, v)| format!("\"D{i}\":{v}"))
            .collect();
        // The clocks as the last scan saw them; nothing before a scan has run.
        let flags: Vec<String> = SPECIAL
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let on = self.special[i] && (i < 2 || self.tick > 0);
                format!("\"M{n}\":{}", u8::from(on))
            })
            .collect();
        let mut bits = Vec::new();
        for (area, values) in [(Area::I, &self.input_image), (Area::Q, &self.q), (Area::M, &self.m)] {
            for (i, _) in values.iter().enumerate().filter(|(_, b)| **b) {
                bits.push(format!("\"{}\":1", point_name(area, i as u32)));
            }
        }
        let last = match self.last_error {
            None => "null".to_string(),
            Some(e) => format!(
                "{{\"kind\":\"{}\",\"line\":{},\"tick\":{}}}",
                e.kind, e.line, e.tick
            ),
        };
        format!(
            "\"registers\":{{{}}},\"flags\":{{{}}},\"bits\":{{{}}},\"error_count\":{},\"last_error\":{last}",
            regs.join(","),
            flags.join(","),
            bits.join(","),
            self.error_count
        )
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
            let _ = writeln!(out, "last error: {} on line {} in scan {}", e.kind, e.line, e.tick);
        }
        out
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

impl Machine for OpenNet {
    fn run_observed<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        limit: Pos,
        stop: F,
        observe: O,
    ) -> StopReason {
        crate::machine::run_scans(self, limit, stop, observe)
    }

    fn run_bare(&mut self, limit: Pos) -> StopReason {
        crate::machine::run_scans_bare(self, limit)
    }

    /// Returns None while a line breakpoint is set: every scan would halt at it.
    fn run_quiet(
        &mut self,
        limit: Pos,
        quiet: &mut crate::machine::Quiet,
        _stop: &mut dyn FnMut(&Self) -> bool,
    ) -> Option<StopReason> {
        crate::machine::run_scans_quiet(self, limit, quiet)
    }
}
