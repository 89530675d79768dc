//! The fast paths are the slow ones, faster: SilverLode's pre-decoded loop leaves the machine
//! exactly as the full executor does tick by tick, and a timeline recorded through the quiet
//! loop holds exactly what one recorded tick by tick holds (trace, positions, checkpoints,
//! "who wrote this?"), for random programs mixing plain commands with jumps, waits, moves,
//! faults and edits.

use crate::common;

use std::sync::Arc;

use common::agree::{fast_is_full, quiet_is_observed};
use common::channel_named;
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use servoscope_core::debugger::history::{Change, Timeline, UserEvent};
use servoscope_core::debugger::trace::Channel;
use servoscope_core::machine::silverlode::program::{ClcOp, ExtOp};
use servoscope_core::machine::silverlode::{SilverLode, assemble, view::reg};
use servoscope_core::machine::{Machine, MachineView, Pos};

const REGS: &[u8] = &[0, 1, 6, 10, 20, 21, 22, 23];

fn register() -> impl Strategy<Value = u8> {
    prop::sample::select(REGS)
}

fn data() -> impl Strategy<Value = i32> {
    prop_oneof![
        -3i32..4,
        any::<i32>(),
        // Register numbers for COPY_REF/SAVE_REF, a queue's slots, Q_READ's reach.
        prop::sample::select(vec![20, 21, 41, 199, 200, -4]),
        prop::sample::select(vec![i32::MIN, i32::MAX, 0x7FFF_FFFF, 65536, 98304]),
    ]
}

/// The queue every program sets up first: four slots at R40.
const QUEUE: &str = "CLD Q_INIT, 11, 40, 4\n";

/// A jump's condition, or none.
fn condition() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "",
        ", ZERO",
        ", !ZERO",
        ", NEGATIVE",
        ", !POSITIVE",
        ", IO1",
    ])
}

/// One line of a program with `lines` lines (jump targets are line labels): every command
/// the fast loop runs, and some it hands over.
fn line(lines: usize) -> impl Strategy<Value = String> {
    let ext = prop::sample::select(
        ExtOp::NAMES
            .iter()
            .copied()
            .filter(|n| *n != "Q_INIT")
            .collect::<Vec<_>>(),
    );
    let clc = prop::sample::select(ClcOp::NAMES.to_vec());
    let cond = condition();
    let queue_op = prop::sample::select(vec![
        "Q_PUSH_HEAD",
        "Q_POP_HEAD",
        "Q_PUSH_TAIL",
        "Q_POP_TAIL",
        "Q_READ",
        "Q_PUSH_TAIL_ERR",
        "Q_POP_HEAD_ERR",
    ]);
    // Mostly the queue at R40, sometimes a register that holds no queue.
    let base = prop_oneof![4 => Just(40u8), 1 => register()];
    prop_oneof![
        6 => (ext.clone(), register(), register(), data())
            .prop_map(|(op, r, a, d)| format!("CLD {op}, {r}, {a}, {d}")),
        4 => (ext, register(), register(), register())
            .prop_map(|(op, r, a, b)| format!("CLX {op}, {r}, {a}, {b}")),
        3 => (queue_op, register(), base, data())
            .prop_map(|(op, r, b, d)| format!("CLD {op}, {r}, {b}, {d}")),
        6 => (clc, register()).prop_map(|(op, r)| format!("CLC {op}, {r}")),
        4 => (0..lines, cond).prop_map(|(t, c)| format!("JMP l{t}{c}")),
        1 => (0..lines).prop_map(|t| format!("CALL l{t}")),
        1 => Just("RET".to_string()),
        1 => (0..lines).prop_map(|t| format!("CER l{t}")),
        1 => (register(), data()).prop_map(|(r, v)| format!("WRP {r}, {v}")),
        1 => (1u32..5).prop_map(|n| format!("DLY {n}")),
        1 => (-300i32..300).prop_map(|d| format!("MRV {d}, 3865, 67108864")),
        1 => Just("WBS IO1".to_string()),
    ]
}

