//! Forcing bits of the scanned PLCs (DL250/260 override, WindLDR set/reset forced): a forced
//! bit keeps its level whatever the program writes and the program reads that level; forces are
//! user events, so time travel replays them, "who wrote this?" names them, sessions keep them
//! and the runner takes them.

use crate::common::debugger;

use servoscope_core::debugger::{Debugger, EditError, Event};
use servoscope_core::machine::WriteError;
use servoscope_core::session::{Session, ViewSettings};

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
    m.read(m.find(name).unwrap_or_else(|| panic!("{name}")))
}

fn force(d: &mut Debugger, name: &str, level: Option<bool>) -> Result<(), EditError> {
    let loc = d.find(name).unwrap_or_else(|| panic!("{name}"));
    d.force(loc, level)
}

// Y0 follows X0; Y1 follows Y0 (so the program reads the forced level).
const DL: &str = "STR X0\nOUT Y0\nSTR Y0\nOUT Y1\nEND\n";

#[test]
fn a_forced_output_holds_against_the_program_and_the_program_reads_it() {
    let mut d = debugger("dl205", DL);
    to_tick(&mut d, 3);
    assert_eq!((get(&d, "Y0"), get(&d, "Y1")), (0, 0));
    force(&mut d, "Y0", Some(true)).expect("Y0 can be forced");
    assert_eq!(get(&d, "Y0"), 1, "on at once");
    to_tick(&mut d, 10);
    assert_eq!(get(&d, "Y0"), 1, "OUT Y0 with X0 off does not turn it off");
    assert_eq!(get(&d, "Y1"), 1, "STR Y0 reads the forced level");
    assert_eq!(d.machine().forced(d.find("Y0").expect("Y0")), Some(true));
    // A user's write to it is refused while it is forced.
    let y0 = d.find("Y0").expect("Y0");
    assert!(matches!(
        d.set_value(y0, 0),
        Err(EditError::Refused(WriteError::Forced { on: true, .. }))
    ));
    // Released, the program drives it again from the next instruction that writes it.
    force(&mut d, "Y0", None).expect("released");
    to_tick(&mut d, 12);
    assert_eq!((get(&d, "Y0"), get(&d, "Y1")), (0, 0));
    assert!(d.machine().forces().is_empty());
}

#[test]
fn a_forced_input_is_what_the_program_sees_and_its_switch_is_refused() {
    let mut d = debugger("dl205", DL);
    force(&mut d, "X0", Some(true)).expect("X0 can be forced");
    to_tick(&mut d, 2);
    assert_eq!(
        get(&d, "Y0"),
        1,
        "the scan's input image holds the forced X0"
    );
    let x0 = d.find("X0").expect("X0");
    assert!(d.set_input(x0, false).is_err(), "the switch does nothing");
    assert_eq!(get(&d, "X0"), 1);
    // Timer bits are the CPU's: not forceable, with a message saying so.
    let t = debugger("dl205", "STR X0\nTMR T0 K10\nEND\n");
    let err = t.machine().can_force(t.find("T0").expect("T0"));
    assert!(!err);
}

#[test]
fn time_travel_replays_forces() {
    let mut d = debugger("dl205", DL);
    to_tick(&mut d, 5);
    force(&mut d, "Y0", Some(true)).expect("forced");
    to_tick(&mut d, 20);
    assert_eq!(get(&d, "Y1"), 1);
    // Back before the force: nothing forced, Y1 off.
    to_tick(&mut d, 3);
    assert!(d.machine().forces().is_empty());
    assert_eq!(get(&d, "Y1"), 0);
    // Forward again: the force comes back at its scan.
    to_tick(&mut d, 15);
    assert_eq!(get(&d, "Y0"), 1);
    assert_eq!(get(&d, "Y1"), 1);
    // Step back over single instructions keeps it too.
    d.step_back_command();
    assert_eq!(d.machine().forced(d.find("Y0").expect("Y0")), Some(true));
}

#[test]
fn who_wrote_a_forced_bit_names_the_force() {
    let mut d = debugger("dl205", DL);
    to_tick(&mut d, 4);
    force(&mut d, "Y0", Some(true)).expect("forced");
    to_tick(&mut d, 9);
    let y0 = d.find("Y0").expect("Y0");
    let at = d.who_wrote(y0).expect("an answer");
    assert_eq!(at.tick, 4, "where the force was made");
    match d.event() {
        Some(Event::WrittenBy { explanation, .. }) => {
            assert!(explanation.contains("force"), "{explanation}");
            assert!(explanation.contains("ON"), "{explanation}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn sessions_keep_forces() {
    let mut d = debugger("opennet", "LOD I0\nOUT Q0\nLOD Q0\nOUT M0\nEND\n");
    to_tick(&mut d, 2);
    force(&mut d, "Q0", Some(true)).expect("Q0 can be forced");
    force(&mut d, "I1", Some(true)).expect("I1 can be forced");
    to_tick(&mut d, 6);
    let text = Session::capture(&d, None, ViewSettings::default())
        .to_ron()
        .expect("saved");
    assert!(text.contains("Force(Some(true))"), "{text}");
    let back = Session::from_ron(&text, "s.ron")
        .and_then(|s| s.restore("s.ron"))
        .expect("restored");
    assert_eq!(back.machine().forces(), d.machine().forces());
    assert_eq!(get(&back, "M0"), 1, "the program read the forced Q0");
    assert_eq!(back.machine().ticks(), 6);
}

#[test]
fn releasing_a_forced_input_gives_the_program_its_switch_again() {
    let mut d = debugger("dl205", DL);
    // The switch is off; the force holds it on for the program.
    force(&mut d, "X0", Some(true)).expect("forced");
    to_tick(&mut d, 3);
    assert_eq!(get(&d, "Y0"), 1);
    force(&mut d, "X0", None).expect("released");
    assert_eq!(get(&d, "X0"), 0, "the switch as the user left it");
    to_tick(&mut d, 5);
    assert_eq!(get(&d, "Y0"), 0, "the next scan reads the real switch");
    // OpenNet likewise: I0 forced off while its switch is on, then released.
    let mut o = debugger("opennet", "LOD I0\nOUT Q0\nEND\n");
    let i0 = o.find("I0").expect("I0");
    o.set_input(i0, true).expect("switched on");
    force(&mut o, "I0", Some(false)).expect("forced");
    to_tick(&mut o, 2);
    assert_eq!(get(&o, "Q0"), 0);
    force(&mut o, "I0", None).expect("released");
    to_tick(&mut o, 4);
    assert_eq!(get(&o, "Q0"), 1, "the switch was on all along");
}
