//! The Lesson panel: the open lesson's current step as rendered Markdown, Back/Next, Check
//! (each check of the step on the present state, ✓ or ✗ with the values involved) and Reset
//! lesson. Edit lesson turns the texts and checks into fields, so teachers write lessons in the
//! app (File → Save as lesson starts one from the current session).

use egui::RichText;
use egui_commonmark::{CommonMarkCache, CommonMarkViewer};

use super::Command;
use servoscope_core::debugger::Debugger;
use servoscope_core::lesson::{CheckOutcome, Lesson, LessonStep};
use servoscope_core::machine::Pos;
use servoscope_core::session::Session;

pub const TITLE: &str = "Lesson";

pub struct LessonView {
    pub lesson: Lesson,
    /// The step shown, from 0.
    pub step: usize,
    /// The last Check: the step and position it was made at, and its outcomes.
    pub checked: Option<(usize, Pos, Vec<CheckOutcome>)>,
    pub editing: bool,
    /// The lesson as it was opened (program, position, edits): what Reset lesson goes back to.
    pub start: Option<Session>,
    cache: CommonMarkCache,
}

impl LessonView {
    pub fn new(lesson: Lesson, start: Option<Session>) -> Self {
        LessonView {
            lesson,
            step: 0,
            checked: None,
            editing: false,
            start,
            cache: CommonMarkCache::default(),
        }
    }

    /// Evaluate the shown step's checks on the debugger's present state.
    pub fn check(&mut self, debugger: &Debugger) {
        let m = debugger.machine();
        let outcomes = self
            .lesson
            .steps
            .get(self.step)
            .map(|s| {
                s.checks
                    .iter()
                    .map(|c| servoscope_core::lesson::evaluate(self.step + 1, c, m))
                    .collect()
            })
            .unwrap_or_default();
        self.checked = Some((self.step, m.pos(), outcomes));
    }

    pub fn go_to(&mut self, step: usize) {
        self.step = step.min(self.lesson.steps.len().saturating_sub(1));
    }
}

pub fn show(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: Option<&mut LessonView>,
    out: &mut Vec<Command>,
) {
    let Some(view) = view else {
        ui.label("No lesson is open.");
        ui.label(
            "Examples → a lesson opens one; File → Save as lesson… makes one of this session.",
        );
        return;
    };
    let steps = view.lesson.steps.len();
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(&view.lesson.title).strong());
        ui.label(format!("step {} of {steps}", view.step + 1));
    });
    ui.horizontal_wrapped(|ui| {
        if ui
            .add_enabled(view.step > 0, egui::Button::new("◀ Previous step"))
            .clicked()
        {
            out.push(Command::LessonStep(view.step - 1));
        }
        if ui
            .add_enabled(view.step + 1 < steps, egui::Button::new("Next step ▶"))
            .clicked()
        {
            out.push(Command::LessonStep(view.step + 1));
        }
        let has_checks = view
            .lesson
            .steps
            .get(view.step)
            .is_some_and(|s| !s.checks.is_empty());
        if ui
            .add_enabled(has_checks, egui::Button::new("✔ Check this step"))
            .on_hover_text(
                "Evaluate this step's checks on the present state: run the program first",
            )
            .on_disabled_hover_text("This step has no checks")
            .clicked()
        {
            out.push(Command::LessonCheck);
        }
        if ui
            .add_enabled(view.start.is_some(), egui::Button::new("Reset lesson"))
            .on_hover_text("Back to the lesson's program and position")
            .clicked()
        {
            out.push(Command::LessonReset);
        }
        ui.toggle_value(&mut view.editing, "Edit lesson")
            .on_hover_text("Write the title, the steps' texts and their checks");
    });
    ui.separator();
    if view.editing {
        edit(ui, debugger, view);
        return;
    }
    results(ui, debugger, view);
    let Some(step) = view.lesson.steps.get(view.step) else {
        ui.label("This lesson has no steps yet: Edit lesson adds them.");
        return;
    };
    let text = step.text.clone();
    egui::ScrollArea::vertical()
        .id_salt("lesson_text")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            CommonMarkViewer::new().show(ui, &mut view.cache, &text);
        });
}

