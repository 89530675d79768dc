//! The PLCs' fast loops are their executors, faster: for random OpenNet and DL205 programs, a
//! machine run in the fast loop ends exactly where and as the executor leaves it, and a
//! timeline recorded through the quiet loop holds exactly what one recorded scan by scan holds
//! (trace, positions, checkpoints, "who wrote this?"), input switches and edits included.

use crate::common;

use common::agree::{fast_is_full, quiet_is_observed};
use proptest::prelude::*;
use servoscope_core::debugger::history::{Change, UserEvent};
use servoscope_core::machine::{Loc, MachineView, Pos};

/// `src` assembled by `open` (a program the generator got wrong is skipped, not failed), then
/// `check`ed; a failure names the program.
fn with_program<M>(
    src: &str,
    open: fn(&str) -> Option<M>,
    check: impl FnOnce(M) -> Result<(), TestCaseError>,
) -> Result<(), TestCaseError> {
    let start = open(src);
    prop_assume!(start.is_some());
    let Some(start) = start else { return Ok(()) };
    check(start).map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))
}

/// Input switches flipped and registers edited at these scans.
fn events(
    inputs: &'static [&'static str],
    registers: &'static [&'static str],
) -> impl Strategy<Value = Vec<(u64, String, u64)>> {
    prop::collection::vec(
        (
            0u64..3_000,
            prop::sample::select(inputs.iter().chain(registers).copied().collect::<Vec<_>>()),
            0u64..70_000,
        )
            .prop_map(|(tick, name, value)| (tick, name.to_string(), value)),
        0..6,
    )
}

fn user_events(m: &dyn MachineView, raw: &[(u64, String, u64)]) -> Vec<UserEvent> {
    raw.iter()
        .map(|(tick, name, value)| {
            let loc: Loc = m.find(name).expect("a location of the dialect");
            let width = m.info(loc).map_or(1, |i| i.width);
            UserEvent {
                at: Pos::at_tick(*tick),
                loc,
                change: Change::Set(value & ((1u64 << width) - 1)),
            }
        })
        .collect()
}

// ---------------------------------------------------------------------------------------
// OpenNet

fn on_bit() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "I0", "I1", "I2", "Q0", "Q1", "M0", "M1", "M2", "M8003", "M8004", "M8120", "M8121", "M8122",
    ])
}

fn on_out_bit() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec!["Q0", "Q1", "M0", "M1", "M2", "M8003"])
}

/// A source of type `ty`: a register (repeated or not), a constant, or bit points as a word.
fn on_source(rep: bool) -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (0u32..8, any::<bool>()).prop_map(move |(n, r)| format!("D{n}{}", if r && rep { "(R)" } else { "" })),
        2 => (0u32..32_000).prop_map(|v| v.to_string()),
        1 => Just("M10".to_string()),
        1 => Just("I0".to_string()),
    ]
}

fn on_dest(rep: bool) -> impl Strategy<Value = String> {
    prop_oneof![
        5 => (0u32..10, any::<bool>()).prop_map(move |(n, r)| format!("D{n}{}", if r && rep { "(R)" } else { "" })),
        1 => Just("M10".to_string()),
        1 => Just("Q0".to_string()),
    ]
}

