//! The Queues panel: every queue the program initialised, drawn as a ring of slots (a grid when a ring would be
//! unreadable), with head (H, outside the ring) and tail (T, inside) pointers, `len / size`,
//! FULL or EMPTY when they meet, the header words decoded bit by bit, and the slot the last
//! command touched.

use std::f32::consts::TAU;

use egui::{Align2, Color32, FontId, Pos2, Rect, RichText, Sense, Shape, Stroke, Vec2, pos2, vec2};

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::{Palette, palette};
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::view::{QueueAccess, QueueHeader, QueueView};

/// The queues, registered by SilverLode's dialect entry; each drawn as the program uses it
/// (a ring for a FIFO, a column for a stack) unless the user chose.
#[derive(Default)]
pub struct QueuePanel {
    /// Drawings the user chose, by queue base.
    chosen: std::collections::BTreeMap<usize, Drawing>,
}

/// How a queue is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drawing {
    Ring,
    /// A column, the top (the end pushed and popped) marked.
    Stack {
        top_at_head: bool,
    },
}

/// How the program uses the queue at `base`: pushed and popped at the same end only, it is a
/// stack (spec §5.3: Push Head + Pop Head is a LIFO); anything else is drawn as the ring.
pub fn usage(program: &servoscope_core::machine::silverlode::Program, base: usize) -> Drawing {
    use servoscope_core::machine::silverlode::program::{ExtOp, Instr};
    let (mut push_head, mut push_tail, mut pop_head, mut pop_tail) = (false, false, false, false);
    for instr in &program.instrs {
        let (Instr::Cld { op, reg1, .. } | Instr::Clx { op, reg1, .. }) = *instr else {
            continue;
        };
        if usize::from(reg1) != base {
            continue;
        }
        match op {
            ExtOp::QPushHead | ExtOp::QPushHeadErr => push_head = true,
            ExtOp::QPushTail | ExtOp::QPushTailErr => push_tail = true,
            ExtOp::QPopHead | ExtOp::QPopHeadErr => pop_head = true,
            ExtOp::QPopTail | ExtOp::QPopTailErr => pop_tail = true,
            _ => {}
        }
    }
    match (push_head, push_tail, pop_head, pop_tail) {
        (true, false, true, false) => Drawing::Stack { top_at_head: true },
        (false, true, false, true) => Drawing::Stack { top_at_head: false },
        _ => Drawing::Ring,
    }
}

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
        show(ui, debugger, height, &mut self.chosen);
    }
}

/// SilverLode's panels, for the registry.
/// Largest queue drawn as a ring; bigger ones become a grid.
pub const MAX_RING_SLOTS: usize = 12;

pub fn show(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    height: f32,
    chosen: &mut std::collections::BTreeMap<usize, Drawing>,
) {
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
                let by_use = usage(machine.program(), q.base);
                let drawing = chosen.get(&q.base).copied().unwrap_or(by_use);
                let mut switched = None;
                let mut switch = |ui: &mut egui::Ui| {
                    switched = drawing_switch(ui, drawing, by_use);
                };
                match (drawing, &q.header) {
                    (Drawing::Stack { top_at_head }, Some(h)) => {
                        let name = format!("Queue R{}", q.base);
                        stack(ui, &name, h, touched, top_at_head, &p, &mut switch);
                        header_words(ui, q, &p);
                    }
                    _ => queue(ui, q, touched, &p, ring_room, &mut switch),
                }
                if let Some(new) = switched {
                    chosen.insert(q.base, new);
                }
                ui.separator();
            }
        });
}

/// "as ring | as stack": the user's choice over the drawing the program's use suggests.
fn drawing_switch(ui: &mut egui::Ui, now: Drawing, by_use: Drawing) -> Option<Drawing> {
    let mut chosen = None;
    ui.scope(|ui| {
        let ring = ui
            .selectable_label(now == Drawing::Ring, "as ring")
            .on_hover_text(if now == by_use {
                "A FIFO: the slots in a circle with the head and tail pointers (as the program uses it)"
            } else {
                "A FIFO: the slots in a circle with the head and tail pointers"
            });
        if ring.clicked() {
            chosen = Some(Drawing::Ring);
        }
        // A stack's top is the end the program pushes and pops; the head when it does not say.
        let as_stack = match by_use {
            Drawing::Stack { .. } => by_use,
            Drawing::Ring => Drawing::Stack { top_at_head: true },
        };
        let stack = ui
            .selectable_label(matches!(now, Drawing::Stack { .. }), "as stack")
            .on_hover_text("A LIFO: the values in a column, the top (next pop) first");
        if stack.clicked() {
            chosen = Some(as_stack);
        }
    });
    chosen
}

/// `3 / 4 used`, with FULL or EMPTY when the pointers meet.
fn used_text(h: &QueueHeader) -> String {
    let state = if h.len == h.size {
        " FULL"
    } else if h.len == 0 {
        " EMPTY"
    } else {
        ""
    };
    format!("{} / {} used{state}", h.len, h.size)
}

