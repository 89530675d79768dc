//! The program view for long programs: only the visible lines are laid out, each as one row
//! that holds its gutter (number, breakpoint, the arrow), its background and its coloured text,
//! so they can never drift apart, at any length and scroll position. Work per frame is
//! proportional to the rows on screen, not to the program (a 100,000-line program draws as
//! fast as a 20-line one). Editing such a program switches to the text editor on request.

use egui::text::LayoutJob;
use egui::{Id, Rect, RichText, Sense, Stroke, TextStyle, Vec2, pos2, vec2};
use servoscope_core::debugger::Action;

use super::Command;
use super::code::{CodeView, append_line, error_underlines};
use super::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::Diagnostic;

/// Where each line starts in the program text, rebuilt only when the text changes.
#[derive(Default)]
pub struct LineIndex {
    text: String,
    /// Byte offset of each line's start; one entry per line shown (a trailing newline opens an
    /// empty last line, as in an editor).
    starts: Vec<usize>,
    /// The longest line, in characters, for the horizontal extent.
    widest: usize,
    /// Lines of text (a trailing newline does not count one more).
    text_lines: usize,
}

impl LineIndex {
    pub fn update(&mut self, source: &str) {
        if self.text == source && !self.starts.is_empty() {
            return;
        }
        self.text = source.to_string();
        self.starts = std::iter::once(0)
            .chain(source.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        self.widest = source.lines().map(|l| l.chars().count()).max().unwrap_or(0);
        self.text_lines = source.lines().count();
    }

    /// Lines of text, as a person counts them.
    pub fn text_lines(&self) -> usize {
        self.text_lines
    }

    pub fn count(&self) -> usize {
        self.starts.len().max(1)
    }

    /// Line `n` (1-based) with its line ending.
    pub fn line(&self, n: usize) -> &str {
        let Some(&start) = self.starts.get(n.wrapping_sub(1)) else {
            return "";
        };
        let end = self.starts.get(n).copied().unwrap_or(self.text.len());
        &self.text[start..end]
    }
}

/// Diagnostics on `line`, from a list sorted by line.
fn on_line(diagnostics: &[Diagnostic], line: usize) -> &[Diagnostic] {
    let from = diagnostics.partition_point(|d| d.line < line);
    let to = diagnostics.partition_point(|d| d.line <= line);
    &diagnostics[from..to]
}

pub fn show(ui: &mut egui::Ui, debugger: &Debugger, view: &mut CodeView, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    view.lines.update(debugger.source());
    let font = TextStyle::Monospace.resolve(ui.style());
    let row_height = ui.fonts_mut(|f| f.row_height(&font)).ceil();
    let char_width = ui.fonts_mut(|f| f.glyph_width(&font, '0'));
    let count = view.lines.count();
    let digits = count.to_string().len().max(3);
    let gutter_width = char_width * (digits as f32 + 3.5);
    let text_width = char_width * (view.lines.widest as f32 + 2.0);
    let machine = debugger.machine();
    let pc_line = machine.pc_line().filter(|_| machine.run_state().is_live());
    let fault_line = machine.fault().map(|f| f.line);
    let diagnostics = debugger.diagnostics();
    let classify = debugger.dialect().classify;

    let mut area = egui::ScrollArea::both()
        .id_salt("code_rows")
        .auto_shrink([false, false]);
    if let Some(line) = view.scroll_to.take() {
        // Two lines of margin above, so the line never sits on the edge; never past the end,
        // where the scroll area would clamp it a frame later and the rows would jump.
        let end = (count + 3) as f32 * row_height - view.viewport_height;
        let offset = (line.saturating_sub(3) as f32 * row_height).min(end.max(0.0));
        area = area.vertical_scroll_offset(offset);
    }
    let mut shown = 0..0;
    // Rows touch: the scroll area's row arithmetic and the rows drawn share one height.
    ui.spacing_mut().item_spacing = Vec2::ZERO;
    // Three blank rows past the end, so the last lines can scroll clear of the scroll bar.
    let output = area.show_rows(ui, row_height, count + 3, |ui, rows| {
        shown = rows.start + 1..rows.end + 1;
        let width = (gutter_width + 4.0 + text_width).max(ui.available_width());
        for line in rows.start + 1..=rows.end {
            let (rect, _) = ui.allocate_exact_size(vec2(width, row_height), Sense::hover());
            if line > count {
                continue;
            }
            let gutter = Rect::from_min_size(rect.min, vec2(gutter_width, row_height));
            let text_rect = Rect::from_min_max(pos2(gutter.right() + 4.0, rect.top()), rect.max);
            let painter = ui.painter();
            if pc_line == Some(line) {
                painter.rect_filled(text_rect, 0.0, p.current_line);
            } else if fault_line == Some(line) {
                painter.rect_filled(text_rect, 0.0, p.fault_line);
            }
            if view.cursor_line == Some(line) {
                painter.rect_stroke(
                    text_rect,
                    0.0,
                    Stroke::new(1.0, p.dim),
                    egui::StrokeKind::Inside,
                );
            }

            // The gutter: click for a breakpoint.
            let response = ui.interact(gutter, Id::unique(("code_gutter", line)), Sense::click());
            let has_bp = debugger.breakpoints().contains(&line);
            let label = format!("Breakpoint line {line}");
            response.widget_info(|| {
                egui::WidgetInfo::selected(egui::Role::CheckBox, true, has_bp, &label)
            });
            if response.clicked() {
                out.push(Command::Debug(Action::ToggleBreakpoint(line)));
            }
            let dot = gutter.left_center() + vec2(row_height * 0.5, 0.0);
            if has_bp {
                painter.circle_filled(dot, row_height * 0.32, p.breakpoint);
            } else if response.hovered() {
                painter.circle_filled(dot, row_height * 0.3, p.breakpoint.gamma_multiply(0.35));
            }
            if pc_line == Some(line) {
                let tip = gutter.left_center() + vec2(row_height * 1.45, 0.0);
                let h = row_height * 0.3;
                painter.add(egui::Shape::convex_polygon(
                    vec![tip + vec2(-h * 1.3, -h), tip, tip + vec2(-h * 1.3, h)],
                    p.written,
                    Stroke::NONE,
                ));
            }
            let errors = on_line(diagnostics, line);
            painter.text(
                gutter.right_center() - vec2(6.0, 0.0),
                egui::Align2::RIGHT_CENTER,
                line.to_string(),
                font.clone(),
                if errors.is_empty() {
                    p.dim
                } else if errors
                    .iter()
                    .all(|d| d.severity == servoscope_core::machine::Severity::Warning)
                {
                    p.written
                } else {
                    p.error
                },
            );

            // The text, coloured; click to put the cursor on the line.
            let text = view.lines.line(line);
            let mut job = LayoutJob::default();
            append_line(&mut job, text, classify, &p, &font);
            let galley = ui.fonts_mut(|f| f.layout_job(job));
            ui.painter().extend(error_underlines(
                &galley,
                text_rect.left_top(),
                line,
                errors,
                line..line + 1,
                p.error,
                p.written,
            ));
            ui.painter().galley(text_rect.left_top(), galley, p.text);
            let response = ui.interact(text_rect, Id::unique(("code_line", line)), Sense::click());
            let body = text.trim_end_matches(['\n', '\r']);
            let label = format!("Line {line}: {body}");
            response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, &label));
            if response.clicked() {
                view.cursor_line = Some(line);
            }
            if !errors.is_empty() {
                let messages: Vec<String> = errors
                    .iter()
                    .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
                    .collect();
                response.on_hover_text(messages.join("\n"));
            }
        }
    });
    // The machine's notes (a loop's turn, a call, an edge that fired) on the rows shown.
    let notes: Vec<(usize, String)> = machine
        .line_notes()
        .into_iter()
        .filter(|(l, _)| shown.contains(l))
        .collect();
    if !notes.is_empty() {
        let inner = output.inner_rect;
        let top = inner.top() - output.state.clamped_offset().y;
        let row = |l: usize| {
            let y = top + (l - 1) as f32 * row_height;
            Some(Rect::from_min_size(
                pos2(inner.left(), y),
                vec2(inner.width(), row_height),
            ))
        };
        let ui = ui.new_child(egui::UiBuilder::new().max_rect(inner));
        super::code::line_notes(&ui, &notes, inner.right(), row, &p);
    }
    view.viewport_height = output.inner_rect.height();
    // Keep the line about to run in view: scroll when it moved off the rows on screen.
    let moved = pc_line.is_some() && pc_line != view.last_pc_line;
    if moved {
        view.last_pc_line = pc_line;
        if let Some(line) = pc_line
            && !(shown.start + 2..shown.end.saturating_sub(2)).contains(&line)
        {
            view.scroll_to = Some(line);
            ui.ctx().request_repaint();
        }
    }
}

/// The header's switch between the row view and the text editor, for long programs.
pub fn edit_switch(ui: &mut egui::Ui, view: &mut CodeView, lines: usize) {
    if view.edit_long {
        if ui
            .button("Done editing")
            .on_hover_text("Back to the fast view of this long program")
            .clicked()
        {
            view.edit_long = false;
        }
    } else if ui
        .button("Edit text")
        .on_hover_text(format!(
            "Edit the program's {lines} lines in place (the editor lays out every line: slow for long programs)"
        ))
        .clicked()
    {
        view.edit_long = true;
    }
    ui.label(RichText::new(format!("{lines} lines")).small());
}
