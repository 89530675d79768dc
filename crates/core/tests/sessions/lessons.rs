//! Lessons (issue: teaching): the lesson section of a session, checks evaluated on a machine's
//! state with the values involved, `servoscope check` (exit codes, text, JSON), and every
//! shipped lesson failing on its starting program and passing on a correct answer.

use crate::common;
use common::lessons::{ANSWER, LESSON};

use std::path::{Path, PathBuf};

use servoscope_core::debugger::expr::Expr;
use servoscope_core::lesson::{self, Lesson, LessonStep};
use servoscope_core::registry;
use servoscope_core::session::Session;

#[test]
fn a_session_with_a_lesson_section_keeps_it_through_save_and_load() {
    let session = Session::from_ron(LESSON, "scaling.ron").expect("a lesson session");
    let lesson = session.lesson.clone().expect("the lesson section");
    assert_eq!(lesson.title, "Scaling");
    assert_eq!(lesson.steps.len(), 2);
    assert_eq!(lesson.steps[1].checks, ["R21 == 1016", "R20 == 40000"]);
    let again =
        Session::from_ron(&session.to_ron().expect("encodes"), "again.ron").expect("reads back");
    assert_eq!(again.lesson, Some(lesson));
    // A session without the section is an ordinary session.
    let plain = LESSON.replace("lesson: Some", "no_lesson: Some");
    let plain = Session::from_ron(&plain, "plain.ron").expect("a session");
    assert_eq!(plain.lesson, None);
}

#[test]
fn a_lesson_with_absurd_sizes_is_refused_not_loaded() {
    let step = "(text: \"x\", checks: []),".repeat(10_001);
    let text = LESSON.replace(
        "(text: \"# Read\\nNothing to check here.\", checks: []),",
        &step,
    );
    let refused = Session::from_ron(&text, "huge.ron").expect_err("too many steps");
    assert!(refused.to_string().contains("lesson steps"), "{refused}");
}

/// Run `source` of `dialect` from tick 0 to its end or `max_ticks`, with `session`'s edits.
fn run_to_end(
    session: &Session,
    source: &str,
    max_ticks: u64,
) -> Box<dyn servoscope_core::debugger::Engine> {
    let dialect = session.dialect();
    let settings = dialect.settings_from(&session.settings);
    let engine = match dialect.open_text(source, &settings) {
        Ok(engine) => engine,
        Err(diagnostics) => panic!("does not assemble: {diagnostics:?}\n{source}"),
    };
    let events = session
        .user_events(engine.machine(), "lesson")
        .expect("the lesson's edits name locations of the program");
    servoscope_core::runner::run_engine(engine.as_ref(), &events, max_ticks)
}

#[test]
fn a_failing_check_names_the_value_and_what_was_expected() {
    let session = Session::from_ron(LESSON, "scaling.ron").expect("a lesson session");
    // 40000 × q16(0.0254) >> 16 = 40000 × 1665 >> 16 = 1016 (spec: MULT_S64_SHR16), then DEC.
    let done = run_to_end(&session, &session.program, 1_000);
    let m = done.machine();
    let outcomes = lesson::evaluate_all(session.lesson.as_ref().expect("lesson"), m);
    assert_eq!(outcomes.len(), 2);
    let first = &outcomes[0];
    assert_eq!(first.step, 2, "steps count from 1; step 1 has no checks");
    assert!(!first.pass);
    assert_eq!(first.values, [("R21".to_string(), 1015)]);
    assert_eq!(first.detail(), "R21 = 1015, expected 1016");
    assert!(outcomes[1].pass);
    assert_eq!(outcomes[1].detail(), "R20 = 40000");
    let answered = run_to_end(&session, ANSWER, 1_000);
    let outcomes =
        lesson::evaluate_all(session.lesson.as_ref().expect("lesson"), answered.machine());
    assert!(outcomes.iter().all(|o| o.pass), "{outcomes:?}");
}

