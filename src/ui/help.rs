//! The Help panel: the dialect's instruction reference, read from `docs/<dialect>.md` (embedded)
//! and rendered as Markdown, so the window and the document never disagree. F1 (or Help →
//! Reference) opens it at the mnemonic under the caret.

use egui::RichText;
use egui_commonmark::{CommonMarkCache, CommonMarkViewer};

use servoscope_core::debugger::Debugger;
use servoscope_core::machine::reference;

pub const TITLE: &str = "Help";

#[derive(Default)]
pub struct HelpView {
    /// The mnemonic whose entry is shown; `None`: the whole document.
    pub selected: Option<String>,
    pub filter: String,
    cache: CommonMarkCache,
}

impl HelpView {
    /// Show `mnemonic`'s entry (the whole reference when it has none).
    pub fn open_at(&mut self, mnemonic: Option<&str>) {
        self.selected = mnemonic.map(str::to_ascii_uppercase);
    }
}

pub fn show(ui: &mut egui::Ui, debugger: &Debugger, view: &mut HelpView) {
    let dialect = debugger.dialect();
    let entries = reference::entries(dialect.reference);
    let entry = view
        .selected
        .as_deref()
        .and_then(|s| entries.iter().find(|e| e.covers(s)));
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(format!("{} reference", dialect.display_name)).strong());
        let label = ui.label("Find");
        ui.add(
            egui::TextEdit::singleline(&mut view.filter)
                .desired_width(90.0)
                .hint_text("mnemonic")
                .id_salt("help_filter"),
        )
        .labelled_by(label.id);
        if ui
            .selectable_label(view.selected.is_none(), "Whole document")
            .clicked()
        {
            view.selected = None;
        }
    });
    let filter = view.filter.trim().to_ascii_uppercase();
    let height = ui.available_height();
    ui.horizontal_top(|ui| {
        let column = egui::Layout::top_down(egui::Align::LEFT);
        ui.allocate_ui_with_layout(egui::vec2(130.0, height), column, |ui| {
            egui::ScrollArea::vertical()
                .id_salt("help_index")
                .auto_shrink([false, false])
                .show(ui, |ui| {
                    for e in &entries {
                        // Names first; then the titles and texts (MULT_S64_SHR16 is in CLD's).
                        if !filter.is_empty()
                            && !e.names.iter().any(|n| n.contains(&filter))
                            && !e.title.to_ascii_uppercase().contains(&filter)
                            && !e.markdown.to_ascii_uppercase().contains(&filter)
                        {
                            continue;
                        }
                        let shown = entry.is_some_and(|s| s.names == e.names);
                        let name = e.names.join(", ");
                        if ui
                            .selectable_label(shown, RichText::new(&name).monospace())
                            .on_hover_text(&e.title)
                            .clicked()
                        {
                            view.selected = e.names.first().cloned();
                        }
                    }
                });
        });
        ui.separator();
        let text = match entry {
            Some(e) => e.markdown.clone(),
            None => match &view.selected {
                Some(s) => format!(
                    "*{s} has no entry in the {} reference.*\n\n{}",
                    dialect.display_name, dialect.reference
                ),
                None => dialect.reference.to_string(),
            },
        };
        let room = egui::vec2(ui.available_width(), height);
        ui.allocate_ui_with_layout(room, column, |ui| {
            egui::ScrollArea::vertical()
                .id_salt("help_text")
                .auto_shrink([false, false])
                .show(ui, |ui| {
                    CommonMarkViewer::new().show(ui, &mut view.cache, &text);
                });
        });
    });
}
