//! Interpreter throughput through each machine's fastest loop (`run_bare`, the headless
//! runner's), on what users run: every example program of every dialect (turned into an endless
//! loop where it ends), the vendor manual's calculation idiom, and the older synthetic loops.
//! Throughput is criterion's "elements/s": commands (statements, scans) for the loops, ticks
//! (scans) for the examples, whose names say how many commands a tick they run.
//!
//! `cargo bench --bench machine` (or `-- silverlode`, `-- examples`, … to pick)

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use servoscope_core::machine::silverlode::{SilverLode, assemble};
use servoscope_core::machine::{Machine, Pos, RunState};

const COMMANDS: u64 = 1_000_000;

#[path = "common/programs.rs"]
mod programs;
use programs::{
    ARITHMETIC, IDIOM, TML_ARITHMETIC, dl205_ladder_program, dl205_program, opennet_ladder_program,
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

/// The idiom loop (`common/idiom.qsl`) as plain Rust, every result kept as above.
fn idiom_as_plain_rust(rounds: u32, step: i32) -> i32 {
    let mut r20 = 40_000i32;
    let q = 1665i64; // q16(0.0254)
    let mut r25 = rounds;
    let (r10, r24) = loop {
        let mut r10 = black_box(r20);
        r10 = black_box(r10.wrapping_add(step));
        r20 = black_box(r10);
        let r23 = black_box(((i64::from(r20) * q) >> 16) as i32);
        let r24 = black_box(r23 ^ r20);
        r25 = black_box(r25.wrapping_sub(1));
        if r25 == 0 {
            break (r10, r24);
        }
    };
    r10 ^ r24
}

/// The program made endless: where it ends (`END`), it starts again from its first line, with
/// the registers as they are.
fn endless(src: &str, comment: &str, restart: &str) -> String {
    let mut out = String::from("bench_restart:\n");
    for line in src.lines() {
        let code = line.split(comment).next().unwrap_or("");
        let word = code
            .rsplit(':')
            .next()
            .unwrap_or("")
            .trim()
            .trim_end_matches(';');
        if word.trim().eq_ignore_ascii_case("END") {
            let label = code.rsplit_once(':').map_or("", |(label, _)| label);
            let label = if label.is_empty() {
                String::new()
            } else {
                format!("{label}:")
            };
            out.push_str(&format!("{label} {restart}\n"));
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// Run a machine `ticks` ticks from `start`, starting over should it stop (a fault).
fn run_ticks<M: Machine + Clone>(start: &M, ticks: u64) -> M {
    let mut m = start.clone();
    let mut left = ticks;
    while left > 0 {
        let from = m.pos().tick;
        m.run_bare(Pos::at_tick(from + left));
        left -= m.pos().tick - from;
        if left > 0 && matches!(m.run_state(), RunState::Ended | RunState::Faulted) {
            m = start.clone();
        }
    }
    m
}

/// One example: `ticks` ticks (scans) an iteration, named with its commands a tick.
fn bench_example<M: Machine + Clone>(
    group: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    start: M,
    ticks: u64,
) {
    let probe = run_ticks(&start, ticks);
    let per_tick = probe.steps() as f64 / probe.pos().tick.max(1) as f64;
    group.throughput(Throughput::Elements(ticks));
    group.bench_function(format!("{name} ({per_tick:.3} commands a tick)"), |b| {
        b.iter(|| black_box(run_ticks(&start, ticks).steps()))
    });
}

/// Every example of `assets/examples`, by dialect.
fn examples(c: &mut Criterion) {
    let dir =
        std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("assets/examples");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("assets/examples")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    files.sort();
    let mut group = c.benchmark_group("examples");
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    for path in files {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("")
            .to_string();
        if path.is_dir() {
            // A TML project (EasyMotion's layout): its top file made endless, then assembled
            // with its included files.
            let tml = servoscope_core::registry::by_name("tml").expect("TML");
            let mut project = tml.load(&path.join("motion.tml")).expect("project reads");
            project.files[0].text = endless(&project.files[0].text, "//", "GOTO bench_restart;");
            let program = servoscope_core::machine::tml::assembler::assemble_project(&project)
                .expect("project assembles");
            let start = servoscope_core::machine::tml::Tml::new(std::sync::Arc::new(program));
            bench_example(
                &mut group,
                &format!("{name}/motion.tml"),
                start,
                COMMANDS / 10,
            );
            continue;
        }
        let src = std::fs::read_to_string(&path).expect("example reads");
        match path.extension().and_then(|e| e.to_str()) {
            Some("qsl") => {
                let start = machine(&endless(&src, ";", "JMP bench_restart"));
                bench_example(&mut group, &name, start, COMMANDS);
            }
            Some("tml") => {
                let start = servoscope_core::machine::tml::dialect::machine(&endless(
                    &src,
                    "//",
                    "GOTO bench_restart;",
                ))
                .expect("example assembles");
                bench_example(&mut group, &name, start, COMMANDS / 10);
            }
            Some("dl205") => {
                let start = servoscope_core::machine::dl205::dialect::machine(&src)
                    .expect("example assembles");
                bench_example(&mut group, &name, start, 10_000);
            }
            Some("opennet") => {
                let start = servoscope_core::machine::opennet::dialect::machine(&src)
                    .expect("example assembles");
                bench_example(&mut group, &name, start, 10_000);
            }
            _ => {}
        }
    }
    group.finish();
}

/// A SilverLode program run `COMMANDS` ticks an iteration; `kept` is a register it writes.
fn bench_loop(
    group: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    src: &str,
    kept: usize,
) {
    let start = machine(src);
    group.bench_function(name, |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(COMMANDS));
            black_box(m.reg(kept))
        })
    });
}

