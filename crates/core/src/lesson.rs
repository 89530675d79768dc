//! Lessons: a session with a title and steps, each step a text (Markdown) and checks —
//! expressions of the condition language that a correct answer makes true, such as
//! `R21 == 1016`, `V2000 == bcd(1250)` or `T0 && !Y0`.
//!
//! The section is the field `lesson: Some((title: "…", steps: [(text: "…", checks: ["EXPR"]),
//! …]))` of a session file; a session without it is an ordinary session. The window shows the
//! steps and evaluates a step's checks on the present state; `servoscope check` runs a program
//! from tick 0 with the lesson's settings and edits and evaluates every check of every step.
//!
//! Decided: a lesson may say how long grading runs (`max_ticks`: a PLC's runner default is one
//! scan, too short for a timer exercise); steps are numbered from 1 (as the window shows them); a check that does not
//! compile against the program (a name the student's program lacks, a typing error) fails,
//! with the reason, rather than stopping the grading of the other checks.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};
use serde_json::json;

use crate::debugger::expr::Expr;
use crate::machine::{Format, MachineView, value};

#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct Lesson {
    pub title: String,
    pub steps: Vec<LessonStep>,
    /// How many ticks (scans for a PLC) `servoscope check` runs the program before grading;
    /// `None`: the dialect's runner default. `--max-ticks` overrides it.
    pub max_ticks: Option<u64>,
    /// Handed out to students: the window offers no Edit lesson (the teacher's copy, without
    /// it, keeps it).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub handed_out: bool,
}

#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct LessonStep {
    /// What the student reads, in Markdown.
    pub text: String,
    /// Expressions that hold once the step's task is done.
    pub checks: Vec<String>,
}

/// One check evaluated on a machine's state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckOutcome {
    /// The step it belongs to, from 1.
    pub step: usize,
    pub expr: String,
    pub pass: bool,
    /// Every location the check reads, by its canonical name, with its value as the check
    /// sees it (sign-extended when the location is signed).
    pub values: Vec<(String, i64)>,
    /// The same values as the location shows them, where that differs from the number
    /// (a BCD word, a Q16.16 register): for the text, not the JSON.
    readings: Vec<Option<String>>,
    /// The other side of a comparison with a constant (`== 1016`), for "expected 1016".
    pub expected: Option<String>,
    /// Why it could not be evaluated at all (then it fails).
    pub error: Option<String>,
}

impl CheckOutcome {
    /// The values involved, in words: `R21 = 1015, expected 1016`.
    pub fn detail(&self) -> String {
        if let Some(error) = &self.error {
            return error.clone();
        }
        let mut out = String::new();
        for ((name, number), reading) in self.values.iter().zip(&self.readings) {
            if !out.is_empty() {
                out.push_str(", ");
            }
            match reading {
                Some(reading) => write!(out, "{name} = {reading}"),
                None => write!(out, "{name} = {number}"),
            }
            .ok();
        }
        if let Some(expected) = self.expected.as_ref().filter(|_| !self.pass) {
            if !out.is_empty() {
                out.push_str(", ");
            }
            let _ = write!(out, "expected {expected}");
        }
        out
    }

    /// `{"step": 1, "expr": "…", "pass": false, "values": {"R21": 1015}}` (then `"error"` when
    /// the check could not be evaluated), fields in that order.
    pub fn to_json(&self) -> serde_json::Value {
        let values: serde_json::Map<String, serde_json::Value> = (self.values.iter())
            .map(|(name, v)| (name.clone(), json!(v)))
            .collect();
        let mut out = json!({
            "step": self.step,
            "expr": self.expr,
            "pass": self.pass,
            "values": values,
        });
        if let Some(error) = &self.error {
            out["error"] = json!(error);
        }
        out
    }
}

/// Evaluate one check of step `step` on `m`'s present state.
pub fn evaluate(step: usize, text: &str, m: &dyn MachineView) -> CheckOutcome {
    let mut outcome = CheckOutcome {
        step,
        expr: text.trim().to_string(),
        pass: false,
        values: Vec::new(),
        readings: Vec::new(),
        expected: None,
        error: None,
    };
    let expr = match Expr::compile(text, m) {
        Ok(expr) => expr,
        Err(e) => {
            outcome.error = Some(format!("not a check for this program: {e}"));
            return outcome;
        }
    };
    outcome.pass = expr.holds(m);
    let mut seen = Vec::new();
    for loc in expr.locations() {
        if seen.contains(&loc) {
            continue;
        }
        seen.push(loc);
        let Some(info) = m.info(loc) else { continue };
        let number = crate::machine::value_of(m, loc);
        let reading = match info.reading() {
            Format::Signed | Format::Unsigned => None,
            format => Some(format!(
                "{} ({})",
                format.show(m.read(loc), info.width),
                format.name(),
            )),
        };
        outcome.values.push((info.name, number));
        outcome.readings.push(reading);
    }
    outcome.expected = expected_side(text, m);
    outcome
}

