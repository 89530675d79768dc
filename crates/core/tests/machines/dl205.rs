//! DL205 against its spec (`dl205.md`) and the vendor text (`dl205-subs.txt`): the SUBS example
//! first, the push rule and the stack's edges, every BCD and binary instruction against an
//! integer reference, rungs, comparisons, the assembler, the runner and the examples.

use crate::common::{get, set};

fn errors(src: &str) -> Vec<String> {
    crate::common::error_texts(machine(src))
}

use proptest::prelude::*;
use servoscope_core::machine::PlcView;
use servoscope_core::machine::dl205::dialect::machine;
use servoscope_core::machine::dl205::program::sp;
use servoscope_core::machine::dl205::{Dl205, bcd_value, to_bcd};
use servoscope_core::machine::{Machine, MachineView};

fn scans(src: &str, n: u64) -> Dl205 {
    let mut m = machine(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    m.run_until(n, |_| false);
    m
}

/// One scan of `body` on an always-on rung.
fn once(body: &str) -> Dl205 {
    scans(&format!("STR SP1\n{body}\nEND"), 1)
}

// ---- The seed's SUBS example (spec §6.7) ------------------------------------------------------

#[test]
fn the_manuals_subs_example() {
    let mut m = machine("STR X1\nLDD V1400\nLDD V1420\nSUBS\nOUTD V1500\nEND").unwrap();
    set(&mut m, "V1401", 0x0017);
    set(&mut m, "V1400", 0x2056);
    set(&mut m, "V1421", 0x0039);
    set(&mut m, "V1420", 0x5026);
    set(&mut m, "X1", 1);
    // Step the scan instruction by instruction and watch the stack.
    m.step_command(1); // STR X1
    m.step_command(1); // LDD V1400
    assert_eq!((m.acc, m.depth), (0x0017_2056, 0));
    m.step_command(1); // LDD V1420: pushes
    assert_eq!((m.acc, m.stack[0], m.depth), (0x0039_5026, 0x0017_2056, 1));
    m.step_command(1); // SUBS
    assert_eq!((m.acc, m.depth), (0x0022_2970, 0));
    m.step_command(1); // OUTD
    m.step_command(1); // END
    assert_eq!((get(&m, "V1501"), get(&m, "V1500")), (0x0022, 0x2970));
    for f in [sp::SP63, sp::SP64, sp::SP65, sp::SP70, sp::SP75] {
        assert!(!m.sp[f], "flag {f} off");
    }
    let text = {
        let mut m2 = machine("STR X1\nLDD V1400\nLDD V1420\nSUBS\nOUTD V1500\nEND").unwrap();
        set(&mut m2, "V1401", 0x0017);
        set(&mut m2, "V1400", 0x2056);
        set(&mut m2, "V1421", 0x0039);
        set(&mut m2, "V1420", 0x5026);
        set(&mut m2, "X1", 1);
        m2.step_command(1);
        m2.step_command(1);
        m2.step_command(1);
        let load = m2.explain_last().unwrap();
        m2.step_command(1);
        (load, m2.explain_last().unwrap())
    };
    assert!(
        text.0
            .contains("LDD V1420: load pending → push ACC 00172056 to L1; ACC = 00395026"),
        "{}",
        text.0
    );
    assert!(
        text.1
            .contains("SUBS: ACC 00395026 − L1 00172056 = 00222970 (BCD); pop: L1 ← L2 … L8 ← 0"),
        "{}",
        text.1
    );
}

// ---- The push rule and the stack's edges ------------------------------------------------------

#[test]
fn a_value_falls_off_l8_only_when_all_eight_levels_were_in_use() {
    use servoscope_core::machine::dl205::StackMove;
    // Each LD after the first pushes ACC: after n loads the depth is n - 1.
    for loads in 2..=11u32 {
        let body: String = (1..=loads).map(|k| format!("LD K{k:X}\n")).collect();
        let mut m = machine(&format!("STR SP1\n{body}END")).expect("assembles");
        // Stopped before END, right after the last load.
        let end = loads as usize + 2;
        m.run_until(1, |m| m.pc_line() == Some(end));
        let depth_before = (loads - 2).min(8);
        match m.moved {
            StackMove::Push { entered, lost } => {
                assert_eq!(entered, loads - 1, "ACC of the load before");
                let expect = (depth_before == 8).then(|| loads - 9);
                assert_eq!(
                    lost, expect,
                    "{loads} loads: depth {depth_before} before the push"
                );
            }
            other => panic!("{other:?}"),
        }
    }
}

#[test]
fn nine_loads_push_eight_and_one_falls_off() {
    let loads: String = (1..=10).map(|k| format!("LD K{k:X}\n")).collect();
    let m = once(&loads);
    assert_eq!(m.acc, 10);
    assert_eq!(m.depth, 8);
    assert_eq!(m.stack, [9, 8, 7, 6, 5, 4, 3, 2], "1 fell off L8");
    // Outs cancel the pending load: the next load replaces ACC.
    let m = once("LD K5\nOUT V0\nLD K6");
    assert_eq!((m.acc, m.depth), (6, 0));
    // Coils and math do not.
    let m = once("LD K5\nOUT C0\nLD K6");
    assert_eq!((m.acc, m.stack[0]), (6, 5));
    // Pops on an empty stack read 0.
    let m = once("LD K5\nPOP\nPOP");
    assert_eq!((m.acc, m.depth), (0, 0));
}

#[test]
fn the_stack_is_cleared_at_each_scan_start() {
    let m = scans("STR SP1\nLD K1\nLD K2\nEND", 3);
    assert_eq!(
        (m.acc, m.stack[0], m.depth),
        (2, 1, 1),
        "not 3 levels after 3 scans"
    );
}

// ---- BCD math ----------------------------------------------------------------------------------

#[test]
fn bcd_worked_examples() {
    // Analog scaling: 2048 × 1000 ÷ 4095 = 500 r 500, remainder pushed.
    let m = once("LD K2048\nMUL K1000\nDIV K4095");
    assert_eq!((m.acc, m.stack[0]), (0x0500, 0x0500));
    // A borrow leaves the ten's complement and reads negative.
    let m = once("LDD K0\nSUBD K1");
    assert_eq!(m.acc, 0x9999_9999);
    assert!(m.sp[sp::SP65] && m.sp[sp::SP64] && m.sp[sp::SP70]);
    // ADD keeps 4 digits and carries into SP66.
    let m = scans("STR SP1\nLD K9999\nOUT V0\nLD K2\nADD V0\nEND", 1);
    assert_eq!(m.acc, 0x0001);
    assert!(m.sp[sp::SP66] && !m.sp[sp::SP67]);
    // MULD pushes the upper 8 digits.
    let m = scans("STR SP1\nLDD K99999999\nOUTD V0\nLDD K12\nMULD V0\nEND", 1);
    assert_eq!((m.acc, m.stack[0]), (to_bcd(99_999_988), 0x11));
    // DIVS replaces L1 with the remainder.
    let m = once("LD K7\nLDD K100\nDIVS");
    assert_eq!((m.acc, m.stack[0], m.depth), (0x14, 0x2, 1));
}

#[test]
fn non_bcd_and_divide_by_zero_change_nothing_else() {
    let m = once("LDD K1234\nOUT V0\nLDD K0000001A\nBIN");
    assert!(m.sp[sp::SP75]);
    assert_eq!(m.acc, 0x1A, "ACC unchanged");
    let m = once("LD K0\nOUT V0\nLDD K1234\nADDD K1\nDIV V0");
    assert!(m.sp[sp::SP53]);
    assert_eq!((m.acc, m.depth), (0x1235, 0), "nothing pushed, ACC kept");
    assert!(!m.sp[sp::SP75]);
    // SP flags persist across scans until an instruction writes them.
    let m = scans("STR SP0\nLDD K1A\nBIN\nEND", 3);
    assert!(m.sp[sp::SP75]);
}

fn bcd8(v: u64) -> u32 {
    to_bcd(v)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn bcd_add_and_sub_against_decimal(a in 0u64..100_000_000, b in 0u64..100_000_000, a4 in 0u64..10_000, b4 in 0u64..10_000) {
        let m = scans(&format!("STR SP1\nLDD K{:X}\nOUTD V0\nLDD K{:X}\nADDD V0\nOUTD V10\nLDD K{:X}\nSUBD V0\nEND", bcd8(b), bcd8(a), bcd8(a)), 1);
        let sum = a + b;
        prop_assert_eq!(m.pair(0o10), bcd8(sum % 100_000_000));
        let diff = (a as i64 - b as i64).rem_euclid(100_000_000) as u64;
        prop_assert_eq!(m.acc, bcd8(diff));
        prop_assert_eq!(m.sp[sp::SP65], a < b);
        prop_assert_eq!(m.sp[sp::SP64], a % 10_000 < b % 10_000);
        prop_assert_eq!(m.sp[sp::SP63], diff == 0);
        // 4-digit ADD/SUB.
        let m = scans(&format!("STR SP1\nLD K{:X}\nOUT V0\nLD K{:X}\nADD V0\nOUT V1\nLD K{:X}\nSUB V0\nEND", bcd8(b4), bcd8(a4), bcd8(a4)), 1);
        prop_assert_eq!(u32::from(m.v[1]), bcd8((a4 + b4) % 10_000));
        prop_assert_eq!(m.acc, bcd8((a4 as i64 - b4 as i64).rem_euclid(10_000) as u64));
        prop_assert_eq!(m.sp[sp::SP64], a4 < b4);
    }

    #[test]
    fn bcd_mul_and_div_against_decimal(a in 0u64..100_000_000, w in 0u64..10_000, a4 in 0u64..10_000) {
        let m = scans(&format!("STR SP1\nLD K{:X}\nOUT V0\nLD K{:X}\nMUL V0\nOUTD V10\nLDD K{:X}\nDIV V0\nEND", bcd8(w), bcd8(a4), bcd8(a)), 1);
        prop_assert_eq!(m.pair(0o10), bcd8(a4 * w));
        match (a.checked_div(w), a.checked_rem(w)) {
            (Some(q), Some(r)) => {
                prop_assert_eq!(m.acc, bcd8(q));
                prop_assert_eq!(m.stack[0], bcd8(r));
                prop_assert!(!m.sp[sp::SP53]);
            }
            _ => {
                prop_assert!(m.sp[sp::SP53], "÷0");
                prop_assert_eq!(m.acc, bcd8(a));
            }
        }
    }

    #[test]
    fn a_non_bcd_digit_is_caught(digit in 0xAu32..=0xF, at in 0u32..4) {
        let bad = digit << (4 * at);
        let m = scans(&format!("STR SP1\nLD K{bad:X}\nOUT V0\nLD K1\nOUT V1\nLD V0\nADD V1\nEND"), 1);
        prop_assert!(m.sp[sp::SP75]);
        prop_assert_eq!(m.acc, bad, "ACC unchanged");
    }

    #[test]
    fn binary_math_against_u64(a in any::<u32>(), y in any::<u32>(), w in 1u16..) {
        let m = once(&format!("LDD K{a:X}\nADDBD K{y:X}"));
        prop_assert_eq!(m.acc, a.wrapping_add(y));
        prop_assert_eq!(m.sp[sp::SP67], u64::from(a) + u64::from(y) > u64::from(u32::MAX));
        prop_assert_eq!(m.sp[sp::SP66], (a & 0xFFFF) + (y & 0xFFFF) > 0xFFFF);
        let r = a.wrapping_add(y);
        prop_assert_eq!(m.sp[sp::SP73], (a >> 31 == y >> 31) && (r >> 31 != a >> 31));
        let m = once(&format!("LDD K{a:X}\nSUBBD K{y:X}"));
        prop_assert_eq!(m.acc, a.wrapping_sub(y));
        prop_assert_eq!(m.sp[sp::SP65], a < y);
        prop_assert_eq!(m.sp[sp::SP64], (a & 0xFFFF) < (y & 0xFFFF));
        let m = once(&format!("LDD K{a:X}\nMULB K{w:X}"));
        prop_assert_eq!(m.acc, a.wrapping_mul(u32::from(w)));
        let m = once(&format!("LDD K{a:X}\nDIVB K{w:X}"));
        prop_assert_eq!((m.acc, m.stack[0]), (a / u32::from(w), a % u32::from(w)));
        prop_assert_eq!(m.sp[sp::SP70], m.acc >> 31 == 1);
    }

    #[test]
    fn bcd_conversion_round_trips(v in 0u64..100_000_000) {
        let m = once(&format!("LDD K{:X}\nBIN", bcd8(v)));
        prop_assert_eq!(u64::from(m.acc), v);
        let m = once(&format!("LDD K{v:X}\nBCD"));
        prop_assert_eq!(m.acc, bcd8(v));
        prop_assert_eq!(bcd_value(bcd8(v), 8), Some(v));
    }

    #[test]
    fn mutated_programs_never_panic(cut in 0usize..600, insert in "[ -~]{0,6}") {
        let base = include_str!("../../../../assets/examples/subs.dl205");
        let at = base.char_indices().map(|(i, _)| i).nth(cut % base.chars().count()).unwrap_or(0);
        let text = format!("{}{insert}{}", &base[..at], &base[at..]);
        if let Ok(mut m) = machine(&text) {
            m.run_until(2, |_| false);
        }
    }

    #[test]
    fn random_text_never_panics(text in "[ -~\\n]{0,200}") {
        if let Ok(mut m) = machine(&text) {
            m.run_until(2, |_| false);
        }
    }
}

#[test]
fn logic_shifts_and_increments() {
    let m = scans("STR SP1\nLD KF0F0\nOUT V0\nLDD K12345678\nAND V0\nEND", 1);
    assert_eq!(m.acc, 0x5070, "16-bit AND clears the upper word");
    let m = once("LDD KFFFF0000\nORD K0000FFFF");
    assert_eq!(m.acc, 0xFFFF_FFFF);
    assert!(m.sp[sp::SP70]);
    let m = once("LD K1\nLD K3\nXORS");
    assert_eq!((m.acc, m.depth), (2, 0));
    let m = once("LDD K80000001\nSHFL K1");
    assert_eq!(m.acc, 2);
    let m = once("LDD K80000001\nROTL K1");
    assert_eq!(m.acc, 3);
    let m = once("LDD K1\nSHFR K32");
    assert_eq!(m.acc, 0);
    let m = once("INCB V0\nDECB V1");
    assert_eq!((m.v[0], m.v[1]), (1, 0xFFFF));
    assert!(!m.sp[sp::SP63]);
}

// ---- Rungs, coils, comparisons ----------------------------------------------------------------

#[test]
fn rung_power_gates_outputs_and_coils_follow_every_scan() {
    let src = "STR X0\nOUT Y0\nLD K5\nOUT V0\nSET C0 C3\nSTRN X0\nRST C1\nEND";
    let mut m = machine(src).unwrap();
    m.step_tick();
    assert_eq!(
        (get(&m, "Y0"), m.v[0]),
        (0, 0),
        "unpowered: no load, no out"
    );
    set(&mut m, "X0", 1);
    m.step_tick();
    assert_eq!((get(&m, "Y0"), m.v[0]), (1, 5));
    assert_eq!(
        (0..4)
            .map(|i| get(&m, &format!("C{i}")))
            .collect::<Vec<_>>(),
        [1, 1, 1, 1]
    );
    set(&mut m, "X0", 0);
    m.step_tick();
    assert_eq!(get(&m, "Y0"), 0, "OUT writes the power every scan");
    assert_eq!(get(&m, "C0"), 1, "SET holds");
    assert_eq!(get(&m, "C1"), 0, "RST on the powered second rung");
    // Branches: (X0 AND X1) OR X2 → Y1.
    let mut m = machine("STR X0\nAND X1\nSTR X2\nORSTR\nOUT Y1\nEND").unwrap();
    set(&mut m, "X2", 1);
    m.step_tick();
    assert_eq!(get(&m, "Y1"), 1);
}

#[test]
fn comparisons_are_unsigned_16_bit() {
    let src = "STR SP1\nLD K8000\nOUT V0\nSTRE V0 K8000\nOUT Y0\nSTRNE V0 K8000\nOUT Y1\nSTR V0 K7FFF\nOUT Y2\nSTRN V0 K7FFF\nOUT Y3\nEND";
    let m = scans(src, 1);
    assert_eq!(
        [get(&m, "Y0"), get(&m, "Y1"), get(&m, "Y2"), get(&m, "Y3")],
        [1, 0, 1, 0]
    );
}

// ---- The assembler -----------------------------------------------------------------------------

#[test]
fn every_recognised_instruction_of_spec_6_12_is_named_not_unknown() {
    for m in [
        "SR", "MOVW", "FILL", "FIND", "FDGT", "FDGTHS", "TSHFL", "TSHFR", "DRUM", "BCALL",
    ] {
        let e = errors(&format!("STR X1\n{m} V2000\nEND\n"));
        assert_eq!(
            e.first().map(String::as_str),
            Some(
                format!("2:1: error: {m} is a DL205 instruction not supported by servoscope yet")
                    .as_str()
            ),
            "{m}"
        );
    }
}

#[test]
fn outf_writes_only_y_c_and_s_bits() {
    // Spec §1: writing X, SP, T or CT bits is an error; §6.2: OUTF's start is Y, C or S.
    for start in ["T0", "CT0", "X0"] {
        let e = errors(&format!("STR X1\nLD K5\nOUTF {start} K4\nEND\n"));
        assert_eq!(
            e.first().map(String::as_str),
            Some(format!("3:6: error: {start} cannot be written: OUTF needs Y, C or S").as_str())
        );
    }
    assert!(errors("STR X1\nLD K5\nOUTF S0 K4\nEND\n").is_empty());
}

#[test]
fn every_error_class_with_line_and_column() {
    let src = "STR X1\nLDD V1983\nDRUM T0 K10\nOUT X1\nINC V0\nLD K12345\nADDD KA\nSET C5 C2\nLDF X1776 K5\nSTR SP77\nLDD V37777\nDIV K0\nSTR GX0\nSTRR X1\nLD\n";
    let e = errors(src);
    let expect = [
        "2:5: error: V1983: element numbers are octal",
        "3:1: error: DRUM is a DL205 instruction not supported by servoscope yet",
        "4:5: error: X1 cannot be written",
        "5:1: error: unknown mnemonic 'INC' (did you mean INCB?)",
        "6:4: error: K12345 is out of range",
        "7:6: error: KA is not BCD",
        "8:8: error: SET range C5–C2 must stay in one kind and run upwards",
        "9:11: error: X1776 with K5 runs past the last X element",
        "10:5: error: SP77 is a special relay not supported by servoscope yet",
        "11:5: error: V37777 and the next word run past V37777",
        "12:5: error: K0 is out of range",
        "13:5: error: GX0 is one of the remote I/O bits",
        "14:1: error: unknown mnemonic 'STRR' (did you mean STR?)",
        "15:1: error: LD takes 1 operand(s), found 0",
    ];
    assert_eq!(e.len(), expect.len(), "{e:#?}");
    for (got, want) in e.iter().zip(expect) {
        assert!(got.starts_with(want), "{got}\n  should start with {want}");
    }
}

#[test]
fn rung_structure_errors_are_all_reported() {
    let e = errors("OUT Y0\nAND X1\nSTR X0\nSTR X1\nOUT Y1\nSTR X2\nANDSTR\nEND");
    let lines: Vec<&str> = e
        .iter()
        .map(|s| s.split(": ").nth(2).unwrap_or(""))
        .collect();
    assert!(
        e[0].starts_with("1:1: error: needs a rung condition"),
        "{e:?}"
    );
    assert!(e[1].starts_with("2:1: error: AND needs a rung"), "{e:?}");
    assert!(
        e[2].starts_with("5:1: error: branches are not merged"),
        "{e:?}"
    );
    assert!(
        e[3].starts_with("7:1: error: ANDSTR needs two levels"),
        "{e:?}"
    );
    assert!(
        e[4].starts_with("8:1: error: a rung with no output"),
        "{e:?}"
    );
    assert_eq!(e.len(), 5, "{lines:?}");
    let e = errors("STR X0\nOUT Y0");
    assert!(e[0].starts_with("2:1: error: no END"), "{e:?}");
    let e = errors("STR X0\nOUT Y0\nEND\nNOP");
    assert!(e[0].starts_with("4:1: error: NOP after END"), "{e:?}");
    assert!(errors("")[0].starts_with("1:1: error: no END"));
    assert!(errors("END").is_empty());
    let e = errors(
        "#BEGIN COMMENTS\nanything at all\n#END\n// a comment\nstr x0 // lower case\nout y0\nend",
    );
    assert!(e.is_empty(), "{e:?}");
    assert!(errors("#BEGIN ELEMENT_DOC\nSTR X0")[0].starts_with("1:1: error: #BEGIN without #END"));
    let nine: String = (0..9).map(|i| format!("STR C{i:o}\n")).collect();
    let e = errors(&format!("{nine}OUT Y0\nEND"));
    assert!(
        e.iter()
            .any(|s| s.starts_with("9:1: error: more than 8 levels")),
        "{e:?}"
    );
}

#[test]
fn the_examples_end_as_their_comments_say() {
    let m = scans(include_str!("../../../../assets/examples/subs.dl205"), 1);
    assert_eq!(m.pair(0o1500), 0x0022_2970);
    assert_eq!(m.stack[..7], [7, 6, 5, 4, 3, 2, 1]);
    let mut m = machine(include_str!("../../../../assets/examples/totaliser.dl205")).unwrap();
    set(&mut m, "X0", 1);
    m.run_until(40, |_| false);
    assert_eq!((get(&m, "V2000"), get(&m, "V2001")), (0, 1));
    set(&mut m, "X0", 0);
    m.run_until(45, |_| false);
    assert_eq!(get(&m, "V2001"), 1, "no carry without X0");
    let m = scans(include_str!("../../../../assets/examples/scaling.dl205"), 1);
    assert_eq!((get(&m, "V2010"), get(&m, "V2011")), (0x0500, 0x0500));
    let mut m = machine(include_str!("../../../../assets/examples/latch.dl205")).unwrap();
    set(&mut m, "X0", 1);
    m.run_until(3, |_| false);
    set(&mut m, "X0", 0);
    m.run_until(6, |_| false);
    assert_eq!(
        (get(&m, "Y0"), get(&m, "V2000")),
        (1, 1),
        "latched; counted once"
    );
    set(&mut m, "X1", 1);
    m.run_until(8, |_| false);
    assert_eq!(get(&m, "Y0"), 0, "stopped");
    let m = scans(include_str!("../../../../assets/examples/nonbcd.dl205"), 1);
    assert!(m.sp[sp::SP75]);
    assert_eq!(get(&m, "Y1"), 1);
    assert_eq!(m.acc, 0x1A);
}

#[test]
fn the_code_view_gets_the_rung_power_of_each_line() {
    use servoscope_core::machine::LinePower::{Off, On, Skipped};
    let mut m = machine("STR X0\nOUT Y0\nLD K5\nOUT V0\nSTR SP1\nOUT Y1\nEND").unwrap();
    m.step_command(1);
    m.step_command(1);
    m.step_command(1);
    assert_eq!(
        m.line_power(),
        [(1, Off), (2, Off), (3, Skipped)],
        "only what ran so far"
    );
    m.run_until(1, |_| false);
    // After END the next scan has not started: the whole scan's power is still shown.
    let power = m.line_power();
    assert_eq!(
        &power[..6],
        [
            (1, Off),
            (2, Off),
            (3, Skipped),
            (4, Skipped),
            (5, On),
            (6, On)
        ]
    );
}

#[test]
fn rungs_start_where_the_spec_says() {
    use servoscope_core::machine::dl205::program::rung_starts;
    // A contact after an output stays in its rung; the next STR after that starts a new one.
    let m = machine("STR X0\nOUT Y0\nAND X1\nOUT Y1\nSTR X2\nSTR X3\nORSTR\nOUT Y2\nEND").unwrap();
    assert_eq!(rung_starts(&m.program.instrs), [0, 4]);
}

#[test]
fn incb_and_set_are_explained_by_what_they_wrote_not_by_acc() {
    let mut m = machine("STR SP1\nLD K7\nINCB V2000\nSET C3\nDECB V2000\nEND").expect("assembles");
    let explained_at = |m: &mut Dl205, line: usize| {
        m.run_until(1, |m| m.pc_line() == Some(line + 1));
        m.explain_last().unwrap_or_default()
    };
    let incb = explained_at(&mut m, 3);
    assert!(incb.contains("V2000 = 0000 + 1 = 0001"), "{incb}");
    assert!(!incb.contains("ACC ="), "INCB does not touch ACC: {incb}");
    let set = explained_at(&mut m, 4);
    assert!(set.ends_with("C3 = 1"), "{set}");
    let decb = explained_at(&mut m, 5);
    assert!(decb.contains("V2000 = 0001 − 1 = 0000"), "{decb}");
}