fn program() -> impl Strategy<Value = String> {
    (2usize..14)
        .prop_flat_map(|n| (prop::collection::vec(line(n), n), any::<bool>()))
        .prop_map(|(lines, handled)| {
            let mut text = String::from(QUEUE);
            // Most generated programs fault soon; a handler keeps half of them running past
            // their faults, so long runs go through the fast loop's hand-overs.
            if handled {
                text.push_str("CER l0\n");
            }
            text.extend(
                lines
                    .iter()
                    .enumerate()
                    .map(|(i, l)| format!("l{i}: {l}\n")),
            );
            // Round and round, so runs last to their tick limits.
            text.push_str("JMP l0\n");
            text
        })
}

fn machine(src: &str) -> SilverLode {
    SilverLode::new(Arc::new(
        assemble(src).expect("generated programs assemble"),
    ))
}

fn channel(index: u32) -> Channel {
    Channel {
        loc: reg(index),
        name: format!("R{index}"),
        label: format!("R{index}"),
        width: 32,
        signed: true,
        reading: servoscope_core::machine::Format::Signed,
        group: 0,
        expr: None,
    }
}

/// Input switches and register edits at these ticks.
fn events() -> impl Strategy<Value = Vec<UserEvent>> {
    prop::collection::vec((0u64..3000, any::<bool>(), register(), data()), 0..6).prop_map(|v| {
        v.into_iter()
            .map(|(tick, input, r, value)| UserEvent {
                at: Pos::at_tick(tick),
                loc: if input {
                    servoscope_core::machine::silverlode::view::io(0)
                } else {
                    reg(u32::from(r))
                },
                change: if input {
                    Change::Set(u64::from(tick % 2 == 0))
                } else {
                    Change::Set(u64::from(value as u32))
                },
            })
            .collect()
    })
}

/// `src` run to increasing ticks (`legs` apart) in the fast loop and by the full executor:
/// the same reason to stop and the same machine after each leg.
fn fast_and_full_agree(src: &str, legs: &[u64]) -> Result<(), TestCaseError> {
    let legs: Vec<(u64, u32)> = legs.iter().map(|&ticks| (ticks, 0)).collect();
    fast_is_full(machine(src), &legs).map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))
}

/// `src` recorded through the quiet loop and tick by tick, to `ticks` in two legs (so the
/// second begins where a quiet stretch may have ended): the same recording, last writes of
/// `regs` and machine after going back.
fn recordings_agree(
    src: &str,
    events: Vec<UserEvent>,
    plotted: &[u32],
    ticks: u64,
    regs: &[u8],
) -> Result<(), TestCaseError> {
    let plotted: Vec<String> = plotted.iter().map(|r| format!("R{r}")).collect();
    let plotted: Vec<&str> = plotted.iter().map(String::as_str).collect();
    let written: Vec<String> = regs.iter().map(|r| format!("R{r}")).collect();
    let written: Vec<&str> = written.iter().map(String::as_str).collect();
    let legs = (Pos::at_tick(ticks / 3), Pos::at_tick(ticks));
    quiet_is_observed(machine(src), events, &plotted, &written, legs)
        .map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))
}

