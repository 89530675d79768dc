//! The Lesson panel: the open lesson's current step as rendered Markdown, Back/Next, Check
//! (each check of the step on the present state, ✓ or ✗ with the values involved) and Reset
//! lesson. Edit lesson turns the texts and checks into fields, so teachers write lessons in the
//! app (File → Save as lesson starts one from the current session).

use egui::RichText;
use egui_commonmark::{CommonMarkCache, CommonMarkViewer};

use super::Command;
use servoscope_core::debugger::Debugger;
use servoscope_core::lesson::{CheckOutcome, Lesson, LessonStep};
use servoscope_core::session::Session;

pub const TITLE: &str = "Lesson";

pub struct LessonView {
    pub lesson: Lesson,
    /// The step shown, from 0.
    pub step: usize,
    /// The last Check, once graded.
    pub checked: Option<Graded>,
    /// A Check being graded in the background.
    grading: Option<Grading>,
    pub editing: bool,
    /// Reset lesson was pressed on a changed program: asking whether to lose the changes.
    pub confirm_reset: bool,
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
            grading: None,
            editing: false,
            confirm_reset: false,
            start,
            cache: CommonMarkCache::default(),
        }
    }

    /// Grade the shown step as `servoscope check` grades the lesson: the program in the editor,
    /// run from its start with the lesson's inputs for the lesson's grading length, on a worker
    /// (a long run never holds up the window). A program that does not assemble is not graded:
    /// the result says so, as `check` does.
    pub fn check(&mut self, debugger: &Debugger) {
        let step = self.step;
        let source = debugger.project().clone();
        let dialect = debugger.dialect();
        let start = self.start.clone().unwrap_or_default();
        let settings = if self.start.is_some() {
            dialect.settings_from(&start.settings)
        } else {
            debugger.settings().clone()
        };
        let engine = match dialect.open_program(&source, &settings) {
            Ok(engine) => engine,
            Err(diagnostics) => {
                let errors: Vec<_> = (diagnostics.iter())
                    .filter(|d| d.severity == servoscope_core::machine::Severity::Error)
                    .collect();
                let first = errors.first().map_or(String::new(), |d| {
                    format!(": {}", source.diagnostic(debugger.name(), d).trim_end())
                });
                self.grading = None;
                self.checked = Some(Graded {
                    step,
                    source,
                    result: Err(format!(
                        "Not graded: the program in the editor does not assemble ({} error(s)){first}.                          servoscope check would grade nothing either: fix it, then Check again.",
                        errors.len()
                    )),
                });
                return;
            }
        };
        let lesson = servoscope_core::lesson::Lesson {
            steps: self.lesson.steps.get(step).cloned().into_iter().collect(),
            ..self.lesson.clone()
        };
        let ticks = servoscope_core::lesson::grading_ticks(&lesson, None, dialect);
        let (tx, rx) = std::sync::mpsc::channel();
        let name = debugger.name().to_string();
        std::thread::spawn(move || {
            let result = servoscope_core::lesson::grading_run(
                engine.as_ref(),
                &start,
                &lesson,
                ticks,
                &name,
                std::time::Duration::from_secs_f64(
                    servoscope_core::lesson::DEFAULT_GRADING_SECONDS,
                ),
            )
            .map(|graded| {
                let mut outcomes = graded.outcomes;
                // The step's checks were graded as step 1 of a one-step lesson.
                outcomes.iter_mut().for_each(|o| o.step = step + 1);
                let m = graded.run.machine();
                let how = if !graded.finished {
                    format!(
                        "stopped by the time budget at {} {}",
                        m.ticks(),
                        ticks_word(m)
                    )
                } else if m.run_state().is_live() {
                    format!(
                        "stopped at the grading length, {} {}",
                        m.ticks(),
                        ticks_word(m)
                    )
                } else {
                    format!("ended after {} {}", m.ticks(), ticks_word(m))
                };
                (how, outcomes)
            })
            .map_err(|e| e.to_string());
            let _ = tx.send(result);
        });
        self.grading = Some(Grading {
            step,
            source,
            results: rx,
        });
    }

    /// Whether a Check is still being graded.
    pub fn is_grading(&self) -> bool {
        self.grading.is_some()
    }

    /// Take a finished grading's result (asked every frame).
    pub fn poll(&mut self) {
        let Some(g) = &self.grading else { return };
        let result = match g.results.try_recv() {
            Ok(result) => result,
            Err(std::sync::mpsc::TryRecvError::Empty) => return,
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                Err("the grading stopped without a result".to_string())
            }
        };
        if let Some(g) = self.grading.take() {
            self.checked = Some(Graded {
                step: g.step,
                source: g.source,
                result,
            });
        }
    }

    pub fn go_to(&mut self, step: usize) {
        self.step = step.min(self.lesson.steps.len().saturating_sub(1));
    }
}

