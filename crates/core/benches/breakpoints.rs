//! What breakpoints cost a run (goal: with a conditional breakpoint, running stays at least 25 %
//! of the speed without one). Each run records its timeline as the window does (checkpoints and
//! the plot's trace), 1,000,000 commands of the SilverLode arithmetic loop.
//!
//! `cargo bench --bench breakpoints`

use std::cell::RefCell;
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use servoscope_core::debugger::breakpoints::Checker;
use servoscope_core::debugger::{Breakpoint, DataTrigger, StopWhen};
use servoscope_core::machine::Pos;
use servoscope_core::registry;

const COMMANDS: u64 = 1_000_000;

#[path = "common/programs.rs"]
mod programs;
use programs::ARITHMETIC;

fn benches(c: &mut Criterion) {
    let dialect = registry::by_name("silverlode").expect("SilverLode is registered");
    let Ok(start) = dialect.open_text(ARITHMETIC, &dialect.default_settings()) else {
        panic!("the bench program assembles")
    };
    let cases: [(&str, Vec<Breakpoint>); 5] = [
        ("no breakpoint", Vec::new()),
        (
            "a conditional breakpoint, asked every round",
            vec![Breakpoint::line(3).with_condition("R25 < 0 && R20 != 7")],
        ),
        (
            "a conditional breakpoint on every line",
            (1..=8)
                .map(|l| Breakpoint::line(l).with_condition("R25 < 0"))
                .collect(),
        ),
        (
            "a data breakpoint (R24 equals 1)",
            vec![Breakpoint::data("R24", DataTrigger::Equal(1))],
        ),
        (
            "a data breakpoint on a register the loop never writes (R30 written)",
            vec![Breakpoint::data("R30", DataTrigger::Write)],
        ),
    ];
    let mut group = c.benchmark_group("run with breakpoints (commands)");
    group.throughput(Throughput::Elements(COMMANDS));
    for (name, list) in cases {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut engine = start.restarted(Vec::new(), Vec::new());
                let checker = RefCell::new(Checker::new(
                    &list,
                    engine.machine(),
                    &[ARITHMETIC.lines().count()],
                ));
                let stop = StopWhen {
                    checker: (!checker.borrow().is_empty()).then_some(&checker),
                    ..StopWhen::default()
                };
                black_box(engine.forward(Pos::at_tick(COMMANDS), &stop));
                black_box(engine.machine().ticks())
            })
        });
    }
    group.finish();
}

criterion_group!(breakpoint_benches, benches);
criterion_main!(breakpoint_benches);
