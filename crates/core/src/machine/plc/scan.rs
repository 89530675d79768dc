//! The scanned PLC, written once: a dialect implements [`ScannedPlc`] (its program's shape, its
//! bit stores, which spaces can be forced, the start of a scan and one instruction), and gets
//! from here the scan loop in its three speeds, forcing, the PLC face ([`PlcView`]), the
//! debugger's [`Machine`] and the way a program is opened with the `scan_ms` setting. A third
//! scanned PLC writes only its own rules.

use std::sync::Arc;

use super::ladder::Ladder;
use super::{BoxRow, Forces, TimeBase};
use crate::machine::dialect::Settings;
use crate::machine::project::Project;
use crate::machine::{
    Diagnostic, LinePower, Loc, Machine, MachineView, PlcView, Pos, Quiet, StopReason, WriteError,
    WriteSet,
};

/// What a scanned PLC dialect provides.
pub trait ScannedPlc: MachineView + Clone + PartialEq {
    /// Assemble `source` into a machine whose scans take `time`.
    fn assemble(source: &str, time: TimeBase) -> Result<Self, Vec<Diagnostic>>;
    fn instruction_count(&self) -> usize;
    /// The source line of instruction `index`: where line breakpoints halt.
    fn instruction_line(&self, index: usize) -> usize;
    /// Every location a scan may write (a superset of what `note_writes` notes over a scan).
    fn scan_writes(&self) -> WriteSet;
    /// The program as a ladder, laid out on first use.
    fn diagram(&self) -> Arc<Ladder>;
    /// The program's rungs, wired when it was assembled, not laid out.
    fn wired(&self) -> Arc<Ladder>;
    /// Whether the contact-like element of instruction `index` conducts now.
    fn conducts(&self, index: usize) -> bool;
    /// Rung power per source line at this point of the scan.
    fn rung_power(&self) -> Vec<(usize, LinePower)>;
    /// The timers, counters and other boxes of the program, as the panel lists them.
    fn box_rows(&self) -> Vec<BoxRow>;
    /// Status relays the CPU drives at every scan's start (see [`PlcView::driven_by_scan`]).
    fn relay_driven_by_scan(&self, _loc: Loc) -> bool {
        false
    }
    /// The forced bits.
    fn force_table(&self) -> &Forces;
    fn force_table_mut(&mut self) -> &mut Forces;
    /// Whether bits of `space` can be forced (inputs, outputs and internal relays; the CPU's
    /// own timer, counter and special relays cannot).
    fn forceable(space: u8) -> bool;
    /// The store a forced bit of `space` is held in: the input image for inputs (the switch
    /// stays as the user left it, so a release gives the next scan the real switch), the bits
    /// themselves for the rest.
    fn forced_store(&mut self, space: u8) -> Option<&mut [bool]>;
    /// The scan's start: input image, first-scan relays, cleared logic state.
    fn begin_scan(&mut self);
    /// Run the instruction at the program counter; after the scan's last one the tick counter
    /// moves on and the step returns to 0.
    fn execute(&mut self);
    /// Count a scan of a program with no instructions.
    fn count_empty_scan(&mut self);
    /// One whole scan from its start in the dialect's fast loop, leaving the machine as the
    /// executor leaves it at the scan's end; false, with nothing run, where it cannot.
    fn scan_fast(&mut self) -> bool;
    /// Bytes a clone holds, its vectors included (a checkpoint's cost).
    fn state_bytes(&self) -> usize;
}

/// A program of a scanned PLC with the scan time of `settings`.
pub fn open<P: ScannedPlc>(project: &Project, settings: &Settings) -> Result<P, Vec<Diagnostic>> {
    P::assemble(project.top_text(), TimeBase::from_settings(settings))
}

/// Store each forced bit's level where the program reads it.
pub fn hold_forces<P: ScannedPlc>(plc: &mut P) {
    for k in 0..plc.force_table().0.len() {
        let (loc, on) = plc.force_table().0[k];
        if let Some(bit) = plc
            .forced_store(loc.space)
            .and_then(|bits| bits.get_mut(loc.index as usize))
        {
            *bit = on;
        }
    }
}

fn start_scan<P: ScannedPlc>(plc: &mut P) {
    plc.begin_scan();
    if !plc.force_table().is_empty() {
        hold_forces(plc);
    }
}

fn run_instruction<P: ScannedPlc>(plc: &mut P) {
    plc.execute();
    if !plc.force_table().is_empty() {
        hold_forces(plc);
    }
}

/// The fast loop does not hold forces: it stands aside while any bit is forced.
fn fast_scan<P: ScannedPlc>(plc: &mut P) -> bool {
    plc.force_table().is_empty() && plc.scan_fast()
}

