//! The OpenNet assembler and its MICRO3 warnings (§1, §5.1).

use super::*;

// ---- §1, §5.1 The assembler ----------------------------------------------------------------

/// §1: operand kinds and ranges of the new forms, each on its line.
#[test]
fn operand_errors_of_the_new_forms() {
    for (src, line, words) in [
        ("LOD I0\nTIM D0 5", 2, "D0"),
        ("LOD I0\nTIM T0 M0", 2, "M0"),
        ("LOD I0\nTIM T256 5", 2, "T256"),
        ("LOD I0\nTMH T0 65536", 2, "65536"),
        ("LOD I0\nTIM T0 D8000", 2, "D8000"),
        ("LOD I0\nTIM T0", 2, "TIM"),
        ("LOD I0\nLOD I1\nCNT T0 5", 3, "T0"),
        ("LOD I0\nLOD I1\nCNT C256 5", 3, "C256"),
        ("CC= D0 5\nOUT Q0", 1, "D0"),
        ("DC= C0 5\nOUT Q0", 1, "C0"),
        ("CC>= C0 70000\nOUT Q0", 1, "70000"),
        ("LOD I0\nOUT T0", 2, "T0"),
        ("LOD I0\nSET C3", 2, "C3"),
        ("LOD I0\nOUT M8121", 2, "M8121"),
        ("LOD I0\nMOV(W) 1 M8121", 2, "M8121"),
        ("LOD I0\nCMP=(W) D0 D1 D2", 2, "D2"),
        ("LOD I0\nCMP=(W) D0 D1 T0", 2, "T0"),
        ("LOD I0\nANDW(I) D0 D1 D2", 2, "ANDW"),
        ("LOD I0\nHTOB(L) D0 D1", 2, "HTOB"),
        ("LOD I0\nSFTL(W) T0 1", 2, "T0"),
        ("LOD I0\nSFTL(W) D0 16", 2, "16"),
        ("LOD I0\nSFTR(D) D0 32", 2, "32"),
        ("LOD I0\nSFTL(W) D0 1 REP 2", 2, "REP"),
        ("LOD M8120\nMOV(W) 1 R241", 2, "R255"),
        ("LOD M8120\nMOV(W) 5 T255(R) REP 2", 2, "T255"),
    ] {
        assert_error(src, line, words);
    }
}

/// §1: SFR's k is a constant 1–256 within R255, its first operand an R bit.
#[test]
fn shift_register_operand_errors() {
    for (src, words) in [
        ("LOD I0\nLOD I1\nLOD I2\nSFR R0 257", "257"),
        ("LOD I0\nLOD I1\nLOD I2\nSFR R250 7", "R255"),
        ("LOD I0\nLOD I1\nLOD I2\nSFRN R0 0", ""),
        ("LOD I0\nLOD I1\nLOD I2\nSFR M0 4", "M0"),
        ("LOD I0\nLOD I1\nLOD I2\nSFR R0 D0", "D0"),
    ] {
        assert_error(src, 4, words);
    }
    assert_assembles("LOD I0\nLOD I1\nLOD I2\nSFR R250 6");
    assert_assembles("LOD I0\nLOD I1\nLOD I2\nSFRN R0 256");
}

/// §1: the same timer (counter) number in two timer (counter) instructions is an error; a
/// timer and a counter may share a number, and a T or C may also be a contact or word operand.
#[test]
fn a_timer_or_counter_number_has_one_instruction() {
    assert_error("LOD I0\nTIM T0 5\nLOD I1\nTMH T0 7", 4, "T0");
    assert_error(
        "LOD I0\nLOD I1\nCNT C1 5\nLOD I2\nLOD I3\nLOD I4\nCDP C1 5",
        7,
        "C1",
    );
    assert_assembles("LOD I0\nTIM T0 5\nLOD I0\nLOD I1\nCNT C0 5");
    assert_assembles("LOD T0\nOUT Q0\nLOD I0\nTIM T0 5\nLOD M8125\nMOV(W) T0 D0\nMOV(W) C9 D1");
}

