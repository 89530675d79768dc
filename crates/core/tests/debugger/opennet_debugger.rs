//! OpenNet's timers, counters, MCS and jumps as the debugger shows them (issue: everything
//! visible by name, the code view's dimming, the Log's words, warnings that do not stop a run,
//! the scan time as a setting kept in sessions).

use servoscope_core::debugger::Debugger;
use servoscope_core::debugger::log::LogFilter;
use servoscope_core::machine::{LinePower, Severity};
use servoscope_core::registry::{Settings, by_name};
use servoscope_core::session::{Session, ViewSettings};

fn debugger(source: &str) -> Debugger {
    let dialect = by_name("opennet").expect("registered");
    let mut d = Debugger::with_dialect(dialect, "test.opennet", source);
    assert!(d.assemble(), "assembles: {:?}", d.diagnostics());
    d
}

/// Go to the start of scan `tick`, running there if it is beyond what was run.
fn to_tick(d: &mut Debugger, tick: u64) {
    d.goto_tick(tick);
    for _ in 0..10_000 {
        if d.goal().is_none() {
            break;
        }
        d.advance(1.0, std::time::Duration::from_millis(50));
    }
    assert_eq!(d.machine().ticks(), tick);
}

fn get(d: &Debugger, name: &str) -> u64 {
    let m = d.machine();
    m.read(
        m.find(name)
            .unwrap_or_else(|| panic!("{name} has a location")),
    )
}

/// Every name of spec §2 reaches its location; watches and conditions take them.
#[test]
fn timers_counters_r_bits_and_mc_by_name() {
    let mut d = debugger("LOD M8125\nTIM T3 40\nLOD I0\nLOD M8122\nCNT C0 7\nLOD I1\nOUT R7\n");
    to_tick(&mut d, 11);
    // T3 first powered in scan 0: after scan 10, 10 scans × 10 ms = 100 ms: one tenth.
    assert_eq!(get(&d, "T3.current"), 39);
    assert_eq!(get(&d, "T3.preset"), 40);
    assert_eq!(get(&d, "T3"), 0);
    // M8122 rises in scans 0 and 10 (on for scans 0–4 of every 10).
    assert_eq!(get(&d, "C0.current"), 2);
    assert_eq!(get(&d, "c0.preset"), 7, "names are case-insensitive");
    assert_eq!(get(&d, "MC"), 1);
    assert_eq!(get(&d, "R7"), 0);
    let names: Vec<String> = [
        "T3",
        "T3.current",
        "T3.preset",
        "C0",
        "C0.current",
        "MC",
        "R7",
    ]
    .iter()
    .map(|n| {
        let m = d.machine();
        m.info(m.find(n).unwrap()).unwrap().name
    })
    .collect();
    assert_eq!(
        names,
        [
            "T3",
            "T3.current",
            "T3.preset",
            "C0",
            "C0.current",
            "MC",
            "R7"
        ]
    );
    assert_eq!(d.evaluate("T3.current + C0.current"), Ok(41));
    assert_eq!(d.evaluate("T3.current < 40 && MC"), Ok(1));
    assert!(d.evaluate("T3.bogus").is_err());
    // A preset typed in the debugger is what the timer uses from its next start.
    let preset = d.find("T3.preset").unwrap();
    d.set_value(preset, 5).expect("a preset is editable");
    assert_eq!(get(&d, "T3.preset"), 5);
    let output = d.find("T3").unwrap();
    assert!(
        d.set_value(output, 1).is_err(),
        "the timer alone sets its output"
    );
}

/// The Log and the explanation say what a timer and a counter did.
#[test]
fn the_log_says_what_timers_and_counters_did() {
    let mut d = debugger("LOD M8125\nTIM T0 12\nLODN M8125\nLOD M8122\nCNT C0 10\n");
    to_tick(&mut d, 3);
    let log = d.execution_log(LogFilter::Line(2), 10, 10);
    let last = log.rows.last().expect("the timer ran").explanation.clone();
    // Scan 2: the second counted scan, 1 tenth each 10 scans: 0 ms of the tenth so far → 20.
    assert!(
        last.contains("T0: 1200 → 1200 ms left") && last.contains("20 ms toward the next"),
        "{last}"
    );
    let first = &log.rows[0].explanation;
    assert!(first.contains("timing starts at 1200 ms"), "{first}");
    to_tick(&mut d, 11);
    let log = d.execution_log(LogFilter::Line(5), 20, 20);
    let counted: Vec<&str> = log
        .rows
        .iter()
        .map(|r| r.explanation.as_str())
        .filter(|e| e.contains("counted"))
        .collect();
    // M8122 rises in scans 0 and 10.
    assert_eq!(counted.len(), 2, "{counted:?}");
    assert!(counted[1].contains("C0 counted 1 → 2"), "{}", counted[1]);
    let written: Vec<&str> = log.rows[0]
        .written
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    assert!(written.contains(&"C0.current"), "{written:?}");
}

