//! The register view: status words as named bits, R0–R199 in decimal, hex and binary with a
//! display format per view or per register, a filter, and the bit grid of the selected register
//! with in-place editing.

use std::collections::BTreeMap;

use egui::{RichText, Sense, Vec2, vec2};
use egui_extras::{Column, TableBuilder};

use super::theme::palette;
use super::{Command, Prefs};
use crate::debugger::Debugger;
use crate::debugger::format::{self, Format};
use crate::machine::Machine;

pub struct RegisterView {
    pub format: Format,
    /// Formats chosen for single registers (right-click a row).
    pub overrides: BTreeMap<usize, Format>,
    pub only_used: bool,
    pub selected: Option<usize>,
    pub edit_text: String,
    pub edit_error: Option<String>,
}

impl RegisterView {
    pub fn new(prefs: &Prefs) -> Self {
        RegisterView {
            format: prefs.register_format,
            overrides: BTreeMap::new(),
            only_used: prefs.only_used_registers,
            selected: None,
            edit_text: String::new(),
            edit_error: None,
        }
    }

    pub fn format_of(&self, register: usize) -> Format {
        self.overrides
            .get(&register)
            .copied()
            .unwrap_or(self.format)
    }

    fn select(&mut self, register: usize, value: u32) {
        if self.selected != Some(register) {
            self.selected = Some(register);
            self.edit_text = (value as i32).to_string();
            self.edit_error = None;
        }
    }
}

/// Registers shown: those the program mentions (plus the dedicated ones) or all.
pub fn visible_registers(debugger: &Debugger, only_used: bool) -> Vec<usize> {
    let count = debugger.machine().register_count();
    if !only_used {
        return (0..count).collect();
    }
    let mut regs: Vec<usize> = [0, 1, 2, 4, 6, 7, 10]
        .into_iter()
        .chain(debugger.used_registers().iter().map(|&r| r as usize))
        .filter(|&r| r < count)
        .collect();
    regs.sort_unstable();
    regs.dedup();
    regs
}

pub fn show(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut RegisterView,
    out: &mut Vec<Command>,
) {
    status_words(ui, debugger, out);
    ui.separator();
    ui.horizontal(|ui| {
        egui::ComboBox::new("register_format", "Format")
            .selected_text(view.format.name())
            .show_ui(ui, |ui| {
                for f in Format::ALL {
                    ui.selectable_value(&mut view.format, f, f.name());
                }
            });
        ui.checkbox(&mut view.only_used, "Only registers this program uses");
    });
    if let Some(r) = view.selected {
        ui.separator();
        bit_grid(ui, debugger, view, r, out);
    }
    ui.separator();
    table(ui, debugger, view);
}

fn status_words(ui: &mut egui::Ui, debugger: &Debugger, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    for word in debugger.machine().status_words() {
        ui.horizontal_wrapped(|ui| {
            ui.spacing_mut().item_spacing = vec2(3.0, 3.0);
            ui.add_sized(
                [34.0, 18.0],
                egui::Label::new(RichText::new(word.name).strong()),
            )
            .on_hover_text(format!(
                "{} = 0x{:04X} = {:016b}",
                word.name, word.value, word.value
            ));
            for bit in word.bits {
                let on = word.is_set(bit.bit);
                let text = RichText::new(bit.name).small().color(if on {
                    egui::Color32::WHITE
                } else {
                    p.dim
                });
                let chip = egui::Button::new(text)
                    .fill(if on {
                        p.bit_on
                    } else {
                        p.bit_off.gamma_multiply(0.5)
                    })
                    .min_size(Vec2::ZERO);
                let r = ui.add(chip);
                let label = format!("{} {}", word.name, bit.name);
                r.widget_info(|| {
                    egui::WidgetInfo::selected(egui::Role::CheckBox, true, on, &label)
                });
                let r = r.on_hover_text(format!(
                    "bit {}: {} ({}) — click to flip",
                    bit.bit,
                    bit.description,
                    if on { "set" } else { "clear" }
                ));
                if r.clicked() {
                    out.push(Command::SetStatusBit(word.name, bit.bit, !on));
                }
            }
        });
    }
}

