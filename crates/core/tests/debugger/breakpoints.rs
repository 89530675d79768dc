//! Breakpoints beyond a line, watches, the execution log and "who wrote this?", through the
//! debugger's plain Rust calls, for every dialect.

use std::time::Duration;

use servoscope_core::debugger::log::LogFilter;
use servoscope_core::debugger::{
    BreakError, BreakKind, Breakpoint, DataTrigger, Debugger, Event, Speed,
};
use servoscope_core::machine::{Format, Pos, value_of};
use servoscope_core::session::{Session, ViewSettings};

use crate::common;
use common::debugger;

const LOOP: &str = common::ROUNDS;

/// Run until the debugger stops on its own (breakpoint, end, fault).
fn run_to_stop(d: &mut Debugger) {
    d.set_speed(Speed::Unlimited);
    d.run();
    while d.advance(0.016, Duration::from_millis(200)) {}
}

fn value(d: &Debugger, name: &str) -> i64 {
    let loc = d.find(name).unwrap_or_else(|| panic!("{name} exists"));
    value_of(d.machine(), loc)
}

#[test]
fn a_condition_stops_only_when_it_holds() {
    let mut d = debugger("silverlode", LOOP);
    let i = d.add_breakpoint(Breakpoint::line(3).with_condition("R12 == 4 && R11 > 0"));
    assert_eq!(d.breakpoint_error(i), None);
    run_to_stop(&mut d);
    assert_eq!(d.event(), Some(&Event::Breakpoint(3)));
    assert_eq!(
        value(&d, "R12"),
        4,
        "stopped before line 3 ran a fifth time"
    );
    run_to_stop(&mut d);
    assert_eq!(d.event(), Some(&Event::Ended), "never true again");
    assert_eq!(value(&d, "R12"), 10);
}

#[test]
fn a_condition_that_does_not_parse_says_where_and_stops_nothing() {
    let mut d = debugger("silverlode", LOOP);
    let i = d.add_breakpoint(Breakpoint::line(3).with_condition("R12 >"));
    match d.breakpoint_error(i) {
        Some(BreakError::Condition(e)) => assert_eq!(e.col, 6, "{e}"),
        other => panic!("expected a condition error, got {other:?}"),
    }
    let j = d.add_breakpoint(Breakpoint::line(5).with_condition("BANANA == 1"));
    assert!(
        d.breakpoint_error(j)
            .is_some_and(|e| e.to_string().contains("BANANA"))
    );
    run_to_stop(&mut d);
    assert_eq!(
        d.event(),
        Some(&Event::Ended),
        "broken breakpoints are inactive"
    );
    // Fixing it makes it work.
    let mut fixed = d.breakpoint_list()[i].clone();
    fixed.condition = "R12 > 7".into();
    d.update_breakpoint(i, fixed);
    assert_eq!(d.breakpoint_error(i), None);
    d.reset();
    run_to_stop(&mut d);
    assert_eq!(d.event(), Some(&Event::Breakpoint(3)));
    assert_eq!(value(&d, "R12"), 8);
}

#[test]
fn a_hit_count_lets_the_first_hits_pass() {
    let mut d = debugger("silverlode", LOOP);
    let i = d.add_breakpoint(Breakpoint::line(3).with_hit_count(3));
    run_to_stop(&mut d);
    assert_eq!(d.event(), Some(&Event::Breakpoint(3)));
    assert_eq!(value(&d, "R12"), 2, "the third arrival: two rounds done");
    assert_eq!(d.breakpoint_hits(i), 3);
    run_to_stop(&mut d);
    assert_eq!(value(&d, "R12"), 3, "and every later one");
    d.reset();
    assert_eq!(d.breakpoint_hits(i), 0, "a new run counts afresh");
}

#[test]
fn a_log_point_writes_instead_of_stopping() {
    let mut d = debugger("silverlode", LOOP);
    d.add_breakpoint(Breakpoint::line(5).with_log("round {R12}: R11 was {R11}"));
    run_to_stop(&mut d);
    assert_eq!(d.event(), Some(&Event::Ended));
    let log: Vec<String> = d.log_messages().iter().map(|m| m.text.clone()).collect();
    assert_eq!(log.len(), 10);
    assert_eq!(log[0], "round 1: R11 was 10");
    assert_eq!(log[9], "round 10: R11 was 1");
    assert!(d.log_messages().iter().all(|m| m.line == 5));
    // Going back and running the same stretch again logs nothing twice.
    d.goto_tick(3);
    run_to_stop(&mut d);
    assert_eq!(d.log_messages().len(), 10);
}