/// What the last command did to this queue, and at which slot.
fn last_access(ui: &mut egui::Ui, h: &QueueHeader, access: Option<&QueueAccess>, p: &Palette) {
    let Some(a) = access else {
        return;
    };
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

/// A queue used as a stack: a column with the top (the newest value, the next pop) first, the
/// free slots above it, each value with its register.
fn stack(
    ui: &mut egui::Ui,
    name: &str,
    h: &QueueHeader,
    access: Option<&QueueAccess>,
    top_at_head: bool,
    p: &Palette,
    switch: &mut dyn FnMut(&mut egui::Ui),
) {
    let end = if top_at_head { "head" } else { "tail" };
    ui.horizontal_wrapped(|ui| {
        ui.strong(format!("{name} as a stack"));
        ui.label(used_text(h));
        ui.label(RichText::new(format!("top at the {end}")).color(p.dim));
        switch(ui);
    });
    last_access(ui, h, access, p);
    // Items run tail (oldest) to head (newest); the top is the newest end when pushing at the
    // head, the tail end otherwise.
    let mut order: Vec<usize> = (0..h.len).map(|i| (h.tail + i) % h.size).collect();
    if top_at_head {
        order.reverse();
    }
    let cell = vec2(110.0, 20.0);
    let free = h.size - h.len;
    let font = FontId::monospace(12.0);
    for row in 0..h.size {
        let (rect, _) = ui.allocate_exact_size(vec2(cell.x + 120.0, cell.y), Sense::hover());
        let slot_rect = Rect::from_min_size(rect.min, cell - vec2(0.0, 2.0));
        let painter = ui.painter();
        if row < free {
            painter.rect_stroke(
                slot_rect,
                2.0,
                Stroke::new(1.0, p.bit_off),
                egui::StrokeKind::Inside,
            );
            painter.text(
                slot_rect.center(),
                Align2::CENTER_CENTER,
                "free",
                font.clone(),
                p.dim,
            );
            continue;
        }
        let depth = row - free;
        let slot = order[depth];
        let value = h.slots[slot];
        let (fill, text) = slot_colours(h, slot, p);
        painter.rect_filled(slot_rect, 2.0, fill);
        painter.text(
            slot_rect.center(),
            Align2::CENTER_CENTER,
            value.to_string(),
            font.clone(),
            text,
        );
        let register = h.first_slot_register + slot;
        let note = if depth == 0 {
            format!("R{register}  ◀ top (next pop)")
        } else {
            format!("R{register}")
        };
        painter.text(
            pos2(slot_rect.right() + 6.0, slot_rect.center().y),
            Align2::LEFT_CENTER,
            &note,
            FontId::proportional(12.0),
            if depth == 0 { p.written } else { p.dim },
        );
        accessible(
            ui,
            slot_rect,
            (name, "stack", depth),
            format!("{name} stack depth {depth}: {value}"),
            format!("depth {depth} from the top: {}", slot_tooltip(h, slot)),
        );
    }
    if h.len == 0 {
        ui.label(RichText::new(format!("empty: a pop at the {end} fails")).color(p.dim));
    }
}

/// The title, the queue's two text lines and its header words: what the ring leaves room for.
const QUEUE_TEXT_HEIGHT: f32 = 80.0 + HEADER_WORDS_HEIGHT;

fn queue(
    ui: &mut egui::Ui,
    q: &QueueView,
    access: Option<&QueueAccess>,
    p: &Palette,
    ring_room: f32,
    switch: &mut dyn FnMut(&mut egui::Ui),
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
    ui.horizontal_wrapped(|ui| {
        ui.strong(&name);
        ui.label(used_text(h));
        ui.label(
            RichText::new(format!(
                "slots R{}–R{}",
                h.first_slot_register,
                h.first_slot_register + h.size - 1
            ))
            .color(p.dim),
        );
        switch(ui);
    });
    last_access(ui, h, access, p);
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
                let halves = [
                    (hi_name, word >> 16, p.label),
                    (lo_name, word & 0xFFFF, p.number),
                ];
                for (i, (name, value, colour)) in halves.into_iter().enumerate() {
                    let bits = if i == 0 { "31–16" } else { "15–0" };
                    ui.label(
                        RichText::new(if i == 0 {
                            format!("R{reg}")
                        } else {
                            String::new()
                        })
                        .monospace()
                        .strong(),
                    );
                    ui.label(
                        RichText::new(format!("{name} = {value}"))
                            .monospace()
                            .color(colour),
                    );
                    ui.label(
                        RichText::new(half(value))
                            .monospace()
                            .size(11.0)
                            .color(colour),
                    )
                    .on_hover_text(format!("R{reg} bits {bits}"));
                    ui.end_row();
                }
            }
        });
    ui.label(
        RichText::new("high half over low half")
            .small()
            .color(p.dim),
    );
}

/// A value short enough for its slot; hovering shows it in full.
/// A slot's value in the few characters a cell holds: exact below 100,000, else three
/// significant digits with k, M or G (`-2.15G` for -2147483648; the tooltip has every digit).
/// Scientific notation (`-2.1e9`) read as nonsense to the students it is for.
pub fn compact(v: i32) -> String {
    let magnitude = v.unsigned_abs();
    if magnitude < 100_000 {
        return v.to_string();
    }
    // 999,999 is 1.00M, not 1000k: a value that rounds up to 1000 takes the next unit.
    let (scale, suffix) = match magnitude {
        0..999_500 => (1e3, "k"),
        999_500..999_500_000 => (1e6, "M"),
        _ => (1e9, "G"),
    };
    let scaled = f64::from(magnitude) / scale;
    let digits = if scaled >= 100.0 {
        0
    } else if scaled >= 10.0 {
        1
    } else {
        2
    };
    let sign = if v < 0 { "-" } else { "" };
    format!("{sign}{scaled:.digits$}{suffix}")
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
        // over it read as part of the value, and up to a band of 40 points it printed on it.
        if outer - inner >= 40.0 {
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
        !tail_inside,
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
