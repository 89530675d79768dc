//! The I/O board of the scanned PLCs: a lamp for every bit the program uses, grouped as the
//! vendor groups them (DL205 X, Y, C, SP, T, CT, S; OpenNet I, Q, M, R, T, C and the special
//! relays the program reads), inputs switched by a click, any input, output or relay forced by
//! a right-click, and the list of forces with Release all.

use egui::{Align2, Color32, FontId, Rect, RichText, Sense, Stroke, vec2};
use servoscope_core::debugger::Action;

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::push_buttons::{is_push_button, push_button_item, switch_input};
use crate::ui::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::plc::ladder::Symbol;
use servoscope_core::machine::{Loc, MachineView, SpaceKind};

pub const TITLE: &str = "I/O board";

const LAMP: f32 = 44.0;
/// A lamp with a label beside it: wider, and a line taller for the label.
const LABELLED_WIDTH: f32 = 76.0;
const LABEL_LINE: f32 = 12.0;

#[derive(Default)]
pub struct IoBoard {
    /// Each bit's label (its nickname, else the comment of the line that drives or first reads
    /// it), for the timeline (generation) it was read from.
    labels: Option<(u64, std::collections::HashMap<Loc, String>)>,
}

/// Each bit's label: the program's documentation of it (a DirectSOFT nickname), else the
/// trailing comment of the first coil that drives it, else of the first contact that reads it.
fn labels(debugger: &Debugger) -> std::collections::HashMap<Loc, String> {
    let m = debugger.machine();
    let mut out = std::collections::HashMap::new();
    let Some(ladder) = servoscope_core::machine::plc::ladder::wiring_with_comments(
        m,
        debugger.source(),
        debugger.dialect().classify,
    ) else {
        return out;
    };
    let elements = || ladder.rungs.iter().flat_map(|r| r.elements.iter());
    let coils = elements().filter(|e| matches!(e.symbol, Symbol::Coil(_)));
    let contacts = elements().filter(|e| matches!(e.symbol, Symbol::Contact { .. }));
    for e in coils.chain(contacts) {
        if let Some(loc) = m.find(&e.operand)
            && !e.comment.is_empty()
        {
            out.entry(loc).or_insert_with(|| e.comment.clone());
        }
    }
    for loc in m.used() {
        if let Some(doc) = m.location_doc(loc) {
            out.insert(loc, doc);
        }
    }
    out
}

/// The bits of each group: (space title and name, its locations), in the machine's order.
fn groups(m: &dyn MachineView) -> Vec<(String, Vec<Loc>)> {
    let used = m.used();
    let named: Vec<String> = m
        .as_plc()
        .map(|plc| plc.wiring())
        .map(|l| {
            l.rungs
                .iter()
                .flat_map(|r| r.elements.iter().map(|e| e.operand.to_ascii_uppercase()))
                .collect()
        })
        .unwrap_or_default();
    let spaces = m.spaces();
    let mut out: Vec<(String, Vec<Loc>)> = Vec::new();
    for (s, space) in spaces.iter().enumerate() {
        let mut locs: Vec<Loc> = used
            .iter()
            .copied()
            .filter(|l| usize::from(l.space) == s)
            .filter(|&l| m.info(l).is_some_and(|i| i.width == 1))
            // Status relays: only those the program reads.
            .filter(|&l| {
                space.kind != SpaceKind::Flags
                    || m.info(l)
                        .is_some_and(|i| named.contains(&i.name.to_ascii_uppercase()))
            })
            .collect();
        locs.sort();
        locs.dedup();
        if !locs.is_empty() {
            // "Inputs (X)"; a space whose name is a word is titled by its title alone.
            let title = if space.name.len() <= 3 {
                format!("{} ({})", space.title, space.name)
            } else {
                space.title.to_string()
            };
            out.push((title, locs));
        }
    }
    out
}

