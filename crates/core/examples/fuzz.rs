//! The fuzz campaign: mutated and generated programs for every registered dialect, and mutated
//! session files, driven through the library in-process (assemble → run with breakpoints and
//! edits → step, step back, reverse-continue, go to → save → restore → compare), each case
//! under `catch_unwind` and a watchdog's time limit. Four more targets test limits: `includes`
//! (TML include trees on disk, with cycles, bombs and paths out of the folder), `rungs` (one
//! DL205 or OpenNet rung of up to 300 000 elements, assembled, scanned and drawn), `outputs`
//! (what `output::may_write` lets a command write over) and `lessons` (a lesson's tick count
//! and its grading run's time budget). `all` runs every target, the four last.
//!
//! ```text
//! cargo run -p servoscope-core --release --example fuzz -- DIALECT|session|includes|rungs|outputs|lessons|all CASES SEED [--out DIR] [--limit-ms N]
//! cargo run -p servoscope-core --release --example fuzz -- repro DIALECT|session|includes|rungs|outputs|lessons FILE CASE_SEED
//! ```
//!
//! A failing case (a panic, a case over the time limit, or a difference: a restored session or
//! a replayed position that is not the state it should be, or a broken limit) is written to the
//! output folder (default `target/fuzz-failures`) with a one-line reproduction in
//! `failures.txt`. Exit code 0 when every case passed, 1 when any failed, 2 for bad arguments.
//! For overflow checks in a release build: `CARGO_PROFILE_RELEASE_OVERFLOW_CHECKS=true cargo run -p servoscope-core --release --example fuzz`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use servoscope_core::debugger::{Breakpoint, DataTrigger, Debugger, Speed};
use servoscope_core::machine::plc::ladder;
use servoscope_core::machine::project::{IncludeFolders, MAX_FILES, MAX_INCLUDE_DEPTH, Project};
use servoscope_core::machine::{Format, Loc, MachineView, Pos};
use servoscope_core::output::{Input, Output, may_write};
use servoscope_core::registry::{DIALECTS, Dialect, by_name};
use servoscope_core::session::{Session, ViewSettings};

/// A small, fast, seedable generator (SplitMix64): the campaign needs no statistical quality,
/// only cases that are the same for the same seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> Option<&'a T> {
        items.get(self.below(items.len()))
    }
}

/// Numbers that find edges: widths, signs, the limits of every integer type.
const INTERESTING: &[&str] = &[
    "0",
    "1",
    "-1",
    "2",
    "7",
    "8",
    "15",
    "16",
    "31",
    "32",
    "63",
    "64",
    "99",
    "100",
    "127",
    "128",
    "255",
    "256",
    "999",
    "1000",
    "9999",
    "32767",
    "32768",
    "-32768",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "-2147483648",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "99999999999999999999",
    "0x7FFFFFFF",
    "0xFFFFFFFF",
    "0b101",
    "1e12",
    "0.5",
    "-0.0",
    "1000000000",
];

/// Odd text: other scripts, controls, operators, brackets, separators.
const ODD: &[&str] = &[
    "é", "٣", "\u{200b}", "\t", ";", ",", ":", "(", ")", "[", "]", "{", "}", "\"", "'", "//", "/*",
    "#", "$", "%", "@", "!", "=", "==", ".", "..", "\\", "q16(", "bcd(", "REP", "\u{feff}", " ",
    "\n", "\r",
];

/// Words of `text` (what a mutation may copy elsewhere).
fn words(text: &str) -> Vec<&str> {
    text.split(|c: char| c.is_whitespace() || ",;()".contains(c))
        .filter(|w| !w.is_empty())
        .collect()
}

/// A mutation of `text`: lines and words moved, doubled, dropped or replaced, numbers swapped
/// for edge values, odd characters inserted.
fn mutate(text: &str, corpus: &[&str], rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for _ in 0..=rng.below(4) {
        if lines.is_empty() {
            lines.push(String::new());
        }
        let i = rng.below(lines.len());
        match rng.below(9) {
            0 => {
                lines.remove(i);
            }
            1 => {
                let copy = lines[i].clone();
                lines.insert(rng.below(lines.len() + 1), copy);
            }
            2 => {
                let j = rng.below(lines.len());
                lines.swap(i, j);
            }
            3 | 4 => {
                // A number (or any word) replaced by an edge value.
                let line = lines[i].clone();
                let ws = words(&line);
                if let Some(w) = rng.pick(&ws) {
                    let with = rng.pick(INTERESTING).copied().unwrap_or("0");
                    lines[i] = line.replacen(w, with, 1);
                }
            }
            5 => {
                // A word from elsewhere in the corpus.
                let line = lines[i].clone();
                let ws = words(&line);
                if let (Some(w), Some(with)) = (rng.pick(&ws), rng.pick(corpus)) {
                    lines[i] = line.replacen(w, with, 1);
                }
            }
            6 => {
                let odd = rng.pick(ODD).copied().unwrap_or("é");
                let chars: Vec<char> = lines[i].chars().collect();
                let at = rng.below(chars.len() + 1);
                lines[i] = chars[..at].iter().collect::<String>()
                    + odd
                    + &chars[at..].iter().collect::<String>();
            }
            7 => {
                let chars: Vec<char> = lines[i].chars().collect();
                let cut = rng.below(chars.len() + 1);
                lines[i] = chars[..cut].iter().collect();
            }
            _ => {
                // A generated line of words from the corpus.
                let n = 1 + rng.below(4);
                let ws: Vec<&str> = (0..n).filter_map(|_| rng.pick(corpus).copied()).collect();
                lines.insert(
                    rng.below(lines.len() + 1),
                    ws.join(if rng.chance(50) { " " } else { ", " }),
                );
            }
        }
    }
    let mut out = lines.join("\n");
    if rng.chance(80) {
        out.push('\n');
    }
    out
}

