//! The motion model of spec §6, in integer fixed point so every platform gives the same ticks.
//!
//! Positions and velocities carry [`FRAC`] fractional bits: a position is counts × 2^26, a
//! velocity counts/tick × 2^26 (the servo's native velocity unit), an acceleration
//! counts/tick² × 2^26 (the native acceleration unit).
//!
//! Trajectory: each tick the speed is the largest of `speed + accel`, `vel` and the discrete
//! braking bound (the speed from which braking at `accel` per tick covers exactly the remaining
//! distance). When the remaining distance is at most one tick's travel the target lands on the
//! end position with zero speed: every move lands exactly.
//!
//! Follower: `a = ωn²·dt²·(r − x) − 2ζωn·dt·v` per tick, semi-implicit Euler, coefficients in
//! Q32, products in i128. Once the error and velocity are below 1/1024 count the follower snaps
//! onto the target and sleeps, so an idle motor costs nothing per tick.

use serde::{Deserialize, Serialize};

use super::program::Cond;

pub const FRAC: u32 = 26;
/// One tick in seconds (spec §3: 120 µs).
const TICK_SECONDS: f64 = super::TICK_MICROS as f64 * 1e-6;
pub const ONE: i64 = 1 << FRAC;
const SETTLE: i64 = ONE >> 10;

/// Servo model settings (spec §6), settable per session.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ServoSettings {
    /// Natural frequency of the position loop, Hz (0.5 ..= 200).
    pub natural_frequency_hz: f64,
    /// Damping ratio (0.05 ..= 2).
    pub damping: f64,
    /// ISW bit 8 is set while |R6| exceeds this during a move (counts).
    pub moving_error_limit: u32,
    /// ISW bit 9 is set while |R6| exceeds this with no move running (counts).
    pub holding_error_limit: u32,
}

impl Default for ServoSettings {
    fn default() -> Self {
        ServoSettings {
            natural_frequency_hz: 25.0,
            damping: 0.7,
            moving_error_limit: 2000,
            holding_error_limit: 2000,
        }
    }
}

impl ServoSettings {
    pub const FREQUENCY_RANGE: std::ops::RangeInclusive<f64> = 0.5..=200.0;
    pub const DAMPING_RANGE: std::ops::RangeInclusive<f64> = 0.05..=2.0;

    /// The settings with frequency and damping brought into the ranges where the discrete model
    /// is stable (NaN becomes the default).
    pub fn clamped(self) -> Self {
        let d = ServoSettings::default();
        let clamp = |v: f64, r: &std::ops::RangeInclusive<f64>, dflt: f64| {
            if v.is_nan() {
                dflt
            } else {
                v.clamp(*r.start(), *r.end())
            }
        };
        ServoSettings {
            natural_frequency_hz: clamp(
                self.natural_frequency_hz,
                &Self::FREQUENCY_RANGE,
                d.natural_frequency_hz,
            ),
            damping: clamp(self.damping, &Self::DAMPING_RANGE, d.damping),
            ..self
        }
    }

    /// (k1, k2) in Q32. Only IEEE basic operations, so the result is the same everywhere.
    pub fn coefficients(self) -> (i64, i64) {
        let s = self.clamped();
        let w_dt = 2.0 * std::f64::consts::PI * s.natural_frequency_hz * TICK_SECONDS;
        let q32 = 4_294_967_296.0;
        (
            (w_dt * w_dt * q32).round() as i64,
            (2.0 * s.damping * w_dt * q32).round() as i64,
        )
    }
}

/// The motion part of the machine state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Motion {
    /// A trajectory is running.
    pub active: bool,
    /// The stop condition fired: braking to a stop.
    pub stopping: bool,
    /// Trajectory position (Q26) while active.
    pub pos: i64,
    /// Trajectory speed (Q26 counts/tick, ≥ 0) along `dir`.
    pub speed: i64,
    pub end: i64,
    pub dir: i64,
    pub accel: i64,
    pub vmax: i64,
    pub stop_cond: Option<Cond>,
    /// Follower position (Q26) and velocity (Q26 counts/tick).
    pub x: i64,
    pub v: i64,
    pub settled: bool,
    /// R0 and R1 as the model last wrote them: a difference means a program or user wrote them.
    pub seen_r0: i32,
    pub seen_r1: i32,
}

impl Motion {
    pub fn at_rest() -> Self {
        Motion {
            settled: true,
            ..Motion::default()
        }
    }