/// The machine stepped instruction by instruction: after each step, where it is, the value of
/// `name`, and whether the step wrote it.
fn straight_run(d: &mut Debugger, name: &str, until_tick: u64) -> Vec<(Pos, i64, bool)> {
    d.reset();
    let loc = d.find(name).expect("the location exists");
    let mut out = vec![(d.pos(), value_of(d.machine(), loc), false)];
    while d.machine().run_state().is_live() && d.pos().tick < until_tick {
        d.step_command();
        while d.advance(0.016, Duration::from_millis(200)) {}
        out.push((d.pos(), value_of(d.machine(), loc), d.machine().wrote(loc)));
    }
    d.reset();
    out
}

/// Where each kind of data breakpoint must stop, from the straight run.
fn expected_stops(run: &[(Pos, i64, bool)], trigger: DataTrigger) -> Vec<Pos> {
    run.windows(2)
        .filter(|w| {
            let ((_, before, _), (_, now, wrote)) = (w[0], w[1]);
            match trigger {
                DataTrigger::Write => wrote,
                DataTrigger::Change => now != before,
                DataTrigger::Equal(v) => now == v && before != v,
            }
        })
        .map(|w| w[1].0)
        .collect()
}

fn forward_stops(d: &mut Debugger, until_tick: u64) -> Vec<Pos> {
    let mut stops = Vec::new();
    d.reset();
    loop {
        run_to_stop_before(d, until_tick);
        match d.event() {
            Some(Event::Watchpoint { .. }) if d.pos().tick < until_tick => stops.push(d.pos()),
            _ => return stops,
        }
    }
}

fn run_to_stop_before(d: &mut Debugger, until_tick: u64) {
    d.set_speed(Speed::Unlimited);
    d.run();
    while d.advance(0.016, Duration::from_millis(2)) {
        if d.pos().tick >= until_tick {
            d.pause();
        }
    }
}

fn backward_stops(d: &mut Debugger) -> Vec<Pos> {
    let mut stops = Vec::new();
    loop {
        d.reverse_continue();
        match d.event() {
            Some(Event::Watchpoint { .. }) => stops.push(d.pos()),
            _ => break,
        }
    }
    stops.reverse();
    stops
}

/// A data breakpoint of each kind, forward and backward, against the straight run.
fn data_breakpoints_match_a_straight_run(
    dialect: &str,
    source: &str,
    name: &str,
    equal: i64,
    until_tick: u64,
) {
    let mut d = debugger(dialect, source);
    let run = straight_run(&mut d, name, until_tick);
    for trigger in [
        DataTrigger::Write,
        DataTrigger::Change,
        DataTrigger::Equal(equal),
    ] {
        let expected = expected_stops(&run, trigger);
        assert!(
            !expected.is_empty(),
            "{dialect} {name} {trigger:?}: the test program exercises it"
        );
        d.set_breakpoint_list(vec![Breakpoint::data(name, trigger)]);
        let forward = forward_stops(&mut d, until_tick);
        assert_eq!(forward, expected, "{dialect} {name} {trigger:?} forward");
        // Backward from the furthest point of the straight run.
        d.set_breakpoint_list(Vec::new());
        let last = run.last().expect("a straight run").0;
        d.reset();
        d.goto(last);
        while d.advance(0.016, Duration::from_millis(200)) {}
        d.set_breakpoint_list(vec![Breakpoint::data(name, trigger)]);
        let end = d.pos();
        let backward: Vec<Pos> = backward_stops(&mut d)
            .into_iter()
            .filter(|&p| p < end)
            .collect();
        let expected_back: Vec<Pos> = expected.iter().copied().filter(|&p| p < end).collect();
        assert_eq!(
            backward, expected_back,
            "{dialect} {name} {trigger:?} backward"
        );
    }
}

