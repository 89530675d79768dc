//! The program view: line numbers, breakpoints in the gutter, syntax colouring, the line about
//! to run highlighted and kept in view, errors underlined on their lines, and the problems list.

use egui::text::{CCursor, CCursorRange, LayoutJob, TextFormat};
use egui::{FontId, Id, Rect, RichText, Sense, Stroke, TextStyle, Vec2, pos2, vec2};

use super::Command;
use super::theme::{Palette, palette};
use crate::debugger::Debugger;
use crate::machine::Diagnostic;
use crate::machine::registry::TokenClass;

pub const TEXT_ID: &str = "program_text";

/// Programs longer than this open in the row view (only visible lines laid out); shorter ones
/// in the text editor, where they are edited in place.
pub const EDIT_IN_PLACE_LINES: usize = 5_000;

#[derive(Default)]
pub struct CodeView {
    /// Line of the text cursor (for F9 and Run to cursor), 1-based.
    pub cursor_line: Option<usize>,
    /// The pc line the view last scrolled to.
    pub(super) last_pc_line: Option<usize>,
    /// A line to move the cursor to and show (clicked in the problems list).
    pub pending_jump: Option<usize>,
    /// The program's lines, for the row view.
    pub lines: super::code_rows::LineIndex,
    /// A line the row view scrolls to on the next frame.
    pub scroll_to: Option<usize>,
    /// A long program is being edited in the text editor instead of the row view.
    pub edit_long: bool,
    /// The row view's visible height, from the last frame.
    pub viewport_height: f32,
}

impl CodeView {
    pub fn reset_view(&mut self) {
        *self = CodeView::default();
    }

    /// The line F9 and Ctrl+F10 act on: the text cursor's, else the one about to run.
    pub fn target_line(&self, debugger: &Debugger) -> Option<usize> {
        self.cursor_line.or_else(|| debugger.machine().pc_line())
    }
}

fn color(p: &Palette, kind: TokenClass) -> egui::Color32 {
    match kind {
        TokenClass::Plain => p.text,
        TokenClass::Mnemonic => p.mnemonic,
        TokenClass::Operation => p.operation,
        TokenClass::Number => p.number,
        TokenClass::Location => p.register,
        TokenClass::Label => p.label,
        TokenClass::Comment => p.comment,
        TokenClass::Condition => p.condition,
    }
}

/// The whole text as a coloured layout, errors underlined. The job's text is exactly `text`.
pub fn highlight(
    text: &str,
    classify: fn(&str) -> Vec<TokenClass>,
    diagnostics: &[Diagnostic],
    p: &Palette,
    font: &FontId,
) -> LayoutJob {
    let mut job = LayoutJob::default();
    // Diagnostics in line order, walked alongside the lines: linear however many there are.
    let mut sorted: Vec<&Diagnostic> = diagnostics.iter().collect();
    sorted.sort_by_key(|d| d.line);
    let mut next = 0;
    for (index, line) in text.split_inclusive('\n').enumerate() {
        let number = index + 1;
        while sorted.get(next).is_some_and(|d| d.line < number) {
            next += 1;
        }
        let on_line = sorted[next..]
            .iter()
            .take_while(|d| d.line == number)
            .copied();
        append_line(&mut job, line, classify, on_line, p, font);
    }
    job.wrap.max_width = f32::INFINITY;
    job
}

/// One line (with its line ending, if any) coloured by class, its errors underlined.
pub fn append_line<'a>(
    job: &mut LayoutJob,
    line: &str,
    classify: fn(&str) -> Vec<TokenClass>,
    errors: impl Iterator<Item = &'a Diagnostic>,
    p: &Palette,
    font: &FontId,
) {
    let body = line.strip_suffix('\n').unwrap_or(line);
    let body = body.strip_suffix('\r').unwrap_or(body);
    let kinds = classify(body);
    let mut error = vec![false; kinds.len()];
    for d in errors {
        let start = (d.col - 1).min(error.len());
        let end = (start + d.len).min(error.len());
        error[start..end].fill(true);
    }
    let chars: Vec<(usize, char)> = line.char_indices().collect();
    let mut start = 0;
    while start < chars.len() {
        let style = |i: usize| (kinds.get(i).copied(), error.get(i).copied());
        let mut end = start + 1;
        while end < chars.len() && style(end) == style(start) {
            end += 1;
        }
        let from = chars[start].0;
        let to = chars.get(end).map_or(line.len(), |&(b, _)| b);
        let (kind, is_error) = style(start);
        job.append(
            &line[from..to],
            0.0,
            TextFormat {
                font_id: font.clone(),
                color: color(p, kind.unwrap_or(TokenClass::Plain)),
                underline: if is_error == Some(true) {
                    Stroke::new(2.0, p.error)
                } else {
                    Stroke::NONE
                },
                ..Default::default()
            },
        );
        start = end;
    }
}

