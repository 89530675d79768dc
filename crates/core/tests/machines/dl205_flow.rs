//! DL205 program control against `dl205.md` §2, §5, §6.8 and §6.10: GOTO/LBL, FOR/NEXT,
//! GTS/SBR/RT/RTC, MLS/MLR, stages with their clean-up pass, and what counts as a step.

use crate::common::{get, set};

fn errors(src: &str) -> Vec<String> {
    crate::common::error_texts(assemble(src))
}

use servoscope_core::debugger::Debugger;
use servoscope_core::machine::PlcView;
use servoscope_core::machine::dl205::Dl205;
use servoscope_core::machine::dl205::assembler::assemble;
use servoscope_core::machine::{Machine, MachineView};
use std::sync::Arc;

fn plc(src: &str) -> Dl205 {
    let program = assemble(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    Dl205::new(Arc::new(program))
}

fn scan(m: &mut Dl205) -> u64 {
    let steps = m.steps();
    let t = m.ticks();
    m.run_until(t + 1, |_| false);
    m.steps() - steps
}

fn settle(d: &mut Debugger) {
    while d.advance(0.016, std::time::Duration::from_millis(200)) {}
}

#[test]
fn goto_skips_forward_and_skipped_code_is_not_a_step() {
    let mut m = plc("STR X0\nGOTO K1\nSTR SP1\nOUT Y0\nLBL K1\nSTR SP1\nOUT Y1\nEND");
    assert_eq!(scan(&mut m), 8);
    assert_eq!((get(&m, "Y0"), get(&m, "Y1")), (1, 1));
    set(&mut m, "X0", 1);
    // STR, GOTO, LBL, STR, OUT, END: the skipped rung keeps Y0 as it was.
    assert_eq!(scan(&mut m), 6);
    assert_eq!((get(&m, "Y0"), get(&m, "Y1")), (1, 1));
}

#[test]
fn for_next_runs_its_body_n_times() {
    let mut m = plc("STR SP1\nFOR K3\nSTR SP1\nINCB V0\nNEXT\nEND");
    // STR, FOR, 3 × (STR, INCB, NEXT), END.
    assert_eq!(scan(&mut m), 12);
    assert_eq!(get(&m, "V0"), 3);
    // An unpowered FOR continues after its NEXT.
    let mut m = plc("STR X0\nFOR K3\nSTR SP1\nINCB V0\nNEXT\nEND");
    assert_eq!(scan(&mut m), 3);
    assert_eq!(get(&m, "V0"), 0);
    // A count from V: BCD; 0 runs nothing, a non-BCD count sets SP75 and runs nothing.
    let mut m = plc("STR SP1\nFOR V1\nSTR SP1\nINCB V0\nNEXT\nEND");
    set(&mut m, "V1", 0x12);
    scan(&mut m);
    assert_eq!(get(&m, "V0"), 12);
    set(&mut m, "V1", 0x1A);
    scan(&mut m);
    assert_eq!((get(&m, "V0"), get(&m, "SP75")), (12, 1));
    // A timer in a loop counts its scan once (§9.14).
    let mut m = plc("STR SP1\nFOR K5\nSTR SP1\nTMRF T0 K100\nNEXT\nEND");
    scan(&mut m);
    assert_eq!(get(&m, "TA0"), 1);
}

#[test]
fn subroutines_return_with_the_callers_rung() {
    let src = "STR SP1\nGTS K1\nOUT Y1\nSTR X0\nGTS K2\nEND\nSBR K1\nSTR SP1\nINCB V0\nRT\n\
               SBR K2\nSTR X1\nRTC\nSTR SP1\nINCB V1\nRT\nSBR K3\nSTR SP1\nINCB V2\nRT\n";
    let mut m = plc(src);
    scan(&mut m);
    // The caller's rung (SP1) powers OUT Y1 after the return; K3 is never called.
    assert_eq!((get(&m, "V0"), get(&m, "Y1"), get(&m, "V2")), (1, 1, 0));
    set(&mut m, "X0", 1);
    scan(&mut m);
    assert_eq!(get(&m, "V1"), 1, "K2 ran to RT");
    set(&mut m, "X1", 1);
    scan(&mut m);
    assert_eq!(get(&m, "V1"), 1, "RTC returned early");
}

#[test]
fn step_over_runs_a_subroutine_whole_and_step_out_leaves_it() {
    let dl205 = servoscope_core::registry::by_name("dl205").expect("registered");
    let src = "STR SP1\nGTS K1\nSTR SP1\nOUT Y1\nEND\nSBR K1\nSTR SP1\nINCB V0\nINCB V0\nRT\n";
    let mut d = Debugger::with_dialect(dl205, "call.dl205", src);
    d.step_command();
    d.step_over();
    settle(&mut d);
    let m = d.machine();
    assert_eq!(m.pc_line(), Some(3), "stopped after the GTS");
    assert_eq!(m.read(m.find("V0").unwrap()), 2);
    let mut d = Debugger::with_dialect(dl205, "call.dl205", src);
    for _ in 0..4 {
        d.step_command();
    }
    assert_eq!(d.machine().call_depth(), 1, "inside the subroutine");
    d.step_out();
    settle(&mut d);
    assert_eq!(d.machine().call_depth(), 0);
    assert_eq!(d.machine().pc_line(), Some(3));
}

#[test]
fn master_lines_cut_the_power_of_their_zone() {
    let src = "STR X0\nMLS K1\nSTR SP1\nOUT Y0\nSTR SP1\nSTR SP2\nTMRA T2 K50\nMLR K0\nSTR SP1\nOUT Y1\nEND";
    let mut m = plc(src);
    set(&mut m, "Y0", 1);
    scan(&mut m);
    // Zone 1 is off: OUT writes 0, the TMRA's legs see no power (it holds, not resets).
    assert_eq!((get(&m, "Y0"), get(&m, "Y1"), get(&m, "TA2")), (0, 1, 0));
    set(&mut m, "X0", 1);
    for _ in 0..10 {
        scan(&mut m);
    }
    assert_eq!((get(&m, "Y0"), get(&m, "TA2")), (1, 0x1));
}

#[test]
fn stages_run_skip_and_clean_up() {
    let src = "ISG S0\nSTR SP1\nOUT Y0\nSTR X0\nJMP S1\nSG S1\nSTR SP1\nOUT Y1\nSTR SP1\nTMR T1 K50\nSTR X1\nJMP S0\nEND";
    let mut m = plc(src);
    assert_eq!(get(&m, "S0"), 1, "ISG is on before scan 0");
    // S0 runs, S1 is skipped: its instructions are not steps.
    assert_eq!(scan(&mut m), 6 + 1);
    assert_eq!((get(&m, "Y0"), get(&m, "Y1")), (1, 0));
    set(&mut m, "X0", 1);
    scan(&mut m);
    // The jump goes to a later stage: it runs in the same scan; S0 still ran to its end.
    assert_eq!((get(&m, "S0"), get(&m, "S1"), get(&m, "Y1")), (0, 1, 1));
    assert_eq!(get(&m, "Y0"), 1, "S0 cleans up in the next scan");
    set(&mut m, "X0", 0);
    scan(&mut m);
    assert_eq!(get(&m, "Y0"), 0, "the clean-up pass turned S0's coil off");
    for _ in 0..8 {
        scan(&mut m);
    }
    assert_ne!(get(&m, "TA1"), 0);
    set(&mut m, "X1", 1);
    scan(&mut m);
    set(&mut m, "X1", 0);
    assert_eq!((get(&m, "S0"), get(&m, "S1")), (1, 0));
    // The target is before S1: it runs from the next scan, when S1 also cleans up.
    scan(&mut m);
    assert_eq!(
        (get(&m, "Y0"), get(&m, "Y1"), get(&m, "TA1"), get(&m, "T1")),
        (1, 0, 0, 0)
    );
}

#[test]
fn the_push_on_off_example_switches_once_per_press() {
    let mut m = plc(include_str!(
        "../../../../assets/examples/push_on_off.dl205"
    ));
    let mut lamp = Vec::new();
    for x0 in [0, 1, 1, 0, 0, 1, 1, 1, 0, 0, 1, 0] {
        set(&mut m, "X0", x0);
        scan(&mut m);
        lamp.push(get(&m, "Y0"));
    }
    // On in the scan of the first press (S1 comes after S0: it runs in the same scan). The
    // second press turns S2 off after its OUT ran: the lamp goes off in the next scan, S2's
    // clean-up pass.
    assert_eq!(lamp, [0, 1, 1, 1, 1, 1, 0, 0, 0, 0, 1, 1]);
}

#[test]
fn control_structure_errors() {
    let cases = [
        ("STR X0\nGOTO K2\nEND", "GOTO K2: no LBL K2"),
        ("LBL K1\nSTR X0\nGOTO K1\nEND", "GOTO only jumps forward"),
        (
            "STR SP1\nFOR K2\nSTR X0\nGOTO K1\nNEXT\nLBL K1\nEND",
            "leaves its block",
        ),
        ("STR SP1\nFOR K2\nSTR SP1\nOUT Y0\nEND", "FOR without NEXT"),
        ("NEXT\nEND", "NEXT without FOR"),
        (
            "STR SP1\nFOR K2\nSTR SP1\nFOR K2\nNEXT\nNEXT\nEND",
            "loops do not nest",
        ),
        ("STR SP1\nGTS K5\nEND", "GTS K5: no SBR K5"),
        (
            "STR SP1\nGTS K1\nEND\nSBR K1\nSTR SP1\nGTS K1\nRT",
            "recursion",
        ),
        (
            "STR SP1\nGTS K1\nEND\nSBR K1\nSTR SP1\nOUT Y0",
            "SBR without RT",
        ),
        (
            "STR SP1\nOUT Y0\nEND\nSTR SP1\nOUT Y1",
            "only subroutines (SBR … RT) may follow END",
        ),
        ("STR SP1\nOUT Y0\nRT\nEND", "RT outside a subroutine"),
        (
            "STR X0\nJMP S1\nSG S1\nSTR SP1\nOUT Y0\nEND",
            "JMP outside a stage",
        ),
        ("SG S1\nSTR X0\nJMP S7\nEND", "no SG or ISG S7"),
        (
            "SG S1\nSTR X0\nOUT Y0\nSG S1\nSTR X0\nOUT Y1\nEND",
            "already has its SG/ISG",
        ),
        ("STR X0\nMLS K2\nEND", "MLS K2 must follow level 1"),
        (
            "STR X0\nMLS K1\nMLR K1\nEND",
            "MLR K1 must be below the current level 1",
        ),
        ("STR SP1\nFOR K2\nAND X1\nNEXT\nEND", "AND after FOR"),
        ("LBL K1\nLBL K1\nEND", "LBL K1 is already defined"),
    ];
    for (src, want) in cases {
        let e = errors(src);
        assert!(
            e.iter().any(|m| m.contains(want)),
            "{src}\n{e:#?}\nshould say {want}"
        );
    }
    let deep: String = (1..=9)
        .map(|k| format!("SBR K{k}\nSTR SP1\nGTS K{}\nRT\n", k + 1))
        .collect::<String>()
        + "SBR K10\nSTR SP1\nOUT Y0\nRT\n";
    let e = errors(&format!("STR SP1\nGTS K1\nEND\n{deep}"));
    assert!(
        e.iter().any(|m| m.contains("calls nested 10 deep")),
        "{e:#?}"
    );
}

// ---- Tables and bit-mapped words (§1, §6.6) --------------------------------------------

/// Manual p. 5-149: `STR X0 / LD K2 / LDA O3000 / SETBIT O34` sets V3001 bit 12.
#[test]
fn setbit_the_manuals_example() {
    let mut m = plc("STR X0\nLD K2\nLDA O3000\nSETBIT O34\nEND");
    set(&mut m, "X0", 1);
    scan(&mut m);
    assert_eq!(get(&m, "V3001"), 0x1000);
    let mut m = plc("STR SP1\nLD K2\nLDA O3000\nRSTBIT O34\nEND");
    set(&mut m, "V3001", 0xFFFF);
    scan(&mut m);
    assert_eq!(get(&m, "V3001"), 0xEFFF);
}

#[test]
fn mov_copies_ascending_and_checks_its_range() {
    let mut m = plc("STR SP1\nLD K3\nLDA O2000\nMOV V3000\nEND");
    for (i, v) in [11, 22, 33].into_iter().enumerate() {
        set(&mut m, &format!("V{:o}", 0o2000 + i), v);
    }
    scan(&mut m);
    assert_eq!(
        (get(&m, "V3000"), get(&m, "V3001"), get(&m, "V3002")),
        (11, 22, 33)
    );
    assert_eq!(
        (get(&m, "SP53"), get(&m, "ACC"), get(&m, "L1")),
        (0, 0o2000, 3),
        "ACC and stack kept"
    );
    // Overlapping upwards copies ascending: each word takes the one below it, already copied.
    let mut m = plc("STR SP1\nLD K3\nLDA O2000\nMOV V2001\nEND");
    set(&mut m, "V2000", 7);
    scan(&mut m);
    assert_eq!(
        (get(&m, "V2001"), get(&m, "V2002"), get(&m, "V2003")),
        (7, 7, 7)
    );
    let mut m = plc("STR SP1\nLD K2\nLDA O37777\nMOV V100\nEND");
    scan(&mut m);
    assert_eq!(
        (get(&m, "SP53"), get(&m, "SP75"), get(&m, "V100")),
        (1, 0, 0)
    );
    let mut m = plc("STR SP1\nLD KA\nLDA O100\nMOV V200\nEND");
    scan(&mut m);
    assert_eq!((get(&m, "SP75"), get(&m, "SP53")), (1, 0));
}

#[test]
fn bit_mapped_words_read_and_write_their_elements() {
    let src = "STR SP1\nLD VX0\nOUT V2000\nLD K5\nOUT VY0\nLD K3\nOUT VC20\nLD VSP0\nOUT V2001\nLD VS0\nOUT V2002\nEND";
    let mut m = plc(src);
    set(&mut m, "X0", 1);
    set(&mut m, "X3", 1);
    set(&mut m, "S1", 1);
    scan(&mut m);
    assert_eq!(get(&m, "V2000"), 0b1001, "X0 and X3");
    assert_eq!((get(&m, "Y0"), get(&m, "Y1"), get(&m, "Y2")), (1, 0, 1));
    assert_eq!((get(&m, "C20"), get(&m, "C21"), get(&m, "C22")), (1, 1, 0));
    assert_eq!(get(&m, "V2001") & 0b11, 0b11, "SP0 and SP1 in scan 0");
    assert_eq!(get(&m, "V2002"), 0b10, "S1");
    assert_eq!(m.find("VY0"), m.find("V40500"));
    assert_eq!(get(&m, "VY0"), 5);
    assert_eq!(get(&m, "VC20"), 3);
    let e = |src: &str| errors(src);
    assert!(e("STR SP1\nLD K1\nOUT VX0\nEND")[0].contains("VX0 is read-only"));
    assert!(e("STR SP1\nINCB V41100\nEND")[0].contains("read-only"));
    assert!(e("STR SP1\nLD V40000\nEND")[0].contains("GX/GY"));
    assert!(e("STR SP1\nLD V41120\nEND")[0].contains("does not exist"));
    assert!(e("STR SP1\nLD VX7\nEND")[0].contains("multiple of 20"));
    assert!(e("STR SP1\nLD VX1760\nLD VT360\nLD VCT360\nLD VSP760\nOUTD VS1740\nEND").is_empty());
}

/// Spec §1: other controllers' notation is named, with what to write instead.
#[test]
fn other_controllers_notation_is_named() {
    for (src, want) in [
        (
            "STR 0125\nOUT Y0\nEND",
            "1:5: error: '0125' is a bare element number in DL305/handheld notation",
        ),
        (
            "0001 STR X0\nOUT Y0\nEND",
            "1:1: error: '0001' is a line number in DL305/handheld notation",
        ),
        (
            "STR X0\nTMR T1 003.0\nEND",
            "2:8: error: '003.0' is a decimal preset in DL305/handheld notation",
        ),
        (
            "STR X0\nOR NOT X1\nOUT Y0\nEND",
            "2:1: error: OR NOT: DirectSOFT writes ORN",
        ),
        (
            "LD X1\nOUT Y0\nEND",
            "1:1: error: LD loads the accumulator: a contact on X1 is STR X1",
        ),
        ("LOD X0\nOUT Y0\nEND", "LOD is IDEC notation"),
        ("STR X0\nTIM T1 K5\nEND", "TIM is Omron notation"),
        ("STR X0\nTON T1 K5\nEND", "TON is IEC 61131-3 notation"),
        ("XIC X0\nOTE Y0\nEND", "XIC is Allen-Bradley notation"),
    ] {
        let e = errors(src);
        assert!(
            e.iter().any(|m| m.starts_with(want) || m.contains(want)),
            "{src}\n{e:#?}\nshould say {want}"
        );
    }
}

/// Issue #23 item 4: code a scan jumped over or did not reach (an inactive stage) is marked
/// for the code view; an output in a master-line zone that is off is skipped.
#[test]
fn line_power_marks_code_the_scan_did_not_run() {
    use servoscope_core::machine::LinePower;
    let mut m = plc("STR X0\nGOTO K1\nSTR SP1\nOUT Y0\nLBL K1\nSTR SP1\nOUT Y1\nEND");
    set(&mut m, "X0", 1);
    scan(&mut m);
    let power = m.line_power();
    let at = |line: usize| power.iter().find(|(l, _)| *l == line).map(|(_, s)| *s);
    assert_eq!(
        (at(3), at(4)),
        (Some(LinePower::NotRun), Some(LinePower::NotRun))
    );
    assert_eq!((at(2), at(7)), (Some(LinePower::On), Some(LinePower::On)));
    // Mid-scan: after the GOTO ran, the jumped-over lines are known; later ones are not yet.
    let mut m = plc("STR X0\nGOTO K1\nSTR SP1\nOUT Y0\nLBL K1\nSTR SP1\nOUT Y1\nEND");
    set(&mut m, "X0", 1);
    m.run_observed(
        servoscope_core::machine::Pos { tick: 0, step: 3 },
        |_| false,
        |_| {},
    );
    let power = m.line_power();
    let at = |line: usize| power.iter().find(|(l, _)| *l == line).map(|(_, s)| *s);
    assert_eq!((at(3), at(6)), (Some(LinePower::NotRun), None));
    let mut m = plc("STR X0\nMLS K1\nSTR SP1\nOUT Y0\nMLR K0\nSTR SP1\nOUT Y1\nEND");
    scan(&mut m);
    let power = m.line_power();
    let at = |line: usize| power.iter().find(|(l, _)| *l == line).map(|(_, s)| *s);
    assert_eq!(
        (at(4), at(7)),
        (Some(LinePower::Off), Some(LinePower::On)),
        "OUT runs: it writes 0"
    );
    let mut m = plc("ISG S0\nSTR SP1\nOUT Y0\nSG S1\nSTR SP1\nOUT Y1\nEND");
    scan(&mut m);
    let power = m.line_power();
    let at = |line: usize| power.iter().find(|(l, _)| *l == line).map(|(_, s)| *s);
    assert_eq!(
        (at(5), at(6)),
        (Some(LinePower::NotRun), Some(LinePower::NotRun))
    );
}

/// The batch mixer: fill until the high level, mix 10.0 s, drain until empty, and the
/// subroutine counts the batch once (V2000 in BCD) and adds 250 litres (V2002/V2003).
#[test]
fn the_batch_mixer_runs_a_batch_and_counts_it_once() {
    let mut m = plc(include_str!(
        "../../../../assets/examples/batch_mixer.dl205"
    ));
    let outputs = |m: &Dl205| (get(m, "Y0"), get(m, "Y1"), get(m, "Y2"));
    scan(&mut m);
    assert_eq!(outputs(&m), (0, 0, 0), "idle");
    set(&mut m, "X0", 1);
    scan(&mut m);
    set(&mut m, "X0", 0);
    assert_eq!(outputs(&m), (1, 0, 0), "filling");
    set(&mut m, "X1", 1);
    set(&mut m, "X2", 1);
    scan(&mut m);
    // The jump to S2 comes after S1: S2 runs in the same scan, and its timer counts it.
    assert_eq!(get(&m, "Y1"), 1, "mixing");
    // 10.0 s at 10 ms scans: T0 is on in the 1000th counted scan.
    for _ in 0..998 {
        scan(&mut m);
    }
    assert_eq!((get(&m, "Y1"), get(&m, "Y2")), (1, 0), "still mixing");
    scan(&mut m);
    assert_eq!(get(&m, "Y2"), 1, "draining");
    set(&mut m, "X1", 0);
    for _ in 0..5 {
        scan(&mut m);
    }
    set(&mut m, "X2", 0);
    for _ in 0..5 {
        scan(&mut m);
    }
    assert_eq!(outputs(&m), (0, 0, 0), "back to idle");
    assert_eq!(
        (get(&m, "V2000"), get(&m, "V2002")),
        (0x1, 0x250),
        "one batch, 250 litres"
    );
}

/// Issue #23 item 4: the code view's notes: a FOR loop's turn, the call a subroutine runs in,
/// and the edge contacts that fired this scan.
#[test]
fn line_notes_tell_the_turn_the_call_and_the_edges() {
    let src = "STRPD X0\nOUT Y0\nSTR SP1\nFOR K3\nSTR SP1\nGTS K1\nNEXT\nEND\nSBR K1\nSTR SP1\nINCB V0\nRT\n";
    let mut m = plc(src);
    set(&mut m, "X0", 1);
    // STRPD, OUT, STR, FOR, STR, GTS, SBR: inside the first turn's call.
    m.run_observed(
        servoscope_core::machine::Pos { tick: 0, step: 7 },
        |_| false,
        |_| {},
    );
    let notes = m.line_notes();
    assert!(notes.contains(&(4, "turn 1 of 3".to_string())), "{notes:?}");
    assert!(
        notes.contains(&(9, "called from line 6 (depth 1)".to_string())),
        "{notes:?}"
    );
    assert!(notes.contains(&(1, "fired".to_string())), "{notes:?}");
    // Two turns later.
    m.run_observed(
        servoscope_core::machine::Pos {
            tick: 0,
            step: 7 + 2 * 6,
        },
        |_| false,
        |_| {},
    );
    assert!(
        m.line_notes().contains(&(4, "turn 3 of 3".to_string())),
        "{:?}",
        m.line_notes()
    );
}
