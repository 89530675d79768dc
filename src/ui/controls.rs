//! Run controls: keyboard shortcuts, the menu bar and the toolbar. All emit [`Command`]s.

use egui::{Key, KeyboardShortcut, Modifiers, RichText};
use servoscope_core::debugger::Action;

use super::code::CodeView;
use super::layout::Pane;
use super::{Command, ServoscopeApp};
use servoscope_core::debugger::{Debugger, Speed};
use servoscope_core::machine::{Loc, MachineView, SpaceKind};
use servoscope_core::registry::{self, DIALECTS};

pub const RUN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F5);
pub const PAUSE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F6);
pub const RESET: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::F5);
// The stepping keys of Visual Studio and VS Code: F10 over, F11 into, Shift+F11 out; the
// Shift of each goes back (Shift+F10 back over; back into and back out add Ctrl). A whole tick
// or scan moved to F8.
pub const STEP: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F10);
pub const STEP_INTO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F11);
pub const STEP_OUT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::SHIFT, Key::F11);
pub const STEP_TICK: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F8);
pub const RUN_TO_CURSOR: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::F10);
pub const TOGGLE_BREAKPOINT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F9);
pub const ASSEMBLE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Enter);
pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
pub const SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
pub const SAVE_AS: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::S);
pub const REVERSE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::SHIFT, Key::F5);
pub const STEP_BACK: KeyboardShortcut = KeyboardShortcut::new(Modifiers::SHIFT, Key::F10);
pub const STEP_BACK_INTO: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::F10);
pub const STEP_BACK_OUT: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::F11);
pub const TICK_BACK: KeyboardShortcut = KeyboardShortcut::new(Modifiers::SHIFT, Key::F8);
pub const HELP: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F1);

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
    let table: [(&KeyboardShortcut, Option<Command>); 18] = [
        (&RESET, Some(Command::Debug(Action::Reset))),
        (
            &STEP_BACK_INTO,
            Some(Command::Debug(Action::StepBackCommand)),
        ),
        (&STEP_BACK_OUT, Some(Command::Debug(Action::StepBackOut))),
        (&REVERSE, Some(Command::Debug(Action::ReverseContinue))),
        (&STEP_BACK, Some(Command::Debug(Action::StepBackOver))),
        (&STEP_OUT, Some(Command::Debug(Action::StepOut))),
        (&TICK_BACK, Some(Command::Debug(Action::StepBackTick))),
        (&SAVE_AS, Some(Command::SaveSessionDialog)),
        (&SAVE, Some(Command::SaveSession)),
        (
            &RUN_TO_CURSOR,
            target.map(|line| Action::RunToLine(line).into()),
        ),
        (&ASSEMBLE, Some(Command::Debug(Action::Assemble))),
        (&OPEN, Some(Command::OpenDialog)),
        (&RUN, Some(Command::Debug(Action::Run))),
        (&PAUSE, Some(Command::Debug(Action::Pause))),
        (&STEP, Some(Command::Debug(Action::StepOver))),
        (&STEP_INTO, Some(Command::Debug(Action::StepCommand))),
        (&STEP_TICK, Some(Command::Debug(Action::StepTick))),
        (
            &TOGGLE_BREAKPOINT,
            target.map(|line| Action::ToggleBreakpoint(line).into()),
        ),
    ];
    let help = ctx.input_mut(|i| {
        for (shortcut, command) in table {
            if i.consume_shortcut(shortcut) {
                out.extend(command);
            }
        }
        i.consume_shortcut(&HELP)
    });
    // The mnemonic under the caret is looked up only when F1 is pressed.
    if help {
        out.push(Command::OpenHelp(code.word_at_caret(debugger)));
    }
}

/// Whether the `i`th shipped session of [`registry::lessons`] is a lesson with steps (read once).
fn has_steps(i: usize) -> bool {
    static STEPS: std::sync::OnceLock<Vec<bool>> = std::sync::OnceLock::new();
    STEPS
        .get_or_init(|| {
            registry::lessons()
                .map(|(_, name, text)| {
                    servoscope_core::session::Session::from_ron(text, name)
                        .is_ok_and(|s| s.lesson.is_some())
                })
                .collect()
        })
        .get(i)
        .copied()
        .unwrap_or(false)
}

fn shortcut_text(ctx: &egui::Context, s: &KeyboardShortcut) -> String {
    ctx.format_shortcut(s)
}

