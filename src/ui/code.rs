//! The program view: line numbers, breakpoints in the gutter, syntax colouring, the line about
//! to run highlighted and kept in view, errors underlined on their lines, and the problems list.

use egui::text::{CCursor, CCursorRange, LayoutJob, TextFormat};
use egui::{FontId, Id, Rect, RichText, Sense, Stroke, TextStyle, Vec2, pos2, vec2};

use super::Command;
use super::theme::{Palette, palette};
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::Diagnostic;
use servoscope_core::machine::project::{FILE_LINES, Project};
use servoscope_core::registry::TokenClass;

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
    /// Where to put the caret next frame, and show (a problem clicked, a match found, a line
    /// asked for).
    pub pending_jump: Option<Jump>,
    /// The location named where the editor was right-clicked (its context menu).
    pub menu_location: Option<(String, servoscope_core::machine::Loc)>,
    /// The caret as a character index into the text, from the last frame.
    pub cursor_char: Option<usize>,
    /// The find or go-to-line bar above the editor, when open.
    pub bar: Option<Bar>,
    pub bar_text: String,
    /// What the bar has to say: "3 of 7", "not found", "no line 900".
    pub bar_note: Option<String>,
    /// The editor's visible height, from the last frame (PageUp/PageDown move by it).
    pub editor_height: f32,
    /// Give the editor focus next frame too: a click elsewhere that asked for it (a problem
    /// in the list) may take focus for itself meanwhile.
    focus_again: bool,
    /// The program's lines, for the row view.
    pub lines: super::code_rows::LineIndex,
    /// A line the row view scrolls to on the next frame.
    pub scroll_to: Option<usize>,
    /// A long program is being edited in the text editor instead of the row view.
    pub edit_long: bool,
    /// The row view's visible height, from the last frame.
    pub viewport_height: f32,
    /// The editor's visible height when the line about to run was last kept in view.
    pc_view_height: f32,
    /// The file shown (index into the program's files; 0, the top file, for most programs).
    pub file: usize,
    /// The gutter shows each statement's program-memory address (TML, spec §5.11).
    pub addresses: bool,
    /// The file the line about to run was in at the last frame: entering another brings its
    /// tab forward.
    pc_file: Option<usize>,
    /// The line about to run at the last frame.
    pc_seen: Option<usize>,
    /// Which files differ from what was opened or last saved (set by the window each frame):
    /// their tabs are marked.
    pub unsaved: Vec<bool>,
}

/// A place in the text: 1-based line and column (in characters), and how many characters
/// from there to select.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Jump {
    pub line: usize,
    pub col: usize,
    pub len: usize,
}

