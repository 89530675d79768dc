//! SilverLode's own panel (compiled with the `gui` feature only): every queue the program
//! initialised, drawn as a ring of slots (a grid when a ring would be
//! unreadable), with head (H, outside the ring) and tail (T, inside) pointers, `len / size`,
//! FULL or EMPTY when they meet, the header words decoded bit by bit, and the slot the last
//! command touched.

use std::f32::consts::TAU;

use egui::{Align2, Color32, FontId, Pos2, Rect, RichText, Sense, Shape, Stroke, Vec2, pos2, vec2};

use super::SilverLode;
use super::view::{QueueAccess, QueueHeader, QueueView};
use crate::debugger::Debugger;
use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::{Palette, palette};

/// The queue rings, registered by SilverLode's dialect entry.
pub struct QueuePanel;

impl DialectPanel for QueuePanel {
    fn title(&self) -> &'static str {
        "Queues"
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        debugger
            .machine_as::<SilverLode>()
            .is_some_and(|m| !m.queues().is_empty())
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, height: f32, _: &mut Vec<Command>) {
        show(ui, debugger, height);
    }
}

/// SilverLode's panels, for the registry.
pub fn panels() -> Vec<Box<dyn DialectPanel>> {
    vec![Box::new(QueuePanel)]
}

/// Largest queue drawn as a ring; bigger ones become a grid.
pub const MAX_RING_SLOTS: usize = 12;

pub fn show(ui: &mut egui::Ui, debugger: &Debugger, height: f32) {
    let p = palette(ui.visuals().dark_mode);
    let Some(machine) = debugger.machine_as::<SilverLode>() else {
        return;
    };
    let queues = machine.queues();
    if queues.is_empty() {
        ui.horizontal(|ui| {
            ui.strong("Queues (0)");
            ui.label(
                RichText::new("none yet: CLD Q_INIT, res, base, size makes one.").color(p.dim),
            );
        });
        return;
    }
    ui.strong(format!("Queues ({})", queues.len()));
    let access = machine.last_queue_access();
    // One queue fits the panel whole, its ring shrunk so the header words show under it;
    // several scroll, each at full size.
    let ring_room = if queues.len() == 1 {
        height - QUEUE_TEXT_HEIGHT
    } else {
        f32::INFINITY
    };
    egui::ScrollArea::vertical()
        .id_salt("queues_scroll")
        .max_height((height - 24.0).max(60.0))
        .auto_shrink([false, false])
        .show(ui, |ui| {
            for q in &queues {
                let touched = access.as_ref().filter(|a| a.base == q.base);
                queue(ui, q, touched, &p, ring_room);
                ui.separator();
            }
        });
}

/// The title, the queue's two text lines and its header words: what the ring leaves room for.
const QUEUE_TEXT_HEIGHT: f32 = 80.0 + HEADER_WORDS_HEIGHT;

fn queue(
    ui: &mut egui::Ui,
    q: &QueueView,
    access: Option<&QueueAccess>,
    p: &Palette,
    ring_room: f32,
) {
    let name = format!("Queue R{}", q.base);
    let Some(h) = &q.header else {
        ui.label(
            RichText::new(format!("{name}: not a valid queue any more"))
                .strong()
                .color(p.error),
        );
        ui.label(
            RichText::new(
                "The program overwrote its header; queue commands on it fault with bad_queue.",
            )
            .color(p.dim),
        );
        header_words(ui, q, p);
        return;
    };
    ui.horizontal(|ui| {
        ui.strong(&name);
        let state = if h.len == h.size {
            " FULL"
        } else if h.len == 0 {
            " EMPTY"
        } else {
            ""
        };
        ui.label(format!("{} / {} used{state}", h.len, h.size));
        ui.label(
            RichText::new(format!(
                "slots R{}–R{}",
                h.first_slot_register,
                h.first_slot_register + h.size - 1
            ))
            .color(p.dim),
        );
    });
    if let Some(a) = access {
        let text = match (a.ok, a.slot) {
            (true, Some(slot)) => format!(
                "last: {} at slot {slot} (R{})",
                a.action,
                h.first_slot_register + slot
            ),
            (true, None) => format!("last: {}", a.action),
            (false, _) => format!(
                "last: {} FAILED ({})",
                a.action,
                a.failure.unwrap_or("error")
            ),
        };
        ui.label(RichText::new(text).color(if a.ok { p.written } else { p.error }));
    }
    let picture = |ui: &mut egui::Ui, ring_room: f32| {
        if h.size <= MAX_RING_SLOTS {
            ring(ui, &name, h, access, p, ring_room);
        } else {
            grid(ui, &name, h, access, p);
        }
    };
    // The header decode beside the picture when the panel is wide enough, so both show at
    // once; under it otherwise.
    let beside_ring = ui.available_width() - header_words_width(ui);
    if beside_ring >= 2.0 * MIN_RING_RADIUS + 44.0 {
        ui.horizontal_top(|ui| {
            ui.allocate_ui(vec2(beside_ring, 0.0), |ui| {
                picture(ui, ring_room + HEADER_WORDS_HEIGHT)
            });
            ui.vertical(|ui| header_words(ui, q, p));
        });
    } else {
        picture(ui, ring_room);
        header_words(ui, q, p);
    }
}

