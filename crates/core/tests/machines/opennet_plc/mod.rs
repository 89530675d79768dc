//! OpenNet's scanned-PLC instructions against `opennet.md`: timers in virtual time at several
//! `scan_ms` (§3, §5.8), counters and the vendor's counter-built timer (§5.9), shift registers
//! (§5.10), comparisons, word logic, shifts and BCD conversions (§5.11, §6), T/C word operands
//! (§4.3), master control and jumps (§5.12), the clocks (§3), the new assembler errors and the
//! MICRO3 warnings (§1, §5.1) and the runner's JSON (§9). Every expected value comes from the
//! spec's rules and examples; the comments derive it.

use crate::common::{get, set};

use servoscope_core::machine::opennet::OpenNet;

use servoscope_core::machine::opennet::assembler::assemble;

use servoscope_core::machine::plc::TimeBase;

use servoscope_core::machine::{Machine, MachineView, Severity};

use std::sync::Arc;

fn plc(src: &str, scan_ms: u32) -> OpenNet {
    let program = assemble(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    OpenNet::with_time(Arc::new(program), TimeBase { scan_ms })
}

/// Run until `n` scans have completed.
fn to_scan(m: &mut OpenNet, n: u64) {
    m.run_until(n, |_| false);
    assert_eq!(m.ticks(), n);
}

/// Run `count` more scans.
fn scans(m: &mut OpenNet, count: u64) {
    let t = m.ticks();
    to_scan(m, t + count);
}

/// One rising edge on `input`: on for one scan, then off for one scan.
fn pulse(m: &mut OpenNet, input: &str) {
    set(m, input, 1);
    scans(m, 1);
    set(m, input, 0);
    scans(m, 1);
}

fn values(m: &OpenNet, names: &[&str]) -> Vec<u64> {
    names.iter().map(|n| get(m, n)).collect()
}

/// `k` R bits from `Rfirst`.
fn r_bits(m: &OpenNet, first: usize, k: usize) -> Vec<u64> {
    (first..first + k)
        .map(|i| get(m, &format!("R{i}")))
        .collect()
}

/// `src` after `LOD M8120` (so its advanced instructions act in scan 0 only), one scan at 10 ms.
/// The program's line n is line n + 1 of the file.
fn once(src: &str) -> OpenNet {
    let mut m = plc(&format!("LOD M8120\n{src}"), 10);
    to_scan(&mut m, 1);
    m
}

fn timer(m: &OpenNet, t: &str) -> (u64, u64, u64) {
    (
        get(m, &format!("{t}.preset")),
        get(m, &format!("{t}.current")),
        get(m, t),
    )
}

fn counter(m: &OpenNet, c: &str) -> (u64, u64, u64) {
    timer(m, c)
}

fn last_error(m: &OpenNet) -> (&'static str, usize, u64) {
    let e = m
        .last_error
        .as_ref()
        .expect("an execution error was recorded");
    (e.kind, e.line, e.tick)
}

/// The increment of a timer instruction in ms (§5.8).
fn increment(op: &str) -> u64 {
    match op {
        "TML" => 1000,
        "TIM" => 100,
        "TMH" => 10,
        "TMS" => 1,
        _ => unreachable!("{op}"),
    }
}

/// The error diagnostics of `src` as (line, message); empty when it assembles.
fn errors(src: &str) -> Vec<(usize, String)> {
    match assemble(src) {
        Ok(_) => Vec::new(),
        Err(e) => e
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .map(|d| {
                assert!(d.to_string().contains(": error: "), "{d}");
                (d.line, d.message.clone())
            })
            .collect(),
    }
}

/// Require an error on `line` whose message contains one of the `|`-separated `words`
/// (case-insensitive; an empty `words` asks only for the line).
fn assert_error(src: &str, line: usize, words: &str) {
    let e = errors(src);
    let found = e.iter().any(|(l, msg)| {
        *l == line
            && (words.is_empty()
                || words
                    .split('|')
                    .any(|w| msg.to_lowercase().contains(&w.to_lowercase())))
    });
    assert!(
        found,
        "{src}\n---\n{e:#?}\nshould have an error on line {line} mentioning {words}"
    );
}

fn assert_assembles(src: &str) {
    if let Err(e) = assemble(src) {
        let text: Vec<String> = e.iter().map(ToString::to_string).collect();
        panic!("{src}\n---\nshould assemble:\n{}", text.join("\n"));
    }
}

/// The warnings of a program that assembles, as (line, message).
fn warnings(src: &str) -> Vec<(usize, String)> {
    let program = assemble(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    program
        .warnings
        .iter()
        .map(|d| {
            assert_eq!(d.severity, Severity::Warning, "{d}");
            assert!(d.to_string().contains(": warning: "), "{d}");
            (d.line, d.message.clone())
        })
        .collect()
}

mod assembler;
mod counters;
mod flow;
mod timers;
mod words;
