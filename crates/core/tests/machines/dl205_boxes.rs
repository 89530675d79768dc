//! DL205 timers, counters, edges and the scan's time base against `dl205.md` §4–§6.1, §6.5,
//! §6.9 and §6.11 (the manual's timing diagrams, p. 5-41), at several scan times.

use crate::common::{get, set};

fn errors(src: &str) -> Vec<String> {
    crate::common::error_texts(assemble(src))
}

use servoscope_core::machine::dl205::Dl205;
use servoscope_core::machine::dl205::assembler::assemble;
use servoscope_core::machine::plc::TimeBase;
use servoscope_core::machine::{Machine, MachineView};
use std::sync::Arc;

fn plc(src: &str, scan_ms: u32) -> Dl205 {
    let program = assemble(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    Dl205::with_time(Arc::new(program), TimeBase { scan_ms })
}

/// Run until `n` scans have completed.
fn to_scan(m: &mut Dl205, n: u64) {
    m.run_until(n, |_| false);
    assert_eq!(m.ticks(), n);
}

// ---- §6.11: the manual's timing diagrams ---------------------------------------------------

/// `TMR T1 K30` with X1 on: V1 = 10, 20, 30, 40 (BCD) after 100, 200, 300, 400 scans at 10 ms;
/// T1 on from the 300th scan; X1 off resets.
#[test]
fn tmr_counts_tenths_and_turns_on_at_its_preset() {
    let mut m = plc("STR X1\nTMR T1 K30\nSTR T1\nOUT Y0\nEND", 10);
    set(&mut m, "X1", 1);
    for (scans, v1) in [(100, 0x10), (200, 0x20), (300, 0x30), (400, 0x40)] {
        to_scan(&mut m, scans);
        assert_eq!(get(&m, "V1"), v1, "after {scans} scans");
        assert_eq!(get(&m, "TA1"), v1, "TA1 is V1");
    }
    let mut m = plc("STR X1\nTMR T1 K30\nSTR T1\nOUT Y0\nEND", 10);
    set(&mut m, "X1", 1);
    to_scan(&mut m, 299);
    assert_eq!((get(&m, "V1"), get(&m, "T1")), (0x29, 0));
    to_scan(&mut m, 300);
    assert_eq!(
        (get(&m, "V1"), get(&m, "T1")),
        (0x30, 1),
        "on from the 300th scan"
    );
    set(&mut m, "X1", 0);
    to_scan(&mut m, 301);
    assert_eq!((get(&m, "V1"), get(&m, "T1")), (0, 0), "enable off resets");
}

/// The same timer at other scan times: after N enabled scans it holds N × scan_ms (§9.14).
#[test]
fn tmr_keeps_controller_time_at_any_scan_time() {
    for scan_ms in [1, 7, 20, 30, 250, 1000] {
        let mut m = plc("STR X1\nTMR T1 K30\nEND", scan_ms);
        set(&mut m, "X1", 1);
        // The first scan whose end reaches 3.0 s.
        let on_at = 3000u64.div_ceil(u64::from(scan_ms));
        to_scan(&mut m, on_at - 1);
        let tenths = (on_at - 1) * u64::from(scan_ms) / 100;
        assert_eq!(get(&m, "T1"), 0, "scan_ms {scan_ms}");
        assert_eq!(
            get(&m, "V1"),
            u64::from(servoscope_core::machine::dl205::to_bcd(tenths)),
            "scan_ms {scan_ms}"
        );
        to_scan(&mut m, on_at);
        assert_eq!(
            get(&m, "T1"),
            1,
            "scan_ms {scan_ms}: on after {on_at} scans"
        );
    }
}

/// `TMRA T0 K30` (X1 enable, X2 reset), X1 on for scans 0–99 and from 200, X2 on at 600:
/// V0 = 10, 10, 20, 30, 40, 50 after 100…600 scans, T0 on from the 400th, 0 after the 601st.
#[test]
fn tmra_keeps_its_time_while_disabled() {
    let src = "STR X1\nSTR X2\nTMRA T0 K30\nSTR T0\nOUT Y0\nEND";
    let mut m = plc(src, 10);
    set(&mut m, "X1", 1);
    let mut seen = Vec::new();
    for scans in [100, 200, 300, 400, 500, 600] {
        to_scan(&mut m, scans);
        seen.push(get(&m, "V0"));
        match scans {
            100 => set(&mut m, "X1", 0),
            200 => set(&mut m, "X1", 1),
            _ => {}
        }
    }
    assert_eq!(seen, [0x10, 0x10, 0x20, 0x30, 0x40, 0x50]);
    let mut m = plc(src, 10);
    set(&mut m, "X1", 1);
    to_scan(&mut m, 100);
    set(&mut m, "X1", 0);
    to_scan(&mut m, 200);
    set(&mut m, "X1", 1);
    to_scan(&mut m, 399);
    assert_eq!(get(&m, "T0"), 0);
    to_scan(&mut m, 400);
    assert_eq!(
        (get(&m, "T0"), get(&m, "Y0")),
        (1, 1),
        "on from the 400th scan"
    );
    to_scan(&mut m, 600);
    set(&mut m, "X2", 1);
    to_scan(&mut m, 601);
    assert_eq!((get(&m, "V0"), get(&m, "V1"), get(&m, "T0")), (0, 0, 0));
}

/// TMRF counts hundredths; values stop at their maximum; a timer run twice in a scan counts
/// the scan once; a non-BCD current value is not counted and sets SP75 (§9.14, §9.16).
#[test]
fn timer_units_limits_and_bad_data() {
    let mut m = plc("STR SP1\nTMRF T2 K9999\nEND", 10);
    to_scan(&mut m, 37);
    assert_eq!(get(&m, "V2"), 0x37);
    let mut m = plc("STR SP1\nTMRF T2 K9999\nEND", 1000);
    to_scan(&mut m, 200);
    assert_eq!(
        (get(&m, "V2"), get(&m, "T2")),
        (0x9999, 1),
        "saturates at 9999"
    );
    // Two boxes with one number do not assemble (§2).
    assert!(assemble("STR SP1\nTMR T3 K5\nSTR SP1\nTMR T3 K5\nEND").is_err());
    let mut m = plc("STR SP1\nTMR T4 K5\nEND", 100);
    set(&mut m, "V4", 0x00A0);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "V4"), 0x00A0, "not counted");
    assert_eq!(get(&m, "SP75"), 1);
    assert_eq!(get(&m, "T4"), 1, "compares the raw pattern: A0 ≥ 5");
}