#[test]
fn silverlode_data_breakpoints() {
    // R13 is written with the same value each round, then changed once.
    data_breakpoints_match_a_straight_run("silverlode", LOOP, "R13", 7, u64::MAX);
    data_breakpoints_match_a_straight_run("silverlode", LOOP, "R12", 6, u64::MAX);
}

#[test]
fn tml_data_breakpoints() {
    let source = "\
int a;
int b;
        b = 6;
loop:   a = 5;
        b -= 1;
        GOTO loop, b, GT;
        a = 9;
        END;
";
    data_breakpoints_match_a_straight_run("tml", source, "a", 9, u64::MAX);
    data_breakpoints_match_a_straight_run("tml", source, "b", 2, u64::MAX);
}

#[test]
fn dl205_data_breakpoints() {
    let source = "\
STR SP1
LD V2000
ADDB K1
OUT V2000
STR SP1
LD K5
OUT V2001
END
";
    data_breakpoints_match_a_straight_run("dl205", source, "V2000", 4, 12);
    data_breakpoints_match_a_straight_run("dl205", source, "V2001", 5, 12);
}

#[test]
fn opennet_data_breakpoints() {
    let source = "\
LODN M0
INC(W) D0
MOV(W) 5 D1
END
";
    data_breakpoints_match_a_straight_run("opennet", source, "D0", 3, 12);
    data_breakpoints_match_a_straight_run("opennet", source, "D1", 5, 12);
}

#[test]
fn a_data_breakpoint_takes_a_condition_and_names_the_write() {
    let mut d = debugger("silverlode", LOOP);
    d.add_breakpoint(Breakpoint::data("R12", DataTrigger::Change).with_condition("R12 > 7"));
    run_to_stop(&mut d);
    assert_eq!(
        d.event(),
        Some(&Event::Watchpoint {
            location: "R12".into(),
            line: 3,
            old: "7".into(),
            new: "8".into()
        })
    );
    assert_eq!(
        d.machine().last_line(),
        Some(3),
        "stopped right after the write"
    );
    let i = d.add_breakpoint(Breakpoint::data("R999", DataTrigger::Write));
    assert!(matches!(
        d.breakpoint_error(i),
        Some(BreakError::Location(_))
    ));
}

#[test]
fn who_wrote_walks_back_through_the_writes() {
    let source = "\
WRP 20, 1
WRP 21, 0
CLC INC, 20
WRP 22, 0
CLC INC, 20
WRP 21, 9
END
";
    let mut d = debugger("silverlode", source);
    run_to_stop(&mut d);
    let r20 = d.find("R20").expect("R20");
    let mut lines = Vec::new();
    let mut values = Vec::new();
    while let Some(at) = d.who_wrote(r20) {
        assert_eq!(d.pos(), at);
        lines.push(d.machine().last_line().expect("a line ran"));
        values.push(value_of(d.machine(), r20));
        match d.event() {
            Some(Event::WrittenBy { line, .. }) => assert_eq!(*line, lines.last().copied()),
            other => panic!("expected WrittenBy, got {other:?}"),
        }
    }
    assert_eq!(lines, [5, 3, 1], "each step back lands on the write before");
    assert_eq!(values, [3, 2, 1], "the value each write left");
    assert!(matches!(d.event(), Some(Event::NeverWritten(n)) if n == "R20"));
}

#[test]
fn who_wrote_finds_the_users_edit() {
    let mut d = debugger("silverlode", "WRP 20, 1\nDLY 5\nCLC INC, 21\nEND\n");
    d.step_command();
    d.step_command();
    while d.advance(0.016, Duration::from_millis(200)) {}
    d.set_text("R20", "42").expect("an edit");
    let edit_at = d.pos();
    d.step_command();
    let r20 = d.find("R20").expect("R20");
    assert_eq!(d.who_wrote(r20), Some(edit_at));
    assert!(matches!(
        d.event(),
        Some(Event::WrittenBy { line: None, .. })
    ));
    assert_eq!(value_of(d.machine(), r20), 42);
    let first = d.who_wrote(r20).expect("WRP wrote it before");
    assert_eq!(d.machine().last_line(), Some(1));
    assert!(first < edit_at);
}