/// §1, §4.3: T and C are 16-bit operands: an error in a D or L instruction.
#[test]
fn timers_and_counters_are_not_d_or_l_operands() {
    for (src, words) in [
        ("LOD I0\nMOV(D) T0 D0", "T0"),
        ("LOD I0\nADD(L) D0 C1 D2", "C1"),
        ("LOD I0\nMOV(D) 5 T0", "T0"),
        ("LOD I0\nCMP=(D) C0 D0 M0", "C0"),
    ] {
        assert_error(src, 2, words);
    }
    assert_assembles("LOD I0\nMOV(I) T0 D0\nADD(W) C0 1 T1");
}

/// §1: the off-delay timers belong to later CPUs; TMR and BCD get "did you mean".
#[test]
fn later_cpu_timers_and_suggestions() {
    for op in ["TIMO", "TMHO", "TMLO", "TMSO"] {
        assert_error(&format!("LOD I0\n{op} T0 5"), 2, "FC5A");
    }
    assert_error("LOD I0\nTMR T0 5", 2, "did you mean");
    assert_error("LOD I0\nTMR T0 5", 2, "TIM");
    assert_error("LOD I0\nBCD D0 D1", 2, "did you mean");
    assert_error("LOD I0\nBCD D0 D1", 2, "HTOB");
}

/// §1: an untyped ADD (MICRO3 style) says the MICRO3 instruction is the W type.
#[test]
fn an_untyped_add_mentions_micro3_and_w() {
    assert_error("LOD I0\nADD D0 D1 D2", 2, "MICRO3");
    let e = errors("LOD I0\nADD D0 D1 D2");
    assert!(
        e.iter().any(|(l, msg)| *l == 2 && msg.contains('W')),
        "{e:?}"
    );
}

/// §5.1: a counter takes 2 (CNT) or 3 (CDP, CUD) LOD blocks and a shift register 3; a counter,
/// shift register, MCS or JMP ends its rung.
#[test]
fn counter_and_shift_register_rung_rules() {
    for (src, line) in [
        ("LOD I0\nCNT C0 5", 2),
        ("LOD I0\nLOD I1\nLOD I2\nCNT C0 5", 4),
        ("LOD I0\nLOD I1\nCDP C0 5", 3),
        ("LOD I0\nLOD I1\nCUD C0 5", 3),
        ("LOD I0\nLOD I1\nSFR R0 4", 3),
    ] {
        assert_error(src, line, "CNT|CDP|CUD|SFR|block|input");
    }
    for (src, line) in [
        ("LOD I0\nLOD I1\nCNT C0 5\nOUT Q0", 4),
        ("LOD I0\nLOD I1\nCNT C0 5\nAND I2\nOUT Q0", 4),
        ("LOD I0\nLOD I1\nLOD I2\nSFR R0 4\nOUT Q0", 5),
        ("LOD I0\nMCS\nOUT Q0\nMCR", 3),
        ("LOD I0\nJMP\nAND I1\nOUT Q0\nJEND", 3),
    ] {
        assert_error(src, line, "rung|LOD");
    }
    assert_assembles("LOD I0\nLOD I1\nCNT C0 5\nLOD I2\nLOD I3\nLOD I4\nCUD C1 5\nNOP\nEND");
    assert_assembles(
        "LOD I0\nMCS\nLOD I0\nLOD I1\nCNT C0 5\nMCR\nLOD I1\nJMP\nLOD I0\nLOD I1\nLOD I2\nSFR R0 4\nJEND",
    );
    assert_assembles("CC>= C0 5\nOUT Q0\nDC= D0 D1\nAND I0\nOUT Q1");
}

