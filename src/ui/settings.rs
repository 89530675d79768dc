//! The dialect's settings (SilverLode: the servo model of spec §6 — natural frequency, damping
//! and the error limits), drawn from the dialect's own description of them. Applying them
//! restarts the program, since the recorded history came from the old settings.

use egui::RichText;

use super::Command;
use servoscope_core::debugger::Debugger;
use servoscope_core::registry::Settings;

#[derive(Default)]
pub struct SettingsView {
    pub open: bool,
    /// The values being edited; `None` until the window opens on the current settings.
    pub draft: Option<Settings>,
}

pub fn window(
    ctx: &egui::Context,
    debugger: &Debugger,
    view: &mut SettingsView,
    out: &mut Vec<Command>,
) {
    let dialect = debugger.dialect();
    if !view.open || dialect.settings.is_empty() {
        view.draft = None;
        view.open = false;
        return;
    }
    let current = debugger.settings().clone();
    let draft = view.draft.get_or_insert_with(|| current.clone());
    let mut open = true;
    egui::Window::new(format!("{} settings", dialect.display_name))
        .collapsible(false)
        .resizable(false)
        .open(&mut open)
        .show(ctx, |ui| {
            egui::Grid::new("dialect_settings")
                .num_columns(2)
                .show(ui, |ui| {
                    for s in dialect.settings {
                        let label = ui.label(s.label).on_hover_text(s.help);
                        let value = draft.entry(s.key.to_string()).or_insert(s.default);
                        let speed = if s.integer {
                            1.0
                        } else {
                            (s.max - s.min) / 1000.0
                        };
                        let mut drag = egui::DragValue::new(value)
                            .range(s.min..=s.max)
                            .speed(speed);
                        if s.integer {
                            drag = drag.fixed_decimals(0);
                        }
                        ui.add(drag).labelled_by(label.id).on_hover_text(s.help);
                        ui.end_row();
                    }
                });
            ui.label(
                RichText::new(format!(
                    "Applying restarts the program from {} 0, inputs off: the recorded run came from the old settings.",
                    dialect.vocabulary.tick
                ))
                .small(),
            );
            ui.horizontal(|ui| {
                let changed = dialect.settings_from(draft) != current;
                if ui.add_enabled(changed, egui::Button::new("Apply")).clicked() {
                    out.push(Command::SetSettings(draft.clone()));
                }
                if ui.button("Defaults").clicked() {
                    *draft = dialect.default_settings();
                }
            });
        });
    if !open {
        view.open = false;
    }
}