fn bit_grid(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut RegisterView,
    r: usize,
    out: &mut Vec<Command>,
) {
    let p = palette(ui.visuals().dark_mode);
    let machine = debugger.machine();
    let info = machine.register_info(r);
    let value = machine.register(r);
    if view.edit_text.is_empty() && view.edit_error.is_none() {
        // Selected from a session or a fresh view: start the field at the current value.
        view.edit_text = (value as i32).to_string();
    }
    ui.horizontal(|ui| {
        ui.heading(&info.name);
        if let Some(alias) = info.alias {
            ui.label(RichText::new(alias).strong());
        }
        ui.label(RichText::new(info.description).color(p.dim));
        if ui
            .small_button("Close")
            .on_hover_text("Close the bit view")
            .clicked()
        {
            view.selected = None;
        }
    });
    let cell = vec2(14.0, 18.0);
    let nibble_gap = 4.0;
    let word_gap = 10.0;
    let gap_after = |bit: u32| -> f32 {
        if bit == 16 {
            word_gap
        } else if bit.is_multiple_of(4) && bit != 0 {
            nibble_gap
        } else {
            0.0
        }
    };
    let half_width = 16.0 * cell.x + 3.0 * nibble_gap;
    ui.horizontal(|ui| {
        ui.spacing_mut().item_spacing.x = 0.0;
        ui.add_sized(
            [half_width, 14.0],
            egui::Label::new(RichText::new("HI word (bits 31–16)").small().color(p.dim)),
        );
        ui.add_space(word_gap);
        ui.add_sized(
            [half_width, 14.0],
            egui::Label::new(RichText::new("LO word (bits 15–0)").small().color(p.dim)),
        );
    });
    ui.horizontal(|ui| {
        ui.spacing_mut().item_spacing.x = 0.0;
        for bit in (0..32u32).rev() {
            ui.add_sized(
                [cell.x, 12.0],
                egui::Label::new(RichText::new(bit.to_string()).size(8.5).color(p.dim)),
            );
            ui.add_space(gap_after(bit));
        }
    });
    ui.horizontal(|ui| {
        ui.spacing_mut().item_spacing.x = 0.0;
        ui.spacing_mut().button_padding = vec2(0.0, 0.0);
        for bit in (0..32u32).rev() {
            let on = value >> bit & 1 == 1;
            let button = egui::Button::new(
                RichText::new(if on { "1" } else { "0" })
                    .monospace()
                    .color(if on { egui::Color32::WHITE } else { p.dim }),
            )
            .fill(if on { p.bit_on } else { p.bit_off })
            .min_size(cell);
            let resp = ui.add_sized(cell, button);
            let label = format!("{} bit {bit}", info.name);
            resp.widget_info(|| egui::WidgetInfo::selected(egui::Role::CheckBox, true, on, &label));
            if resp
                .on_hover_text(format!("bit {bit} = {} — click to flip", u8::from(on)))
                .clicked()
            {
                out.push(Command::ToggleRegisterBit(r, bit as u8));
                view.edit_text = ((value ^ (1 << bit)) as i32).to_string();
                view.edit_error = None;
            }
            ui.add_space(gap_after(bit));
        }
    });
    let hi = value >> 16;
    let lo = value & 0xFFFF;
    egui::Grid::new("bit_readouts")
        .num_columns(4)
        .spacing([14.0, 2.0])
        .show(ui, |ui| {
            ui.label("signed");
            ui.monospace((value as i32).to_string());
            ui.label("unsigned");
            ui.monospace(value.to_string());
            ui.end_row();
            ui.label("hex");
            ui.monospace(format::hex(value));
            ui.label("Q16.16");
            ui.monospace(format::q16(value));
            ui.end_row();
            ui.label("HI word");
            ui.monospace(format!("0x{hi:04X} = {hi} = {}", hi as u16 as i16));
            ui.label("LO word");
            ui.monospace(format!("0x{lo:04X} = {lo} = {}", lo as u16 as i16));
            ui.end_row();
        });
    ui.horizontal(|ui| {
        let label = ui.label(format!("Value of {}", info.name));
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut view.edit_text)
                    .desired_width(150.0)
                    .hint_text("42, 0x2A, 0b101, q16(1.5)"),
            )
            .labelled_by(label.id);
        let entered = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("Set").clicked() || entered {
            match format::parse_value(&view.edit_text) {
                Ok(v) => {
                    out.push(Command::SetRegister(r, v));
                    view.edit_error = None;
                }
                Err(e) => view.edit_error = Some(e),
            }
        }
    });
    if let Some(error) = &view.edit_error {
        ui.label(RichText::new(format!("Not changed: {error}")).color(p.error));
    }
}

