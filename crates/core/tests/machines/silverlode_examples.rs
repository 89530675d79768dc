//! Every example program in assets/examples runs and ends in the state its comments promise.
//! Expected values are worked out by hand from the programs' arithmetic.

use std::path::Path;

use crate::common;
use servoscope_core::machine::silverlode::SilverLode;
use servoscope_core::machine::{Machine, MachineView, RunState};

use common::load;
use servoscope_core::runner::{InputToggle, parse_input_spec, run_with_inputs};

fn example(name: &str, inputs: &[InputToggle]) -> SilverLode {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("assets/examples")
        .join(name);
    let text = std::fs::read_to_string(&path).expect("example exists");
    let mut m = load(&text).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    run_with_inputs(&mut m, inputs, 10_000_000);
    assert_eq!(m.run_state(), RunState::Ended, "{name}: {:?}", m.fault());
    m
}

#[test]
fn every_example_on_disk_is_built_in_and_ends() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("assets/examples");
    let dialect = servoscope_core::registry::by_name("silverlode").expect("registered");
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .expect("examples folder")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".qsl"))
        .collect();
    on_disk.sort();
    let mut built_in: Vec<String> = dialect
        .examples
        .iter()
        .map(|(n, _)| n.to_string())
        .collect();
    built_in.sort();
    assert_eq!(on_disk, built_in, "the Examples menu offers every file");
    for (name, text) in dialect.examples {
        let file = std::fs::read_to_string(dir.join(name)).expect("readable");
        assert_eq!(&file, text, "{name}: the built-in copy is the file");
        // Each runs to its END (the per-example tests below check what it computes).
        example(name, &io3_at_3000());
    }
}

#[test]
fn fixed_point() {
    let m = example("fixed_point.qsl", &[]);
    assert_eq!(m.reg(21), 1016, "(40000 × 1665) >> 16");
    assert_eq!(m.reg(22), 10162, "(400000 × 1665) >> 16");
    assert_eq!(m.reg(25), 254346);
    assert_eq!(
        m.reg(28),
        -2,
        "(-3 × 32768) >> 16 rounds toward minus infinity"
    );
}

#[test]
fn fifo_moves_visit_positions_in_order() {
    let text = std::fs::read_to_string(
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .join("assets/examples/fifo_moves.qsl"),
    )
    .unwrap();
    let mut m = load(&text).unwrap();
    // Record the target every time a move completes.
    let mut visited = Vec::new();
    while m.run_state().is_live() {
        let was_moving = m.run_state().label() == "waiting for move";
        m.step_tick();
        if was_moving && m.run_state().label() != "waiting for move" {
            visited.push(m.reg(0));
        }
    }
    assert_eq!(visited, [1000, 2500, -500, 4000, 0]);
    assert_eq!(m.reg(32), 5);
    let q = &m.queues()[0];
    let h = q.header.as_ref().unwrap();
    assert_eq!(
        (h.len, h.head, h.tail),
        (0, 1, 1),
        "five pushes on a ring of four wrapped"
    );
    assert_eq!(m.reg(1), 0, "settled on the last position");
}

fn io3_at_3000() -> Vec<InputToggle> {
    let m = load("END").expect("assembles");
    parse_input_spec(&m, "IO3=3000").expect("IO3 is an input")
}

#[test]
fn homing_zeroes_on_the_sensor() {
    let m = example("homing.qsl", &io3_at_3000());
    assert_eq!((m.reg(0), m.reg(1)), (0, 0));
    assert_eq!(m.reg(11), 0, "the sensor was found");
    // 3000 ticks = 0.36 s: 0.05 s ramp (50 counts) then 2000 counts/s ≈ 670 counts of target;
    // the 25 Hz follower lags 2ζ/ωn × v ≈ 18 counts behind.
    assert!((630..=680).contains(&m.reg(4)), "trigger at {}", m.reg(4));
}

#[test]
fn homing_without_a_sensor_reports_failure() {
    let m = example("homing.qsl", &[]);
    assert_eq!(m.reg(11), -1);
    assert_eq!(m.reg(0), 1_000_000);
}

#[test]
fn lifo_undo() {
    let m = example("lifo_undo.qsl", &[]);
    assert_eq!(m.reg(20), 20, "99 → 35 → 20");
    assert_eq!((m.reg(22), m.reg(23)), (35, 10), "peek newest and oldest");
    let h = m.queues()[0].header.clone().unwrap();
    assert_eq!(h.items, [10]);
}

#[test]
fn call_ret_sums_squares() {
    let m = example("call_ret.qsl", &[]);
    assert_eq!(m.reg(22), 385);
    assert_eq!(m.reg(20), 0);
    assert!(m.call_stack_lines().is_empty());
}

/// A move's comment that names its acceleration or speed in counts/s² or counts/s says what its
/// operands are (spec §6: a = accel / 2^26 counts/tick², v = vel / 2^26 counts/tick, a tick of
/// 120 µs), within half a percent: what a student reads beside the numbers is what they do.
#[test]
fn the_examples_moves_are_commented_in_the_units_they_run_at() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let tick = 120e-6;
    let mut checked = 0;
    // The examples, and the programs the sessions carry (a walk-through kept an old comment).
    let mut programs = Vec::new();
    for entry in std::fs::read_dir(root.join("assets/examples")).expect("the examples") {
        let path = entry.expect("an entry").path();
        if path.extension().is_some_and(|e| e == "qsl") {
            programs.push((
                path.clone(),
                std::fs::read_to_string(&path).expect("an example"),
            ));
        }
    }
    for entry in std::fs::read_dir(root.join("sessions")).expect("the sessions") {
        let path = entry.expect("an entry").path();
        let session = servoscope_core::session::Session::load(&path).expect("a session");
        if session.dialect == "silverlode" {
            programs.push((path, session.program));
        }
    }
    for (path, text) in &programs {
        for line in text.lines() {
            let Some((code, comment)) = line.split_once(';') else {
                continue;
            };
            let words: Vec<&str> = code
                .split([' ', ',', '\t'])
                .filter(|w| !w.is_empty())
                .collect();
            let Some(at) = words
                .iter()
                .position(|w| ["MAV", "MRV", "RAV", "RRV"].contains(w))
            else {
                continue;
            };
            let number = |i: usize| words.get(at + i).and_then(|w| w.parse::<f64>().ok());
            let (Some(accel), Some(vel)) = (number(2), number(3)) else {
                continue;
            };
            let stated = |unit: &str| {
                let before = comment.split(unit).next()?;
                let figure = before.split([' ', '(']).rfind(|w| !w.is_empty())?;
                figure.replace([',', '_'], "").parse::<f64>().ok()
            };
            let close = |a: f64, b: f64| (a - b).abs() <= b.abs() * 0.005;
            let per_s2 = accel / 2f64.powi(26) / (tick * tick);
            let per_s = vel / 2f64.powi(26) / tick;
            if let Some(said) = stated("counts/s²") {
                assert!(
                    close(said, per_s2),
                    "{}: {line}: {per_s2:.0} counts/s²",
                    path.display()
                );
                checked += 1;
            }
            let speed_unit = ["counts/s,", "counts/s)"]
                .into_iter()
                .find(|u| comment.contains(u));
            if let Some(said) = speed_unit.and_then(stated) {
                assert!(
                    close(said, per_s),
                    "{}: {line}: {per_s:.0} counts/s",
                    path.display()
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 3, "read the moves' comments ({checked})");
}
