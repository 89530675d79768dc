//! Run controls: keyboard shortcuts, the menu bar and the toolbar. All emit [`Command`]s.

use egui::{Key, KeyboardShortcut, Modifiers};

use super::code::CodeView;
use super::{Command, EXAMPLES, ServoscopeApp};
use crate::debugger::{Debugger, Speed};
use crate::machine::Machine;

pub const RUN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F5);
pub const PAUSE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F6);
pub const RESET: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::F5);
pub const STEP: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F10);
pub const STEP_TICK: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F11);
pub const RUN_TO_CURSOR: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::F10);
pub const TOGGLE_BREAKPOINT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F9);
pub const ASSEMBLE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Enter);
pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
pub const SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
pub const SAVE_AS: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::S);
pub const REVERSE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::SHIFT, Key::F5);
pub const STEP_BACK: KeyboardShortcut = KeyboardShortcut::new(Modifiers::SHIFT, Key::F10);
pub const TICK_BACK: KeyboardShortcut = KeyboardShortcut::new(Modifiers::SHIFT, Key::F11);

/// Shortcuts, most specific first (egui ignores extra Shift when matching).
pub fn shortcuts(
    ctx: &egui::Context,
    debugger: &Debugger,
    code: &CodeView,
    out: &mut Vec<Command>,
) {
    let target = code.target_line(debugger);
    // Most specific first: egui ignores an extra Shift when matching the plain keys.
    // A command needing the cursor's line is skipped (its key still consumed) without one.
    let table: [(&KeyboardShortcut, Option<Command>); 14] = [
        (&RESET, Some(Command::Reset)),
        (&REVERSE, Some(Command::ReverseContinue)),
        (&STEP_BACK, Some(Command::StepBackCommand)),
        (&TICK_BACK, Some(Command::StepBackTick)),
        (&SAVE_AS, Some(Command::SaveSessionDialog)),
        (&SAVE, Some(Command::SaveSession)),
        (&RUN_TO_CURSOR, target.map(Command::RunToLine)),
        (&ASSEMBLE, Some(Command::Assemble)),
        (&OPEN, Some(Command::OpenDialog)),
        (&RUN, Some(Command::Run)),
        (&PAUSE, Some(Command::Pause)),
        (&STEP, Some(Command::StepCommand)),
        (&STEP_TICK, Some(Command::StepTick)),
        (&TOGGLE_BREAKPOINT, target.map(Command::ToggleBreakpoint)),
    ];
    ctx.input_mut(|i| {
        for (shortcut, command) in table {
            if i.consume_shortcut(shortcut) {
                out.extend(command);
            }
        }
    });
}

fn shortcut_text(ctx: &egui::Context, s: &KeyboardShortcut) -> String {
    ctx.format_shortcut(s)
}

pub fn menu_bar(ui: &mut egui::Ui, app: &ServoscopeApp, out: &mut Vec<Command>) {
    let ctx = ui.ctx().clone();
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            let file_items = [
                ("Open program or session…", &OPEN, Command::OpenDialog),
                ("Save session", &SAVE, Command::SaveSession),
                ("Save session as…", &SAVE_AS, Command::SaveSessionDialog),
            ];
            for (label, shortcut, command) in file_items {
                let button = egui::Button::new(label).shortcut_text(shortcut_text(&ctx, shortcut));
                if ui.add(button).clicked() {
                    out.push(command);
                }
            }
            ui.menu_button("Open recent", |ui| {
                if app.prefs.recent.is_empty() {
                    ui.label("No recent files");
                }
                for path in &app.prefs.recent {
                    if ui.button(path.display().to_string()).clicked() {
                        out.push(Command::OpenPath(path.clone()));
                    }
                }
            });
            ui.menu_button("Examples", |ui| {
                for (i, (name, _)) in EXAMPLES.iter().enumerate() {
                    if ui.button(*name).clicked() {
                        out.push(Command::LoadExample(i));
                    }
                }
            });
        });
        ui.menu_button("Debug", |ui| {
            let target = app.code.target_line(&app.debugger);
            let items: [(&str, &KeyboardShortcut, Option<Command>); 11] = [
                ("Run / Continue", &RUN, Some(Command::Run)),
                ("Pause", &PAUSE, Some(Command::Pause)),
                ("Step command", &STEP, Some(Command::StepCommand)),
                ("Step tick", &STEP_TICK, Some(Command::StepTick)),
                ("Reverse continue", &REVERSE, Some(Command::ReverseContinue)),
                (
                    "Step back command",
                    &STEP_BACK,
                    Some(Command::StepBackCommand),
                ),
                ("Step back tick", &TICK_BACK, Some(Command::StepBackTick)),
                (
                    "Run to cursor",
                    &RUN_TO_CURSOR,
                    target.map(Command::RunToLine),
                ),
                ("Reset", &RESET, Some(Command::Reset)),
                ("Assemble", &ASSEMBLE, Some(Command::Assemble)),
                (
                    "Toggle breakpoint",
                    &TOGGLE_BREAKPOINT,
                    target.map(Command::ToggleBreakpoint),
                ),
            ];
            for (label, shortcut, command) in items {
                let button = egui::Button::new(label).shortcut_text(shortcut_text(&ctx, shortcut));
                if ui.add_enabled(command.is_some(), button).clicked() {
                    out.extend(command);
                }
            }
        });
        ui.menu_button("View", |ui| {
            if ui.button("Servo model…").clicked() {
                out.push(Command::OpenServoSettings);
            }
            if ui.radio(app.prefs.dark, "Dark theme").clicked() {
                out.push(Command::SetDark(true));
            }
            if ui.radio(!app.prefs.dark, "Light theme").clicked() {
                out.push(Command::SetDark(false));
            }
        });
        ui.menu_button("Help", |ui| {
            ui.label("F5 run · F6 pause · F10 step · F11 tick");
            ui.label("F9 breakpoint · Ctrl+F10 run to cursor");
            ui.label("Ctrl+Shift+F5 reset · Ctrl+Enter assemble");
            ui.label("Shift+F10 step back · Shift+F11 tick back · Shift+F5 reverse");
            ui.label("Ctrl+S save session · Ctrl+O open program or session");
            ui.label("Click the gutter to toggle a breakpoint.");
        });
    });
}