/// [`Machine::run_bare`] of a scanned PLC: the rest of a begun scan in the executor, whole
/// scans in the fast loop, then what is left of `limit` in the executor.
pub fn run_scans_bare<P: ScannedPlc>(plc: &mut P, limit: Pos) -> StopReason {
    if plc.pos().step != 0 {
        let scan_end = Pos::at_tick(plc.ticks() + 1).min(limit);
        run_scans(plc, scan_end, |_| false, |_| {});
    }
    while Pos::at_tick(plc.ticks() + 1) <= limit && fast_scan(plc) {}
    run_scans(plc, limit, |_| false, |_| {})
}

/// [`Machine::run_quiet`] of a scanned PLC: whole scans in the fast loop while the watched
/// values at scan ends stay as they were; the first scan that changes one is the last run.
/// A breakpoint line, which every scan passes, leaves the run to the timeline (None).
pub fn run_scans_quiet<P: ScannedPlc>(
    plc: &mut P,
    limit: Pos,
    quiet: &mut Quiet,
) -> Option<StopReason> {
    // A scan's writes are seen only at its end, too late for a data breakpoint.
    if !quiet.guarded.is_empty() || !plc.force_table().is_empty() {
        return None;
    }
    if quiet
        .halts_for(plc.instruction_count(), |i| plc.instruction_line(i))
        .contains(&true)
    {
        return None;
    }
    quiet.held.clear();
    quiet
        .held
        .extend(quiet.watched.iter().map(|&loc| plc.read(loc)));
    let mut ran = false;
    while plc.pos().step == 0 && Pos::at_tick(plc.ticks() + 1) <= limit && fast_scan(plc) {
        ran = true;
        if quiet
            .watched
            .iter()
            .zip(&quiet.held)
            .any(|(&loc, &was)| plc.read(loc) != was)
        {
            break;
        }
    }
    if ran {
        quiet.written.union(plc.scan_writes());
    }
    Some(StopReason::TickLimit)
}

/// The run loop of a scanned PLC: `stop` is asked before every instruction, `observe` after
/// every completed scan.
pub fn run_scans<P: ScannedPlc, F: FnMut(&P) -> bool, O: FnMut(&P)>(
    plc: &mut P,
    limit: Pos,
    mut stop: F,
    mut observe: O,
) -> StopReason {
    loop {
        if plc.pos() >= limit {
            return StopReason::TickLimit;
        }
        if plc.instruction_count() == 0 {
            start_scan(plc);
            plc.count_empty_scan();
            observe(plc);
            continue;
        }
        if stop(plc) {
            return StopReason::Predicate;
        }
        if plc.pos().step == 0 {
            start_scan(plc);
        }
        let tick = plc.ticks();
        run_instruction(plc);
        if plc.ticks() > tick {
            observe(plc);
        }
    }
}

impl<P: ScannedPlc> PlcView for P {
    fn ladder(&self) -> Arc<Ladder> {
        self.diagram()
    }
    fn wiring(&self) -> Arc<Ladder> {
        self.wired()
    }
    fn ladder_conducts(&self, index: usize) -> bool {
        self.conducts(index)
    }
    fn line_power(&self) -> Vec<(usize, LinePower)> {
        self.rung_power()
    }
    fn boxes(&self) -> Vec<BoxRow> {
        self.box_rows()
    }
    fn driven_by_scan(&self, loc: Loc) -> bool {
        self.relay_driven_by_scan(loc)
    }
    fn force(&mut self, loc: Loc, level: Option<bool>) -> Result<(), WriteError> {
        let info = self.info(loc);
        if !self.can_force(loc) {
            return Err(match info {
                Some(i) => WriteError::NotForceable(i.name),
                None => WriteError::NoSuchLocation,
            });
        }
        self.force_table_mut().set(loc, info, level)?;
        hold_forces(self);
        Ok(())
    }
    fn can_force(&self, loc: Loc) -> bool {
        P::forceable(loc.space) && self.info(loc).is_some()
    }
    fn forces(&self) -> Vec<(Loc, bool)> {
        self.force_table().0.clone()
    }
    fn forced(&self, loc: Loc) -> Option<bool> {
        self.force_table().get(loc)
    }
}

impl<P: ScannedPlc> Machine for P {
    fn snapshot_bytes(&self) -> usize {
        self.state_bytes()
    }

    fn run_observed<F: FnMut(&Self) -> bool, O: FnMut(&Self)>(
        &mut self,
        limit: Pos,
        stop: F,
        observe: O,
    ) -> StopReason {
        run_scans(self, limit, stop, observe)
    }

    fn run_bare(&mut self, limit: Pos) -> StopReason {
        run_scans_bare(self, limit)
    }

    /// Returns None while a line breakpoint is set: every scan would halt at it.
    fn run_quiet(
        &mut self,
        limit: Pos,
        quiet: &mut Quiet,
        _stop: &mut dyn FnMut(&Self) -> bool,
    ) -> Option<StopReason> {
        run_scans_quiet(self, limit, quiet)
    }
}
