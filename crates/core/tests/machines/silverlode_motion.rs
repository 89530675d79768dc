//! The motion model of spec §6: trapezoid and triangle profiles that land exactly, a
//! second-order follower, moves that do not move the motor, and stop-on-input.
//! Expected figures come from the continuous formulas (v = vel/2^26 counts/tick,
//! a = accel/2^26 counts/tick²), not from running the model.

use crate::common;
use common::{machine, reg, run_ok};
use servoscope_core::machine::silverlode::view::io;
use servoscope_core::machine::silverlode::{ServoSettings, SilverLode};
use servoscope_core::machine::{Machine, MachineView, RunState};
use servoscope_core::runner::{InputToggle, run_with_inputs};

const UNIT: f64 = 67_108_864.0; // 2^26

/// Ticks the MAV on line 1 keeps the program waiting (the move's own duration).
fn move_ticks(src: &str) -> u64 {
    let mut m = machine(src);
    m.step_command(10_000_000);
    m.ticks()
}

#[test]
fn trapezoid_lands_exactly_in_the_expected_time() {
    // 4000 counts at 1000 counts/s with 4000 counts/s²: 0.25 s up, 3.75 s cruise, 0.25 s down.
    let ticks = move_ticks("MAV 4000, 3865, 8053064\nEND");
    let (v, a) = (8053064.0 / UNIT, 3865.0 / UNIT);
    let expected = 4000.0 / v + v / a;
    assert!(
        (ticks as f64 - expected).abs() < 3.0,
        "{ticks} vs {expected}"
    );
    let m = run_ok("MAV 4000, 3865, 8053064\nEND");
    assert_eq!(reg(&m, 0), 4000, "the target lands exactly");
}

#[test]
fn triangle_when_top_speed_is_not_reached() {
    let ticks = move_ticks("MAV 100, 3865, 8053064\nEND");
    let a = 3865.0 / UNIT;
    let expected = 2.0 * (100.0 / a).sqrt();
    assert!(
        (ticks as f64 - expected).abs() < 3.0,
        "{ticks} vs {expected}"
    );
    // The trajectory speed never reaches the velocity limit.
    let mut m = machine("MAV 100, 3865, 8053064\nEND");
    let mut peak = 0;
    while m.run_state() != RunState::Ended {
        m.step_tick();
        peak = peak.max(m.state().motion.speed);
    }
    assert!(peak < 8053064 && peak > 8053064 / 3, "peak {peak}");
    assert_eq!(reg(&m, 0), 100);
}

#[test]
fn trapezoid_cruises_at_the_velocity_limit() {
    let mut m = machine("MAV -20000, 38650, 8053064\nEND");
    let mut at_limit = 0;
    while m.run_state() != RunState::Ended {
        m.step_tick();
        if m.state().motion.speed == 8053064 {
            at_limit += 1;
        }
    }
    assert!(at_limit > 100_000, "cruised {at_limit} ticks");
    assert_eq!(reg(&m, 0), -20000, "negative moves land exactly too");
}

#[test]
fn moves_land_exactly_for_awkward_parameters() {
    for (pos, accel, vel) in [
        (1, 1, 1_000_000),
        (7, 1_073_741_824, 2_147_483_648u32),
        (-99_999, 12_345, 98_765_432),
        (3, 100_000_000, 5_000),
    ] {
        let m = run_ok(&format!("MAV {pos}, {accel}, {vel}\nEND"));
        assert_eq!(reg(&m, 0), pos, "MAV {pos}, {accel}, {vel}");
    }
}

#[test]
fn relative_and_register_moves() {
    let m = run_ok(
        "MAV 1000, 386500, 80530640\nMRV 250, 386500, 80530640\nWRP 30, -500\nRRV 30, 386500, 80530640\nWRP 31, 42\nRAV 31, 386500, 80530640\nEND",
    );
    assert_eq!(reg(&m, 0), 42);
    let m = run_ok("MAV 1000, 386500, 80530640\nMRV 250, 386500, 80530640\nEND");
    assert_eq!(reg(&m, 0), 1250, "MRV is relative to the target");
}

