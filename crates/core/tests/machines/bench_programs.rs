//! The benchmarks' programs are what their names say (a benchmark run is not a test: a
//! program that stopped assembling would only show when someone ran it).

#[path = "../../benches/common/programs.rs"]
mod programs;

use servoscope_core::machine::dl205::assembler::assemble;
use servoscope_core::machine::dl205::program::Op;

#[test]
fn the_dl205_ladder_benchmark_is_100_instructions_of_ladder() {
    let program = assemble(&programs::dl205_ladder_program()).expect("assembles");
    assert_eq!(program.instrs.len(), 100);
    let timers = program
        .boxes
        .iter()
        .filter(|b| b.status.kind.letter() == "T")
        .count();
    assert_eq!(
        (timers, program.boxes.len() - timers),
        (8, 8),
        "8 timers, 8 counters"
    );
    let count = |f: fn(&Op) -> bool| program.instrs.iter().filter(|i| f(&i.op)).count();
    assert_eq!(count(|op| matches!(op, Op::Sg { .. })), 2, "two stages");
    assert_eq!(count(|op| matches!(op, Op::Gts(_))), 1, "a call");
    assert!(assemble(&programs::dl205_program()).is_ok());
}

#[test]
fn the_opennet_ladder_benchmark_is_100_instructions_of_ladder() {
    use servoscope_core::machine::opennet::program::Op as On;
    let program =
        servoscope_core::machine::opennet::assembler::assemble(&programs::opennet_ladder_program())
            .expect("assembles");
    assert_eq!(program.instrs.len(), 100);
    let count = |f: fn(&On) -> bool| program.instrs.iter().filter(|i| f(&i.op)).count();
    assert_eq!(count(|op| matches!(op, On::Timer { .. })), 8, "8 timers");
    assert_eq!(
        count(|op| matches!(op, On::Counter { .. })),
        8,
        "8 counters"
    );
    assert_eq!(count(|op| matches!(op, On::WordCompare { .. })), 1, "a CMP");
    assert_eq!(count(|op| matches!(op, On::Mcs(_))), 1, "an MCS area");
    assert!(
        servoscope_core::machine::opennet::assembler::assemble(&programs::opennet_program())
            .is_ok()
    );
}