/// The ring's radius range, and the room the header words take.
const MAX_RING_RADIUS: f32 = 90.0;
const MIN_RING_RADIUS: f32 = 46.0;

/// The header words' width in this font: `R41`, `head = 65535` and 16 bits in four groups,
/// with the grid's spacing.
fn header_words_width(ui: &egui::Ui) -> f32 {
    let mono = egui::TextStyle::Monospace.resolve(ui.style());
    let small = FontId::monospace(11.0);
    let (wide, narrow) = ui.fonts_mut(|f| (f.glyph_width(&mono, '0'), f.glyph_width(&small, '0')));
    wide * (3.0 + 12.0) + narrow * 19.0 + 2.0 * 6.0 + 8.0
}
const HEADER_WORDS_HEIGHT: f32 = 100.0;

/// `R[base]` as size | len and `R[base+1]` as head | tail, in binary with the halves marked.
fn header_words(ui: &mut egui::Ui, q: &QueueView, p: &Palette) {
    let half = |w: u32| {
        let s = format!("{w:016b}");
        format!("{} {} {} {}", &s[0..4], &s[4..8], &s[8..12], &s[12..16])
    };
    let rows = [
        (q.base, q.raw[0], "size", "len"),
        (q.base + 1, q.raw[1], "head", "tail"),
    ];
    // One half-word per row (name, value, its 16 bits): narrow enough to sit beside the ring.
    egui::Grid::new(("queue_header", q.base))
        .num_columns(3)
        .spacing([6.0, 0.0])
        .show(ui, |ui| {
            for (reg, word, hi_name, lo_name) in rows {
                let halves = [(hi_name, word >> 16, p.label), (lo_name, word & 0xFFFF, p.number)];
                for (i, (name, value, colour)) in halves.into_iter().enumerate() {
                    let bits = if i == 0 { "31–16" } else { "15–0" };
                    ui.label(
                        RichText::new(if i == 0 { format!("R{reg}") } else { String::new() })
                            .monospace()
                            .strong(),
                    );
                    ui.label(
                        RichText::new(format!("{name} = {value}"))
                            .monospace()
                            .color(colour),
                    );
                    ui.label(RichText::new(half(value)).monospace().size(11.0).color(colour))
                        .on_hover_text(format!("R{reg} bits {bits}"));
                    ui.end_row();
                }
            }
        });
    ui.label(RichText::new("high half over low half").small().color(p.dim));
}

/// A value short enough for its slot; hovering shows it in full.
fn compact(v: i32) -> String {
    if v.unsigned_abs() < 100_000 {
        v.to_string()
    } else {
        format!("{:.1e}", f64::from(v))
    }
}

fn slot_colours(h: &QueueHeader, slot: usize, p: &Palette) -> (Color32, Color32) {
    if h.is_occupied(slot) {
        (p.bit_on.gamma_multiply(0.8), Color32::WHITE)
    } else {
        (p.bit_off.gamma_multiply(0.6), p.dim)
    }
}

fn slot_tooltip(h: &QueueHeader, slot: usize) -> String {
    let reg = h.first_slot_register + slot;
    let state = if h.is_occupied(slot) {
        "queued"
    } else {
        "free (stale value)"
    };
    let mut text = format!("slot {slot} = R{reg}: {} ({state})", h.slots[slot]);
    if slot == h.head {
        text.push_str("\nH: the next head push goes here");
    }
    if slot == h.tail {
        text.push_str("\nT: the next tail pop reads here");
    }
    text
}

