//! The assembler (spec §1): syntax, every error with line and column, and no panic on any input.

use crate::common;
use common::{reg, run_ok};
use proptest::prelude::*;
use servoscope_core::machine::silverlode::assemble;
use servoscope_core::machine::{Diagnostic, Machine, MachineView};

fn errors(source: &str) -> Vec<Diagnostic> {
    assemble(source).expect_err("expected errors")
}

fn at(d: &Diagnostic) -> (usize, usize) {
    (d.line, d.col)
}

#[test]
fn syntax_labels_defs_aliases_and_literals() {
    let m = run_ok(
        "; a comment line\n\
         DEF speed = R30\n\
         DEF one_rps = 3865\n\
         DEF gain = q16(254.3467)\n\
         \n\
         start:\n\
         \tWRP speed, one_rps   ; alias of R30 and a number\n\
         loop: clc inc, r31\n\
         CLD SUB, 32, R31, 0b11\n\
         JMP loop, !zero\n\
         WRP 26, 1_000\n\
         CLD MULT_S64_SHR16, 25, 26, gain\n\
         WRP acc, 0xABCD_893F\n\
         WRP last_trig, -15\n",
    );
    assert_eq!(reg(&m, 30), 3865);
    assert_eq!(reg(&m, 31), 3);
    assert_eq!(reg(&m, 25), 254346);
    assert_eq!(m.reg(10) as u32, 0xABCD_893F);
    assert_eq!(reg(&m, 4), -15);
}

#[test]
fn data_accepts_the_full_32_bit_range() {
    let m = run_ok("WRP 11, 4294967295\nWRP 12, -2147483648");
    assert_eq!((reg(&m, 11), reg(&m, 12)), (-1, i32::MIN));
    let e = errors("WRP 11, 4294967296\nWRP 12, -2147483649");
    assert_eq!(e.len(), 2);
}

#[test]
fn labels_are_case_sensitive_mnemonics_are_not() {
    let e = errors("Loop: wrp 11, 1\njmp loop");
    assert_eq!(e.len(), 1);
    assert_eq!(at(&e[0]), (2, 5));
    assert!(
        e[0].message.contains("did you mean 'Loop'"),
        "{}",
        e[0].message
    );
}

#[test]
fn every_error_is_reported_with_line_and_column() {
    let source = "CLK ADD, 1\n\
                  CLD ADDD, 25, 26, 10\n\
                  CLD ADD, 250, 26, 0x1_0000_0000\n\
                  JMP nowhere\n\
                  JMP ok, ZEROO\n\
                  ok: CLC SAVE, R26, 5\n\
                  CLC ADD, 12z\n\
                  ok: END\n\
                  CLD SAVE, 1, 2, 3\n\
                  CLC Q_INIT, 5\n";
    let e = errors(source);
    let got: Vec<(usize, usize)> = e.iter().map(at).collect();
    assert_eq!(
        got,
        vec![
            (1, 1),
            (2, 5),
            (3, 10),
            (3, 19),
            (4, 5),
            (5, 9),
            (6, 20),
            (7, 10),
            (8, 1),
            (9, 5),
            (10, 5)
        ],
        "{e:#?}"
    );
    assert!(e[0].message.contains("did you mean CLC"));
    assert!(e[1].message.contains("did you mean ADD"));
    assert!(e[2].message.contains("R0–R199"));
    assert!(e[3].message.contains("32 bits"));
    assert!(e[4].message.contains("undefined label 'nowhere'"));
    assert!(e[5].message.contains("did you mean ZERO"));
    assert!(e[6].message.contains("takes 2 operands"));
    assert!(e[7].message.contains("not a number"));
    assert!(e[8].message.contains("duplicate label 'ok'"));
    assert!(e[9].message.contains("CLC operation"));
    assert!(e[10].message.contains("CLD/CLX operation"));
    // The file:line:col form.
    assert_eq!(
        e[0].with_file("prog.qsl").to_string(),
        "prog.qsl:1:1: error: unknown command 'CLK'; did you mean CLC?"
    );
}

