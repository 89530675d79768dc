//! What recording a run costs: the bare machine (the headless runner's path) against the same
//! run recorded as the window records it (checkpoints, the plot's trace with the dialect's
//! default channels, and the write sets of "who wrote this?"), for every dialect.
//!
//! `cargo bench --bench recording`

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use servoscope_core::debugger::{Debugger, Speed};
use servoscope_core::registry;

#[path = "common/programs.rs"]
mod programs;

fn benches(c: &mut Criterion) {
    let cases: [(&str, String, u64); 4] = [
        ("silverlode", programs::ARITHMETIC.to_string(), 1_000_000),
        ("tml", programs::TML_ARITHMETIC.to_string(), 100_000),
        ("opennet", programs::opennet_program(), 10_000),
        ("dl205", programs::dl205_program(), 10_000),
    ];
    let mut group = c.benchmark_group("recording (ticks)");
    group.sample_size(20);
    for (name, source, ticks) in cases {
        let dialect = registry::by_name(name).expect("a registered dialect");
        let Ok(engine) = dialect.open_text(&source, &dialect.default_settings()) else {
            panic!("the {name} bench program assembles")
        };
        group.throughput(Throughput::Elements(ticks));
        group.bench_function(format!("{name}: bare machine"), |b| {
            b.iter(|| {
                let run = servoscope_core::runner::run_engine(engine.as_ref(), &[], ticks);
                black_box(run.machine().ticks())
            })
        });
        group.bench_function(format!("{name}: recorded"), |b| {
            b.iter(|| {
                let mut d = Debugger::with_dialect(dialect, "bench", source.as_str());
                d.set_speed(Speed::Unlimited);
                d.goto_tick(ticks);
                while d.advance(0.016, Duration::from_secs(60)) {}
                black_box(d.machine().ticks())
            })
        });
    }
    group.finish();
}

criterion_group!(recording_benches, benches);
criterion_main!(recording_benches);
