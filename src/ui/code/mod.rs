//! The program view: line numbers, breakpoints in the gutter, syntax colouring, the line about
//! to run highlighted and kept in view, errors underlined on their lines, and the problems list.

use egui::text::{CCursor, CCursorRange, LayoutJob, TextFormat};
use egui::{FontId, Id, Rect, RichText, Sense, Stroke, TextStyle, Vec2, pos2, vec2};
use servoscope_core::debugger::Action;

use super::Command;
use super::theme::{Palette, palette};
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::Diagnostic;
use servoscope_core::machine::project::{FILE_LINES, Project};
use servoscope_core::registry::TokenClass;

mod find;
mod gutter;
mod hover;
mod problems;
mod text;

use find::bar;
pub use find::{BAR_ID, find_match};
use gutter::{GutterView, LineRows, gutter_ui};
pub use hover::{hover_value, mnemonic_hover, mnemonic_in};
use problems::problems;
use text::*;
pub use text::{append_line, error_underlines, highlight, line_notes};

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
    crate::ui::window_state::note_scroll_area(ui.ctx(), "code", scrolled.id);
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

/// The line about to run, when it moved since the last frame: scroll it into view once.
fn pc_moved(view: &mut CodeView, pc_line: Option<usize>) -> Option<usize> {
    if pc_line.is_some() && pc_line != view.last_pc_line {
        view.last_pc_line = pc_line;
        return pc_line;
    }
    None
}

#[cfg(test)]
mod tests;
