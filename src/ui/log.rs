//! The Log panel: the log points' messages, and the execution log — the instructions executed up
//! to the current position, newest last, each with its position, line, explanation and the
//! locations it wrote. Click an entry to go there; filter by line or by location written;
//! export what is shown as CSV.
//!
//! The log is recomputed from the timeline (a bounded replay) only when the position, the
//! history or the filter changed, and only while the panel is shown.

use egui::RichText;
use servoscope_core::debugger::Action;

use super::Command;
use super::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::debugger::log::{ExecutionLog, LogFilter, LogSearch};
use servoscope_core::machine::Pos;

/// Entries shown at most.
pub const MAX_ROWS: usize = 500;
/// Ticks searched back at most for a filter that matches rarely.
pub const MAX_SEARCH_TICKS: u64 = 2_000_000;
/// Wall time a frame gives the log's search; the rest goes on in the next frames. Each step of
/// the search replays at most one checkpoint interval, so a frame overshoots this by at most
/// one step.
pub const SEARCH_PER_FRAME: std::time::Duration = std::time::Duration::from_millis(8);

const FILTERS: [&str; 3] = ["every instruction", "line", "writes to"];

#[derive(Default)]
pub struct LogView {
    /// 0 all, 1 line, 2 writes to a location.
    pub filter_kind: usize,
    pub filter_text: String,
    pub log: ExecutionLog,
    pub filter_error: Option<String>,
    /// What the shown log was computed for.
    key: Option<(u64, Pos, Pos, usize, LogFilter)>,
    /// Scroll to the newest entry on the next draw.
    scroll_to_end: bool,
    /// The search in progress for `key`, going on over frames.
    search: Option<LogSearch>,
}

/// A line as a user types it: `12`, or `setup.tml:12` in a program of several files.
fn parse_line(debugger: &Debugger, text: &str) -> Option<usize> {
    use servoscope_core::machine::project::Project;
    match text.rsplit_once(':') {
        Some((file, line)) => {
            let file = debugger.project().index_of(file.trim())?;
            Some(Project::line(file, line.trim().parse().ok()?))
        }
        None => text.parse().ok(),
    }
}

impl LogView {
    fn filter(&mut self, debugger: &Debugger) -> LogFilter {
        let text = self.filter_text.trim();
        self.filter_error = None;
        match self.filter_kind {
            1 => match parse_line(debugger, text) {
                Some(line) => LogFilter::Line(line),
                None => {
                    if !text.is_empty() {
                        self.filter_error = Some(format!("'{text}' is not a line number"));
                    }
                    LogFilter::All
                }
            },
            2 => match debugger.find(text) {
                Some(loc) => LogFilter::Writes(loc),
                None => {
                    if !text.is_empty() {
                        self.filter_error = Some(format!("there is no location named '{text}'"));
                    }
                    LogFilter::All
                }
            },
            _ => LogFilter::All,
        }
    }

    /// Recompute the log if anything it depends on changed.
    pub fn refresh(&mut self, debugger: &mut Debugger) {
        if debugger.has_errors() || debugger.is_edited() || debugger.is_running() {
            return;
        }
        let filter = self.filter(debugger);
        let key = (
            debugger.generation(),
            debugger.pos(),
            debugger.furthest(),
            debugger.events().len(),
            filter,
        );
        if self.key.as_ref() != Some(&key) {
            self.search = Some(LogSearch::new(
                filter,
                MAX_ROWS,
                MAX_SEARCH_TICKS,
                debugger.pos(),
            ));
            self.key = Some(key);
        }
        self.go_on_searching(debugger, SEARCH_PER_FRAME);
    }

    /// Search on for `budget` (at least one step), showing what was found so far.
    pub fn go_on_searching(&mut self, debugger: &mut Debugger, budget: std::time::Duration) {
        let Some(search) = &mut self.search else {
            return;
        };
        let started = std::time::Instant::now();
        loop {
            debugger.search_log(search);
            if search.is_done() || started.elapsed() >= budget {
                break;
            }
        }
        self.log = debugger.log_found(search);
        self.scroll_to_end = true;
        if search.is_done() {
            self.search = None;
        }
    }

    /// Where the search in progress has got to (None when the log is complete).
    pub fn searching_from(&self) -> Option<Pos> {
        self.search.as_ref().map(LogSearch::searched_from)
    }

    /// The shown entries as CSV: position, line, explanation, written locations.
    /// Lines are as `project` names them (`12`, or `main.tml:12` with several files).
    pub fn write_csv(
        &self,
        w: &mut dyn std::io::Write,
        project: &servoscope_core::machine::project::Project,
    ) -> std::io::Result<()> {
        writeln!(w, "{}", servoscope_core::output::LOG_CSV_HEADER)?;
        for r in &self.log.rows {
            let written: Vec<String> = r.written.iter().map(|(n, v)| format!("{n}={v}")).collect();
            writeln!(
                w,
                "{},{},{},{},{},{}",
                r.at.tick,
                r.at.step,
                r.step,
                csv_field(&project.describe(r.line)),
                csv_field(&r.explanation),
                csv_field(&written.join(" "))
            )?;
        }
        Ok(())
    }
}