fn on_output() -> impl Strategy<Value = String> {
    let ty = prop::sample::select(vec!["W", "I", "D", "L"]);
    // REP n with (R) operands, or neither.
    let rep = prop::option::weighted(0.3, 1u8..4);
    let arith = (
        prop::sample::select(vec!["ADD", "SUB", "MUL", "DIV"]),
        ty.clone(),
        rep.clone(),
    )
        .prop_flat_map(|(op, t, r)| {
            let on = r.is_some();
            (
                Just(op),
                Just(t),
                on_source(on),
                on_source(on),
                on_dest(on),
                Just(r),
            )
        })
        .prop_map(|(op, t, a, b, d, r)| {
            let r = r.map_or(String::new(), |n| format!(" REP {n}"));
            format!("{op}({t}) {a} {b} {d}{r}")
        });
    let mov = (ty, rep)
        .prop_flat_map(|(t, r)| {
            (
                Just(t),
                on_source(r.is_some()),
                on_dest(r.is_some()),
                Just(r),
            )
        })
        .prop_map(|(t, s, d, r)| {
            let r = r.map_or(String::new(), |n| format!(" REP {n}"));
            format!("MOV({t}) {s} {d}{r}")
        });
    prop_oneof![
        2 => (prop::sample::select(vec!["OUT", "OUTN", "SET", "RST"]), on_out_bit())
            .prop_map(|(op, b)| format!("{op} {b}")),
        4 => arith,
        2 => mov,
        1 => (prop::sample::select(vec!["INC", "DEC"]), prop::sample::select(vec!["W", "D"]), 0u32..8)
            .prop_map(|(op, t, n)| format!("{op}({t}) D{n}")),
    ]
}

/// One rung: a condition with blocks or an edge, then outputs (some under a branch).
fn on_rung() -> impl Strategy<Value = String> {
    let term = (
        prop::sample::select(vec!["AND", "ANDN", "OR", "ORN"]),
        on_bit(),
    )
        .prop_map(|(op, b)| format!("{op} {b}\n"));
    let block = (
        prop::sample::select(vec!["LOD", "LODN"]),
        on_bit(),
        prop::sample::select(vec!["ANDLOD", "ORLOD"]),
    )
        .prop_map(|(op, b, join)| format!("{op} {b}\n{join}\n"));
    let condition = prop::collection::vec(prop_oneof![3 => term, 1 => block], 0..3);
    let edge = prop::sample::select(vec!["", "SOTU\n", "SOTD\n"]);
    (
        prop::sample::select(vec!["LOD", "LODN"]),
        on_bit(),
        condition,
        edge,
        prop::collection::vec(on_output(), 1..3),
        prop::option::of((on_bit(), on_output(), on_output())),
    )
        .prop_map(|(op, b, condition, edge, outputs, branch)| {
            let mut text = format!("{op} {b}\n{}{edge}", condition.concat());
            match branch {
                Some((b, first, second)) => {
                    text.push_str(&format!("BPS\n{first}\nBRD\nAND {b}\n{second}\nBPP\n"));
                    for o in outputs {
                        text.push_str(&format!("{o}\n"));
                    }
                }
                None => {
                    for o in outputs {
                        text.push_str(&format!("{o}\n"));
                    }
                }
            }
            text
        })
}

fn on_program() -> impl Strategy<Value = String> {
    (prop::collection::vec(on_rung(), 1..6), any::<bool>())
        .prop_map(|(rungs, end)| rungs.concat() + if end { "END\n" } else { "" })
}

fn opennet(src: &str) -> Option<servoscope_core::machine::opennet::OpenNet> {
    servoscope_core::machine::opennet::dialect::machine(src).ok()
}

// OpenNet's control instructions (spec §5.8–§5.12): timers, counters, shift registers,
// compare contacts, CMP, word logic, shifts, conversions, MCS areas and jumps. `T#`/`C#` are
// numbered in program order (a number has one instruction).

fn ctl_bit() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "I0", "I1", "Q0", "M0", "M1", "M8121", "M8122", "M8123", "M8125", "T0", "T1", "C0", "C1",
        "R0", "R3",
    ])
}