fn line_of_char(text: &str, char_index: usize) -> usize {
    text.chars().take(char_index).filter(|&c| c == '\n').count() + 1
}

fn char_of_line(text: &str, line: usize) -> usize {
    if line <= 1 {
        return 0;
    }
    let mut seen = 1;
    for (i, c) in text.chars().enumerate() {
        if c == '\n' {
            seen += 1;
            if seen == line {
                return i + 1;
            }
        }
    }
    text.chars().count()
}

pub fn show(ui: &mut egui::Ui, debugger: &Debugger, view: &mut CodeView, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    if !debugger.diagnostics().is_empty() {
        problems(ui, debugger, view);
    }
    view.lines.update(debugger.source());
    let long = view.lines.text_lines() > EDIT_IN_PLACE_LINES;
    let header = ui
        .horizontal(|ui| {
            // The tab says "Program"; the header names it, and names the editor for screen
            // readers.
            let label = ui.label(RichText::new(debugger.name()).monospace().strong());
            if long {
                super::code_rows::edit_switch(ui, view, view.lines.text_lines());
            }
            if debugger.is_edited() {
                ui.label(
                    RichText::new("edited: Ctrl+Enter assembles (or just step / run)")
                        .color(p.written),
                );
            }
            label.id
        })
        .inner;
    if long && !view.edit_long {
        if let Some(line) = view.pending_jump.take() {
            view.cursor_line = Some(line);
            view.scroll_to = Some(line);
        }
        super::code_rows::show(ui, debugger, view, out);
        return;
    }
    let font = TextStyle::Monospace.resolve(ui.style());
    let row_height = ui.fonts_mut(|f| f.row_height(&font));
    let char_width = ui.fonts_mut(|f| f.glyph_width(&font, '0'));
    let mut text = debugger.source().to_string();
    let line_count = text.lines().count().max(1) + usize::from(text.ends_with('\n'));
    let digits = line_count.to_string().len().max(3);
    let gutter_width = char_width * (digits as f32 + 3.5);
    let machine = debugger.machine();
    let pc_line = machine.pc_line().filter(|_| machine.run_state().is_live());
    let fault_line = machine.fault().map(|f| f.line);
    let text_id = Id::unique(TEXT_ID);

    let jump = view.pending_jump.take();
    if let Some(line) = jump {
        let ctx = ui.ctx().clone();
        if let Some(mut state) = egui::TextEdit::load_state(&ctx, text_id) {
            let index = char_of_line(&text, line);
            state
                .cursor
                .set_char_range(Some(CCursorRange::one(CCursor::new(index))));
            state.store(&ctx, text_id);
        }
        ctx.memory_mut(|m| m.request_focus(text_id));
        view.cursor_line = Some(line);
    }

    egui::ScrollArea::both()
        .id_salt("code_scroll")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            ui.horizontal_top(|ui| {
                ui.spacing_mut().item_spacing.x = 0.0;
                let (gutter, _) = ui.allocate_exact_size(
                    vec2(gutter_width, row_height * line_count as f32),
                    Sense::hover(),
                );
                let text_left = gutter.right() + 4.0;
                // Line backgrounds go under the text, but where the lines are is known only once
                // the text is laid out: keep their place in the paint order now, fill it after.
                let backgrounds = ui.painter().add(egui::Shape::Noop);

                let diagnostics = debugger.diagnostics();
                let classify = debugger.dialect().classify;
                let mut layouter = |ui: &egui::Ui, buf: &dyn egui::TextBuffer, _wrap: f32| {
                    let job = highlight(buf.as_str(), classify, diagnostics, &p, &font);
                    ui.fonts_mut(|f| f.layout_job(job))
                };
                let output = egui::TextEdit::multiline(&mut text)
                    .id(text_id)
                    .font(font.clone())
                    .frame(egui::Frame::NONE)
                    .margin(egui::Margin::ZERO)
                    .desired_width(f32::INFINITY)
                    .desired_rows(line_count)
                    .lock_focus(true)
                    .layouter(&mut layouter)
                    .show(ui);
                egui::Response::clone(&output.response).labelled_by(header);
                // Every row's place comes from the laid-out text itself (rows are placed on
                // whole pixels, so a computed `line × height` drifts in long programs).
                let rows = LineRows::of(&output.galley, output.galley_pos, text_left);
                let fills: Vec<egui::Shape> =
                    [(pc_line, p.current_line), (fault_line, p.fault_line)]
                        .into_iter()
                        .filter_map(|(line, fill)| {
                            let rect = rows
                                .rect(line?)?
                                .with_max_x(ui.clip_rect().right() + 2000.0);
                            Some(egui::Shape::rect_filled(rect, 0.0, fill))
                        })
                        .collect();
                ui.painter().set(backgrounds, egui::Shape::Vec(fills));
                let scroll_to = jump.or_else(|| pc_moved(view, pc_line));
                if let Some(rect) = scroll_to.and_then(|line| rows.rect(line)) {
                    // Two lines of margin, so the line never hides under a scroll bar.
                    // Only vertically: from the gutter's edge, so the line numbers stay in view
                    // in a narrow window.
                    let rect = rect
                        .with_min_x(gutter.left())
                        .with_max_x(gutter.left() + 1.0)
                        .expand2(vec2(0.0, 2.0 * row_height));
                    ui.scroll_to_rect(rect, None);
                }
                if output.response.changed() {
                    out.push(Command::EditSource(text.clone()));
                }
                if let Some(range) = output.cursor_range {
                    view.cursor_line = Some(line_of_char(&text, range.primary.index.0));
                }
                if let Some(pos) = output.response.hover_pos()
                    && let Some(line) = rows.line_at(pos.y)
                {
                    let messages: Vec<String> = diagnostics
                        .iter()
                        .filter(|d| d.line == line)
                        .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
                        .collect();
                    if !messages.is_empty() {
                        egui::Response::clone(&output.response)
                            .on_hover_text_at_pointer(messages.join("\n"));
                    }
                }
                gutter_ui(ui, debugger, gutter, &rows, pc_line, &p, &font, out);
            });
        });
}

