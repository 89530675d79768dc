//! OpenNet shift registers, comparisons, word logic, shifts, conversions and T/C word operands (§5.10, §5.11, §4.3).

use super::*;

// ---- §5.10 Shift registers ---------------------------------------------------------------------

/// §5.10 SFR R0 4 (reset I0, pulse I1, data I2): a rising pulse moves R0…R3 up (R3 lost) and
/// sets R0 = data; R4 is outside and keeps the 1 that SET put there. R0 as W is R0–R15 (§4.2).
#[test]
fn sfr_shifts_up_on_rising_pulses_and_reset_clears() {
    let src = "LOD M8120\nSET R4\nLOD I0\nLOD I1\nLOD I2\nSFR R0 4\nLOD R2\nOUT Q0\nLOD M8125\nMOV(W) R0 D0";
    let mut m = plc(src, 10);
    let shift = |m: &mut OpenNet, data: u64| {
        set(m, "I2", data);
        pulse(m, "I1");
        r_bits(m, 0, 5)
    };
    assert_eq!(shift(&mut m, 1), [1, 0, 0, 0, 1]);
    assert_eq!(shift(&mut m, 0), [0, 1, 0, 0, 1]);
    assert_eq!(shift(&mut m, 1), [1, 0, 1, 0, 1]);
    assert_eq!(shift(&mut m, 1), [1, 1, 0, 1, 1]);
    assert_eq!(
        shift(&mut m, 0),
        [0, 1, 1, 0, 1],
        "R3's 1 is lost, R4 untouched"
    );
    assert_eq!(get(&m, "Q0"), 1, "R2 as a contact");
    assert_eq!(get(&m, "D0"), 2 + 4 + 16, "R1, R2, R4 as bits 1, 2, 4");
    // A pulse held on shifts once.
    set(&mut m, "I2", 1);
    set(&mut m, "I1", 1);
    scans(&mut m, 3);
    assert_eq!(r_bits(&m, 0, 5), [1, 0, 1, 1, 1]);
    set(&mut m, "I1", 0);
    set(&mut m, "I0", 1);
    scans(&mut m, 1);
    assert_eq!(r_bits(&m, 0, 5), [0, 0, 0, 0, 1], "reset clears R0–R3 only");
    pulse(&mut m, "I1");
    assert_eq!(
        r_bits(&m, 0, 5),
        [0, 0, 0, 0, 1],
        "reset wins over the pulse"
    );
}

/// §5.10 SFRN R10 4: each rising pulse moves R10…R13 down (R10 lost) and sets R13 = data;
/// R9 and R14 are outside.
#[test]
fn sfrn_shifts_down() {
    let src = "LOD M8120\nSET R9\nSET R14\nLOD I0\nLOD I1\nLOD I2\nSFRN R10 4";
    let mut m = plc(src, 10);
    let shift = |m: &mut OpenNet, data: u64| {
        set(m, "I2", data);
        pulse(m, "I1");
        r_bits(m, 9, 6)
    };
    assert_eq!(shift(&mut m, 1), [1, 0, 0, 0, 1, 1]);
    assert_eq!(shift(&mut m, 0), [1, 0, 0, 1, 0, 1]);
    assert_eq!(shift(&mut m, 1), [1, 0, 1, 0, 1, 1]);
    assert_eq!(shift(&mut m, 1), [1, 1, 0, 1, 1, 1]);
    assert_eq!(shift(&mut m, 0), [1, 0, 1, 1, 0, 1], "R10's 1 is lost");
}

/// §5.10: a data input and a pulse on in scan 0 shift (the memory starts at 0).
#[test]
fn sfr_pulse_on_in_scan_0_shifts() {
    let mut m = plc("LOD I0\nLOD I1\nLOD I2\nSFR R0 3", 10);
    set(&mut m, "I1", 1);
    set(&mut m, "I2", 1);
    to_scan(&mut m, 3);
    assert_eq!(r_bits(&m, 0, 3), [1, 0, 0], "one shift for a pulse held on");
}