#[test]
fn checks_read_names_bits_bcd_and_logic_and_a_bad_check_fails_with_its_reason() {
    let session = Session::from_ron(LESSON, "scaling.ron").expect("a lesson session");
    let done = run_to_end(&session, ANSWER, 1_000);
    let m = done.machine();
    let eval = |text: &str| lesson::evaluate(1, text, m);
    // DEF names resolve to their register; values are reported under the canonical name.
    let by_alias = eval("mm_per_count == 1665");
    assert!(by_alias.pass, "q16(0.0254) = round(0.0254 × 65536) = 1665");
    assert!(eval("R21 > 1000 && !(R20 != 40000)").pass);
    let either = eval("R21 == 1 || R20 == 40000");
    assert!(either.pass);
    assert_eq!(either.expected, None, "no single constant side to expect");
    let below = eval("R21 < 1000");
    assert!(!below.pass);
    assert_eq!(below.detail(), "R21 = 1016, expected < 1000");
    let bcd = eval("R21 == bcd(1016)");
    assert!(!bcd.pass);
    assert_eq!(bcd.detail(), "R21 = 1016, expected bcd(1016) = 4118");
    let broken = eval("R21 === 3");
    assert!(!broken.pass);
    assert!(
        broken.detail().starts_with("not a check for this program"),
        "{broken:?}"
    );
    let unknown = eval("speed == 3");
    assert!(!unknown.pass);
    assert!(
        unknown.detail().contains("no location named 'speed'"),
        "{unknown:?}"
    );
}

#[test]
fn bcd_in_an_expression_is_the_decimal_digits_as_nibbles() {
    let m = common::machine("END\n");
    let value = |text: &str| Expr::compile(text, &m).expect("compiles").eval(&m);
    assert_eq!(value("bcd(1250)"), 0x1250);
    assert_eq!(value("bcd(0)"), 0);
    assert_eq!(value("bcd(9999)"), 0x9999);
    assert_eq!(value("BCD(12) + 1"), 0x13);
    assert_eq!(value("bcd(-5)"), -5, "the negated pattern of the magnitude");
    assert!(Expr::compile("bcd(12", &m).is_err(), "an unclosed call");
}

#[test]
fn a_watch_becomes_a_check_that_holds_now() {
    let session = Session::from_ron(LESSON, "scaling.ron").expect("a lesson session");
    let done = run_to_end(&session, ANSWER, 1_000);
    let m = done.machine();
    assert_eq!(
        lesson::check_from_watch("R21", m).as_deref(),
        Some("R21 == 1016")
    );
    let expr = lesson::check_from_watch("R21 - 16", m).expect("compiles");
    assert_eq!(expr, "(R21 - 16) == 1000");
    assert!(lesson::evaluate(1, &expr, m).pass);
    assert_eq!(lesson::check_from_watch("R21 +", m), None);
}

/// The answer file of a shipped lesson: `tests/fixtures/lessons/<stem>.<extension>`.
fn answer_of(name: &str, dialect: &registry::Dialect) -> PathBuf {
    let stem = Path::new(name).file_stem().expect("a file name");
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("crates/core/tests/fixtures/lessons")
        .join(stem)
        .with_extension(dialect.extensions[0])
}

#[test]
fn every_shipped_lesson_fails_on_its_start_and_passes_on_an_answer() {
    let mut graded = 0;
    for (dialect, name, text) in registry::lessons() {
        let session = Session::from_ron(text, name).expect("a shipped lesson loads");
        let Some(lesson) = &session.lesson else {
            continue;
        };
        assert!(!lesson.title.is_empty(), "{name}: a title");
        assert!(
            lesson.steps.iter().any(|s| !s.checks.is_empty()),
            "{name}: a task with checks"
        );
        let limit = lesson.max_ticks.unwrap_or(dialect.default_max_ticks);
        let start = run_to_end(&session, &session.program, limit);
        let outcomes = lesson::evaluate_all(lesson, start.machine());
        assert!(
            outcomes.iter().all(|o| o.error.is_none()),
            "{name}: every check compiles against the starting program: {outcomes:?}"
        );
        assert!(
            outcomes.iter().any(|o| !o.pass),
            "{name}: the starting program must fail a check"
        );
        let answer = answer_of(name, dialect);
        let source = std::fs::read_to_string(&answer)
            .unwrap_or_else(|e| panic!("{name}: its answer {}: {e}", answer.display()));
        let done = run_to_end(&session, &source, limit);
        let outcomes = lesson::evaluate_all(lesson, done.machine());
        let failed: Vec<String> = outcomes
            .iter()
            .filter(|o| !o.pass)
            .map(|o| format!("{} ({})", o.expr, o.detail()))
            .collect();
        assert!(failed.is_empty(), "{name}: the answer fails {failed:?}");
        graded += 1;
    }
    // Q16.16 scaling, FIFO/LIFO, TML product, DL205 BCD and stack, OpenNet overflow, and a
    // timer/counter exercise for each PLC.
    assert!(graded >= 7, "only {graded} lessons with tasks");
}