/// A CSV field, quoted when it needs to be.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

pub fn show(ui: &mut egui::Ui, debugger: &Debugger, view: &mut LogView, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    let tick = debugger.dialect().vocabulary.tick;
    let messages = debugger.log_messages();
    if !messages.is_empty() {
        egui::CollapsingHeader::new(format!("Log point messages ({})", messages.len()))
            .id_salt("log_messages")
            .default_open(true)
            .show(ui, |ui| {
                egui::ScrollArea::vertical()
                    .id_salt("log_messages_scroll")
                    .max_height(100.0)
                    .stick_to_bottom(true)
                    .show(ui, |ui| {
                        for m in messages.iter().rev().take(MAX_ROWS).rev() {
                            let text = format!(
                                "{tick} {} · {}: {}",
                                m.at,
                                debugger.where_line(m.line),
                                m.text
                            );
                            if ui
                                .add(
                                    egui::Label::new(RichText::new(text).monospace())
                                        .sense(egui::Sense::click()),
                                )
                                .on_hover_text("Go there")
                                .clicked()
                            {
                                out.push(Command::Debug(Action::GoTo(m.at)));
                            }
                        }
                    });
            });
        ui.separator();
    }
    drop(messages);
    ui.horizontal_wrapped(|ui| {
        ui.label("Show");
        egui::ComboBox::new("log_filter", "")
            .selected_text(FILTERS[view.filter_kind.min(2)])
            .show_ui(ui, |ui| {
                for (k, f) in FILTERS.iter().enumerate() {
                    ui.selectable_value(&mut view.filter_kind, k, *f);
                }
            })
            .response
            .widget_info(|| egui::WidgetInfo::labeled(egui::Role::ComboBox, true, "Log shows"));
        if view.filter_kind > 0 {
            ui.add(
                egui::TextEdit::singleline(&mut view.filter_text)
                    .hint_text(if view.filter_kind == 1 {
                        "7"
                    } else {
                        debugger.dialect().vocabulary.location_hint
                    })
                    .desired_width(70.0),
            )
            .widget_info(|| egui::WidgetInfo::labeled(egui::Role::TextInput, true, "Log filter"));
        }
        if ui.button("Export CSV…").clicked() {
            out.push(Command::ExportLogDialog);
        }
    });
    if let Some(e) = &view.filter_error {
        ui.colored_label(p.error, e);
    }
    if debugger.is_running() {
        ui.label(RichText::new("Running: the log shows when the run stops.").color(p.dim));
        return;
    }
    let log = &view.log;
    if let Some(from) = view.searching_from() {
        ui.ctx().request_repaint();
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(
                RichText::new(format!("Searching back… at {tick} {from}"))
                    .small()
                    .color(p.dim),
            );
        });
    } else if log.rows.is_empty() {
        ui.label(RichText::new("Nothing executed before here matches.").color(p.dim));
    } else if !log.complete && log.rows.len() < MAX_ROWS {
        ui.label(
            RichText::new(format!("Searched back to {tick} {}.", log.searched_from))
                .small()
                .color(p.dim),
        );
    }
    let row_height = ui.text_style_height(&egui::TextStyle::Monospace) + 2.0;
    let mut area = egui::ScrollArea::both()
        .id_salt("execution_log")
        .auto_shrink([false, false]);
    if std::mem::take(&mut view.scroll_to_end) {
        // Rows are spaced by the item spacing too; past the end is clamped to the last row.
        let pitch = row_height + ui.spacing().item_spacing.y;
        area = area.vertical_scroll_offset(pitch * (log.rows.len() + 1) as f32);
    }
    let shown = area.show_rows(ui, row_height, log.rows.len(), |ui, range| {
        for r in &log.rows[range] {
            let written: Vec<String> = r.written.iter().map(|(n, v)| format!("{n}={v}")).collect();
            let text = format!(
                "{:>9}  {:>4}  {}{}",
                r.at.to_string(),
                debugger.describe_line(r.line),
                r.explanation,
                if written.is_empty() {
                    String::new()
                } else {
                    format!("   -> {}", written.join(" "))
                }
            );
            let here = r.at == debugger.pos();
            let label = egui::Label::new(RichText::new(text).monospace().color(if here {
                p.written
            } else {
                ui.visuals().text_color()
            }))
            .wrap_mode(egui::TextWrapMode::Extend)
            .sense(egui::Sense::click());
            if ui
                .add(label)
                .on_hover_text(format!("Go to {tick} {} (after it ran)", r.at))
                .clicked()
            {
                out.push(Command::Debug(Action::GoTo(r.at)));
            }
        }
    });
    crate::ui::window_state::note_scroll_area(ui.ctx(), "log", shown.id);
}