fn ctl_output() -> impl Strategy<Value = String> {
    prop_oneof![
        2 => (prop::sample::select(vec!["OUT", "OUTN", "SET", "RST"]), prop::sample::select(vec!["Q0", "M0", "M1", "R2"]))
            .prop_map(|(op, b)| format!("{op} {b}")),
        3 => (prop::sample::select(vec!["TML", "TIM", "TMH", "TMS"]), prop_oneof![(0u32..40).prop_map(|p| p.to_string()), Just("D6".to_string())])
            .prop_map(|(op, p)| format!("{op} T# {p}")),
        2 => (prop::sample::select(vec!["CMP=", "CMP<>", "CMP<", "CMP>=", "ICMP>="]), prop::sample::select(vec!["W", "I", "D", "L"]), 0u32..4, 0u32..300, prop::option::of(1u8..4))
            .prop_map(|(op, t, d, v, rep)| {
                let third = if op == "ICMP>=" { " 7" } else { "" };
                match rep {
                    Some(n) => format!("{op}({t}) D{d}(R) {v}{third} M10(R) REP {n}"),
                    None => format!("{op}({t}) D{d} {v}{third} M10"),
                }
            }),
        1 => (prop::sample::select(vec!["ANDW", "ORW", "XORW"]), prop::sample::select(vec!["W", "D"]))
            .prop_map(|(op, t)| format!("{op}({t}) D1 D2 D3")),
        1 => (prop::sample::select(vec!["SFTL", "SFTR"]), prop::sample::select(vec![("W", "D2"), ("D", "D2"), ("W", "R0")]), 1u8..8)
            .prop_map(|(op, (t, x), n)| format!("{op}({t}) {x} {n}")),
        1 => (prop::sample::select(vec!["HTOB", "BTOH"]), prop::sample::select(vec!["W", "D"]))
            .prop_map(|(op, t)| format!("{op}({t}) D0 D4")),
        1 => Just("MOV(W) C1 D5".to_string()),
        1 => Just("MOV(W) D5 T1".to_string()),
        1 => Just("ADD(W) C0(R) D1 D1 REP 2".to_string()),
        2 => prop::sample::select(vec!["INC(W) D0", "DEC(W) D6", "ADD(W) D0 1 D1"]).prop_map(String::from),
    ]
}

fn ctl_start() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (prop::sample::select(vec!["LOD", "LODN"]), ctl_bit()).prop_map(|(op, b)| format!("{op} {b}")),
        1 => (prop::sample::select(vec!["CC=", "CC>="]), 0u32..2, 0u32..5).prop_map(|(op, c, v)| format!("{op} C{c} {v}")),
        1 => (prop::sample::select(vec!["DC=", "DC>="]), 0u32..3, 0u32..50).prop_map(|(op, d, v)| format!("{op} D{d} {v}")),
    ]
}

fn ctl_rung() -> impl Strategy<Value = String> {
    let plain = (
        ctl_start(),
        prop::collection::vec(
            (
                prop::sample::select(vec!["AND", "ANDN", "OR", "ORN"]),
                ctl_bit(),
            ),
            0..2,
        ),
        prop::sample::select(vec!["", "SOTU\n", "SOTD\n"]),
        prop::collection::vec(ctl_output(), 1..3),
    )
        .prop_map(|(start, terms, edge, outputs)| {
            let terms: String = terms.iter().map(|(op, b)| format!("{op} {b}\n")).collect();
            format!("{start}\n{terms}{edge}{}\n", outputs.join("\n"))
        });
    let counter = (
        prop::sample::select(vec!["CNT", "CDP", "CUD", "SFR", "SFRN"]),
        ctl_start(),
        ctl_bit(),
        ctl_bit(),
        prop_oneof![
            (0u32..6).prop_map(|p| p.to_string()),
            Just("D2".to_string())
        ],
    )
        .prop_map(|(op, first, b, c, p)| {
            let third = if op == "CNT" {
                String::new()
            } else {
                format!("LOD {c}\n")
            };
            match op {
                "SFR" | "SFRN" => format!("{first}\nLOD {b}\n{third}{op} R0 6\n"),
                _ => format!("{first}\nLOD {b}\n{third}{op} C# {p}\n"),
            }
        });
    prop_oneof![3 => plain, 2 => counter]
}