/// The line about to run, when it moved since the last frame: scroll it into view once.
fn pc_moved(view: &mut CodeView, pc_line: Option<usize>) -> Option<usize> {
    if pc_line.is_some() && pc_line != view.last_pc_line {
        view.last_pc_line = pc_line;
        return pc_line;
    }
    None
}

/// Where each line of the laid-out program text is (one row per line: the text never wraps).
struct LineRows {
    /// Top and bottom of each line, in screen coordinates; line n is index n − 1.
    spans: Vec<(f32, f32)>,
    left: f32,
}

impl LineRows {
    fn of(galley: &egui::Galley, origin: egui::Pos2, left: f32) -> Self {
        let spans = galley
            .rows
            .iter()
            .map(|row| {
                let rect = row.rect().translate(origin.to_vec2());
                (rect.top(), rect.bottom())
            })
            .collect();
        LineRows { spans, left }
    }

    /// The row of `line` (1-based), from the text's left edge.
    fn rect(&self, line: usize) -> Option<Rect> {
        let &(top, bottom) = self.spans.get(line.checked_sub(1)?)?;
        Some(Rect::from_min_max(
            pos2(self.left, top),
            pos2(self.left + 1.0, bottom),
        ))
    }

    /// The line at height `y`.
    fn line_at(&self, y: f32) -> Option<usize> {
        let i = self.spans.partition_point(|&(_, bottom)| bottom <= y);
        (i < self.spans.len() && self.spans[i].0 <= y).then_some(i + 1)
    }

    /// The lines whose rows meet the band `top..bottom`.
    fn visible(&self, top: f32, bottom: f32) -> std::ops::Range<usize> {
        let first = self.spans.partition_point(|&(_, b)| b <= top);
        let last = self.spans.partition_point(|&(t, _)| t < bottom);
        first + 1..last + 1
    }
}