pub fn toolbar(ui: &mut egui::Ui, debugger: &Debugger, out: &mut Vec<Command>) {
    let ctx = ui.ctx().clone();
    let machine = debugger.machine();
    let live = machine.run_state().is_live();
    let can_run = live && !debugger.has_errors();
    ui.horizontal(|ui| {
        let tip = |s: &KeyboardShortcut| shortcut_text(&ctx, s);
        if debugger.is_running() {
            if ui.button("Pause").on_hover_text(tip(&PAUSE)).clicked() {
                out.push(Command::Pause);
            }
        } else if ui
            .add_enabled(can_run, egui::Button::new("Run"))
            .on_hover_text(format!(
                "Run until a breakpoint, the end or a fault ({})",
                tip(&RUN)
            ))
            .clicked()
        {
            out.push(Command::Run);
        }
        if ui
            .add_enabled(can_run, egui::Button::new("Step"))
            .on_hover_text(format!("Execute one command ({})", tip(&STEP)))
            .clicked()
        {
            out.push(Command::StepCommand);
        }
        if ui
            .add_enabled(can_run, egui::Button::new("Tick"))
            .on_hover_text(format!("Advance one tick of 120 µs ({})", tip(&STEP_TICK)))
            .clicked()
        {
            out.push(Command::StepTick);
        }
        if ui
            .button("Reset")
            .on_hover_text(format!("Back to the start ({})", tip(&RESET)))
            .clicked()
        {
            out.push(Command::Reset);
        }
        if (debugger.is_edited() || debugger.has_errors())
            && ui
                .button("Assemble")
                .on_hover_text(format!("Assemble the edited text ({})", tip(&ASSEMBLE)))
                .clicked()
        {
            out.push(Command::Assemble);
        }
        ui.separator();
        let speed = debugger.speed();
        let combo = egui::ComboBox::new("speed", "Speed")
            .selected_text(speed.label())
            .show_ui(ui, |ui| {
                for preset in Speed::PRESETS {
                    if ui
                        .selectable_label(preset == speed, preset.label())
                        .clicked()
                    {
                        out.push(Command::SetSpeed(preset));
                    }
                }
            });
        combo
            .response
            .on_hover_text("Commands per second while running");
        ui.separator();
        ui.label("Inputs:");
        for i in 0..machine.input_count() {
            let high = machine.input(i);
            let name = format!("IO{}", i + 1);
            let mut button = egui::Button::new(&name).selected(high);
            if high {
                button = button.fill(egui::Color32::from_rgb(60, 170, 90));
            }
            let r = ui.add(button).on_hover_text(format!(
                "{name} is {}: click to switch it (works while running)",
                if high { "high" } else { "low" }
            ));
            if r.clicked() {
                out.push(Command::SetInput(i, !high));
            }
        }
    });
}
