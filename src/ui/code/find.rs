//! The find and go-to-line bar.

use super::*;

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

pub const BAR_ID: &str = "code_bar_field";

/// The find / go-to-line bar.
pub(super) fn bar(ui: &mut egui::Ui, debugger: &Debugger, view: &mut CodeView) {
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