#[test]
fn def_must_come_before_use() {
    let e = errors("WRP 11, later\nDEF later = 5\nDEF later = 6\nDEF R12 = 4\nDEF target = 3");
    assert_eq!(e.len(), 4, "{e:#?}");
    assert!(e[0].message.contains("used before its DEF on line 2"));
    assert_eq!(at(&e[0]), (1, 9));
    assert!(e[1].message.contains("already defined on line 2"));
    assert!(e[2].message.contains("register name"));
    assert!(e[3].message.contains("register name"));
}

#[test]
fn registers_and_numbers_are_not_confused() {
    let e = errors(
        "DEF speed = R30\nCLD ADD, 25, 26, R27\nWRP 11, speed\nCLC ADD, q16(1.5)\nDEF big = 300\nCLC INC, big",
    );
    assert_eq!(e.len(), 4, "{e:#?}");
    assert!(e[0].message.contains("CLX takes its data from a register"));
    assert!(e[1].message.contains("names register R30"));
    assert!(e[2].message.contains("not a register"));
    assert!(e[3].message.contains("outside R0–R199"));
}

#[test]
fn malformed_numbers_and_literals() {
    let e = errors(
        "WRP 11, 0x\nWRP 11, 0b102\nWRP 11, --5\nWRP 11, q16(1.2.3)\nWRP 11, q16(40000)\nDLY -5\nWRP 11,\nCER 1",
    );
    assert_eq!(e.len(), 8, "{e:#?}");
    assert!(e[4].message.contains("does not fit"));
    assert!(e[5].message.contains("negative"));
    assert!(e[6].message.contains("missing"));
}

#[test]
fn a_program_with_errors_produces_nothing_but_one_without_runs() {
    assert!(assemble("WRP 11, 1\nBOGUS").is_err());
    assert!(assemble("WRP 11, 1").is_ok());
}

#[test]
fn used_registers_include_implicit_ones() {
    let p = assemble("CLC ADD, 20\nCLD Q_INIT, 11, 40, 3\nCLD MULT_U64, 50, 21, 3\nMAV 5, 1, 1")
        .unwrap();
    for r in [10, 20, 11, 40, 41, 42, 43, 44, 50, 51, 21, 0, 1, 6, 7] {
        assert!(
            p.used_registers.contains(&r),
            "R{r} missing from {:?}",
            p.used_registers
        );
    }
}

/// Fragments of real programs, recombined and mutated.
fn fragment() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "CLC",
            "CLD",
            "CLX",
            "WRP",
            "JMP",
            "CALL",
            "RET",
            "DLY",
            "WBS",
            "CER",
            "END",
            "MAV",
            "MRV",
            "RAV",
            "RRV",
            "ZTP",
            "TTP",
            "DEF",
            "Q_INIT",
            "Q_PUSH_HEAD",
            "Q_POP_TAIL_ERR",
            "Q_READ",
            "DIV",
            "MOD_REV",
            "COPY_REF",
            "SAVE_REF",
            "MULT_U64",
            "DIV_U64",
            "SUB_TARGET",
            "loop",
            "loop:",
            "x =",
            ",",
            ", ",
            ";",
            "!",
            "IO1",
            "!ZERO",
            "R199",
            "199",
            "0",
            "-1",
            "0xFFFF",
            "0b1",
            "q16(",
            ")",
            "q16(-1.5)",
            "2147483648",
            "-2147483648",
            "4294967295",
            "1_0",
            "\n",
            "\t",
            " ",
            "(",
            "=",
        ])
        .prop_map(str::to_string),
        "[ -~]{0,6}",
        "\\PC{0,3}",
    ]
}

fn program_text() -> impl Strategy<Value = String> {
    prop::collection::vec(fragment(), 0..40).prop_map(|parts| parts.join(" "))
}

