//! The register view for any dialect: flag words and relays as named chips, every data location
//! in the dialect's spaces with a display format per view or per location, a filter, and the
//! bit grid of the selected location (any width, in 16-bit words) with in-place editing.

use servoscope_core::debugger::Action;
use std::collections::BTreeMap;

use egui::{RichText, Sense, Stroke, Vec2, vec2};
use egui_extras::{Column, TableBuilder};

use super::theme::palette;
use super::{Command, Prefs};
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::value::{self, Format, sign_extend};
use servoscope_core::machine::{Loc, LocInfo, MachineView, SpaceKind};

pub struct RegisterView {
    /// The Value column's format for every location, per dialect (by name), where the user
    /// chose one; in a dialect not listed each location shows in its own reading (DL205 words
    /// in BCD, a TML `fixed` in Q16.16, an OpenNet D word by its data type).
    pub every: BTreeMap<String, Format>,
    /// The dialect on show: whose entry of `every` applies.
    pub dialect: &'static str,
    /// Formats chosen for single locations (right-click a row).
    pub overrides: BTreeMap<Loc, Format>,
    pub only_used: bool,
    pub selected: Option<Loc>,
    pub edit_text: String,
    pub edit_error: Option<String>,
    /// The value `edit_text` was last filled from: when the location changes (a step, a step
    /// back, a click on the plot) the field follows, unless the user is typing in it.
    edit_shown: Option<u64>,
    /// The format `edit_text` was filled in: a new format refills it.
    edit_format: Option<Format>,
}

/// The format list's entry for "each location in its own reading".
pub const OWN_READING: &str = "each its own";

impl RegisterView {
    pub fn new(prefs: &Prefs) -> Self {
        RegisterView {
            every: prefs.register_formats.clone(),
            dialect: "",
            overrides: BTreeMap::new(),
            only_used: prefs.only_used_registers,
            selected: None,
            edit_text: String::new(),
            edit_error: None,
            edit_shown: None,
            edit_format: None,
        }
    }

    /// The format chosen for every location of the dialect on show, if one was.
    pub fn column(&self) -> Option<Format> {
        self.every.get(self.dialect).copied()
    }

    pub fn set_column(&mut self, format: Option<Format>) {
        match format {
            Some(f) => self.every.insert(self.dialect.to_string(), f),
            None => self.every.remove(self.dialect),
        };
    }

    /// The format a location is shown in: its own choice, else the one chosen for every
    /// location, else its dialect's reading.
    pub fn format_of(&self, loc: Loc, info: &LocInfo) -> Format {
        self.overrides
            .get(&loc)
            .copied()
            .or(self.column())
            .unwrap_or_else(|| info.reading())
    }

    pub fn select(&mut self, loc: Loc, _m: &dyn MachineView) {
        if self.selected != Some(loc) {
            self.selected = Some(loc);
            // The bit grid fills the field in the location's format on its next frame.
            self.edit_shown = None;
            self.edit_error = None;
        }
    }
}

/// Locations shown in the table: those the program mentions (plus the dedicated ones that have
/// names) or every location of the data spaces.
pub fn visible_locations(m: &dyn MachineView, only_used: bool) -> Vec<Loc> {
    let spaces = m.spaces();
    let data: Vec<u8> = spaces
        .iter()
        .enumerate()
        .filter(|(_, s)| s.kind == SpaceKind::Registers)
        .map(|(i, _)| i as u8)
        .collect();
    if !only_used {
        return data
            .iter()
            .flat_map(|&s| (0..spaces[usize::from(s)].len).map(move |i| Loc::new(s, i)))
            .collect();
    }
    let named = data.iter().flat_map(|&s| {
        // Dedicated locations (those with an alias) are always worth seeing; scanning is
        // bounded by the small spaces that have them.
        let len = spaces[usize::from(s)].len.min(4096);
        (0..len)
            .map(move |i| Loc::new(s, i))
            .filter(|&loc| m.info(loc).is_some_and(|i| i.alias.is_some()))
    });
    let mut locs: Vec<Loc> = named
        .chain(m.used())
        .chain(m.program_names().into_iter().map(|(_, l)| l))
        .filter(|l| data.contains(&l.space))
        .collect();
    locs.sort_unstable();
    locs.dedup();
    locs
}