/// A generated program: lines of corpus words, mostly instruction-shaped.
fn generate(corpus: &[&str], rng: &mut Rng) -> String {
    let lines = 1 + rng.below(30);
    (0..lines)
        .map(|_| {
            let n = 1 + rng.below(4);
            let ws: Vec<String> = (0..n)
                .map(|_| {
                    if rng.chance(20) {
                        rng.pick(INTERESTING).copied().unwrap_or("0").to_string()
                    } else {
                        rng.pick(corpus).copied().unwrap_or("END").to_string()
                    }
                })
                .collect();
            ws.join(" ")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The whole observable state: run state, fault, position, every location.
fn moment(d: &Debugger) -> String {
    let m = d.machine();
    let mut out = format!(
        "{:?} {:?} {} steps {}\n",
        m.run_state(),
        m.fault().map(|f| (f.kind, f.line, f.message)),
        m.pos(),
        m.steps()
    );
    for (space, info) in m.spaces().iter().enumerate() {
        for index in 0..info.len {
            let loc = Loc::new(space as u8, index);
            let v = m.read(loc);
            if v != 0 {
                out.push_str(&format!("{}:{index}={v:x} ", info.name));
            }
        }
    }
    out
}

/// Let the debugger's goal run for at most `frames` frames, then pause it: a step of an
/// instruction that waits for ever (a move of 2^31 counts) is a user's to pause, not a hang.
/// Each frame has no time budget, so it runs one chunk (they double while cheap): cases cost
/// work, not wall time.
fn settle(d: &mut Debugger, frames: usize) {
    for _ in 0..frames {
        if !d.advance(0.016, Duration::ZERO) {
            return;
        }
    }
    d.pause();
}

/// A location of the program (one it uses, or any).
fn some_loc(m: &dyn MachineView, rng: &mut Rng) -> Option<Loc> {
    let used = m.used();
    if !used.is_empty() && rng.chance(80) {
        return rng.pick(&used).copied();
    }
    let spaces = m.spaces();
    let space = rng.below(spaces.len());
    let len = spaces.get(space)?.len;
    Some(Loc::new(space as u8, rng.below(len as usize + 2) as u32))
}

/// One program case. `Err` names a difference (a state that is not what it should be).
fn program_case(dialect: &'static Dialect, source: &str, rng: &mut Rng) -> Result<bool, String> {
    // As a file is read: one kind of line end, no byte-order mark.
    let source: &str = &servoscope_core::text::normalize(source);
    let settings = dialect.default_settings();
    let lines = source.lines().count().max(1);
    if let Err(diags) = dialect.open_text(source, &settings) {
        for d in &diags {
            if d.line == 0 || d.line > lines + 1 || d.col == 0 {
                return Err(format!("a diagnostic outside the text: {d}"));
            }
        }
        return Ok(false);
    }
    let mut d = Debugger::with_dialect(dialect, "fuzz", source);
    if d.has_errors() {
        return Err("assembled once, not twice".to_string());
    }
    d.set_speed(Speed::Unlimited);
    // Breakpoints: lines (with conditions now and then) and data breakpoints.
    for _ in 0..rng.below(3) {
        let mut b = Breakpoint::line(1 + rng.below(lines + 2));
        if rng.chance(40)
            && let Some(loc) = some_loc(d.machine(), rng)
            && let Some(info) = d.machine().info(loc)
        {
            b = b.with_condition(format!("{} != {}", info.name, rng.below(5)));
        }
        d.add_breakpoint(b);
    }
    if rng.chance(30)
        && let Some(info) = some_loc(d.machine(), rng).and_then(|l| d.machine().info(l))
    {
        d.add_breakpoint(Breakpoint::data(info.name, DataTrigger::Change));
    }
    if let Some(info) = some_loc(d.machine(), rng).and_then(|l| d.machine().info(l)) {
        d.add_watch(format!("{} + 1", info.name), Format::Hex);
    }
    // A run: to a tick (beyond a checkpoint now and then), with edits on the way.
    let far = if rng.chance(10) { 20_000 } else { 2_000 };
    for _ in 0..1 + rng.below(3) {
        let tick = d.pos().tick + rng.below(far) as u64;
        d.goto_tick(tick);
        settle(&mut d, 200);
        if let Some(loc) = some_loc(d.machine(), rng) {
            let _ = match rng.below(3) {
                0 => d.set_value(loc, rng.next() >> rng.below(64)),
                1 => d.toggle_bit(loc, rng.below(80) as u8),
                _ => d.set_input(loc, rng.chance(50)),
            };
        }
        let _ = d.watch_value(0);
    }
    // A run to a breakpoint or the end, or for a few frames of an endless program.
    d.run();
    settle(&mut d, 4);
    for _ in 0..rng.below(5) {
        d.step_command();
        settle(&mut d, 5);
    }
    // New plot channels rebuild the timeline from its events: nothing else changes.
    if rng.chance(30) {
        let before = moment(&d);
        let mut channels = d.channel_choices().to_vec();
        channels.truncate(rng.below(channels.len() + 1));
        d.set_channels(channels);
        if moment(&d) != before {
            return Err(format!(
                "new plot channels changed the state:\n{before}\n{}",
                moment(&d)
            ));
        }
    }
    // Time travel: back and forth must land on the same state.
    let here = d.pos();
    let now = moment(&d);
    d.step_back_command();
    settle(&mut d, 200);
    d.reverse_continue();
    settle(&mut d, 200);
    let furthest = d.furthest();
    let somewhere = Pos {
        tick: rng.next() % (furthest.tick + 1),
        step: (rng.next() % 4) as u32,
    };
    d.goto(somewhere);
    d.goto(here);
    if moment(&d) != now {
        return Err(format!(
            "going back and to {here} again gives another state:\n{now}\n{}",
            moment(&d)
        ));
    }
    // Save and restore: the same moment.
    let text = Session::capture(&d, None, ViewSettings::default())
        .to_ron()
        .map_err(|e| e.to_string())?;
    let back = Session::from_ron(&text, "case.ron")
        .and_then(|s| s.restore("case.ron"))
        .map_err(|e| format!("its own session does not restore: {e}"))?;
    if moment(&back) != now {
        return Err(format!(
            "the restored session differs at {here}:\n{now}\n{}",
            moment(&back)
        ));
    }
    // The runner's bare loop agrees with the debugger's timeline where no edit intervened.
    if d.events().is_empty() {
        let end = Pos::at_tick(furthest.tick);
        d.goto(end);
        let mut runner = dialect
            .open_text(source, &settings)
            .map_err(|_| "assembles")?;
        // A run that stopped at its furthest tick is run by the runner to that stop.
        let stop = u64::from(d.stopped_at_furthest());
        runner.run_headless(&[], end.tick + stop);
        let headless = runner.machine();
        let timeline = d.machine();
        let same = headless.pos() == timeline.pos()
            && headless.run_state() == timeline.run_state()
            && headless.fault() == timeline.fault();
        if !same {
            return Err(format!(
                "the runner ends at {} {:?}, the debugger's timeline at {} {:?}",
                headless.pos(),
                headless.run_state(),
                timeline.pos(),
                timeline.run_state()
            ));
        }
    }
    Ok(true)
}

/// Ticks a mutated session may replay before the case cancels it (a file may ask for a
/// billion; the limit on that is tested elsewhere).
const SESSION_REPLAY: u64 = 500_000;

/// One session case: a mutated session file read, restored, saved and restored again.
fn session_case(text: &str) -> Result<bool, String> {
    let Ok(session) = Session::from_ron(text, "fuzz.ron") else {
        return Ok(false);
    };
    let Ok(d) = session.restore_with("fuzz.ron", &mut |tick| tick < SESSION_REPLAY) else {
        return Ok(false);
    };
    let saved = Session::capture(&d, None, session.view.clone())
        .to_ron()
        .map_err(|e| e.to_string())?;
    let again = Session::from_ron(&saved, "again.ron")
        .and_then(|s| s.restore("again.ron"))
        .map_err(|e| format!("a session it saved does not restore: {e}"))?;
    if moment(&again) != moment(&d) {
        return Err(format!(
            "round trip differs:\n{}\n{}",
            moment(&d),
            moment(&again)
        ));
    }
    Ok(true)
}

/// Sessions to mutate: the lessons, and a session of each dialect's examples with breakpoints,
/// watches, edits and a run.
fn session_seeds() -> Vec<String> {
    let mut seeds = Vec::new();
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("sessions");
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            if let Ok(text) = std::fs::read_to_string(e.path()) {
                seeds.push(text);
            }
        }
    }
    let mut rng = Rng(7);
    for dialect in DIALECTS {
        for (name, source) in dialect.examples {
            let mut d = Debugger::with_dialect(dialect, *name, *source);
            d.set_speed(Speed::Unlimited);
            d.toggle_breakpoint(2);
            d.add_breakpoint(
                Breakpoint::line(3)
                    .with_condition("1 == 1")
                    .with_hit_count(3),
            );
            d.goto_tick(300);
            settle(&mut d, 200);
            if let Some(loc) = some_loc(d.machine(), &mut rng) {
                let _ = d.set_value(loc, 1);
            }
            d.goto_tick(900);
            settle(&mut d, 200);
            if let Ok(text) = Session::capture(&d, None, ViewSettings::default()).to_ron() {
                seeds.push(text);
            }
        }
    }
    seeds
}

/// A mutation of a session's text: its numbers swapped for edge values, pieces doubled or cut.
fn mutate_session(text: &str, rng: &mut Rng) -> String {
    let mut out = text.to_string();
    for _ in 0..=rng.below(3) {
        let chars: Vec<char> = out.chars().collect();
        if chars.is_empty() {
            break;
        }
        let at = rng.below(chars.len());
        let head: String = chars[..at].iter().collect();
        let tail: String = chars[at..].iter().collect();
        out = match rng.below(6) {
            0 | 1 => {
                // The number nearest after `at`, replaced.
                match tail.find(|c: char| c.is_ascii_digit()) {
                    Some(s) => {
                        let rest = &tail[s..];
                        let e = rest
                            .find(|c: char| !c.is_ascii_alphanumeric() && c != '.')
                            .unwrap_or(rest.len());
                        let with = rng.pick(INTERESTING).copied().unwrap_or("0");
                        format!("{head}{}{with}{}", &tail[..s], &rest[e..])
                    }
                    None => out,
                }
            }
            2 => {
                let n = rng.below(40).min(tail.len());
                let cut = tail.char_indices().nth(n).map_or(tail.len(), |(i, _)| i);
                format!("{head}{}", &tail[cut..])
            }
            3 => {
                let n = rng.below(60);
                let piece: String = tail.chars().take(n).collect();
                format!("{head}{piece}{tail}")
            }
            4 => format!("{head}{}{tail}", rng.pick(ODD).copied().unwrap_or("é")),
            _ => {
                // A whole event, breakpoint or mark with an absurd field.
                let odd = [
                    "Line(0x14294967295)",
                    "Bit(bit: 200, on: true)",
                    "RealTime(1e12)",
                    "(tick: 18446744073709551615, step: 4294967295)",
                    "Set(18446744073709551615)",
                    "\"é\"",
                ];
                format!("{head}{}{tail}", rng.pick(&odd).copied().unwrap_or(""))
            }
        };
    }
    out
}

/// The targets besides the dialects and `session`, in the order `all` runs them (last).
const LIMIT_TARGETS: &[&str] = &["includes", "rungs", "outputs", "lessons"];

/// Whether `target` names a campaign.
fn known(target: &str) -> bool {
    target == "session"
        || LIMIT_TARGETS.contains(&target)
        || DIALECTS.iter().any(|d| d.name == target)
}

/// A case's own folder under the system's temporary folder, removed when the case ends (a
/// panicking one too: the guard is dropped while unwinding).
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> Scratch {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let dir = std::env::temp_dir().join(format!(
            "servoscope-fuzz-{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `name` (relative, with `/`) under `dir`, or `None` when it would lead out of it: a repro
/// file may have been edited by hand, and a case writes only in its own folder.
fn inside(dir: &Path, name: &str) -> Option<PathBuf> {
    if name.is_empty() || name.starts_with('/') || name.contains(['\\', ':']) {
        return None;
    }
    let mut depth = 0usize;
    for part in name.split('/') {
        match part {
            "" | "." => {}
            ".." => depth = depth.checked_sub(1)?,
            _ => depth += 1,
        }
    }
    Some(dir.join(name))
}

/// The value of a `key: value` line of a case's text ("" when there is none).
fn field<'a>(text: &'a str, key: &str) -> &'a str {
    text.lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(": "))
        .unwrap_or("")
}

/// What an include tree's folder must never let the program read: the text of a file beside
/// the program's folder, in no message either.
const SECRET: &str = "hunter2";
/// Stands for the case folder's absolute path in a tree's texts (a repro runs in another one).
const SCRATCH_MARK: &str = "@SCRATCH@";
/// Lines a generated tree (not a bomb) expands to at most: far below the assembler's limit, so
/// a case stays cheap and being refused for size is a fault.
const TREE_LINES: usize = 4_000;
/// Statements for the files of a tree, besides the TML examples' lines.
const SIMPLE_TML: &[&str] = &[
    "END;",
    "CACC = 0.5;",
    "CSPD = 20.;",
    "CPOS = 1000L;",
    "CPA;",
    "UPD;",
    "NOP;",
    "// a comment",
    "",
];

/// Lines of the TML examples (no directives): statements for the files of include trees.
fn tml_lines() -> Vec<String> {
    by_name("tml")
        .map(|d| {
            d.examples
                .iter()
                .flat_map(|(_, text)| text.lines())
                .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default()
}

/// The statements of file `k` of a tree: declarations of its own names, assignments to them,
/// simple statements and lines of the examples.
fn statements(k: usize, corpus: &[String], rng: &mut Rng) -> Vec<String> {
    let mut declared: Vec<String> = Vec::new();
    let mut lines = Vec::new();
    for i in 0..1 + rng.below(6) {
        let line = match rng.below(20) {
            0..=4 => {
                let name = format!("v{k}_{i}");
                let line = format!("int {name};");
                declared.push(name);
                line
            }
            5..=9 => match rng.pick(&declared) {
                Some(name) => format!("{name} = {};", rng.below(1000)),
                None => "CPA;".to_string(),
            },
            10..=16 => rng.pick(SIMPLE_TML).copied().unwrap_or("END;").to_string(),
            _ => rng.pick(corpus).cloned().unwrap_or_default(),
        };
        lines.push(line);
    }
    lines
}

/// An `#include` line, now and then indented, upper-case or with a comment.
fn include_line(path: &str, rng: &mut Rng) -> String {
    match rng.below(10) {
        0 => format!("   #include \"{path}\"   // why"),
        1 => format!("#INCLUDE \"{path}\""),
        _ => format!("#include \"{path}\""),
    }
}

/// The path file `k` of a tree (named as under `prog/`) writes to include another, and the file
/// it expands when it names one the tree has without a cycle: a later file spelled in one of
/// the ways the spec allows (or out of the folder and back in), the file itself or the top
/// file (cycles), a missing file, the secret beside the folder (relative, with `\`, in other
/// case, absolute, through a link), a system file.
fn include_path(
    names: &[String],
    k: usize,
    top_cycles: bool,
    rng: &mut Rng,
) -> (String, Option<usize>) {
    let from_lib = names[k].starts_with("lib/");
    // From the includer's folder up to `prog/`.
    let up = if from_lib { "../" } else { "" };
    if k + 1 < names.len() && rng.chance(45) {
        let j = k + 1 + rng.below(names.len() - k - 1);
        let to = &names[j];
        let plain = match to.strip_prefix("lib/") {
            Some(rest) if from_lib => rest.to_string(),
            _ => format!("{up}{to}"),
        };
        let path = match rng.below(7) {
            0 => plain.replace('/', "\\"),
            1 => plain.to_uppercase(),
            2 => format!("./{plain}"),
            3 => format!("{up}../prog/{to}"),
            _ => plain,
        };
        return (path, Some(j));
    }
    let own = names[k]
        .rsplit('/')
        .next()
        .unwrap_or("main.tml")
        .to_string();
    let path = match rng.below(11) {
        0 => own,
        1 if top_cycles => format!("{up}main.tml"),
        1 | 2 => "missing.tml".to_string(),
        3 => format!("{up}../secret.tml"),
        4 => format!("{up}../secret.tml").replace('/', "\\"),
        5 => format!("{up}../SECRET.TML"),
        6 => format!("{SCRATCH_MARK}/secret.tml"),
        7 => format!("{up}lib/../../secret.tml"),
        8 => format!("{up}link.tml"),
        9 => "C:\\Windows\\win.ini".to_string(),
        _ => rng
            .pick(&["/etc/hostname", "/etc/passwd"])
            .copied()
            .unwrap_or("/etc/hostname")
            .to_string(),
    };
    (path, None)
}

/// A tree of 1 to 20 files (names under `prog/`, the top file `main.tml`), each including
/// later files only, so that what a tree expands to is known: each file's expanded size is
/// counted from the last file up, and an include that would pass [`TREE_LINES`] is left out.
fn tree_files(corpus: &[String], top_cycles: bool, rng: &mut Rng) -> Vec<(String, String)> {
    let n = 1 + rng.below(20);
    let names: Vec<String> = (0..n)
        .map(|k| match k {
            0 => "main.tml".to_string(),
            _ if rng.chance(30) => format!("lib/f{k}.tml"),
            _ => format!("f{k}.tml"),
        })
        .collect();
    let mut sizes = vec![0usize; n];
    let mut texts = vec![String::new(); n];
    for k in (0..n).rev() {
        let mut lines = statements(k, corpus, rng);
        let mut size = lines.len();
        for _ in 0..rng.below(7) {
            let (path, expands) = include_path(&names, k, top_cycles, rng);
            if let Some(j) = expands {
                if size + 1 + sizes[j] > TREE_LINES {
                    continue;
                }
                size += sizes[j];
            }
            size += 1;
            let at = rng.below(lines.len() + 1);
            lines.insert(at, include_line(&path, rng));
        }
        sizes[k] = size;
        texts[k] = lines.join("\n") + "\n";
    }
    names.into_iter().zip(texts).collect()
}

/// An include bomb: each file includes the next four times, down to a leaf. A leaf of one long
/// line passes the assembler's limit on characters in a few hundred lines; a short one passes
/// its limit on lines (a million: slower, so rarer).
fn bomb_files(rng: &mut Rng) -> Vec<(String, String)> {
    let long = rng.chance(80);
    // 4^5 leaves of 60 000 characters pass 16 MiB; 4^10 one-line leaves pass 2^20 lines.
    let least = if long { 5 } else { 10 };
    let depth = least + rng.below(MAX_INCLUDE_DEPTH - least + 1);
    let names: Vec<String> = (0..=depth)
        .map(|k| match k {
            0 => "main.tml".to_string(),
            _ if rng.chance(30) => format!("lib/b{k}.tml"),
            _ => format!("b{k}.tml"),
        })
        .collect();
    let mut files = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let mut text = format!("// level {k}\n");
        match names.get(k + 1) {
            Some(next) => {
                let from_lib = name.starts_with("lib/");
                let plain = match next.strip_prefix("lib/") {
                    Some(rest) if from_lib => rest.to_string(),
                    _ if from_lib => format!("../{next}"),
                    _ => next.clone(),
                };
                for _ in 0..4 {
                    let path = match rng.below(4) {
                        0 => plain.replace('/', "\\"),
                        1 => plain.to_uppercase(),
                        _ => plain.clone(),
                    };
                    text.push_str(&include_line(&path, rng));
                    text.push('\n');
                }
            }
            None if long => text = format!("// {}\n", "x".repeat(60_000)),
            None => {}
        }
        files.push((name.clone(), text));
    }
    files
}

/// An include tree as a case's text: `key: value` lines, then each file after a
/// `==> PATH <==` line (PATH under the case's folder; the program's files under `prog/`, the
/// secret beside them).
fn include_tree(corpus: &[String], rng: &mut Rng) -> String {
    let bomb = rng.below(40) == 0;
    let allow_lib = rng.chance(20);
    let link = rng.chance(30);
    let yes = |b: bool| if b { "yes" } else { "no" };
    let mut out = format!(
        "bomb: {}\nallow: {}\nlink: {}\n",
        yes(bomb),
        if allow_lib { "lib" } else { "none" },
        yes(link)
    );
    // With a folder allowed, `../prog/main.tml` is a second name of the top file, and a cycle
    // through it expands the whole tree again: no top-file cycles there, to keep cases small.
    let files = if bomb {
        bomb_files(rng)
    } else {
        tree_files(corpus, !allow_lib, rng)
    };
    for (name, text) in files {
        out.push_str(&format!("==> prog/{name} <==\n{text}"));
    }
    out.push_str(&format!("==> secret.tml <==\n{SECRET} secret;\n"));
    out
}

/// The header and the files (path, text) of [`include_tree`]'s text.
fn parse_tree(input: &str) -> (&str, Vec<(String, String)>) {
    let (header, body) = input.split_at(input.find("==> ").unwrap_or(input.len()));
    let mut files: Vec<(String, String)> = Vec::new();
    for line in body.lines() {
        if let Some(name) = line
            .strip_prefix("==> ")
            .and_then(|l| l.strip_suffix(" <=="))
        {
            files.push((name.to_string(), String::new()));
        } else if let Some((_, text)) = files.last_mut() {
            text.push_str(line);
            text.push('\n');
        }
    }
    (header, files)
}

/// One include tree: written to disk, loaded and assembled. Nothing outside the top file's
/// folder may be loaded (by name or by text) or quoted, a bomb must be refused for its size and
/// a small tree must not be.
fn includes_case(input: &str) -> Result<bool, String> {
    let (header, files) = parse_tree(input);
    let bomb = field(header, "bomb") == "yes";
    let scratch = Scratch::new();
    let root = scratch.0.to_string_lossy().replace('\\', "/");
    for (name, text) in &files {
        let Some(path) = inside(&scratch.0, name) else {
            continue;
        };
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).expect("a folder of the tree");
        }
        std::fs::write(&path, text.replace(SCRATCH_MARK, &root)).expect("a file of the tree");
    }
    let prog = scratch.0.join("prog");
    std::fs::create_dir_all(prog.join("lib")).expect("the tree's folders");
    #[cfg(unix)]
    {
        // A link in the folder to the secret outside it is outside.
        if field(header, "link") == "yes" {
            std::os::unix::fs::symlink("../secret.tml", prog.join("link.tml")).expect("a link");
        }
    }
    // An allowed folder inside the top folder lets nothing more out.
    let defaults = field(header, "allow") != "lib";
    let folders = IncludeFolders {
        allowed: if defaults {
            Vec::new()
        } else {
            vec![prog.join("lib")]
        },
    };
    let tml = by_name("tml").ok_or("no TML dialect")?;
    let project = tml
        .load_with(&prog.join("main.tml"), &folders)
        .map_err(|e| format!("the top file does not load: {e}"))?;
    if project.files.len() > MAX_FILES {
        return Err(format!("{} files loaded", project.files.len()));
    }
    if defaults
        && let Some(f) = project
            .files
            .iter()
            .find(|f| f.name == ".." || f.name.starts_with("../") || f.name.starts_with('/'))
    {
        return Err(format!(
            "a file outside the top folder was loaded: {}",
            f.name
        ));
    }
    if let Some(f) = project.files.iter().find(|f| f.text.contains(SECRET)) {
        return Err(format!(
            "the file beside the folder was loaded as {}",
            f.name
        ));
    }
    match tml.open_program(&project, &tml.default_settings()) {
        Ok(_) if bomb => Err("an include bomb assembled".to_string()),
        Ok(_) => Ok(true),
        Err(diags) => {
            if let Some(d) = diags.iter().find(|d| d.message.contains(SECRET)) {
                return Err(format!(
                    "a diagnostic quotes the file beside the folder: {d}"
                ));
            }
            let grows = diags.iter().any(|d| d.message.contains("grows past"));
            if bomb && !grows {
                let first = diags.first().map(ToString::to_string).unwrap_or_default();
                return Err(format!(
                    "an include bomb is not refused for its size: {first}"
                ));
            }
            if !bomb && defaults && grows {
                return Err(format!(
                    "a tree of at most {TREE_LINES} lines is refused for its size"
                ));
            }
            Ok(false)
        }
    }
}