pub fn menu_bar(ui: &mut egui::Ui, app: &ServoscopeApp, out: &mut Vec<Command>) {
    let ctx = ui.ctx().clone();
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            ui.menu_button("New program", |ui| {
                for d in DIALECTS {
                    if ui
                        .button(d.display_name)
                        .on_hover_text(format!(
                            "An empty {} program (.{})",
                            d.display_name, d.extensions[0]
                        ))
                        .clicked()
                    {
                        out.push(Command::NewProgram(d.name));
                    }
                }
            });
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
            ui.separator();
            if ui
                .button("Save program")
                .on_hover_text("Write the program text to its file")
                .clicked()
            {
                out.push(Command::SaveProgram);
            }
            if ui.button("Save program as…").clicked() {
                out.push(Command::SaveProgramDialog);
            }
            if app.debugger.machine().is_plc()
                && ui
                    .button("Export ladder…")
                    .on_hover_text("The ladder diagram with its power flow now, as SVG")
                    .clicked()
            {
                out.push(Command::ExportLadderDialog);
            }
            ui.separator();
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
            ui.menu_button("Examples and lessons", |ui| {
                for d in DIALECTS {
                    ui.menu_button(d.display_name, |ui| {
                        ui.label(RichText::new("Examples").weak());
                        for (i, (dialect, name, _)) in registry::examples().enumerate() {
                            if dialect.name == d.name && ui.button(name).clicked() {
                                out.push(Command::LoadExample(i));
                            }
                        }
                        for (i, (dialect, title, project)) in
                            registry::example_projects().enumerate()
                        {
                            let title = format!(
                                "{title}/{} ({} files)",
                                project.top_name(),
                                project.files.len()
                            );
                            if dialect.name == d.name
                                && ui
                                    .button(title)
                                    .on_hover_text("A program of several files, as EasyMotion Studio lays them out")
                                    .clicked()
                            {
                                out.push(Command::LoadExampleProject(i));
                            }
                        }
                        // Lessons (with steps and checks) apart from walk-through sessions.
                        for (heading, with_steps) in [("Lessons", true), ("Sessions", false)] {
                            ui.separator();
                            ui.label(RichText::new(heading).weak());
                            for (i, (dialect, name, _)) in registry::lessons().enumerate() {
                                if dialect.name != d.name || has_steps(i) != with_steps {
                                    continue;
                                }
                                let tip = if with_steps {
                                    "A lesson: its program, its steps and checks (Lesson panel)"
                                } else {
                                    "A saved debugging moment to walk through"
                                };
                                if ui.button(name).on_hover_text(tip).clicked() {
                                    out.push(Command::LoadLesson(i));
                                }
                            }
                        }
                    });
                }
            });
            if ui
                .button("Save as lesson…")
                .on_hover_text(
                    "This session as a lesson: write its steps and checks in the Lesson panel",
                )
                .clicked()
            {
                out.push(Command::SaveAsLesson);
            }
        });
        ui.menu_button("Debug", |ui| {
            let target = app.code.target_line(&app.debugger);
            let words = app.debugger.dialect().vocabulary;
            let (step, step_back) = (
                format!("Step over (one {}; a call runs whole)", words.step),
                format!("Step back over (one {}; a call runs whole)", words.step),
            );
            let (into, back_into) = (
                format!("Step into (one {})", words.step),
                format!("Step back into (one {})", words.step),
            );
            let (tick, tick_back) = (
                format!("Step {}", words.tick),
                format!("Step back {}", words.tick),
            );
            let items: [(&str, &KeyboardShortcut, Option<Command>); 15] = [
                ("Run / Continue", &RUN, Some(Command::Debug(Action::Run))),
                ("Pause", &PAUSE, Some(Command::Debug(Action::Pause))),
                (&step, &STEP, Some(Command::Debug(Action::StepOver))),
                (&into, &STEP_INTO, Some(Command::Debug(Action::StepCommand))),
                (
                    "Step out (until the subroutine returns)",
                    &STEP_OUT,
                    Some(Command::Debug(Action::StepOut)),
                ),
                (&tick, &STEP_TICK, Some(Command::Debug(Action::StepTick))),
                ("Reverse continue", &REVERSE, Some(Command::Debug(Action::ReverseContinue))),
                (&step_back, &STEP_BACK, Some(Command::Debug(Action::StepBackOver))),
                (&back_into, &STEP_BACK_INTO, Some(Command::Debug(Action::StepBackCommand))),
                (
                    "Step back out (to the CALL)",
                    &STEP_BACK_OUT,
                    Some(Command::Debug(Action::StepBackOut)),
                ),
                (&tick_back, &TICK_BACK, Some(Command::Debug(Action::StepBackTick))),
                (
                    "Run to cursor",
                    &RUN_TO_CURSOR,
                    target.map(|line| Action::RunToLine(line).into()),
                ),
                ("Reset", &RESET, Some(Command::Debug(Action::Reset))),
                ("Assemble", &ASSEMBLE, Some(Command::Debug(Action::Assemble))),
                (
                    "Toggle breakpoint",
                    &TOGGLE_BREAKPOINT,
                    target.map(|line| Action::ToggleBreakpoint(line).into()),
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
            let dialect = app.debugger.dialect();
            if !dialect.settings.is_empty()
                && ui
                    .button(format!("{} settings…", dialect.display_name))
                    .clicked()
            {
                out.push(Command::OpenSettings);
            }
            if dialect.includes.is_some()
                && ui
                    .button("Include folders…")
                    .on_hover_text("Folders besides the program's own that #include may read")
                    .clicked()
            {
                out.push(Command::OpenIncludeFolders);
            }
            ui.separator();
            let dialect_panes = app
                .panel_titles()
                .into_iter()
                .map(|t| Pane::Dialect(t.to_string()));
            let extra = [Pane::Help]
                .into_iter()
                .chain(app.lesson.is_some().then_some(Pane::Lesson));
            for pane in Pane::COMMON.into_iter().chain(dialect_panes).chain(extra) {
                let mut shown = app.layout.contains(&pane);
                let title = pane.title().to_string();
                if ui
                    .checkbox(&mut shown, format!("{title} panel"))
                    .on_hover_text("Shown in the window; drag its tab to move it")
                    .changed()
                {
                    out.push(Command::ShowPane(pane, shown));
                }
            }
            if ui.button("Reset layout").clicked() {
                out.push(Command::ResetLayout);
            }
            // Program memory addresses (TML, spec §5.11).
            if !app.debugger.machine().line_addresses().is_empty() {
                let mut shown = app.code.addresses;
                if ui
                    .checkbox(&mut shown, "Statement addresses in the gutter")
                    .on_hover_text("Each line's first statement's address in program memory (hex)")
                    .changed()
                {
                    out.push(Command::ShowAddresses(shown));
                }
            }
            ui.separator();
            if ui.radio(app.prefs.dark, "Dark theme").clicked() {
                out.push(Command::SetDark(true));
            }
            if ui.radio(!app.prefs.dark, "Light theme").clicked() {
                out.push(Command::SetDark(false));
            }
        });
        ui.menu_button("Help", |ui| {
            let button =
                egui::Button::new(format!("{} reference", app.debugger.dialect().display_name))
                    .shortcut_text(shortcut_text(&ctx, &HELP));
            if ui.add(button).clicked() {
                out.push(Command::OpenHelp(None));
            }
            ui.separator();
            ui.label("F5 run · F6 pause · F10 step over · F11 step into · Shift+F11 step out");
            ui.label("F8 one tick or scan · F9 breakpoint · Ctrl+F10 run to cursor");
            ui.label("Ctrl+Shift+F5 reset · Ctrl+Enter assemble");
            ui.label(
                "Shift+F10 step back over · Ctrl+Shift+F10 back into · Ctrl+Shift+F11 back out",
            );
            ui.label("Shift+F8 tick back · Shift+F5 reverse");
            ui.label("Ctrl+S save session · Ctrl+O open program or session");
            ui.label("Ctrl+F find · Ctrl+G go to line · PageUp/PageDown");
            ui.label("Click the gutter to toggle a breakpoint.");
            ui.label("Drag a panel's tab to move it; View reopens closed panels.");
        });
    });
}