pub fn show(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut RegisterView,
    out: &mut Vec<Command>,
) {
    ui.horizontal_wrapped(|ui| {
        view.dialect = debugger.dialect().name;
        let mut column = view.column();
        egui::ComboBox::new("register_format", "Format")
            .selected_text(column.map_or(OWN_READING, Format::name))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut column, None, OWN_READING)
                    .on_hover_text(
                        "Each location in its dialect's reading: DL205 words in BCD, a TML \
                         fixed in Q16.16, an OpenNet D word by its data type",
                    );
                for f in Format::ALL {
                    ui.selectable_value(&mut column, Some(f), f.name());
                }
            });
        if column != view.column() {
            view.set_column(column);
        }
        ui.checkbox(&mut view.only_used, "Only what this program uses");
    });
    ui.separator();
    // The table fits its columns to the panel (leaving out Binary when narrow) and scrolls
    // its rows itself, with its scroll bar in view.
    table(ui, debugger, view, out);
}

/// The Bits panel: flag words as named bits, then the selected location bit by bit.
pub fn show_bits(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut RegisterView,
    out: &mut Vec<Command>,
) {
    egui::ScrollArea::vertical()
        .id_salt("bits_scroll")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            flags(ui, debugger, out);
            ui.separator();
            match view.selected {
                Some(loc) => bit_grid(ui, debugger, view, loc, out),
                None => {
                    ui.label(
                        RichText::new("Click a row of Registers to see and set its bits here.")
                            .color(palette(ui.visuals().dark_mode).dim),
                    );
                }
            }
        });
}

/// Flag words as rows of named-bit chips; single flag relays as one row of chips.
fn flags(ui: &mut egui::Ui, debugger: &Debugger, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    let m = debugger.machine();
    for (s, space) in m.spaces().iter().enumerate() {
        if space.kind != SpaceKind::Flags {
            continue;
        }
        let locs = (0..space.len).map(|i| Loc::new(s as u8, i));
        // Before the first scan the PLC is not running: the relays its scan drives are neither
        // on nor off yet (issue #22 item 16).
        let not_started = m.pos().tick == 0 && m.pos().step == 0;
        let mut chip =
            |ui: &mut egui::Ui, loc: Loc, bit: u8, name: &str, tip: String, label: String| {
                if not_started && m.as_plc().is_some_and(|plc| plc.driven_by_scan(loc)) {
                    let text = RichText::new(name).size(12.0).color(p.dim);
                    let r = ui.add_enabled(
                        false,
                        egui::Button::new(text)
                            .fill(egui::Color32::TRANSPARENT)
                            .min_size(Vec2::ZERO),
                    );
                    r.widget_info(|| {
                        egui::WidgetInfo::labeled(
                            egui::Role::Label,
                            false,
                            format!("{label} not driven before the first scan"),
                        )
                    });
                    r.on_disabled_hover_text(format!(
                        "{tip}: not driven yet, the PLC has not started its first scan"
                    ));
                    return;
                }
                let on = m.read(loc) >> bit & 1 == 1;
                // Readable at any window size (`small` was ~8 px at 1920×1080).
                let text = RichText::new(name).size(12.0).color(if on {
                    egui::Color32::WHITE
                } else {
                    p.dim
                });
                let button = egui::Button::new(text)
                    .fill(if on {
                        p.bit_on
                    } else {
                        p.bit_off.gamma_multiply(0.5)
                    })
                    .min_size(Vec2::ZERO);
                let r = ui.add(button);
                r.widget_info(|| {
                    egui::WidgetInfo::selected(egui::Role::CheckBox, true, on, &label)
                });
                let r = r.on_hover_text(format!(
                    "{tip} ({}) — click to flip",
                    if on { "set" } else { "clear" }
                ));
                if r.clicked() {
                    out.push(Command::Debug(Action::SetBit(loc, bit, !on)));
                }
            };
        let words: Vec<(Loc, LocInfo)> = locs
            .filter_map(|loc| m.info(loc).map(|i| (loc, i)))
            .collect();
        let singles: Vec<&(Loc, LocInfo)> = words.iter().filter(|(_, i)| i.width == 1).collect();
        for (loc, info) in words.iter().filter(|(_, i)| i.width > 1) {
            ui.horizontal_wrapped(|ui| {
                ui.spacing_mut().item_spacing = vec2(3.0, 3.0);
                let raw = m.read(*loc);
                ui.add_sized(
                    [34.0, 18.0],
                    egui::Label::new(RichText::new(&info.name).strong()),
                )
                .on_hover_text(format!(
                    "{} = {} = {}",
                    info.name,
                    value::hex(raw, info.width),
                    value::binary(raw, info.width)
                ));
                for bit in info.bits {
                    chip(
                        ui,
                        *loc,
                        bit.bit,
                        bit.name,
                        format!("bit {}: {}", bit.bit, bit.description),
                        format!("{} {}", info.name, bit.name),
                    );
                }
            });
        }
        if !singles.is_empty() {
            ui.horizontal_wrapped(|ui| {
                ui.spacing_mut().item_spacing = vec2(3.0, 3.0);
                ui.add_sized(
                    [34.0, 18.0],
                    egui::Label::new(RichText::new(space.title).strong()),
                );
                for (loc, info) in singles {
                    chip(
                        ui,
                        *loc,
                        0,
                        &info.name,
                        format!("{}: {}", info.name, info.description),
                        info.name.clone(),
                    );
                }
            });
        }
    }
}