/// §5.10, §5.12: with MC = 0 the bits hold (reset does not act) and the pulse memory becomes 0.
#[test]
fn sfr_in_an_mcs_area_that_is_off_holds_and_forgets_its_pulse() {
    let mut m = plc("LOD I3\nMCS\nLOD I0\nLOD I1\nLOD I2\nSFR R0 4\nMCR", 10);
    set(&mut m, "I3", 1);
    set(&mut m, "I2", 1);
    pulse(&mut m, "I1");
    assert_eq!(r_bits(&m, 0, 4), [1, 0, 0, 0]);
    set(&mut m, "I2", 0);
    set(&mut m, "I1", 1);
    to_scan(&mut m, 3);
    assert_eq!(r_bits(&m, 0, 4), [0, 1, 0, 0], "scan 2: a rising pulse");
    set(&mut m, "I3", 0);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 4);
    assert_eq!(r_bits(&m, 0, 4), [0, 1, 0, 0], "MC = 0: held, no reset");
    set(&mut m, "I3", 1);
    set(&mut m, "I0", 0);
    to_scan(&mut m, 5);
    assert_eq!(
        r_bits(&m, 0, 4),
        [0, 0, 1, 0],
        "I1 still on is an edge again"
    );
}

/// §4.2: R bits as word operands — `R16` as W is R16–R31, `R240` is R240–R255 — and as CMP
/// destinations.
#[test]
fn r_bits_are_word_operands() {
    let m = once("MOV(W) 8001h R16\nMOV(W) 8000h R240\nCMP=(W) 1 1 R5\nMOV(W) R16 D0");
    assert_eq!(
        values(&m, &["R16", "R17", "R30", "R31", "R32"]),
        [1, 0, 0, 1, 0]
    );
    assert_eq!(values(&m, &["R254", "R255", "R5"]), [0, 1, 1]);
    assert_eq!(get(&m, "D0"), 0x8001);
}

// ---- §5.11 Comparisons, word logic, shifts, conversions --------------------------------------

/// §5.11: the six comparisons, W.
#[test]
fn the_six_comparisons() {
    let m = once(
        "MOV(W) 3 D0\nCMP=(W) D0 5 M0\nCMP<>(W) D0 5 M1\nCMP<(W) D0 5 M2\nCMP>(W) D0 5 M3\n\
         CMP<=(W) D0 5 M4\nCMP>=(W) D0 5 M5\nCMP=(W) D0 3 M10\nCMP<>(W) D0 3 M11\nCMP<(W) D0 3 M12\n\
         CMP>(W) D0 3 M13\nCMP<=(W) D0 3 M14\nCMP>=(W) D0 3 M15\nCMP>(W) 5 3 Q0\nCMP>(W) 5 3 R7",
    );
    // 3 vs 5: = 0, <> 1, < 1, > 0, <= 1, >= 0; 3 vs 3: 1, 0, 0, 0, 1, 1.
    assert_eq!(
        values(&m, &["M0", "M1", "M2", "M3", "M4", "M5"]),
        [0, 1, 1, 0, 1, 0]
    );
    assert_eq!(
        values(&m, &["M10", "M11", "M12", "M13", "M14", "M15"]),
        [1, 0, 0, 0, 1, 1]
    );
    assert_eq!(values(&m, &["Q0", "R7"]), [1, 1]);
}

/// §5.11: signed for I and L, unsigned for W and D. FFFFh is 65535 as W but −1 as I.
#[test]
fn comparisons_are_signed_for_i_and_l_and_unsigned_for_w_and_d() {
    let m = once(
        "MOV(W) FFFFh D0\nMOV(D) FFFFFFFFh D2\nCMP<(W) D0 1 M0\nCMP<(I) D0 1 M1\nCMP<(D) D2 1 M2\n\
         CMP<(L) D2 1 M3\nCMP>(W) D0 32767 M4\nCMP>(I) D0 32767 M5\nMOV(D) 00010000h D10\n\
         CMP>(D) D10 0000FFFFh M6\nMOV(D) 80000000h D12\nCMP<(L) D12 -2147483647 M7\n\
         CMP>=(D) D12 7FFFFFFFh M10",
    );
    assert_eq!(
        values(&m, &["M0", "M1"]),
        [0, 1],
        "65535 < 1 no; −1 < 1 yes"
    );
    assert_eq!(
        values(&m, &["M2", "M3"]),
        [0, 1],
        "4294967295 < 1 no; −1 < 1 yes"
    );
    assert_eq!(
        values(&m, &["M4", "M5"]),
        [1, 0],
        "65535 > 32767; −1 > 32767 no"
    );
    assert_eq!(get(&m, "M6"), 1, "65536 > 65535: the upper word counts");
    assert_eq!(
        values(&m, &["M7", "M10"]),
        [1, 1],
        "80000000h: −2147483648 as L, 2147483648 as D"
    );
}