/// Up to this many inputs are all shown as switches; they fit any toolbar.
pub const ALL_INPUTS_UP_TO: u32 = 8;

/// Inputs shown as switches: all of a small input space; of a large one (TML's 16, X0–X1777),
/// those the program uses, those that are on and those the user added with "+".
pub fn shown_inputs(m: &dyn MachineView, extra: &[Loc]) -> Vec<Loc> {
    let used = m.used();
    let mut out = Vec::new();
    for (s, space) in m.spaces().iter().enumerate() {
        if space.kind != SpaceKind::Inputs {
            continue;
        }
        let s = s as u8;
        if space.len <= ALL_INPUTS_UP_TO {
            out.extend((0..space.len).map(|i| Loc::new(s, i)));
        } else {
            out.extend(used.iter().copied().filter(|l| l.space == s));
            out.extend(extra.iter().copied().filter(|l| l.space == s));
            out.extend(
                (0..space.len)
                    .map(|i| Loc::new(s, i))
                    .filter(|&l| m.read(l) != 0),
            );
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

pub fn toolbar(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    extra_inputs: &mut Vec<Loc>,
    new_input: &mut String,
    out: &mut Vec<Command>,
) {
    let ctx = ui.ctx().clone();
    let machine = debugger.machine();
    let words = debugger.dialect().vocabulary;
    let live = machine.run_state().is_live();
    let can_run = live && !debugger.has_errors();
    ui.horizontal(|ui| {
        let tip = |s: &KeyboardShortcut| shortcut_text(&ctx, s);
        if debugger.is_running() {
            if ui.button("Pause").on_hover_text(tip(&PAUSE)).clicked() {
                out.push(Command::Debug(Action::Pause));
            }
        } else if ui
            .add_enabled(can_run, egui::Button::new("Run"))
            .on_hover_text(format!(
                "Run until a breakpoint, the end or a fault ({})",
                tip(&RUN)
            ))
            .clicked()
        {
            out.push(Command::Debug(Action::Run));
        }
        if ui
            .add_enabled(can_run, egui::Button::new("Step"))
            .on_hover_text(format!(
                "Execute one {}; a call runs whole ({}). Into a call: {}",
                words.step,
                tip(&STEP),
                tip(&STEP_INTO)
            ))
            .clicked()
        {
            out.push(Command::Debug(Action::StepOver));
        }
        // Inside a subroutine: a way out of it, where the user sees it is one.
        if machine.call_depth() > 0
            && ui
                .add_enabled(can_run, egui::Button::new("Step out"))
                .on_hover_text(format!(
                    "Run until this subroutine returns ({})",
                    tip(&STEP_OUT)
                ))
                .clicked()
        {
            out.push(Command::Debug(Action::StepOut));
        }
        let tick_button = super::timeline::capitalised(words.tick);
        if ui
            .add_enabled(can_run, egui::Button::new(tick_button))
            .on_hover_text(format!(
                "Finish this {} ({} µs) ({})",
                words.tick,
                machine.tick_micros(),
                tip(&STEP_TICK)
            ))
            .clicked()
        {
            out.push(Command::Debug(Action::StepTick));
        }
        if ui
            .button("Reset")
            .on_hover_text(format!("Back to the start ({})", tip(&RESET)))
            .clicked()
        {
            out.push(Command::Debug(Action::Reset));
        }
        if (debugger.is_edited() || debugger.has_errors())
            && ui
                .button("Assemble")
                .on_hover_text(format!("Assemble the edited text ({})", tip(&ASSEMBLE)))
                .clicked()
        {
            out.push(Command::Debug(Action::Assemble));
        }
        ui.separator();
        let speed = debugger.speed();
        let combo = egui::ComboBox::new("speed", "Speed")
            .selected_text(speed.label(words.step, words.steps))
            .show_ui(ui, |ui| {
                for preset in Speed::PRESETS {
                    if ui
                        .selectable_label(preset == speed, preset.label(words.step, words.steps))
                        .clicked()
                    {
                        out.push(Command::Debug(Action::SetSpeed(preset)));
                    }
                }
            });
        combo.response.on_hover_text(format!(
            "How fast Run goes: {} per second, or simulated time at a factor of real time",
            words.steps
        ));
        ui.separator();
        ui.label("Inputs:");
        for loc in shown_inputs(machine, extra_inputs) {
            let high = machine.read(loc) != 0;
            let name = machine.info(loc).map_or_else(String::new, |i| i.name);
            let forced = machine.forced(loc);
            let mut button = egui::Button::new(&name).selected(high);
            if high {
                button = button.fill(egui::Color32::from_rgb(60, 170, 90));
            }
            if forced.is_some() {
                // The force's colour: this switch does nothing until the force is released.
                button = button.stroke(egui::Stroke::new(
                    2.0,
                    egui::Color32::from_rgb(230, 120, 20),
                ));
            }
            let level = if high { "high" } else { "low" };
            let push = super::push_buttons::is_push_button(ui.ctx(), loc);
            let hint = match forced {
                Some(_) => format!("{name} is forced {level}: release the force to switch it"),
                None if push => format!(
                    "{name} is {level}: a push button, high while you hold it down \
                     (right-click to make it a switch)"
                ),
                None => format!(
                    "{name} is {level}: click to switch it (works while running); right-click \
                     to make it a push button"
                ),
            };
            let r = ui
                .add(button.sense(egui::Sense::click_and_drag()))
                .on_hover_text(hint);
            if forced.is_none() {
                super::push_buttons::switch_input(&r, loc, high, out);
            }
            r.context_menu(|ui| super::push_buttons::push_button_item(ui, loc));
        }
        let large = machine
            .spaces()
            .iter()
            .any(|s| s.kind == SpaceKind::Inputs && s.len > ALL_INPUTS_UP_TO);
        if large {
            super::form_menu_button(ui, "+", |ui| {
                let label = ui.label("Show input");
                let edit = ui
                    .add(egui::TextEdit::singleline(new_input).desired_width(70.0))
                    .labelled_by(label.id);
                let entered = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                if ui.button("Show").clicked() || entered {
                    let found = machine.find(new_input).filter(|l| {
                        machine
                            .spaces()
                            .get(usize::from(l.space))
                            .is_some_and(|s| s.kind == SpaceKind::Inputs)
                    });
                    if let Some(loc) = found {
                        extra_inputs.push(loc);
                        new_input.clear();
                        ui.close();
                    }
                }
            })
            .on_hover_text("Show a switch for another input");
        }
    });
}
