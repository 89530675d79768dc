//! The Timers & counters panel every scanned PLC shares: each box of the program in program
//! order, with its preset and where it came from, its current value (and time, for timers), a
//! progress bar toward the preset, its done bit, and what is special about it (at its maximum,
//! data not in the dialect's format). Clicking a row shows its line.

use egui::{RichText, vec2};

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::plc::BoxRow;

/// The panel, over any scanned PLC.
#[derive(Default)]
pub struct BoxesPanel;

/// The program's boxes (None when the machine is no PLC).
fn rows(debugger: &Debugger) -> Option<Vec<BoxRow>> {
    Some(debugger.machine().as_plc()?.boxes())
}

impl DialectPanel for BoxesPanel {
    fn title(&self) -> &'static str {
        "Timers & counters"
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        rows(debugger).is_some_and(|rows| !rows.is_empty())
    }
    fn wants_focus(&self, debugger: &Debugger) -> bool {
        self.has_content(debugger)
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, out: &mut Vec<Command>) {
        let Some(rows) = rows(debugger) else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        if rows.is_empty() {
            ui.label(RichText::new("This program has no timers or counters.").color(p.dim));
            return;
        }
        egui::ScrollArea::both()
            .id_salt("plc_boxes")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                egui::Grid::new("plc_boxes_grid")
                    .num_columns(6)
                    .spacing([10.0, 4.0])
                    .striped(true)
                    .show(ui, |ui| {
                        for h in ["Box", "Preset", "Current", "Done", "", ""] {
                            ui.strong(h);
                        }
                        ui.end_row();
                        for row in &rows {
                            box_row(ui, row, &p, out);
                            ui.end_row();
                        }
                    });
            });
    }
}

fn scans_to_go(n: u64) -> String {
    format!("{n} scan{} to go", if n == 1 { "" } else { "s" })
}

fn box_row(ui: &mut egui::Ui, row: &BoxRow, p: &crate::ui::theme::Palette, out: &mut Vec<Command>) {
    let title = ui
        .add(egui::Button::new(RichText::new(&row.title).monospace()).frame(false))
        .on_hover_text(format!("Line {}: click to show it", row.line));
    if title.clicked() {
        out.push(Command::ShowLine(row.line));
    }
    let preset = match row.preset {
        // A constant preset: its time; a register's: where it came from too.
        Some(v)
            if row.preset_from.starts_with(['K', 'k'])
                || row.preset_from.starts_with(|c: char| c.is_ascii_digit()) =>
        {
            row.amount(v)
        }
        Some(v) => format!("{} = {}", row.preset_from, row.amount(v)),
        None => format!("{} (not BCD)", row.preset_from),
    };
    ui.monospace(preset);
    let current = match row.value {
        Some(v) => format!("{} = {}", row.value_at, row.amount(v)),
        None => format!("{} = {:X}", row.value_at, row.raw),
    };
    let note = row.note();
    let current =
        ui.monospace(RichText::new(current).color(if note.is_some() { p.error } else { p.text }));
    if let Some(note) = &note {
        current.on_hover_text(note);
    }
    // The lamp before the bar: it stays in view in a narrow pane.
    let chip = ui.add(
        egui::Button::new(RichText::new(&row.status).size(12.0).color(if row.done {
            egui::Color32::WHITE
        } else {
            p.dim
        }))
        .fill(if row.done {
            p.bit_on
        } else {
            p.bit_off.gamma_multiply(0.5)
        })
        .min_size(vec2(0.0, 0.0)),
    );
    let label = format!(
        "{} {}",
        row.status,
        if row.done { "done" } else { "not done" }
    );
    chip.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, &label));
    let bar = ui.add(
        egui::ProgressBar::new(row.progress())
            .desired_width(90.0)
            .desired_height(10.0),
    );
    match row.elapsed() {
        Some((ms, scans)) => {
            let to_go = match scans {
                Some(n) => scans_to_go(n),
                None if row.done => "done".to_string(),
                None => "not timing".to_string(),
            };
            bar.on_hover_text(format!("{ms} ms elapsed, {to_go}"));
        }
        None => {
            bar.on_hover_text(format!("{:.0} % of the preset", row.progress() * 100.0));
        }
    }
    if let Some(note) = note {
        ui.label(RichText::new(note).size(12.0).color(p.error));
    } else if let Some((ms, scans)) = row.elapsed() {
        // A count-down timer: the time so far and the scans until its output turns on.
        let text = match scans {
            Some(n) => format!("{ms} ms elapsed, {}", scans_to_go(n)),
            None if row.done => format!("{ms} ms elapsed"),
            None => "not timing".to_string(),
        };
        ui.label(RichText::new(text).size(12.0).color(p.dim));
    }
}