// ---- Counters ------------------------------------------------------------------------------

#[test]
fn cnt_counts_rises_and_resets() {
    let mut m = plc("STR X0\nSTR X1\nCNT CT3 K3\nSTR CT3\nOUT Y0\nEND", 10);
    let pulse = |m: &mut Dl205| {
        let t = m.ticks();
        set(m, "X0", 1);
        to_scan(m, t + 2);
        set(m, "X0", 0);
        to_scan(m, t + 4);
    };
    pulse(&mut m);
    pulse(&mut m);
    assert_eq!((get(&m, "CTA3"), get(&m, "CT3")), (2, 0));
    assert_eq!(get(&m, "V1003"), 2, "CTA3 is V1003");
    pulse(&mut m);
    assert_eq!((get(&m, "CTA3"), get(&m, "CT3"), get(&m, "Y0")), (3, 1, 1));
    set(&mut m, "X1", 1);
    let t = m.ticks();
    to_scan(&mut m, t + 1);
    assert_eq!((get(&m, "CTA3"), get(&m, "CT3")), (0, 0));
    // Counting while reset is held does nothing; its memory still follows the input.
    set(&mut m, "X0", 1);
    to_scan(&mut m, t + 2);
    set(&mut m, "X1", 0);
    to_scan(&mut m, t + 4);
    assert_eq!(get(&m, "CTA3"), 0, "the rise came during reset");
}