/// Make a painted thing findable by tests and screen readers, with a tooltip.
fn accessible(
    ui: &mut egui::Ui,
    rect: Rect,
    id: impl std::hash::Hash + std::fmt::Debug,
    label: String,
    tooltip: String,
) {
    let r = ui.interact(rect, ui.scope_id().with(id), Sense::hover());
    r.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, &label));
    r.on_hover_text(tooltip);
}

fn ring(
    ui: &mut egui::Ui,
    name: &str,
    h: &QueueHeader,
    access: Option<&QueueAccess>,
    p: &Palette,
    height: f32,
) {
    // As big as the column allows (never drawn over its neighbour), 90 px at most.
    let room = ui.available_width().min(height);
    let outer = ((room - 44.0) / 2.0).clamp(MIN_RING_RADIUS, MAX_RING_RADIUS);
    let inner = outer * 5.0 / 9.0;
    let size = Vec2::splat(2.0 * outer + 44.0);
    let (rect, _) = ui.allocate_exact_size(size, Sense::hover());
    let c = rect.center();
    let n = h.size;
    let angle = |slot: f32| -TAU / 4.0 + TAU * slot / n as f32;
    let at = |a: f32, r: f32| c + vec2(a.cos(), a.sin()) * r;
    let painter = ui.painter().clone();
    let font = FontId::monospace(11.0);
    for slot in 0..n {
        let (a0, a1) = (angle(slot as f32), angle(slot as f32 + 1.0));
        let (fill, text_colour) = slot_colours(h, slot, p);
        // Convex pieces of at most ~6° make up the annular sector.
        let pieces = (((a1 - a0) / 0.1).ceil() as usize).max(1);
        for k in 0..pieces {
            let b0 = a0 + (a1 - a0) * k as f32 / pieces as f32;
            let b1 = a0 + (a1 - a0) * (k + 1) as f32 / pieces as f32;
            painter.add(Shape::convex_polygon(
                vec![at(b0, outer), at(b1, outer), at(b1, inner), at(b0, inner)],
                fill,
                Stroke::NONE,
            ));
        }
        painter.line_segment(
            [at(a0, inner), at(a0, outer)],
            Stroke::new(1.5, p.text.gamma_multiply(0.5)),
        );
        let mid = (a0 + a1) / 2.0;
        let centre = at(mid, (inner + outer) / 2.0);
        painter.text(
            centre,
            Align2::CENTER_CENTER,
            compact(h.slots[slot]),
            font.clone(),
            text_colour,
        );
        // A narrow band has room for the value only (the slot is in its tooltip): the number
        // over it read as part of the value.
        if outer - inner >= 28.0 {
            painter.text(
                at(mid, outer - 7.0),
                Align2::CENTER_CENTER,
                slot.to_string(),
                FontId::proportional(9.0),
                text_colour.gamma_multiply(0.7),
            );
        }
        if access.and_then(|a| a.slot) == Some(slot) {
            let colour = p.written;
            let pts: Vec<Pos2> = (0..=8)
                .map(|k| at(a0 + (a1 - a0) * k as f32 / 8.0, outer + 2.0))
                .collect();
            painter.add(Shape::line(pts, Stroke::new(3.0, colour)));
        }
        let label = format!(
            "{name} slot {slot} (R{}) = {}",
            h.first_slot_register + slot,
            h.slots[slot]
        );
        accessible(
            ui,
            Rect::from_center_size(centre, Vec2::splat(16.0)),
            ("slot", slot),
            label,
            slot_tooltip(h, slot),
        );
    }
    for r in [inner, outer] {
        painter.circle_stroke(c, r, Stroke::new(1.0, p.text.gamma_multiply(0.5)));
    }
    // H outside, pointing in; T inside, pointing out.
    let marker = |slot: usize, outside: bool, letter: &str, colour: Color32| {
        let a = angle(slot as f32 + 0.5);
        let (tip, base) = if outside {
            (outer + 3.0, outer + 14.0)
        } else {
            (inner - 2.0, inner - 10.0)
        };
        let dir = vec2(a.cos(), a.sin());
        let side = vec2(-dir.y, dir.x) * 5.0;
        let base_pt = c + dir * base;
        painter.add(Shape::convex_polygon(
            vec![c + dir * tip, base_pt + side, base_pt - side],
            colour,
            Stroke::NONE,
        ));
        let label_pos = c + dir * if outside { outer + 22.0 } else { inner - 17.0 };
        painter.text(
            label_pos,
            Align2::CENTER_CENTER,
            letter,
            FontId::proportional(13.0),
            colour,
        );
        label_pos
    };
    // In a small ring T's letter inside would land on "2/4" or "FULL": it goes outside too,
    // and one letter pair names the slot both point at.
    let tail_inside = inner - 17.0 >= 22.0;
    let together = !tail_inside && h.head == h.tail;
    let head_pos = marker(h.head, true, if together { "H T" } else { "H" }, p.mnemonic);
    let tail_pos = marker(
        h.tail,
        tail_inside,
        if together { "" } else { "T" },
        p.condition,
    );
    let (state, colour) = if h.len == h.size {
        ("FULL", p.error)
    } else if h.len == 0 {
        ("EMPTY", p.dim)
    } else {
        ("", p.text)
    };
    painter.text(
        c - vec2(0.0, 7.0),
        Align2::CENTER_CENTER,
        format!("{}/{}", h.len, h.size),
        FontId::proportional(13.0),
        p.text,
    );
    if !state.is_empty() {
        painter.text(
            c + vec2(0.0, 8.0),
            Align2::CENTER_CENTER,
            state,
            FontId::proportional(11.0),
            colour,
        );
    }
    accessible(
        ui,
        Rect::from_center_size(head_pos, Vec2::splat(14.0)),
        "head",
        format!("{name} head at slot {}", h.head),
        "H: where the next head push goes".into(),
    );
    accessible(
        ui,
        Rect::from_center_size(tail_pos, Vec2::splat(14.0)),
        "tail",
        format!("{name} tail at slot {}", h.tail),
        "T: where the next tail pop reads".into(),
    );
    accessible(
        ui,
        Rect::from_center_size(c, vec2(40.0, 30.0)),
        "state",
        format!("{name} {}/{} {state}", h.len, h.size)
            .trim_end()
            .to_string(),
        "used / size".into(),
    );
}