impl DialectPanel for IoBoard {
    fn title(&self) -> &'static str {
        TITLE
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        debugger.machine().is_plc()
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, out: &mut Vec<Command>) {
        let m = debugger.machine();
        let p = palette(ui.visuals().dark_mode);
        let forced_colour = Color32::from_rgb(230, 120, 20);
        let forces = m.forces();
        // One line that scrolls sideways: forcing never moves the lamps under the pointer.
        egui::ScrollArea::horizontal()
            .id_salt("io_forces")
            .auto_shrink([false, true])
            // No bar that comes and goes: the lamps below never move (the wheel scrolls it).
            .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysHidden)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.label(RichText::new(format!("Forces: {}", forces.len())).strong());
                    if !forces.is_empty() && ui.button("Release all").clicked() {
                        out.push(Command::Debug(Action::ReleaseAllForces));
                    }
                    for &(loc, on) in &forces {
                        let name = m.info(loc).map_or_else(String::new, |i| i.name);
                        ui.label(
                            RichText::new(format!("{name} {}", if on { "ON" } else { "OFF" }))
                                .color(forced_colour),
                        );
                        if ui
                            .small_button(format!("Release {name}"))
                            .on_hover_text(format!("{name} follows the program again"))
                            .clicked()
                        {
                            out.push(Command::Debug(Action::Force(loc, None)));
                        }
                    }
                    if forces.is_empty() {
                        ui.label(
                            RichText::new("right-click an I/O or relay lamp to force it")
                                .color(p.dim),
                        );
                    }
                });
            });
        ui.separator();
        let generation = debugger.generation();
        if self.labels.as_ref().is_none_or(|(g, _)| *g != generation) {
            self.labels = Some((generation, labels(debugger)));
        }
        let labels = self.labels.as_ref().map(|(_, l)| l);
        lamps(ui, m, labels, &p, forced_colour, out);
    }
}

const GROUP_TITLE: f32 = 20.0;
const SPACING: f32 = 4.0;

/// The groups of lamps in a scrolled grid that draws only the rows in view (a program may use
/// thousands of relays).
fn lamps(
    ui: &mut egui::Ui,
    m: &dyn MachineView,
    labels: Option<&std::collections::HashMap<Loc, String>>,
    p: &crate::ui::theme::Palette,
    forced_colour: Color32,
    out: &mut Vec<Command>,
) {
    let groups = groups(m);
    // Labels make each lamp wider and a line taller.
    let labelled = labels.is_some_and(|l| !l.is_empty());
    let cell = if labelled {
        vec2(LABELLED_WIDTH, LAMP + LABEL_LINE)
    } else {
        vec2(LAMP, LAMP)
    };
    let inputs: Vec<bool> = m
        .spaces()
        .iter()
        .map(|s| s.kind == SpaceKind::Inputs)
        .collect();
    let forces = m.forces();
    egui::ScrollArea::vertical()
        .id_salt("io_board")
        .auto_shrink([false, false])
        .show_viewport(ui, |ui, viewport| {
            let width = ui.available_width().max(cell.x);
            let per_row = ((width + SPACING) / (cell.x + SPACING)).floor().max(1.0) as usize;
            let height: f32 = groups
                .iter()
                .map(|(_, locs)| {
                    GROUP_TITLE + locs.len().div_ceil(per_row) as f32 * (cell.y + SPACING) + SPACING
                })
                .sum();
            let (rect, _) = ui.allocate_exact_size(vec2(width, height), Sense::hover());
            let mut y = rect.min.y;
            let view = viewport.translate(rect.min.to_vec2());
            for (title, locs) in &groups {
                ui.painter().text(
                    egui::pos2(rect.min.x, y + 2.0),
                    Align2::LEFT_TOP,
                    title,
                    FontId::proportional(13.0),
                    p.text,
                );
                y += GROUP_TITLE;
                for (r, row) in locs.chunks(per_row).enumerate() {
                    let top = y + r as f32 * (cell.y + SPACING);
                    if top + cell.y < view.min.y || top > view.max.y {
                        continue;
                    }
                    for (k, &loc) in row.iter().enumerate() {
                        let x = rect.min.x + k as f32 * (cell.x + SPACING);
                        let at = Rect::from_min_size(egui::pos2(x, top), cell);
                        let input = inputs.get(usize::from(loc.space)).copied().unwrap_or(false);
                        let forced = forces.iter().find(|(l, _)| *l == loc).map(|&(_, on)| on);
                        let label = labels.and_then(|l| l.get(&loc)).map(String::as_str);
                        let lamp_at = Lamp {
                            loc,
                            rect: at,
                            input,
                            forced,
                            label,
                        };
                        lamp(ui, m, &lamp_at, p, forced_colour, out);
                    }
                }
                y += row_count(locs.len(), per_row) * (cell.y + SPACING) + SPACING;
            }
        });
}

fn row_count(n: usize, per_row: usize) -> f32 {
    n.div_ceil(per_row) as f32
}