/// The most bytes a drawn ladder may have: a long rung must not become an unbounded file.
const MAX_SVG_BYTES: usize = 64 << 20;

/// One rung of many elements as a case's text: the dialect's name on the first line, then the
/// program. Mostly short; one case in 50 up to 300 000 elements.
fn long_rung(rng: &mut Rng) -> String {
    let n = if rng.below(50) == 0 {
        1 + rng.below(300_000)
    } else if rng.chance(70) {
        1 + rng.below(199)
    } else {
        200 + rng.below(1_801)
    };
    let (dialect, first, contacts, out, boxes) = if rng.chance(50) {
        (
            "dl205",
            "STR X0",
            ["AND X1", "OR X2", "ANDN C0"],
            "OUT Y0",
            None,
        )
    } else {
        let boxes = rng.chance(40).then_some("ADD(W) D0 D1 D2");
        (
            "opennet",
            "LOD I0",
            ["AND I1", "OR I2", "ANDN M0"],
            "OUT Q0",
            boxes,
        )
    };
    // One kind of contact all along, or a mix (ORs amid ANDs nest branches).
    let mode = rng.below(4);
    let mut text = String::with_capacity(16 * n + 64);
    text.push_str(&format!("{dialect}\n{first}\n"));
    for _ in 0..n {
        let element = match (boxes, mode) {
            (Some(b), _) => b,
            (None, 3) => contacts[rng.below(3)],
            (None, m) => contacts[m],
        };
        text.push_str(element);
        text.push('\n');
    }
    if boxes.is_none() {
        text.push_str(out);
        text.push('\n');
    }
    text.push_str("END\n");
    text
}