/// Run to `ticks` with one data breakpoint on `r` and a line breakpoint on `line`, through the
/// quiet loop and the observed path: the same stops, machine and trace.
fn data_stops_agree(
    src: &str,
    breakpoint: servoscope_core::debugger::Breakpoint,
    plotted: &[u32],
    line: usize,
    ticks: u64,
) -> Result<(), TestCaseError> {
    let start = machine(src);
    let channels: Vec<Channel> = plotted.iter().map(|&r| channel(r)).collect();
    let mut quiet = Timeline::new(start.clone(), Vec::new(), channels.clone());
    let mut observed = Timeline::new(start, Vec::new(), channels);
    let end = Pos::at_tick(ticks);
    prop_assert_eq!(
        data_stops(&mut quiet, true, &breakpoint, line, end),
        data_stops(&mut observed, false, &breakpoint, line, end),
        "{}",
        src
    );
    prop_assert_eq!(&quiet.machine, &observed.machine);
    prop_assert!(quiet.trace.samples().eq(observed.trace.samples()));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn the_fast_loop_leaves_the_machine_as_the_full_executor(
        src in program(),
        legs in prop::collection::vec(0u64..200, 1..30),
    ) {
        fast_and_full_agree(&src, &legs)?;
    }

    #[test]
    fn a_compiled_loop_leaves_the_machine_as_the_full_executor(
        src in loop_program(),
        legs in prop::collection::vec(0u64..5000, 1..12),
    ) {
        fast_and_full_agree(&src, &legs)?;
    }

    #[test]
    fn a_quiet_recording_is_the_observed_recording(
        src in program(),
        events in events(),
        plotted in prop::collection::vec(prop::sample::select(vec![0u32, 1, 6, 21, 22]), 1..4),
        ticks in 1u64..40_000,
    ) {
        recordings_agree(&src, events, &plotted, ticks, REGS)?;
    }
}

#[test]
fn a_write_that_ends_at_a_checkpoint_is_found_from_either_recording() {
    // Around the first checkpoint (tick 16,384): the only write of R23 ends at its boundary.
    for rounds in 8_185u64..8_196 {
        // WRP in tick 0, two ticks a round, the add in tick 2 × rounds + 1.
        let src = format!(
            "WRP 20, {rounds}\nl1: CLD SUB, 20, 20, 1\nJMP l1, !ZERO\nCLD ADD, 23, 23, 5\nspin: JMP spin\n"
        );
        let start = machine(&src);
        let mut quiet = Timeline::new(start.clone(), Vec::new(), vec![channel(0)]);
        let mut observed = Timeline::new(start, Vec::new(), vec![channel(0)]);
        quiet.forward_unstopped(Pos::at_tick(40_000));
        observed.forward(Pos::at_tick(40_000), |_| false);
        let before = Pos::at_tick(30_000);
        let found = quiet.find_write_back(before, reg(23));
        assert_eq!(
            found,
            observed.find_write_back(before, reg(23)),
            "{rounds} rounds"
        );
        assert_eq!(found, Some(Pos::at_tick(2 * rounds + 2)), "{rounds} rounds");
    }
}