#[test]
fn a_move_waits_and_counts_as_one_step() {
    let mut m = machine("MAV 50, 386500, 80530640\nEND");
    m.step_tick();
    assert_eq!(m.run_state().label(), "waiting for move");
    assert_eq!(m.steps(), 0);
    m.run_until(1_000_000, |_| false);
    assert_eq!(m.steps(), 2);
    // A zero-length move finishes in its one tick.
    let m = run_ok("MAV 0, 10, 10\nEND");
    assert_eq!((m.ticks(), m.steps()), (2, 2));
}

#[test]
fn follower_settles_onto_the_target() {
    let m = run_ok("MAV 4000, 3865, 8053064\nDLY 5000\nEND");
    assert_eq!(
        (reg(&m, 0), reg(&m, 1), reg(&m, 6), reg(&m, 7)),
        (4000, 4000, 0, 0)
    );
}

#[test]
fn follower_step_response_is_second_order() {
    // A 1000-count step of the target with 25 Hz, damping 0.7: overshoot
    // exp(-ζπ/√(1-ζ²)) ≈ 4.6 %, peak at π/(ωn√(1-ζ²)) ≈ 28 ms ≈ 233 ticks.
    let mut m = machine("WRP 0, 1000\nDLY 3000\nEND");
    let (mut peak, mut peak_tick) = (0, 0);
    while m.run_state() != RunState::Ended {
        m.step_tick();
        if reg(&m, 1) > peak {
            peak = reg(&m, 1);
            peak_tick = m.ticks();
        }
        assert_eq!(reg(&m, 6), reg(&m, 0) - reg(&m, 1), "R6 = R0 - R1");
    }
    let zeta: f64 = 0.7;
    let wn = 2.0 * std::f64::consts::PI * 25.0;
    let overshoot = 1000.0 * (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
    let t_peak = std::f64::consts::PI / (wn * (1.0 - zeta * zeta).sqrt()) / 120e-6;
    assert!(
        (f64::from(peak - 1000) - overshoot).abs() < 6.0,
        "peak {peak}, expected ≈ {}",
        1000.0 + overshoot
    );
    assert!(
        (peak_tick as f64 - t_peak).abs() < 15.0,
        "peak at {peak_tick}, expected ≈ {t_peak:.0}"
    );
    assert_eq!(reg(&m, 1), 1000);
}

#[test]
fn settings_change_the_follower() {
    // A stiffer loop overshoots the same but peaks sooner.
    let program =
        servoscope_core::machine::silverlode::assemble("WRP 0, 1000\nDLY 2000\nEND").unwrap();
    let settings = ServoSettings {
        natural_frequency_hz: 100.0,
        ..ServoSettings::default()
    };
    let mut m = SilverLode::with_settings(std::sync::Arc::new(program), settings);
    let mut peak_tick = 0;
    let mut peak = 0;
    while m.run_state() != RunState::Ended {
        m.step_tick();
        if m.reg(1) > peak {
            peak = m.reg(1);
            peak_tick = m.ticks();
        }
    }
    assert!((50..70).contains(&peak_tick), "peak at {peak_tick}");
}

#[test]
fn sub_target_and_ztp_do_not_move_the_motor() {
    // Settle at 4000, then zero there: nothing may move afterwards.
    let mut m = machine(
        "MAV 4000, 38650, 80530640\nDLY 3000\nWRP 4, 4000\nCLC SUB_TARGET, 4\nDLY 500\nEND",
    );
    m.run_until(1_000_000, |m| m.pc_line() == Some(4));
    let velocity_before = reg(&m, 7);
    m.step_command(1);
    assert_eq!((reg(&m, 0), reg(&m, 1)), (0, 0));
    m.run_until(1_000_000, |_| false);
    assert_eq!(
        (reg(&m, 0), reg(&m, 1), reg(&m, 7)),
        (0, 0, velocity_before)
    );

    // ZTP while the follower still lags: the error is kept and closes on the new zero.
    let mut m = machine("MAV 4000, 386500, 805306400\nZTP\nDLY 3000\nEND");
    m.step_command(1_000_000);
    let error = reg(&m, 6);
    assert!(error != 0, "the follower lags at the end of a fast move");
    m.step_command(1);
    assert_eq!((reg(&m, 0), reg(&m, 1)), (0, 0), "ZTP sets both to 0");
    m.run_until(1_000_000, |_| false);
    assert_eq!((reg(&m, 0), reg(&m, 1)), (0, 0));
}

#[test]
fn ttp_sets_the_target_to_the_actual_position() {
    let mut m = machine("MAV 4000, 386500, 805306400\nTTP\nEND");
    m.step_command(1_000_000);
    let actual = reg(&m, 1);
    m.step_command(1);
    assert_eq!(reg(&m, 0), actual);
}

#[test]
fn stop_on_input_records_the_trigger_position() {
    let program = "MAV 100000, 3865, 8053064, IO1\nDLY 3000\nEND";
    let mut m = machine(program);
    run_with_inputs(&mut m, &[], 5000);
    let r1_at_trigger = reg(&m, 1);
    run_with_inputs(
        &mut m,
        &[InputToggle {
            tick: 5000,
            input: io(0),
        }],
        10_000_000,
    );
    assert_eq!(m.run_state(), RunState::Ended);
    assert_eq!(
        reg(&m, 4),
        r1_at_trigger,
        "R4 = R1 at the tick the input was seen"
    );
    assert!(
        m.isw() & 1 << 11 != 0 && m.psw() & 1 << 11 != 0,
        "input found in ISW and PSW"
    );
    // Braking from 1000 counts/s at 4000 counts/s² takes ≈ v²/2a = 125 counts.
    let (v, a) = (8053064.0 / UNIT, 3865.0 / UNIT);
    let braking = f64::from(reg(&m, 0) - r1_at_trigger);
    assert!(reg(&m, 0) < 100_000);
    assert!(
        (braking - v * v / (2.0 * a)).abs() < 30.0,
        "braked over {braking} counts"
    );
}

#[test]
fn homing_with_sub_target_zeroes_at_the_trigger() {
    let program = "MAV 100000, 38650, 80530640, IO3\nCLC SUB_TARGET, 4\nDLY 5000\nMAV 0, 38650, 80530640\nDLY 5000\nEND";
    let mut m = machine(program);
    run_with_inputs(
        &mut m,
        &[InputToggle {
            tick: 2000,
            input: io(2),
        }],
        10_000_000,
    );
    assert_eq!(m.run_state(), RunState::Ended);
    assert_eq!(
        (reg(&m, 0), reg(&m, 1)),
        (0, 0),
        "back at the sensor position"
    );
}

#[test]
fn error_flags_follow_the_limits() {
    let program =
        servoscope_core::machine::silverlode::assemble("MAV 4000, 3865, 8053064\nEND").unwrap();
    let tight = ServoSettings {
        moving_error_limit: 1,
        ..ServoSettings::default()
    };
    let mut m = SilverLode::with_settings(std::sync::Arc::new(program), tight);
    let mut seen = false;
    while m.run_state() != RunState::Ended {
        m.step_tick();
        seen |= m.isw() & 1 << 8 != 0;
    }
    assert!(seen, "moving error set when |R6| exceeds the limit");
    // Default limits: a gentle move never trips it.
    let mut m = machine("MAV 4000, 3865, 8053064\nEND");
    while m.run_state() != RunState::Ended {
        m.step_tick();
        assert_eq!(m.isw() & 1 << 8, 0);
    }
    // A 10000-count step with no move running trips the holding error, which clears on settling.
    let mut m = machine("WRP 0, 10000\nDLY 4000\nEND");
    m.step_tick();
    m.step_tick();
    assert!(m.isw() & 1 << 9 != 0, "holding error while |R6| > 2000");
    m.run_until(1_000_000, |_| false);
    assert_eq!(m.isw() & 1 << 9, 0);
}

/// SUB_TARGET moves the zero point by any amount, as often as a program likes: positions wrap
/// as the registers do (no overflow, even with overflow checks on), the motor does not move,
/// and a move afterwards still lands exactly.
#[test]
fn the_zero_point_moves_any_distance_any_number_of_times() {
    let src = "WRP 22, -2000000000\nWRP 23, 20000\n\
               l: CLC SUB_TARGET, 22\nCLC DEC, 23\nJMP l, !ZERO\n\
               MRV 500, 3865, 67108864\nEND\n";
    let m = run_ok(src);
    // 20,000 shifts by −2·10⁹, modulo 2^32.
    let shifted = (20_000i64 * 2_000_000_000).rem_euclid(1 << 32) as u32 as i32;
    assert_eq!(
        reg(&m, 0),
        shifted.wrapping_add(500),
        "R0: the target, then the move"
    );
    assert_eq!(reg(&m, 1), reg(&m, 0), "R1 settles on the target");
}