/// One long rung: it assembles (or is refused), scans once and draws within the time limit,
/// and its drawing stays below [`MAX_SVG_BYTES`].
fn rungs_case(input: &str) -> Result<bool, String> {
    let (name, program) = input.split_once('\n').unwrap_or((input, ""));
    let dialect = by_name(name).ok_or_else(|| format!("no dialect '{name}'"))?;
    let project = Project::single(format!("p.{}", dialect.extensions[0]), program);
    let Ok(mut engine) = dialect.open_program(&project, &dialect.default_settings()) else {
        return Ok(false);
    };
    engine.run_headless(&[], 1);
    let m = engine.machine();
    if let Some(diagram) = ladder::with_comments(m, program, dialect.classify) {
        let svg = ladder::svg_of(m, &diagram, "t");
        if svg.len() >= MAX_SVG_BYTES {
            return Err(format!(
                "a rung of {} lines draws {} bytes of SVG",
                program.lines().count(),
                svg.len()
            ));
        }
    }
    Ok(true)
}

/// The kinds of output, as a case's text names them.
const OUTPUTS: &[Output] = &[
    Output::LadderSvg,
    Output::Trace,
    Output::LogCsv,
    Output::Session,
];
/// Where an output case writes: the fixtures of [`outputs_case`] (the program, its links and
/// other names of it, files of other kinds, our own earlier outputs, a folder, link loops) and
/// new names.
const OUTPUT_TARGETS: &[&str] = &[
    "p.dl205",
    "./p.dl205",
    "d/../p.dl205",
    "P.DL205",
    "s.ron",
    "notes.txt",
    "t.jsonl",
    "ours.svg",
    "log.csv",
    "empty.svg",
    "d",
    "d/",
    "link.svg",
    "out_link.svg",
    "chain.svg",
    "hard.svg",
    "loop.svg",
    "dangling.svg",
    "new.svg",
    "new.jsonl",
    "new.csv",
    "new.ron",
    "d/new.svg",
    "missing/x.svg",
];

