//! Helpers shared by the integration tests.

#![allow(dead_code)]

pub mod agree;
pub mod lessons;
pub mod scanned;
pub mod sessions;

use std::path::PathBuf;

use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::{Machine, MachineView, RunState};

/// A SilverLode loop for the debugger's tests: R13 is written with the same value every
/// round and changed once at the end; R12 counts the rounds, R11 counts down from 10.
pub const ROUNDS: &str = "\
WRP 13, 5
WRP 11, 10
loop: CLC INC, 12
WRP 13, 5
CLC DEC, 11
JMP loop, !ZERO
WRP 13, 7
END
";

/// Assemble `source` into a SilverLode machine with the default servo model.
pub fn load(source: &str) -> Result<SilverLode, Vec<servoscope_core::machine::Diagnostic>> {
    servoscope_core::machine::silverlode::dialect::machine(source, &Default::default())
}

/// Assemble `source` or fail the test with every diagnostic.
pub fn machine(source: &str) -> SilverLode {
    match load(source) {
        Ok(m) => m,
        Err(diags) => {
            let text: Vec<String> = diags.iter().map(ToString::to_string).collect();
            panic!("program did not assemble:\n{}\n{source}", text.join("\n"))
        }
    }
}

/// Run `source` to its end (at most 10 M ticks).
pub fn run(source: &str) -> SilverLode {
    let mut m = machine(source);
    m.run_until(10_000_000, |_| false);
    m
}

/// Run and require the program to have ended normally.
pub fn run_ok(source: &str) -> SilverLode {
    let m = run(source);
    assert_eq!(
        m.run_state(),
        RunState::Ended,
        "fault: {:?}\n{source}",
        m.fault()
    );
    m
}

pub fn reg(m: &SilverLode, r: usize) -> i32 {
    m.reg(r)
}

pub fn ureg(m: &SilverLode, r: usize) -> u32 {
    m.reg(r) as u32
}

/// The ISW arithmetic flags as (zero, positive, negative).
pub fn flags(m: &SilverLode) -> (bool, bool, bool) {
    let isw = m.isw();
    (isw & 2 != 0, isw & 4 != 0, isw & 8 != 0)
}

/// A program file in the temporary directory, named apart for each test process.
pub fn scratch_file(name: &str, text: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("servoscope-{}-{name}", std::process::id()));
    std::fs::write(&path, text).expect("write a scratch file");
    path
}

/// A plot channel of the location `name` of `m`.
pub fn channel_named(m: &dyn MachineView, name: &str) -> servoscope_core::debugger::trace::Channel {
    let loc = m.find(name).unwrap_or_else(|| panic!("{name} exists"));
    let info = m.info(loc).expect("a location has its description");
    servoscope_core::debugger::trace::Channel {
        loc,
        name: name.to_string(),
        label: name.to_string(),
        width: info.width,
        signed: info.signed,
        reading: info.reading(),
        group: 0,
        expr: None,
    }
}

/// Every location of `m` with its value, by name: what "the whole state" means when two
/// machines are compared through the dialect-neutral view.
pub fn every_value(m: &dyn MachineView) -> Vec<(String, u64)> {
    let mut out = Vec::new();
    for (space, info) in m.spaces().iter().enumerate() {
        for index in 0..info.len {
            let loc = servoscope_core::machine::Loc::new(space as u8, index);
            if let Some(i) = m.info(loc) {
                out.push((i.name, m.read(loc)));
            }
        }
    }
    out
}

/// The value of the location named `name` (which must exist).
pub fn get(m: &(impl MachineView + ?Sized), name: &str) -> u64 {
    m.read(m.find(name).unwrap_or_else(|| panic!("{name} exists")))
}

/// Store `value` in the location named `name` (which must exist and take it).
pub fn set(m: &mut (impl MachineView + ?Sized), name: &str, value: u64) {
    let loc = m.find(name).unwrap_or_else(|| panic!("{name} exists"));
    m.write(loc, value)
        .unwrap_or_else(|e| panic!("write {name}: {e:?}"));
}

/// Each diagnostic as the user reads it; none when the program assembled.
pub fn error_texts<T>(
    assembled: Result<T, Vec<servoscope_core::machine::Diagnostic>>,
) -> Vec<String> {
    match assembled {
        Ok(_) => Vec::new(),
        Err(e) => e.iter().map(ToString::to_string).collect(),
    }
}

/// A debugger on `source` in the dialect named `dialect`; the program must assemble.
pub fn debugger(dialect: &str, source: &str) -> servoscope_core::debugger::Debugger {
    let dialect = servoscope_core::registry::by_name(dialect).expect("a registered dialect");
    let d = servoscope_core::debugger::Debugger::with_dialect(dialect, "test", source);
    assert!(!d.has_errors(), "{dialect:?} {:?}", d.diagnostics());
    d
}

/// A fresh directory for files on disk.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("servoscope-proj-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    dir
}

pub fn write(dir: &std::path::Path, name: &str, text: &str) {
    let path = dir.join(name);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).expect("folders");
    }
    std::fs::write(path, text).expect("write");
}

/// `command` with a home of its own (HOME and the XDG folders in a scratch folder): a process
/// a test starts never reads or writes the user's preferences, recent files or data folders.
pub fn with_scratch_home(command: &mut std::process::Command) -> &mut std::process::Command {
    let home = std::env::temp_dir().join(format!("servoscope-home-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&home);
    command
        .env("HOME", &home)
        .env("XDG_DATA_HOME", home.join(".local/share"))
        .env("XDG_CONFIG_HOME", home.join(".config"))
        .env("XDG_CACHE_HOME", home.join(".cache"))
        .env("XDG_STATE_HOME", home.join(".local/state"))
}

/// `f` on a thread of its own, given `seconds` before the test fails as a hang: a budget that
/// ends a test of something that once ran for minutes, not a speed asserted.
pub fn within<T: Send + 'static>(seconds: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(std::time::Duration::from_secs(seconds))
        .expect("finished within its time budget")
}