/// Rungs, some inside an MCS area or after a JMP.
fn ctl_program() -> impl Strategy<Value = String> {
    let group = (
        prop::sample::select(vec!["", "MCS", "JMP"]),
        ctl_bit(),
        prop::collection::vec(ctl_rung(), 1..4),
    )
        .prop_map(|(area, b, rungs)| match area {
            "" => rungs.concat(),
            "MCS" => format!("LOD {b}\nMCS\n{}MCR\n", rungs.concat()),
            _ => format!("LOD {b}\nJMP\n{}JEND\n", rungs.concat()),
        });
    (prop::collection::vec(group, 1..5), any::<bool>()).prop_map(|(groups, end)| {
        let mut text = groups.concat() + if end { "END\n" } else { "" };
        for letter in ["T", "C"] {
            let mut n = 0;
            while let Some(at) = text.find(&format!("{letter}#")) {
                text.replace_range(at..at + 2, &format!("{letter}{n}"));
                n += 1;
            }
        }
        text
    })
}

/// OpenNet at a scan time other than the default.
fn opennet_at(scan_ms: u32) -> impl Fn(&str) -> Option<servoscope_core::machine::opennet::OpenNet> {
    move |src| {
        let program = servoscope_core::machine::opennet::assembler::assemble(src).ok()?;
        Some(servoscope_core::machine::opennet::OpenNet::with_time(
            std::sync::Arc::new(program),
            servoscope_core::machine::plc::TimeBase { scan_ms },
        ))
    }
}

// ---------------------------------------------------------------------------------------
// DL205

fn dl_contact_bit() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "X0", "X1", "Y0", "C0", "C1", "SP0", "SP1", "SP63", "SP66", "SP75", "T1", "CT2", "S0",
        "SP4", "SP5", "SP7", "SP61",
    ])
}

/// A contact: a bit, or a comparison of a V word with a V word or a constant.
fn dl_contact(kind: &'static str) -> impl Strategy<Value = String> {
    let compare = (
        prop::sample::select(vec!["E", "NE", "", "N"]),
        prop::sample::select(vec!["V0", "V1", "V2"]),
        prop::sample::select(vec!["V3", "K0", "K5", "K1234"]),
    );
    prop_oneof![
        3 => (prop::sample::select(vec!["", "N"]), dl_contact_bit())
            .prop_map(move |(n, b)| format!("{kind}{n} {b}")),
        1 => compare.prop_map(move |(c, a, b)| format!("{kind}{c} {a} {b}")),
        1 => (prop::sample::select(vec!["PD", "ND"]), dl_contact_bit())
            .prop_map(move |(e, b)| format!("{kind}{e} {b}")),
    ]
}

fn dl_output() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => prop::sample::select(vec![
            "OUT Y0", "OUT C0", "OUT C1", "SET C2", "RST C2", "SET Y1 Y3", "RST Y0 Y1",
            "PD C3", "PD Y2", "OROUT Y4", "OROUT C1", "OUT S0", "SET S1", "RST S0 S1", "RST T1",
            "RST CT2", "RST T0 T3",
        ]).prop_map(str::to_string),
        2 => prop::sample::select(vec![
            "CMP V0", "CMP K1234", "CMPD V2", "CMPD K5", "INV", "LD VX0", "OUT VY0", "LDD VSP0",
            "OUT VC0", "MOV V200", "SETBIT O5", "RSTBIT O21",
        ]).prop_map(str::to_string),
        2 => (prop::sample::select(vec!["TMR", "TMRF", "SGCNT"]), 0u32..12, prop::sample::select(vec!["K3", "K0", "V0", "K9999"]))
            .prop_map(|(m, n, p)| {
                let t = if m == "SGCNT" { "CT" } else { "T" };
                format!("{m} {t}{n:o} {p}")
            }),
        6 => prop::sample::select(vec![
            "LD V0", "LD K1234", "LD K12", "LDD V2", "LDD K12345678", "LDA O17", "LDF X0 K8",
            "OUT V4", "OUT V0", "OUTD V2", "OUTD V6", "OUTF C10 K4", "POP",
        ]).prop_map(str::to_string),
        6 => prop::sample::select(vec![
            "ADD V0", "SUB V1", "ADDD K1", "SUBD V2", "ADDS", "SUBS", "MUL K3", "MULS", "MULD V2",
            "DIV K7", "DIV V1", "DIVD V2", "DIVS", "ADDB K5", "ADDBD V2", "ADDBS", "SUBB K5",
            "SUBBD V2", "SUBBS", "MULB K3", "MULBS", "DIVB K3", "DIVB V1", "DIVBS", "INCB V0",
            "DECB V1", "BIN", "BCD", "ANDD K00FF", "ORD V2", "XORS", "SHFL K2", "SHFR V0",
        ]).prop_map(str::to_string),
    ]
}