/// One TML statement of a program with `lines` labelled lines: 16-bit `i`, `j`; 32-bit `l`,
/// `m` and the fixed `f`, mixed only where TML allows it.
fn tml_line(lines: usize) -> impl Strategy<Value = String> {
    let any = prop::sample::select(vec!["i", "j", "l", "m", "f"]);
    let short = prop::sample::select(vec!["i", "j"]);
    let long = prop::sample::select(vec!["l", "m", "f"]);
    let add = prop::sample::select(vec!["+=", "-="]);
    let cond = prop::sample::select(vec!["EQ", "NEQ", "LT", "LEQ", "GT", "GEQ"]);
    prop_oneof![
        2 => (short.clone(), -32_768i64..32_767).prop_map(|(v, n)| format!("{v} = {n};")),
        2 => (long.clone(), -32_768i64..32_767).prop_map(|(v, n)| format!("{v} = {n};")),
        2 => (short.clone(), short.clone()).prop_map(|(a, b)| format!("{a} = {b};")),
        2 => (long.clone(), long.clone()).prop_map(|(a, b)| format!("{a} = {b};")),
        3 => (short.clone(), add.clone(), -3_000i64..3_000)
            .prop_map(|(v, op, n)| format!("{v} {op} {n};")),
        3 => (long.clone(), add.clone(), -32_768i64..32_767)
            .prop_map(|(v, op, n)| format!("{v} {op} {n};")),
        2 => (short.clone(), add.clone(), short.clone())
            .prop_map(|(a, op, b)| format!("{a} {op} {b};")),
        3 => (long.clone(), add, any.clone()).prop_map(|(a, op, b)| format!("{a} {op} {b};")),
        2 => (any.clone(), prop::sample::select(vec!["<<=", ">>="]), 0u8..16)
            .prop_map(|(v, op, n)| format!("{v} {op} {n};")),
        2 => (any.clone(), short.clone(), prop::sample::select(vec!["<<", ">>"]), 0u8..12)
            .prop_map(|(a, b, op, n)| format!("{a} * {b} {op} {n};")),
        1 => long.clone().prop_map(|v| format!("{v} = PRODH;")),
        2 => (short.clone(), short.clone()).prop_map(|(a, b)| format!("{a} = -{b};")),
        1 => (long.clone(), long.clone()).prop_map(|(a, b)| format!("{a} = -{b};")),
        2 => (any.clone(), prop::sample::select(vec!["<<", ">>"]), 0u8..16)
            .prop_map(|(a, op, n)| format!("{a} = {a} {op} {n};")),
        1 => (prop::sample::select(vec!["<<=", ">>="]), 0u8..8)
            .prop_map(|(op, n)| format!("PROD {op} {n};")),
        1 => (short.clone(), prop::num::u16::ANY, prop::num::u16::ANY)
            .prop_map(|(v, a, o)| format!("SRB {v}, 0x{a:04X}, 0x{o:04X};")),
        1 => prop::sample::select(vec!["NOP;", "BEGIN;", "ENDINIT;"]).prop_map(str::to_string),
        1 => Just("f += 0.5;".to_string()),
        2 => (prop::sample::select(vec!["f", "l"]), short.clone()).prop_map(|(a, b)| format!("{a} /= {b};")),
        3 => (0..lines, any, cond).prop_map(|(t, v, c)| format!("GOTO l{t}, {v}, {c};")),
        1 => (0..lines).prop_map(|t| format!("GOTO l{t};")),
    ]
}