#[test]
fn the_execution_log_lists_steps_newest_last_and_filters() {
    let mut d = debugger("silverlode", LOOP);
    run_to_stop(&mut d);
    let all = d.execution_log(LogFilter::All, 1000, u64::MAX);
    assert!(all.complete);
    assert_eq!(all.rows.len() as u64, d.machine().steps());
    assert_eq!(all.rows[0].line, 1);
    assert_eq!(all.rows.last().map(|r| r.line), Some(8), "END last");
    assert!(all.rows.windows(2).all(|w| w[0].at < w[1].at));
    assert!(all.rows.iter().all(|r| !r.explanation.is_empty()));
    let line5 = d.execution_log(LogFilter::Line(5), 1000, u64::MAX);
    assert_eq!(line5.rows.len(), 10);
    assert!(line5.rows.iter().all(|r| r.line == 5));
    // CLC DEC wrote R11 and the ISW flags (spec §4: 9 is positive, so bit 2 and not 1 or 3).
    let written = &line5.rows[0].written;
    assert_eq!(written[0], ("R11".to_string(), "9".to_string()));
    assert_eq!(written.len(), 2);
    assert_eq!(written[1].0, "ISW");
    // ISW reads in binary, as its view shows it.
    let isw = u64::from_str_radix(&written[1].1.replace(' ', ""), 2).expect("ISW in binary");
    assert_eq!(isw & 0b1110, 0b0100);
    let r13 = d.find("R13").expect("R13");
    let writes = d.execution_log(LogFilter::Writes(r13), 1000, u64::MAX);
    assert_eq!(
        writes.rows.iter().map(|r| r.line).collect::<Vec<_>>(),
        [1, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 7]
    );
    let last3 = d.execution_log(LogFilter::Line(4), 3, u64::MAX);
    assert_eq!(last3.rows.len(), 3);
    assert!(!last3.complete);
    assert_eq!(last3.rows[2].at, line5.rows[9].at.min(last3.rows[2].at));
    // From the middle of the history: only what ran before here.
    let middle = all.rows[10].at;
    d.goto(middle);
    let before = d.execution_log(LogFilter::All, 1000, u64::MAX);
    assert_eq!(before.rows, all.rows[..=10]);
    assert_eq!(
        d.pos(),
        middle,
        "building the log leaves the position alone"
    );
}

#[test]
fn watches_evaluate_and_plot() {
    let mut d = debugger("silverlode", LOOP);
    let w = d.add_watch("R12 * 2 + R11", Format::Signed);
    let bad = d.add_watch("R12 +", Format::Hex);
    run_to_stop(&mut d);
    assert_eq!(d.watch_value(w), Ok(20));
    assert!(d.watch_value(bad).is_err());
    assert!(d.plot_watch(w));
    assert!(!d.plot_watch(bad));
    let channel = d
        .channels()
        .iter()
        .position(|c| c.name == "R12 * 2 + R11")
        .expect("plotted");
    let last = d.trace().samples().last().expect("samples");
    assert_eq!(last.get(channel), 20);
    d.goto_tick(3);
    assert_eq!(d.watch_value(w), Ok(2 + 10), "watches follow the position");
}

#[test]
fn break_on_error_flags_in_every_dialect() {
    // Each program sets its dialect's error flag at a known line and goes on.
    let cases = [
        (
            "silverlode",
            "CER handler\nWRP 10, 0\nCLC DIV, 10\nWRP 11, 1\nEND\nhandler: END\n",
            6,
        ),
        (
            "tml",
            "int a;\n        a = 1;\n        UPD;\n        a = 2;\n        END;\n",
            4,
        ),
        ("dl205", "STR SP1\nLD K4\nDIV V2002\nOUT V2000\nEND\n", 4),
        ("opennet", "LODN M0\nDIV(W) 5 0 D0\nMOV(W) 1 D1\nEND\n", 3),
    ];
    for (dialect, source, line) in cases {
        let mut d = debugger(dialect, source);
        d.set_break_on_error(true);
        run_to_stop(&mut d);
        assert_eq!(
            d.event(),
            Some(&Event::ErrorLamp(line)),
            "{dialect}: {}",
            d.dialect().error_flags
        );
        assert!(d.machine().error_lamp());
    }
}

