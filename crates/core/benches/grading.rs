//! What `servoscope check` and a lesson's Check run: every example program (and the vendor
//! idioms of the machine benchmark) from its start for
//! a fixed number of ticks, the straight headless run (`runner::run_engine`, what grading ran
//! before it had a time budget) beside the run under a budget (`runner::run_engine_until`,
//! the clock read between instructions), in one session so the two compare.

use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use servoscope_core::registry;
use servoscope_core::runner::{run_engine, run_engine_until};

/// Ticks graded per example: a drive's 10,000 (1.2 s of a SilverLode, 10 s of TML), a
/// PLC's 1,000 scans.
fn ticks(dialect: &str) -> u64 {
    match dialect {
        "silverlode" | "tml" => 10_000,
        _ => 1_000,
    }
}

fn grading(c: &mut Criterion) {
    let dir =
        std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("assets/examples");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("assets/examples")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    files.sort();
    // The vendor idioms the machine benchmark loops on, as programs a lesson would grade.
    let idioms = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/benches/common"));
    files.extend(["idiom.qsl", "tml_arithmetic.tml"].map(|f| idioms.join(f)));
    let mut group = c.benchmark_group("grading");
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(1));
    for path in files {
        let top = if path.is_dir() {
            path.join("motion.tml")
        } else {
            path.clone()
        };
        let Ok(dialect) = registry::choose(&top, None) else {
            continue;
        };
        let project = dialect.load(&top).expect("example reads");
        let Ok(engine) = dialect.open_program(&project, &dialect.default_settings()) else {
            panic!("{} assembles", top.display());
        };
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let n = ticks(dialect.name);
        group.bench_function(format!("{name} straight ({n} ticks)"), |b| {
            b.iter(|| run_engine(engine.as_ref(), &[], n).machine().ticks())
        });
        group.bench_function(format!("{name} with a budget ({n} ticks)"), |b| {
            b.iter(|| {
                let deadline = Instant::now() + Duration::from_secs(3600);
                run_engine_until(engine.as_ref(), &[], n, deadline)
                    .0
                    .machine()
                    .ticks()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, grading);
criterion_main!(benches);
