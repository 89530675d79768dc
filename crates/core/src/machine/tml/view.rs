//! TML's face for the debugger and the runner: storage spaces, readings, the JSON report of
//! spec §9.

use std::any::Any;

use serde_json::{Value, json};

use crate::machine::JsonMap;
use std::fmt::Write;

use super::program::{Data, Op, Operand, Ty};
use super::{Event, INPUTS, PREDEFINED, Tml, d, der, mer, srl};
use crate::machine::{
    BitInfo, FaultInfo, Format, Loc, LocInfo, Machine, MachineView, Pos, RunState, SpaceInfo,
    SpaceKind, StopReason, WaitReason, WriteError, find_by_name,
};

pub const DATA: u8 = 0;
pub const VARS: u8 = 1;
pub const STATUS: u8 = 2;
pub const INPUT: u8 = 3;

/// The data space: predefined data except the status words, then PREG.
const DATA_ORDER: [u8; 13] = [
    d::CPOS,
    d::CSPD,
    d::CACC,
    d::TPOS,
    d::TSPD,
    d::APOS,
    d::ASPD,
    d::POSERR,
    d::ATIME,
    d::UPGRADE,
    d::FLAGUV,
    d::PROD,
    d::PRODH,
];
/// PREG's index in the data space.
pub const PREG_INDEX: u32 = DATA_ORDER.len() as u32;
/// Table B data after PREG (MCR, a status word, is with the status words), so the indexes of
/// older sessions' edits stay where they were.
const DATA_B_ORDER: [u8; 13] = [
    d::TACC,
    d::RTIME,
    d::POSOKLIM,
    d::TONPOSOK,
    d::VAR_I1,
    d::VAR_I2,
    d::VAR_I3,
    d::VAR_LF,
    d::DO_TML_INITIALIZATIONS,
    d::EXECUTE_MAIN,
    d::EXECUTE_AUTOTUNING,
    d::HOMINGTABLE_POINTER,
    d::FUNCTIONTABLE_POINTER,
];
const STATUS_ORDER: [u8; 5] = [d::SRL, d::SRH, d::MER, d::DER, d::MCR];

/// The predefined datum at index `i` of the data space (not PREG).
fn data_pre(i: usize) -> Option<u8> {
    if i < DATA_ORDER.len() {
        Some(DATA_ORDER[i])
    } else {
        DATA_B_ORDER
            .get(i.checked_sub(DATA_ORDER.len() + 1)?)
            .copied()
    }
}

const UPGRADE_BITS: &[BitInfo] = &[BitInfo {
    bit: 11,
    name: "INPOS_RULE",
    description: "motion complete waits until |TPOS − APOS| ≤ POSOKLIM for TONPOSOK ticks",
}];
const MCR_BITS: &[BitInfo] = &[
    BitInfo {
        bit: 0,
        name: "PP",
        description: "MODE PP was given (with bits 8, 9, 10, 15: 0x8701)",
    },
    BitInfo {
        bit: 13,
        name: "CPA",
        description: "CPOS is absolute",
    },
    BitInfo {
        bit: 14,
        name: "TUM1",
        description: "the next UPD starts from the reference",
    },
];

const SRL_BITS: &[BitInfo] = &[
    BitInfo {
        bit: 10,
        name: "MC",
        description: "motion complete",
    },
    BitInfo {
        bit: 14,
        name: "EVENT",
        description: "the programmed event occurred",
    },
    BitInfo {
        bit: 15,
        name: "AXISON",
        description: "the power stage is on",
    },
];
const MER_BITS: &[BitInfo] = &[BitInfo {
    bit: 14,
    name: "CMD_ERROR",
    description: "command error (stack fault, UPD ignored)",
}];
const DER_BITS: &[BitInfo] = &[
    BitInfo {
        bit: 0,
        name: "STACK_OVF",
        description: "TML stack overflow",
    },
    BitInfo {
        bit: 1,
        name: "STACK_UNF",
        description: "TML stack underflow",
    },
    BitInfo {
        bit: 4,
        name: "UPD_IGNORED",
        description: "UPD ignored: no MODE PP, axis off, CSPD or CACC not positive",
    },
];

pub fn data_loc(pre: u8) -> Loc {
    if let Some(i) = DATA_ORDER.iter().position(|&p| p == pre) {
        Loc::new(DATA, i as u32)
    } else if let Some(i) = DATA_B_ORDER.iter().position(|&p| p == pre) {
        Loc::new(DATA, PREG_INDEX + 1 + i as u32)
    } else {
        let i = STATUS_ORDER.iter().position(|&p| p == pre).unwrap_or(0);
        Loc::new(STATUS, i as u32)
    }
}