#[test]
fn sessions_keep_breakpoints_watches_and_switches() {
    let mut d = debugger("silverlode", LOOP);
    d.toggle_breakpoint(2);
    d.add_breakpoint(
        Breakpoint::line(3)
            .with_condition("R12 > 2")
            .with_hit_count(2),
    );
    d.add_breakpoint(Breakpoint::line(5).with_log("R11={R11}"));
    d.add_breakpoint(Breakpoint::data("R13", DataTrigger::Equal(7)));
    let mut off = Breakpoint::data("R12", DataTrigger::Change);
    off.enabled = false;
    d.add_breakpoint(off);
    d.add_watch("R12 + R11", Format::Hex);
    d.set_break_on_error(true);
    let saved = Session::capture(&d, None, ViewSettings::default());
    let text = saved.to_ron().expect("encodes");
    let loaded = Session::from_ron(&text, "s.ron").expect("parses");
    let r = loaded.restore("s.ron").expect("restores");
    assert_eq!(r.breakpoint_list(), d.breakpoint_list());
    assert_eq!(r.watches(), d.watches());
    assert!(r.break_on_error());
    // A file from before breakpoint lists: plain lines still load.
    let old = text
        .lines()
        .filter(|l| !l.contains("breakpoint_list"))
        .collect::<Vec<_>>()
        .join("\n");
    assert!(old.len() < text.len());
    let mut plain = saved.clone();
    plain.breakpoint_list.clear();
    let r = plain.restore("p.ron").expect("restores");
    assert_eq!(r.breakpoints(), [2].into());
    assert!(
        r.breakpoint_list()
            .iter()
            .all(|b| matches!(b.kind, BreakKind::Line(2)))
    );
}

#[test]
fn breakpoints_follow_edits_and_data_ones_survive_them() {
    let mut d = debugger("silverlode", LOOP);
    d.add_breakpoint(Breakpoint::line(5).with_condition("R11 == 3"));
    d.add_breakpoint(Breakpoint::data("R13", DataTrigger::Write));
    *d.source_mut() = format!("WRP 30, 1\n{LOOP}");
    assert!(d.assemble());
    assert_eq!(d.breakpoint_list()[0].kind, BreakKind::Line(6));
    assert_eq!(d.breakpoint_list()[0].condition, "R11 == 3");
    assert!(matches!(
        d.breakpoint_list()[1].kind,
        BreakKind::Data { .. }
    ));
}

#[test]
fn mnemonics_are_the_first_word_of_the_statement() {
    use servoscope_core::runner::mnemonic;
    assert_eq!(mnemonic("loop: CLC INC, 12"), "CLC");
    assert_eq!(mnemonic("        MOV(W) 5 D1"), "MOV(W)");
    assert_eq!(mnemonic("        UPD;"), "UPD");
    assert_eq!(mnemonic("STR X0"), "STR");
}

#[test]
fn who_wrote_reaches_far_back_and_follows_rewritten_history() {
    // About 90,000 ticks: R20 is written by the first command only.
    let source = "\
WRP 20, 1
WRP 11, 30000
loop: CLC INC, 21
CLC DEC, 11
JMP loop, !ZERO
WRP 22, 5
END
";
    let mut d = debugger("silverlode", source);
    run_to_stop(&mut d);
    assert!(d.pos().tick > 80_000);
    let (r20, r21) = (d.find("R20").expect("R20"), d.find("R21").expect("R21"));
    assert!(d.who_wrote(r20).is_some());
    assert_eq!(
        d.machine().last_line(),
        Some(1),
        "back to the very first command"
    );
    run_to_stop(&mut d);
    assert!(d.who_wrote(r21).is_some());
    assert_eq!(d.machine().last_line(), Some(3));
    assert_eq!(value_of(d.machine(), r21), 30_000);
    // Rewrite the history in the middle, run on: the edit is the last write of R20 now.
    d.goto_tick(40_000);
    d.set_text("R20", "9").expect("an edit");
    let edit_at = d.pos();
    run_to_stop(&mut d);
    assert_eq!(d.who_wrote(r20), Some(edit_at));
    // And a write recorded after the rewrite is found in the rewritten stretch.
    d.goto_tick(40_001);
    d.set_text("R11", "3").expect("an edit");
    run_to_stop(&mut d);
    assert!(d.who_wrote(r21).is_some());
    assert_eq!(d.machine().last_line(), Some(3));
    assert!(d.pos().tick > 40_001 && d.pos().tick < 40_020);
}

