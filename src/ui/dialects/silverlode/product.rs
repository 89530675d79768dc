//! SilverLode's Product panel: what the multiply or divide at the program counter does to the
//! bits ([`servoscope_core::machine::silverlode::arith`]), and, once it has run, the same for the last one seen.

use egui::RichText;

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::bits::Breakdown;
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::arith;
use servoscope_core::machine::{MachineView, Pos};

pub const TITLE: &str = "Product";

/// The breakdown of the arithmetic command at the program counter, remembered with where it was
/// made, so it is still shown (as "last run") once the command has run.
#[derive(Default)]
pub struct ProductPanel {
    seen: Option<(Pos, (u64, usize), Breakdown)>,
}

impl DialectPanel for ProductPanel {
    fn title(&self) -> &'static str {
        TITLE
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        debugger
            .machine_as::<SilverLode>()
            .is_some_and(|m| m.program().instrs.iter().any(arith::is_explained))
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, _: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<SilverLode>() else {
            return;
        };
        let pos = m.pos();
        // A new timeline or a user edit since makes a remembered breakdown stale.
        let generation = (debugger.generation(), debugger.events().len());
        let next = arith::at_pc(m);
        if let Some(b) = &next {
            self.seen = Some((pos, generation, b.clone()));
        }
        // A breakdown made at an earlier position of this same run is what that command did:
        // the command at the program counter always runs next.
        // Else the command that ran last, if it multiplied or divided: a run that stopped
        // right after it (a data breakpoint on its result) never showed it at the counter.
        let just_run = next.is_none().then(|| arith::last_run(m)).flatten();
        let last = match (&next, &self.seen) {
            _ if just_run.is_some() => None,
            (None, Some((at, g, b))) if *at < pos && *g == generation => Some((*at, b)),
            _ => None,
        };
        let p = palette(ui.visuals().dark_mode);
        egui::ScrollArea::both()
            .id_salt("sl_product_scroll")
            .auto_shrink([false, false])
            .show(ui, |ui| match (&next, last) {
                (Some(b), _) => breakdown(ui, b, "About to run", &p),
                (None, _) if let Some(b) = &just_run => {
                    breakdown(ui, b, "Last run (the command that ran last)", &p);
                }
                (None, Some((at, b))) => {
                    breakdown(ui, b, &format!("Last run (at tick {at})"), &p);
                }
                (None, None) => {
                    ui.label(
                        RichText::new(
                            "Step onto a multiply or divide (MULT_S64_SHR16, MULT_U64, MULT_S, \
                             MULT_U, DIV, DIV_U64, MOD) to see its bits here.",
                        )
                        .color(p.dim),
                    );
                }
            });
    }
}

fn breakdown(ui: &mut egui::Ui, b: &Breakdown, when: &str, p: &crate::ui::theme::Palette) {
    crate::ui::bitrows::breakdown(ui, b, when, &|l| format!("line {l}"), p);
}