#[test]
fn udc_counts_both_ways_and_holds_at_zero() {
    let src = "STR X0\nSTR X1\nSTR X2\nUDC CT4 K2\nEND";
    let mut m = plc(src, 10);
    let step = |m: &mut Dl205, input: &str| {
        let t = m.ticks();
        set(m, input, 1);
        to_scan(m, t + 1);
        set(m, input, 0);
        to_scan(m, t + 2);
    };
    step(&mut m, "X1");
    assert_eq!(get(&m, "V1004"), 0, "holds at 0");
    step(&mut m, "X0");
    step(&mut m, "X0");
    assert_eq!((get(&m, "V1004"), get(&m, "CT4")), (2, 1));
    step(&mut m, "X1");
    assert_eq!((get(&m, "V1004"), get(&m, "CT4")), (1, 0));
    // Up and down together do nothing.
    set(&mut m, "X0", 1);
    set(&mut m, "X1", 1);
    let t = m.ticks();
    to_scan(&mut m, t + 1);
    assert_eq!(get(&m, "V1004"), 1);
}

#[test]
fn sgcnt_is_cleared_only_by_rst() {
    let src = "STR X0\nSGCNT CT1 K2\nSTR X1\nRST CT1\nEND";
    let mut m = plc(src, 10);
    for k in 0..3 {
        set(&mut m, "X0", 1);
        to_scan(&mut m, 2 * k + 1);
        set(&mut m, "X0", 0);
        to_scan(&mut m, 2 * k + 2);
    }
    assert_eq!((get(&m, "CTA1"), get(&m, "CT1")), (3, 1));
    set(&mut m, "X1", 1);
    to_scan(&mut m, 7);
    assert_eq!((get(&m, "CTA1"), get(&m, "CT1")), (0, 0));
}

#[test]
fn rst_of_a_timer_clears_value_and_status() {
    let src = "STR SP1\nSTR X1\nTMRA T6 K1\nSTR X2\nRST T6\nEND";
    let mut m = plc(src, 100);
    to_scan(&mut m, 5);
    assert_eq!((get(&m, "V6"), get(&m, "T6")), (5, 1));
    set(&mut m, "V7", 0x12);
    set(&mut m, "X2", 1);
    to_scan(&mut m, 6);
    // RST ran after the box in scan 5: both words cleared (§9.26).
    assert_eq!((get(&m, "V6"), get(&m, "V7"), get(&m, "T6")), (0, 0, 0));
}

// ---- Edges and coils -----------------------------------------------------------------------

#[test]
fn edge_contacts_fire_once_per_change() {
    let src = "STRPD X0\nOUT Y0\nSTRND X0\nOUT Y1\nSTR X0\nPD Y2\nEND";
    let mut m = plc(src, 10);
    set(&mut m, "X0", 1);
    to_scan(&mut m, 1);
    // An input already on fires in scan 0 (§9.18).
    assert_eq!((get(&m, "Y0"), get(&m, "Y1"), get(&m, "Y2")), (1, 0, 1));
    to_scan(&mut m, 2);
    assert_eq!((get(&m, "Y0"), get(&m, "Y2")), (0, 0), "one scan only");
    set(&mut m, "X0", 0);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "Y1"), 1, "falling edge");
    to_scan(&mut m, 4);
    assert_eq!(get(&m, "Y1"), 0);
}

#[test]
fn orout_ors_the_rungs_of_one_scan_and_not_inverts() {
    let src = "STR X0\nOROUT Y0\nSTR X1\nOROUT Y0\nSTR X0\nNOT\nOUT Y1\nEND";
    let mut m = plc(src, 10);
    to_scan(&mut m, 1);
    assert_eq!((get(&m, "Y0"), get(&m, "Y1")), (0, 1));
    set(&mut m, "X1", 1);
    to_scan(&mut m, 2);
    assert_eq!(get(&m, "Y0"), 1, "the second OROUT ORs");
    set(&mut m, "X1", 0);
    to_scan(&mut m, 3);
    assert_eq!(get(&m, "Y0"), 0, "the first OROUT of a scan writes");
}

// ---- CMP, INV, clocks ----------------------------------------------------------------------