/// §5.11: ICMP>= S1 S2 S3 D1 gives 1 when a ≥ b and b ≥ c.
#[test]
fn icmp_checks_both_bounds() {
    let m = once(
        "MOV(W) FFFFh D0\nICMP>=(W) 10 5 1 M0\nICMP>=(W) 10 5 6 M1\nICMP>=(W) 4 5 1 M2\n\
         ICMP>=(W) 5 5 5 M3\nICMP>=(I) 5 D0 D0 M4\nICMP>=(W) 5 D0 D0 M5\nICMP>=(I) D0 -2 -3 M6\n\
         ICMP>=(W) D0 2 1 M7",
    );
    // 10≥5≥1; 5≥6 no; 4≥5 no; 5≥5≥5; 5≥−1≥−1; 5≥65535 no; −1≥−2≥−3; 65535≥2≥1.
    assert_eq!(
        values(&m, &["M0", "M1", "M2", "M3", "M4", "M5", "M6", "M7"]),
        [1, 0, 0, 1, 1, 0, 1, 1]
    );
}

/// §5.2, §5.11: with REP a marked CMP D1 advances one point per cycle (IDEC numbering: M37 is
/// followed by M40); an unmarked D1 ends with the last cycle's result.
#[test]
fn comparisons_with_rep() {
    let m = once(
        "MOV(W) 9 D10\nMOV(W) 6 D11\nMOV(W) 1 D12\nMOV(W) 5 D13\nCMP>(W) D10(R) 5 M0(R) REP 4\n\
         CMP>(W) D10(R) 5 M20 REP 4\nCMP>(W) D10(R) 4 M21 REP 4\nMOV(W) 9 D20(R) REP 10\n\
         CMP=(W) D20(R) 9 M30(R) REP 10",
    );
    assert_eq!(
        values(&m, &["M0", "M1", "M2", "M3", "M4"]),
        [1, 1, 0, 0, 0],
        "9, 6, 1, 5 > 5"
    );
    assert_eq!(
        values(&m, &["M20", "M21"]),
        [0, 1],
        "last cycle: 5 > 5 no, 5 > 4 yes"
    );
    let ten = [
        "M30", "M31", "M32", "M33", "M34", "M35", "M36", "M37", "M40", "M41",
    ];
    assert_eq!(values(&m, &ten), [1; 10]);
    assert_eq!(get(&m, "M42"), 0, "ten points only");
}

/// §5.11: comparisons act only while their input is on; otherwise D1 keeps its value.
#[test]
fn a_comparison_whose_input_is_off_keeps_its_result() {
    let mut m = plc("LOD I0\nCMP=(W) D0 0 M0", 10);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "M0"), 1);
    set(&mut m, "I0", 0);
    set(&mut m, "D0", 5);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "M0"), 1, "not an OUT: kept");
    set(&mut m, "I0", 1);
    to_scan(&mut m, 4);
    assert_eq!(get(&m, "M0"), 0);
}

