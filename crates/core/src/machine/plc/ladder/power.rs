//! The live power flow of a diagram: where each rung is in the scan, the power at each node
//! and which elements conduct.

use super::{Ladder, RAIL, Rung, Symbol};

/// Where a rung is in the scan now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RungState {
    /// Evaluated in this scan (or the previous one, between scans).
    Done,
    /// Later in the scan than where the machine stands.
    NotYet,
    /// Not run this scan: jumped over, an inactive stage, a subroutine not called.
    NotRun,
    /// In a master-control area that is off.
    MasterOff,
}

/// The live power of one rung.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RungPower {
    pub state: RungState,
    /// Power at each node.
    pub node: Vec<bool>,
    /// Per element: a contact conducts, a coil or box has power at its (first) input.
    pub element: Vec<bool>,
}

impl RungPower {
    /// The power of `rung` when `conducts(instr)` says which contacts conduct.
    pub fn of(rung: &Rung, state: RungState, conducts: impl Fn(usize) -> bool) -> RungPower {
        let mut node = vec![false; rung.nodes as usize];
        // Only a rung this scan evaluated has power: one not reached yet, jumped over or in an
        // MCS area that is off shows its contacts' bits, its coils and boxes no power.
        node[RAIL as usize] = state == RungState::Done;
        let mut order: Vec<usize> = (0..rung.elements.len()).collect();
        order.sort_by_key(|&i| {
            let e = &rung.elements[i];
            e.from
                .first()
                .map_or(0, |&f| rung.node_col.get(f as usize).copied().unwrap_or(0))
        });
        let mut element = vec![false; rung.elements.len()];
        for i in order {
            let e = &rung.elements[i];
            let input = e
                .from
                .first()
                .is_some_and(|&f| node.get(f as usize).copied().unwrap_or(false));
            let (shown, out) = match e.symbol {
                Symbol::Contact { .. } | Symbol::Compare => {
                    let c = conducts(e.instr);
                    (c, input && c)
                }
                Symbol::Invert => (!input, !input),
                Symbol::PowerEdge(_) => {
                    let c = conducts(e.instr);
                    (c, c)
                }
                Symbol::Coil(_) | Symbol::Box => (input, false),
            };
            element[i] = shown;
            if let Some(to) = e.to
                && out
                && let Some(n) = node.get_mut(to as usize)
            {
                *n = true;
            }
        }
        RungPower {
            state,
            node,
            element,
        }
    }
}

/// The live state of a diagram: each rung's power.
pub fn power_of(ladder: &Ladder, m: &dyn crate::machine::MachineView) -> Vec<RungPower> {
    let Some(plc) = m.as_plc() else {
        return Vec::new();
    };
    let lines = plc.line_power();
    let now = m.pos();
    let pc = m.pc_line();
    ladder
        .rungs
        .iter()
        .map(|rung| {
            let first = rung.first_line();
            let power = lines.iter().find(|(l, _)| *l == first).map(|(_, p)| *p);
            let state = rung_state(first, power, now, pc);
            RungPower::of(rung, state, |i| plc.ladder_conducts(i))
        })
        .collect()
}

/// Where a rung whose first line is `first` stands in the scan, from that line's power, the
/// position and the line about to run: the one rule the panel and the SVG share.
pub fn rung_state(
    first: usize,
    line_power: Option<crate::machine::LinePower>,
    now: crate::machine::Pos,
    pc: Option<usize>,
) -> RungState {
    match line_power {
        Some(crate::machine::LinePower::NotRun) => RungState::NotRun,
        Some(crate::machine::LinePower::MasterOff) => RungState::MasterOff,
        // Before the first scan no rung has been evaluated: nothing has power yet.
        _ if now == crate::machine::Pos::default() => RungState::NotYet,
        _ if now.step > 0 && pc.is_some_and(|pc| first >= pc) => RungState::NotYet,
        _ => RungState::Done,
    }
}