fn tml_program() -> impl Strategy<Value = String> {
    (2usize..14)
        .prop_flat_map(|n| prop::collection::vec(tml_line(n), n))
        .prop_map(|lines| {
            let mut text = String::from("int i; int j; long l; long m; fixed f;\n");
            for (i, l) in lines.iter().enumerate() {
                text.push_str(&format!("l{i}: {l}\n"));
            }
            text.push_str("GOTO l0;\n");
            text
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn the_tml_fast_loop_leaves_the_drive_as_the_full_executor(
        src in tml_program(),
        legs in prop::collection::vec((0u64..40, 0u32..10), 1..30),
    ) {
        let start = servoscope_core::machine::tml::dialect::machine(&src);
        // The generator keeps to TML's width rules; a form it gets wrong is skipped, not failed.
        prop_assume!(start.is_ok());
        let Ok(start) = start else { return Ok(()) };
        let mut fast = start.clone();
        let mut full = start;
        let mut tick = 0;
        for (ticks, step) in legs {
            tick += ticks;
            let to = Pos { tick, step };
            let fast_reason = fast.run_bare(to);
            let full_reason = full.run_observed(to, |_| false, |_| {});
            prop_assert_eq!(fast_reason, full_reason);
            prop_assert!(fast == full, "{} at {:?}", src, to);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn a_quiet_tml_recording_is_the_observed_recording(
        src in tml_program(),
        plotted in prop::collection::vec(prop::sample::select(vec!["TPOS", "APOS", "i", "l", "f", "PROD"]), 1..4),
        ticks in 1u64..20_000,
        step in 0u32..10,
    ) {
        let start = servoscope_core::machine::tml::dialect::machine(&src);
        prop_assume!(start.is_ok());
        let Ok(start) = start else { return Ok(()) };
        let channels: Vec<Channel> = plotted.iter().map(|n| channel_named(&start, n)).collect();
        let mut quiet = Timeline::new(start.clone(), Vec::new(), channels.clone());
        let mut observed = Timeline::new(start, Vec::new(), channels);
        // The first leg ends inside a tick, so the second begins there.
        let first = Pos { tick: ticks / 3, step };
        prop_assert_eq!(quiet.forward_unstopped(first), observed.forward(first, |_| false));
        let end = Pos::at_tick(ticks);
        prop_assert_eq!(quiet.forward_unstopped(end), observed.forward(end, |_| false));
        prop_assert!(quiet.machine == observed.machine);
        prop_assert_eq!(quiet.furthest(), observed.furthest());
        prop_assert!(quiet.trace.samples().eq(observed.trace.samples()), "{}", src);
        prop_assert_eq!(quiet.trace.end_tick(), observed.trace.end_tick());
        let furthest = quiet.furthest();
        for at in [furthest, Pos::at_tick(furthest.tick / 2), Pos::at_tick(17_000)] {
            for name in ["i", "j", "l", "m", "f", "PROD"] {
                let loc = quiet.machine.find(name).expect("declared");
                prop_assert_eq!(
                    quiet.find_write_back(at, loc),
                    observed.find_write_back(at, loc),
                    "{} before {:?}", name, at
                );
            }
            quiet.goto(at);
            observed.goto(at);
            prop_assert!(quiet.machine == observed.machine);
        }
    }
}

/// Where a run stopped, and every position at which it was asked on a breakpoint line.
type Stops = (Vec<(servoscope_core::machine::StopReason, Pos)>, Vec<Pos>);

/// Run to `end`, stopping before an instruction on `lines` whenever an odd condition holds,
/// resuming past each stop: the stops and the questions, as the quiet loop with halts or the
/// observed path saw them (a breakpoint counts its hits: it must be asked once a boundary).
fn line_stops<M: Machine>(t: &mut Timeline<M>, quiet: bool, lines: &[usize], end: Pos) -> Stops {
    let mut out = Vec::new();
    let mut asked = Vec::new();
    for _ in 0..8 {
        let start = t.machine.pos();
        let stop = |m: &M| {
            let on_line = m.pc_line().is_some_and(|l| lines.contains(&l));
            if on_line {
                asked.push(m.pos());
            }
            m.pos() != start && on_line && m.steps() % 3 != 1
        };
        let reason = if quiet {
            t.forward_lines(end, lines.to_vec(), stop)
        } else {
            t.forward(end, stop)
        };
        out.push((reason, t.machine.pos()));
        if reason != servoscope_core::machine::StopReason::Predicate {
            break;
        }
    }
    (out, asked)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn line_breakpoints_stop_the_quiet_loop_where_they_stop_the_observed_run(
        src in program(),
        tml in tml_program(),
        lines in prop::collection::vec(1usize..16, 1..3),
        ticks in 1u64..20_000,
    ) {
        let start = machine(&src);
        let channels = vec![channel(0), channel(22)];
        let mut quiet = Timeline::new(start.clone(), Vec::new(), channels.clone());
        let mut observed = Timeline::new(start, Vec::new(), channels);
        let end = Pos::at_tick(ticks);
        prop_assert_eq!(
            line_stops(&mut quiet, true, &lines, end),
            line_stops(&mut observed, false, &lines, end),
            "{}", src
        );
        prop_assert_eq!(&quiet.machine, &observed.machine);
        prop_assert!(quiet.trace.samples().eq(observed.trace.samples()));

        let start = servoscope_core::machine::tml::dialect::machine(&tml);
        prop_assume!(start.is_ok());
        let Ok(start) = start else { return Ok(()) };
        let channels = vec![channel_named(&start, "l")];
        let mut quiet = Timeline::new(start.clone(), Vec::new(), channels.clone());
        let mut observed = Timeline::new(start, Vec::new(), channels);
        let end = Pos::at_tick(ticks / 4);
        prop_assert_eq!(
            line_stops(&mut quiet, true, &lines, end),
            line_stops(&mut observed, false, &lines, end),
            "{}", tml
        );
        prop_assert!(quiet.machine == observed.machine);
        prop_assert!(quiet.trace.samples().eq(observed.trace.samples()));
    }
}

/// A counter bumped all along while the plot holds still, in every dialect: its last write
/// before tick 10,000 lies in the first checkpoint stretch, which the quiet loop recorded whole
/// (with the write sets it notes without looking at each instruction), and is found there as
/// from a recording observed tick by tick.
#[test]
fn a_write_inside_a_quiet_stretch_is_found() {
    fn last_write<M: Machine + std::fmt::Debug>(
        start: M,
        plotted: &str,
        counter: &str,
    ) -> Option<Pos> {
        let channels = vec![channel_named(&start, plotted)];
        let loc = start.find(counter).expect("a location of the dialect");
        let mut quiet = Timeline::new(start.clone(), Vec::new(), channels.clone());
        let mut observed = Timeline::new(start, Vec::new(), channels);
        quiet.forward_unstopped(Pos::at_tick(30_000));
        observed.forward(Pos::at_tick(30_000), |_| false);
        let before = Pos::at_tick(10_000);
        let found = quiet.find_write_back(before, loc);
        assert_eq!(found, observed.find_write_back(before, loc), "{counter}");
        found
    }
    // One command a tick: the add runs on even ticks and its boundary is the next tick.
    let sl = machine("l1: CLD ADD, 23, 23, 1\nJMP l1\n");
    assert_eq!(last_write(sl, "R0", "R23"), Some(Pos::at_tick(9_999)));
    // Ten statements a tick: the add is statements 0, 2, 4, 6 and 8 of each.
    let tml = servoscope_core::machine::tml::dialect::machine("int i;\nl0: i += 1;\nGOTO l0;\n")
        .expect("assembles");
    assert_eq!(
        last_write(tml, "TPOS", "i"),
        Some(Pos {
            tick: 9_999,
            step: 9
        })
    );
}

/// Run to `end` with one data breakpoint (and a line breakpoint with an odd condition),
/// resuming past each stop as the debugger does: where each stop came, through the quiet loop
/// (which halts before a write of the location) or the observed path.
fn data_stops<M: Machine>(
    t: &mut Timeline<M>,
    quiet: bool,
    breakpoint: &servoscope_core::debugger::Breakpoint,
    line: usize,
    end: Pos,
) -> Vec<(servoscope_core::machine::StopReason, Pos)> {
    use servoscope_core::debugger::breakpoints::Checker;
    let list = [
        breakpoint.clone(),
        servoscope_core::debugger::Breakpoint::line(line).with_condition("R25 % 3 != 1"),
    ];
    let checker = std::cell::RefCell::new(Checker::new(&list, &t.machine, &[usize::MAX]));
    let (lines, guarded) = checker.borrow().quiet_plan();
    let mut out = Vec::new();
    for _ in 0..8 {
        let start = t.machine.pos();
        let stop = |m: &M| m.pos() != start && checker.borrow_mut().check(m);
        let reason = if quiet {
            t.forward_quiet(end, lines.clone(), guarded.clone(), stop)
        } else {
            t.forward(end, stop)
        };
        out.push((reason, t.machine.pos()));
        if reason != servoscope_core::machine::StopReason::Predicate {
            break;
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn data_breakpoints_stop_the_quiet_loop_where_they_stop_the_observed_run(
        src in program(),
        r in prop::sample::select(vec![1u32, 6, 20, 21, 22, 23]),
        trigger in prop_oneof![
            Just(servoscope_core::debugger::DataTrigger::Write),
            Just(servoscope_core::debugger::DataTrigger::Change),
            (-3i64..40).prop_map(servoscope_core::debugger::DataTrigger::Equal),
        ],
        line in 1usize..16,
        ticks in 1u64..20_000,
    ) {
        let breakpoint = servoscope_core::debugger::Breakpoint::data(format!("R{r}"), trigger);
        data_stops_agree(&src, breakpoint, &[0, 22], line, ticks)?;
    }
}

/// Every SilverLode command that cannot fault with these operands, wait, move, end or write the
/// motion model's inputs has a form in the fast loop, so a program of them never leaves it.
#[test]
fn every_register_only_command_has_a_fast_form() {
    use servoscope_core::machine::silverlode::program::{ClcWrites, Op};
    let mut src = String::from("top: CLD Q_INIT, 11, 40, 4\n");
    // Operands that fault nowhere: R20 = 3 names a register and divides; R22 = 5, and
    // R24:R25 = 2^32 + 3 divided by 3 or 5 fits 32 bits; the queue has room for the two pushes
    // of each kind.
    let clc = ClcOp::ALL
        .iter()
        .filter(|op| op.writes() != ClcWrites::Positions);
    for op in clc {
        src.push_str(&format!("WRP 20, 3\nCLC {}, 20\n", op.name()));
    }
    src.push_str("WRP 22, 5\nWRP 24, 1\nWRP 25, 3\n");
    for op in ExtOp::ALL.iter().filter(|&&op| op != ExtOp::QInit) {
        let a = if op.is_queue() { 40 } else { 24 };
        let name = op.name();
        src.push_str(&format!(
            "CLD {name}, 30, {a}, 3\nCLX {name}, 30, {a}, 22\n"
        ));
    }
    src.push_str("CALL sub\nJMP top\nsub: RET\nJMP top\n");
    let program = assemble(&src).expect("assembles");
    let slow: Vec<String> = (1..program.instrs.len() - 1)
        .filter(|&i| program.flat[i] == Op::Full)
        .map(|i| format!("line {}: {:?}", program.lines[i], program.instrs[i]))
        .collect();
    assert!(slow.is_empty(), "left to the full executor: {slow:#?}");
    // A loop of them runs in the fast loop as the full executor runs it.
    let mut fast = machine(&src);
    let mut full = fast.clone();
    assert_eq!(
        fast.run_bare(Pos::at_tick(50_000)),
        full.run_observed(Pos::at_tick(50_000), |_| false, |_| {})
    );
    assert_eq!(fast, full);
    assert_eq!(fast.steps(), 50_000, "{:?}", fast.state().fault);
}

/// A command a compiled loop may hold (mostly), or any other (the loop then stays interpreted).
fn loop_line() -> impl Strategy<Value = String> {
    let r = || prop::sample::select(vec![6u8, 10, 20, 21, 22, 23, 25]);
    let ext = prop::sample::select(vec![
        "ADD",
        "SUB",
        "AND",
        "OR",
        "XOR",
        "MULT_S",
        "MULT_U",
        "MULT_S64_SHR16",
    ]);
    let clc = prop::sample::select(vec![
        "ADD", "SUB", "MULT_S", "MULT_U", "AND", "OR", "XOR", "COPY", "SAVE", "INC", "DEC",
    ]);
    prop_oneof![
        4 => (ext.clone(), r(), r(), data()).prop_map(|(op, x, a, d)| format!("CLD {op}, {x}, {a}, {d}")),
        4 => (ext, r(), r(), r()).prop_map(|(op, x, a, b)| format!("CLX {op}, {x}, {a}, {b}")),
        6 => (clc, r()).prop_map(|(op, x)| format!("CLC {op}, {x}")),
        1 => (r(), data()).prop_map(|(x, v)| format!("WRP {x}, {v}")),
        1 => line(1),
    ]
}

/// A loop (counted down in R25, or ending on a flag) between a start and a tail, round and
/// round.
fn loop_program() -> impl Strategy<Value = String> {
    let cond = condition();
    (
        1i32..3000,
        prop::collection::vec(loop_line(), 1..8),
        any::<bool>(),
        cond,
        prop::collection::vec(loop_line(), 0..3),
    )
        .prop_map(|(count, body, counted, cond, tail)| {
            let mut text = format!("{QUEUE}top: WRP 25, {count}\n");
            text.push_str(&format!("l0: {}\n", body[0]));
            body[1..]
                .iter()
                .for_each(|l| text.push_str(&format!("{l}\n")));
            if counted {
                text.push_str("CLC DEC, 25\nJMP l0, !ZERO\n");
            } else {
                text.push_str(&format!("JMP l0{cond}\n"));
            }
            tail.iter().for_each(|l| text.push_str(&format!("{l}\n")));
            text.push_str("JMP top\n");
            text
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn a_quiet_recording_through_compiled_loops_is_the_observed_recording(
        src in loop_program(),
        plotted in prop::collection::vec(prop::sample::select(vec![0u32, 6, 21, 23]), 1..3),
        ticks in 1u64..60_000,
    ) {
        recordings_agree(&src, Vec::new(), &plotted, ticks, &[10, 20, 21, 22, 25])?;
    }

    #[test]
    fn breakpoints_stop_compiled_loops_where_they_stop_the_observed_run(
        src in loop_program(),
        r in prop::sample::select(vec![6u32, 20, 22, 23]),
        line in 1usize..14,
        ticks in 1u64..40_000,
    ) {
        let breakpoint = servoscope_core::debugger::Breakpoint::data(
            format!("R{r}"),
            servoscope_core::debugger::DataTrigger::Equal(7),
        );
        data_stops_agree(&src, breakpoint, &[0], line, ticks)?;
    }
}

/// The vendor's calculation idiom runs compiled where the host has a code generator, and ends
/// with the values its arithmetic gives (spec §3: MULT_S64_SHR16 keeps bits 16..47).
#[test]
fn the_idiom_loop_runs_compiled_and_right() {
    let src = "WRP 20, 40000\nWRP 21, 7\nWRP 25, 1000\n\
               loop: CLC COPY, 20\nCLC ADD, 21\nCLC SAVE, 20\n\
               CLD MULT_S64_SHR16, 23, 20, q16(0.0254)\nCLX XOR, 24, 23, 20\n\
               CLC DEC, 25\nJMP loop, !ZERO\nEND\n";
    let mut m = machine(src);
    m.run_bare(Pos::at_tick(1_000_000));
    // Three WRPs, 1000 rounds of seven commands, END.
    assert_eq!(m.steps(), 3 + 7_000 + 1);
    let r20 = 40_000 + 7 * 1000;
    let r23 = ((i64::from(r20) * 1665) >> 16) as i32;
    assert_eq!(m.state().regs[20], r20);
    assert_eq!(m.state().regs[23], r23);
    assert_eq!(m.state().regs[24], r23 ^ r20);
    assert_eq!(m.state().regs[25], 0);
    let head = m.program().loops.at(3).expect("the loop is found");
    assert_eq!((head.head, head.end), (3, 9));
    if cfg!(all(
        feature = "jit",
        any(target_arch = "x86_64", target_arch = "aarch64")
    )) {
        assert!(head.is_compiled(), "the loop ran compiled");
    }
}

/// Loops of plain arithmetic up to `MAX_LOOP` commands are compiled; a longer one, or one
/// with a call in it, stays in the interpreter and runs as the full executor runs it.
#[test]
fn only_loops_of_plain_arithmetic_up_to_the_limit_are_compiled() {
    use servoscope_core::machine::silverlode::jit::MAX_LOOP;
    let long = |body: usize| format!("l0: {}JMP l0\n", "CLC INC, 20\n".repeat(body));
    let found = |src: &str| assemble(src).expect("assembles").loops.at(0).is_some();
    assert!(
        found(&long(MAX_LOOP - 1)),
        "{MAX_LOOP} commands with the jump"
    );
    assert!(!found(&long(MAX_LOOP)));
    let with_call = "l0: CLC INC, 20\nCALL sub\nJMP l0\nsub: RET\n";
    assert!(!found(with_call));
    for src in [long(MAX_LOOP), with_call.to_string()] {
        let legs = [40 * MAX_LOOP as u64, 7, 3 * MAX_LOOP as u64];
        fast_and_full_agree(&src, &legs).expect("the fast loop is the full executor");
    }
}
