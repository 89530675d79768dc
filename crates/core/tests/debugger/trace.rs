//! The motion trace: it records what the machine did at every tick, and its decimation keeps
//! every column's minimum and maximum (checked against a brute-force version).

use std::time::Duration;

use proptest::prelude::*;
use servoscope_core::debugger::trace::{BLOCK, Trace};
use servoscope_core::debugger::{Debugger, Speed};
use servoscope_core::machine::Machine;

use crate::common;

#[test]
fn the_trace_records_every_tick_of_a_run() {
    let program = "MAV 300, 386500, 80530640\nDLY 500\nWRP 0, -50\nDLY 2000\nEND";
    let mut d = Debugger::new("t", program);
    d.set_speed(Speed::Unlimited);
    d.run();
    while d.advance(0.016, Duration::from_millis(50)) {}
    let end = d.machine().ticks();
    assert!(end > 1000);
    // Replay the same program tick by tick and compare every tick: SilverLode's default
    // channels are target R0, actual R1 and error R6.
    let names: Vec<&str> = d.channels().iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["R0", "R1", "R6"]);
    let mut m = common::load(program).unwrap();
    let trace = d.trace();
    for tick in 0..=end {
        let s = trace.at(tick).expect("covered");
        assert_eq!(
            s.values,
            [m.reg(0), m.reg(1), m.reg(6)].map(i64::from),
            "tick {tick}"
        );
        m.step_tick();
    }
    assert_eq!(trace.end_tick(), Some(end));
    assert!(trace.len() < end as usize, "idle ticks are not stored");
}

#[test]
fn stepping_records_too_and_reset_restarts_the_trace() {
    let mut d = Debugger::new("t", "WRP 0, 100\nDLY 50\nEND");
    d.step_command();
    d.step_command();
    assert_eq!(d.trace().at(0).unwrap().values[0], 0);
    assert_eq!(
        d.trace().at(1).unwrap().values[0],
        100,
        "R0 written in tick 1"
    );
    assert!(
        d.trace().at(51).unwrap().values[1] > 0,
        "the follower moved while waiting"
    );
    d.reset();
    assert_eq!(d.trace().len(), 1);
    assert_eq!(d.trace().end_tick(), Some(0));
}

/// Brute force: the step function's values at every tick a column touches.
fn brute(samples: &[(u64, i32)], end: u64, t0: f64, t1: f64, columns: usize) -> Vec<[f64; 2]> {
    let value_at = |x: u64| {
        let i = samples.partition_point(|(t, _)| *t <= x);
        i.checked_sub(1).map(|i| samples[i].1)
    };
    let first = samples[0].0;
    let width = (t1 - t0) / columns as f64;
    let mut out = Vec::new();
    for c in 0..columns {
        let c0 = t0 + width * c as f64;
        let c1 = c0 + width;
        if c1 <= first as f64 || c0 > end as f64 {
            continue;
        }
        // Real x in [c0, c1) reads the value of tick floor(x).
        let mut ticks = vec![c0.max(0.0).floor() as u64];
        let mut k = ticks[0] + 1;
        while (k as f64) < c1 {
            ticks.push(k);
            k += 1;
        }
        let values: Vec<i32> = ticks
            .into_iter()
            .filter(|&x| x >= first && x <= end)
            .filter_map(value_at)
            .collect();
        let (lo, hi) = match (values.iter().min(), values.iter().max()) {
            (Some(&lo), Some(&hi)) => (lo, hi),
            _ => (samples[0].1, samples[0].1),
        };
        let x = c0 + width / 2.0;
        out.push([x, f64::from(lo)]);
        if hi != lo {
            out.push([x, f64::from(hi)]);
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn decimation_keeps_every_column_min_and_max(
        steps in prop::collection::vec((1u64..40, -1000i32..1000), 1..(6 * BLOCK)),
        start in 0u64..50,
        // Whole-trace views with few columns reach the block summaries; narrow ones the edges.
        view in prop_oneof![Just((0.0f64, 1.0f64)), (0.0f64..1.0, 0.0f64..1.0)],
        columns in prop_oneof![1usize..5, 1usize..120],
        tail in 0u64..30,
    ) {
        let mut trace = Trace::new(4);
        let mut samples = Vec::new();
        let mut tick = start;
        for (dt, v) in steps {
            trace.record(tick, &[i64::from(v), 0, 0, 0]);
            if samples.last().is_none_or(|&(_, last)| last != v) {
                samples.push((tick, v));
            }
            tick += dt;
        }
        let end = tick - 1 + tail;
        trace.record(end, &[i64::from(samples.last().unwrap().1), 0, 0, 0]);
        let span = (end + 20) as f64;
        let (a, b) = (view.0 * span, view.1 * span);
        let (t0, t1) = if a < b { (a, b) } else { (b, a + 1.0) };
        let got = trace.decimate(0, t0, t1, columns);
        let want = brute(&samples, end, t0, t1, columns);
        prop_assert_eq!(got, want);
    }
}