impl Jump {
    pub fn line(line: usize) -> Self {
        Jump {
            line,
            col: 1,
            len: 0,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bar {
    Find,
    GoToLine,
}

pub const FIND: egui::KeyboardShortcut =
    egui::KeyboardShortcut::new(egui::Modifiers::COMMAND, egui::Key::F);
pub const GO_TO_LINE: egui::KeyboardShortcut =
    egui::KeyboardShortcut::new(egui::Modifiers::COMMAND, egui::Key::G);

impl CodeView {
    /// Scroll to `line` and put the caret at its start.
    pub fn show_line(&mut self, line: usize) {
        self.pending_jump = Some(Jump::line(line));
    }

    /// Back to the start, keeping the user's choice of gutter addresses.
    pub fn reset_view(&mut self) {
        *self = CodeView {
            addresses: self.addresses,
            ..CodeView::default()
        };
    }

    /// The program line of the shown file's 1-based line `local`.
    pub fn program_line(&self, local: usize) -> usize {
        Project::line(self.file, local)
    }

    /// The line F9 and Ctrl+F10 act on: the text cursor's, else the one about to run.
    pub fn target_line(&self, debugger: &Debugger) -> Option<usize> {
        self.cursor_line.or_else(|| debugger.machine().pc_line())
    }

    /// The mnemonic F1 opens the reference at: the word at the caret when it is one, else the
    /// first mnemonic of the caret's line (of the line about to run without a caret).
    pub fn word_at_caret(&self, debugger: &Debugger) -> Option<String> {
        let dialect = debugger.dialect();
        let text = shown_text(debugger, self.file);
        if let Some(m) = self
            .cursor_char
            .and_then(|at| mnemonic_in(dialect, &token_at(text, at)))
        {
            return Some(m);
        }
        let line = text.lines().nth(
            Project::split(self.target_line(debugger)?)
                .1
                .checked_sub(1)?,
        )?;
        line.split_whitespace()
            .find_map(|token| mnemonic_in(dialect, token))
    }
}

/// The whitespace-separated token around character `at`.
fn token_at(text: &str, at: usize) -> String {
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

/// What hovering a mnemonic tells: its reference entry's first paragraph (syntax, effect,
/// flags), from the dialect's document.
pub fn mnemonic_hover(dialect: &servoscope_core::registry::Dialect, token: &str) -> Option<String> {
    let mnemonic = mnemonic_in(dialect, token)?;
    let entry = dialect.reference_entry(&mnemonic)?;
    Some(format!(
        "{} — {}\n{}\nF1: the whole entry in the Help panel",
        entry.names.join(", "),
        entry.title,
        entry.summary.replace('`', "")
    ))
}

/// `token` as one of `dialect`'s mnemonics: `ADD(W)` is ADD, `WAIT!` is WAIT, `loop:CLC` is CLC.
pub fn mnemonic_in(dialect: &servoscope_core::registry::Dialect, token: &str) -> Option<String> {
    let token = token.rsplit(':').next().unwrap_or(token);
    let token = token.split('(').next().unwrap_or(token);
    let token = token.trim_end_matches([';', '!', ',']);
    dialect
        .is_mnemonic(token)
        .then(|| token.to_ascii_uppercase())
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
fn char_of(text: &str, line: usize, col: usize) -> usize {
    let start = char_of_line(text, line);
    let line_len = text.chars().skip(start).take_while(|&c| c != '\n').count();
    start + col.saturating_sub(1).min(line_len)
}

/// Line and column (1-based) of a character index.
fn line_col(text: &str, char_index: usize) -> (usize, usize) {
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

/// The next match of `needle` (ASCII case ignored) starting at character `from`, wrapping to
/// the start; or the previous one ending before `from` when `backwards`. Returns its
/// character index, the number of matches, and the match's number among them (1-based).
pub fn find_match(
    text: &str,
    needle: &str,
    from: usize,
    backwards: bool,
) -> Option<(usize, usize, usize)> {
    if needle.is_empty() {
        return None;
    }
    // ASCII-only folding keeps byte offsets, so matches map straight back to the text.
    let hay = text.to_ascii_lowercase();
    let needle = needle.to_ascii_lowercase();
    let starts: Vec<usize> = hay
        .match_indices(&needle)
        .map(|(byte, _)| text[..byte].chars().count())
        .collect();
    let chosen = if backwards {
        starts
            .iter()
            .rposition(|&s| s < from)
            .unwrap_or(starts.len().checked_sub(1)?)
    } else {
        starts.iter().position(|&s| s >= from).unwrap_or(0)
    };
    let at = *starts.get(chosen)?;
    Some((at, starts.len(), chosen + 1))
}

/// The word under character `index`: a name, a register, or a whole `q16(…)`/`bcd(…)`.
fn word_at(text: &str, index: usize) -> Option<String> {
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

/// What hovering `word` in the code tells: a location's value in every format, or what a
/// `q16(…)`/`bcd(…)` literal stores.
pub fn hover_value(m: &dyn servoscope_core::machine::MachineView, word: &str) -> Option<String> {
    use servoscope_core::machine::Format;
    use servoscope_core::machine::value::parse_value;
    let loc = m.find(word).or_else(|| {
        m.program_names()
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(word))
            .map(|(_, l)| *l)
    });
    if let Some(loc) = loc {
        let info = m.info(loc)?;
        let raw = m.read(loc);
        let mut lines = vec![match info.alias {
            Some(alias) => format!("{} ({alias})", info.name),
            None => info.name.clone(),
        }];
        if info.width == 1 {
            // A relay or an input is on or off: "signed −1" or "Q16.16 −0.000015" would be
            // readings of a number it is not.
            lines.push(if raw != 0 { "ON" } else { "OFF" }.to_string());
            if let Some(on) = m.forced(loc) {
                let level = if on { "ON" } else { "OFF" };
                lines.push(format!(
                    "FORCED {level}: the program reads {level} whatever it writes or the switch says"
                ));
            }
        } else {
            lines.extend(
                Format::ALL
                    .iter()
                    .map(|f| format!("{:>8}  {}", f.name(), f.show(raw, info.width))),
            );
        }
        lines.push(if m.can_force(loc) {
            "Right-click: who wrote it, break on it, watch it, force it".to_string()
        } else {
            "Right-click: who wrote it, break on it, watch it".to_string()
        });
        return Some(lines.join("\n"));
    }
    if let Some((name, value)) = m.program_constants().into_iter().find(|(n, _)| n == word) {
        // A constant is a 32-bit data value: every reading of it, like a register's.
        let raw = value as u64 & 0xFFFF_FFFF;
        let mut lines = vec![format!(
            "{name} (a constant; watches and conditions may use it)"
        )];
        lines.extend(
            Format::ALL
                .iter()
                .map(|f| format!("{:>8}  {}", f.name(), f.show(raw, 32))),
        );
        return Some(lines.join("\n"));
    }
    let lower = word.to_ascii_lowercase();
    // A Q16.16 literal, or a TML fixed literal (digits, a point, digits): what it really stores.
    let fixed_literal = (servoscope_core::registry::by_name(m.dialect())
        .is_some_and(|d| d.decimal_literals_are_fixed)
        && word.contains('.')
        && word.chars().all(|c| c.is_ascii_digit() || c == '.'))
    .then_some(word);
    let q16_inner = lower
        .strip_prefix("q16(")
        .and_then(|r| r.strip_suffix(')'))
        .map(|inner| &word[4..4 + inner.len()]);
    if let Some(typed) = q16_inner.or(fixed_literal)
        && let Ok(q) = servoscope_core::machine::value::quantize_q16(typed)
    {
        let raw = q.raw as u64 & 0xFFFF_FFFF;
        let mut lines = vec![
            format!("{word} stores {} ({})", q.raw, Format::Hex.show(raw, 32)),
            format!("   binary  {}", Format::Binary.show(raw, 32)),
            format!("which is {} (= {} / 65536)", q.stands_for, q.raw),
        ];
        lines.push(match &q.relative {
            Some(relative) => format!("quantization error {} ({relative})", q.error),
            None => format!("quantization error {}", q.error),
        });
        return Some(lines.join("\n"));
    }
    if lower.starts_with("q16(") || lower.starts_with("bcd(") {
        let raw = parse_value(word, 32).ok()?;
        let mut lines = vec![format!("{word} stores")];
        lines.extend(
            [Format::Signed, Format::Hex, Format::Binary]
                .iter()
                .map(|f| format!("{:>8}  {}", f.name(), f.show(raw, 32))),
        );
        return Some(lines.join("\n"));
    }
    None
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

/// The text of file `file` of the program (the top file's when there is no such file).
pub fn shown_text(debugger: &Debugger, file: usize) -> &str {
    let files = &debugger.project().files;
    files
        .get(file)
        .or_else(|| files.first())
        .map_or("", |f| f.text.as_str())
}

/// The file an `#include` line names, if `line` is one that names a file of the program.
fn included_file(debugger: &Debugger, file: usize, line: &str) -> Option<usize> {
    let includes = debugger.dialect().includes?;
    let path = includes(line).into_iter().next()?;
    let project = debugger.project();
    let includer = project.files.get(file)?.name.as_str();
    project.index_of(&servoscope_core::machine::project::resolve_include(
        includer, &path,
    ))
}

/// One tab per file, the top file first; the one holding the line about to run is marked.
fn file_tabs(ui: &mut egui::Ui, debugger: &Debugger, view: &mut CodeView, pc: Option<usize>) {
    let p = palette(ui.visuals().dark_mode);
    ui.horizontal_wrapped(|ui| {
        for (k, f) in debugger.project().files.iter().enumerate() {
            let edited = view.unsaved.get(k).copied().unwrap_or(false);
            let running = pc.is_some_and(|l| Project::split(l).0 == k);
            let mut text = RichText::new(format!(
                "{}{}{}",
                if running { "▶ " } else { "" },
                f.name,
                if edited { " •" } else { "" }
            ))
            .monospace();
            if running {
                text = text.color(p.written);
            }
            let tab =
                ui.selectable_label(view.file == k, text)
                    .on_hover_text(match (running, edited) {
                        (true, true) => {
                            "The statement about to run is in this file; • unsaved changes"
                        }
                        (true, false) => "The statement about to run is in this file",
                        (false, true) => "Show this file; • unsaved changes",
                        (false, false) => "Show this file",
                    });
            tab.widget_info(|| {
                egui::WidgetInfo::selected(
                    egui::Role::Tab,
                    true,
                    view.file == k,
                    format!("File {}", f.name),
                )
            });
            if tab.clicked() {
                view.file = k;
            }
        }
    });
}

pub fn show(ui: &mut egui::Ui, debugger: &Debugger, view: &mut CodeView, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    // First: a problem clicked in its list may ask for a line of another file.
    if !debugger.diagnostics().is_empty() {
        problems(ui, debugger, view);
    }
    let files = debugger.project().files.len().max(1);
    {
        let m = debugger.machine();
        let pc = m.pc_line().filter(|_| m.run_state().is_live());
        let pc_file = pc.map(|l| Project::split(l).0);
        // The file of the statement about to run comes forward when execution enters it, and
        // at every step or stop; not at every statement of a run, so another file can be
        // read while the program runs.
        let entered = pc_file != view.pc_file;
        let stopped_elsewhere = pc != view.pc_seen && !debugger.is_running();
        if (entered || stopped_elsewhere)
            && let Some(f) = pc_file.filter(|&f| f < files)
        {
            view.file = f;
        }
        view.pc_file = pc_file;
        view.pc_seen = pc;
    }
    // A line asked for in another file shows that file.
    if let Some(j) = view.pending_jump {
        let (f, _) = Project::split(j.line);
        if f < files {
            view.file = f;
        }
    }
    if view.file >= files {
        view.file = 0;
    }
    let file = view.file;
    let base = Project::line(file, 0);
    let to_local =
        move |line: usize| (line > base && line < base + FILE_LINES).then(|| line - base);
    for (shortcut, bar) in [(FIND, Bar::Find), (GO_TO_LINE, Bar::GoToLine)] {
        if ui.input_mut(|i| i.consume_shortcut(&shortcut)) {
            if view.bar != Some(bar) {
                view.bar_text.clear();
            }
            view.bar = Some(bar);
            view.bar_note = None;
            ui.memory_mut(|m| m.request_focus(Id::unique(BAR_ID)));
        }
    }
    let multi = debugger.project().is_multi();
    if multi {
        let m = debugger.machine();
        file_tabs(
            ui,
            debugger,
            view,
            m.pc_line().filter(|_| m.run_state().is_live()),
        );
    }
    // This file's diagnostics, at its own line numbers.
    let diagnostics: Vec<Diagnostic> = debugger
        .diagnostics()
        .iter()
        .filter_map(|d| {
            Some(Diagnostic {
                line: to_local(d.line)?,
                ..d.clone()
            })
        })
        .collect();
    view.lines.update(debugger.source());
    // The row view of long programs shows the top file.
    let long = file == 0 && view.lines.text_lines() > EDIT_IN_PLACE_LINES;
    let header = ui
        .horizontal(|ui| {
            // The tab says "Program"; the header names it, and names the editor for screen
            // readers.
            let shown = if multi {
                debugger.project().files[file].name.as_str()
            } else {
                debugger.name()
            };
            let label = ui.label(RichText::new(shown).monospace().strong());
            if long {
                super::code_rows::edit_switch(ui, view, view.lines.text_lines());
            }
            if debugger.is_file_edited(file) {
                ui.label(
                    RichText::new("edited: Ctrl+Enter assembles (or just step / run)")
                        .color(p.written),
                );
            } else if debugger.is_edited() {
                ui.label(
                    RichText::new("another file is edited: Ctrl+Enter assembles them all")
                        .color(p.written),
                );
            }
            label.id
        })
        .inner;
    if view.bar.is_some() {
        bar(ui, debugger, view);
    }
    if long && let Some(j) = view.pending_jump.as_mut() {
        j.line = Project::split(j.line).1;
    }
    if long && !view.edit_long {
        if let Some(jump) = view.pending_jump.take() {
            view.cursor_line = Some(jump.line);
            view.scroll_to = Some(jump.line);
        }
        super::code_rows::show(ui, debugger, view, out);
        return;
    }
    let font = TextStyle::Monospace.resolve(ui.style());
    let row_height = ui.fonts_mut(|f| f.row_height(&font));
    let char_width = ui.fonts_mut(|f| f.glyph_width(&font, '0'));
    let mut text = shown_text(debugger, file).to_string();
    let line_count = text.lines().count().max(1) + usize::from(text.ends_with('\n'));
    let digits = line_count.to_string().len().max(3);
    let addresses = if view.addresses {
        debugger.machine().line_addresses()
    } else {
        Vec::new()
    };
    let address_width = if addresses.is_empty() { 0.0 } else { 7.0 };
    let gutter_width = char_width * (digits as f32 + 3.5 + address_width);
    let machine = debugger.machine();
    let pc_line = machine
        .pc_line()
        .filter(|_| machine.run_state().is_live())
        .and_then(to_local);
    let fault_line = machine.fault().and_then(|f| to_local(f.line));
    let text_id = Id::unique(TEXT_ID);

    // PageUp/PageDown move the caret by a screenful (the text editor itself ignores them).
    let editor_focused = ui.memory(|m| m.has_focus(text_id));
    if editor_focused && view.pending_jump.is_none() {
        let page = ((view.editor_height / row_height).floor() as usize).max(1);
        let (line, col) = line_col(&text, view.cursor_char.unwrap_or(0));
        let (up, down) = ui.input_mut(|i| {
            (
                i.consume_key(egui::Modifiers::NONE, egui::Key::PageUp),
                i.consume_key(egui::Modifiers::NONE, egui::Key::PageDown),
            )
        });
        let target = if down {
            Some((line + page).min(line_count))
        } else if up {
            Some(line.saturating_sub(page).max(1))
        } else {
            None
        };
        if let Some(line) = target {
            view.pending_jump = Some(Jump { line, col, len: 0 });
        }
    }
    let jump = view.pending_jump.take();
    if jump.is_none() && std::mem::take(&mut view.focus_again) {
        ui.memory_mut(|m| m.request_focus(text_id));
    }
    let jump = jump.map(|j| Jump {
        line: Project::split(j.line).1,
        ..j
    });
    if let Some(j) = jump {
        let ctx = ui.ctx().clone();
        let mut state = egui::TextEdit::load_state(&ctx, text_id).unwrap_or_default();
        let index = char_of(&text, j.line, j.col);
        state.cursor.set_char_range(Some(CCursorRange::two(
            CCursor::new(index),
            CCursor::new(index + j.len),
        )));
        state.store(&ctx, text_id);
        ctx.memory_mut(|m| m.request_focus(text_id));
        view.focus_again = true;
        view.cursor_line = Some(base + j.line);
        view.cursor_char = Some(index);
    }
    let enter_pressed =
        editor_focused && ui.input(|i| i.key_pressed(egui::Key::Enter) && i.modifiers.is_none());

    let scrolled = egui::ScrollArea::both()
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

                let classify = debugger.dialect().classify;
                let mut layouter = |ui: &egui::Ui, buf: &dyn egui::TextBuffer, _wrap: f32| {
                    let job = highlight(buf.as_str(), classify, &p, &font);
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
                // Outputs skipped on an unpowered rung are greyed over.
                // Code the scan did not run at all (jumped over, an inactive stage) more so.
                let power: Vec<(usize, servoscope_core::machine::LinePower)> = machine
                    .as_plc()
                    .map(|plc| plc.line_power())
                    .unwrap_or_default()
                    .into_iter()
                    .filter_map(|(l, s)| Some((to_local(l)?, s)))
                    .collect();
                let skipped: Vec<(Option<usize>, egui::Color32)> = power
                    .iter()
                    .filter(|(_, s)| *s == servoscope_core::machine::LinePower::Skipped)
                    .map(|(l, _)| (Some(*l), p.dim.gamma_multiply(0.25)))
                    .collect();
                // Code the scan did not run at all (jumped over, an inactive stage): its text
                // fades under a veil of the background.
                // Code that ran with its outputs forced off (an MCS area whose MC is 0) fades
                // less: it still ran.
                let background = ui.visuals().extreme_bg_color;
                let veils: Vec<egui::Shape> = power
                    .iter()
                    .filter_map(|(l, s)| match s {
                        servoscope_core::machine::LinePower::NotRun => {
                            Some((l, background.gamma_multiply(0.6)))
                        }
                        servoscope_core::machine::LinePower::MasterOff => {
                            Some((l, background.gamma_multiply(0.45)))
                        }
                        _ => None,
                    })
                    .filter_map(|(l, veil)| {
                        let rect = rows.rect(*l)?;
                        // From the text's first column (it starts at the gutter's edge).
                        let rect = rect
                            .with_min_x(rect.left() - 4.0)
                            .with_max_x(ui.clip_rect().right() + 2000.0);
                        Some(egui::Shape::rect_filled(rect, 0.0, veil))
                    })
                    .collect();
                ui.painter().extend(veils);
                let fills: Vec<egui::Shape> =
                    [(pc_line, p.current_line), (fault_line, p.fault_line)]
                        .into_iter()
                        .chain(skipped)
                        .filter_map(|(line, fill)| {
                            let rect = rows
                                .rect(line?)?
                                .with_max_x(ui.clip_rect().right() + 2000.0);
                            Some(egui::Shape::rect_filled(rect, 0.0, fill))
                        })
                        .collect();
                ui.painter().set(backgrounds, egui::Shape::Vec(fills));
                let clip = ui.clip_rect();
                let notes: Vec<(usize, String)> = machine
                    .line_notes()
                    .into_iter()
                    .filter_map(|(l, n)| Some((to_local(l)?, n)))
                    .collect();
                line_notes(ui, &notes, clip.right(), |l| rows.rect(l), &p);
                ui.painter().extend(error_underlines(
                    &output.galley,
                    output.galley_pos,
                    1,
                    &diagnostics,
                    rows.visible(clip.top(), clip.bottom()),
                    p.error,
                    p.written,
                ));
                // When the pane's height changes (the window is laid out, or resized) the line
                // about to run is brought back into view if it fell out of it.
                let resized = (view.pc_view_height - clip.height()).abs() > 0.5;
                view.pc_view_height = clip.height();
                // Hidden also when cut by the pane's edge.
                let pc_hidden = pc_line.is_some_and(|l| {
                    !rows
                        .rect(l)
                        .is_some_and(|r| r.top() >= clip.top() && r.bottom() <= clip.bottom())
                });
                let moved_to = jump.map(|j| j.line).or_else(|| pc_moved(view, pc_line));
                // After a resize the line comes back to the middle: asked again in the frames
                // of one resize, a centre stays put where a minimal scroll would add up.
                let recentre = moved_to.is_none() && resized && pc_hidden;
                let scroll_to = moved_to.or(if recentre { pc_line } else { None });
                if let Some(rect) = scroll_to.and_then(|line| rows.rect(line)) {
                    // Two lines of margin, so the line never hides under a scroll bar.
                    // Only vertically: from the gutter's edge, so the line numbers stay in view
                    // in a narrow window.
                    let rect = rect
                        .with_min_x(gutter.left())
                        .with_max_x(gutter.left() + 1.0)
                        .expand2(vec2(0.0, 2.0 * row_height));
                    ui.scroll_to_rect(rect, recentre.then_some(egui::Align::Center));
                }
                let mut caret = output.cursor_range.map(|r| r.primary.index.0);
                if output.response.changed() {
                    if enter_pressed && let Some(at) = caret {
                        caret = Some(keep_indent(ui.ctx(), text_id, &mut text, at));
                    }
                    out.push(Command::EditFile(file, text.clone()));
                }
                if let Some(at) = caret {
                    view.cursor_line = Some(base + line_of_char(&text, at));
                    view.cursor_char = Some(at);
                }
                // Ctrl+click on an `#include` line opens the file it names.
                if output.response.clicked()
                    && ui.input(|i| i.modifiers.command)
                    && let Some(pos) = output.response.interact_pointer_pos()
                    && let Some(line) = rows.line_at(pos.y)
                    && let Some(target) = text
                        .lines()
                        .nth(line - 1)
                        .and_then(|l| included_file(debugger, file, l))
                {
                    view.pending_jump = Some(Jump::line(Project::line(target, 1)));
                }
                if let Some(pos) = output.response.hover_pos()
                    && let Some(line) = rows.line_at(pos.y)
                {
                    let include_hint = text
                        .lines()
                        .nth(line - 1)
                        .and_then(|l| included_file(debugger, file, l))
                        .map(|k| format!("Ctrl+click opens {}", debugger.project().files[k].name));
                    let messages: Vec<String> = diagnostics
                        .iter()
                        .filter(|d| d.line == line)
                        .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
                        .collect();
                    let under = output
                        .galley
                        .cursor_from_pos(pos - output.galley_pos)
                        .index
                        .0;
                    let value = word_at(&text, under)
                        .and_then(|word| hover_value(debugger.machine(), &word))
                        .or_else(|| mnemonic_hover(debugger.dialect(), &token_at(&text, under)));
                    let tip: Vec<String> = messages
                        .into_iter()
                        .chain(include_hint)
                        .chain(value)
                        .collect();
                    if !tip.is_empty() {
                        egui::Response::clone(&output.response).on_hover_ui_at_pointer(|ui| {
                            ui.label(RichText::new(tip.join("\n\n")).monospace());
                        });
                    }
                }
                // Right-click on a name: who wrote it, break on it, watch it.
                if output.response.secondary_clicked()
                    && let Some(pos) = output.response.interact_pointer_pos()
                {
                    let under = output
                        .galley
                        .cursor_from_pos(pos - output.galley_pos)
                        .index
                        .0;
                    view.menu_location = word_at(&text, under).and_then(|word| {
                        let m = debugger.machine();
                        let loc = m.find(&word).or_else(|| {
                            m.program_names()
                                .into_iter()
                                .find(|(n, _)| n.eq_ignore_ascii_case(&word))
                                .map(|(_, l)| l)
                        })?;
                        Some((m.info(loc)?.name, loc))
                    });
                }
                if let Some((name, loc)) = view.menu_location.clone() {
                    egui::Response::clone(&output.response).context_menu(|ui| {
                        super::breakpoints::location_menu(ui, debugger.machine(), &name, loc, out);
                    });
                }
                let gutter_view = GutterView {
                    base,
                    diagnostics: &diagnostics,
                    power: &power,
                    addresses: &addresses,
                };
                gutter_ui(
                    ui,
                    debugger,
                    gutter,
                    &rows,
                    pc_line,
                    &gutter_view,
                    &p,
                    &font,
                    out,
                );
            });
            // Clicking below the last line puts the caret at the end, as in any editor.
            let below = ui.available_rect_before_wrap();
            if below.height() > 0.0
                && ui
                    .allocate_rect(below, Sense::click())
                    .on_hover_cursor(egui::CursorIcon::Text)
                    .clicked()
            {
                view.pending_jump = Some(Jump {
                    line: line_count,
                    col: usize::MAX,
                    len: 0,
                });
            }
        });
    view.editor_height = scrolled.inner_rect.height();
}

/// After Enter: the new line starts with the indentation of the line before. Returns the caret.
fn keep_indent(ctx: &egui::Context, id: Id, text: &mut String, caret: usize) -> usize {
    let chars: Vec<char> = text.chars().collect();
    if caret == 0 || chars.get(caret - 1) != Some(&'\n') {
        return caret;
    }
    let previous_start = chars[..caret - 1]
        .iter()
        .rposition(|&c| c == '\n')
        .map_or(0, |i| i + 1);
    let indent: String = chars[previous_start..caret - 1]
        .iter()
        .take_while(|c| **c == ' ' || **c == '\t')
        .collect();
    if indent.is_empty() {
        return caret;
    }
    let byte = text
        .char_indices()
        .nth(caret)
        .map_or(text.len(), |(b, _)| b);
    text.insert_str(byte, &indent);
    let caret = caret + indent.chars().count();
    let mut state = egui::TextEdit::load_state(ctx, id).unwrap_or_default();
    state
        .cursor
        .set_char_range(Some(CCursorRange::one(CCursor::new(caret))));
    state.store(ctx, id);
    caret
}

pub const BAR_ID: &str = "code_bar_field";

/// The find / go-to-line bar.
fn bar(ui: &mut egui::Ui, debugger: &Debugger, view: &mut CodeView) {
    let Some(kind) = view.bar else {
        return;
    };
    let p = palette(ui.visuals().dark_mode);
    let text = shown_text(debugger, view.file);
    let base = view.program_line(0);
    let field_id = Id::unique(BAR_ID);
    ui.horizontal_wrapped(|ui| {
        let label = ui.label(match kind {
            Bar::Find => "Find in program",
            Bar::GoToLine => "Go to line",
        });
        let field = ui
            .add(
                egui::TextEdit::singleline(&mut view.bar_text)
                    .id(field_id)
                    .desired_width(160.0),
            )
            .labelled_by(label.id);
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        let shift = ui.input(|i| i.modifiers.shift);
        if entered {
            // The editor takes focus for the caret this same frame: it must not get this Enter.
            ui.input_mut(|i| {
                i.consume_key(egui::Modifiers::NONE, egui::Key::Enter);
                i.consume_key(egui::Modifiers::SHIFT, egui::Key::Enter);
            });
        }
        let escape = (field.has_focus() || field.lost_focus())
            && ui.input(|i| i.key_pressed(egui::Key::Escape));
        let mut search = None;
        match kind {
            Bar::Find => {
                if ui.button("Next").clicked() || (entered && !shift) {
                    search = Some(false);
                }
                if ui.button("Previous").clicked() || (entered && shift) {
                    search = Some(true);
                }
            }
            Bar::GoToLine => {
                let lines = text.lines().count().max(1);
                if ui.button("Go").clicked() || entered {
                    match view.bar_text.trim().parse::<usize>() {
                        Ok(line) if (1..=lines).contains(&line) => {
                            view.pending_jump = Some(Jump::line(base + line));
                            view.bar = None;
                        }
                        _ => {
                            view.bar_note = Some(format!(
                                "'{}' is not a line: 1 to {lines}",
                                view.bar_text.trim()
                            ))
                        }
                    }
                }
            }
        }
        if let Some(backwards) = search {
            let caret = view.cursor_char.unwrap_or(0);
            let needle_len = view.bar_text.trim().chars().count();
            // After a match the caret sits at its end: "Previous" starts before it.
            let from = if backwards {
                caret.saturating_sub(needle_len)
            } else {
                caret + 1
            };
            match find_match(text, view.bar_text.trim(), from, backwards) {
                Some((at, count, number)) => {
                    let (line, col) = line_col(text, at);
                    view.pending_jump = Some(Jump {
                        line: base + line,
                        col,
                        len: view.bar_text.trim().chars().count(),
                    });
                    view.bar_note = Some(format!("{number} of {count}"));
                }
                None => view.bar_note = Some("not found".to_string()),
            }
        }
        if let Some(note) = &view.bar_note {
            ui.label(RichText::new(note).color(p.dim));
        }
        if ui
            .small_button("Close bar")
            .on_hover_text("Escape")
            .clicked()
            || escape
        {
            view.bar = None;
        }
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
    /// Top and bottom of each line, in screen coordinates; line n is index n - 1.
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

/// What the gutter shows of the file in view, at its own line numbers.
struct GutterView<'a> {
    /// The program line before the file's first (its lines are `base + 1 ..`).
    base: usize,
    diagnostics: &'a [Diagnostic],
    power: &'a [(usize, servoscope_core::machine::LinePower)],
    /// Program lines and the address of the statement starting each (when shown).
    addresses: &'a [(usize, u32)],
}

#[allow(clippy::too_many_arguments)]
fn gutter_ui(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    gutter: Rect,
    rows: &LineRows,
    pc_line: Option<usize>,
    gv: &GutterView<'_>,
    p: &Palette,
    font: &FontId,
    out: &mut Vec<Command>,
) {
    let clip = ui.clip_rect();
    let base = gv.base;
    let error_lines: Vec<usize> = gv.diagnostics.iter().map(|d| d.line).collect();
    let warning_only = |line: usize| {
        gv.diagnostics
            .iter()
            .filter(|d| d.line == line)
            .all(|d| d.severity == servoscope_core::machine::Severity::Warning)
    };
    let power = gv.power;
    // Per line: whether any breakpoint is on it, any enabled, and any with more than a line.
    let marks: std::collections::BTreeMap<usize, (bool, bool)> = debugger
        .breakpoint_list()
        .iter()
        .filter_map(|b| {
            let line = b.line_number()?;
            (line > base && line < base + FILE_LINES).then(|| (line - base, b))
        })
        .fold(Default::default(), |mut acc, (line, b)| {
            let entry = acc.entry(line).or_insert((false, false));
            entry.0 |= b.enabled;
            entry.1 |= !b.is_plain() && b.enabled;
            acc
        });
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
        let mark = marks.get(&line).copied();
        let has_bp = mark.is_some_and(|(enabled, _)| enabled);
        response
            .widget_info(|| egui::WidgetInfo::selected(egui::Role::CheckBox, true, has_bp, &label));
        if response.clicked() {
            out.push(Command::ToggleBreakpoint(base + line));
        }
        let response = response.on_hover_text_at_pointer(
            "Click: breakpoint. Right-click: a conditional breakpoint or a log point",
        );
        response.context_menu(|ui| {
            if ui.button("Add a conditional breakpoint").clicked() {
                out.push(Command::AddBreakpoint(
                    servoscope_core::debugger::Breakpoint::line(base + line).with_condition("1"),
                ));
                ui.close();
            }
            if ui.button("Add a log point").clicked() {
                out.push(Command::AddBreakpoint(
                    servoscope_core::debugger::Breakpoint::line(base + line)
                        .with_log(format!("line {}", debugger.describe_line(base + line))),
                ));
                ui.close();
            }
        });
        let painter = ui.painter();
        let has_error = error_lines.contains(&line);
        if response.hovered() && !has_bp {
            painter.circle_filled(
                row.left_center() + vec2(row_height * 0.5, 0.0),
                row_height * 0.3,
                p.breakpoint.gamma_multiply(0.35),
            );
        }
        match mark {
            // Enabled, with a condition, count or message: a ring around a dot.
            Some((true, true)) => {
                let centre = row.left_center() + vec2(row_height * 0.5, 0.0);
                painter.circle_stroke(centre, row_height * 0.32, Stroke::new(1.5, p.breakpoint));
                painter.circle_filled(centre, row_height * 0.16, p.breakpoint);
            }
            Some((true, false)) => {
                painter.circle_filled(
                    row.left_center() + vec2(row_height * 0.5, 0.0),
                    row_height * 0.32,
                    p.breakpoint,
                );
            }
            // Disabled: an outline.
            Some((false, _)) => {
                painter.circle_stroke(
                    row.left_center() + vec2(row_height * 0.5, 0.0),
                    row_height * 0.3,
                    Stroke::new(1.0, p.breakpoint.gamma_multiply(0.6)),
                );
            }
            None => {}
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
        // Rung power after this line's instruction (ladder dialects): a bar at the gutter's edge.
        if let Some((_, state)) = power.iter().find(|(l, _)| *l == line) {
            let colour = match state {
                servoscope_core::machine::LinePower::On => p.bit_on,
                servoscope_core::machine::LinePower::Off
                | servoscope_core::machine::LinePower::Skipped
                | servoscope_core::machine::LinePower::MasterOff => p.dim,
                servoscope_core::machine::LinePower::NotRun => egui::Color32::TRANSPARENT,
            };
            let bar = Rect::from_min_max(
                pos2(row.right() - 3.0, row.top() + 2.0),
                pos2(row.right() - 1.0, row.bottom() - 2.0),
            );
            painter.rect_filled(bar, 0.0, colour);
        }
        let number_color = match has_error {
            true if warning_only(line) => p.written,
            true => p.error,
            false => p.dim,
        };
        painter.text(
            row.right_center() - vec2(6.0, 0.0),
            egui::Align2::RIGHT_CENTER,
            line.to_string(),
            font.clone(),
            number_color,
        );
        // The address of the line's first statement in program memory.
        if let Ok(k) = gv
            .addresses
            .binary_search_by_key(&(base + line), |&(l, _)| l)
        {
            painter.text(
                pos2(row.left() + row_height * 1.6, row.center().y),
                egui::Align2::LEFT_CENTER,
                format!("{:04X}", gv.addresses[k].1),
                font.clone(),
                p.dim,
            );
        }
        if has_error {
            let messages: Vec<String> = gv
                .diagnostics
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
    // As tall as its rows (up to six), never more than half the pane: one error must not take
    // the room of the program it is about. A new panel per row count, so it refits when the
    // count changes; a size the user dragged holds while it stays the same.
    let rows_shown = debugger.diagnostics().len().min(6);
    let row_height = ui.spacing().interact_size.y + ui.spacing().item_spacing.y;
    let fit = row_height * (rows_shown as f32 + 1.0) + 12.0;
    egui::Panel::bottom(Id::unique(("problems", rows_shown)))
        .resizable(true)
        .default_size(fit)
        .min_size(fit.min(60.0))
        .max_size((ui.available_height() * 0.5).max(fit.min(60.0)))
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.strong(format!("Problems ({})", debugger.diagnostics().len()));
                let note = if debugger.has_errors() {
                    "Nothing runs until the errors are fixed."
                } else {
                    "Warnings only: the program runs."
                };
                ui.label(egui::RichText::new(note).color(p.dim));
            });
            let diagnostics = debugger.diagnostics();
            let row_height = ui.spacing().interact_size.y;
            // Only the visible rows are laid out: a file with 100,000 errors stays responsive.
            egui::ScrollArea::vertical()
                .id_salt("problems_scroll")
                .auto_shrink([false, true])
                .show_rows(ui, row_height, diagnostics.len(), |ui, rows| {
                    for d in &diagnostics[rows] {
                        let warning = d.severity == servoscope_core::machine::Severity::Warning;
                        let text = format!(
                            "{}:{}  {}{}",
                            debugger.describe_line(d.line),
                            d.col,
                            if warning { "warning: " } else { "" },
                            servoscope_core::machine::diagnostics::printable(&d.message)
                        );
                        let r = ui.add(
                            egui::Button::selectable(
                                false,
                                egui::RichText::new(text).color(if warning {
                                    p.written
                                } else {
                                    p.error
                                }),
                            )
                            .min_size(Vec2::ZERO),
                        );
                        if r.clicked() {
                            view.pending_jump = Some(Jump {
                                line: d.line,
                                col: d.col,
                                len: 0,
                            });
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
        let classify = servoscope_core::machine::silverlode::syntax::classify;
        let job = highlight(text, classify, &palette(true), &FontId::monospace(12.0));
        assert_eq!(job.text, text);
    }

    /// Issue #22 item 13: an error's underline lies inside its own row, under its own columns,
    /// so a line scrolled out of view leaves nothing on the line below it.
    #[test]
    fn error_underlines_stay_inside_their_row() {
        let text = "WRP 11, 1\n\nbad: BOGUS ; x\nEND\n";
        let diags = vec![Diagnostic::error(3, 6, 5, "unknown")];
        let classify = servoscope_core::machine::silverlode::syntax::classify;
        let ctx = egui::Context::default();
        let mut shapes = Vec::new();
        let mut rows = Vec::new();
        let mut output = ctx.run_ui(egui::RawInput::default(), |ui| {
            let job = highlight(text, classify, &palette(true), &FontId::monospace(12.0));
            let galley = ui.fonts_mut(|f| f.layout_job(job));
            let origin = pos2(10.0, 20.0);
            rows = galley
                .rows
                .iter()
                .map(|r| r.rect().translate(origin.to_vec2()))
                .collect();
            shapes = error_underlines(
                &galley,
                origin,
                1,
                &diags,
                1..5,
                egui::Color32::RED,
                egui::Color32::YELLOW,
            );
            assert!(
                error_underlines(
                    &galley,
                    origin,
                    1,
                    &diags,
                    4..5,
                    egui::Color32::RED,
                    egui::Color32::YELLOW
                )
                .is_empty()
            );
        });
        output.textures_delta.clear();
        assert_eq!(shapes.len(), 1);
        let bounds = shapes[0].visual_bounding_rect();
        let row = rows[2];
        assert!(
            bounds.top() >= row.top() && bounds.bottom() <= row.bottom(),
            "{bounds:?} leaves row {row:?}"
        );
        let egui::Shape::LineSegment { points, .. } = shapes[0] else {
            panic!("a line");
        };
        let char_width = row.width() / "bad: BOGUS ; x".len() as f32;
        assert!((points[0].x - (row.left() + 5.0 * char_width)).abs() < 0.5);
        assert!((points[1].x - points[0].x - 5.0 * char_width).abs() < 0.5);
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
