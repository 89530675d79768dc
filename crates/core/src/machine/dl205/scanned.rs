//! Dl205 as a scanned PLC: what it tells the shared scan loop, forcing and the PLC face
//! (`crate::machine::plc::scan`) about its program, its bit stores and its scan.

use super::view::{C, S, SP, X, Y};
use super::*;
use crate::machine::Loc;
use crate::machine::plc::{Forces, ScannedPlc, TimeBase};

impl ScannedPlc for Dl205 {
    fn assemble(source: &str, time: TimeBase) -> Result<Self, Vec<crate::machine::Diagnostic>> {
        Ok(Dl205::with_time(
            std::sync::Arc::new(super::assemble(source)?),
            time,
        ))
    }
    fn instruction_count(&self) -> usize {
        self.program.instrs.len()
    }
    fn instruction_line(&self, index: usize) -> usize {
        self.program.instrs.get(index).map_or(0, |i| i.line)
    }
    fn scan_writes(&self) -> crate::machine::WriteSet {
        self.program.scan_writes
    }
    fn diagram(&self) -> std::sync::Arc<crate::machine::plc::ladder::Ladder> {
        self.program.diagram.of(&self.program.ladder)
    }
    fn wired(&self) -> std::sync::Arc<crate::machine::plc::ladder::Ladder> {
        self.program.ladder.clone()
    }
    fn conducts(&self, index: usize) -> bool {
        Dl205::conducts(self, index)
    }
    fn rung_power(&self) -> Vec<(usize, crate::machine::LinePower)> {
        use crate::machine::LinePower;
        // What this scan has passed: in the main program execution only moves forward (FOR
        // loops go back inside what already ran), so an instruction before the frontier that
        // did not run was jumped over. Between scans the whole last scan is known.
        let scan_over = self.step == 0 && self.tick > 0;
        let frontier = self.calls.first().map_or(self.pc, |f| f.ret - 1) as usize;
        let end = self
            .program
            .instrs
            .iter()
            .position(|i| i.op == super::program::Op::End)
            .unwrap_or(usize::MAX);
        self.program
            .instrs
            .iter()
            .zip(&self.power)
            .enumerate()
            .filter_map(|(i, (ins, power))| {
                let state = match *power {
                    None if scan_over || (i < frontier && i <= end && self.step > 0) => {
                        LinePower::NotRun
                    }
                    None => return None,
                    Some(true) => LinePower::On,
                    Some(false) if ins.op.is_output() && !ins.op.always_runs() => {
                        LinePower::Skipped
                    }
                    Some(false) => LinePower::Off,
                };
                Some((ins.line, state))
            })
            .collect()
    }

    fn box_rows(&self) -> Vec<crate::machine::plc::BoxRow> {
        self.boxes()
    }
    fn relay_driven_by_scan(&self, loc: Loc) -> bool {
        loc.space == SP && (loc.index as usize) <= super::program::sp::SP7
    }
    fn force_table(&self) -> &Forces {
        &self.forces
    }
    fn force_table_mut(&mut self) -> &mut Forces {
        &mut self.forces
    }
    /// X, Y, C and S bits can be forced (DL250/260 override); timer, counter and special
    /// relays are the CPU's own.
    fn forceable(space: u8) -> bool {
        matches!(space, X | Y | C | S)
    }
    fn forced_store(&mut self, space: u8) -> Option<&mut [bool]> {
        Some(match space {
            X => &mut self.x_image,
            Y => &mut self.y,
            C => &mut self.c,
            S => &mut self.s,
            _ => return None,
        })
    }
    fn begin_scan(&mut self) {
        self.scan_start();
    }
    fn execute(&mut self) {
        Dl205::execute(self);
    }
    fn count_empty_scan(&mut self) {
        self.tick += 1;
    }
    fn scan_fast(&mut self) -> bool {
        Dl205::scan_fast(self)
    }
    fn state_bytes(&self) -> usize {
        use std::mem::size_of_val as bytes;
        bytes(self)
            + bytes(&self.v[..])
            + bytes(&self.x[..])
            + bytes(&self.x_image[..])
            + bytes(&self.y[..])
            + bytes(&self.c[..])
            + bytes(&self.s[..])
            + bytes(&self.t[..])
            + bytes(&self.ct[..])
            + bytes(&self.t_ms[..])
            + bytes(&self.t_counted[..])
            + bytes(&self.ct_in[..])
            + bytes(&self.edges.0[..])
            + bytes(&self.fired_this_scan[..])
            + bytes(&self.orout_marks[..])
            + bytes(&self.calls[..])
            + bytes(&self.stage_marks[..])
            + bytes(&self.stage_changes[..])
            + bytes(&self.bstack[..])
            + bytes(&self.power[..])
            + bytes(&self.forces.0[..])
    }
}