fn benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("silverlode");
    group.throughput(Throughput::Elements(COMMANDS));

    bench_loop(&mut group, "idiom loop (commands)", IDIOM, 24);
    group.bench_function("idiom loop as plain Rust (commands)", |b| {
        // Seven commands a round; the three WRPs before the loop are not counted.
        b.iter(|| {
            black_box(idiom_as_plain_rust(
                black_box(COMMANDS as u32 / 7),
                black_box(7),
            ))
        })
    });

    bench_loop(&mut group, "arithmetic loop (commands)", ARITHMETIC, 24);
    group.bench_function("arithmetic loop as plain Rust (commands)", |b| {
        b.iter(|| black_box(plain_rust(black_box(COMMANDS / 8), black_box(7))))
    });

    bench_loop(&mut group, "queue push/pop loop (commands)", QUEUE, 14);

    // A long move: 1,000,000 ticks of trajectory and follower.
    bench_loop(
        &mut group,
        "long move (ticks)",
        "MAV 1000000, 3865, 67108864\nEND",
        1,
    );
    group.finish();

    // TML: ten statements a tick, so 100,000 ticks run 1,000,000 statements.
    let mut group = c.benchmark_group("tml");
    group.throughput(Throughput::Elements(COMMANDS));
    let start = servoscope_core::machine::tml::dialect::machine(TML_ARITHMETIC)
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
    let start = servoscope_core::machine::opennet::dialect::machine(&opennet_program())
        .expect("bench program assembles");
    group.bench_function("100-instruction arithmetic scan with REP (scans)", |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(SCANS));
            black_box(m.d[0])
        })
    });
    let ladder = servoscope_core::machine::opennet::dialect::machine(&opennet_ladder_program())
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
    let start = servoscope_core::machine::dl205::dialect::machine(&dl205_program())
        .expect("bench program assembles");
    group.bench_function("100-instruction math rung scan (scans)", |b| {
        b.iter(|| {
            let mut m = start.clone();
            m.run_bare(Pos::at_tick(SCANS));
            black_box(m.acc)
        })
    });
    let boxes = servoscope_core::machine::dl205::dialect::machine(&dl205_ladder_program())
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

criterion_group!(machine_benches, benches, examples);
criterion_main!(machine_benches);