/// §5.11: ANDW/ORW/XORW bit by bit in W and D, REP, a bit-operand destination; M8003 untouched.
#[test]
fn word_logic() {
    let m = once(
        "ADD(W) 65535 1 D90\nANDW(W) F0F0h 0FF0h D0\nORW(W) F0F0h 0FF0h D1\nXORW(W) F0F0h 0FF0h D2\n\
         ANDW(D) 12345678h 0000FFFFh D10\nORW(D) 12340000h 00005678h D12\n\
         XORW(D) FFFFFFFFh 0F0F0F0Fh D14\nMOV(W) 1234h D30\nMOV(W) ABCDh D31\n\
         ANDW(W) D30(R) 000Fh D40(R) REP 2\nANDW(W) D0 D1 Q0",
    );
    assert_eq!(values(&m, &["D0", "D1", "D2"]), [0x00F0, 0xFFF0, 0xFF00]);
    assert_eq!(values(&m, &["D10", "D11"]), [0x0000, 0x5678]);
    assert_eq!(values(&m, &["D12", "D13"]), [0x1234, 0x5678]);
    assert_eq!(values(&m, &["D14", "D15"]), [0xF0F0, 0xF0F0]);
    assert_eq!(values(&m, &["D40", "D41"]), [0x4, 0xD]);
    // 00F0h & FFF0h = 00F0h: bits 4–7 = Q4–Q7.
    assert_eq!(
        values(&m, &["Q0", "Q3", "Q4", "Q7", "Q10", "Q17"]),
        [0, 0, 1, 1, 0, 0]
    );
    assert_eq!(
        get(&m, "M8003"),
        1,
        "the ADD's carry: word logic leaves M8003 alone"
    );
}

/// §5.11's examples: `SFTL(W) D0 4` with D0 = 1234h → 2340h, M8003 = 1 (bit 12 of 1234h);
/// and the other shifts, each writing M8003 with the last bit out.
#[test]
fn sftl_and_sftr_write_the_last_bit_out_to_m8003() {
    for (src, d, m8003) in [
        ("MOV(W) 1234h D0\nSFTL(W) D0 4", vec![("D0", 0x2340)], 1),
        // 1234h >> 4 = 0123h; bit 3 of 1234h (the 4 = 0100b) is 0; the ADD's carry is rewritten.
        (
            "ADD(W) 65535 1 D9\nMOV(W) 1234h D0\nSFTR(W) D0 4",
            vec![("D0", 0x0123)],
            0,
        ),
        // 1234h >> 3 = 0246h; bit 2 of 1234h is 1.
        ("MOV(W) 1234h D0\nSFTR(W) D0 3", vec![("D0", 0x0246)], 1),
        // 1 << 15 = 8000h; bit 16 − 15 = 1 of 0001h is 0.
        ("MOV(W) 1 D0\nSFTL(W) D0 15", vec![("D0", 0x8000)], 0),
        // 12345678h << 4 = 23456780h; bit 28 (the 1) is 1.
        (
            "MOV(D) 12345678h D0\nSFTL(D) D0 4",
            vec![("D0", 0x2345), ("D1", 0x6780)],
            1,
        ),
        // 12345678h >> 4 = 01234567h; bit 3 (the 8 = 1000b) is 1.
        (
            "MOV(D) 12345678h D0\nSFTR(D) D0 4",
            vec![("D0", 0x0123), ("D1", 0x4567)],
            1,
        ),
    ] {
        let m = once(src);
        for (name, v) in d {
            assert_eq!(get(&m, name), v, "{src}: {name}");
        }
        assert_eq!(get(&m, "M8003"), m8003, "{src}");
    }
    // A bit operand: M0 as W (M0–M7, M10–M17) = 8001h; shifted left 1 → 0002h, bit 15 out.
    let m = once("MOV(W) 8001h M0\nSFTL(W) M0 1");
    assert_eq!(values(&m, &["M0", "M1", "M17", "M8003"]), [0, 1, 0, 1]);
}

/// §3, §5.11: an advanced instruction acts in every scan its input is on; each SFTL writes
/// M8003. D0 = 1 shifted once a scan: 8000h after scan 14, 0 after scan 15 with bit 15 out
/// (M8003 = 1), then 0 out (M8003 = 0).
#[test]
fn sftl_acts_every_scan_its_input_is_on() {
    let mut m = plc("LOD M8125\nSFTL(W) D0 1", 10);
    set(&mut m, "D0", 1);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "D0"), 8);
    to_scan(&mut m, 15);
    assert_eq!((get(&m, "D0"), get(&m, "M8003")), (0x8000, 0));
    to_scan(&mut m, 16);
    assert_eq!((get(&m, "D0"), get(&m, "M8003")), (0, 1));
    to_scan(&mut m, 17);
    assert_eq!((get(&m, "D0"), get(&m, "M8003")), (0, 0));
}