/// §5.1: MCR/JEND need an opener since the previous closer, openers must be closed (reported on
/// the first one left open), and MCR/JEND may not stand inside a rung's open logic.
#[test]
fn mcs_and_jmp_structure_errors() {
    assert_error("LOD I0\nOUT Q0\nMCR", 3, "MCS|MCR");
    assert_error("LOD I0\nMCS\nLOD I1\nOUT Q0\nMCR\nMCR", 6, "MCS|MCR");
    assert_error("LOD I0\nOUT Q0\nJEND", 3, "JMP|JEND");
    assert_error("LOD I0\nJMP\nLOD I1\nOUT Q0", 2, "JMP|JEND");
    assert_error("LOD I0\nJMP\nLOD I1\nJMP\nLOD I2\nOUT Q0", 2, "JMP|JEND");
    assert_error("LOD I0\nMCS\nLOD I1\nOUT Q0", 2, "MCS|MCR");
    assert_error("LOD I0\nMCS\nLOD I1\nOUT Q0\nLOD I2\nMCR", 6, "MCR|rung");
    assert_error("LOD I0\nJMP\nLOD I1\nOUT Q0\nLOD I2\nJEND", 6, "JEND|rung");
    assert_assembles(
        "LOD I0\nMCS\nLOD I1\nMCS\nLOD I2\nOUT Q0\nMCR\nLOD I0\nJMP\nLOD I1\nJMP\nJEND",
    );
}

// ---- §1 MICRO3 warnings ---------------------------------------------------------------------

/// §1: reading a MICRO3 special relay never written gives one warning per number, at its first
/// read, naming MICRO3 and the OpenNet relay to use.
#[test]
fn micro3_relays_read_but_never_written_warn_once_at_their_first_read() {
    let w = warnings("LOD M303\nOUT Q0\nLOD I0\nAND M303\nOUT Q1");
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].0, 1);
    assert!(
        w[0].1.contains("MICRO3") && w[0].1.contains("M8003"),
        "{w:?}"
    );
    for (relay, opennet, read) in [
        ("M301", "M8120", "LODN"),
        ("M303", "M8003", "AND"),
        ("M304", "M8004", "ANDN"),
        ("M311", "M8121", "OR"),
        ("M312", "M8122", "ORN"),
        ("M313", "M8123", "AND"),
    ] {
        let src = if read.starts_with("LOD") {
            format!("LOD I0\nOUT Q1\n{read} {relay}\nOUT Q0")
        } else {
            format!("LOD I0\nOUT Q1\nLOD I1\n{read} {relay}\nOUT Q0")
        };
        let line = if read.starts_with("LOD") { 3 } else { 4 };
        let w = warnings(&src);
        assert_eq!(w.len(), 1, "{src}: {w:?}");
        assert_eq!(w[0].0, line, "{src}");
        assert!(
            w[0].1.contains("MICRO3") && w[0].1.contains(opennet),
            "{src}: {w:?}"
        );
    }
    let w = warnings("LOD M301\nAND M312\nOUT Q0\nLODN M312\nOUT Q1");
    let mut lines: Vec<usize> = w.iter().map(|(l, _)| *l).collect();
    lines.sort_unstable();
    assert_eq!(lines, [1, 2], "one per number: {w:?}");
}

/// §1: a relay the program writes (OUT, OUTN, SET, RST, an advanced destination or SFTL/SFTR
/// operand) is not warned about; nor are other M3xx relays.
#[test]
fn a_written_micro3_relay_is_not_warned_about() {
    for src in [
        "LOD M303\nOUT Q0\nLOD I0\nOUT M303",
        "LOD M311\nOUT Q0\nLOD I0\nOUTN M311",
        "LOD M301\nOUT Q0\nLOD I0\nSET M301",
        "LOD M304\nOUT Q0\nLOD I0\nRST M304",
        "LOD M312\nOUT Q0\nLOD I0\nMOV(W) 0 M300",
        "LOD M313\nOUT Q0\nLOD I0\nSFTL(W) M300 1",
        "LOD M302\nOUT Q0\nLOD M317\nOUT Q1",
    ] {
        let w = warnings(src);
        assert!(w.is_empty(), "{src}: {w:?}");
    }
}

/// §1: warnings never stop assembly; the relay is an ordinary one, 0 here.
#[test]
fn a_program_with_warnings_runs_and_the_relay_is_0() {
    let mut m = plc("LOD M303\nOUT Q0\nLOD M303\nOUTN Q1", 10);
    to_scan(&mut m, 2);
    assert_eq!(values(&m, &["Q0", "Q1", "M303"]), [0, 1, 0]);
}