/// Every check of every step, in order.
pub fn evaluate_all(lesson: &Lesson, m: &dyn MachineView) -> Vec<CheckOutcome> {
    lesson
        .steps
        .iter()
        .enumerate()
        .flat_map(|(i, step)| step.checks.iter().map(move |c| evaluate(i + 1, c, m)))
        .collect()
}

/// How many ticks grading runs: `asked` (`--max-ticks`), else the lesson's `max_ticks`, else
/// the dialect's runner default (one scan for a PLC, to the end or 10^7 ticks otherwise).
pub fn grading_ticks(
    lesson: &Lesson,
    asked: Option<u64>,
    dialect: &crate::registry::Dialect,
) -> u64 {
    asked
        .or(lesson.max_ticks)
        .unwrap_or(dialect.default_max_ticks)
        .min(MAX_LESSON_TICKS)
}

/// The most ticks (scans) a lesson is graded over: the drives' runner default, 20 minutes of a
/// SilverLode's time and far past any exercise; a session asking more is cut to it with a
/// warning, as a replay past [`crate::session::MAX_REPLAY_TICKS`] is refused.
pub const MAX_LESSON_TICKS: u64 = 10_000_000;

/// The wall-clock budget of `servoscope check` unless `--timeout` says otherwise.
pub const DEFAULT_GRADING_SECONDS: f64 = 60.0;

/// A graded run: the machine at its end, every check's outcome, and whether the run got to
/// its last tick within the time budget (if not, every check failed unevaluated).
pub struct Grading {
    pub run: Box<dyn crate::debugger::Engine>,
    pub outcomes: Vec<CheckOutcome>,
    pub finished: bool,
}

/// The run a lesson grades, the same for `servoscope check` and the window's Check: `engine`'s
/// program from its start, with the lesson session's edits and inputs, for `ticks`; every check
/// of every step evaluated at its end. `Err` when the session's edits name what the program
/// lacks.
///
/// `budget` bounds the wall-clock time: a run that has not reached `ticks` when it is spent
/// stops there, and every check fails unevaluated saying so (grading half a run would grade
/// the wrong moment).
pub fn grading_run(
    engine: &dyn crate::debugger::Engine,
    session: &crate::session::Session,
    lesson: &Lesson,
    ticks: u64,
    path: &str,
    budget: std::time::Duration,
) -> Result<Grading, crate::session::SessionError> {
    let events = session.user_events(engine.machine(), path)?;
    let started = std::time::Instant::now();
    let deadline = started
        .checked_add(budget)
        .unwrap_or(started + std::time::Duration::from_secs(86_400 * 365));
    let (run, finished) = crate::runner::run_engine_until(engine, &events, ticks, deadline);
    let outcomes = if finished {
        evaluate_all(lesson, run.machine())
    } else {
        let unit = if run.machine().is_plc() {
            "scan"
        } else {
            "tick"
        };
        unevaluated(
            lesson,
            &format!(
                "grading stopped after {:.1} s at {unit} {} of {ticks}: the time budget (--timeout) ran out",
                started.elapsed().as_secs_f64(),
                run.machine().ticks()
            ),
        )
    };
    Ok(Grading {
        run,
        outcomes,
        finished,
    })
}

/// Every check of `lesson` failed without being evaluated, each saying `why` (the program
/// did not assemble: nothing ran to look at).
pub fn unevaluated(lesson: &Lesson, why: &str) -> Vec<CheckOutcome> {
    (lesson.steps.iter().enumerate())
        .flat_map(|(i, step)| {
            step.checks.iter().map(move |c| CheckOutcome {
                step: i + 1,
                expr: c.trim().to_string(),
                pass: false,
                values: Vec::new(),
                readings: Vec::new(),
                expected: None,
                error: Some(why.to_string()),
            })
        })
        .collect()
}

