//! Time travel at 10 M ticks of history (goals: step back ≤ 10 ms, go to any tick ≤ 50 ms,
//! memory ≤ 64 bytes a tick), and saving / loading a session at 10 M ticks.
//!
//! `cargo bench --bench time_travel`
//!
//! The motor moves back and forth all the time, so the trace stores a sample on about every
//! other tick (whenever R0, R1, R6 or R7 changes; at constant speed the follower's velocity
//! settles and some ticks change nothing). A sample costs about 27 bytes at most.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use servoscope_core::debugger::{Debugger, Speed};

use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::silverlode::view::io;
use servoscope_core::session::{Session, ViewSettings};

const TICKS: u64 = 10_000_000;

const PROGRAM: &str = "\
      WRP 30, 7
loop: MRV 3000, 38650, 16106128
      CLC INC, 20
      CLD Q_INIT, 10, 40, 4
      MRV -3000, 38650, 16106128
      CLX MULT_S, 21, 20, 20
      JMP loop
";

fn sl(d: &Debugger) -> &SilverLode {
    d.machine_as::<SilverLode>().expect("a SilverLode machine")
}

fn history() -> Debugger {
    let mut d = Debugger::new("bench.qsl", PROGRAM);
    d.set_speed(Speed::Unlimited);
    d.set_input(io(0), true).expect("an input");
    d.goto_tick(TICKS);
    while d.advance(0.016, Duration::from_secs(60)) {}
    assert_eq!(d.machine().ticks(), TICKS);
    d
}

/// Ticks spread over the whole history, different every iteration.
fn tick_for(i: u64) -> u64 {
    (i.wrapping_mul(2_654_435_761) % TICKS).max(1)
}

fn benches(c: &mut Criterion) {
    let mut d = history();
    let bytes = d.history_bytes();
    eprintln!(
        "history of {TICKS} ticks: {} MB, {:.1} bytes a tick (trace samples: {})",
        bytes >> 20,
        bytes as f64 / TICKS as f64,
        d.trace().len()
    );
    let mut group = c.benchmark_group("time travel at 10M ticks");
    group.bench_function("go to a tick anywhere in the history", |b| {
        let mut i = 0;
        b.iter(|| {
            i += 1;
            d.goto_tick(tick_for(i));
            black_box(sl(&d).reg(1))
        })
    });
    group.bench_function("step back one tick", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for i in 0..iters {
                d.goto_tick(tick_for(i + 1));
                let start = Instant::now();
                d.step_back_tick();
                total += start.elapsed();
            }
            total
        })
    });
    group.bench_function("step back one command", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for i in 0..iters {
                d.goto_tick(tick_for(i + 1));
                let start = Instant::now();
                d.step_back_command();
                total += start.elapsed();
            }
            total
        })
    });
    // "Who wrote this?" at the end of the history: R20 is written every round; R30 once, by
    // the first command, so the whole history is searched.
    d.goto_tick(TICKS);
    let end = d.pos();
    for (name, register) in [
        ("R20 (written every round)", 20),
        ("R30 (written once, at the start)", 30),
    ] {
        let loc = servoscope_core::machine::Loc::new(0, register);
        group.bench_function(format!("who wrote {name}"), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    d.goto(end);
                    let start = Instant::now();
                    black_box(d.who_wrote(loc));
                    total += start.elapsed();
                }
                total
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("session at 10M ticks");
    group.sample_size(10);
    d.goto_tick(TICKS);
    let path = std::env::temp_dir().join(format!("servoscope-bench-{}.ron", std::process::id()));
    group.bench_function("save", |b| {
        b.iter(|| {
            Session::capture(&d, None, ViewSettings::default())
                .save(&path)
                .unwrap()
        })
    });
    group.bench_function("load (replays 10M ticks)", |b| {
        b.iter(|| {
            let s = Session::load(&path).unwrap();
            black_box(s.restore("bench").unwrap().machine().ticks())
        })
    });
    group.finish();
    let _ = std::fs::remove_file(&path);
}

criterion_group!(time_travel_benches, benches);
criterion_main!(time_travel_benches);
