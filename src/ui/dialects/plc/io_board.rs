//! The I/O board of the scanned PLCs: a lamp for every bit the program uses, grouped as the
//! vendor groups them (DL205 X, Y, C, SP, T, CT, S; OpenNet I, Q, M, R, T, C and the special
//! relays the program reads), inputs switched by a click, any input, output or relay forced by
//! a right-click, and the list of forces with Release all.

use egui::{Align2, Color32, FontId, Rect, RichText, Sense, Stroke, vec2};
use servoscope_core::debugger::Action;

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::{Loc, MachineView, SpaceKind};

pub const TITLE: &str = "I/O board";

const LAMP: f32 = 44.0;

#[derive(Default)]
pub struct IoBoard;

/// The bits of each group: (space title and name, its locations), in the machine's order.
fn groups(m: &dyn MachineView) -> Vec<(String, Vec<Loc>)> {
    let used = m.used();
    let named: Vec<String> = m
        .as_plc()
        .map(|plc| plc.ladder())
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
        lamps(ui, m, &p, forced_colour, out);
    }
}

const GROUP_TITLE: f32 = 20.0;
const SPACING: f32 = 4.0;

/// The groups of lamps in a scrolled grid that draws only the rows in view (a program may use
/// thousands of relays).
fn lamps(
    ui: &mut egui::Ui,
    m: &dyn MachineView,
    p: &crate::ui::theme::Palette,
    forced_colour: Color32,
    out: &mut Vec<Command>,
) {
    let groups = groups(m);
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
            let width = ui.available_width().max(LAMP);
            let per_row = ((width + SPACING) / (LAMP + SPACING)).floor().max(1.0) as usize;
            let height: f32 = groups
                .iter()
                .map(|(_, locs)| {
                    GROUP_TITLE + locs.len().div_ceil(per_row) as f32 * (LAMP + SPACING) + SPACING
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
                    let top = y + r as f32 * (LAMP + SPACING);
                    if top + LAMP < view.min.y || top > view.max.y {
                        continue;
                    }
                    for (k, &loc) in row.iter().enumerate() {
                        let x = rect.min.x + k as f32 * (LAMP + SPACING);
                        let cell = Rect::from_min_size(egui::pos2(x, top), vec2(LAMP, LAMP));
                        let input = inputs.get(usize::from(loc.space)).copied().unwrap_or(false);
                        let forced = forces.iter().find(|(l, _)| *l == loc).map(|&(_, on)| on);
                        lamp(ui, m, loc, cell, input, forced, p, forced_colour, out);
                    }
                }
                y += row_count(locs.len(), per_row) * (LAMP + SPACING) + SPACING;
            }
        });
}

fn row_count(n: usize, per_row: usize) -> f32 {
    n.div_ceil(per_row) as f32
}

#[allow(clippy::too_many_arguments)]
fn lamp(
    ui: &mut egui::Ui,
    m: &dyn MachineView,
    loc: Loc,
    rect: Rect,
    input: bool,
    forced: Option<bool>,
    p: &crate::ui::theme::Palette,
    forced_colour: Color32,
    out: &mut Vec<Command>,
) {
    let Some(info) = m.info(loc) else { return };
    let on = m.read(loc) != 0;
    let id = ui.scope_id().with(("io_lamp", loc.space, loc.index));
    let response = ui.interact(rect, id, Sense::click());
    let painter = ui.painter();
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
    let label = format!("{} lamp", info.name);
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, &label));
    let response = response.on_hover_text(format!("{} is {state}{force_text}: {hint}", info.name));
    // A forced input's switch is refused: a click does nothing (the hover says why).
    if input && forced.is_none() && response.clicked() {
        out.push(Command::Debug(Action::SetInput(loc, !on)));
    }
    if !input && response.clicked() {
        out.push(Command::SelectLocation(loc));
    }
    if forceable {
        response.context_menu(|ui| {
            crate::ui::breakpoints::force_items(ui, &info.name, loc, forced, out);
        });
    }
}