/// "scans" or "ticks", as the machine counts.
fn ticks_word(m: &dyn servoscope_core::machine::MachineView) -> &'static str {
    if m.is_plc() { "scan(s)" } else { "tick(s)" }
}

/// A Check's result: for which step, of which program text, and either how the run ended
/// with the outcomes, or why nothing was graded.
pub struct Graded {
    pub step: usize,
    source: servoscope_core::machine::project::Project,
    pub result: Result<(String, Vec<CheckOutcome>), String>,
}

/// A Check being graded on a worker.
struct Grading {
    step: usize,
    source: servoscope_core::machine::project::Project,
    results: std::sync::mpsc::Receiver<Result<(String, Vec<CheckOutcome>), String>>,
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
            "File → Examples and lessons → a dialect → Lessons opens one; File → Save as lesson… makes one of this session.",
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
                "Grade this step as servoscope check does: the program in the editor, run from its start with the lesson's inputs",
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
            // The student's program is thrown away: ask first when it was changed.
            let changed = view
                .start
                .as_ref()
                .is_some_and(|s| s.project() != *debugger.project());
            if changed {
                view.confirm_reset = true;
            } else {
                out.push(Command::LessonReset);
            }
        }
        if !view.lesson.handed_out || view.editing {
            ui.toggle_value(&mut view.editing, "Edit lesson")
                .on_hover_text("Write the title, the steps' texts and their checks");
        }
    });
    if view.confirm_reset {
        ui.horizontal_wrapped(|ui| {
            ui.label(
                RichText::new(
                    "Reset lesson puts back the lesson's program: your changes to it are lost.",
                )
                .color(super::theme::palette(ui.visuals().dark_mode).error),
            );
            if ui.button("Reset and lose my changes").clicked() {
                view.confirm_reset = false;
                out.push(Command::LessonReset);
            }
            if ui.button("Keep my program").clicked() {
                view.confirm_reset = false;
            }
        });
    }
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
    let palette = super::theme::palette(ui.visuals().dark_mode);
    if view.grading.as_ref().is_some_and(|g| g.step == view.step) {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label("Grading: the program runs from its start, as servoscope check runs it…");
        });
        ui.ctx().request_repaint();
        return;
    }
    let Some(graded) = &view.checked else {
        return;
    };
    if graded.step != view.step {
        return;
    }
    let (how, outcomes) = match &graded.result {
        Ok(done) => done,
        Err(why) => {
            ui.label(RichText::new(why).color(palette.error));
            ui.separator();
            return;
        }
    };
    let (pass, fail) = (palette.bit_on, palette.error);
    let passed = outcomes.iter().filter(|o| o.pass).count();
    let mut summary = format!(
        "{passed} of {} checks pass (graded as servoscope check grades: the program run from \
         its start with the lesson's inputs, {how})",
        outcomes.len()
    );
    if graded.source != *debugger.project() {
        summary.push_str(" — the program has changed since: Check again");
    }
    ui.label(RichText::new(summary).strong());
    // At most two fifths of the panel, scrolled: the step's text stays in view under it (in a
    // 900×600 window the results left only the step's heading).
    egui::ScrollArea::vertical()
        .id_salt("lesson_results")
        .max_height(ui.available_height() * 0.4)
        .auto_shrink([false, true])
        .show(ui, |ui| {
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
        });
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
                        .char_limit(servoscope_core::session::limits::TEXT)
                        .desired_width(f32::INFINITY)
                        .id_salt("lesson_title"),
                )
                .labelled_by(label.id);
            });
            ui.checkbox(
                &mut view.lesson.handed_out,
                "Hand out: students get no Edit lesson",
            )
            .on_hover_text(
                "Saved with the lesson: whoever opens it sees the steps and Check, not the \
                 editor (keep a copy without it for yourself)",
            );
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
                            .char_limit(servoscope_core::session::limits::TEXT)
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
                    .char_limit(servoscope_core::session::limits::STEP_TEXT)
                    .desired_width(f32::INFINITY)
                    .desired_rows(8)
                    .code_editor()
                    .id_salt("lesson_step_text"),
            );
        });
}