fn bit_grid(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut RegisterView,
    loc: Loc,
    out: &mut Vec<Command>,
) {
    let p = palette(ui.visuals().dark_mode);
    let m = debugger.machine();
    let Some(info) = m.info(loc) else {
        view.selected = None;
        return;
    };
    let raw = m.read(loc);
    let width = info.width;
    view.dialect = debugger.dialect().name;
    let format = view.format_of(loc, &info);
    let field = egui::Id::unique("location_value_field");
    let typing = ui.memory(|m| m.has_focus(field));
    let format_changed = view.edit_format != Some(format);
    if format_changed || !typing && view.edit_error.is_none() && view.edit_shown != Some(raw) {
        // The value changed under the field (or it was just selected, or shown in another
        // format): show the current one, so Set never writes a stale value back.
        view.edit_text = editable_text(raw, width, format);
        view.edit_shown = Some(raw);
        view.edit_format = Some(format);
        view.edit_error = None;
    }
    ui.horizontal(|ui| {
        ui.heading(&info.name)
            .on_hover_text("Right-click: who wrote it, break on it, watch it")
            .context_menu(|ui| super::breakpoints::location_menu(ui, m, &info.name, loc, out));
        if let Some(alias) = info.alias {
            ui.label(RichText::new(alias).strong());
        }
        if let Some(on) = m.forced(loc) {
            ui.label(
                RichText::new(if on { "FORCED ON" } else { "FORCED OFF" })
                    .strong()
                    .color(egui::Color32::from_rgb(230, 120, 20)),
            )
            .on_hover_text(
                "It holds this level whatever the program writes: release it to change it",
            );
        }
        for (name, _) in m
            .program_names()
            .iter()
            .filter(|(n, l)| *l == loc && *n != info.name)
        {
            ui.label(RichText::new(name).italics());
        }
        ui.label(RichText::new(info.description).color(p.dim));
        if ui
            .small_button("Deselect")
            .on_hover_text("Show no location here")
            .clicked()
        {
            view.selected = None;
        }
    });
    let cell = vec2(14.0, 18.0);
    let nibble_gap = 4.0;
    let words = u32::from(width).div_ceil(16);
    // A fixed 16.16 (its dialect reads it as Q16.16): the binary point sits between bits 16
    // and 15, i.e. between the two rows.
    // A SilverLode register read as Q16.16 too.
    let fixed_point = (info.format == Some(Format::Q16) || format == Format::Q16) && width == 32;
    let bcd = format == Format::Bcd;
    // One row per 16-bit word, the most significant first.
    for word in (0..words).rev() {
        let low = word * 16;
        let high = (low + 15).min(u32::from(width) - 1);
        if fixed_point && word == 0 {
            ui.horizontal(|ui| {
                ui.add_space(64.0);
                ui.label(
                    RichText::new(format!(
                        "● binary point: {} (exactly)",
                        value::q16_exact(sign_extend(raw, 32))
                    ))
                    .monospace()
                    .color(p.written),
                );
            });
        }
        let row_name = match (fixed_point, word) {
            (true, 1) => "integer 31–16".to_string(),
            (true, _) => "fraction 15–0".to_string(),
            _ => format!("bits {high}–{low}"),
        };
        ui.horizontal(|ui| {
            ui.spacing_mut().item_spacing.x = 0.0;
            ui.spacing_mut().button_padding = vec2(0.0, 0.0);
            ui.add_sized(
                [64.0, cell.y],
                egui::Label::new(RichText::new(row_name).small().color(p.dim)),
            );
            for bit in (low..=high).rev() {
                let on = raw >> bit & 1 == 1;
                let button = egui::Button::new(
                    RichText::new(if on { "1" } else { "0" })
                        .monospace()
                        .color(if on { egui::Color32::WHITE } else { p.dim }),
                )
                .fill(if on { p.bit_on } else { p.bit_off })
                .min_size(cell);
                let resp = ui.add_sized(cell, button);
                let label = format!("{} bit {bit}", info.name);
                resp.widget_info(|| {
                    egui::WidgetInfo::selected(egui::Role::CheckBox, true, on, &label)
                });
                let name = info.bits.iter().find(|b| u32::from(b.bit) == bit);
                let tip = match name {
                    Some(b) => format!("bit {bit} {} = {} — click to flip", b.name, u8::from(on)),
                    None => format!(
                        "{} — click to flip",
                        super::bitrows::bit_tooltip(bit as u8, on, fixed_point.then_some(16))
                    ),
                };
                if resp.on_hover_text(tip).clicked() {
                    out.push(Command::Debug(Action::ToggleBit(loc, bit as u8)));
                    view.edit_error = None;
                }
                if bit % 4 == 0 && bit != low {
                    ui.add_space(nibble_gap);
                }
            }
        });
        // Under the bits, tight against them: their numbers (every fourth), or a BCD word's
        // digits centred under their nibbles.
        ui.add_space(-ui.spacing().item_spacing.y);
        let strip_width = 64.0 + 16.0 * cell.x + 3.0 * nibble_gap;
        let (strip, _) = ui.allocate_exact_size(vec2(strip_width, 9.0), egui::Sense::hover());
        let painter = ui.painter_at(strip);
        let small = egui::FontId::monospace(8.5);
        if bcd {
            painter.text(
                egui::pos2(strip.left(), strip.center().y),
                egui::Align2::LEFT_CENTER,
                "BCD digits",
                small.clone(),
                p.dim,
            );
        }
        let mut x = strip.left() + 64.0;
        for bit in (low..=high).rev() {
            let (text, colour, at) = if bcd {
                let digit = raw >> (bit / 4 * 4) & 0xF;
                let colour = if digit <= 9 { p.written } else { p.error };
                (
                    (bit % 4 == 2).then(|| format!("{digit:X}")),
                    colour,
                    x + cell.x,
                )
            } else {
                (
                    (bit % 4 == 0 || bit == high).then(|| bit.to_string()),
                    p.dim,
                    x + cell.x / 2.0,
                )
            };
            if let Some(text) = text {
                painter.text(
                    egui::pos2(at, strip.center().y),
                    egui::Align2::CENTER_CENTER,
                    text,
                    small.clone(),
                    colour,
                );
            }
            x += cell.x;
            if bit % 4 == 0 && bit != low {
                x += nibble_gap;
            }
        }
    }
    if bcd && !value::is_bcd(raw) {
        ui.label(
            RichText::new("A nibble above 9 (red) is not a BCD digit: this is not a BCD number")
                .color(p.error),
        );
    }
    egui::Grid::new("bit_readouts")
        .num_columns(4)
        .spacing([14.0, 2.0])
        .show(ui, |ui| {
            let mut cells = vec![
                ("signed", Format::Signed.show(raw, width)),
                ("unsigned", Format::Unsigned.show(raw, width)),
                ("hex", Format::Hex.show(raw, width)),
                ("BCD", Format::Bcd.show(raw, width)),
            ];
            if width >= 17 {
                cells.push(("Q16.16", Format::Q16.show(raw, width)));
                cells.push(("octal", Format::Octal.show(raw, width)));
            }
            if width > 16 {
                for word in (0..u32::from(width).div_ceil(16)).rev() {
                    let w = raw >> (word * 16) & 0xFFFF;
                    let name = match (word, width) {
                        (1, 32) => "HI word".to_string(),
                        (0, 32) => "LO word".to_string(),
                        _ => format!("word {word}"),
                    };
                    cells.push((
                        "",
                        format!("{name}: 0x{w:04X} = {w} = {}", sign_extend(w, 16)),
                    ));
                }
            }
            for pair in cells.chunks(2) {
                for (label, text) in pair {
                    ui.label(*label);
                    ui.monospace(text);
                }
                ui.end_row();
            }
        });
    ui.horizontal_wrapped(|ui| {
        let label = ui.label(format!("Value of {}", info.name));
        ui.label(RichText::new(format!("in {}", format.name())).color(p.dim));
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut view.edit_text)
                    .id(field)
                    .desired_width(150.0)
                    .hint_text(format!("in {}, or 0x2A, bcd(12), q16(1.5)", format.name())),
            )
            .labelled_by(label.id);
        if edit.changed() {
            view.edit_error = None;
        }
        let entered = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("Set").clicked() || entered {
            match value::parse_in(&view.edit_text, width, format) {
                Ok((v, _)) => {
                    out.push(Command::Debug(Action::SetValue(loc, v)));
                    view.edit_error = None;
                }
                Err(e) => view.edit_error = Some(e.to_string()),
            }
        }
    });
    // Say how the text will be read before Set, so a BCD field never stores binary unseen.
    let untouched = view.edit_text.trim() == editable_text(raw, width, format);
    let preview = match value::parse_in(&view.edit_text, width, format) {
        Ok((v, reading)) if !untouched => Some(format!(
            "Set stores {}: {}",
            value::hex(v, width),
            reading.describe()
        )),
        _ => None,
    };
    if let Some(error) = &view.edit_error {
        ui.label(RichText::new(format!("Not changed: {error}")).color(p.error));
    } else if let Some(text) = preview {
        ui.label(RichText::new(text).small().color(p.dim));
    }
}