#[test]
fn cmp_sets_exactly_one_of_sp60_to_sp62() {
    for (acc, operand, want) in [
        ("K5", "K6", "SP60"),
        ("K6", "K6", "SP61"),
        ("K7", "K6", "SP62"),
        ("KFFFF0005", "K6", "SP60"),
    ] {
        let m = {
            let mut m = plc(&format!("STR SP1\nLDD {acc}\nCMP {operand}\nEND"), 10);
            to_scan(&mut m, 1);
            m
        };
        for flag in ["SP60", "SP61", "SP62"] {
            assert_eq!(
                get(&m, flag),
                u64::from(flag == want),
                "{acc} vs {operand}: {flag}"
            );
        }
    }
    let mut m = plc("STR SP1\nLDD KFFFF0005\nCMPD K6\nEND", 10);
    to_scan(&mut m, 1);
    assert_eq!(get(&m, "SP62"), 1, "CMPD compares all 32 bits");
    let mut m = plc("STR SP1\nLDD K0000FFFF\nINV\nEND", 10);
    to_scan(&mut m, 1);
    assert_eq!(
        (get(&m, "ACC"), get(&m, "SP70"), get(&m, "SP63")),
        (0xFFFF_0000, 1, 0)
    );
}

#[test]
fn clock_relays_follow_virtual_time() {
    let src = "STR SP5\nOUT Y5\nSTR SP4\nOUT Y4\nSTR SP7\nOUT Y7\nSTR SP2\nOUT Y2\nEND";
    let mut m = plc(src, 10);
    let mut sp5 = Vec::new();
    let mut sp7 = Vec::new();
    for k in 1..=10 {
        to_scan(&mut m, k);
        sp5.push(get(&m, "Y5"));
        sp7.push(get(&m, "Y7"));
        assert_eq!(get(&m, "Y2"), 0);
    }
    // 100 ms clock at 10 ms scans: off in scans 0–4, on in 5–9 (§9.19).
    assert_eq!(sp5, [0, 0, 0, 0, 0, 1, 1, 1, 1, 1]);
    assert_eq!(sp7, [0, 1, 0, 1, 0, 1, 0, 1, 0, 1]);
    to_scan(&mut m, 50);
    assert_eq!(get(&m, "Y4"), 0, "SP4 off for the first 0.5 s");
    to_scan(&mut m, 51);
    assert_eq!(get(&m, "Y4"), 1);
    // 1000 ms scans alias the 1 s clock: always off.
    let mut m = plc(src, 1000);
    to_scan(&mut m, 5);
    assert_eq!(get(&m, "Y4"), 0);
}

// ---- The assembler -------------------------------------------------------------------------

#[test]
fn box_structure_errors() {
    let cases = [
        (
            "STR X1\nTMRA T0 K30\nEND",
            "TMRA takes 2 inputs (enable and reset)",
        ),
        (
            "STR X1\nSTR X2\nTMRA T0 K30\nAND X3\nOUT Y0\nEND",
            "AND after TMRA",
        ),
        (
            "STR X1\nTMR T0 K30\nSTR X2\nTMR T0 K5\nEND",
            "T0 is already used by the box on line 2",
        ),
        (
            "STR X1\nSTR X2\nTMRA T0 K30\nSTR X1\nTMR T1 K5\nEND",
            "T1 is already used",
        ),
        (
            "STR X1\nSTR X2\nTMRA T377 K30\nEND",
            "T377 is out of range (T0–T376)",
        ),
        (
            "STR X1\nOUT T1\nEND",
            "T1 cannot be written: OUT needs Y, C or S",
        ),
        (
            "STR X1\nSET CT1\nEND",
            "CT1 cannot be written: SET needs Y, C or S",
        ),
        ("STR X1\nTMR CT1 K5\nEND", "TMR needs a timer number"),
        (
            "STR X1\nTMR T1 K12345\nEND",
            "K12345 is out of range (K0–K9999)",
        ),
        ("STR X1\nCNT CT1 KA\nEND", "KA is not BCD"),
        (
            "STR X1\nSTR X2\nSTR X3\nCNT CT1 K5\nEND",
            "CNT takes 2 inputs (count and reset)",
        ),
        ("STR X1\nOUT Y0\nSTR X2\nSTR X3\nCNT CT1 K5\nEND", ""),
    ];
    for (src, want) in cases {
        let e = errors(src);
        if want.is_empty() {
            assert!(e.is_empty(), "{src}: {e:?}");
        } else {
            assert!(
                e.iter().any(|m| m.contains(want)),
                "{src}: {e:?} should say {want}"
            );
        }
    }
    assert!(
        errors("STR X1\nSTR X2\nSTR X3\nUDC CT1 K99999999\nSTR X4\nRST T0\nRST CT1\nEND")
            .is_empty()
    );
}