/// An output case as text: the target, the kind of output and whether overwriting is allowed.
fn output_target(rng: &mut Rng) -> String {
    format!(
        "target: {}\nkind: {:?}\noverwrite: {}\n",
        rng.pick(OUTPUT_TARGETS).copied().unwrap_or("new.svg"),
        rng.pick(OUTPUTS).copied().unwrap_or(Output::LadderSvg),
        if rng.chance(50) { "yes" } else { "no" }
    )
}

/// Whether `a` and `b` are one file once links are followed (on Unix one inode: a hard link is
/// the same file).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b))
            && x.dev() == y.dev()
            && x.ino() == y.ino()
        {
            return true;
        }
    }
    matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
}

/// One output case: `may_write` never lets a command write over its input, nor without
/// `overwrite` over a file of another kind; a write it allows leaves the program as it was.
fn outputs_case(input: &str) -> Result<bool, String> {
    let (name, overwrite) = (field(input, "target"), field(input, "overwrite") == "yes");
    let Some(kind) = OUTPUTS
        .iter()
        .copied()
        .find(|k| format!("{k:?}") == field(input, "kind"))
    else {
        return Err(format!("no output kind '{}'", field(input, "kind")));
    };
    let scratch = Scratch::new();
    let dir = &scratch.0;
    let Some(target) = inside(dir, name) else {
        return Err(format!("'{name}' is not a name in the case's folder"));
    };
    let program_text = "STR X0\nOUT Y0\nEND\n";
    let fixtures = [
        ("p.dl205", program_text.to_string()),
        (
            "s.ron",
            "(format: 2, dialect: \"dl205\", program: \"END\\n\")\n".to_string(),
        ),
        ("notes.txt", "my notes\n".to_string()),
        (
            "t.jsonl",
            "{\"n\":1,\"tick\":0,\"step\":0,\"mnemonic\":\"STR\",\"written\":{}}\n".to_string(),
        ),
        (
            "ours.svg",
            format!(
                "<svg xmlns=\"http://www.w3.org/2000/svg\">\n{}\n</svg>\n",
                ladder::SVG_MARK
            ),
        ),
        (
            "log.csv",
            format!("{}\n", servoscope_core::output::LOG_CSV_HEADER),
        ),
        ("empty.svg", String::new()),
    ];
    for (file, text) in &fixtures {
        std::fs::write(dir.join(file), text).expect("a fixture");
    }
    std::fs::create_dir(dir.join("d")).expect("a folder");
    #[cfg(unix)]
    {
        let links = [
            ("link.svg", "p.dl205"),
            ("out_link.svg", "notes.txt"),
            ("chain.svg", "link.svg"),
            ("loop.svg", "loop.svg"),
            ("dangling.svg", "gone.svg"),
        ];
        for (link, to) in links {
            std::os::unix::fs::symlink(to, dir.join(link)).expect("a link");
        }
        std::fs::hard_link(dir.join("p.dl205"), dir.join("hard.svg")).expect("a hard link");
    }
    let program = dir.join("p.dl205");
    let inputs = [Input::new(&program, "the program")];
    let is = |file: &str| same_file(&target, &dir.join(file));
    let verdict = may_write(&target, kind, &inputs, overwrite);
    if verdict.is_ok() {
        if is("p.dl205") {
            return Err(format!(
                "{kind:?} may be written over the program through {name}"
            ));
        }
        if !overwrite && (is("notes.txt") || (kind != Output::Session && is("s.ron"))) {
            return Err(format!(
                "{kind:?} may replace another kind of file, {name}, without overwrite"
            ));
        }
        let _ = servoscope_core::atomic::write_atomically(&target, |w| w.write_all(b"x"));
    }
    if std::fs::read_to_string(&program).ok().as_deref() != Some(program_text) {
        return Err(format!("writing {kind:?} to {name} changed the program"));
    }
    Ok(verdict.is_ok())
}