/// Programs that assemble more often: real command shapes with random operands.
fn plausible_program() -> impl Strategy<Value = String> {
    let line = (
        prop::sample::select(vec![
            "CLC INC, {a}",
            "CLC COPY_REF, {a}",
            "CLC SAVE_REF, {a}",
            "CLC DIV, {a}",
            "CLD Q_INIT, {a}, {b}, {c}",
            "CLD Q_PUSH_HEAD_ERR, {a}, {b}, {c}",
            "CLD Q_POP_TAIL, {a}, {b}, {c}",
            "CLX Q_READ, {a}, {b}, {c}",
            "CLD DIV_U64, {a}, {b}, {c}",
            "CLD MULT_U64, {a}, {b}, {c}",
            "CLX MOD_REV, {a}, {b}, {c}",
            "WRP {a}, {v}",
            "JMP l{c}, !ZERO",
            "CALL l{c}",
            "RET",
            "DLY {c}",
            "MRV {v}, {v}, {v}",
            "RAV {a}, {v}, {v}, IO2",
            "ZTP",
            "CLC SUB_TARGET, {a}",
            "CER l{c}",
            "END",
        ]),
        0u8..200,
        0u8..200,
        0u8..6,
        any::<i32>(),
    )
        .prop_map(|(shape, a, b, c, v)| {
            shape
                .replace("{a}", &a.to_string())
                .replace("{b}", &b.to_string())
                .replace("{c}", &c.to_string())
                .replace("{v}", &v.to_string())
        });
    prop::collection::vec(line, 1..30).prop_map(|lines| {
        let mut text = lines.join("\n");
        for c in 0..6 {
            text.push_str(&format!("\nl{c}: CLC INC, 150"));
        }
        text
    })
}

/// 2000 cases in a normal run; `FUZZ_CASES=1000000 cargo test --release --test assembler` to
/// fuzz for longer.
fn fuzz_cases() -> u32 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2000)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(fuzz_cases()))]

    #[test]
    fn never_panics_on_any_text(text in program_text()) {
        if let Ok(program) = assemble(&text) {
            let mut m = servoscope_core::machine::silverlode::SilverLode::new(std::sync::Arc::new(program));
            m.run_until(2_000, |_| false);
            let _ = m.explain_last();
        }
    }

    #[test]
    fn never_panics_running_plausible_programs(text in plausible_program()) {
        let program = assemble(&text);
        prop_assert!(program.is_ok(), "{:?}", program.err());
        let mut m = servoscope_core::machine::silverlode::SilverLode::new(std::sync::Arc::new(program.unwrap()));
        for _ in 0..300 {
            m.step_tick();
            let _ = (m.explain_last(), m.last_written(), m.queues(), m.fault(), m.call_stack_lines());
        }
    }

    /// Line endings and a byte-order mark from other editors change nothing: the same
    /// diagnostics, the same program.
    #[test]
    fn other_editors_line_endings_read_the_same(text in program_text(), ending in 0..3usize, bom: bool) {
        let lf = servoscope_core::text::normalize(&text).into_owned();
        let ended = match ending {
            0 => lf.replace('\n', "\r\n"),
            1 => lf.replace('\n', "\r"),
            _ => lf.clone(),
        };
        let other = if bom { format!("\u{feff}{ended}") } else { ended };
        let a = servoscope_core::debugger::Debugger::new("a.qsl", lf.as_str());
        let b = servoscope_core::debugger::Debugger::new("b.qsl", other.as_str());
        prop_assert_eq!(a.diagnostics(), b.diagnostics());
        prop_assert_eq!(a.source(), b.source());
    }

    /// Names of any length: "did you mean" stays bounded and the errors are still all there.
    #[test]
    fn long_undefined_names_fail_cleanly(len in 60usize..3_000, labels in 0usize..400) {
        let mut text: String = (0..labels).map(|i| format!("l{i}: WRP 11, {i}\n")).collect();
        text.push_str(&format!("JMP {}\nCLC INC, {}\n", "x".repeat(len), "y".repeat(len)));
        let diags = assemble(&text).expect_err("two undefined names");
        prop_assert_eq!(diags.len(), 2);
        prop_assert!(diags.iter().all(|d| !d.message.contains("did you mean")));
    }

    #[test]
    fn errors_point_inside_their_line(text in program_text()) {
        if let Err(diags) = assemble(&text) {
            let lines: Vec<&str> = text.lines().collect();
            for d in diags {
                prop_assert!(d.line >= 1 && d.line <= lines.len(), "{d:?}");
                prop_assert!(d.col >= 1 && d.col <= lines[d.line - 1].chars().count() + 1, "{d:?} in {:?}", lines[d.line - 1]);
            }
        }
    }
}

#[test]
fn a_register_past_r199_is_out_of_range_wherever_it_stands() {
    let e = errors("WRP 20, R300\nCLD ADD, 20, 21, r250\nEND\n");
    assert_eq!(e.len(), 2);
    for d in &e {
        assert!(d.message.contains("outside R0–R199"), "{}", d.message);
    }
}
