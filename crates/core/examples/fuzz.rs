//! The fuzz campaign: mutated and generated programs for every registered dialect, and mutated
//! session files, driven through the library in-process (assemble → run with breakpoints and
//! edits → step, step back, reverse-continue, go to → save → restore → compare), each case
//! under `catch_unwind` and a watchdog's time limit.
//!
//! ```text
//! cargo run -p servoscope-core --release --example fuzz -- DIALECT|session|all CASES SEED [--out DIR] [--limit-ms N]
//! cargo run -p servoscope-core --release --example fuzz -- repro DIALECT|session FILE CASE_SEED
//! ```
//!
//! A failing case (a panic, a case over the time limit, or a difference: a restored session or
//! a replayed position that is not the state it should be) is written to the output folder
//! (default `target/fuzz-failures`) with a one-line reproduction in `failures.txt`. Exit code
//! 0 when every case passed, 1 when any failed, 2 for bad arguments. For overflow checks in a
//! release build: `CARGO_PROFILE_RELEASE_OVERFLOW_CHECKS=true cargo run -p servoscope-core --release --example fuzz`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use servoscope_core::debugger::{Breakpoint, DataTrigger, Debugger, Speed};
use servoscope_core::machine::{Format, Loc, MachineView, Pos};
use servoscope_core::registry::{DIALECTS, Dialect};
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
        "session" => "ron".to_string(),
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

/// The case's input, from its seed.
fn input_for(target: &str, seeds: &[String], corpus: &[&str], rng: &mut Rng) -> String {
    if target == "session" {
        let base = rng.pick(seeds).cloned().unwrap_or_default();
        return mutate_session(&base, rng);
    }
    if rng.chance(15) {
        generate(corpus, rng)
    } else {
        let base = rng.pick(seeds).cloned().unwrap_or_default();
        mutate(&base, corpus, rng)
    }
}

fn run_case(target: &str, input: &str, rng: &mut Rng) -> Result<bool, String> {
    match DIALECTS.iter().find(|d| d.name == target) {
        Some(dialect) => program_case(dialect, input, rng),
        None => session_case(input),
    }
}

fn seeds_of(target: &str) -> Vec<String> {
    match DIALECTS.iter().find(|d| d.name == target) {
        Some(d) => {
            let mut seeds: Vec<String> = d.examples.iter().map(|(_, s)| s.to_string()).collect();
            seeds.push(d.new_program.to_string());
            seeds
        }
        None => session_seeds(),
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
    eprintln!(
        "usage: fuzz DIALECT|session|all CASES SEED [--out DIR] [--limit-ms N]\n       fuzz repro DIALECT|session FILE CASE_SEED\n(dialects: {})",
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
        "all" => DIALECTS.iter().map(|d| d.name).chain(["session"]).collect(),
        "session" => vec!["session"],
        name if DIALECTS.iter().any(|d| d.name == name) => vec![name],
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
