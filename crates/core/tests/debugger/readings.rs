//! Every text that shows a location's value shows it as the location reads (#43 items 1, 2):
//! a DL205 V word's BCD digits, never its bit pattern as a decimal number.

use std::time::Duration;

use servoscope_core::debugger::history::Change;
use servoscope_core::debugger::log::LogFilter;
use servoscope_core::debugger::{Breakpoint, DataTrigger, Debugger, Event, ScriptedEvent, Speed};
use servoscope_core::lesson;
use servoscope_core::machine::Pos;

use crate::common::{debugger, get};

const PARTS_COUNTER: &str = include_str!("../../../../assets/examples/parts_counter.dl205");

/// The parts counter with `pulses` X0 pulses (on at tick 2k + 1, off at 2k + 2).
fn counter_with_pulses(pulses: u64) -> Debugger {
    let mut d = debugger("dl205", PARTS_COUNTER);
    let events = (0..pulses)
        .flat_map(|k| {
            [(2 * k + 1, 1), (2 * k + 2, 0)].map(|(tick, level)| ScriptedEvent {
                at: Pos::at_tick(tick),
                location: "X0".to_string(),
                change: Change::Set(level),
            })
        })
        .collect();
    d.set_scripted_events(events);
    d.reset();
    d.set_speed(Speed::Unlimited);
    d
}

/// Run until a breakpoint stops the scans or scan 100 (well after the last pulse) is reached.
fn run_to_stop(d: &mut Debugger) {
    d.run();
    for _ in 0..1000 {
        if !d.advance(0.016, Duration::from_millis(5)) {
            return;
        }
        if d.pos().tick >= 100 {
            d.pause();
            return;
        }
    }
    panic!("the run went on past any bound");
}

#[test]
fn a_bcd_data_breakpoint_fires_at_the_count_and_says_it_in_bcd() {
    let mut d = counter_with_pulses(14);
    // "equals 12" in the location's reading: BCD 12 is the pattern 0x0012.
    d.add_breakpoint(Breakpoint::data("V1000", DataTrigger::Equal(0x12)));
    assert_eq!(
        d.breakpoint_list()[0].describe(d.machine()),
        "V1000 becomes 12"
    );
    run_to_stop(&mut d);
    let Some(Event::Watchpoint { old, new, .. }) = d.event() else {
        panic!("stopped on {:?}, not the data breakpoint", d.event());
    };
    assert_eq!((old.as_str(), new.as_str()), ("11", "12"));
    assert_eq!(get(d.machine(), "V1000"), 0x12, "12 parts counted, in BCD");
    let status = d.event().map(|e| e.describe("scan")).unwrap_or_default();
    assert!(status.ends_with(": 11 -> 12"), "{status}");
}

#[test]
fn who_wrote_and_the_log_show_a_v_word_in_bcd() {
    let mut d = counter_with_pulses(16);
    run_to_stop(&mut d);
    assert_eq!(
        get(d.machine(), "V1000"),
        0x16,
        "16 parts, BCD 16 = 0x16 = 22"
    );
    // The Log's writes of V1000: each new count in BCD digits, the last 16 (not 22).
    let v1000 = d.find("V1000").expect("V1000");
    let log = d.execution_log(LogFilter::Writes(v1000), 10_000, u64::MAX);
    let last = log.rows.last().expect("a write of V1000");
    let written: Vec<_> = last.written.iter().filter(|(n, _)| n == "V1000").collect();
    assert_eq!(written, [&("V1000".to_string(), "16".to_string())]);
    let counts: Vec<String> = (log.rows.iter())
        .flat_map(|r| r.written.iter().filter(|(n, _)| n == "V1000"))
        .map(|(_, v)| v.clone())
        .collect();
    assert!(
        counts.contains(&"10".to_string()),
        "ten reads 10: {counts:?}"
    );
    assert!(!counts.iter().any(|c| c == "22"), "{counts:?}");
    // "Who wrote this?" names the value as the register view shows it.
    d.who_wrote(v1000).expect("the counter wrote V1000");
    let text = d.event().map(|e| e.describe("scan")).unwrap_or_default();
    assert!(text.ends_with("(V1000 = 16)"), "{text}");
}

#[test]
fn check_output_reads_a_bcd_word_and_its_expected_value_in_bcd() {
    let mut d = counter_with_pulses(0);
    d.set_text("V0", "bcd(39)").expect("V0 takes BCD 39");
    let m = d.machine();
    let passing = lesson::evaluate(1, "V0 == bcd(39)", m);
    assert!(passing.pass);
    let failing = lesson::evaluate(1, "V0 == bcd(40)", m);
    assert!(!failing.pass);
    assert_eq!(failing.detail(), "V0 = 39 (BCD), expected 40");
    // A plain number against a BCD word names the BCD digits it stands for.
    let plain = lesson::evaluate(1, "V0 == 64", m);
    assert_eq!(plain.detail(), "V0 = 39 (BCD), expected 64 (BCD 40)");
    // The JSON keeps the number the expression computes with.
    assert_eq!(failing.to_json()["values"]["V0"], 0x39);
}

/// #43 item 12: a PLC program's plot starts on the bits it uses (the traffic light's lamps,
/// not DL205's accumulator), and the next program loaded does not inherit them.
#[test]
fn the_plot_starts_on_what_the_program_uses() {
    let traffic = include_str!("../../../../assets/examples/traffic_light.dl205");
    let mut d = debugger("dl205", traffic);
    let names = |d: &Debugger| -> Vec<String> {
        d.channel_choices()
            .iter()
            .map(|c| c.location.clone())
            .collect()
    };
    let lamps = names(&d);
    for lamp in ["Y0", "Y1", "Y2"] {
        assert!(lamps.contains(&lamp.to_string()), "{lamps:?}");
    }
    assert!(!lamps.contains(&"ACC".to_string()), "{lamps:?}");
    // The outputs share the first plot.
    assert!(d.channel_choices().iter().all(|c| c.group == 0));
    d.load_as(d.dialect(), "parts.dl205", PARTS_COUNTER);
    let parts = names(&d);
    assert!(parts.contains(&"X0".to_string()), "{parts:?}");
    assert!(!parts.contains(&"Y1".to_string()), "{parts:?}");
    // A servo program keeps its target and actual position.
    let d = debugger("silverlode", "WRP 20, 1\nEND\n");
    assert_eq!(names(&d), ["R0", "R1", "R6"]);
}

/// Stepping scan by scan (F8) stops at a data breakpoint inside the scan, as a run does (it
/// went past, and the hit was never counted).
#[test]
fn a_data_breakpoint_stops_a_scan_step_too() {
    let mut d = counter_with_pulses(14);
    d.add_breakpoint(Breakpoint::data("V1000", DataTrigger::Equal(0x12)));
    let mut stopped = None;
    for _ in 0..100 {
        d.step_tick();
        if let Some(Event::Watchpoint { new, .. }) = d.event() {
            stopped = Some(new.clone());
            break;
        }
    }
    assert_eq!(stopped.as_deref(), Some("12"));
    assert_eq!(d.breakpoint_hits(0), 1);
    assert_eq!(get(d.machine(), "V1000"), 0x12);
    // The next step goes on from there, past the breakpoint.
    let at = d.pos();
    d.step_tick();
    assert!(d.pos() > at);
}