#[allow(clippy::too_many_arguments)]
fn gutter_ui(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    gutter: Rect,
    rows: &LineRows,
    pc_line: Option<usize>,
    p: &Palette,
    font: &FontId,
    out: &mut Vec<Command>,
) {
    let clip = ui.clip_rect();
    let error_lines: Vec<usize> = debugger.diagnostics().iter().map(|d| d.line).collect();
    for line in rows.visible(clip.top(), clip.bottom()) {
        let Some(text_row) = rows.rect(line) else {
            continue;
        };
        let row = Rect::from_min_max(
            pos2(gutter.left(), text_row.top()),
            pos2(gutter.right(), text_row.bottom()),
        );
        let row_height = row.height();
        let id = Id::unique(("gutter", line));
        let response = ui.interact(row, id, Sense::click());
        let label = format!("Breakpoint line {line}");
        let has_bp = debugger.breakpoints().contains(&line);
        response
            .widget_info(|| egui::WidgetInfo::selected(egui::Role::CheckBox, true, has_bp, &label));
        if response.clicked() {
            out.push(Command::ToggleBreakpoint(line));
        }
        let painter = ui.painter();
        let has_error = error_lines.contains(&line);
        if response.hovered() && !has_bp {
            painter.circle_filled(
                row.left_center() + vec2(row_height * 0.5, 0.0),
                row_height * 0.3,
                p.breakpoint.gamma_multiply(0.35),
            );
        }
        if has_bp {
            painter.circle_filled(
                row.left_center() + vec2(row_height * 0.5, 0.0),
                row_height * 0.32,
                p.breakpoint,
            );
        }
        if pc_line == Some(line) {
            let tip = row.left_center() + vec2(row_height * 1.45, 0.0);
            let h = row_height * 0.3;
            painter.add(egui::Shape::convex_polygon(
                vec![
                    tip + vec2(-h * 1.3, -h),
                    tip + vec2(0.0, 0.0),
                    tip + vec2(-h * 1.3, h),
                ],
                p.written,
                Stroke::NONE,
            ));
        }
        let number_color = if has_error { p.error } else { p.dim };
        painter.text(
            row.right_center() - vec2(6.0, 0.0),
            egui::Align2::RIGHT_CENTER,
            line.to_string(),
            font.clone(),
            number_color,
        );
        if has_error {
            let messages: Vec<String> = debugger
                .diagnostics()
                .iter()
                .filter(|d| d.line == line)
                .map(|d| d.message.clone())
                .collect();
            response.on_hover_text(messages.join("\n"));
        }
    }
}

/// The problems list: every diagnostic; clicking one moves the cursor to its line.
fn problems(ui: &mut egui::Ui, debugger: &Debugger, view: &mut CodeView) {
    let p = palette(ui.visuals().dark_mode);
    egui::Panel::bottom("problems")
        .resizable(true)
        .default_size(120.0)
        .min_size(60.0)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.strong(format!("Problems ({})", debugger.diagnostics().len()));
                ui.label(egui::RichText::new("Nothing runs until these are fixed.").color(p.dim));
            });
            let diagnostics = debugger.diagnostics();
            let row_height = ui.spacing().interact_size.y;
            // Only the visible rows are laid out: a file with 100,000 errors stays responsive.
            egui::ScrollArea::vertical()
                .id_salt("problems_scroll")
                .auto_shrink([false, false])
                .show_rows(ui, row_height, diagnostics.len(), |ui, rows| {
                    for d in &diagnostics[rows] {
                        let text = format!(
                            "{}:{}  {}",
                            d.line,
                            d.col,
                            crate::machine::diagnostics::printable(&d.message)
                        );
                        let r = ui.add(
                            egui::Button::selectable(
                                false,
                                egui::RichText::new(text).color(p.error),
                            )
                            .min_size(Vec2::ZERO),
                        );
                        if r.clicked() {
                            view.pending_jump = Some(d.line);
                        }
                    }
                });
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn highlight_keeps_the_text_exactly() {
        let text = "WRP 11, 1\r\n\nbad: BOGUS ; x\nü\n";
        let diags = vec![Diagnostic::error(3, 6, 5, "unknown")];
        let classify = crate::machine::silverlode::syntax::classify;
        let job = highlight(
            text,
            classify,
            &diags,
            &palette(true),
            &FontId::monospace(12.0),
        );
        assert_eq!(job.text, text);
        let underlined: String = job
            .sections
            .iter()
            .filter(|s| s.format.underline != Stroke::NONE)
            .map(|s| &job.text[s.byte_range.start.0..s.byte_range.end.0])
            .collect();
        assert_eq!(underlined, "BOGUS");
    }

    #[test]
    fn lines_and_chars() {
        let text = "a\nbc\nd";
        assert_eq!(line_of_char(text, 0), 1);
        assert_eq!(line_of_char(text, 3), 2);
        assert_eq!(char_of_line(text, 3), 5);
        assert_eq!(char_of_line(text, 1), 0);
    }
}
