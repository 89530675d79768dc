//! Plot decimation: 10 M trace samples to a 1000-pixel-wide view (goal ≤ 5 ms).
//!
//! `cargo bench --bench trace`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use servoscope_core::debugger::trace::Trace;

const SAMPLES: u64 = 10_000_000;

fn trace() -> Trace {
    let mut t = Trace::new(4);
    // A value that changes every tick (a motor always moving), so every tick is a sample.
    let mut x: i64 = 0;
    for tick in 0..SAMPLES {
        x += ((tick * 2654435761) % 1000) as i64 - 499;
        t.record(tick, &[x, x / 2, x % 97, tick as i64]);
    }
    assert_eq!(t.len() as u64, SAMPLES);
    t
}

fn benches(c: &mut Criterion) {
    let t = trace();
    let mut group = c.benchmark_group("trace");
    group.bench_function("decimate 10M samples to 1000 columns (whole trace)", |b| {
        b.iter(|| black_box(t.decimate(0, 0.0, SAMPLES as f64, black_box(1000))))
    });
    group.bench_function("decimate a 100k-tick zoom to 1000 columns", |b| {
        b.iter(|| black_box(t.decimate(0, 5e6, 5.1e6, black_box(1000))))
    });
    group.finish();
    eprintln!(
        "trace memory for {SAMPLES} samples: {} MB",
        t.memory_bytes() >> 20
    );
}

criterion_group!(trace_benches, benches);
criterion_main!(trace_benches);