fn table(ui: &mut egui::Ui, debugger: &Debugger, view: &mut RegisterView) {
    let p = palette(ui.visuals().dark_mode);
    let machine = debugger.machine();
    let rows = visible_registers(debugger, view.only_used);
    let written = machine.last_written();
    let row_height = ui.text_style_height(&egui::TextStyle::Monospace) + 4.0;
    let mut clicked: Option<usize> = None;
    // Cells are read, not selected: clicks go to the row (select) and its context menu.
    ui.style_mut().interaction.selectable_labels = false;
    let mut format_change: Option<(usize, Option<Format>)> = None;
    TableBuilder::new(ui)
        .id_salt("register_table")
        .striped(true)
        .sense(Sense::click())
        .cell_layout(egui::Layout::left_to_right(egui::Align::Center))
        .column(Column::exact(44.0))
        .column(Column::exact(84.0))
        .column(Column::initial(96.0).at_least(60.0).resizable(true))
        .column(Column::exact(92.0))
        .column(Column::remainder().at_least(100.0))
        .header(20.0, |mut header| {
            for title in ["Reg", "Name", "Value", "Hex", "Binary"] {
                header.col(|ui| {
                    ui.strong(title);
                });
            }
        })
        .body(|body| {
            body.rows(row_height, rows.len(), |mut row| {
                let r = rows[row.index()];
                let value = machine.register(r);
                let info = machine.register_info(r);
                let fresh = written.contains(&r);
                let colour = if fresh { p.written } else { p.text };
                let format = view.format_of(r);
                row.set_selected(view.selected == Some(r));
                row.col(|ui| {
                    let mut text = RichText::new(&info.name).monospace().color(colour);
                    if fresh {
                        text = text.strong();
                    }
                    ui.label(text);
                });
                row.col(|ui| {
                    ui.label(RichText::new(info.alias.unwrap_or("")).small().color(p.dim));
                });
                row.col(|ui| {
                    let mut shown = RichText::new(format.show(value)).monospace().color(colour);
                    if view.overrides.contains_key(&r) {
                        shown = shown.italics();
                    }
                    ui.label(shown);
                });
                row.col(|ui| {
                    ui.label(RichText::new(format::hex(value)).monospace().color(colour));
                });
                row.col(|ui| {
                    ui.label(
                        RichText::new(format::binary(value))
                            .monospace()
                            .size(11.0)
                            .color(colour),
                    );
                });
                let response = row.response();
                if response.clicked() {
                    clicked = Some(r);
                }
                response.context_menu(|ui| {
                    ui.label(format!("Show {} as", info.name));
                    for f in Format::ALL {
                        if ui
                            .selectable_label(
                                view.format_of(r) == f && view.overrides.contains_key(&r),
                                f.name(),
                            )
                            .clicked()
                        {
                            format_change = Some((r, Some(f)));
                            ui.close();
                        }
                    }
                    if ui.button("Like the others").clicked() {
                        format_change = Some((r, None));
                        ui.close();
                    }
                });
            });
        });
    if let Some(r) = clicked {
        view.select(r, machine.register(r));
    }
    match format_change {
        Some((r, Some(f))) => {
            view.overrides.insert(r, f);
        }
        Some((r, None)) => {
            view.overrides.remove(&r);
        }
        None => {}
    }
}