/// One lamp: where, what it is, and the label beside it.
struct Lamp<'a> {
    loc: Loc,
    rect: Rect,
    input: bool,
    forced: Option<bool>,
    label: Option<&'a str>,
}

fn lamp(
    ui: &mut egui::Ui,
    m: &dyn MachineView,
    at: &Lamp<'_>,
    p: &crate::ui::theme::Palette,
    forced_colour: Color32,
    out: &mut Vec<Command>,
) {
    let Lamp {
        loc,
        input,
        forced,
        label,
        ..
    } = *at;
    let Some(info) = m.info(loc) else { return };
    let on = m.read(loc) != 0;
    let id = ui.scope_id().with(("io_lamp", loc.space, loc.index));
    let response = ui.interact(at.rect, id, Sense::click_and_drag());
    // The lamp itself is the top LAMP × LAMP of its cell, centred; the label goes under it.
    let rect = Rect::from_center_size(
        egui::pos2(at.rect.center().x, at.rect.top() + LAMP / 2.0),
        vec2(at.rect.width(), LAMP),
    );
    let painter = ui.painter();
    if let Some(label) = label {
        let fitted = fit_label(label, at.rect.width());
        painter.text(
            egui::pos2(rect.center().x, rect.bottom() + 1.0),
            Align2::CENTER_TOP,
            fitted,
            FontId::proportional(10.0),
            p.dim,
        );
    }
    let centre = rect.center() - vec2(0.0, 7.0);
    let fill = if on {
        Color32::from_rgb(60, 200, 90)
    } else {
        p.bit_off
    };
    painter.circle_filled(centre, 11.0, fill);
    let ring = match forced {
        Some(_) => Stroke::new(3.0, forced_colour),
        None => Stroke::new(1.0, p.dim),
    };
    painter.circle_stroke(centre, 11.0, ring);
    if forced.is_some() {
        painter.text(
            centre,
            Align2::CENTER_CENTER,
            "F",
            FontId::proportional(10.0),
            Color32::WHITE,
        );
    }
    painter.text(
        rect.center_bottom() - vec2(0.0, 2.0),
        Align2::CENTER_BOTTOM,
        &info.name,
        FontId::proportional(11.0),
        p.text,
    );
    if input {
        // A switch, not just a lamp.
        painter.rect_stroke(
            Rect::from_center_size(centre, vec2(28.0, 28.0)),
            4.0,
            Stroke::new(1.0, p.dim),
            egui::StrokeKind::Outside,
        );
    }
    let state = if on { "ON" } else { "OFF" };
    let force_text = match forced {
        Some(true) => " — forced ON",
        Some(false) => " — forced OFF",
        None => "",
    };
    let forceable = m.can_force(loc);
    let hint = match (input, forced.is_some(), forceable) {
        (true, true, _) => "release the force to switch it",
        (true, false, true) => "click to switch it, right-click to force it",
        (true, false, false) => "click to switch it",
        (false, _, true) => "click to show it; right-click to force it",
        (false, _, false) => "the CPU drives it: it cannot be forced",
    };
    let push = input && is_push_button(ui.ctx(), loc);
    let hint = if push && forced.is_none() {
        "a push button: on while you hold it down (right-click to make it a switch)"
    } else {
        hint
    };
    let accessible = match label {
        Some(l) => format!("{} lamp ({l})", info.name),
        None => format!("{} lamp", info.name),
    };
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, &accessible));
    let documented = label.map_or(String::new(), |l| format!(" — {l}"));
    let response = response.on_hover_text(format!(
        "{}{documented} is {state}{force_text}: {hint}",
        info.name
    ));
    // A forced input's switch is refused: a click does nothing (the hover says why).
    if input && forced.is_none() {
        switch_input(&response, loc, on, out);
    }
    if !input && response.clicked() {
        out.push(Command::SelectLocation(loc));
    }
    if forceable || input {
        response.context_menu(|ui| {
            if input {
                push_button_item(ui, loc);
            }
            if forceable {
                crate::ui::breakpoints::force_items(ui, &info.name, loc, forced, out);
            }
        });
    }
}

/// `label` cut to what `width` points hold at the label's size, with "…" when cut.
fn fit_label(label: &str, width: f32) -> String {
    // About 5.5 points a character at 10 points proportional.
    let most = ((width / 5.5).floor() as usize).max(3);
    if label.chars().count() <= most {
        label.to_string()
    } else {
        let cut: String = label.chars().take(most - 1).collect();
        format!("{cut}…")
    }
}
