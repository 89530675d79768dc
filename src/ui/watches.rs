//! The Watches panel: expressions in the condition language, each in a format of its own,
//! evaluated at the current position; any of them can join the plot as a channel.

use egui::RichText;
use servoscope_core::debugger::Action;

use super::Command;
use super::theme::palette;
use servoscope_core::debugger::{Debugger, Watch};
use servoscope_core::machine::Format;

#[derive(Default)]
pub struct WatchesView {
    pub new_expr: String,
}

/// A watch's value in `format`. A watch of one location reads its bits at the location's width,
/// so "signed" means what it means in the register view; any other expression is 32 bits wide
/// when its value fits, else 64.
pub fn shown(v: i64, format: Format, location_width: Option<u8>) -> String {
    if let Some(width) = location_width {
        return format.show(v as u64, width);
    }
    let width = if i32::try_from(v).is_ok() || u32::try_from(v).is_ok() {
        32
    } else {
        64
    };
    let raw = if width == 32 {
        u64::from(v as u32)
    } else {
        v as u64
    };
    match format {
        Format::Signed => v.to_string(),
        f => f.show(raw, width),
    }
}

pub fn show(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut WatchesView,
    out: &mut Vec<Command>,
) {
    let p = palette(ui.visuals().dark_mode);
    ui.horizontal(|ui| {
        let field = ui.add(
            egui::TextEdit::singleline(&mut view.new_expr)
                .char_limit(servoscope_core::session::limits::TEXT)
                .hint_text(debugger.dialect().vocabulary.watch_hint)
                .desired_width(ui.available_width() - 60.0),
        );
        field.widget_info(|| egui::WidgetInfo::labeled(egui::Role::TextInput, true, "New watch"));
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if (ui.button("Add").clicked() || entered) && !view.new_expr.trim().is_empty() {
            out.push(Command::AddWatch(std::mem::take(&mut view.new_expr)));
        }
    });
    ui.separator();
    if debugger.watches().is_empty() {
        ui.label(RichText::new("No watches: type an expression above.").color(p.dim));
        return;
    }
    egui::ScrollArea::vertical()
        .id_salt("watch_list")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            for (i, w) in debugger.watches().iter().enumerate() {
                watch_row(ui, debugger, i, w, out);
            }
        });
}

fn watch_row(ui: &mut egui::Ui, debugger: &Debugger, i: usize, w: &Watch, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    let n = i + 1;
    let mut edited = w.clone();
    let mut error = None;
    // The buttons come before the value, and an error goes under the row, so a long one never
    // pushes them out of view.
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(&mut edited.expr)
                .char_limit(servoscope_core::session::limits::TEXT)
                .desired_width(150.0)
                .min_size(egui::vec2(150.0, 0.0)),
        )
        .widget_info(|| {
            egui::WidgetInfo::labeled(egui::Role::TextInput, true, format!("Watch {n}"))
        });
        egui::ComboBox::new(("watch_format", i), "")
            .selected_text(w.format.name())
            .show_ui(ui, |ui| {
                for f in Format::ALL {
                    ui.selectable_value(&mut edited.format, f, f.name());
                }
            })
            .response
            .widget_info(|| {
                egui::WidgetInfo::labeled(
                    egui::Role::ComboBox,
                    true,
                    format!("Format of watch {n}"),
                )
            });
        let plotted = debugger.channels().iter().any(|c| c.name == w.expr);
        let plot = ui
            .add_enabled(!plotted, egui::Button::new("Plot").small())
            .on_hover_text("Add it to the plot as a channel");
        plot.widget_info(|| {
            egui::WidgetInfo::labeled(egui::Role::Button, !plotted, format!("Plot watch {n}"))
        });
        if plot.clicked() {
            out.push(Command::PlotWatch(i));
        }
        let delete = ui.small_button("×");
        delete.widget_info(|| {
            egui::WidgetInfo::labeled(egui::Role::Button, true, format!("Delete watch {n}"))
        });
        if delete.clicked() {
            out.push(Command::Debug(Action::RemoveWatch(i)));
        }
        match debugger.watch_value(i) {
            Ok(v) => {
                let text = shown(v, w.format, debugger.watch_width(i));
                ui.label(RichText::new(&text).monospace()).widget_info(|| {
                    egui::WidgetInfo::labeled(
                        egui::Role::Label,
                        true,
                        format!("Value of watch {n}: {text}"),
                    )
                });
            }
            Err(e) => error = Some(e.to_string()),
        }
    });
    if error.is_none()
        && let Some(note) = debugger.watch_wrap_note(i)
    {
        ui.add(egui::Label::new(RichText::new(note).small().color(p.written)).wrap())
            .widget_info(|| {
                egui::WidgetInfo::labeled(egui::Role::Label, true, format!("Note of watch {n}"))
            });
    }
    if let Some(e) = error {
        ui.add(egui::Label::new(RichText::new(e).color(p.error)).wrap())
            .widget_info(|| {
                egui::WidgetInfo::labeled(egui::Role::Label, true, format!("Error of watch {n}"))
            });
    }
    ui.separator();
    if edited != *w {
        out.push(Command::Debug(Action::UpdateWatch(i, edited)));
    }
}
