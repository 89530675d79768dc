//! OpenNet as a scanned PLC: what it tells the shared scan loop, forcing and the PLC face
//! (`crate::machine::plc::scan`) about its program, its bit stores and its scan.

use super::view::{I, M, Q, R};
use super::*;
use crate::machine::LinePower;
use crate::machine::plc::{Forces, ScannedPlc, TimeBase};

impl ScannedPlc for OpenNet {
    fn assemble(source: &str, time: TimeBase) -> Result<Self, Vec<crate::machine::Diagnostic>> {
        Ok(OpenNet::with_time(
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
        OpenNet::conducts(self, index)
    }
    fn rung_power(&self) -> Vec<(usize, LinePower)> {
        self.program
            .instrs
            .iter()
            .zip(&self.marks)
            .filter_map(|(ins, mark)| {
                let state = match mark {
                    Mark::NotReached => return None,
                    // An MCS area that is off: everything in it is dimmed.
                    Mark::MasterOff => LinePower::MasterOff,
                    Mark::Jumped => LinePower::NotRun,
                };
                Some((ins.line, state))
            })
            .collect()
    }

    fn box_rows(&self) -> Vec<crate::machine::plc::BoxRow> {
        self.timer_rows()
    }
    fn force_table(&self) -> &Forces {
        &self.forces
    }
    fn force_table_mut(&mut self) -> &mut Forces {
        &mut self.forces
    }
    /// I, Q, M and R bits can be forced (WindLDR set/reset forced).
    fn forceable(space: u8) -> bool {
        matches!(space, I | Q | M | R)
    }
    fn forced_store(&mut self, space: u8) -> Option<&mut [bool]> {
        Some(match space {
            I => &mut self.input_image,
            Q => &mut self.q,
            M => &mut self.m,
            R => &mut self.r,
            _ => return None,
        })
    }
    fn begin_scan(&mut self) {
        self.refresh();
    }
    fn execute(&mut self) {
        OpenNet::execute(self);
    }
    fn count_empty_scan(&mut self) {
        self.tick += 1;
    }
    fn scan_fast(&mut self) -> bool {
        OpenNet::scan_fast(self)
    }
    fn state_bytes(&self) -> usize {
        use std::mem::size_of_val as bytes;
        bytes(self)
            + bytes(&self.d[..])
            + bytes(&self.inputs[..])
            + bytes(&self.input_image[..])
            + bytes(&self.q[..])
            + bytes(&self.m[..])
            + bytes(&self.r[..])
            + bytes(&self.blocks[..])
            + bytes(&self.branches[..])
            + bytes(&self.edges.0[..])
            + bytes(&self.pulses.0[..])
            + bytes(&self.edge_scans[..])
            + bytes(&self.forces.0[..])
            + bytes(&self.timers[..])
            + bytes(&self.counters[..])
            + bytes(&self.marks[..])
            + bytes(&self.last_cycles[..])
    }
}
