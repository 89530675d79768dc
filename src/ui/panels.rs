//! A dialect's own panels (SilverLode's queue rings, DL205's accumulator stack, TML's product
//! register): a small trait, implemented in the dialect's folder under `ui/dialects/` and listed
//! in [`super::dialects::PANELS`]. A panel appears only for its dialect.

use super::Command;
use servoscope_core::debugger::Debugger;

pub trait DialectPanel {
    fn title(&self) -> &'static str;
    /// Whether there is anything to show now; without content the panel gives its space away.
    fn has_content(&self, _debugger: &Debugger) -> bool {
        true
    }
    /// Whether a newly opened program is best watched in this panel (a DL205 program with
    /// stages: the Stages panel): its tab comes to the front.
    fn wants_focus(&self, _debugger: &Debugger) -> bool {
        false
    }
    /// Draw into `ui`, which is `height` points tall; emit what the user asks for.
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, height: f32, out: &mut Vec<Command>);
}