/// A lesson session as a case's text: a PLC program, checks, now and then an input event,
/// and a tick count from none to far past the limit (those rarer: grading them costs its time
/// budget).
fn lesson_session(rng: &mut Rng) -> String {
    let (dialect, program, out, input) = if rng.chance(60) {
        ("dl205", "STR X0\\nOUT Y0\\nEND\\n", "Y0", "X0")
    } else {
        ("opennet", "LOD I0\\nOUT Q0\\nEND\\n", "Q0", "I0")
    };
    let ticks = if rng.chance(10) {
        let huge = [10_000_000, 1_000_000_000, u64::MAX, rng.next()];
        rng.pick(&huge).copied().unwrap_or(u64::MAX)
    } else {
        let small = [0, 1, 10, 1000, rng.below(5000) as u64];
        rng.pick(&small).copied().unwrap_or(0)
    };
    let max_ticks = if rng.chance(10) {
        "None".to_string()
    } else {
        format!("Some({ticks})")
    };
    let choices = [
        format!("{out} == 0"),
        format!("{out} == 1"),
        input.to_string(),
        format!("{out} == {input}"),
        "1 +".to_string(),
    ];
    let checks: Vec<String> = (0..1 + rng.below(3))
        .filter_map(|_| rng.pick(&choices).map(|c| format!("\"{c}\"")))
        .collect();
    let events = if rng.chance(40) {
        let at = [0, 5, 999, u64::MAX];
        format!(
            "events: [(at: (tick: {}, step: 0), location: \"{}\", change: Set(1))], ",
            rng.pick(&at).copied().unwrap_or(0),
            if rng.chance(90) { input } else { "Z9" }
        )
    } else {
        String::new()
    };
    format!(
        "(format: {}, dialect: \"{dialect}\", program: \"{program}\", {events}lesson: Some((title: \"t\", steps: [(text: \"s\", checks: [{}])], max_ticks: {max_ticks})))\n",
        2 + rng.below(2),
        checks.join(", ")
    )
}