pub fn operand_loc(op: &Operand) -> Loc {
    match op.data {
        Data::Pre(p) => data_loc(p),
        Data::Var(v) => Loc::new(VARS, u32::from(v)),
    }
}

fn pre_info(pre: u8) -> LocInfo {
    let p = PREDEFINED[pre as usize];
    LocInfo {
        name: p.name.to_string(),
        alias: p.alias,
        description: p.description,
        width: p.ty.bits(),
        signed: p.ty != Ty::Uint,
        format: match p.ty {
            Ty::Fixed => Some(Format::Q16),
            Ty::Uint => Some(Format::Hex),
            _ => None,
        },
        bits: match pre {
            d::SRL => SRL_BITS,
            d::MER => MER_BITS,
            d::DER => DER_BITS,
            d::MCR => MCR_BITS,
            d::UPGRADE => UPGRADE_BITS,
            _ => &[],
        },
        editable: p.writable,
    }
}

impl Tml {
    /// The runner's and the views' name for a value: the declared spelling of a variable.
    pub fn var_name(&self, v: usize) -> &str {
        &self.program.vars[v].name
    }

    /// The call stack's lines, and for a program of several files each line's file.
    fn stack_json(&self, out: &mut JsonMap) {
        let lines = self.call_stack_lines();
        let split = crate::machine::project::Project::split;
        if self.program.files.is_empty() {
            out.insert("stack".into(), json!(lines));
            return;
        }
        let local: Vec<usize> = lines.iter().map(|&l| split(l).1).collect();
        let names: Vec<&str> = (lines.iter())
            .map(|&l| {
                self.program
                    .files
                    .get(split(l).0)
                    .map_or("", String::as_str)
            })
            .collect();
        out.insert("stack".into(), json!(local));
        out.insert("stack_files".into(), json!(names));
    }

    fn event_json(&self) -> Value {
        match self.event {
            None => Value::Null,
            Some(Event::MotionComplete) => json!({"kind": "MC"}),
            Some(Event::Time { after, .. }) => json!({"kind": "RT", "value": after}),
            Some(Event::Input { input, level }) => {
                json!({"kind": "IN", "input": input, "level": u8::from(level)})
            }
        }
    }

    /// Value of a predefined datum as the runner prints it.
    fn report_value(&self, pre: u8) -> i64 {
        let p = PREDEFINED[pre as usize];
        let raw = self.raw(Data::Pre(pre));
        match p.ty {
            Ty::Uint => i64::from(raw & 0xFFFF),
            Ty::Int => i64::from(raw as u16 as i16),
            Ty::Long | Ty::Fixed => i64::from(raw as i32),
        }
    }

    fn var_value(&self, v: usize) -> i64 {
        let raw = self.vars[v];
        match self.program.vars[v].ty {
            Ty::Int | Ty::Uint => i64::from(raw as u16 as i16),
            Ty::Long | Ty::Fixed => i64::from(raw as i32),
        }
    }
}

impl Tml {
    /// Each location the last executed instruction wrote (one may come twice).
    #[inline]
    fn each_written<F: FnMut(Loc)>(&self, mut f: F) {
        self.each_statement_written(&mut f);
        self.each_motion_written(f);
    }

    /// What the last statement itself wrote, without the motion profile's tick.
    fn each_statement_written<F: FnMut(Loc)>(&self, mut f: F) {
        if let Some(stmt) = self.last.and_then(|i| self.program.stmts.get(i as usize)) {
            match stmt.op {
                Op::Assign(dst, _)
                | Op::Negate(dst, _)
                | Op::AssignShift { dst, .. }
                | Op::Add { dst, .. }
                | Op::Divide(dst, _)
                | Op::Shift { dst, .. }
                | Op::Srb { dst, .. } => f(operand_loc(&dst)),
                Op::Multiply { .. } | Op::ShiftProduct { .. } => {
                    [
                        Loc::new(DATA, PREG_INDEX),
                        data_loc(d::PROD),
                        data_loc(d::PRODH),
                    ]
                    .into_iter()
                    .for_each(&mut f);
                }
                Op::Sap(_) => [data_loc(d::APOS), data_loc(d::TPOS)]
                    .into_iter()
                    .for_each(&mut f),
                // An ignored UPD sets its error bits (spec §5.8).
                Op::Upd if self.last_vals[0] != 0 => [data_loc(d::MER), data_loc(d::DER)]
                    .into_iter()
                    .for_each(&mut f),
                _ => {}
            }
        }
    }