/// For a check that compares something with a constant (`R21 == 1016`, `V2000 >=
/// bcd(100)`), what the constant side asks for: `1016`, `>= bcd(100) = 256`. `None` for
/// anything else (`T0 && !Y0`, two locations compared).
fn expected_side(text: &str, m: &dyn MachineView) -> Option<String> {
    let chars: Vec<char> = text.chars().collect();
    let mut depth = 0i32;
    let mut split = None;
    let mut i = 0;
    while i < chars.len() {
        let pair: String = chars[i..chars.len().min(i + 2)].iter().collect();
        match chars[i] {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ if depth != 0 => {}
            _ if pair == "&&" || pair == "||" => return None,
            _ if pair == "<<" || pair == ">>" => i += 1,
            _ if ["==", "!=", "<=", ">="].contains(&pair.as_str()) => {
                if split.is_some() {
                    return None;
                }
                split = Some((i, pair));
                i += 1;
            }
            '<' | '>' => {
                if split.is_some() {
                    return None;
                }
                split = Some((i, chars[i].to_string()));
            }
            _ => {}
        }
        i += 1;
    }
    let (at, op) = split?;
    let right: String = chars[at + op.chars().count()..].iter().collect();
    let right = right.trim();
    let constant = Expr::compile(right, m).ok()?;
    if constant.locations().next().is_some() {
        return None;
    }
    let value = constant.eval(m);
    // Against one location read in BCD or Q16.16, the constant in that reading too: `V0 ==
    // bcd(39)` expects 39, as the view shows V0; a plain number there names its BCD digits.
    let left: String = chars[..at].iter().collect();
    let reading = m
        .find(left.trim())
        .and_then(|loc| m.info(loc))
        .filter(|info| matches!(info.reading(), Format::Bcd | Format::Q16));
    let plain = right.parse::<i64>().is_ok_and(|n| n == value);
    let shown = match reading {
        Some(info) => {
            let format = info.reading();
            let shown = format.show(value as u64, info.width);
            let written_so = right.to_ascii_lowercase().starts_with(match format {
                Format::Bcd => "bcd(",
                _ => "q16(",
            });
            if written_so {
                shown
            } else {
                format!("{right} ({} {shown})", format.name())
            }
        }
        None if plain => right.to_string(),
        None => format!("{right} = {value}"),
    };
    Some(if op == "==" {
        shown
    } else {
        format!("{op} {shown}")
    })
}

/// The report of `servoscope check` as one JSON object: `lesson`, `passed`, `failed`,
/// `checks`, then `run` (the program, how its run stopped, its ticks).
pub fn report_json(title: &str, outcomes: &[CheckOutcome], run: serde_json::Value) -> String {
    let passed = outcomes.iter().filter(|o| o.pass).count();
    let checks: Vec<serde_json::Value> = outcomes.iter().map(CheckOutcome::to_json).collect();
    json!({
        "lesson": title,
        "passed": passed,
        "failed": outcomes.len() - passed,
        "checks": checks,
        "run": run,
    })
    .to_string()
}

/// The report of `servoscope check` as text: one line a check, then the totals.
pub fn report_text(title: &str, outcomes: &[CheckOutcome], run: &str) -> String {
    let mut out = format!("{title}\n{run}\n");
    for o in outcomes {
        let verdict = if o.pass { "pass" } else { "FAIL" };
        let detail = o.detail();
        let _ = write!(out, "step {}: {verdict}  {}", o.step, o.expr);
        if !detail.is_empty() {
            let _ = write!(out, "  ({detail})");
        }
        out.push('\n');
    }
    let passed = outcomes.iter().filter(|o| o.pass).count();
    let _ = writeln!(out, "{passed} passed, {} failed", outcomes.len() - passed);
    out
}

/// A watch made into a check that holds on the present state, for "Save as lesson": a watched
/// location `R21` (now 1016) becomes `R21 == 1016` (`V2000 == bcd(1250)` for a BCD word); any
/// other expression `E` (now 7) becomes `(E) == 7`. `None` when it does not compile.
pub fn check_from_watch(watch: &str, m: &dyn MachineView) -> Option<String> {
    let expr = Expr::compile(watch, m).ok()?;
    if let Some(loc) = m.find(watch.trim())
        && let Some(info) = m.info(loc)
    {
        let raw = m.read(loc);
        return Some(match info.reading() {
            Format::Bcd if value::is_bcd(raw) => {
                format!("{} == bcd({})", info.name, value::bcd_decimal(raw))
            }
            _ => format!("{} == {}", info.name, crate::machine::value_of(m, loc)),
        });
    }
    Some(format!("({}) == {}", expr.text(), expr.eval(m)))
}