#[test]
fn every_dialect_ships_a_lesson_with_a_task() {
    for d in registry::DIALECTS {
        let tasks = d
            .lessons
            .iter()
            .filter_map(|(name, text)| Session::from_ron(text, name).ok())
            .filter(|s| s.lesson.is_some())
            .count();
        assert!(tasks >= 1, "{} has no lesson with a task", d.display_name);
    }
}

#[test]
fn a_lesson_written_in_code_round_trips() {
    let lesson = Lesson {
        title: "Timers".to_string(),
        steps: vec![LessonStep {
            text: "**Start** the timer.\n\n- X0 on\n- wait".to_string(),
            checks: vec!["T0 && !Y0".to_string()],
        }],
        max_ticks: Some(400),
        handed_out: true,
    };
    let session = Session {
        lesson: Some(lesson.clone()),
        ..Session::from_ron(LESSON, "x.ron").expect("loads")
    };
    let text = session.to_ron().expect("encodes");
    assert!(text.contains("lesson: Some"), "{text}");
    assert_eq!(
        Session::from_ron(&text, "y.ron").expect("reads").lesson,
        Some(lesson)
    );
}

#[test]
fn a_grading_budget_stops_even_inside_one_long_scan() {
    // One scan of 9999 × 100 instructions: the clock is read between instructions, not only
    // between scans (a program cheap at first and slow later cannot outrun it).
    let body = "STR SP1\nINCB V0\n".repeat(50);
    let source = format!("STR SP1\nFOR K9999\n{body}NEXT\nEND\n");
    let d = servoscope_core::registry::by_name("dl205").expect("registered");
    let engine = d
        .open_text(&source, &d.default_settings())
        .expect("assembles");
    let (run, finished) = servoscope_core::runner::run_engine_until(
        engine.as_ref(),
        &[],
        10,
        std::time::Instant::now(),
    );
    assert!(!finished);
    assert_eq!(run.machine().ticks(), 0, "stopped inside the first scan");
    assert!(
        run.machine().steps() < 100_000,
        "{} steps",
        run.machine().steps()
    );
    // Given the time, the same call is the straight run exactly.
    let (run, finished) = servoscope_core::runner::run_engine_until(
        engine.as_ref(),
        &[],
        3,
        std::time::Instant::now() + std::time::Duration::from_secs(3600),
    );
    assert!(finished);
    let straight = servoscope_core::runner::run_engine(engine.as_ref(), &[], 3);
    assert_eq!(
        crate::common::every_value(run.machine()),
        crate::common::every_value(straight.machine())
    );
}

#[test]
fn a_lessons_tick_limit_past_the_bound_is_cut_with_a_warning() {
    let text = "(format: 2, dialect: \"dl205\", program: \"STR X0\\nOUT Y0\\nEND\", \
                lesson: Some((title: \"t\", steps: [(text: \"s\", checks: [\"Y0 == 0\"])], max_ticks: Some(1000000000))))";
    let session = servoscope_core::session::Session::from_ron(text, "l.ron").expect("opens");
    let lesson = session.lesson.as_ref().expect("a lesson");
    assert_eq!(
        lesson.max_ticks,
        Some(servoscope_core::lesson::MAX_LESSON_TICKS)
    );
    assert!(
        session.warnings.iter().any(|w| w.contains("1000000000")),
        "{:?}",
        session.warnings
    );
    let ticks = servoscope_core::lesson::grading_ticks(lesson, Some(u64::MAX), session.dialect());
    assert_eq!(ticks, servoscope_core::lesson::MAX_LESSON_TICKS);
}
