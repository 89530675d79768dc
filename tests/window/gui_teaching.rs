//! The teaching parts of the window, driven through egui_kittest: the Lesson panel (steps,
//! Check with the values involved, Reset lesson, Save as lesson), the Help panel on F1, and
//! what hovering a Q16.16 literal tells.

use crate::common;
use servoscope_core::debugger::Action;

use egui::Key;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use servoscope::ui::layout::Pane;
use servoscope::ui::{Command, Prefs, ServoscopeApp};

const LESSON: &str = r##"(
  format: 2,
  dialect: "silverlode",
  program_name: "scaling.qsl",
  program: "DEF mm_per_count = q16(0.0254)\n        WRP 20, 40000\n        CLD MULT_S64_SHR16, 21, 20, mm_per_count\n        CLC DEC, 21\n        END\n",
  watches: [(expr: "R21", format: Signed)],
  lesson: Some((
    title: "Scaling counts to millimetres",
    steps: [
      (text: "# Read first\nThe factor is `q16(0.0254)`.", checks: []),
      (text: "Make **R21** hold 1016.", checks: ["R21 == 1016"]),
    ],
  )),
)"##;

fn harness(app: ServoscopeApp) -> Harness<'static, ServoscopeApp> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(2);
    h
}

fn lesson_app(name: &str) -> ServoscopeApp {
    let path = common::scratch_file(name, LESSON);
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(path);
    assert!(app.notice.is_none(), "{:?}", app.notice);
    app
}

fn apply(h: &mut Harness<'static, ServoscopeApp>, command: Command) {
    let ctx = h.ctx.clone();
    h.state_mut().apply(&ctx, command);
    h.run_steps(2);
}

#[test]
fn a_lesson_opens_in_its_panel_and_check_shows_the_values_involved() {
    let mut h = harness(lesson_app("gui-lesson.ron"));
    assert!(
        h.state().layout.is_shown(&Pane::Lesson),
        "the panel comes forward"
    );
    h.get_by_label("Scaling counts to millimetres");
    h.get_by_label("step 1 of 2");
    h.get_by_label("Read first");
    h.get_by_label("Next step ▶").click();
    h.run_steps(2);
    h.get_by_label("step 2 of 2");
    // Check grades the lesson's run, as servoscope check does, whatever the position on
    // screen: the program to its end, R21 = 1016 − 1 = 1015.
    check_and_wait(&mut h);
    h.get_by_label_contains("0 of 1 checks pass");
    h.get_by_label_contains("ended after");
    h.get_by_label("✗ R21 == 1016   R21 = 1015, expected 1016");
    // The student fixes the program and checks: graded on the text in the editor.
    let fixed = h.state().debugger.source().replace("CLC DEC, 21", "");
    apply(&mut h, Command::EditSource(fixed));
    h.get_by_label_contains("the program has changed since");
    check_and_wait(&mut h);
    h.get_by_label_contains("1 of 1 checks pass");
    h.get_by_label("✓ R21 == 1016   R21 = 1016");
}

