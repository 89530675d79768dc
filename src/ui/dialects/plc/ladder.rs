//! The Ladder panel of the scanned PLCs: the program as rungs between two rails, drawn from the
//! core's [`Ladder`] model with the power flow at the current position (energised wires and
//! conducting contacts in the "on" colour), live values in the boxes, forced bits marked, and
//! inside a scan the rungs not evaluated yet drawn as such. Only the rungs on screen are drawn.
//!
//! Click an element: the program goes to its line and the registers to its operand. Click a
//! rung's left rail: a breakpoint on its first line. Hover: the value in every format.
//! Right-click a bit: force it, or release it.

use servoscope_core::debugger::Action;
use std::sync::Arc;

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, pos2, vec2};

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::plc::ladder::{
    self, CoilKind, EdgeKind, Element, Ladder, Rung, RungPower, RungState, Symbol,
};
use servoscope_core::machine::{LinePower, MachineView, value::Format};

pub const TITLE: &str = "Ladder";

const CELL_W: f32 = 84.0;
const CELL_H: f32 = 72.0;
const LEFT: f32 = 22.0;
const GAP: f32 = 12.0;
/// The drawing grows with a wide panel up to this factor (text and symbols with it).
const MAX_ZOOM: f32 = 1.6;
/// A narrow panel draws the ladder smaller, down to this, so a rung of four contacts keeps
/// its coil in view at 1366×768 (text stays readable at 0.7).
const MIN_ZOOM: f32 = 0.7;
/// Room right of the right rail for a rung's state ("not yet / this scan").
const NOTE_W: f32 = 76.0;
const COMMENT_H: f32 = 15.0;
/// Rung comment lines the panel shows.
const COMMENT_LINES: usize = 2;

/// The diagram of the program now in the debugger, with its comments, and where each rung
/// starts on the canvas.
struct Drawn {
    source: Arc<Ladder>,
    ladder: Ladder,
    /// Each rung's top at zoom 1, and the whole height.
    tops: Vec<f32>,
    height: f32,
}

/// The drawing's measures at a zoom.
#[derive(Clone, Copy)]
struct Geo {
    z: f32,
}

impl Geo {
    fn cell_w(self) -> f32 {
        CELL_W * self.z
    }
    fn cell_h(self) -> f32 {
        CELL_H * self.z
    }
    fn left(self) -> f32 {
        LEFT * self.z
    }
    fn comment_h(self) -> f32 {
        COMMENT_H * self.z
    }
    fn font(self, size: f32) -> FontId {
        FontId::proportional(size * self.z)
    }
    fn mono(self, size: f32) -> FontId {
        FontId::monospace(size * self.z)
    }
    /// Points at zoom 1 in this zoom.
    fn at(self, v: f32) -> f32 {
        v * self.z
    }
}

#[derive(Default)]
pub struct LadderPanel {
    drawn: Option<Drawn>,
    /// The line the view last followed: stepping onto another rung brings it into view.
    followed: Option<usize>,
}

/// A rung's height at zoom 1: its comment lines, its rows, the gap below.
fn rung_height(r: &Rung) -> f32 {
    let comments = r.comment.lines().take(COMMENT_LINES).count() as f32;
    comments * COMMENT_H + f32::from(r.rows) * CELL_H + GAP
}

impl LadderPanel {
    /// The diagram for `d`'s program, rebuilt when the program changed.
    fn drawn(&mut self, d: &Debugger) -> Option<&Drawn> {
        let m = d.machine();
        let source = m.as_plc()?.ladder();
        let stale = self
            .drawn
            .as_ref()
            .is_none_or(|dr| !Arc::ptr_eq(&dr.source, &source));
        if stale {
            let ladder = ladder::with_comments(m, d.source(), d.dialect().classify)?;
            let mut tops = Vec::with_capacity(ladder.rungs.len());
            let mut y = 4.0;
            for r in &ladder.rungs {
                tops.push(y);
                y += rung_height(r);
            }
            self.drawn = Some(Drawn {
                source,
                ladder,
                tops,
                height: y,
            });
        }
        self.drawn.as_ref()
    }
}

/// Colours of the drawing.
struct Ink {
    on: Color32,
    off: Color32,
    text: Color32,
    dim: Color32,
    comment: Color32,
    forced: Color32,
    current: Color32,
    breakpoint: Color32,
}