#[test]
fn the_parts_counter_fills_a_box_of_twelve() {
    let mut m = plc(
        include_str!("../../../../assets/examples/parts_counter.dl205"),
        10,
    );
    for part in 1..=12u64 {
        let t = m.ticks();
        set(&mut m, "X0", 1);
        to_scan(&mut m, t + 1);
        set(&mut m, "X0", 0);
        to_scan(&mut m, t + 2);
        assert_eq!(get(&m, "Y0"), u64::from(part == 12), "after part {part}");
    }
    assert_eq!(get(&m, "CTA0"), 0x12);
    set(&mut m, "X1", 1);
    let t = m.ticks();
    to_scan(&mut m, t + 5);
    assert_eq!(
        (get(&m, "CTA0"), get(&m, "Y0"), get(&m, "V2000")),
        (0, 0, 1)
    );
}

/// The remaining rows of §6.1 and §6.5 one by one, values from their formulas.
#[test]
fn contact_and_logic_rows() {
    let src = "STR SP1\nANDE V0 K5\nOUT Y0\nSTR SP2\nORE V0 K5\nOUT Y1\nSTR SP1\nANDNE V0 K5\nOUT Y2\n\
               STR SP2\nORNE V0 K6\nOUT Y3\nSTR SP1\nANDPD X0\nOUT Y4\nSTR SP2\nORND X0\nOUT Y5\n\
               STR SP1\nANDND X0\nOUT Y6\nSTR SP2\nORPD X0\nOUT Y7\n\
               STR SP1\nLDD K0F0F0F0F\nXORD KFFFF0000\nOUTD V10\nLDD K1\nROTR K1\nOUTD V20\n\
               LD K21\nOUT V40\nLDD K80000000\nROTL V40\nOUTD V22\nLDD K0000FFFF\nBCD\nOUTD V30\nEND";
    let mut m = plc(src, 10);
    set(&mut m, "V0", 5);
    to_scan(&mut m, 1);
    let y = |m: &Dl205| (0..8).map(|i| get(m, &format!("Y{i}"))).collect::<Vec<_>>();
    assert_eq!(y(&m), [1, 1, 0, 1, 0, 0, 0, 0]);
    set(&mut m, "X0", 1);
    to_scan(&mut m, 2);
    assert_eq!(y(&m)[4..], [1, 0, 0, 1], "X0 rose: the PD contacts fire");
    to_scan(&mut m, 3);
    assert_eq!(y(&m)[4..], [0, 0, 0, 0], "once");
    set(&mut m, "X0", 0);
    to_scan(&mut m, 4);
    assert_eq!(y(&m)[4..], [0, 1, 1, 0], "X0 fell: the ND contacts fire");
    let pair = |m: &Dl205, v: &str, w: &str| get(m, v) | get(m, w) << 16;
    assert_eq!(pair(&m, "V10", "V11"), 0xF0F0_0F0F, "XORD");
    assert_eq!(pair(&m, "V20", "V21"), 0x8000_0000, "ROTR 1");
    assert_eq!(
        pair(&m, "V22", "V23"),
        1,
        "ROTL by V40 = 33 (binary) is ROTL 1"
    );
    assert_eq!(pair(&m, "V30", "V31"), 0x0006_5535, "BCD of 65535");
}