/// One lesson: graded over at most [`servoscope_core::lesson::MAX_LESSON_TICKS`], within its
/// time budget; a run the budget stopped passes no check.
fn lessons_case(input: &str, rng: &mut Rng) -> Result<bool, String> {
    use servoscope_core::lesson::{MAX_LESSON_TICKS, grading_run, grading_ticks};
    let Ok(session) = Session::from_ron(input, "l.ron") else {
        return Ok(false);
    };
    let Some(lesson) = session.lesson.clone() else {
        return Err("the lesson was lost in reading".to_string());
    };
    if let Some(asked) = lesson.max_ticks.filter(|&t| t > MAX_LESSON_TICKS) {
        return Err(format!("a lesson of {asked} ticks was read as it was"));
    }
    let dialect = session.dialect();
    let Ok(engine) = dialect.open_program(
        &session.project(),
        &dialect.settings_from(&session.settings),
    ) else {
        return Ok(false);
    };
    let ticks = grading_ticks(&lesson, None, dialect);
    if ticks > MAX_LESSON_TICKS {
        return Err(format!("graded over {ticks} ticks"));
    }
    // A budget of nothing too: the deadline has passed before the first slice.
    let budget = Duration::from_millis(rng.pick(&[0, 1, 10, 200]).copied().unwrap_or(200));
    let started = Instant::now();
    let Ok(grading) = grading_run(engine.as_ref(), &session, &lesson, ticks, "l.ron", budget)
    else {
        return Ok(false);
    };
    let took = started.elapsed();
    if took > budget + Duration::from_secs(2) {
        return Err(format!(
            "grading {ticks} ticks took {took:?} on a budget of {budget:?}"
        ));
    }
    let checks: usize = lesson.steps.iter().map(|s| s.checks.len()).sum();
    if grading.outcomes.len() != checks {
        return Err(format!(
            "{} outcomes of {checks} checks",
            grading.outcomes.len()
        ));
    }
    if !grading.finished && grading.outcomes.iter().any(|o| o.pass) {
        return Err("a check passed on a run the time budget stopped".to_string());
    }
    let reached = grading.run.machine().pos();
    if reached.tick > ticks {
        return Err(format!(
            "graded over {ticks} ticks, the run is at {reached}"
        ));
    }
    Ok(true)
}

#[derive(Default)]
struct Counts {
    cases: u64,
    accepted: u64,
    panics: u64,
    differences: u64,
}

/// What the watchdog sees: the case under way and when it began.
struct Watch {
    started: Mutex<Option<(Instant, String, PathBuf)>>,
    stop: AtomicBool,
}

fn save_failure(out: &Path, kind: &str, target: &str, case_seed: u64, input: &str, why: &str) {
    let _ = std::fs::create_dir_all(out);
    let ext = match target {
        "session" | "lessons" => "ron".to_string(),
        name => DIALECTS
            .iter()
            .find(|d| d.name == name)
            .map_or("txt".to_string(), |d| d.extensions[0].to_string()),
    };
    let file = out.join(format!("{kind}-{target}-{case_seed:016x}.{ext}"));
    let _ = std::fs::write(&file, input);
    let line = format!(
        "{kind}: {} | cargo run -p servoscope-core --release --example fuzz -- repro {target} {} {case_seed}\n",
        why.lines().next().unwrap_or(""),
        file.display()
    );
    use std::io::Write as _;
    if let Ok(mut f) = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(out.join("failures.txt"))
    {
        let _ = f.write_all(line.as_bytes());
    }
    eprint!("{line}");
}

/// The case's input, from its seed: all a limit target's case is (its files, program,
/// target or session), so a repro from the saved file is the same case.
fn input_for(target: &str, seeds: &[String], corpus: &[&str], rng: &mut Rng) -> String {
    match target {
        "session" => {
            let base = rng.pick(seeds).cloned().unwrap_or_default();
            mutate_session(&base, rng)
        }
        "includes" => include_tree(seeds, rng),
        "rungs" => long_rung(rng),
        "outputs" => output_target(rng),
        "lessons" => lesson_session(rng),
        _ => {
            if rng.chance(15) {
                generate(corpus, rng)
            } else {
                let base = rng.pick(seeds).cloned().unwrap_or_default();
                mutate(&base, corpus, rng)
            }
        }
    }
}

fn run_case(target: &str, input: &str, rng: &mut Rng) -> Result<bool, String> {
    match target {
        "session" => session_case(input),
        "includes" => includes_case(input),
        "rungs" => rungs_case(input),
        "outputs" => outputs_case(input),
        "lessons" => lessons_case(input, rng),
        name => match DIALECTS.iter().find(|d| d.name == name) {
            Some(dialect) => program_case(dialect, input, rng),
            None => Err(format!("no target '{name}'")),
        },
    }
}