impl DialectPanel for LadderPanel {
    fn title(&self) -> &'static str {
        TITLE
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        debugger.machine().is_plc()
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, out: &mut Vec<Command>) {
        let p = palette(ui.visuals().dark_mode);
        let ink = Ink {
            on: Color32::from_rgb(40, 170, 70),
            off: p.dim,
            text: p.text,
            dim: p.dim,
            comment: p.comment,
            forced: Color32::from_rgb(230, 120, 20),
            current: p.current_line,
            breakpoint: p.breakpoint,
        };
        let pc = debugger.machine().pc_line();
        let followed = std::mem::replace(&mut self.followed, pc);
        let Some(drawn) = self.drawn(debugger) else {
            return;
        };
        let m = debugger.machine();
        if drawn.ladder.rungs.is_empty() {
            ui.label("This program has no rungs.");
            return;
        }
        // Per frame: the power of each line once, not per rung.
        let lines: std::collections::HashMap<usize, LinePower> = m
            .as_plc()
            .map(|p| p.line_power())
            .unwrap_or_default()
            .into_iter()
            .collect();
        let breakpoints = debugger.breakpoints();
        let now = m.pos();
        let cols = drawn.ladder.last_col + 1;
        let natural = LEFT + NOTE_W + f32::from(cols) * CELL_W;
        // A wide panel draws the ladder larger, up to MAX_ZOOM; a narrow one smaller, down to
        // MIN_ZOOM (then it scrolls sideways).
        let g = Geo {
            z: (ui.available_width() / natural).clamp(MIN_ZOOM, MAX_ZOOM),
        };
        let width = natural * g.z;
        // The rung holding the line about to run, when the position moved there.
        let follow = (pc != followed)
            .then(|| {
                let pc = pc?;
                drawn
                    .ladder
                    .rungs
                    .iter()
                    .position(|r| r.elements.iter().any(|e| e.line == pc))
            })
            .flatten();
        let shown = egui::ScrollArea::both()
            .id_salt("ladder_scroll")
            .auto_shrink([false, false])
            .show_viewport(ui, |ui, viewport| {
                let (rect, _) =
                    ui.allocate_exact_size(vec2(width, drawn.height * g.z), Sense::hover());
                let origin = rect.min;
                if let Some(k) = follow {
                    let top = drawn.tops[k] * g.z;
                    let bottom = drawn.tops.get(k + 1).copied().unwrap_or(drawn.height) * g.z;
                    let rung = Rect::from_min_max(
                        origin + vec2(0.0, top),
                        origin + vec2(width.min(ui.clip_rect().width()), bottom),
                    );
                    ui.scroll_to_rect(rung, None);
                }
                let first = drawn
                    .tops
                    .partition_point(|&t| t * g.z < viewport.min.y)
                    .saturating_sub(1);
                for (k, rung) in drawn.ladder.rungs.iter().enumerate().skip(first) {
                    let top = drawn.tops[k] * g.z;
                    if top > viewport.max.y {
                        break;
                    }
                    let first_line = rung.first_line();
                    let state = servoscope_core::machine::plc::ladder::rung_state(
                        first_line,
                        lines.get(&first_line).copied(),
                        now,
                        pc,
                    );
                    let power = RungPower::of(rung, state, |i| {
                        m.as_plc().is_some_and(|p| p.ladder_conducts(i))
                    });
                    let here = pc.is_some_and(|pc| rung.elements.iter().any(|e| e.line == pc));
                    let drawing = RungDrawing {
                        rung,
                        index: k,
                        power: &power,
                        origin: origin + vec2(0.0, top),
                        cols,
                        ink: &ink,
                        g,
                        here,
                        breakpoint: breakpoints.contains(&first_line),
                    };
                    drawing.show(ui, m, out);
                }
            });
        crate::ui::window_state::note_scroll_area(ui.ctx(), "ladder", shown.id);
    }
}

struct RungDrawing<'a> {
    rung: &'a Rung,
    index: usize,
    power: &'a RungPower,
    origin: Pos2,
    cols: u16,
    ink: &'a Ink,
    g: Geo,
    here: bool,
    breakpoint: bool,
}

