//! Interpreter throughput through each machine's fastest loop (`run_bare`, the headless
//! runner's). Commands per second = throughput reported by criterion ("elements/s"), one
//! element per command (or per tick for the move).
//!
//! `cargo bench --bench machine`

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use servoscope::machine::silverlode::{SilverLode, assemble};
use servoscope::machine::{Machine, Pos};

const COMMANDS: u64 = 1_000_000;

#[path = "common/programs.rs"]
mod programs;
use programs::{
    ARITHMETIC, TML_ARITHMETIC, dl205_ladder_program, dl205_program, opennet_ladder_program,
    opennet_program,
};

const QUEUE: &str = "\
      CLD Q_INIT, 11, 40, 16
loop: CLD Q_PUSH_HEAD, 12, 40, 7
      CLX Q_PUSH_HEAD, 12, 40, 13
      CLD Q_POP_TAIL, 13, 40, 0
      CLD Q_POP_TAIL, 14, 40, 0
      JMP loop
";

fn machine(src: &str) -> SilverLode {
    SilverLode::new(Arc::new(assemble(src).expect("bench program assembles")))
}

/// The arithmetic loop's work written as plain Rust. Every result goes through `black_box`,
/// as the interpreter keeps every result in a register; otherwise the compiler folds the loop.
fn plain_rust(rounds: u64, r22: i32) -> i32 {
    let (mut r10, mut r20, mut r25) = (0i32, 0i32, 0i32);
    let mut last = 0;
    let q = 98304i64; // q16(1.5)
    for _ in 0..rounds {
        r20 = black_box(r20.wrapping_add(3));
        let r21 = black_box(r20.wrapping_mul(r22));
        r10 = black_box(r10.wrapping_add(r21));
        let r23 = black_box(((i64::from(r21) * q) >> 16) as i32);
        let r24 = black_box(r23 ^ r20);
        r25 = black_box(r25.wrapping_add(1));
        let r26 = black_box(r25 & 0x7FFF_FFFF);
        if r26 < 0 {
            break;
        }
        last = r24;
    }
    r10 ^ last
}

fn benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("silverlode");
    group.throughput(Throughput::Elements(COMMANDS));

    let start = machine(ARITHMETIC);
    group.bench_function("arithmetic loop (commands)", |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(COMMANDS));
            black_box(m.reg(24))
        })
    });
    group.bench_function("arithmetic loop as plain Rust (commands)", |b| {
        b.iter(|| black_box(plain_rust(black_box(COMMANDS / 8), black_box(7))))
    });

    let start = machine(QUEUE);
    group.bench_function("queue push/pop loop (commands)", |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(COMMANDS));
            black_box(m.reg(14))
        })
    });

    // A long move: 1,000,000 ticks of trajectory and follower.
    let start = machine("MAV 1000000, 3865, 67108864\nEND");
    group.bench_function("long move (ticks)", |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(COMMANDS));
            black_box(m.reg(1))
        })
    });
    group.finish();

    // TML: ten statements a tick, so 100,000 ticks run 1,000,000 statements.
    let mut group = c.benchmark_group("tml");
    group.throughput(Throughput::Elements(COMMANDS));
    let start = servoscope::machine::tml::dialect::machine(TML_ARITHMETIC)
        .expect("bench program assembles");
    group.bench_function("arithmetic loop (statements)", |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(COMMANDS / 10));
            black_box(m.preg)
        })
    });
    group.finish();

    // OpenNet: scans of 100 instructions.
    const SCANS: u64 = 10_000;
    let mut group = c.benchmark_group("opennet");
    group.throughput(Throughput::Elements(SCANS));
    let start = servoscope::machine::opennet::dialect::machine(&opennet_program())
        .expect("bench program assembles");
    group.bench_function("100-instruction arithmetic scan with REP (scans)", |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(SCANS));
            black_box(m.d[0])
        })
    });
    let ladder = servoscope::machine::opennet::dialect::machine(&opennet_ladder_program())
        .expect("bench program assembles");
    group.bench_function(
        "100-instruction ladder scan: timers, counters, CMP, MCS, a jump (scans)",
        |b| {
            b.iter(|| {
                let mut m = ladder.clone();
                m.run_bare(Pos::at_tick(SCANS));
                black_box(m.d[0])
            })
        },
    );
    group.finish();

    // DL205: scans of 100 instructions of math rungs.
    let mut group = c.benchmark_group("dl205");
    group.throughput(Throughput::Elements(SCANS));
    let start = servoscope::machine::dl205::dialect::machine(&dl205_program())
        .expect("bench program assembles");
    group.bench_function("100-instruction math rung scan (scans)", |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(SCANS));
            black_box(m.acc)
        })
    });
    let boxes = servoscope::machine::dl205::dialect::machine(&dl205_ladder_program())
        .expect("bench program assembles");
    group.bench_function(
        "100-instruction ladder scan: timers, counters, stages, a call (scans)",
        |b| {
            b.iter(|| {
                let mut m = boxes.clone();
                m.run_bare(Pos::at_tick(SCANS));
                black_box(m.acc)
            })
        },
    );
    group.finish();
}

criterion_group!(machine_benches, benches);
criterion_main!(machine_benches);
