//! The program text drawn: syntax colours, error underlines, line notes, and the
//! conversions between characters, lines and columns.

use super::*;

pub(super) fn color(p: &Palette, kind: TokenClass) -> egui::Color32 {
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

/// The whole text as a coloured layout. The job's text is exactly `text`. Errors are
/// underlined apart, by [`error_underlines`].
pub fn highlight(
    text: &str,
    classify: fn(&str) -> Vec<TokenClass>,
    p: &Palette,
    font: &FontId,
) -> LayoutJob {
    let mut job = LayoutJob::default();
    for line in text.split_inclusive('\n') {
        append_line(&mut job, line, classify, p, font);
    }
    job.wrap.max_width = f32::INFINITY;
    job
}

/// One line (with its line ending, if any) coloured by class.
pub fn append_line(
    job: &mut LayoutJob,
    line: &str,
    classify: fn(&str) -> Vec<TokenClass>,
    p: &Palette,
    font: &FontId,
) {
    let body = line.strip_suffix('\n').unwrap_or(line);
    let body = body.strip_suffix('\r').unwrap_or(body);
    let kinds = classify(body);
    let chars: Vec<(usize, char)> = line.char_indices().collect();
    let mut start = 0;
    while start < chars.len() {
        let kind = |i: usize| kinds.get(i).copied();
        let mut end = start + 1;
        while end < chars.len() && kind(end) == kind(start) {
            end += 1;
        }
        let from = chars[start].0;
        let to = chars.get(end).map_or(line.len(), |&(b, _)| b);
        job.append(
            &line[from..to],
            0.0,
            TextFormat {
                font_id: font.clone(),
                color: color(p, kind(start).unwrap_or(TokenClass::Plain)),
                ..Default::default()
            },
        );
        start = end;
    }
}

/// The machine's notes on lines (a loop's turn, a call, an edge that fired), right-aligned at
/// `right` on their rows, over a backing so they read over long lines.
pub fn line_notes(
    ui: &egui::Ui,
    notes: &[(usize, String)],
    right: f32,
    row: impl Fn(usize) -> Option<Rect>,
    p: &Palette,
) {
    let font = FontId::proportional(12.0);
    for (line, note) in notes {
        let Some(rect) = row(*line) else { continue };
        let galley = ui
            .painter()
            .layout_no_wrap(note.clone(), font.clone(), p.written);
        let at = pos2(
            right - 10.0 - galley.size().x,
            rect.center().y - galley.size().y / 2.0,
        );
        let backing = Rect::from_min_size(at, galley.size()).expand(2.0);
        ui.painter()
            .rect_filled(backing, 3.0, ui.visuals().extreme_bg_color);
        ui.painter().galley(at, galley, p.written);
    }
}

/// Each error of `diagnostics` on the lines `visible` as a 2-px line along the bottom of its
/// own row, inside it. (The text layout's underline straddles the row's lower edge: a line
/// scrolled just out of view left a red stroke on the line below it, issue #22 item 13.)
/// `galley`, drawn at `origin`, has one row per line, its first row being `first_line`.
pub fn error_underlines(
    galley: &egui::Galley,
    origin: egui::Pos2,
    first_line: usize,
    diagnostics: &[Diagnostic],
    visible: std::ops::Range<usize>,
    color: egui::Color32,
    warning: egui::Color32,
) -> Vec<egui::Shape> {
    use egui::epaint::text::CharIndex;
    let from = diagnostics.partition_point(|d| d.line < visible.start);
    diagnostics[from..]
        .iter()
        .take_while(|d| d.line < visible.end)
        .filter_map(|d| {
            let row = galley.rows.get(d.line.checked_sub(first_line)?)?;
            let glyphs = row.glyphs.len();
            let start = d.col.saturating_sub(1).min(glyphs);
            let end = (start + d.len).min(glyphs);
            if start >= end {
                return None;
            }
            let rect = row.rect().translate(origin.to_vec2());
            let y = rect.bottom() - 1.0;
            let x = |i: usize| rect.left() + row.x_offset(CharIndex(i));
            // A warning (the program still runs) in the highlight colour, not the error's.
            let colour = match d.severity {
                servoscope_core::machine::Severity::Warning => warning,
                servoscope_core::machine::Severity::Error => color,
            };
            Some(egui::Shape::line_segment(
                [pos2(x(start), y), pos2(x(end), y)],
                Stroke::new(2.0, colour),
            ))
        })
        .collect()
}

/// The character index of `line`:`col` (1-based), kept inside that line.
pub(super) fn char_of(text: &str, line: usize, col: usize) -> usize {
    let start = char_of_line(text, line);
    let line_len = text.chars().skip(start).take_while(|&c| c != '\n').count();
    start + col.saturating_sub(1).min(line_len)
}

/// Line and column (1-based) of a character index.
pub(super) fn line_col(text: &str, char_index: usize) -> (usize, usize) {
    let mut line = 1;
    let mut col = 1;
    for c in text.chars().take(char_index) {
        if c == '\n' {
            line += 1;
            col = 1;
        } else {
            col += 1;
        }
    }
    (line, col)
}

pub(super) fn line_of_char(text: &str, char_index: usize) -> usize {
    text.chars().take(char_index).filter(|&c| c == '\n').count() + 1
}

pub(super) fn char_of_line(text: &str, line: usize) -> usize {
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

/// The whitespace-separated token around character `at`.
pub(super) fn token_at(text: &str, at: usize) -> String {
    let chars: Vec<char> = text.chars().collect();
    let at = at.min(chars.len());
    let mut start = at;
    while start > 0 && !chars[start - 1].is_whitespace() {
        start -= 1;
    }
    let mut end = at;
    while end < chars.len() && !chars[end].is_whitespace() {
        end += 1;
    }
    chars[start..end].iter().collect()
}

/// The word under character `index`: a name, a register, or a whole `q16(…)`/`bcd(…)`.
pub(super) fn word_at(text: &str, index: usize) -> Option<String> {
    let chars: Vec<char> = text.chars().collect();
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '.';
    if !chars
        .get(index)
        .copied()
        .is_some_and(|c| is_word(c) || c == '(' || c == ')')
    {
        return None;
    }
    let mut start = index;
    while start > 0 && is_word(chars[start - 1]) {
        start -= 1;
    }
    let mut end = index;
    while end < chars.len() && is_word(chars[end]) {
        end += 1;
    }
    // Inside a literal's parentheses: widen to the call.
    let line_start = chars[..index]
        .iter()
        .rposition(|&c| c == '\n')
        .map_or(0, |i| i + 1);
    let open = chars[line_start..=index.min(chars.len() - 1)]
        .iter()
        .rposition(|&c| c == '(')
        .map(|i| line_start + i);
    if let Some(open) = open {
        let close = chars[open..].iter().position(|&c| c == ')' || c == '\n');
        if let Some(close) = close
            .map(|c| open + c)
            .filter(|&c| chars[c] == ')' && c >= index)
        {
            let mut call_start = open;
            while call_start > 0 && chars[call_start - 1].is_ascii_alphanumeric() {
                call_start -= 1;
            }
            if call_start < open {
                return Some(chars[call_start..=close].iter().collect());
            }
        }
    }
    (start < end).then(|| chars[start..end].iter().collect())
}