impl RungDrawing<'_> {
    fn lit(&self, node: u32) -> bool {
        self.power.state == RungState::Done
            && self.power.node.get(node as usize).copied().unwrap_or(false)
    }

    fn wire(&self, lit: bool) -> Stroke {
        if lit {
            Stroke::new(self.g.at(3.0), self.ink.on)
        } else {
            Stroke::new(self.g.at(1.5), self.ink.off)
        }
    }

    fn show(&self, ui: &mut egui::Ui, m: &dyn MachineView, out: &mut Vec<Command>) {
        let painter = ui.painter().clone();
        let (g, rung) = (self.g, self.rung);
        let comments: Vec<&str> = rung.comment.lines().take(COMMENT_LINES).collect();
        let top = self.origin.y + comments.len() as f32 * g.comment_h();
        let height = f32::from(rung.rows) * g.cell_h();
        let rail_x = self.origin.x + g.left();
        let right = rail_x + f32::from(self.cols) * g.cell_w();
        // An oversized rung's note is wrapped to what the panel shows, not to the (narrow)
        // drawn rungs; its highlight follows the note.
        let wrap = (ui.clip_rect().right() - rail_x - g.at(8.0)).max(g.at(200.0));
        let body_right = if rung.oversized.is_some() {
            (right + g.left()).max(rail_x + wrap + g.at(4.0))
        } else {
            right + g.left()
        };
        let body = Rect::from_min_max(pos2(self.origin.x, top), pos2(body_right, top + height));
        if self.here {
            painter.rect_filled(body, 2.0, self.ink.current);
        }
        for (i, c) in comments.iter().enumerate() {
            painter.text(
                pos2(rail_x, self.origin.y + i as f32 * g.comment_h()),
                Align2::LEFT_TOP,
                ladder::fit(c, ((right - self.origin.x) / g.at(6.6)) as usize),
                g.mono(10.5),
                self.ink.comment,
            );
        }
        // Too large to draw: its note, which names its lines, in its place.
        if let Some(why) = &rung.oversized {
            let galley = painter.layout(why.clone(), g.mono(11.0), self.ink.comment, wrap);
            let at = pos2(rail_x, top + g.at(4.0));
            let shown = Rect::from_min_size(at, galley.size());
            painter.galley(at, galley, self.ink.comment);
            ui.interact(
                shown,
                ui.scope_id().with(("oversized", self.index)),
                egui::Sense::hover(),
            )
            .widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, why.as_str()));
            return;
        }
        let note = match self.power.state {
            RungState::Done => None,
            RungState::NotYet => Some("not yet\nthis scan"),
            RungState::NotRun => Some("not run\nthis scan"),
            RungState::MasterOff => Some("MC off:\noutputs off"),
        };
        if let Some(note) = note {
            // Right of the right rail, where no element stands.
            painter.text(
                pos2(right + g.at(6.0), top + g.at(4.0)),
                Align2::LEFT_TOP,
                note,
                g.font(10.0),
                self.ink.dim,
            );
        }
        // The rails; the left one is where a click sets a breakpoint.
        let rail = Rect::from_min_max(
            pos2(self.origin.x, top),
            pos2(rail_x + g.at(6.0), top + height),
        );
        let rail_id = ui.scope_id().with(("ladder_rail", self.index));
        let rail_response = ui.interact(rail, rail_id, Sense::click());
        let rail_label = format!("Ladder rung {} rail", self.index);
        rail_response
            .widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, &rail_label));
        let rail_response = rail_response.on_hover_text(format!(
            "Rung {} (line {}): click to toggle a breakpoint",
            self.index,
            rung.first_line()
        ));
        if rail_response.clicked() {
            out.push(Command::Debug(Action::ToggleBreakpoint(rung.first_line())));
        }
        painter.line_segment(
            [pos2(rail_x, top), pos2(rail_x, top + height)],
            self.wire(
                self.power.node.first().copied().unwrap_or(false)
                    && self.power.state == RungState::Done,
            ),
        );
        painter.line_segment(
            [pos2(right, top), pos2(right, top + height)],
            Stroke::new(g.at(1.5), self.ink.off),
        );
        if self.breakpoint {
            painter.circle_filled(
                pos2(self.origin.x + g.at(9.0), top + g.cell_h() / 2.0),
                g.at(6.0),
                self.ink.breakpoint,
            );
        }
        let x_of = |c: u16| rail_x + f32::from(c) * g.cell_w();
        let y_of = |r: u16| top + f32::from(r) * g.cell_h() + g.cell_h() / 2.0;
        for f in &rung.fillers {
            painter.line_segment(
                [
                    pos2(x_of(f.from_col), y_of(f.row)),
                    pos2(x_of(f.to_col), y_of(f.row)),
                ],
                self.wire(self.lit(f.node)),
            );
        }
        for v in &rung.verticals {
            painter.line_segment(
                [
                    pos2(x_of(v.col), y_of(v.top)),
                    pos2(x_of(v.col), y_of(v.bottom)),
                ],
                self.wire(self.lit(v.node)),
            );
        }
        for (i, e) in rung.elements.iter().enumerate() {
            let alone = e.from.is_empty();
            let col = if e.to.is_none() { self.cols - 1 } else { e.col };
            let x = x_of(col);
            let yc = y_of(e.row);
            if e.to.is_none() {
                for (&f, &row) in e.from.iter().zip(&e.leg_rows) {
                    let from = rung.node_col.get(f as usize).copied().unwrap_or(0);
                    if from < col {
                        painter.line_segment(
                            [pos2(x_of(from), y_of(row)), pos2(x, y_of(row))],
                            self.wire(self.lit(f)),
                        );
                    }
                }
            }
            // Contacts show their bits in any rung; coils and boxes their power only where
            // the rung has it.
            let contact = e.to.is_some();
            let shown = (contact || self.power.state == RungState::Done)
                && self.power.element.get(i).copied().unwrap_or(false);
            let cell = if alone {
                // An instruction standing alone (a stage, END): a band across the rung.
                Rect::from_min_max(
                    pos2(rail_x + g.at(6.0), yc - g.cell_h() / 2.0),
                    pos2(right - g.at(6.0), yc + g.cell_h() / 2.0),
                )
            } else {
                Rect::from_min_size(
                    pos2(x, yc - g.cell_h() / 2.0),
                    vec2(g.cell_w(), f32::from(e.height) * g.cell_h()),
                )
            };
            self.element(&painter, e, cell, shown, m);
            let id = ui.scope_id().with(("ladder_element", self.index, i));
            let response = ui.interact(cell.shrink(g.at(4.0)), id, Sense::click());
            let label = format!("Ladder {} line {}", e.operand, e.line);
            response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, &label));
            let forceable = m.find(&e.operand).filter(|&l| m.can_force(l));
            let response = response.on_hover_ui(|ui| hover(ui, e, m, forceable.is_some()));
            if response.clicked() {
                out.push(Command::ShowLine(e.line));
                if let Some(loc) = m.find(&e.operand) {
                    out.push(Command::SelectLocation(loc));
                }
            }
            if let Some(loc) = forceable {
                response.context_menu(|ui| {
                    crate::ui::breakpoints::force_items(ui, &e.operand, loc, m.forced(loc), out);
                });
            }
        }
        // A rung this scan has not evaluated (yet) is veiled, as the code view veils its lines:
        // its state reads even where the note beside the rail is scrolled out of view.
        if self.power.state != RungState::Done {
            let veil = ui.visuals().panel_fill.gamma_multiply(0.55);
            painter.rect_filled(body, 0.0, veil);
        }
    }

    fn element(
        &self,
        painter: &egui::Painter,
        e: &Element,
        cell: Rect,
        shown: bool,
        m: &dyn MachineView,
    ) {
        let (ink, g) = (self.ink, self.g);
        let yc = cell.min.y + g.cell_h() / 2.0;
        let mid = cell.center().x;
        let input_lit = e.from.first().is_some_and(|&f| self.lit(f));
        let out_lit = e.to.is_some_and(|t| self.lit(t));
        let symbol_stroke = if shown {
            Stroke::new(g.at(2.5), ink.on)
        } else {
            Stroke::new(g.at(1.5), ink.text)
        };
        let forced = m.find(&e.operand).and_then(|loc| m.forced(loc));
        match e.symbol {
            Symbol::Box if e.from.is_empty() => {
                // A band: the instruction and its comment, across the rung.
                painter.rect_stroke(
                    cell.shrink2(vec2(0.0, g.at(14.0))),
                    3.0,
                    Stroke::new(g.at(1.5), ink.dim),
                    egui::StrokeKind::Inside,
                );
                let text = if e.comment.is_empty() {
                    e.text.clone()
                } else {
                    format!("{}    {}", e.text, e.comment)
                };
                painter.text(
                    pos2(cell.min.x + g.at(10.0), yc),
                    Align2::LEFT_CENTER,
                    ladder::fit(&text, (cell.width() / g.at(7.0)) as usize),
                    g.font(12.0),
                    ink.text,
                );
            }
            Symbol::Box => {
                for (&f, &row) in e.from.iter().zip(&e.leg_rows) {
                    let y = cell.min.y + f32::from(row - e.row) * g.cell_h() + g.cell_h() / 2.0;
                    painter.line_segment(
                        [pos2(cell.min.x, y), pos2(cell.min.x + g.at(8.0), y)],
                        self.wire(self.lit(f)),
                    );
                }
                let body = cell.shrink2(vec2(g.at(8.0), g.at(6.0)));
                painter.rect_stroke(body, 3.0, symbol_stroke, egui::StrokeKind::Inside);
                let mut lines = vec![e.text.clone()];
                lines.extend(e.values.iter().map(|v| box_value(m, v)));
                for (j, l) in lines.iter().enumerate() {
                    // Long lines in a smaller size, so they stay inside the box.
                    let size = match l.chars().count() {
                        0..=9 => 11.0,
                        10..=12 => 9.5,
                        _ => 8.5,
                    };
                    painter.text(
                        pos2(mid, body.min.y + g.at(4.0) + j as f32 * g.at(14.0)),
                        Align2::CENTER_TOP,
                        ladder::fit(l, 15),
                        g.font(size),
                        if j == 0 { ink.text } else { ink.dim },
                    );
                }
                if !e.comment.is_empty() {
                    painter.text(
                        pos2(mid, body.max.y + g.at(1.0)),
                        Align2::CENTER_TOP,
                        ladder::fit(&e.comment, 13),
                        g.mono(9.0),
                        ink.comment,
                    );
                }
            }
            _ => {
                let (l, r) = (mid - g.at(10.0), mid + g.at(10.0));
                painter.line_segment([pos2(cell.min.x, yc), pos2(l, yc)], self.wire(input_lit));
                painter.line_segment(
                    [pos2(r, yc), pos2(cell.max.x, yc)],
                    self.wire(if e.to.is_some() { out_lit } else { input_lit }),
                );
                match e.symbol {
                    Symbol::Coil(kind) => {
                        // The coil's bit itself: filled while it is on (a forced or earlier
                        // rung may hold it on whatever power this rung gives it now).
                        let bit_on = m.find(&e.operand).is_some_and(|loc| m.read(loc) != 0);
                        if bit_on && kind != CoilKind::Jump {
                            painter.circle_filled(
                                pos2(mid, yc),
                                g.at(11.0),
                                ink.on.gamma_multiply(0.35),
                            );
                        }
                        arc(painter, pos2(mid, yc), g.at(13.0), true, symbol_stroke);
                        arc(painter, pos2(mid, yc), g.at(13.0), false, symbol_stroke);
                        let letters = match kind {
                            CoilKind::Out => "",
                            k => ladder::coil_letters(k),
                        };
                        painter.text(
                            pos2(mid, yc),
                            Align2::CENTER_CENTER,
                            letters,
                            g.font(if letters.len() > 2 { 8.0 } else { 10.0 }),
                            ink.text,
                        );
                    }
                    _ => {
                        if shown {
                            painter.rect_filled(
                                Rect::from_center_size(pos2(mid, yc), vec2(g.at(20.0), g.at(24.0))),
                                0.0,
                                ink.on.gamma_multiply(0.35),
                            );
                        }
                        for x in [l, r] {
                            painter.line_segment(
                                [pos2(x, yc - g.at(12.0)), pos2(x, yc + g.at(12.0))],
                                symbol_stroke,
                            );
                        }
                        let edge = match e.symbol {
                            Symbol::Contact { edge, .. } => edge,
                            Symbol::PowerEdge(edge) => Some(edge),
                            _ => None,
                        };
                        if let Some(edge) = edge {
                            // An arrow drawn, not a glyph: every font has lines.
                            let (tip, tail) = match edge {
                                EdgeKind::Rising => (yc - g.at(8.0), yc + g.at(8.0)),
                                EdgeKind::Falling => (yc + g.at(8.0), yc - g.at(8.0)),
                            };
                            let head = if tip < tail { g.at(4.0) } else { -g.at(4.0) };
                            let arrow = Stroke::new(g.at(1.5), ink.text);
                            painter.line_segment([pos2(mid, tail), pos2(mid, tip)], arrow);
                            for side in [-1.0, 1.0] {
                                painter.line_segment(
                                    [pos2(mid, tip), pos2(mid + side * g.at(4.0), tip + head)],
                                    arrow,
                                );
                            }
                        }
                        let mark = match e.symbol {
                            Symbol::Contact { closed: true, .. } => "/".to_string(),
                            Symbol::Invert => "NOT".to_string(),
                            Symbol::Compare => relation(&e.text),
                            _ => String::new(),
                        };
                        painter.text(
                            pos2(mid, yc),
                            Align2::CENTER_CENTER,
                            &mark,
                            g.font(if mark.chars().count() > 1 { 9.0 } else { 13.0 }),
                            ink.text,
                        );
                    }
                }
                // The name above the symbol and its line's comment above the name, as
                // DirectSOFT and WindLDR put nicknames and comments.
                painter.text(
                    pos2(mid, yc - g.at(12.0)),
                    Align2::CENTER_BOTTOM,
                    ladder::fit(&e.text, 13),
                    g.font(11.0),
                    ink.text,
                );
                if !e.comment.is_empty() {
                    painter.text(
                        pos2(mid, yc - g.at(24.0)),
                        Align2::CENTER_BOTTOM,
                        ladder::fit(&e.comment, 13),
                        g.mono(9.0),
                        ink.comment,
                    );
                }
            }
        }
        if let Some(on) = forced {
            // Below and right of the symbol, where no text stands.
            let badge = Rect::from_min_size(
                pos2(mid + g.at(14.0), yc + g.at(8.0)),
                vec2(g.at(20.0), g.at(13.0)),
            );
            painter.rect_filled(badge, 3.0, ink.forced);
            painter.text(
                badge.center(),
                Align2::CENTER_CENTER,
                if on { "F1" } else { "F0" },
                g.font(9.0),
                Color32::WHITE,
            );
        }
    }
}