/// §5.11's examples: `HTOB(W) 1234 D0` gives 1234h; `BTOH(D) 12345678h D4` gives D4 = 00BCh,
/// D5 = 614Eh (12345678 = 00BC614Eh); and the widest values.
#[test]
fn htob_and_btoh_convert_between_binary_and_bcd() {
    let m = once(
        "HTOB(W) 1234 D0\nHTOB(W) 9999 D1\nHTOB(D) 12345678 D2\nHTOB(D) 99999999 D6\n\
         BTOH(D) 12345678h D4\nBTOH(W) 1234h D10\nBTOH(W) 9999h D11\nMOV(W) 56h D20\nBTOH(W) D20 D21",
    );
    assert_eq!(values(&m, &["D0", "D1"]), [0x1234, 0x9999]);
    assert_eq!(values(&m, &["D2", "D3"]), [0x1234, 0x5678]);
    assert_eq!(values(&m, &["D6", "D7"]), [0x9999, 0x9999]);
    assert_eq!(values(&m, &["D4", "D5"]), [0x00BC, 0x614E]);
    assert_eq!(values(&m, &["D10", "D11", "D21"]), [1234, 9999, 56]);
    assert_eq!((get(&m, "M8004"), m.error_count), (0, 0));
}

/// §5.11, §6: a value over 9999 (W) / 99999999 (D) is `bcd_range`, a nibble over 9 is
/// `bcd_digit`: the destination is unchanged, M8004 = 1, error_count 1, last_error at the
/// instruction's line in scan 0, and M8003 (1 from the ADD) untouched.
#[test]
fn bcd_execution_errors() {
    for (op, kind) in [
        ("HTOB(W) 10000 D0", "bcd_range"),
        ("HTOB(D) 100000000 D0", "bcd_range"),
        ("BTOH(W) 12A4h D0", "bcd_digit"),
        ("BTOH(W) F000h D0", "bcd_digit"),
        ("BTOH(D) 0000000Ah D0", "bcd_digit"),
    ] {
        // Lines: 1 LOD M8120, 2 ADD, 3 MOV, 4 MOV, 5 the conversion.
        let m = once(&format!(
            "ADD(W) 65535 1 D9\nMOV(W) 7 D0\nMOV(W) 8 D1\n{op}"
        ));
        assert_eq!(values(&m, &["D0", "D1"]), [7, 8], "{op}: nothing written");
        assert_eq!(get(&m, "M8004"), 1, "{op}");
        assert_eq!(m.error_count, 1, "{op}");
        assert_eq!(last_error(&m), (kind, 5, 0), "{op}");
        assert_eq!(get(&m, "M8003"), 1, "{op}: M8003 untouched");
    }
}

/// §6: one error per erring REP cycle; the other cycles run.
#[test]
fn bcd_errors_count_per_rep_cycle() {
    // Lines: 1 LOD M8120, 2–6 MOV, 7 HTOB.
    let m = once(
        "MOV(W) 5 D10\nMOV(W) 10000 D11\nMOV(W) 20000 D12\nMOV(W) 1 D21\nMOV(W) 1 D22\n\
         HTOB(W) D10(R) D20(R) REP 3",
    );
    assert_eq!(values(&m, &["D20", "D21", "D22"]), [0x5, 1, 1]);
    assert_eq!(m.error_count, 2);
    assert_eq!(last_error(&m), ("bcd_range", 7, 0));
}

/// §6: last_error's tick is the scan; M8004 stays on; SOTU makes the conversion act once.
#[test]
fn a_bcd_error_in_a_later_scan_records_its_tick() {
    let mut m = plc("LOD I0\nSOTU\nBTOH(W) D1 D0", 10);
    set(&mut m, "D1", 0x00A0);
    set(&mut m, "D0", 77);
    to_scan(&mut m, 3);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 6);
    assert_eq!(m.error_count, 1);
    assert_eq!(last_error(&m), ("bcd_digit", 3, 3));
    assert_eq!(values(&m, &["D0", "M8004", "M8003"]), [77, 1, 0]);
}

// ---- §4.3 T and C word operands --------------------------------------------------------------

