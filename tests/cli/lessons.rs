//! The command line: grading through `servoscope check`.
use crate::common;
use common::lessons::{ANSWER, LESSON};
use common::{scratch_file, servoscope};
use std::path::PathBuf;

fn lesson_file(name: &str) -> PathBuf {
    scratch_file(name, LESSON)
}

fn check_json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "one JSON object ({e}): {}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

#[test]
fn check_grades_the_lessons_program_and_a_students_with_exit_codes_and_json() {
    let lesson_path = lesson_file("grade.ron");
    let lesson_arg = lesson_path.to_str().expect("a UTF-8 path");
    // The lesson's own program stores 1015: one check fails, exit 1.
    let out = servoscope(&["check", lesson_arg]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("step 2: FAIL  R21 == 1016  (R21 = 1015, expected 1016)"),
        "{text}"
    );
    assert!(text.contains("step 2: pass  R20 == 40000"), "{text}");
    assert!(text.contains("1 passed, 1 failed"), "{text}");
    // A correct answer passes every check: exit 0, and the JSON says so.
    let answer = scratch_file("answer.qsl", ANSWER);
    let answer_arg = answer.to_str().expect("a UTF-8 path");
    let out = servoscope(&["check", lesson_arg, answer_arg, "--json"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let json = check_json(&out);
    assert_eq!(json["lesson"], "Scaling");
    assert_eq!(json["passed"], 2);
    assert_eq!(json["failed"], 0);
    assert_eq!(json["checks"][0]["step"], 2);
    assert_eq!(json["checks"][0]["expr"], "R21 == 1016");
    assert_eq!(json["checks"][0]["pass"], true);
    assert_eq!(json["checks"][0]["values"]["R21"], 1016);
    // The JSON of a failing run carries the values involved.
    let out = servoscope(&["check", lesson_arg, "--json"]);
    assert_eq!(out.status.code(), Some(1));
    let json = check_json(&out);
    assert_eq!(json["failed"], 1);
    assert_eq!(json["checks"][0]["pass"], false);
    assert_eq!(json["checks"][0]["values"]["R21"], 1015);
}

#[test]
fn check_exits_2_when_the_program_does_not_assemble_or_a_file_is_missing() {
    let lesson_path = lesson_file("grade2.ron");
    let lesson_arg = lesson_path.to_str().expect("a UTF-8 path");
    let broken = scratch_file("broken.qsl", "WRP 20, 40000\nFOO 1\nEND\n");
    let out = servoscope(&["check", lesson_arg, broken.to_str().expect("UTF-8")]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("broken.qsl:2:1"),
        "file, line and column: {stderr}"
    );
    assert!(
        out.stdout.is_empty(),
        "no grading of a program that did not run"
    );
    // With --json, one object: every check failed because nothing ran, and why.
    let out = servoscope(&[
        "check",
        lesson_arg,
        broken.to_str().expect("UTF-8"),
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let j = check_json(&out);
    assert_eq!(
        (j["passed"].as_u64(), j["failed"].as_u64()),
        (Some(0), Some(2))
    );
    let checks = j["checks"].as_array().expect("a list");
    assert_eq!(checks[0]["expr"], "R21 == 1016");
    assert_eq!(checks[0]["pass"], false);
    assert_eq!(checks[0]["error"], "the program did not assemble");
    assert_eq!(j["run"]["status"], "not assembled");
    assert_eq!(j["run"]["program"], broken.to_str().expect("UTF-8"));
    assert_eq!(j["run"]["diagnostics"][0]["line"], 2);
    assert_eq!(j["run"]["diagnostics"][0]["column"], 1);
    let out = servoscope(&["check", "/nonexistent/lesson.ron"]);
    assert_eq!(out.status.code(), Some(2));
    let out = servoscope(&["check", lesson_arg, "/nonexistent/answer.qsl"]);
    assert_eq!(out.status.code(), Some(2));
    // A session without a lesson section cannot grade anything.
    let plain = scratch_file("plain.ron", &LESSON.replace("lesson: Some", "other: Some"));
    let out = servoscope(&["check", plain.to_str().expect("UTF-8")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("without a lesson section"));
    // A program of another dialect is refused by its extension.
    let other = scratch_file("other.dl205", "END\n");
    let out = servoscope(&["check", lesson_arg, other.to_str().expect("UTF-8")]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn check_stops_at_the_tick_limit_it_is_given() {
    let looping = LESSON.replace(
        r"CLC DEC, 21\n        END\n",
        r"CLC DEC, 21\nspin:   CLC INC, 30\n        JMP spin\n",
    );
    let path = scratch_file("spin.ron", &looping);
    let out = servoscope(&[
        "check",
        path.to_str().expect("UTF-8"),
        "--max-ticks",
        "50",
        "--json",
    ]);
    let json = check_json(&out);
    assert_eq!(json["run"]["status"], "limit");
    assert_eq!(json["run"]["ticks"], 50);
}
