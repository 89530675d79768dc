//! The list of the program's errors and warnings under the text.

use super::*;

/// The problems list: every diagnostic; clicking one moves the cursor to its line.
pub(super) fn problems(ui: &mut egui::Ui, debugger: &Debugger, view: &mut CodeView) {
    let p = palette(ui.visuals().dark_mode);
    // As tall as its rows (up to six), never more than half the pane: one error must not take
    // the room of the program it is about. A new panel per row count, so it refits when the
    // count changes; a size the user dragged holds while it stays the same.
    let rows_shown = debugger.diagnostics().len().min(6);
    let row_height = ui.spacing().interact_size.y + ui.spacing().item_spacing.y;
    let fit = row_height * (rows_shown as f32 + 1.0) + 12.0;
    egui::Panel::bottom(Id::unique(("problems", rows_shown)))
        .resizable(true)
        .default_size(fit)
        .min_size(fit.min(60.0))
        .max_size((ui.available_height() * 0.5).max(fit.min(60.0)))
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.strong(format!("Problems ({})", debugger.diagnostics().len()));
                let note = if debugger.has_errors() {
                    "Nothing runs until the errors are fixed."
                } else {
                    "Warnings only: the program runs."
                };
                ui.label(egui::RichText::new(note).color(p.dim));
            });
            let diagnostics = debugger.diagnostics();
            let row_height = ui.spacing().interact_size.y;
            // Only the visible rows are laid out: a file with 100,000 errors stays responsive.
            egui::ScrollArea::vertical()
                .id_salt("problems_scroll")
                .auto_shrink([false, true])
                .show_rows(ui, row_height, diagnostics.len(), |ui, rows| {
                    for d in &diagnostics[rows] {
                        let warning = d.severity == servoscope_core::machine::Severity::Warning;
                        let text = format!(
                            "{}:{}  {}{}",
                            debugger.describe_line(d.line),
                            d.col,
                            if warning { "warning: " } else { "" },
                            servoscope_core::machine::diagnostics::printable(&d.message)
                        );
                        let r = ui.add(
                            egui::Button::selectable(
                                false,
                                egui::RichText::new(text).color(if warning {
                                    p.written
                                } else {
                                    p.error
                                }),
                            )
                            .min_size(Vec2::ZERO),
                        );
                        if r.clicked() {
                            view.pending_jump = Some(Jump {
                                line: d.line,
                                col: d.col,
                                len: 0,
                            });
                        }
                    }
                });
        });
}
