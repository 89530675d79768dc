//! Assembling big and hostile files: any input assembles or fails in time linear in its size.
//!
//! `cargo bench --bench assembler`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use servoscope_core::machine::silverlode::assemble;

fn benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("assembler");
    group.sample_size(10);
    // Every line jumps to an undefined label: each error looks for a "did you mean".
    let undefined: String = (0..100_000).map(|i| format!("a{i}: JMP b{i}\n")).collect();
    group.bench_function("100,000 lines, every one an error", |b| {
        b.iter(|| black_box(assemble(black_box(&undefined)).is_err()))
    });
    // Many names and one very long undefined one.
    let mut long_name: String = (0..20_000)
        .map(|i| format!("l{i}: WRP 11, {i}\n"))
        .collect();
    long_name.push_str(&format!("JMP {}\n", "x".repeat(100_000)));
    group.bench_function(
        "20,000 labels and a 100,000-character undefined name",
        |b| b.iter(|| black_box(assemble(black_box(&long_name)).is_err())),
    );
    let valid: String = (0..100_000)
        .map(|i| format!("l{i}: CLD ADD, 20, 20, {i} ; line {i}\n"))
        .collect();
    group.bench_function("100,000 valid lines", |b| {
        b.iter(|| black_box(assemble(black_box(&valid)).is_ok()))
    });
    group.finish();
}

criterion_group!(assembler_benches, benches);
criterion_main!(assembler_benches);
