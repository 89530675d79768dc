//! The servo model settings of spec §6: natural frequency, damping and the error limits.
//! Applying them restarts the program, since the recorded history came from the old model.

use egui::RichText;

use super::Command;
use crate::debugger::Debugger;
use crate::machine::silverlode::ServoSettings;

#[derive(Default)]
pub struct ServoView {
    pub open: bool,
    /// The values being edited; `None` until the window opens on the current settings.
    pub draft: Option<ServoSettings>,
}

pub fn window(
    ctx: &egui::Context,
    debugger: &Debugger,
    view: &mut ServoView,
    out: &mut Vec<Command>,
) {
    if !view.open {
        view.draft = None;
        return;
    }
    let current = debugger.settings();
    let draft = view.draft.get_or_insert(current);
    let mut open = true;
    egui::Window::new("Servo model")
        .collapsible(false)
        .resizable(false)
        .open(&mut open)
        .show(ctx, |ui| {
            egui::Grid::new("servo_settings").num_columns(2).show(ui, |ui| {
                let f = ServoSettings::FREQUENCY_RANGE;
                let label = ui.label("Natural frequency (Hz)");
                ui.add(egui::DragValue::new(&mut draft.natural_frequency_hz).range(*f.start()..=*f.end()).speed(0.5))
                    .labelled_by(label.id);
                ui.end_row();
                let d = ServoSettings::DAMPING_RANGE;
                let label = ui.label("Damping ratio");
                ui.add(egui::DragValue::new(&mut draft.damping).range(*d.start()..=*d.end()).speed(0.01))
                    .labelled_by(label.id);
                ui.end_row();
                let label = ui.label("Moving error limit (counts)");
                ui.add(egui::DragValue::new(&mut draft.moving_error_limit).range(0..=u32::MAX))
                    .labelled_by(label.id);
                ui.end_row();
                let label = ui.label("Holding error limit (counts)");
                ui.add(egui::DragValue::new(&mut draft.holding_error_limit).range(0..=u32::MAX))
                    .labelled_by(label.id);
                ui.end_row();
            });
            ui.label(
                RichText::new("Applying restarts the program from tick 0: the recorded run came from the old model.")
                    .small(),
            );
            ui.horizontal(|ui| {
                let changed = *draft != current;
                if ui.add_enabled(changed, egui::Button::new("Apply")).clicked() {
                    out.push(Command::SetServo(*draft));
                }
                if ui.button("Defaults").clicked() {
                    *draft = ServoSettings::default();
                }
            });
        });
    if !open {
        view.open = false;
    }
}