/// §4.3: T or C as a source reads the current value, as a destination writes the preset.
#[test]
fn timer_and_counter_words_read_the_current_value_and_write_the_preset() {
    let src = "LOD I0\nTMH T0 10\nLOD M8125\nMOV(W) T0 D0\nMOV(I) T0 D1\nLOD I1\nMOV(W) 25 T0\n\
               LOD I2\nLOD I3\nCNT C0 50\nLOD M8125\nMOV(W) C0 D2\nLOD I4\nADD(W) T0 100 C0";
    let mut m = plc(src, 10);
    set(&mut m, "I0", 1);
    to_scan(&mut m, 4);
    assert_eq!(values(&m, &["D0", "D1"]), [7, 7], "scan 3: 10 − 3");
    set(&mut m, "I1", 1);
    to_scan(&mut m, 5);
    assert_eq!(
        timer(&m, "T0"),
        (25, 6, 0),
        "preset written, current running on"
    );
    assert_eq!(get(&m, "D0"), 6);
    pulse(&mut m, "I3");
    pulse(&mut m, "I3");
    assert_eq!(get(&m, "D2"), 2, "C0's current value");
    // Scan 9 (the two pulses took scans 5–8): T0.current = 10 − 9 = 1, so C0.preset = 101.
    set(&mut m, "I4", 1);
    scans(&mut m, 1);
    assert_eq!(m.ticks(), 10);
    assert_eq!(get(&m, "T0.current"), 1);
    assert_eq!(
        counter(&m, "C0"),
        (101, 2, 0),
        "C0.preset = T0.current + 100"
    );
}

/// §4.3: a block of n words of T is n consecutive timers; (R) advances by one timer.
#[test]
fn rep_over_timers_advances_one_timer_a_cycle() {
    let src = "LOD I5\nMOV(W) D20(R) T0(R) REP 3\nLOD I0\nTIM T0 4\nTIM T1 5\nTIM T2 6\n\
               LOD M8125\nMOV(W) T0(R) D10(R) REP 3";
    let mut m = plc(src, 10);
    to_scan(&mut m, 1);
    assert_eq!(
        values(&m, &["D10", "D11", "D12"]),
        [4, 5, 6],
        "currents = presets while off"
    );
    for (i, v) in [7, 8, 9].into_iter().enumerate() {
        set(&mut m, &format!("D{}", 20 + i), v);
    }
    set(&mut m, "I5", 1);
    to_scan(&mut m, 2);
    assert_eq!(
        [timer(&m, "T0"), timer(&m, "T1"), timer(&m, "T2")],
        [(7, 7, 0), (8, 8, 0), (9, 9, 0)]
    );
    assert_eq!(values(&m, &["D10", "D11", "D12"]), [7, 8, 9]);
}

/// §5.2's example (MICRO3 p.11-2): C0…C3 at 10, 20, 30, 40 and `ADD(W) C0(R) D0 D0 REP 4`
/// leave D0 = 100. The currents come from CDP preset inputs (M8120) in scan 0.
#[test]
fn the_vendors_totaliser_over_counters() {
    let mut src = String::new();
    for (c, p) in [(0, 10), (1, 20), (2, 30), (3, 40)] {
        src.push_str(&format!("LOD M8120\nLOD I1\nLOD I2\nCDP C{c} {p}\n"));
    }
    src.push_str("LOD M8120\nADD(W) C0(R) D0 D0 REP 4");
    let mut m = plc(&src, 10);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "D0"), 100);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "D0"), 100, "M8120 is off after scan 0");
    assert_eq!(
        values(
            &m,
            &["C0.current", "C1.current", "C2.current", "C3.current"]
        ),
        [10, 20, 30, 40]
    );
}

/// The same totaliser with the counters' current values written by the debugger.
#[test]
fn the_vendors_totaliser_over_written_counters() {
    let mut src = String::new();
    for c in 0..4 {
        src.push_str(&format!("LOD I0\nLOD I1\nCNT C{c} 100\n"));
    }
    src.push_str("LOD M8120\nADD(W) C0(R) D0 D0 REP 4");
    let mut m = plc(&src, 10);
    for (c, v) in [10, 20, 30, 40].into_iter().enumerate() {
        set(&mut m, &format!("C{c}.current"), v);
    }
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "D0"), 100);
}