#[test]
fn who_wrote_and_the_log_in_every_dialect() {
    // (dialect, program, location, the line that writes it, ticks to run)
    let cases = [
        (
            "tml",
            "int a;\n        a = 5;\n        a += 2;\n        END;\n",
            "a",
            [3, 2],
        ),
        (
            "dl205",
            "STR SP1\nLD V2000\nADDB K1\nOUT V2000\nEND\n",
            "V2000",
            [4, 4],
        ),
        ("opennet", "LODN M0\nINC(W) D0\nEND\n", "D0", [2, 2]),
    ];
    for (dialect, source, name, lines) in cases {
        let mut d = debugger(dialect, source);
        d.goto_tick(3);
        while d.advance(0.016, Duration::from_millis(200)) {}
        let loc = d.find(name).expect("the location");
        let end_value = value_of(d.machine(), loc);
        assert!(d.who_wrote(loc).is_some(), "{dialect}");
        assert_eq!(d.machine().last_line(), Some(lines[0]), "{dialect}");
        assert_eq!(
            value_of(d.machine(), loc),
            end_value,
            "{dialect}: the last write"
        );
        let first = d.pos();
        assert!(d.who_wrote(loc).is_some(), "{dialect}");
        assert_eq!(d.machine().last_line(), Some(lines[1]), "{dialect}");
        assert!(d.pos() < first);
        let log = d.execution_log(LogFilter::Writes(loc), 100, u64::MAX);
        assert!(
            log.rows
                .iter()
                .all(|r| r.written.iter().any(|(n, _)| n == name))
        );
        assert_eq!(log.rows.last().map(|r| r.at), Some(d.pos()), "{dialect}");
    }
}

proptest::proptest! {
    #[test]
    fn any_condition_text_compiles_or_says_where_and_never_panics(
        text in "[ -~]{0,40}",
        tokens in proptest::collection::vec(
            proptest::sample::select(vec![
                "R4", "R12", "IO3", "PSW.12", "(", ")", "&&", "||", "!", "-", "~", "+", "*",
                "/", "%", "<<", ">>", "==", "!=", "<", ">=", "0x7FFFFFFFFFFFFFFF", "0", "1",
                "-9223372036854775808", "&", "|", "^", "=", "{", "}", ".",
            ]),
            0..24,
        ),
    ) {
        let d = debugger("silverlode", LOOP);
        for source in [text.clone(), tokens.join(" "), tokens.concat()] {
            let chars = source.chars().count();
            match servoscope_core::debugger::expr::Expr::compile(&source, d.machine()) {
                Ok(e) => {
                    let _ = e.eval(d.machine());
                }
                Err(e) => proptest::prop_assert!(e.col >= 1 && e.col <= chars + 1, "{source}: {e}"),
            }
            if let Ok(m) = servoscope_core::debugger::expr::Message::compile(&source, d.machine()) {
                let _ = m.render(d.machine());
            }
        }
    }
}

#[test]
fn reverse_continue_names_the_breakpoint_it_went_back_to() {
    let mut d = debugger("silverlode", LOOP);
    run_to_stop(&mut d);
    d.add_breakpoint(Breakpoint::line(5));
    d.add_breakpoint(Breakpoint::data("R13", DataTrigger::Change));
    // From the end: the last stop is the change of R13 by line 7, with its values.
    d.reverse_continue();
    assert_eq!(
        d.event(),
        Some(&Event::Watchpoint {
            location: "R13".into(),
            line: 7,
            old: "5".into(),
            new: "7".into()
        })
    );
    // From right before line 5 runs (itself a hit): the one before is the previous round's.
    d.reverse_continue();
    assert_eq!(d.event(), Some(&Event::Breakpoint(5)));
    assert_eq!(
        value(&d, "R11"),
        1,
        "the last round, before line 5 takes R11 to 0"
    );
    d.reverse_continue();
    assert_eq!(d.event(), Some(&Event::Breakpoint(5)));
    assert_eq!(value(&d, "R11"), 2);
}
