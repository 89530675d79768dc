//! #43 item 20: messages that said something confusing now say what to write instead.

use servoscope_core::debugger::{Event, Watch};
use servoscope_core::machine::{Format, Pos};
use servoscope_core::registry::by_name;
use servoscope_core::runner::parse_set_spec;

use crate::common::debugger;

/// The assembler's messages for `source` in `dialect`, as "line:col: message".
fn errors(dialect: &str, source: &str) -> Vec<String> {
    let d = by_name(dialect).expect("registered");
    match d.open_text(source, &d.default_settings()) {
        Ok(_) => Vec::new(),
        Err(diags) => diags
            .iter()
            .map(|e| format!("{}:{}: {}", e.line, e.col, e.message))
            .collect(),
    }
}

#[test]
fn another_dialects_comment_names_this_ones() {
    assert_eq!(
        errors("dl205", "STR X0 ; start\nOUT Y0\nEND\n"),
        ["1:8: DL205 comments start with // (';' starts a comment in OpenNet, not here)"]
    );
    assert_eq!(
        errors("opennet", "LOD I0 // start\nOUT Q0\nEND\n"),
        ["1:8: OpenNet comments start with ; ('//' starts a comment in DL205, not here)"]
    );
}

#[test]
fn dl205_slips_say_what_to_write() {
    assert_eq!(
        errors("dl205", "STR X0\nSTR X1\nOR STR\nOUT Y0\nEND\n"),
        ["3:1: write ORSTR as one word: it joins the last two branches"]
    );
    // Tenths of a second for TMR (K50 = 5.0 s), hundredths for TMRF; counts for a counter.
    let timer = errors("dl205", "STR X0\nTMR T0 50\nEND\n");
    assert!(
        timer[0].ends_with("write K50 (= 5.0 s, in tenths of a second)"),
        "{timer:?}"
    );
    let fast = errors("dl205", "STR X0\nTMRF T1 250\nEND\n");
    assert!(
        fast[0].ends_with("write K250 (= 2.50 s, in hundredths of a second)"),
        "{fast:?}"
    );
    let counter = errors("dl205", "STR X0\nSTR X1\nCNT CT0 12\nEND\n");
    assert!(counter[0].ends_with("write K12 (12 counts)"), "{counter:?}");
}

#[test]
fn opennet_names_its_own_areas_for_another_vendors() {
    let out = errors("opennet", "LOD I0\nOUT Y0\nEND\n");
    assert!(out[0].ends_with("OpenNet's outputs are Q (Q0)"), "{out:?}");
    let input = errors("opennet", "LOD X3\nOUT Q0\nEND\n");
    assert!(
        input[0].ends_with("OpenNet's inputs are I (I3)"),
        "{input:?}"
    );
}

#[test]
fn expressions_take_q16_and_explain_k_constants() {
    let d = debugger("silverlode", "WRP 20, 98304\nEND\n");
    assert_eq!(d.evaluate("q16(1.5)"), Ok(98304));
    assert_eq!(d.evaluate("q16(-0.5)"), Ok(-32768));
    assert_eq!(d.evaluate("R20 == q16(1.5)"), Ok(0), "R20 not yet written");
    let decimal = d.evaluate("R20 > 1.5").expect_err("a decimal outside q16");
    assert!(decimal.message.contains("write q16(1.5)"), "{decimal}");
    let d = debugger("dl205", "STR X0\nOUT Y0\nEND\n");
    let k = d.evaluate("V0 >= K50").expect_err("K50 is not a location");
    assert!(k.message.contains("bcd(50)"), "{k}");
    let too_big = d.evaluate("q16(50000.0)").expect_err("out of range");
    assert!(
        too_big.message.contains("-32768 to 32767.9999847"),
        "{too_big}"
    );
}

#[test]
fn a_watch_says_when_the_machine_would_wrap_what_it_computes() {
    let mut d = debugger("silverlode", "WRP 20, 100000\nWRP 21, 100000\nEND\n");
    d.set_watches(vec![
        Watch {
            expr: "R20 * R21".into(),
            format: Format::Signed,
        },
        Watch {
            expr: "R20 + R21".into(),
            format: Format::Signed,
        },
        Watch {
            expr: "R20".into(),
            format: Format::Signed,
        },
    ]);
    d.set_speed(servoscope_core::debugger::Speed::Unlimited);
    d.run();
    for _ in 0..100 {
        if !d.advance(0.016, std::time::Duration::from_millis(20)) {
            break;
        }
    }
    assert_eq!(d.watch_value(0), Ok(10_000_000_000));
    // 10^10 mod 2^32 = 1410065408, a positive 32-bit value.
    assert_eq!(
        d.watch_wrap_note(0).as_deref(),
        Some("computed in 64 bits: a 32-bit register would hold 1410065408 (it wraps)")
    );
    assert_eq!(d.watch_wrap_note(1), None, "200000 fits");
    assert_eq!(d.watch_wrap_note(2), None, "a location is what it holds");
}

#[test]
fn set_takes_tml_decimals_and_points_to_a_counters_value() {
    let tml = debugger("tml", "fixed f;\nf = 1.5;\nEND;\n");
    for text in ["CSPD=10.", "CSPD=10.0"] {
        let event = parse_set_spec(tml.machine(), text).expect("a decimal speed");
        assert_eq!(
            event.change,
            servoscope_core::debugger::history::Change::Set(10 << 16),
            "{text}"
        );
    }
    let plc = debugger("opennet", "LOD I0\nLOD I1\nCNT C0 10\nEND\n");
    let err = parse_set_spec(plc.machine(), "C0=10").expect_err("C0 is a bit");
    assert!(err.to_string().contains("C0.current"), "{err}");
}

#[test]
fn who_wrote_names_the_scan_and_the_instruction() {
    let event = Event::WrittenBy {
        location: "V0".into(),
        at: Pos {
            tick: 1186,
            step: 2,
        },
        line: Some(3),
        explanation: "OUT V0".into(),
    };
    assert_eq!(
        event.describe("scan"),
        "V0 was written at scan 1186, instruction 2, line 3: OUT V0"
    );
}

/// Sessions named `*_lesson` are lessons: they have checks (walk-throughs, a session at an
/// interesting moment without checks, were named so).
#[test]
fn every_lesson_named_so_has_checks() {
    for dialect in servoscope_core::registry::DIALECTS {
        for (name, text) in dialect.lessons {
            let session = servoscope_core::session::Session::from_ron(text, name)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let checks = session
                .lesson
                .as_ref()
                .map_or(0, |l| l.steps.iter().map(|s| s.checks.len()).sum());
            if name.contains("_lesson") {
                assert!(checks > 0, "{name} is called a lesson and has no checks");
            }
        }
    }
}