    /// Start a trajectory from the current target to `end` (counts).
    pub fn start(&mut self, from: i32, end: i32, accel: u32, vmax: u32, cond: Option<Cond>) {
        self.pos = i64::from(from) << FRAC;
        self.end = i64::from(end) << FRAC;
        self.dir = (self.end - self.pos).signum();
        self.speed = 0;
        self.accel = i64::from(accel);
        self.vmax = i64::from(vmax);
        self.stop_cond = cond;
        self.stopping = false;
        // A zero-length move, or one with no speed allowed, is over before it starts.
        self.active = self.dir != 0 && vmax > 0;
    }

    /// One tick of the trajectory generator. Returns the target in whole counts.
    pub fn advance_trajectory(&mut self) -> i32 {
        if self.stopping {
            self.speed = (self.speed - self.accel).max(0);
            self.pos += self.dir * self.speed;
            if self.speed == 0 {
                // Stop on a whole count so the target register and the model agree.
                self.pos = round_q26(self.pos) << FRAC;
                self.active = false;
            }
        } else {
            let remaining = ((self.end - self.pos) * self.dir) as u128;
            let braking = braking_speed(self.accel as u128, remaining);
            self.speed = (self.speed + self.accel).min(self.vmax).min(braking);
            if self.speed as u128 >= remaining {
                self.pos = self.end;
                self.speed = 0;
                self.active = false;
            } else {
                self.pos += self.dir * self.speed;
            }
        }
        (self.pos >> FRAC) as i32
    }

    /// One tick of the follower towards `reference` (Q26). Returns R1 (whole counts).
    pub fn advance_follower(&mut self, reference: i64, k1: i64, k2: i64) -> i32 {
        let err = reference - self.x;
        let acc = ((i128::from(k1) * i128::from(err)) >> 32)
            - ((i128::from(k2) * i128::from(self.v)) >> 32);
        self.v = self.v.saturating_add(acc as i64);
        self.x = self.x.saturating_add(self.v);
        if !self.active && (reference - self.x).abs() < SETTLE && self.v.abs() < SETTLE {
            self.x = reference;
            self.v = 0;
            self.settled = true;
        }
        round_q26(self.x) as i32
    }

    /// Shift the whole model by whole counts (SUB_TARGET, ZTP): the motor does not move.
    /// Wrapping, as the registers do: a program may shift by any amount again and again, and
    /// 2^64 in Q26 is a whole number of 2^32 counts, so R0/R1 read the same either way.
    pub fn shift(&mut self, target_by: i64, actual_by: i64) {
        let t = target_by << FRAC;
        self.pos = self.pos.wrapping_sub(t);
        self.end = self.end.wrapping_sub(t);
        self.x = self.x.wrapping_sub(actual_by << FRAC);
    }
}

/// Nearest whole count, ties up.
pub fn round_q26(v: i64) -> i64 {
    (v + (ONE >> 1)) >> FRAC
}

/// Largest speed `s` whose discrete braking distance `s + (s−a) + (s−2a) + … ≈ s(s+a)/2a` does
/// not exceed `remaining`: `s = (√(a² + 8a·r) − a) / 2`.
fn braking_speed(accel: u128, remaining: u128) -> i64 {
    let root = isqrt(accel * accel + 8 * accel * remaining);
    let s = (root - accel) / 2;
    s.min(i64::MAX as u128) as i64
}

/// Integer square root (floor), exact for every u128. `u128::isqrt` gives the same result, but
/// its all-integer method costs about 10 % of a move's tick (`cargo bench --bench machine`,
/// "long move"); a hardware f64 estimate corrected exactly is faster.
pub fn isqrt(n: u128) -> u128 {
    if n < 2 {
        return n;
    }
    let mut r = (n as f64).sqrt() as u128;
    while r.checked_mul(r).is_none_or(|sq| sq > n) {
        r -= 1;
    }
    while (r + 1).checked_mul(r + 1).is_some_and(|sq| sq <= n) {
        r += 1;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isqrt_agrees_with_std() {
        for n in [
            0u128,
            1,
            2,
            3,
            4,
            15,
            16,
            17,
            (1 << 52) + 1,
            (1 << 60) - 1,
            1 << 60,
            (1 << 92) + 12345,
            u128::MAX,
        ] {
            assert_eq!(isqrt(n), n.isqrt(), "{n}");
        }
    }

    #[test]
    fn default_coefficients_match_25_hz() {
        let (k1, k2) = ServoSettings::default().coefficients();
        let w_dt = 2.0 * std::f64::consts::PI * 25.0 * 120e-6;
        assert!((k1 as f64 / 4_294_967_296.0 - w_dt * w_dt).abs() < 1e-9);
        assert!((k2 as f64 / 4_294_967_296.0 - 1.4 * w_dt).abs() < 1e-9);
    }
}
