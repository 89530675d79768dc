//! OpenNet against its spec (`opennet.md`) and the vendor text (`opennet-arithmetic.txt`): the
//! storage table, execution errors, every instruction and type against an integer reference,
//! REP, word order, M8003/M8004, edges, rungs, the assembler, the runner and the examples.

fn errors(src: &str) -> Vec<String> {
    crate::common::error_texts(machine(src))
}

use proptest::prelude::*;
use servoscope_core::machine::opennet::dialect::machine;
use servoscope_core::machine::opennet::{M8003, M8004, OpenNet};
use servoscope_core::machine::{Machine, MachineView};

fn scans(src: &str, n: u64) -> OpenNet {
    let mut m = machine(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    m.run_until(n, |_| false);
    m
}

fn once(src: &str) -> OpenNet {
    scans(&format!("LOD M8120\n{src}"), 1)
}

fn pair(m: &OpenNet, n: usize) -> u32 {
    (u32::from(m.d[n]) << 16) | u32::from(m.d[n + 1])
}

// ---- The vendor's examples and table ------------------------------------------------------

#[test]
fn the_vendors_totaliser_with_rep() {
    let m = once(
        "MOV(W) 10 D100\nMOV(W) 20 D101\nMOV(W) 30 D102\nMOV(W) 40 D103\nADD(W) D100(R) D0 D0 REP 4",
    );
    assert_eq!(m.d[0], 100);
}

#[test]
fn the_storage_table_through_programs() {
    // I: 30000 + 5000 = 35000 → 0x08B8 with carry; −32768 − 1 = −32769 → 0xFFFF with borrow.
    let m = once(
        "ADD(I) 30000 5000 D0\nSUB(I) -32768 1 D1\nADD(I) 32767 0 D2\nSUB(W) 0 1 D3\nADD(L) 2147483647 1 D4\nSUB(D) 0 1 D6",
    );
    assert_eq!(m.d[0], 0x08B8);
    assert_eq!(m.d[1], 0xFFFF);
    assert_eq!(m.d[2], 0x7FFF);
    assert_eq!(m.d[3], 0xFFFF, "W −1 → FFFF (BW)");
    assert_eq!(pair(&m, 4), 0x0000_0000, "L 2147483648 → 00000000 (CY)");
    assert_eq!(pair(&m, 6), 0xFFFF_FFFF, "D −1 → FFFFFFFF (BW)");
    assert!(m.special[M8003], "the last SUB borrowed");
    let m = once("ADD(I) 16383 16384 D0");
    assert_eq!(m.d[0], 0x7FFF);
    assert!(!m.special[M8003]);
}

#[test]
fn the_vendors_execution_errors() {
    for (src, kind) in [
        ("DIV(W) 5 0 D0", "divide_by_zero"),
        ("DIV(I) -32768 -1 D0", "divide_overflow"),
        ("DIV(L) -2147483648 -1 D0", "divide_overflow"),
        ("MUL(D) 65536 65536 D0", "mul_range"),
        ("MUL(L) 65536 32768 D0", "mul_range"),
    ] {
        let m = once(&format!("MOV(W) 7 D0\n{src}"));
        assert_eq!(m.d[0], 7, "{src}: nothing written");
        assert!(m.special[M8004], "{src}");
        assert_eq!(m.error_count, 1);
        let e = m.last_error.unwrap();
        assert_eq!((e.kind, e.line, e.tick), (kind, 3, 0), "{src}");
    }
    // MUL in range for D and L, and the widest I product.
    let m = once("MUL(D) 65535 65537 D0\nMUL(L) -46340 46340 D2\nMUL(I) -32768 -32768 D4");
    assert_eq!(pair(&m, 0), 0xFFFF_FFFF);
    assert_eq!(pair(&m, 2) as i32, -46340 * 46340);
    assert_eq!(pair(&m, 4), 1_073_741_824);
    assert!(!m.special[M8004]);
}

#[test]
fn signed_division_truncates_and_the_remainder_takes_the_dividends_sign() {
    let m = once("DIV(I) 7 -2 D0\nDIV(I) -7 2 D2\nDIV(L) -7 2 D4\nDIV(D) 100000 7 D10");
    assert_eq!((m.d[0] as i16, m.d[1] as i16), (-3, 1));
    assert_eq!((m.d[2] as i16, m.d[3] as i16), (-3, -1));
    assert_eq!((pair(&m, 4) as i32, pair(&m, 6) as i32), (-3, -1));
    assert_eq!((pair(&m, 10), pair(&m, 12)), (14285, 5));
}

#[test]
fn pairs_keep_the_upper_word_first_and_bit_operands_start_at_bit_0() {
    let m = once("MOV(D) 12345678h D0\nMOV(W) 0A5h M10\nMOV(D) 80000001h Q0");
    assert_eq!((m.d[0], m.d[1]), (0x1234, 0x5678));
    // 0xA5 = 1010_0101: M10, M12, M15, M17 on (bits 0, 2, 5, 7), M20.. off.
    let on = |name: &str| m.read(m.find(name).unwrap()) == 1;
    assert!(on("M10") && !on("M11") && on("M12") && on("M15") && on("M17") && !on("M20"));
    // Q0 as D: the lower 16 bits first: bit 0 = Q0, bit 31 = Q37.
    assert!(on("Q0") && on("Q37") && !on("Q1"));
}

#[test]
fn inc_and_dec_wrap_without_m8003() {
    let m = once(
        "MOV(W) 65535 D0\nINC(W) D0\nMOV(W) 0 D1\nDEC(W) D1\nMOV(D) 4294967295 D2\nINC(D) D2\nADD(W) 65535 1 D9\nINC(W) D10",
    );
    assert_eq!(m.d[0], 0);
    assert_eq!(m.d[1], 65535);
    assert_eq!(pair(&m, 2), 0);
    assert!(
        m.special[M8003],
        "INC after the carrying ADD leaves M8003 alone"
    );
}

// ---- M8003, M8004, REP ----------------------------------------------------------------------

#[test]
fn m8003_is_the_or_over_rep_cycles_and_rewritten_by_each_add() {
    let m = once("MOV(W) 65535 D100\nMOV(W) 1 D101\nADD(W) D100(R) 1 D0(R) REP 2");
    assert_eq!((m.d[0], m.d[1]), (0, 2));
    assert!(m.special[M8003], "cycle 0 carried");
    let m = once("ADD(W) 65535 1 D0\nADD(W) 1 1 D1");
    assert!(!m.special[M8003], "the second ADD rewrote it");
    let m = once("ADD(W) 65535 1 D0\nMUL(W) 2 2 D2\nDIV(W) 4 2 D4\nMOV(W) 1 D6");
    assert!(m.special[M8003], "MUL, DIV, MOV leave it");
}

#[test]
fn m8004_latches_until_cleared() {
    let src = "LOD I0\nDIV(W) 1 0 D0\nLOD I1\nRST M8004";
    let mut m = machine(src).unwrap();
    let i0 = m.find("I0").unwrap();
    m.write(i0, 1).unwrap();
    m.step_tick();
    m.write(i0, 0).unwrap();
    m.run_until(5, |_| false);
    assert!(m.special[M8004], "still on four scans later");
    assert_eq!(m.error_count, 1);
    let i1 = m.find("I1").unwrap();
    m.write(i1, 1).unwrap();
    m.step_tick();
    assert!(!m.special[M8004], "RST M8004 cleared it");
    assert_eq!(m.error_count, 1, "the record stays");
    // The debugger's Clear errors writes M8004 = 0.
    let mut m = once("DIV(W) 1 0 D0");
    let lamp = m.find("M8004").unwrap();
    m.write(lamp, 0).unwrap();
    assert!(!m.error_lamp());
}

#[test]
fn rep_errors_count_per_cycle_and_the_others_run() {
    let m = once("MOV(W) 10 D0\nMOV(W) 0 D1\nMOV(W) 5 D2\nDIV(W) 100 D0(R) D10(R) REP 3");
    assert_eq!(m.error_count, 1);
    assert_eq!((m.d[10], m.d[11]), (10, 0), "cycle 0: 100 ÷ 10");
    assert_eq!((m.d[12], m.d[13]), (0, 0), "cycle 1: ÷0 wrote nothing");
    assert_eq!((m.d[14], m.d[15]), (20, 0), "cycle 2: 100 ÷ 5");
}

// ---- Edges, rungs, scans ------------------------------------------------------------------------

#[test]
fn sotu_and_sotd_pulse_for_one_scan() {
    let src = "LOD I0\nSOTU\nINC(W) D0\nLOD I0\nSOTD\nINC(W) D1";
    let mut m = machine(src).unwrap();
    let i0 = m.find("I0").unwrap();
    m.step_tick();
    m.write(i0, 1).unwrap();
    m.run_until(4, |_| false);
    assert_eq!(
        (m.d[0], m.d[1]),
        (1, 0),
        "one rising edge over three scans on"
    );
    m.write(i0, 0).unwrap();
    m.run_until(7, |_| false);
    assert_eq!((m.d[0], m.d[1]), (1, 1), "one falling edge");
    // An input already on in scan 0 pulses in scan 0 (the memory starts at 0).
    let mut m = machine(src).unwrap();
    m.write(i0, 1).unwrap();
    m.step_tick();
    assert_eq!(m.d[0], 1);
}

#[test]
fn advanced_instructions_act_every_scan_their_input_is_on() {
    let m = scans("LOD M8121\nINC(W) D0", 120);
    assert_eq!(m.d[0], 70, "1-s clock on for scans 0–49 and 100–119");
    let m = scans("LOD M8122\nINC(W) D0", 20);
    assert_eq!(m.d[0], 10);
    let m = scans("LOD M8120\nINC(W) D0\nEND", 5);
    assert_eq!(m.d[0], 1);
    assert_eq!(m.steps(), 15, "three instructions a scan, END included");
}

#[test]
fn block_and_branch_stacks() {
    // (I0 AND I1) OR (I2 AND I3) → Q0; BPS/BRD/BPP drive Q1 and Q2 from one condition.
    let src = "LOD I0\nAND I1\nLOD I2\nAND I3\nORLOD\nOUT Q0\nLOD I4\nBPS\nAND I5\nOUT Q1\nBPP\nANDN I5\nOUT Q2";
    let mut m = machine(src).unwrap();
    for name in ["I2", "I3", "I4"] {
        let l = m.find(name).unwrap();
        m.write(l, 1).unwrap();
    }
    m.step_tick();
    let on = |m: &OpenNet, n: &str| m.read(m.find(n).unwrap()) == 1;
    assert!(on(&m, "Q0"));
    assert!(!on(&m, "Q1") && on(&m, "Q2"));
}

#[test]
fn inputs_are_read_at_scan_start() {
    let mut m = machine("LOD I0\nOUT Q0\nLOD I0\nOUT Q1").unwrap();
    m.step_command(10);
    let i0 = m.find("I0").unwrap();
    m.write(i0, 1).unwrap();
    m.step_tick();
    let q = |m: &OpenNet, n: &str| m.read(m.find(n).unwrap());
    assert_eq!(
        q(&m, "Q1"),
        0,
        "the image was taken before the switch moved"
    );
    m.step_tick();
    assert_eq!((q(&m, "Q0"), q(&m, "Q1")), (1, 1));
}

// ---- Property tests against an integer reference ------------------------------------------

fn reference_add(ty: char, r: i64) -> (u32, bool) {
    let (min, max, bits) = match ty {
        'W' => (0, 65535, 16),
        'I' => (-32768, 32767, 16),
        'D' => (0, i64::from(u32::MAX), 32),
        _ => (i64::from(i32::MIN), i64::from(i32::MAX), 32),
    };
    let out = r < min || r > max;
    let pattern = if !out || ty == 'W' || ty == 'D' {
        (r as u64 & ((1u64 << bits) - 1)) as u32
    } else {
        let sign = u32::from(r < 0) << (bits - 1);
        let low = r.rem_euclid(1 << (bits - 1)) as u32;
        sign | low
    };
    (pattern, out)
}

fn read(m: &OpenNet, ty: char, at: usize) -> u32 {
    if ty == 'W' || ty == 'I' {
        u32::from(m.d[at])
    } else {
        pair(m, at)
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn add_and_sub_of_every_type(ty in prop::sample::select(vec!['W', 'I', 'D', 'L']), seed in any::<(u64, u64)>(), sub in any::<bool>()) {
        let (a, b) = {
            let span = |s: u64| -> i64 {
                match ty {
                    'W' => (s % 65536) as i64,
                    'I' => (s % 65536) as i64 - 32768,
                    'D' => (s % (1 << 32)) as i64,
                    _ => (s % (1 << 32)) as i64 - (1 << 31),
                }
            };
            (span(seed.0), span(seed.1))
        };
        let op = if sub { "SUB" } else { "ADD" };
        let m = once(&format!("MOV({ty}) {a} D0\nMOV({ty}) {b} D2\n{op}({ty}) D0 D2 D10"));
        let r = if sub { a - b } else { a + b };
        let (pattern, carry) = reference_add(ty, r);
        prop_assert_eq!(read(&m, ty, 10), pattern);
        prop_assert_eq!(m.special[M8003], carry);
    }

    #[test]
    fn mul_and_div_of_every_type(ty in prop::sample::select(vec!['W', 'I', 'D', 'L']), s in any::<(u64, u64)>()) {
        let words = if ty == 'W' || ty == 'I' { 1 } else { 2 };
        let pick = |v: u64| -> i64 {
            match ty {
                'W' => (v % 65536) as i64,
                'I' => (v % 65536) as i64 - 32768,
                'D' => (v % (1 << 32)) as i64,
                _ => (v % (1 << 32)) as i64 - (1 << 31),
            }
        };
        let (a, b) = (pick(s.0), pick(s.1));
        let m = once(&format!("MOV({ty}) {a} D0\nMOV({ty}) {b} D2\nMUL({ty}) D0 D2 D10\nDIV({ty}) D0 D2 D20"));
        let p = i128::from(a) * i128::from(b);
        let fits = match ty { 'D' => p <= i128::from(u32::MAX), 'L' => p >= i128::from(i32::MIN) && p <= i128::from(i32::MAX), _ => true };
        let mut errors = 0;
        if fits {
            prop_assert_eq!(pair(&m, 10), p as u32);
        } else {
            errors += 1;
            prop_assert_eq!(pair(&m, 10), 0);
        }
        let overflow = (ty == 'I' && a == -32768 && b == -1) || (ty == 'L' && a == i64::from(i32::MIN) && b == -1);
        if b == 0 || overflow {
            errors += 1;
        } else {
            let (q, r) = (a / b, a % b);
            prop_assert_eq!(read(&m, ty, 20), (q as u64 & if words == 1 { 0xFFFF } else { 0xFFFF_FFFF }) as u32);
            prop_assert_eq!(read(&m, ty, 20 + words), (r as u64 & if words == 1 { 0xFFFF } else { 0xFFFF_FFFF }) as u32);
        }
        prop_assert_eq!(m.error_count, errors);
        prop_assert_eq!(m.special[M8004], errors > 0);
    }

    #[test]
    fn rep_advances_only_marked_operands(values in prop::collection::vec(0u16..1000, 1..8), k in 0u16..100) {
        let n = values.len();
        let mut src = String::new();
        for (i, v) in values.iter().enumerate() {
            src.push_str(&format!("MOV(W) {v} D{}\n", 100 + i));
        }
        src.push_str(&format!("ADD(W) D100(R) {k} D200(R) REP {n}\nMOV(W) D100(R) D300 REP {n}"));
        let m = once(&src);
        for (i, v) in values.iter().enumerate() {
            prop_assert_eq!(m.d[200 + i], v + k);
        }
        prop_assert_eq!(m.d[300], values[n - 1], "an unmarked destination is written every cycle");
    }

    #[test]
    fn mutated_programs_never_panic(cut in 0usize..600, insert in "[ -~]{0,6}") {
        let base = include_str!("../../../../assets/examples/totaliser.opennet");
        let at = base.char_indices().map(|(i, _)| i).nth(cut % base.chars().count()).unwrap_or(0);
        let text = format!("{}{insert}{}", &base[..at], &base[at..]);
        if let Ok(mut m) = machine(&text) {
            m.run_until(3, |_| false);
        }
    }

    #[test]
    fn random_text_never_panics(text in "[ -~\\n]{0,200}") {
        if let Ok(mut m) = machine(&text) {
            m.run_until(3, |_| false);
        }
    }
}

// ---- The assembler -----------------------------------------------------------------------------

#[test]
fn every_error_class_with_line_and_column() {
    let src = "LD I0\nADDW D0 D1 D2\nINC(I) D0\nLOD I8\nOUT I0\nLOD D0\nMOV(W) 70000 D0\nADD(W) D0(R) D1 D2\nADD(W) D0 D1 D2 REP 100\nMOV(W) 5(R) D0 REP 2\nTIM 10\nLOD L0\nMOV(W) D7999(R) D0 REP 2\nAND(W) I0\nMOV(W) D0\nLOD M8000\n";
    let e = errors(src);
    let expect = [
        "1:1: error: unknown mnemonic 'LD' (did you mean LOD?)",
        "2:1: error: unknown mnemonic 'ADDW' (did you mean ADD(W)?)",
        "3:1: error: INC takes type W or D",
        "4:5: error: I8: the last digit",
        "5:5: error: I0 is an input",
        "6:5: error: D0 is a data register",
        "7:8: error: 70000 is out of range for type W",
        "8:8: error: (R) without REP",
        "9:21: error: REP count outside 1–99",
        "10:8: error: (R) cannot follow a constant",
        "11:1: error: TIM takes 2 operand(s), found 1",
        "12:5: error: L0 is a link register (L), not supported by servoscope yet",
        "13:8: error: D7999(R) with its 2 word(s) runs past D7999",
        "14:1: error: AND is a basic instruction",
        "15:1: error: MOV takes 2 operand(s), found 1",
        "16:5: error: M8000 is a special relay not supported",
    ];
    assert_eq!(e.len(), expect.len(), "{e:#?}");
    for (got, want) in e.iter().zip(expect) {
        assert!(got.starts_with(want), "{got}\n  should start with {want}");
    }
}

#[test]
fn a_line_that_does_not_assemble_adds_no_rung_errors_after_it() {
    for (src, line) in [
        ("LOD I0\nADDW D0 D1 D2\nLOD I1\nOUT Q0\nEND", 2),
        ("LOD I0\nTIM 10\nLOD I1\nOUT Q0\nEND", 2),
        ("LOD I0\nWSFT D0 D1 3\nLOD I1\nOUT Q0\nEND", 2),
        ("LOD I0\nOUT Q9\nLOD I1\nOUT Q0\nEND", 2),
    ] {
        let e = errors(src);
        assert_eq!(e.len(), 1, "{src}: {e:#?}");
        assert!(e[0].starts_with(&format!("{line}:")), "{e:?}");
    }
    let call = errors("LOD I0\nCALL 1\nEND");
    assert!(
        call[0].starts_with("2:1: error: CALL is an OpenNet instruction not supported"),
        "{call:?}"
    );
}

#[test]
fn rung_structure_errors() {
    let first = errors("OUT Q0");
    assert!(
        first[0].starts_with("1:1: error: a program starts with LOD"),
        "{first:?}"
    );
    let e = errors("LOD I0\nLOD I1\nOUT Q0");
    assert!(
        e[0].starts_with("3:1: error: an output while LOD blocks are not combined"),
        "{e:?}"
    );
    let e = errors("LOD I0\nANDLOD\nOUT Q0");
    assert!(
        e[0].starts_with("2:1: error: ANDLOD with no LOD block"),
        "{e:?}"
    );
    let e = errors("LOD I0\nBPS\nOUT Q0\nLOD I1\nOUT Q1");
    assert!(
        e[0].starts_with("4:1: error: a new rung starts while BPS is not closed"),
        "{e:?}"
    );
    let e = errors("LOD I0\nOUT Q0\nLOD I1\nAND I2");
    assert!(
        e[0].starts_with("3:1: error: logic that drives nothing"),
        "{e:?}"
    );
    let e = errors("LOD I0\nBPS\nOUT Q0\nEND");
    assert!(
        e[0].starts_with("4:1: error: the program ends with BPS not closed"),
        "{e:?}"
    );
    let e = errors("LOD I0\nOUT Q0\nEND\nLOD I1");
    assert!(
        e[0].starts_with("4:1: error: an instruction after END"),
        "{e:?}"
    );
    assert!(errors("").is_empty() && errors("END").is_empty());
    assert!(
        errors("; only a comment\n\nlod i0 ; case\nANDN I1\nAND LOD\n").len() == 2,
        "AND LOD needs a block; logic drives nothing"
    );
    assert!(
        errors("LOD I0\nLOD I1\nAND LOD\nOUT Q0").is_empty(),
        "AND LOD is ANDLOD"
    );
}

#[test]
fn the_examples_end_as_their_comments_say() {
    let m = scans(
        include_str!("../../../../assets/examples/signed_overflow.opennet"),
        1,
    );
    assert_eq!(m.d[2], 0x08B8);
    assert_eq!(m.d[3], 35000);
    assert_eq!(pair(&m, 12), 0x6E6B_2800);
    assert_eq!(pair(&m, 14), 4_000_000_000);
    let on = |m: &OpenNet, n: &str| m.read(m.find(n).unwrap()) == 1;
    assert!(on(&m, "M0") && !on(&m, "M1"));
    let m = scans(
        include_str!("../../../../assets/examples/mul_div.opennet"),
        1,
    );
    assert_eq!((m.d[10], m.d[11]), (1, 54464));
    assert_eq!((m.d[20], m.d[21]), (65533, 65535));
    assert_eq!((pair(&m, 40), pair(&m, 42)), (14285, 5));
    let mut m = machine(include_str!(
        "../../../../assets/examples/totaliser.opennet"
    ))
    .unwrap();
    let i0 = m.find("I0").unwrap();
    m.step_tick();
    m.write(i0, 1).unwrap();
    m.run_until(5, |_| false);
    assert_eq!(m.d[0], 100, "once per press");
    let m = scans(
        include_str!("../../../../assets/examples/exec_error.opennet"),
        3,
    );
    assert!(m.error_lamp() && on(&m, "Q0"));
    assert_eq!(m.error_count, 1);
    let m = scans(
        include_str!("../../../../assets/examples/batch_sotu.opennet"),
        3,
    );
    assert_eq!(m.d[0], 0, "no press, no batch");
}

#[test]
fn the_issues_explanation() {
    let mut m = machine("LOD M8120\nMOV(W) 30000 D0\nMOV(W) 5000 D1\nADD(I) D0 D1 D2").unwrap();
    m.step_tick();
    let text = m.explain_last().unwrap();
    assert!(
        text.contains("ADD(I) D0 D1 D2: 30000 + 5000 = 35000 > 32767 → stored 0x08B8 (sign 0, low 15 bits 2232), M8003 = 1"),
        "{text}"
    );
    let mut m =
        machine("LOD M8120\nMOV(W) 10 D100\nMOV(W) 20 D101\nADD(W) D100(R) D0 D0 REP 2").unwrap();
    m.step_tick();
    let text = m.explain_last().unwrap();
    assert!(text.contains("cycle 0: D100 10 + D0 0 = 10 (0x000A) → D0; cycle 1: D101 20 + D0 10 = 30 (0x001E) → D0"), "{text}");
}
