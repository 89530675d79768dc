//! Draws [`BitRow`]s: each bit a cell numbered from the right, a binary point where the row has
//! one, kept bits highlighted and lost bits greyed; hovering a bit tells its number and weight
//! (a fraction bit's weight as 2^-k and its decimal value).

use egui::{Color32, RichText, Sense, Stroke, vec2};

use crate::ui::theme::Palette;
use servoscope_core::machine::bits::{BitRow, Breakdown};

/// Width of one bit cell and the extra gap after every fourth bit.
const CELL: egui::Vec2 = vec2(11.0, 16.0);
const NIBBLE_GAP: f32 = 3.0;
const POINT_GAP: f32 = 7.0;

/// The width a row of `width` bits takes.
pub fn row_width(width: u8, point: Option<u8>) -> f32 {
    let w = f32::from(width);
    w * CELL.x + (w / 4.0).ceil() * NIBBLE_GAP + if point.is_some() { POINT_GAP } else { 0.0 }
}

/// What hovering bit `bit` of a row tells.
pub fn bit_tooltip(bit: u8, on: bool, point: Option<u8>) -> String {
    let state = if on { 1 } else { 0 };
    match point {
        Some(p) if bit < p => {
            let k = u32::from(p - bit);
            // 2^-k exactly: 5^k / 10^k.
            let digits = 5u128.pow(k).to_string();
            let weight = format!("0.{digits:0>width$}", width = k as usize);
            format!("bit {bit} = {state}: a fraction bit, weight 2^-{k} = {weight}")
        }
        Some(p) => format!("bit {bit} = {state}: weight 2^{}", bit - p),
        None => format!("bit {bit} = {state}: weight 2^{bit}"),
    }
}

/// Bits a line holds: a 64-bit row is drawn as two lines (63..32 over 31..0), so it reads in
/// a narrow panel.
const LINE_BITS: u8 = 32;

/// Draw `row` (its label above) and give each bit a hover text.
pub fn show(ui: &mut egui::Ui, row: &BitRow, p: &Palette) {
    ui.label(RichText::new(&row.label).monospace());
    let width = row.width.clamp(1, 64);
    let mut top = width;
    while top > 0 {
        let low = top.saturating_sub(LINE_BITS);
        line(ui, row, low, top - 1, p);
        top = low;
    }
}

/// Bits `high..=low` of `row` as one line of cells, numbers under them.
fn line(ui: &mut egui::Ui, row: &BitRow, low: u8, high: u8, p: &Palette) {
    let count = high - low + 1;
    // The point is drawn in the line that holds the bits on both sides of it.
    let point = row.point.filter(|&pt| pt > low && pt <= high);
    let size = vec2(row_width(count, point), CELL.y + 13.0);
    let (rect, response) = ui.allocate_exact_size(size, Sense::hover());
    // The panel's own painter: cells stay inside `rect` anyway, and a clip rectangle of their
    // own would make each line a separate draw call (a buffer upload each without a GPU).
    let painter = ui.painter();
    let font = egui::FontId::monospace(11.0);
    let small = egui::FontId::monospace(9.5);
    let x_of = |bit: u8| {
        let from_left = high - bit;
        let mut x =
            rect.left() + f32::from(from_left) * CELL.x + f32::from(from_left / 4) * NIBBLE_GAP;
        if point.is_some_and(|pt| bit < pt) {
            x += POINT_GAP;
        }
        x
    };
    let mut hovered = None;
    for bit in low..=high {
        let on = row.value >> bit & 1 == 1;
        let kept = row.keep.keeps(bit);
        let x = x_of(bit);
        let cell = egui::Rect::from_min_size(egui::pos2(x, rect.top()), CELL - vec2(1.0, 1.0));
        let (fill, text) = match (kept, on) {
            (true, true) => (p.bit_on, Color32::WHITE),
            (true, false) => (p.bit_off, p.text),
            (false, true) => (p.dim.gamma_multiply(0.5), p.dim),
            (false, false) => (Color32::TRANSPARENT, p.dim),
        };
        painter.rect_filled(cell, 2.0, fill);
        if !kept {
            painter.rect_stroke(cell, 2.0, Stroke::new(1.0, p.dim), egui::StrokeKind::Inside);
        }
        painter.text(
            cell.center(),
            egui::Align2::CENTER_CENTER,
            if on { "1" } else { "0" },
            font.clone(),
            text,
        );
        // Bit numbers under every fourth bit, the line's first, and the bits at the point.
        let numbered =
            bit % 4 == 0 || bit == high || point.is_some_and(|pt| bit + 1 == pt || bit == pt);
        if numbered {
            painter.text(
                egui::pos2(cell.center().x, cell.bottom() + 1.0),
                egui::Align2::CENTER_TOP,
                bit.to_string(),
                small.clone(),
                p.dim,
            );
        }
        if response
            .hover_pos()
            .is_some_and(|h| cell.expand(0.5).contains(h))
        {
            hovered = Some((bit, on));
        }
    }
    if let Some(pt) = point {
        let x = x_of(pt) + CELL.x + POINT_GAP / 2.0 - 0.5;
        painter.circle_filled(egui::pos2(x, rect.top() + CELL.y - 3.0), 2.0, p.written);
    }
    if let Some((bit, on)) = hovered {
        response.on_hover_text(bit_tooltip(bit, on, row.point));
    }
}

/// A whole breakdown: what and where, its rows, the notes and the real-number line.
/// `place` says where a line is ("line 12", or "main.tml:12" in a program of several files).
pub fn breakdown(
    ui: &mut egui::Ui,
    b: &Breakdown,
    when: &str,
    place: &dyn Fn(usize) -> String,
    p: &Palette,
) {
    ui.label(RichText::new(format!("{when}: {} — {}", place(b.line), b.command)).strong());
    // The arithmetic and what it loses first, the bits that show it after.
    if let Some(real) = &b.real {
        ui.label(RichText::new(real).monospace().color(p.written));
    }
    for note in &b.notes {
        ui.label(format!("• {note}"));
    }
    for row in &b.rows {
        show(ui, row, p);
    }
}
