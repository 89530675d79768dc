//! Issue #22 items 6–8: an explanation says when a result wrapped, saturated, was truncated or
//! set a carry or error flag; an instruction is credited only with what it wrote; the runner's
//! trace carries the same words. Expected numbers are worked by hand from the specs.

use crate::common::debugger;

use servoscope_core::debugger::Debugger;
use servoscope_core::machine::{Loc, MachineView};

/// Step until `line` has run, and return its explanation.
fn explained_after(d: &mut Debugger, line: usize) -> String {
    for _ in 0..200 {
        d.step_command();
        if d.machine().last_line() == Some(line) {
            return d.machine().explain_last().unwrap_or_default();
        }
    }
    panic!("line {line} never ran");
}

fn names(m: &dyn MachineView, locs: &[Loc]) -> Vec<String> {
    locs.iter().filter_map(|&l| Some(m.info(l)?.name)).collect()
}

#[test]
fn a_q16_multiply_that_overflows_says_so() {
    // q16(30000.5) = 1966112768; 100000 × 30000.5 = 3000050000 > 2^31 − 1, and bits 47..16 of the
    // product read as signed 32 bits are 3000050000 − 2^32 = −1294917296 (the numbers).
    let mut d = debugger(
        "silverlode",
        "WRP 20, 100000\nCLD MULT_S64_SHR16, 21, 20, q16(30000.5)\nEND",
    );
    let text = explained_after(&mut d, 2);
    assert!(text.contains("= -1294917296"), "{text}");
    assert!(
        text.contains("overflow: (a × d) >> 16 = 3000050000 does not fit 32 bits"),
        "{text}"
    );
}

#[test]
fn silverlode_wraps_and_remainders_are_said() {
    let mut d = debugger(
        "silverlode",
        "WRP 5, 2147483647\nCLC INC, 5\nWRP 10, 17\nWRP 6, 5\nCLC DIV, 6\nEND",
    );
    let inc = explained_after(&mut d, 2);
    assert!(
        inc.ends_with(
            "— overflow: the exact result 2147483648 does not fit, it wrapped to -2147483648"
        ),
        "{inc}"
    );
    // 17 / 5 = 3 remainder 2.
    let div = explained_after(&mut d, 5);
    assert!(
        div.ends_with("= 3 (truncated toward zero) — remainder 2 discarded"),
        "{div}"
    );
    // A result that fits says nothing more.
    let mut d = debugger("silverlode", "WRP 5, 41\nCLC INC, 5\nEND");
    assert_eq!(explained_after(&mut d, 2), "R5 = R5 + 1 = 41 + 1 = 42");
}

#[test]
fn tml_wraps_at_16_bits_and_says_so() {
    // Spec: "Results wrap: 32767 + 1 = −32768".
    let mut d = debugger("tml", "int big;\nbig = 32767;\nbig += 1;\nEND;\n");
    let text = explained_after(&mut d, 3);
    assert!(
        text.contains("overflow: the exact result 32768 does not fit, it wrapped to -32768"),
        "{text}"
    );
}

#[test]
fn dl205_add_with_a_carry_names_sp66_and_lists_it_as_written() {
    // BCD 9999 + 1 = 10000: the low four digits keep 0000 and SP66 (carry out of the low word)
    // comes on (spec §6.3).
    let mut d = debugger(
        "dl205",
        "STR SP1\nLD K1\nOUT V2010\nLD K9999\nADD V2010\nOUT V2000\nEND\n",
    );
    let text = explained_after(&mut d, 5);
    assert!(
        text.contains("SP66 = 1: carry out of the low word"),
        "{text}"
    );
    let m = d.machine();
    let written = names(m, &m.instruction_written());
    for flag in ["SP63", "SP66", "SP67", "SP70", "SP75"] {
        assert!(written.contains(&flag.to_string()), "{flag} in {written:?}");
    }
    assert!(written.contains(&"ACC".to_string()));
    assert!(
        !written.iter().any(|n| n.starts_with('L')),
        "no stack level moved: {written:?}"
    );
}

#[test]
fn dl205_bin_on_non_bcd_data_names_sp75() {
    let mut d = debugger("dl205", "STR SP1\nLD V2000\nBIN\nOUT V2001\nEND\n");
    d.set_text("V2000", "0x00A0").expect("a value");
    let text = explained_after(&mut d, 3);
    assert!(text.contains("SP75 = 1"), "{text}");
    let m = d.machine();
    assert_eq!(names(m, &m.instruction_written()), ["SP75"]);
}

#[test]
fn opennet_names_its_carry_relay() {
    // ADD(W): 65535 + 1 = 65536 does not fit 16 bits; M8003 (carry/borrow) comes on.
    let mut d = debugger("opennet", "LOD M8120\nADD(W) 65535 1 D0\nEND\n");
    let text = explained_after(&mut d, 2);
    assert!(text.contains("65536 > 65535"), "{text}");
    assert!(text.contains("M8003 = 1 (carry/borrow"), "{text}");
}

/// Item 7: the servo model's writes of the same tick are not credited to the command.
#[test]
fn a_jump_is_not_credited_with_the_motion_models_writes() {
    // The move ends when the target is reached; the motor is still settling in the tick after,
    // where the JMP runs.
    let mut d = debugger(
        "silverlode",
        "MAV 200, 38650, 16106128\nloop: JMP loop, INPUT_FOUND\nEND",
    );
    d.set_speed(servoscope_core::debugger::Speed::Unlimited);
    d.run_to_line(2);
    while d.advance(0.016, std::time::Duration::from_millis(200)) {}
    d.step_command();
    let text = d.machine().explain_last().unwrap_or_default();
    assert!(text.contains("does not hold"), "{text}");
    let m = d.machine();
    assert_eq!(m.last_line(), Some(2));
    assert!(
        !m.last_written().is_empty(),
        "the motor moves: the register view still highlights R0, R1"
    );
    assert!(m.instruction_written().is_empty(), "a JMP writes nothing");
    let log = d.execution_log(servoscope_core::debugger::log::LogFilter::All, 10, u64::MAX);
    assert!(log.rows.last().expect("rows").written.is_empty());
}

/// Item 8: END is credited with PSW (bit 13, program done), a CLC with ISW.
#[test]
fn flag_words_are_listed_as_written() {
    let mut d = debugger("silverlode", "WRP 12, 0\nCLC INC, 12\nEND");
    explained_after(&mut d, 2);
    let m = d.machine();
    assert_eq!(names(m, &m.instruction_written()), ["R12", "ISW"]);
    explained_after(&mut d, 3);
    let m = d.machine();
    assert_eq!(names(m, &m.instruction_written()), ["PSW"]);
    assert_eq!(m.read(m.find("PSW").unwrap()) >> 13 & 1, 1);
}
