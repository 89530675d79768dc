//! The timeline: a scrubber from tick 0 to the furthest tick reached, with breakpoint hits and
//! faults marked on it, the step-back controls and a "go to tick" field.

use egui::{RichText, Stroke, vec2};
use servoscope_core::debugger::Action;

use super::Command;
use super::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::debugger::history::MarkKind;

#[derive(Default)]
pub struct TimelineView {
    pub goto_text: String,
    pub goto_error: Option<String>,
}

pub fn show(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut TimelineView,
    out: &mut Vec<Command>,
) {
    let p = palette(ui.visuals().dark_mode);
    let words = debugger.dialect().vocabulary;
    let pos = debugger.pos();
    let now = pos.tick;
    let furthest = debugger.furthest_tick();
    ui.horizontal_wrapped(|ui| {
        let back_ok = pos > servoscope_core::machine::Pos::default() && !debugger.is_edited();
        if ui
            .add_enabled(back_ok, egui::Button::new("Reverse"))
            .on_hover_text("Back to the previous breakpoint hit (Shift+F5)")
            .clicked()
        {
            out.push(Command::Debug(Action::ReverseContinue));
        }
        if ui
            .add_enabled(back_ok, egui::Button::new("Step back"))
            .on_hover_text(format!(
                "Undo the last {}; a call that just returned, whole (Shift+F10)",
                words.step
            ))
            .clicked()
        {
            out.push(Command::Debug(Action::StepBackOver));
        }
        if ui
            .add_enabled(
                back_ok,
                egui::Button::new(format!("{} back", capitalised(words.tick))),
            )
            .on_hover_text(format!(
                "Back to the start of this or the previous {} (Shift+F8)",
                words.tick
            ))
            .clicked()
        {
            out.push(Command::Debug(Action::StepBackTick));
        }
        ui.label(
            RichText::new(format!("{now} / {furthest}"))
                .monospace()
                .color(p.dim),
        )
        .on_hover_text(format!("This {} / the furthest reached", words.tick));
        let goto_label = ui.label(format!("Go to {}", words.tick));
        // Wide enough for the furthest tick's digits, so a long run never cuts it off.
        let digits = furthest.max(1).ilog10() as f32 + 2.0;
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut view.goto_text)
                    .desired_width((digits * 9.0).max(80.0)),
            )
            .labelled_by(goto_label.id);
        if edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
            match view.goto_text.trim().replace('_', "").parse::<u64>() {
                Ok(t) => {
                    view.goto_error = None;
                    out.push(Command::Debug(Action::GoToTick(t)));
                }
                Err(_) => {
                    view.goto_error = Some(format!(
                        "'{}' is not a {} number",
                        view.goto_text.trim(),
                        words.tick
                    ))
                }
            }
        }
        if let Some(e) = &view.goto_error {
            ui.label(RichText::new(e).color(p.error));
        }
    });
    // The scrubber has a row of its own: the whole width of the panel, at any window size.
    let mut tick = now;
    ui.spacing_mut().slider_width = (ui.available_width() - 12.0).max(60.0);
    let slider = ui
        .add_enabled(
            furthest > 0,
            egui::Slider::new(&mut tick, 0..=furthest.max(1)).show_value(false),
        )
        .on_hover_text(format!(
            "Drag to any {} between 0 and {furthest}, the furthest reached. \
             Marks: breakpoint hits (blue), faults (red).",
            words.tick
        ));
    slider.widget_info(|| {
        egui::WidgetInfo::labeled(egui::Role::Slider, furthest > 0, "Timeline position")
    });
    if slider.changed() && tick != now {
        out.push(Command::Debug(Action::GoToTick(tick)));
    }
    // Marks over the slider's rail.
    let rail = slider.rect.shrink2(vec2(6.0, 0.0));
    let x_of = |t: u64| rail.left() + rail.width() * t as f32 / furthest.max(1) as f32;
    let painter = ui.painter();
    for m in debugger.marks() {
        let colour = match m.kind {
            MarkKind::Breakpoint => p.mnemonic,
            MarkKind::Fault => p.error,
        };
        let x = x_of(m.at.tick);
        painter.line_segment(
            [egui::pos2(x, rail.top()), egui::pos2(x, rail.bottom())],
            Stroke::new(2.0, colour),
        );
    }
}

/// The height the timeline needs: its two rows.
pub fn height(style: &egui::Style) -> f32 {
    let row = style.spacing.interact_size.y.max(20.0);
    2.0 * row + 2.0 * style.spacing.item_spacing.y + 6.0
}

/// `scan` -> `Scan`.
pub fn capitalised(word: &str) -> String {
    let mut chars = word.chars();
    chars
        .next()
        .map(|c| c.to_uppercase().chain(chars).collect())
        .unwrap_or_default()
}