fn dl_rung() -> impl Strategy<Value = String> {
    let term = prop_oneof![
        3 => dl_contact("AND"),
        2 => dl_contact("OR"),
        1 => (dl_contact("STR"), prop::sample::select(vec!["ANDSTR", "ORSTR"]))
            .prop_map(|(c, join)| format!("{c}\n{join}")),
    ];
    (
        dl_contact("STR"),
        prop::collection::vec(term, 0..3),
        prop::collection::vec(dl_output(), 1..5),
    )
        .prop_map(|(first, terms, outputs)| {
            let mut text = format!("{first}\n");
            for t in terms.iter().chain(&outputs) {
                text.push_str(t);
                text.push('\n');
            }
            text
        })
}

/// A multi-input box: each leg its own STR (spec §2), the box alone at the end of its rung.
fn dl_box_rung() -> impl Strategy<Value = String> {
    (
        prop::sample::select(vec![("TMRA", 2), ("TMRAF", 2), ("CNT", 2), ("UDC", 3)]),
        prop::collection::vec(dl_contact("STR"), 3),
        0u32..6,
        prop::sample::select(vec!["K3", "K0", "K30", "V2"]),
    )
        .prop_map(|((m, legs), contacts, n, preset)| {
            let (t, n) = match m {
                "CNT" => ("CT", 20 + n),
                "UDC" => ("CT", 40 + 2 * n),
                _ => ("T", 20 + 2 * n),
            };
            let preset = if preset == "V2" && m == "CNT" {
                "V0"
            } else {
                preset
            };
            format!("{}\n{m} {t}{n:o} {preset}\n", contacts[..legs].join("\n"))
        })
}

fn dl_program() -> impl Strategy<Value = String> {
    prop::collection::vec(prop_oneof![4 => dl_rung(), 1 => dl_box_rung()], 1..6)
        .prop_map(|rungs| rungs.concat() + "END\n")
}

/// A program with every kind of program control around random rungs: a GOTO over a rung, a
/// FOR loop, a master-line zone, a subroutine call and two stages.
fn dl_flow_program() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(dl_rung(), 1..3),
        prop::collection::vec(dl_rung(), 6),
        prop::collection::vec(any::<bool>(), 5),
        1u32..4,
    )
        .prop_map(|(head, body, on, turns)| {
            let mut text = head.concat();
            if on[0] {
                text += &format!("STR X0\nGOTO K1\n{}LBL K1\n", body[0]);
            }
            if on[1] {
                text += &format!("STR X1\nFOR K{turns}\n{}NEXT\n", body[1]);
            }
            if on[2] {
                text += &format!("STR X0\nMLS K1\n{}MLR K0\n", body[2]);
            }
            if on[3] {
                text += "STR SP1\nGTS K1\n";
            }
            if on[4] {
                text += &format!(
                    "ISG S0\n{}STR X0\nJMP S1\nSG S1\n{}STR X1\nNJMP S0\n",
                    body[3], body[4]
                );
            }
            text += "END\n";
            if on[3] {
                text += &format!("SBR K1\n{}RT\n", body[5]);
            }
            text
        })
}