    /// The motion data a tick's end writes while the profile moves.
    fn each_motion_written<F: FnMut(Loc)>(&self, f: F) {
        if self.profile.active || self.data[d::ASPD as usize] != 0 {
            [d::TPOS, d::TSPD, d::APOS, d::ASPD, d::POSERR]
                .into_iter()
                .map(data_loc)
                .for_each(f);
        }
    }

    pub(super) fn note_motion(&self, set: &mut crate::machine::WriteSet) {
        self.each_motion_written(|loc| set.insert(loc));
    }
}

impl MachineView for Tml {
    fn dialect(&self) -> &'static str {
        "tml"
    }
    fn tick_micros(&self) -> u32 {
        super::TICK_MICROS
    }
    fn spaces(&self) -> Vec<SpaceInfo> {
        vec![
            SpaceInfo {
                name: "data",
                title: "TML data",
                kind: SpaceKind::Registers,
                len: PREG_INDEX + 1 + DATA_B_ORDER.len() as u32,
            },
            SpaceInfo {
                name: "vars",
                title: "Variables",
                kind: SpaceKind::Registers,
                len: self.vars.len() as u32,
            },
            SpaceInfo {
                name: "status",
                title: "Status",
                kind: SpaceKind::Flags,
                len: STATUS_ORDER.len() as u32,
            },
            SpaceInfo {
                name: "inputs",
                title: "Inputs",
                kind: SpaceKind::Inputs,
                len: INPUTS as u32,
            },
        ]
    }
    fn info(&self, loc: Loc) -> Option<LocInfo> {
        let i = loc.index as usize;
        match loc.space {
            DATA if loc.index == PREG_INDEX => Some(LocInfo {
                name: "PREG".into(),
                alias: None,
                description: "the 48-bit product register (PROD = bits 31..0, PRODH = 47..16)",
                width: 48,
                signed: true,
                format: None,
                bits: &[],
                editable: true,
            }),
            DATA => data_pre(i).map(pre_info),
            VARS => self.program.vars.get(i).map(|v| LocInfo {
                name: v.name.clone(),
                alias: None,
                description: match v.ty {
                    Ty::Fixed => "user variable, fixed 16.16",
                    Ty::Long => "user variable, long",
                    _ => "user variable, int",
                },
                width: v.ty.bits(),
                signed: true,
                format: (v.ty == Ty::Fixed).then_some(Format::Q16),
                bits: &[],
                editable: true,
            }),
            STATUS => STATUS_ORDER.get(i).map(|&p| pre_info(p)),
            INPUT if i < INPUTS => Some(LocInfo {
                name: format!("IN#{i}"),
                alias: None,
                description: "digital input",
                width: 1,
                signed: false,
                format: None,
                bits: &[],
                editable: true,
            }),
            _ => None,
        }
    }
    fn read(&self, loc: Loc) -> u64 {
        let i = loc.index as usize;
        match loc.space {
            DATA if loc.index == PREG_INDEX => self.preg,
            DATA => data_pre(i).map_or(0, |p| u64::from(self.raw(Data::Pre(p)))),
            VARS => self.vars.get(i).map_or(0, |&v| u64::from(v)),
            STATUS => STATUS_ORDER
                .get(i)
                .map_or(0, |&p| u64::from(self.raw(Data::Pre(p)) & 0xFFFF)),
            INPUT if i < INPUTS => u64::from(self.input(i)),
            _ => 0,
        }
    }
    fn write(&mut self, loc: Loc, value: u64) -> Result<(), WriteError> {
        crate::machine::check_write(self, loc, value)?;
        let i = loc.index as usize;
        match loc.space {
            DATA if loc.index == PREG_INDEX => self.preg = value,
            DATA => match data_pre(i) {
                Some(p) => self.data[p as usize] = value as u32,
                None => return Err(WriteError::NoSuchLocation),
            },
            VARS => self.vars[i] = value as u32,
            INPUT => {
                if value != 0 {
                    self.inputs |= 1 << i;
                } else {
                    self.inputs &= !(1 << i);
                }
            }
            _ => return Err(WriteError::NoSuchLocation),
        }
        Ok(())
    }
    fn find(&self, name: &str) -> Option<Loc> {
        let name = name.trim();
        // A variable first: `in5` may be one (only IN#5 is the input then).
        if let Some(v) = self
            .program
            .vars
            .iter()
            .position(|v| v.name.eq_ignore_ascii_case(name))
        {
            return Some(Loc::new(VARS, v as u32));
        }
        let upper = name.to_ascii_uppercase();
        if let Some(n) = upper
            .strip_prefix("IN#")
            .or_else(|| upper.strip_prefix("IN"))
            .and_then(|n| n.parse::<usize>().ok())
        {
            return (n < INPUTS).then(|| Loc::new(INPUT, n as u32));
        }
        find_by_name(self, super::canonical_name(name))
    }
    fn used(&self) -> Vec<Loc> {
        let p = &self.program;
        let mut out: Vec<Loc> = p.used.iter().map(|&u| data_loc(u)).collect();
        if p.uses_preg {
            out.push(Loc::new(DATA, PREG_INDEX));
        }
        out.extend((0..self.vars.len() as u32).map(|v| Loc::new(VARS, v)));
        out.extend((0..STATUS_ORDER.len() as u32).map(|s| Loc::new(STATUS, s)));
        out.extend(p.used_inputs.iter().map(|&n| Loc::new(INPUT, u32::from(n))));
        out
    }
    fn program_names(&self) -> Vec<(String, Loc)> {
        self.program
            .vars
            .iter()
            .enumerate()
            .map(|(i, v)| (v.name.clone(), Loc::new(VARS, i as u32)))
            .collect()
    }
    fn pc_line(&self) -> Option<usize> {
        self.program.stmts.get(self.pc as usize).map(|s| s.line)
    }
    fn call_depth(&self) -> usize {
        self.stack.len()
    }
    fn call_stack_lines(&self) -> Vec<usize> {
        self.stack
            .iter()
            .filter_map(|&back| self.program.stmts.get(back as usize - 1).map(|s| s.line))
            .collect()
    }
    fn run_state(&self) -> RunState {
        if self.fault.is_some() {
            RunState::Faulted
        } else if self.ended {
            RunState::Ended
        } else if self.wait_since.is_some() {
            RunState::Waiting(WaitReason::Condition)
        } else {
            RunState::Running
        }
    }
    fn fault(&self) -> Option<FaultInfo> {
        self.fault.map(|(f, line)| FaultInfo {
            kind: f.kind(),
            message: f.message(),
            line,
        })
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
    fn instruction_written(&self) -> Vec<Loc> {
        let mut out = Vec::new();
        self.each_statement_written(|loc| {
            if !out.contains(&loc) {
                out.push(loc);
            }
        });
        out
    }
    fn note_writes(&self, set: &mut crate::machine::WriteSet) {
        self.each_written(|loc| set.insert(loc));
    }
    fn explain_last(&self) -> Option<String> {
        super::explain::explain(self)
    }
    fn last_statement_text(&self) -> Option<&str> {
        let stmt = self.last.and_then(|i| self.program.stmts.get(i as usize))?;
        Some(&stmt.text)
    }
    fn last_line(&self) -> Option<usize> {
        self.last
            .and_then(|i| self.program.stmts.get(i as usize))
            .map(|s| s.line)
    }
    /// MER: any motion error bit (bit 14, command error, is the one programs set off).
    fn error_lamp(&self) -> bool {
        self.data[d::MER as usize] != 0
    }
    fn report_json(&self, out: &mut JsonMap) {
        // Table A always; table B only what the program names (spec §9).
        let mut registers: JsonMap = (PREDEFINED.iter().enumerate())
            .filter(|(i, p)| !p.table_b || self.program.used.contains(&(*i as u8)))
            .map(|(i, p)| (p.name.to_string(), json!(self.report_value(i as u8))))
            .collect();
        registers.insert("PREG".into(), json!(self.preg_signed()));
        for (i, v) in self.program.vars.iter().enumerate() {
            registers.insert(v.name.clone(), json!(self.var_value(i)));
        }
        let srl = self.data[d::SRL as usize];
        let mut flags = JsonMap::new();
        flags.insert(
            "MC".into(),
            json!(u8::from(srl & srl::MOTION_COMPLETE != 0)),
        );
        flags.insert("EVENT".into(), json!(u8::from(srl & srl::EVENT != 0)));
        flags.insert("AXISON".into(), json!(u8::from(srl & srl::AXIS_ON != 0)));
        for n in 0..INPUTS {
            flags.insert(format!("IN#{n}"), json!(u8::from(self.input(n))));
        }
        out.insert("registers".into(), registers.into());
        out.insert("flags".into(), flags.into());
        self.stack_json(out);
        out.insert("event".into(), self.event_json());
        let p = &self.profile;
        out.insert(
            "motion".into(),
            json!({
                "mode": self.mode_pp.then_some("PP"),
                "relative": u8::from(self.relative),
                "tum": u8::from(self.tum1),
                "active": u8::from(p.active),
                "stopping": u8::from(p.stopping),
                "end": p.end,
            }),
        );
    }
    fn report_text(&self) -> String {
        let mut out = String::new();
        let srl = self.data[d::SRL as usize];
        let _ = writeln!(
            out,
            "SRL: 0x{srl:04X}  MER: 0x{:04X}  DER: 0x{:04X}",
            self.data[d::MER as usize],
            self.data[d::DER as usize]
        );
        let pre: Vec<String> = PREDEFINED
            .iter()
            .enumerate()
            .filter(|(i, _)| self.report_value(*i as u8) != 0)
            .map(|(i, p)| format!("{}={}", p.name, self.report_value(i as u8)))
            .collect();
        let _ = writeln!(out, "data (non-zero): {}", pre.join(" "));
        let _ = writeln!(out, "PREG: {} (0x{:012X})", self.preg_signed(), self.preg);
        for (i, v) in self.program.vars.iter().enumerate() {
            let value = self.var_value(i);
            if v.ty == Ty::Fixed {
                let _ = writeln!(
                    out,
                    "{} (fixed) = {} ({})",
                    v.name,
                    value,
                    crate::machine::value::q16(value)
                );
            } else {
                let _ = writeln!(out, "{} ({}) = {value}", v.name, v.ty.name());
            }
        }
        out
    }
    fn line_addresses(&self) -> Vec<(usize, u32)> {
        let mut out: Vec<(usize, u32)> = Vec::new();
        for (stmt, &address) in self.program.stmts.iter().zip(&self.program.addresses) {
            if out.last().is_none_or(|&(l, _)| l != stmt.line) {
                out.push((stmt.line, address));
            }
        }
        // A file included twice has its lines twice: the first address of each stands.
        out.sort_by_key(|&(l, _)| l);
        out.dedup_by_key(|&mut (l, _)| l);
        out
    }
    fn line_notes(&self) -> Vec<(usize, String)> {
        // A jump through data: the address it holds now and where that is.
        self.program
            .stmts
            .iter()
            .filter_map(|s| match s.op {
                Op::JumpVia { via, .. } => {
                    let address = self.read_operand(&via) as u16;
                    let whither = match self.program.statement_at(u32::from(address)) {
                        Some(i) if i < self.program.stmts.len() => {
                            format!("'{}'", self.program.stmts[i].text)
                        }
                        Some(_) => "the end".to_string(),
                        None => "no statement starts there".to_string(),
                    };
                    Some((s.line, format!("→ 0x{address:04X} = {whither}")))
                }
                _ => None,
            })
            .collect()
    }
    fn as_motion(&self) -> Option<&dyn crate::machine::MotionView> {
        Some(self)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

impl crate::machine::MotionView for Tml {
    fn plot_band(&self) -> Option<(&'static str, i64, String)> {
        self.in_position_rule().then(|| {
            let band = i64::from(self.data[d::POSOKLIM as usize] as u16);
            (
                "TPOS",
                band,
                // Short: it is a legend entry; the count is in the Drive data panel.
                format!("TPOS ± POSOKLIM ({band})"),
            )
        })
    }
    fn plot_markers(&self) -> Vec<(String, i64)> {
        // The end of the last accepted UPD (there was one when a speed was latched).
        if self.profile.speed > 0 {
            vec![(
                format!("end {}", self.profile.end),
                i64::from(self.profile.end),
            )]
        } else {
            Vec::new()
        }
    }
}

impl Machine for Tml {
    fn snapshot_bytes(&self) -> usize {
        use std::mem::size_of_val as bytes;
        bytes(self) + bytes(&self.vars[..]) + bytes(&self.stack[..])
    }

    fn run_observed<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        limit: Pos,
        stop: F,
        observe: O,
    ) -> StopReason {
        self.run_loop(limit, stop, observe)
    }

    fn run_bare(&mut self, limit: Pos) -> StopReason {
        self.run_bare_to(limit)
    }

    /// Returns before a breakpoint line for the timeline to ask.
    fn run_quiet(
        &mut self,
        limit: Pos,
        quiet: &mut crate::machine::Quiet,
        _stop: &mut dyn FnMut(&Self) -> bool,
    ) -> Option<StopReason> {
        // The fast loop compares at tick ends: too late for a data breakpoint.
        if !quiet.guarded.is_empty() {
            return None;
        }
        Some(self.run_quiet_to(limit, quiet))
    }
}

/// Error bits a view highlights.
pub fn error_bits(m: &Tml) -> (u32, u32) {
    (
        m.data[d::MER as usize] & mer::COMMAND_ERROR,
        m.data[d::DER as usize] & (der::STACK_OVERFLOW | der::STACK_UNDERFLOW | der::UPD_IGNORED),
    )
}