/// `raw` as the value field shows it: in `format`, in a form [`value::parse_in`] reads back to
/// the same bits (a Q16.16 value with every digit, not the six shown in the table).
fn editable_text(raw: u64, width: u8, format: Format) -> String {
    match format {
        Format::Q16 if width <= 32 => value::q16_exact(sign_extend(raw, width)),
        Format::Bcd if !value::is_bcd(raw) => value::hex(raw, width),
        f => f.show(raw, width),
    }
}

fn table(ui: &mut egui::Ui, debugger: &Debugger, view: &mut RegisterView, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    let m = debugger.machine();
    let rows = visible_locations(m, view.only_used);
    let written = m.last_written();
    let names = m.program_names();
    let spaces = m.spaces();
    let row_height = ui.text_style_height(&egui::TextStyle::Monospace) + 4.0;
    // The Binary column is never narrower than its widest value: a narrow panel scrolls
    // sideways (with a scroll bar) instead of clipping bits.
    let mut widest_bits = 1u8;
    let mut last_space = None;
    for loc in &rows {
        if last_space != Some(loc.space) {
            last_space = Some(loc.space);
            if let Some(info) = m.info(*loc) {
                widest_bits = widest_bits.max(info.width);
            }
        }
    }
    let binary_chars = value::binary(0, widest_bits).chars().count() as f32;
    let binary_width = binary_chars * 11.0 * 0.62 + 12.0;
    let mut clicked: Option<Loc> = None;
    // Cells are read, not selected: clicks go to the row (select) and its context menu.
    ui.style_mut().interaction.selectable_labels = false;
    let mut format_change: Option<(Loc, Option<Format>)> = None;
    // A panel too narrow for every column leaves out Binary (the Bits panel shows the selected
    // location's bits), then narrows Name, rather than cutting columns off at the edge.
    // What the columns need with their gaps and the scroll bar.
    let room = ui.available_width() - 40.0;
    let show_binary = room >= 64.0 + 84.0 + 88.0 + 120.0 + binary_width;
    let name_width = if room < 64.0 + 84.0 + 88.0 + 100.0 {
        56.0
    } else {
        84.0
    };
    let mut titles = vec!["Location", "Name", "Value", "Hex"];
    let mut builder = TableBuilder::new(ui)
        .id_salt("register_table")
        // The body fills the panel and no more (egui_extras' default stops at 800 px, which a
        // short panel clipped, scroll bar and all).
        .max_scroll_height(f32::INFINITY)
        .auto_shrink([false, false])
        .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysVisible)
        .striped(true)
        .sense(Sense::click())
        .cell_layout(egui::Layout::left_to_right(egui::Align::Center))
        .column(Column::initial(64.0).at_least(48.0).resizable(true))
        // Names too long for the column are elided (the label truncates), not clipped: a
        // clipped cell is a draw call of its own on every row.
        .column(Column::exact(name_width).clip(false))
        .column(Column::initial(88.0).at_least(60.0).resizable(true));
    if show_binary {
        builder = builder
            .column(Column::exact(120.0).clip(false))
            .column(Column::remainder().at_least(binary_width));
        titles.push("Binary");
    } else {
        builder = builder.column(Column::remainder().at_least(92.0));
    }
    builder
        .header(20.0, |mut header| {
            for title in titles {
                header.col(|ui| {
                    ui.strong(title);
                });
            }
        })
        .body(|body| {
            body.rows(row_height, rows.len(), |mut row| {
                let loc = rows[row.index()];
                let Some(info) = m.info(loc) else {
                    return;
                };
                let raw = m.read(loc);
                let fresh = written.contains(&loc);
                let colour = if fresh { p.written } else { p.text };
                let format = view.format_of(loc, &info);
                row.set_selected(view.selected == Some(loc));
                // Each storage space is a group of its own (TML's variables apart from its
                // predefined data): a line above its first row, its title in the Name column.
                let index = row.index();
                let space_title = (index > 0 && rows[index - 1].space != loc.space)
                    .then(|| spaces.get(usize::from(loc.space)).map(|s| s.title))
                    .flatten();
                let group_line = |ui: &mut egui::Ui| {
                    if space_title.is_some() {
                        let r = ui.max_rect();
                        ui.painter()
                            .hline(r.x_range(), r.top(), Stroke::new(1.0, p.dim));
                    }
                };
                row.col(|ui| {
                    group_line(ui);
                    let mut text = RichText::new(&info.name).monospace().color(colour);
                    if fresh {
                        text = text.strong();
                    }
                    ui.label(text);
                });
                row.col(|ui| {
                    group_line(ui);
                    // A TML variable's location is its name already: no second copy.
                    let own = names
                        .iter()
                        .find(|(n, l)| *l == loc && *n != info.name)
                        .map(|(n, _)| n.as_str());
                    // A space's title on its first row is a group heading, not a name:
                    // set apart in italics. Readable size at any window size.
                    let text = match info.alias.or(own) {
                        Some(name) => RichText::new(name),
                        None => RichText::new(space_title.unwrap_or("")).italics(),
                    };
                    ui.add(egui::Label::new(text.size(11.5).color(p.dim)).truncate());
                });
                row.col(|ui| {
                    let mut shown = RichText::new(format.show(raw, info.width))
                        .monospace()
                        .color(colour);
                    if view.overrides.contains_key(&loc) {
                        shown = shown.italics();
                    }
                    ui.label(shown);
                    if let Some(on) = m.forced(loc) {
                        ui.label(
                            RichText::new(if on { "F1" } else { "F0" })
                                .strong()
                                .color(egui::Color32::from_rgb(230, 120, 20)),
                        )
                        .on_hover_text(format!(
                            "Forced {}: it holds whatever the program writes",
                            if on { "ON" } else { "OFF" }
                        ));
                    }
                });
                row.col(|ui| {
                    // Elided like a name when wider than its column (a 48-bit PREG beside the
                    // Binary column); hovering it shows it whole.
                    ui.add(
                        egui::Label::new(
                            RichText::new(value::hex(raw, info.width))
                                .monospace()
                                .color(colour),
                        )
                        .truncate(),
                    );
                });
                if show_binary {
                    row.col(|ui| {
                        ui.label(
                            RichText::new(value::binary(raw, info.width))
                                .monospace()
                                .size(11.0)
                                .color(colour),
                        );
                    });
                }
                let response = row.response();
                if response.clicked() {
                    clicked = Some(loc);
                }
                response.context_menu(|ui| {
                    ui.label(format!("Show {} as", info.name));
                    for f in Format::ALL {
                        if ui
                            .selectable_label(view.overrides.get(&loc) == Some(&f), f.name())
                            .clicked()
                        {
                            format_change = Some((loc, Some(f)));
                            ui.close();
                        }
                    }
                    if ui.button("Like the others").clicked() {
                        format_change = Some((loc, None));
                        ui.close();
                    }
                    ui.separator();
                    super::breakpoints::location_menu(ui, m, &info.name, loc, out);
                });
            });
        });
    if let Some(loc) = clicked {
        view.select(loc, m);
        // Its bit grid is in Bits: in front of the tabs beside it (a PLC's I/O board).
        out.push(Command::FocusPane(super::layout::Pane::Bits));
    }
    match format_change {
        Some((loc, Some(f))) => {
            view.overrides.insert(loc, f);
        }
        Some((loc, None)) => {
            view.overrides.remove(&loc);
        }
        None => {}
    }
}
