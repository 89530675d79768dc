//! A SilverLode session with a bit of everything (inputs, edits, a breakpoint, a checkpoint
//! passed), for the tests of saving, reopening and resuming.

use std::path::PathBuf;
use std::time::Duration;

use servoscope_core::debugger::history::CHECKPOINT_EVERY;
use servoscope_core::debugger::{Debugger, Speed};
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::view::{ISW, io, reg};

pub fn sl(d: &Debugger) -> &SilverLode {
    d.machine_as::<SilverLode>().expect("a SilverLode machine")
}

pub fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("servoscope-sessions-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

pub const PROGRAM: &str = "\
        CLD Q_INIT, 10, 40, 3
loop:   CLD Q_PUSH_HEAD, 11, 40, 5
        CLD Q_POP_TAIL, 12, 40, 0
        MRV 300, 386500, 80530640, IO2
        CLC INC, 20
        DLY 500
        CLD SUB, 21, 20, 40
        JMP loop, !ZERO
        END
";

pub fn busy_debugger() -> Debugger {
    let mut d = Debugger::new("prog.qsl", PROGRAM);
    d.set_speed(Speed::Unlimited);
    d.toggle_breakpoint(5);
    let drive = |d: &mut Debugger, tick: u64| {
        d.goto_tick(tick);
        while d.advance(0.016, Duration::from_secs(5)) {}
    };
    drive(&mut d, 2_000);
    d.set_input(io(1), true).expect("an input");
    drive(&mut d, 2_500);
    d.set_input(io(1), false).expect("an input");
    d.set_value(reg(30), 0xBEEF).expect("a register edit");
    d.set_bit(ISW, 12, true).expect("an ISW bit");
    drive(&mut d, CHECKPOINT_EVERY + 4_000);
    d.run();
    while d.advance(0.016, Duration::from_secs(5)) {}
    assert_eq!(
        d.event().map(|e| e.describe("tick")),
        Some("Breakpoint hit at line 5".to_string())
    );
    d.goto_tick(CHECKPOINT_EVERY + 123);
    d
}
