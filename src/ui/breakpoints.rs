//! The Breakpoints panel: every breakpoint with its kind, condition, hit count, log message and
//! enabled switch (edit, disable, delete, go to its line), a form for data breakpoints, and
//! "break on error flags". Also the menu every location offers: who wrote it, break on it,
//! watch it.

use egui::RichText;
use servoscope_core::debugger::Action;

use super::Command;
use super::theme::palette;
use servoscope_core::debugger::{BreakKind, Breakpoint, DataTrigger, Debugger};
use servoscope_core::machine::{Loc, value};

/// What the data-breakpoint form holds between frames.
#[derive(Default)]
pub struct BreakpointsView {
    pub location: String,
    /// 0 written, 1 changed, 2 equals.
    pub trigger: usize,
    pub equals: String,
    pub error: Option<String>,
}

const TRIGGERS: [&str; 3] = ["is written", "changes", "equals"];

pub fn show(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut BreakpointsView,
    out: &mut Vec<Command>,
) {
    let p = palette(ui.visuals().dark_mode);
    let mut on_error = debugger.break_on_error();
    if ui
        .checkbox(
            &mut on_error,
            format!("Break on error flags ({})", debugger.dialect().error_flags),
        )
        .changed()
    {
        out.push(Command::Debug(Action::SetBreakOnError(on_error)));
    }
    ui.label(
        RichText::new("A fault always stops the run: the program cannot go on after it.")
            .small()
            .color(p.dim),
    );
    ui.separator();
    data_form(ui, debugger, view, out);
    ui.separator();
    let list = debugger.breakpoint_list();
    if list.is_empty() {
        ui.label(
            RichText::new(
                "No breakpoints. Click a line number to set one; right-click a register for \
                 data breakpoints.",
            )
            .color(p.dim),
        );
        return;
    }
    egui::ScrollArea::vertical()
        .id_salt("breakpoint_list")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            for (i, b) in list.iter().enumerate() {
                row(ui, debugger, i, b, out);
                ui.separator();
            }
        });
}

fn row(ui: &mut egui::Ui, debugger: &Debugger, i: usize, b: &Breakpoint, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    let n = i + 1;
    let mut edited = b.clone();
    ui.horizontal(|ui| {
        ui.checkbox(&mut edited.enabled, "").widget_info(|| {
            egui::WidgetInfo::selected(
                egui::Role::CheckBox,
                true,
                b.enabled,
                format!("Enable breakpoint {n}"),
            )
        });
        let kind = if !b.log.is_empty() {
            "log point"
        } else if matches!(b.kind, BreakKind::Data { .. }) {
            "data"
        } else {
            "line"
        };
        match b.kind {
            BreakKind::Line(line) => {
                if ui
                    .link(format!("Line {}", debugger.describe_line(line)))
                    .on_hover_text("Show the line")
                    .clicked()
                {
                    out.push(Command::ShowLine(line));
                }
            }
            BreakKind::Data { .. } => {
                ui.label(RichText::new(b.describe(debugger.machine())).strong());
            }
        }
        ui.label(RichText::new(kind).small().color(p.dim));
        ui.label(
            RichText::new(format!("hits: {}", debugger.breakpoint_hits(i)))
                .small()
                .color(p.dim),
        );
        let delete = ui.small_button("×").on_hover_text("Delete");
        delete.widget_info(|| {
            egui::WidgetInfo::labeled(egui::Role::Button, true, format!("Delete breakpoint {n}"))
        });
        if delete.clicked() {
            out.push(Command::Debug(Action::RemoveBreakpoint(i)));
        }
    });
    ui.horizontal(|ui| {
        ui.label("if");
        let room = (ui.available_width() - 120.0).max(80.0);
        let words = debugger.dialect().vocabulary;
        text_field(
            ui,
            &mut edited.condition,
            &format!("always, or e.g. {}", words.condition_hint),
            format!("Condition of breakpoint {n}"),
            room,
        );
        ui.label("from hit");
        ui.add(egui::DragValue::new(&mut edited.hit_count).range(0..=u64::MAX))
            .on_hover_text("Let the first N - 1 hits pass (0 or 1: stop on every hit)")
            .widget_info(|| {
                egui::WidgetInfo::labeled(
                    egui::Role::SpinButton,
                    true,
                    format!("Hit count of breakpoint {n}"),
                )
            });
    });
    ui.horizontal(|ui| {
        ui.label("log");
        let room = ui.available_width();
        text_field(
            ui,
            &mut edited.log,
            &format!(
                "stop here, or log e.g. {0} = {{{0}}}",
                debugger.dialect().vocabulary.location_hint
            ),
            format!("Log message of breakpoint {n}"),
            room,
        );
    });
    if let Some(e) = debugger.breakpoint_error(i) {
        ui.colored_label(p.error, format!("Inactive: {e}"));
    }
    if edited != *b {
        out.push(Command::Debug(Action::UpdateBreakpoint(i, edited)));
    }
}