/// Code an MCS area that is off runs dimmed; code a taken JMP skipped is veiled, and the JMP
/// names its JEND.
#[test]
fn the_code_view_dims_what_mc_and_jumps_switch_off() {
    let src = "LOD I0\nMCS\nLOD M8125\nOUT Q0\nMCR\nLOD I1\nJMP\nLOD M8125\nOUT Q1\nJEND\nLOD M8125\nOUT Q2\n";
    let mut d = debugger(src);
    to_tick(&mut d, 1);
    let power = d.machine().as_plc().expect("a PLC").line_power();
    let at = |line: usize| power.iter().find(|(l, _)| *l == line).map(|(_, s)| *s);
    assert_eq!(at(2), None, "the MCS itself ran");
    assert_eq!(at(3), Some(LinePower::MasterOff), "inside the off area");
    assert_eq!(at(5), None, "the MCR runs with MC back on");
    assert_eq!(at(4), Some(LinePower::MasterOff));
    assert_eq!(at(8), None, "the JMP is not taken: nothing dimmed");
    assert_eq!(get(&d, "Q0"), 0);
    assert_eq!(get(&d, "Q1"), 1);
    let notes = d.machine().line_notes();
    assert!(
        notes.contains(&(7, "→ JEND line 10 (not taken)".to_string())),
        "{notes:?}"
    );
    assert!(
        notes.contains(&(10, "← JMP line 7".to_string())),
        "{notes:?}"
    );
    assert!(notes.iter().any(|(l, n)| *l == 2 && n.contains("MC off")));
    for name in ["I0", "I1"] {
        let loc = d.find(name).unwrap();
        d.set_input(loc, true).unwrap();
    }
    to_tick(&mut d, 3);
    let power = d.machine().as_plc().expect("a PLC").line_power();
    let at = |line: usize| power.iter().find(|(l, _)| *l == line).map(|(_, s)| *s);
    assert_eq!(at(4), None, "MC on: nothing dimmed");
    assert_eq!(at(8), Some(LinePower::NotRun), "jumped over");
    assert_eq!(at(9), Some(LinePower::NotRun));
    assert_eq!(at(10), None, "JEND runs");
    assert_eq!(get(&d, "Q0"), 1);
    assert_eq!(get(&d, "Q1"), 1, "held by the jump");
    assert!(
        d.machine()
            .line_notes()
            .contains(&(7, "→ JEND line 10 (taken)".to_string()))
    );
}

/// A MICRO3 relay read and never written is a warning: listed, and the program runs.
#[test]
fn micro3_warnings_do_not_stop_the_program() {
    let d = debugger("LOD M303\nOUT Q0\nLOD M312\nOUT Q1\nLOD M301\nOUT M301\n");
    let warnings: Vec<String> = d.diagnostics().iter().map(ToString::to_string).collect();
    assert_eq!(warnings.len(), 2, "M301 is written: {warnings:?}");
    assert!(
        d.diagnostics()
            .iter()
            .all(|w| w.severity == Severity::Warning)
    );
    assert!(warnings[0].starts_with("1:5: warning: M303") && warnings[0].contains("M8003"));
    assert!(warnings[1].starts_with("3:5: warning: M312") && warnings[1].contains("M8122"));
    assert!(!d.has_errors() && d.error_count() == 0);
    let mut d = d;
    to_tick(&mut d, 2);
    assert_eq!(d.machine().ticks(), 2, "it runs");
}

/// scan_ms is a setting: it changes the timers' time and the scan's length, and a session
/// keeps it.
#[test]
fn scan_ms_is_a_setting_a_session_keeps() {
    let src = "LOD M8125\nTIM T0 10\n";
    let mut d = debugger(src);
    let mut settings = Settings::new();
    settings.insert("scan_ms".into(), 50.0);
    d.set_settings(&settings);
    assert_eq!(d.machine().tick_micros(), 50_000);
    // 1 s at 50 ms: on in scan ⌈1000 / 50⌉ = 20.
    to_tick(&mut d, 20);
    assert_eq!(get(&d, "T0"), 0);
    to_tick(&mut d, 21);
    assert_eq!(get(&d, "T0"), 1);
    let text = Session::capture(&d, None, ViewSettings::default())
        .to_ron()
        .expect("saves");
    let session = Session::from_ron(&text, "t.ron").expect("loads");
    let restored = session.restore("t.ron").expect("restores");
    assert_eq!(restored.settings().get("scan_ms"), Some(&50.0));
    assert_eq!(restored.machine().tick_micros(), 50_000);
    assert_eq!(restored.machine().read(restored.find("T0").unwrap()), 1);
}