fn dl205(src: &str) -> Option<servoscope_core::machine::dl205::Dl205> {
    servoscope_core::machine::dl205::dialect::machine(src).ok()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn the_opennet_fast_loop_leaves_the_plc_as_the_executor(
        src in on_program(),
        legs in prop::collection::vec((0u64..30, 0u32..12), 1..20),
    ) {
        with_program(&src, opennet, |start| fast_is_full(start, &legs))?;
    }

    #[test]
    fn the_opennet_fast_loop_runs_timers_counters_mcs_and_jumps_as_the_executor(
        src in ctl_program(),
        scan_ms in prop::sample::select(vec![1u32, 7, 10, 33, 250]),
        legs in prop::collection::vec((0u64..60, 0u32..30), 1..20),
    ) {
        let open = opennet_at(scan_ms);
        let start = open(&src);
        prop_assert!(start.is_some(), "the generator writes valid programs:\n{src}");
        if let Some(start) = start {
            fast_is_full(start, &legs).map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))?;
        }
    }

    #[test]
    fn the_dl205_fast_loop_leaves_the_plc_as_the_executor(
        src in dl_program(),
        legs in prop::collection::vec((0u64..30, 0u32..12), 1..20),
    ) {
        with_program(&src, dl205, |start| fast_is_full(start, &legs))?;
    }

    #[test]
    fn the_dl205_fast_loop_follows_jumps_loops_calls_and_stages(
        src in dl_flow_program(),
        legs in prop::collection::vec((0u64..30, 0u32..40), 1..20),
    ) {
        with_program(&src, dl205, |start| fast_is_full(start, &legs))?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn a_quiet_opennet_recording_is_the_observed_recording(
        src in on_program(),
        raw in events(&["I0", "I1", "I2"], &["D0", "D3", "D9"]),
        plotted in prop::collection::vec(prop::sample::select(vec!["D0", "D1", "D4", "Q0", "M8003", "M10"]), 1..3),
        ticks in 1u64..20_000,
        step in 0u32..8,
    ) {
        let written = ["D0", "D1", "D2", "D5", "D9", "Q0", "M0", "M10", "M8003", "M8004"];
        let legs = (Pos { tick: ticks / 3, step }, Pos::at_tick(ticks));
        with_program(&src, opennet, |start| {
            let events = user_events(&start, &raw);
            quiet_is_observed(start, events, &plotted, &written, legs)
        })?;
    }

    #[test]
    fn a_quiet_opennet_recording_with_timers_and_jumps_is_the_observed_recording(
        src in ctl_program(),
        raw in events(&["I0", "I1"], &["D0", "D2", "D6", "T0.preset", "C1.current"]),
        plotted in prop::collection::vec(prop::sample::select(vec!["D0", "T0.current", "C0.current", "Q0", "R0", "M10"]), 1..3),
        ticks in 1u64..20_000,
        step in 0u32..8,
    ) {
        let written = ["D0", "D1", "D4", "Q0", "M0", "M10", "R0", "T0.current", "T1.preset", "C0.current", "C0", "M8003", "M8004"];
        let legs = (Pos { tick: ticks / 3, step }, Pos::at_tick(ticks));
        let start = opennet(&src);
        prop_assert!(start.is_some(), "the generator writes valid programs:\n{src}");
        if let Some(start) = start {
            let events = user_events(&start, &raw);
            quiet_is_observed(start, events, &plotted, &written, legs)
                .map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))?;
        }
    }

    #[test]
    fn a_quiet_dl205_recording_is_the_observed_recording(
        src in dl_program(),
        raw in events(&["X0", "X1"], &["V0", "V1", "V2"]),
        plotted in prop::collection::vec(prop::sample::select(vec!["ACC", "V0", "V4", "Y0", "C2", "SP66"]), 1..3),
        ticks in 1u64..20_000,
        step in 0u32..8,
    ) {
        let written = ["ACC", "L1", "V0", "V1", "V2", "V4", "V7", "Y0", "Y2", "C0", "C2", "C12"];
        let legs = (Pos { tick: ticks / 3, step }, Pos::at_tick(ticks));
        with_program(&src, dl205, |start| {
            let events = user_events(&start, &raw);
            quiet_is_observed(start, events, &plotted, &written, legs)
        })?;
    }
}