fn seeds_of(target: &str) -> Vec<String> {
    match target {
        "session" => session_seeds(),
        "includes" => tml_lines(),
        name => DIALECTS
            .iter()
            .find(|d| d.name == name)
            .map(|d| {
                let mut seeds: Vec<String> =
                    d.examples.iter().map(|(_, s)| s.to_string()).collect();
                seeds.push(d.new_program.to_string());
                seeds
            })
            .unwrap_or_default(),
    }
}

fn campaign(target: &str, cases: u64, seed: u64, out: &Path, watch: &Watch) -> Counts {
    let seeds = seeds_of(target);
    let all: String = seeds.join("\n");
    let corpus: Vec<&str> = words(&all);
    let mut counts = Counts::default();
    let started = Instant::now();
    for case in 0..cases {
        let case_seed = seed
            .wrapping_mul(0x100_0000_01B3)
            .wrapping_add(case)
            .wrapping_add(target.len() as u64 * 0x9E37);
        let mut rng = Rng(case_seed);
        let input = input_for(target, &seeds, &corpus, &mut rng);
        if let Ok(mut w) = watch.started.lock() {
            let file = out.join(format!("hang-{target}-{case_seed:016x}"));
            *w = Some((Instant::now(), input.clone(), file));
        }
        let result = catch_unwind(AssertUnwindSafe(|| run_case(target, &input, &mut rng)));
        if let Ok(mut w) = watch.started.lock() {
            *w = None;
        }
        counts.cases += 1;
        match result {
            Ok(Ok(accepted)) => counts.accepted += u64::from(accepted),
            Ok(Err(why)) => {
                counts.differences += 1;
                save_failure(out, "difference", target, case_seed, &input, &why);
            }
            Err(panic) => {
                counts.panics += 1;
                let why = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a panic".to_string());
                save_failure(out, "panic", target, case_seed, &input, &why);
            }
        }
        if (case + 1) % 10_000 == 0 {
            eprintln!(
                "{target}: {} cases, {:.0}/s",
                case + 1,
                (case + 1) as f64 / started.elapsed().as_secs_f64()
            );
        }
    }
    counts
}

fn usage() -> ExitCode {
    let limits = LIMIT_TARGETS.join("|");
    eprintln!(
        "usage: fuzz DIALECT|session|{limits}|all CASES SEED [--out DIR] [--limit-ms N]\n       fuzz repro DIALECT|session|{limits} FILE CASE_SEED\n(dialects: {})",
        DIALECTS
            .iter()
            .map(|d| d.name)
            .collect::<Vec<_>>()
            .join(", ")
    );
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("repro") {
        let (Some(target), Some(file), Some(seed)) = (args.get(1), args.get(2), args.get(3)) else {
            return usage();
        };
        let Ok(seed) = seed.parse::<u64>() else {
            return usage();
        };
        if !known(target) {
            return usage();
        }
        let Ok(input) = std::fs::read_to_string(file) else {
            eprintln!("cannot read {file}");
            return ExitCode::from(2);
        };
        // The same choices as the campaign made: its generator after making the input.
        let mut rng = Rng(seed);
        let seeds = seeds_of(target);
        let all = seeds.join("\n");
        let corpus = words(&all);
        let _ = input_for(target, &seeds, &corpus, &mut rng);
        return match run_case(target, &input, &mut rng) {
            Ok(_) => {
                println!("passed");
                ExitCode::SUCCESS
            }
            Err(why) => {
                println!("{why}");
                ExitCode::from(1)
            }
        };
    }
    let (Some(target), Some(cases), Some(seed)) = (args.first(), args.get(1), args.get(2)) else {
        return usage();
    };
    let (Ok(cases), Ok(seed)) = (cases.parse::<u64>(), seed.parse::<u64>()) else {
        return usage();
    };
    let mut out =
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("target/fuzz-failures");
    let mut limit = Duration::from_secs(20);
    let mut rest = args[3..].iter();
    while let Some(flag) = rest.next() {
        match (flag.as_str(), rest.next()) {
            ("--out", Some(dir)) => out = PathBuf::from(dir),
            ("--limit-ms", Some(ms)) => match ms.parse() {
                Ok(ms) => limit = Duration::from_millis(ms),
                Err(_) => return usage(),
            },
            _ => return usage(),
        }
    }
    let targets: Vec<&str> = match target.as_str() {
        "all" => DIALECTS
            .iter()
            .map(|d| d.name)
            .chain(["session"])
            .chain(LIMIT_TARGETS.iter().copied())
            .collect(),
        name if known(name) => vec![name],
        _ => return usage(),
    };
    // Panics are counted and saved, not printed as they happen.
    std::panic::set_hook(Box::new(|_| {}));
    let watch = Arc::new(Watch {
        started: Mutex::new(None),
        stop: AtomicBool::new(false),
    });
    let current_target = Arc::new(AtomicU64::new(0));
    {
        // The watchdog: a case over the limit is a hang, saved before the process ends.
        let (watch, out) = (Arc::clone(&watch), out.clone());
        let current = Arc::clone(&current_target);
        std::thread::spawn(move || {
            while !watch.stop.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(100));
                let over = watch.started.lock().ok().and_then(|w| {
                    w.as_ref()
                        .filter(|(since, _, _)| since.elapsed() > limit)
                        .map(|(_, input, file)| (input.clone(), file.clone()))
                });
                if let Some((input, file)) = over {
                    let _ = std::fs::create_dir_all(&out);
                    let _ = std::fs::write(&file, &input);
                    eprintln!(
                        "hang: a case ran over {} ms (target #{}): {}",
                        limit.as_millis(),
                        current.load(Ordering::Relaxed),
                        file.display()
                    );
                    std::process::exit(1);
                }
            }
        });
    }
    let mut failed = false;
    for (i, target) in targets.iter().enumerate() {
        current_target.store(i as u64, Ordering::Relaxed);
        let started = Instant::now();
        let c = campaign(target, cases, seed, &out, &watch);
        let seconds = started.elapsed().as_secs_f64();
        println!(
            "{target}: {} cases in {seconds:.1} s ({:.0}/s): {} accepted, {} panics, 0 hangs, {} differences",
            c.cases,
            c.cases as f64 / seconds.max(1e-9),
            c.accepted,
            c.panics,
            c.differences
        );
        failed |= c.panics + c.differences > 0;
    }
    watch.stop.store(true, Ordering::Relaxed);
    if failed {
        println!("failures are in {}", out.display());
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