/// The relation a compare contact tests, for its symbol: `≥` for `V0 >= K50` or `DC>=`.
fn relation(text: &str) -> String {
    for (written, shown) in [
        (">=", "≥"),
        ("<=", "≤"),
        ("<>", "≠"),
        ("≥", "≥"),
        ("≤", "≤"),
        ("≠", "≠"),
        ("<", "<"),
        (">", ">"),
        ("=", "="),
    ] {
        if text.contains(written) {
            return shown.to_string();
        }
    }
    "CMP".to_string()
}

/// A live value as a box line that fits its width: `TA1 = 29`, or for a long name its field
/// alone (`current = 30` under `TIM T0 30`), the value always whole.
fn box_value(m: &dyn MachineView, name: &str) -> String {
    let full = ladder::value_text(m, name);
    if full.chars().count() <= 13 {
        return full;
    }
    match (name.split_once('.'), full.split_once(" = ")) {
        (Some((_, field)), Some((_, value))) => format!("{field} = {value}"),
        _ => full,
    }
}

/// Half a coil: the left `(` or the right `)`.
fn arc(painter: &egui::Painter, c: Pos2, r: f32, left: bool, stroke: Stroke) {
    let points: Vec<Pos2> = (0..=12)
        .map(|k| {
            let a = -0.9 + 1.8 * k as f32 / 12.0;
            let (s, co) = a.sin_cos();
            let dx = if left { -r * co } else { r * co };
            pos2(c.x + dx, c.y + r * s)
        })
        .collect();
    painter.add(egui::Shape::line(points, stroke));
}