fn grid(ui: &mut egui::Ui, name: &str, h: &QueueHeader, access: Option<&QueueAccess>, p: &Palette) {
    let cell = vec2(46.0, 30.0);
    let per_row = ((ui.available_width() / cell.x).floor() as usize).clamp(4, 16);
    let gap = 14.0;
    let rows = h.size.div_ceil(per_row);
    let (rect, _) = ui.allocate_exact_size(
        vec2(per_row as f32 * cell.x, rows as f32 * (cell.y + gap) + gap),
        Sense::hover(),
    );
    let painter = ui.painter().clone();
    for slot in 0..h.size {
        let (row, col) = (slot / per_row, slot % per_row);
        let min = pos2(
            rect.left() + col as f32 * cell.x,
            rect.top() + gap + row as f32 * (cell.y + gap),
        );
        let r = Rect::from_min_size(min, cell - vec2(2.0, 0.0));
        let (fill, text_colour) = slot_colours(h, slot, p);
        painter.rect_filled(r, 3.0, fill);
        if access.and_then(|a| a.slot) == Some(slot) {
            painter.rect_stroke(
                r,
                3.0,
                Stroke::new(2.5, p.written),
                egui::StrokeKind::Outside,
            );
        }
        painter.text(
            r.center(),
            Align2::CENTER_CENTER,
            compact(h.slots[slot]),
            FontId::monospace(10.0),
            text_colour,
        );
        painter.text(
            r.left_bottom() + vec2(2.0, -1.0),
            Align2::LEFT_BOTTOM,
            slot.to_string(),
            FontId::proportional(8.0),
            p.dim,
        );
        let mut marks = Vec::new();
        if slot == h.head {
            marks.push(("H", p.mnemonic));
        }
        if slot == h.tail {
            marks.push(("T", p.condition));
        }
        for (i, (letter, colour)) in marks.iter().enumerate() {
            let pos = r.center_top() + vec2(i as f32 * 12.0 - (marks.len() - 1) as f32 * 6.0, -7.0);
            painter.text(
                pos,
                Align2::CENTER_CENTER,
                *letter,
                FontId::proportional(11.0),
                *colour,
            );
            let what = if *letter == "H" { "head" } else { "tail" };
            accessible(
                ui,
                Rect::from_center_size(pos, Vec2::splat(10.0)),
                (what, slot),
                format!("{name} {what} at slot {slot}"),
                format!("{what} pointer"),
            );
        }
        let label = format!(
            "{name} slot {slot} (R{}) = {}",
            h.first_slot_register + slot,
            h.slots[slot]
        );
        accessible(ui, r, ("slot", slot), label, slot_tooltip(h, slot));
    }
}