/// The last Check's outcomes, when they are of the shown step.
fn results(ui: &mut egui::Ui, debugger: &Debugger, view: &LessonView) {
    let Some((step, at, outcomes)) = &view.checked else {
        return;
    };
    if *step != view.step {
        return;
    }
    let palette = super::theme::palette(ui.visuals().dark_mode);
    let (pass, fail) = (palette.bit_on, palette.error);
    let passed = outcomes.iter().filter(|o| o.pass).count();
    let stale = *at != debugger.machine().pos();
    let tick = debugger.dialect().vocabulary.tick;
    let mut summary = format!(
        "{passed} of {} checks pass (at {tick} {at})",
        outcomes.len()
    );
    if stale {
        summary.push_str(" — the position has changed since: Check again");
    }
    ui.label(RichText::new(summary).strong());
    if *at == servoscope_core::machine::Pos::default() {
        ui.label(
            RichText::new(
                "Nothing has run yet: run the program (F5) or step it, then Check again. \
                 (servoscope check runs it for you.)",
            )
            .color(palette.written),
        );
    }
    for o in outcomes {
        let (mark, colour) = if o.pass { ("✓", pass) } else { ("✗", fail) };
        let detail = o.detail();
        let line = if detail.is_empty() {
            format!("{mark} {}", o.expr)
        } else {
            format!("{mark} {}   {detail}", o.expr)
        };
        ui.label(RichText::new(line).monospace().color(colour));
    }
    ui.separator();
}

/// Fields for the title, the shown step's text and checks, and the steps themselves.
fn edit(ui: &mut egui::Ui, debugger: &Debugger, view: &mut LessonView) {
    egui::ScrollArea::vertical()
        .id_salt("lesson_edit")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                let label = ui.label("Title");
                ui.add(
                    egui::TextEdit::singleline(&mut view.lesson.title)
                        .desired_width(f32::INFINITY)
                        .id_salt("lesson_title"),
                )
                .labelled_by(label.id);
            });
            ui.horizontal(|ui| {
                let words = debugger.dialect().vocabulary;
                let mut own = view.lesson.max_ticks.is_some();
                if ui
                    .checkbox(&mut own, format!("Grade after this many {}", words.ticks))
                    .on_hover_text(format!(
                        "servoscope check runs the program this long; unticked: {} {}",
                        debugger.dialect().default_max_ticks,
                        words.ticks
                    ))
                    .changed()
                {
                    view.lesson.max_ticks = own.then_some(
                        debugger
                            .pos()
                            .tick
                            .max(debugger.dialect().default_max_ticks),
                    );
                }
                if let Some(ticks) = &mut view.lesson.max_ticks {
                    ui.add(
                        egui::DragValue::new(ticks)
                            .range(1..=servoscope_core::session::MAX_REPLAY_TICKS),
                    );
                }
            });
            ui.horizontal(|ui| {
                if ui.button("+ Step after this one").clicked() {
                    let at = (view.step + 1).min(view.lesson.steps.len());
                    view.lesson.steps.insert(at, LessonStep::default());
                    view.step = at;
                }
                if ui
                    .add_enabled(
                        !view.lesson.steps.is_empty(),
                        egui::Button::new("Remove this step"),
                    )
                    .clicked()
                {
                    view.lesson.steps.remove(view.step);
                    view.go_to(view.step);
                }
            });
            let m = debugger.machine();
            let Some(step) = view.lesson.steps.get_mut(view.step) else {
                return;
            };
            ui.label(format!(
                "Checks: expressions that hold once the task is done, e.g. {}",
                debugger.dialect().vocabulary.condition_hint
            ));
            let mut remove = None;
            for (i, check) in step.checks.iter_mut().enumerate() {
                ui.horizontal(|ui| {
                    ui.add(
                        egui::TextEdit::singleline(check)
                            .desired_width(ui.available_width() - 40.0)
                            .id_salt(("lesson_check", i)),
                    );
                    if ui
                        .small_button("✖")
                        .on_hover_text("Remove this check")
                        .clicked()
                    {
                        remove = Some(i);
                    }
                });
                if let Some(e) = (!check.trim().is_empty())
                    .then(|| servoscope_core::debugger::expr::Expr::compile(check, m).err())
                    .flatten()
                {
                    ui.colored_label(ui.visuals().error_fg_color, e.to_string());
                }
            }
            if let Some(i) = remove {
                step.checks.remove(i);
            }
            ui.horizontal_wrapped(|ui| {
                if ui.button("+ Check").clicked() {
                    step.checks.push(String::new());
                }
                let offers: Vec<String> = debugger
                    .watches()
                    .iter()
                    .filter_map(|w| servoscope_core::lesson::check_from_watch(&w.expr, m))
                    .filter(|c| !step.checks.contains(c))
                    .collect();
                for offer in offers {
                    if ui
                        .button(format!("+ {offer}"))
                        .on_hover_text("A watch as a check that holds now")
                        .clicked()
                    {
                        step.checks.push(offer);
                    }
                }
            });
            ui.label("Text of this step (Markdown: # heading, **bold**, `code`, - lists)");
            ui.add(
                egui::TextEdit::multiline(&mut step.text)
                    .desired_width(f32::INFINITY)
                    .desired_rows(8)
                    .code_editor()
                    .id_salt("lesson_step_text"),
            );
        });
}