/// The hover card of an element: its line, and each value it names in its own reading first,
/// then every format.
fn hover(ui: &mut egui::Ui, e: &Element, m: &dyn MachineView, forceable: bool) {
    ui.label(format!("line {}: {}", e.line, e.text));
    if !e.comment.is_empty() {
        ui.label(egui::RichText::new(&e.comment).italics());
    }
    let names: Vec<&str> = std::iter::once(e.operand.as_str())
        .chain(e.values.iter().map(String::as_str))
        .collect();
    for name in names {
        let Some(loc) = m.find(name) else { continue };
        let Some(info) = m.info(loc) else { continue };
        let raw = m.read(loc);
        if info.width == 1 {
            let forced = match m.forced(loc) {
                Some(true) => " — forced ON",
                Some(false) => " — forced OFF",
                None => "",
            };
            ui.label(format!(
                "{} = {}{forced}",
                info.name,
                if raw != 0 { "ON" } else { "OFF" }
            ));
        } else {
            let own = info.reading();
            ui.label(format!(
                "{} = {} ({})",
                info.name,
                own.show(raw, info.width),
                own.name()
            ));
            for f in Format::ALL.into_iter().filter(|&f| f != own) {
                ui.label(
                    egui::RichText::new(format!("    {}: {}", f.name(), f.show(raw, info.width)))
                        .weak(),
                );
            }
        }
    }
    let hint = if forceable {
        "Click: its line and register · right-click: force it"
    } else {
        "Click: its line and register"
    };
    ui.label(egui::RichText::new(hint).weak());
}