/// A one-line field `width` wide, named `name` for screen readers and tests.
fn text_field(ui: &mut egui::Ui, text: &mut String, hint: &str, name: String, width: f32) {
    ui.add(
        egui::TextEdit::singleline(text)
            .char_limit(servoscope_core::session::limits::TEXT)
            .hint_text(hint)
            .desired_width(width),
    )
    .widget_info(|| egui::WidgetInfo::labeled(egui::Role::TextInput, true, &name));
}

fn data_form(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut BreakpointsView,
    out: &mut Vec<Command>,
) {
    ui.horizontal_wrapped(|ui| {
        ui.label("Break when");
        let field = ui.add(
            egui::TextEdit::singleline(&mut view.location)
                .char_limit(servoscope_core::session::limits::TEXT)
                .hint_text(debugger.dialect().vocabulary.location_hint)
                .desired_width(80.0),
        );
        field.widget_info(|| {
            egui::WidgetInfo::labeled(egui::Role::TextInput, true, "Data breakpoint location")
        });
        egui::ComboBox::new("data_trigger", "")
            .selected_text(TRIGGERS[view.trigger.min(2)])
            .show_ui(ui, |ui| {
                for (k, t) in TRIGGERS.iter().enumerate() {
                    ui.selectable_value(&mut view.trigger, k, *t);
                }
            })
            .response
            .widget_info(|| {
                egui::WidgetInfo::labeled(egui::Role::ComboBox, true, "Data breakpoint trigger")
            });
        if view.trigger == 2 {
            ui.add(
                egui::TextEdit::singleline(&mut view.equals)
                    .char_limit(servoscope_core::session::limits::TEXT)
                    .hint_text("value")
                    .desired_width(70.0),
            )
            .widget_info(|| {
                egui::WidgetInfo::labeled(egui::Role::TextInput, true, "Data breakpoint value")
            });
        }
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("Add data breakpoint").clicked() || entered {
            match data_breakpoint(debugger, view) {
                Ok(b) => {
                    view.error = None;
                    out.push(Command::AddBreakpoint(b));
                }
                Err(e) => view.error = Some(e),
            }
        }
    });
    if let Some(e) = &view.error {
        ui.colored_label(palette(ui.visuals().dark_mode).error, e);
    }
}

/// The form's breakpoint, or why it cannot be one.
fn data_breakpoint(debugger: &Debugger, view: &BreakpointsView) -> Result<Breakpoint, String> {
    let name = view.location.trim();
    let loc = debugger
        .find(name)
        .ok_or_else(|| format!("there is no location named '{name}'"))?;
    let info = debugger
        .machine()
        .info(loc)
        .ok_or_else(|| format!("there is no location named '{name}'"))?;
    let trigger = match view.trigger {
        0 => DataTrigger::Write,
        1 => DataTrigger::Change,
        _ => {
            // Read as the location reads (plain digits are BCD in a DL205 V word), as the
            // register Set field does.
            let (raw, _) = value::parse_in(&view.equals, info.width, info.reading())
                .map_err(|e| e.to_string())?;
            let v = if info.signed {
                value::sign_extend(raw, info.width)
            } else {
                raw as i64
            };
            DataTrigger::Equal(v)
        }
    };
    Ok(Breakpoint::data(info.name, trigger))
}

/// The context menu of a location, wherever one is shown.
/// Force ON / Force OFF / Release for a bit that can be forced (`forced`: its force now).
pub fn force_items(
    ui: &mut egui::Ui,
    name: &str,
    loc: Loc,
    forced: Option<bool>,
    out: &mut Vec<Command>,
) {
    // Only what applies: a disabled item would close the menu on a click that does nothing.
    for (text, level) in [
        (format!("Force {name} ON"), Some(true)),
        (format!("Force {name} OFF"), Some(false)),
        (format!("Release {name}"), None),
    ] {
        let applies = match level {
            Some(_) => forced != level,
            None => forced.is_some(),
        };
        if applies && ui.button(text).clicked() {
            out.push(Command::Debug(Action::Force(loc, level)));
            ui.close();
        }
    }
}

pub fn location_menu(
    ui: &mut egui::Ui,
    m: &dyn servoscope_core::machine::MachineView,
    name: &str,
    loc: Loc,
    out: &mut Vec<Command>,
) {
    let mut item = |ui: &mut egui::Ui, text: String, command: Command| {
        if ui.button(text).clicked() {
            out.push(command);
            ui.close();
        }
    };
    item(ui, format!("Who wrote {name}?"), Command::WhoWrote(loc));
    item(
        ui,
        format!("Break when {name} is written"),
        Command::AddBreakpoint(Breakpoint::data(name, DataTrigger::Write)),
    );
    item(
        ui,
        format!("Break when {name} changes"),
        Command::AddBreakpoint(Breakpoint::data(name, DataTrigger::Change)),
    );
    item(
        ui,
        format!("Watch {name}"),
        Command::AddWatch(name.to_string()),
    );
    if m.can_force(loc) {
        ui.separator();
        force_items(ui, name, loc, m.forced(loc), out);
    }
}