/// Press Check this step and let the grading finish.
fn check_and_wait(h: &mut Harness<'static, ServoscopeApp>) {
    h.get_by_label("✔ Check this step").click();
    for _ in 0..500 {
        h.step();
        if !h.state().lesson.as_ref().is_some_and(|l| l.is_grading()) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    h.run_steps(2);
    assert!(!h.state().lesson.as_ref().is_some_and(|l| l.is_grading()));
}

/// #43 item 6: the window's Check grades the same run as `servoscope check` (it graded the
/// scan on screen), and a program that does not assemble is not graded (it silently graded the
/// previous program).
#[test]
fn check_this_step_agrees_with_servoscope_check() {
    let path = common::scratch_file("gui-agree.ron", LESSON);
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(path.clone());
    let mut h = harness(app);
    apply(&mut h, Command::LessonStep(1));
    // At tick 0, nothing run on screen: the grade is the lesson's run all the same.
    assert_eq!(h.state().debugger.pos().tick, 0);
    check_and_wait(&mut h);
    let graded = h.state().lesson.as_ref().and_then(|l| l.checked.as_ref());
    let (_, outcomes) = graded.and_then(|g| g.result.as_ref().ok()).expect("graded");
    let window: Vec<serde_json::Value> = outcomes.iter().map(|o| o.to_json()).collect();
    let out = common::with_scratch_home(&mut std::process::Command::new(env!(
        "CARGO_BIN_EXE_servoscope"
    )))
    .args(["check", path.to_str().expect("a path"), "--json"])
    .output()
    .expect("servoscope check runs");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let cli: Vec<serde_json::Value> = (report["checks"].as_array().expect("checks").iter())
        .filter(|c| c["step"] == 2)
        .cloned()
        .collect();
    assert_eq!(window, cli);
    // An edit that does not assemble is not graded as the program before it.
    apply(
        &mut h,
        Command::EditSource("        CLC FROB, 21\n        END\n".to_string()),
    );
    check_and_wait(&mut h);
    h.get_by_label_contains("Not graded: the program in the editor does not assemble");
    let _ = std::fs::remove_file(path);
}

#[test]
fn reset_lesson_restores_the_lessons_program_and_position() {
    let mut h = harness(lesson_app("gui-reset.ron"));
    let start = h.state().debugger.source().to_string();
    apply(&mut h, Command::EditSource("        END\n".to_string()));
    apply(&mut h, Command::Debug(Action::Assemble));
    apply(&mut h, Command::LessonStep(1));
    h.get_by_label("Reset lesson").click();
    h.run_steps(2);
    h.get_by_label("Reset and lose my changes").click();
    h.run_steps(2);
    let app = h.state();
    assert_eq!(app.debugger.source(), start);
    assert_eq!(app.debugger.machine().pos().tick, 0);
    let lesson = app.lesson.as_ref().expect("the lesson stays open");
    assert_eq!(lesson.step, 1, "at the step the student was on");
    assert!(app.layout.is_shown(&Pane::Lesson));
}

/// #43 item 18: Reset lesson asks before it throws the student's changes away, and a handed
/// out lesson has no Edit lesson.
#[test]
fn reset_lesson_asks_before_losing_changes_and_a_handed_out_lesson_has_no_editor() {
    let mut h = harness(lesson_app("gui-ask.ron"));
    let start = h.state().debugger.source().to_string();
    // Unchanged: Reset goes at once.
    h.get_by_label("Reset lesson").click();
    h.run_steps(2);
    assert!(h.query_by_label("Keep my program").is_none());
    // Changed: it asks, and "Keep my program" keeps it.
    apply(&mut h, Command::EditSource("        END\n".to_string()));
    h.get_by_label("Reset lesson").click();
    h.run_steps(2);
    h.get_by_label_contains("your changes to it are lost");
    h.get_by_label("Keep my program").click();
    h.run_steps(2);
    assert_eq!(h.state().debugger.source(), "        END\n");
    h.get_by_label("Reset lesson").click();
    h.run_steps(2);
    h.get_by_label("Reset and lose my changes").click();
    h.run_steps(2);
    assert_eq!(h.state().debugger.source(), start);

    // A lesson saved with "Hand out" opens without the editor.
    h.get_by_label("Edit lesson").click();
    h.run_steps(2);
    h.get_by_label("Hand out: students get no Edit lesson")
        .click();
    h.run_steps(2);
    h.get_by_label("Edit lesson").click();
    h.run_steps(2);
    let path = std::env::temp_dir().join(format!("servoscope-{}-handout.ron", std::process::id()));
    apply(&mut h, Command::SaveSessionTo(path.clone()));
    let mut student = harness({
        let mut app = ServoscopeApp::new(Prefs::default());
        app.open_path(path.clone());
        app
    });
    student.run_steps(2);
    student.get_by_label("✔ Check this step");
    assert!(student.query_by_label("Edit lesson").is_none());
    let _ = std::fs::remove_file(path);
}

#[test]
fn opening_an_example_closes_the_lesson() {
    let mut h = harness(lesson_app("gui-close.ron"));
    apply(&mut h, Command::LoadExample(0));
    assert!(h.state().lesson.is_none());
    assert!(!h.state().layout.contains(&Pane::Lesson));
}

#[test]
fn save_as_lesson_offers_the_watches_as_checks_and_saves_the_section() {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("scaling.qsl", "WRP 21, 1016\n        END\n");
    let mut h = harness(app);
    apply(&mut h, Command::AddWatch("R21".to_string()));
    h.state_mut().debugger.goto_tick(10);
    apply(&mut h, Command::SaveAsLesson);
    assert!(h.state().layout.is_shown(&Pane::Lesson));
    assert!(h.state().lesson.as_ref().is_some_and(|l| l.editing));
    h.get_by_label("+ R21 == 1016").click();
    h.run_steps(2);
    let checks = h
        .state()
        .lesson
        .as_ref()
        .map(|l| l.lesson.steps[0].checks.clone());
    assert_eq!(checks, Some(vec!["R21 == 1016".to_string()]));
    let path = std::env::temp_dir().join(format!("servoscope-{}-made.ron", std::process::id()));
    apply(&mut h, Command::SaveSessionTo(path.clone()));
    let saved = servoscope_core::session::Session::load(&path).expect("saved");
    let lesson = saved.lesson.expect("the lesson section is saved");
    assert_eq!(
        lesson.title, "scaling",
        "the program's name without its extension"
    );
    assert_eq!(lesson.steps[0].checks, ["R21 == 1016"]);
    assert!(!h.state().is_dirty(), "saved");
}

#[test]
fn f1_opens_the_reference_at_the_instruction_about_to_run() {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program(
        "t.qsl",
        "        WRP 21, 5\n        CLC INC, 21\n        END\n",
    );
    let mut h = harness(app);
    h.key_press(Key::F1);
    h.run_steps(2);
    assert!(h.state().layout.is_shown(&Pane::Help));
    assert_eq!(h.state().help.selected.as_deref(), Some("WRP"));
    h.get_by_label("QuickSilver SilverLode reference");
    apply(&mut h, Command::Debug(Action::StepOver));
    h.key_press(Key::F1);
    h.run_steps(2);
    assert_eq!(h.state().help.selected.as_deref(), Some("CLC"));
}

#[test]
fn hovering_a_q16_literal_tells_the_pattern_the_value_and_the_quantization_error() {
    let app = ServoscopeApp::new(Prefs::default());
    let m = app.debugger.machine();
    let tip = servoscope::ui::code::hover_value(m, "q16(0.00001)").expect("a tooltip");
    // round(0.00001 × 65536) = round(0.65536) = 1, which is 1/65536 = 0.0000152587890625:
    // 0.0000052587890625 too much, +52.59 % of what was typed.
    assert!(tip.contains("q16(0.00001) stores 1 (0x0000_0001)"), "{tip}");
    assert!(tip.contains("0.0000152587890625"), "{tip}");
    assert!(
        tip.contains("quantization error +0.0000052587890625 (+52.59 %)"),
        "{tip}"
    );
    // q16(0.0254) = round(1664.6144) = 1665 = 0.0254058837890625: +0.02 %.
    let tip = servoscope::ui::code::hover_value(m, "q16(0.0254)").expect("a tooltip");
    assert!(tip.contains("stores 1665"), "{tip}");
    assert!(tip.contains("+0.0000058837890625 (+0.02 %)"), "{tip}");
    let tip = servoscope::ui::code::hover_value(m, "q16(-1.5)").expect("a tooltip");
    assert!(tip.contains("stores -98304"), "{tip}");
    assert!(tip.contains("quantization error 0"), "{tip}");
}

#[test]
fn hovering_a_mnemonic_shows_its_reference_summary() {
    let dialect = servoscope_core::registry::by_name("silverlode").expect("registered");
    let tip = servoscope::ui::code::mnemonic_hover(dialect, "CLD").expect("an entry");
    assert!(tip.starts_with("CLD"), "{tip}");
    assert!(tip.contains("F1"), "{tip}");
    assert!(servoscope::ui::code::mnemonic_hover(dialect, "R21").is_none());
    let tml = servoscope_core::registry::by_name("tml").expect("registered");
    assert!(servoscope::ui::code::mnemonic_in(tml, "WAIT!").is_some());
}

#[test]
fn every_reference_and_every_lesson_step_draws_with_the_windows_fonts() {
    // The harness fails on a character no font has: every sign of the documents is drawable.
    let mut h = harness(ServoscopeApp::new(Prefs::default()));
    for (i, (dialect, _, _)) in servoscope_core::registry::examples().enumerate() {
        if h.state().debugger.dialect().name == dialect.name {
            continue;
        }
        apply(&mut h, Command::LoadExample(i));
        if h.state().pending.is_some() {
            apply(&mut h, Command::DiscardAndContinue);
        }
        apply(&mut h, Command::OpenHelp(None));
        assert!(h.state().layout.is_shown(&Pane::Help));
        h.get_by_label(&format!("{} reference", dialect.display_name));
    }
    for (i, (_, name, _)) in servoscope_core::registry::lessons().enumerate() {
        apply(&mut h, Command::LoadLesson(i));
        if h.state().pending.is_some() {
            apply(&mut h, Command::DiscardAndContinue);
        }
        let steps = h
            .state()
            .lesson
            .as_ref()
            .map_or(0, |l| l.lesson.steps.len());
        for step in 0..steps {
            apply(&mut h, Command::LessonStep(step));
            assert!(
                h.state().layout.is_shown(&Pane::Lesson),
                "{name} step {step}"
            );
        }
    }
}

#[test]
fn the_product_panel_shows_the_multiply_about_to_run_and_then_the_last_one() {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program(
        "scale.qsl",
        "WRP 20, 40000\nCLD MULT_S64_SHR16, 21, 20, q16(0.0254)\nEND\n",
    );
    let mut h = harness(app);
    let product = Pane::Dialect("Product".to_string());
    apply(&mut h, Command::Debug(Action::StepOver));
    apply(&mut h, Command::FocusPane(product.clone()));
    assert!(h.state().layout.is_shown(&product));
    h.get_by_label("About to run: line 2 — CLD MULT_S64_SHR16, R21, R20, 1665");
    h.get_by_label(
        "40000 × 0.0254058837890625 = 1016.2353515625 exact; stored 1016; error −0.023 %",
    );
    h.get_by_label_contains("0.2354 dropped by the shift");
    apply(&mut h, Command::Debug(Action::StepOver));
    h.get_by_label_contains("Last run");
    h.get_by_label_contains("stored 1016");
}

/// #43 item 17: a run that stops at a data breakpoint right after a multiply (never showing
/// it at the program counter) still shows that multiply as the last one run.
#[test]
fn the_product_panel_shows_the_multiply_a_data_breakpoint_stopped_after() {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program(
        "scale.qsl",
        "WRP 20, 40000
DLY 50
CLD MULT_S64_SHR16, 21, 20, q16(0.0254)
DLY 50
END
",
    );
    app.debugger
        .set_speed(servoscope_core::debugger::Speed::Unlimited);
    app.debugger
        .add_breakpoint(servoscope_core::debugger::Breakpoint::data(
            "R21",
            servoscope_core::debugger::DataTrigger::Write,
        ));
    let mut h = harness(app);
    let product = Pane::Dialect("Product".to_string());
    apply(&mut h, Command::FocusPane(product.clone()));
    apply(&mut h, Command::Debug(Action::Run));
    for _ in 0..100 {
        h.step();
        if !h.state().debugger.is_running() {
            break;
        }
    }
    h.run_steps(2);
    assert_eq!(h.state().debugger.machine().last_line(), Some(3));
    h.get_by_label_contains("Last run");
    h.get_by_label_contains("stored 1016");
}

#[test]
fn a_fraction_bit_tells_its_weight() {
    use servoscope::ui::bitrows::bit_tooltip;
    assert_eq!(
        bit_tooltip(15, true, Some(16)),
        "bit 15 = 1: a fraction bit, weight 2^-1 = 0.5"
    );
    assert_eq!(
        bit_tooltip(0, false, Some(16)),
        "bit 0 = 0: a fraction bit, weight 2^-16 = 0.0000152587890625"
    );
    assert_eq!(bit_tooltip(16, true, Some(16)), "bit 16 = 1: weight 2^0");
    assert_eq!(bit_tooltip(5, true, None), "bit 5 = 1: weight 2^5");
}

#[test]
fn a_queue_used_as_a_stack_is_drawn_as_one_and_the_user_can_switch() {
    use servoscope::ui::dialects::silverlode::queues::{Drawing, usage};
    use servoscope_core::machine::silverlode::SilverLode;
    // Pushed and popped at the head: a LIFO (spec §5.3).
    let lifo = "CLD Q_INIT, 10, 40, 4\nCLD Q_PUSH_HEAD, 11, 40, 10\nCLD Q_PUSH_HEAD, 11, 40, 20\n\
                CLD Q_PUSH_HEAD, 11, 40, 30\nCLD Q_POP_HEAD, 12, 40, 0\nEND\n";
    let fifo =
        "CLD Q_INIT, 10, 40, 4\nCLD Q_PUSH_HEAD, 11, 40, 10\nCLD Q_POP_TAIL, 12, 40, 0\nEND\n";
    let tail_stack =
        "CLD Q_INIT, 10, 40, 4\nCLD Q_PUSH_TAIL, 11, 40, 10\nCLD Q_POP_TAIL, 12, 40, 0\nEND\n";
    let program_of = |src: &str| common::machine(src).program().clone();
    assert_eq!(
        usage(&program_of(lifo), 40),
        Drawing::Stack { top_at_head: true }
    );
    assert_eq!(usage(&program_of(fifo), 40), Drawing::Ring);
    assert_eq!(
        usage(&program_of(tail_stack), 40),
        Drawing::Stack { top_at_head: false }
    );

    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("lifo.qsl", lifo);
    let mut h = harness(app);
    // Three pushes: 30 on top, then 20, then 10; one free slot.
    for _ in 0..4 {
        apply(&mut h, Command::Debug(Action::StepOver));
    }
    apply(
        &mut h,
        Command::FocusPane(Pane::Dialect("Queues".to_string())),
    );
    assert!(h.state().debugger.machine_as::<SilverLode>().is_some());
    h.get_by_label("Queue R40 as a stack");
    h.get_by_label("Queue R40 stack depth 0: 30");
    h.get_by_label("Queue R40 stack depth 2: 10");
    h.get_by_label("as ring").click();
    h.run_steps(2);
    assert!(
        h.query_by_label("Queue R40 as a stack").is_none(),
        "drawn as the ring now"
    );
    h.get_by_label("as stack").click();
    h.run_steps(2);
    h.get_by_label("Queue R40 stack depth 0: 30");
}

#[test]
fn hovering_a_tml_fixed_literal_tells_what_it_stores() {
    let mut app = ServoscopeApp::new(Prefs::default());
    let tml = servoscope_core::registry::by_name("tml").expect("registered");
    app.load_program_as(tml, "f.tml", "fixed f;\nf = 0.0254;\nEND;\n");
    let m = app.debugger.machine();
    // Spec §1.3: raw = round(0.0254 × 65536) = 1665, as q16(0.0254).
    let tip = servoscope::ui::code::hover_value(m, "0.0254").expect("a tooltip");
    assert!(tip.contains("0.0254 stores 1665"), "{tip}");
    assert!(tip.contains("(+0.02 %)"), "{tip}");
    // In SilverLode a bare decimal is not a literal.
    let sl = ServoscopeApp::new(Prefs::default());
    assert!(servoscope::ui::code::hover_value(sl.debugger.machine(), "0.0254").is_none());
}

#[test]
fn the_lessons_inputs_meet_the_students_edited_program() {
    let text = LESSON.replace(
        "  lesson: Some((",
        "  events: [(at: (tick: 5, step: 0), location: \"IO1\", change: Set(1))],\n  lesson: Some((",
    );
    let path = common::scratch_file("gui-inputs.ron", &text);
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(path);
    let mut h = harness(app);
    let at_tick_5 = |app: &ServoscopeApp| {
        app.debugger
            .events()
            .iter()
            .filter(|e| e.at.tick == 5)
            .count()
    };
    assert_eq!(at_tick_5(h.state()), 1, "the lesson's input");
    let edited = h
        .state()
        .debugger
        .source()
        .replace("CLC DEC, 21", "CLC INC, 21");
    apply(&mut h, Command::EditSource(edited));
    apply(&mut h, Command::Debug(Action::Assemble));
    assert_eq!(
        at_tick_5(h.state()),
        1,
        "still there after the student's edit"
    );
    apply(&mut h, Command::Debug(Action::Reset));
    assert_eq!(at_tick_5(h.state()), 1, "and after a reset");
    // Without the lesson a new program starts with no inputs switched.
    apply(&mut h, Command::LoadExample(0));
    apply(&mut h, Command::DiscardAndContinue);
    assert!(h.state().lesson.is_none());
    apply(&mut h, Command::Debug(Action::Reset));
    assert_eq!(at_tick_5(h.state()), 0);
}
