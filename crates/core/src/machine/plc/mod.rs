//! What the scanned PLC dialects share (DL205 and OpenNet): the virtual time base with its
//! `scan_ms` setting and clock relays, the edge memory of edge contacts, and the arithmetic of
//! timers and counters that differs between vendors only in units, limits and number format.
//! Each dialect keeps only its own rules (which relay is which clock, BCD or binary values,
//! counting up or down); a new scanned PLC reuses this module whole.
//!
//! Time is virtual: scan t starts at t × scan_ms ms. Nothing reads a real clock, so a run is
//! the same on every machine and at every speed the window runs it.

use super::dialect::{SettingInfo, Settings};
use super::{Loc, LocInfo, WriteError};

pub mod ladder;
pub mod scan;

pub use scan::{ScannedPlc, hold_forces, open};

/// The word logic both PLCs' AND/OR/XOR boxes compute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Logic {
    And,
    Or,
    Xor,
}

impl Logic {
    pub fn apply(self, a: u32, b: u32) -> u32 {
        match self {
            Logic::And => a & b,
            Logic::Or => a | b,
            Logic::Xor => a ^ b,
        }
    }
}

/// The bits a user forced, with their levels, in the order forced: each keeps its level
/// whatever the program writes (DL250/260 "override", WindLDR "set/reset forced"). Part of the
/// machine's state, so checkpoints, time travel and sessions carry them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Forces(pub Vec<(Loc, bool)>);

impl Forces {
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    pub fn get(&self, loc: Loc) -> Option<bool> {
        self.0.iter().find(|(l, _)| *l == loc).map(|&(_, on)| on)
    }

    /// Force (Some) or release (None) `loc`, a bit described by `info`: only a one-bit location
    /// a user may write can be forced.
    pub fn set(
        &mut self,
        loc: Loc,
        info: Option<LocInfo>,
        level: Option<bool>,
    ) -> Result<(), WriteError> {
        let info = info.ok_or(WriteError::NoSuchLocation)?;
        if info.width != 1 || !info.editable {
            return Err(WriteError::NotForceable(info.name));
        }
        self.0.retain(|(l, _)| *l != loc);
        if let Some(on) = level {
            self.0.push((loc, on));
        }
        Ok(())
    }

    /// A user's write to a forced bit is refused: the force decides its level.
    pub fn check_write(&self, loc: Loc, name: impl FnOnce() -> String) -> Result<(), WriteError> {
        match self.get(loc) {
            Some(on) => Err(WriteError::Forced { name: name(), on }),
            None => Ok(()),
        }
    }
}

/// The `scan_ms` setting every scanned PLC offers: the controller time one scan takes.
pub const SCAN_MS: SettingInfo = SettingInfo {
    key: "scan_ms",
    label: "Scan time (ms)",
    help: "Controller time of one scan: timers and clock relays advance by this much per scan",
    min: 1.0,
    max: 1000.0,
    default: 10.0,
    integer: true,
};

/// The scan time of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimeBase {
    pub scan_ms: u32,
}

impl Default for TimeBase {
    fn default() -> Self {
        TimeBase { scan_ms: 10 }
    }
}

impl TimeBase {
    /// From a dialect's settings (already clamped by the registry; a missing key is the
    /// default).
    pub fn from_settings(settings: &Settings) -> Self {
        let ms = settings
            .get(SCAN_MS.key)
            .copied()
            .unwrap_or(SCAN_MS.default)
            .clamp(SCAN_MS.min, SCAN_MS.max);
        TimeBase {
            scan_ms: ms.round() as u32,
        }
    }

    /// Controller time at the start of scan `tick`, in ms.
    #[inline]
    pub fn time_ms(self, tick: u64) -> u64 {
        tick.saturating_mul(u64::from(self.scan_ms))
    }

    pub fn micros(self) -> u32 {
        self.scan_ms * 1000
    }

    /// Where scan `tick` starts inside a clock's period of `period_ms`, in ms.
    #[inline]
    pub fn phase(self, tick: u64, period_ms: u64) -> u64 {
        self.time_ms(tick) % period_ms.max(1)
    }

    /// A clock that is off in the first half of each period and on in the second (DL205's
    /// SP3–SP6).
    #[inline]
    pub fn late_half(self, tick: u64, period_ms: u64) -> bool {
        self.phase(tick, period_ms) >= period_ms / 2
    }

    /// A clock that is on in the first half of each period (OpenNet's M8121–M8123).
    #[inline]
    pub fn early_half(self, tick: u64, period_ms: u64) -> bool {
        !self.late_half(tick, period_ms)
    }
}

/// The memory of each edge instruction: its input at its previous execution, false before
/// the first (so an input already on at scan 0 fires then).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Edges(pub Vec<bool>);

impl Edges {
    pub fn new(count: usize) -> Self {
        Edges(vec![false; count])
    }

    /// Whether `now` rose since edge `i` last ran; remembers `now`.
    pub fn rose(&mut self, i: usize, now: bool) -> bool {
        self.swap(i, now).is_some_and(|was| now && !was)
    }

    /// Whether `now` fell since edge `i` last ran; remembers `now`.
    pub fn fell(&mut self, i: usize, now: bool) -> bool {
        self.swap(i, now).is_some_and(|was| !now && was)
    }

    fn swap(&mut self, i: usize, now: bool) -> Option<bool> {
        self.0.get_mut(i).map(|m| std::mem::replace(m, now))
    }

    pub fn get(&self, i: usize) -> bool {
        self.0.get(i).copied().unwrap_or(false)
    }
}

/// Time toward a timer's next unit: add one scan, get the whole units it completes.
/// `ms` is what was left over from earlier scans; returns (whole units, ms left).
pub fn accumulate(ms: u32, scan_ms: u32, unit_ms: u32) -> (u64, u32) {
    let total = u64::from(ms) + u64::from(scan_ms);
    let unit = u64::from(unit_ms.max(1));
    (total / unit, (total % unit) as u32)
}

/// The value of the low `n` BCD digits of `x`, or None if one is not a decimal digit.
pub fn bcd_value(x: u32, n: u32) -> Option<u64> {
    let mut v = 0u64;
    for i in (0..n).rev() {
        let d = x >> (4 * i) & 0xF;
        if d > 9 {
            return None;
        }
        v = v * 10 + u64::from(d);
    }
    Some(v)
}

/// The BCD pattern of the low 8 decimal digits of `v`.
pub fn to_bcd(v: u64) -> u32 {
    let mut v = v % 100_000_000;
    let mut out = 0u32;
    for i in 0..8 {
        out |= ((v % 10) as u32) << (4 * i);
        v /= 10;
    }
    out
}

/// Counter inputs at the previous execution, for counting on off→on changes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CounterInputs {
    pub up: bool,
    pub down: bool,
}

impl CounterInputs {
    /// The rises of up and down since the last execution; remembers the new levels.
    pub fn rises(&mut self, up: bool, down: bool) -> (bool, bool) {
        let rises = (up && !self.up, down && !self.down);
        *self = CounterInputs { up, down };
        rises
    }
}

/// One timer or counter box as the Timers & counters panel shows it: the dialect decodes its
/// own number format (DL205 BCD, OpenNet binary) into these.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxRow {
    /// The box as written: `TMR T1`, `CNT CT3`.
    pub title: String,
    /// The status bit's name (`T1`), for the done chip.
    pub status: String,
    /// The preset as written (`K30`, `V2000`) and its value, None when it is not a number in
    /// the dialect's format.
    pub preset_from: String,
    pub preset: Option<u64>,
    /// The current value's location (`TA1`, `V1`) and its value (None: not in the format).
    pub value_at: String,
    pub value: Option<u64>,
    /// The raw current value, shown when it does not decode.
    pub raw: u64,
    pub max: u64,
    /// Timers: the unit in ms, to show time; None for counters.
    pub unit_ms: Option<u32>,
    pub done: bool,
    /// Source line of the box.
    pub line: usize,
    /// A timer that counts down from its preset (OpenNet); None for one that counts up.
    pub countdown: Option<Countdown>,
}

/// The state of a count-down timer the panel turns into time: where it is toward its next
/// increment and the scan time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Countdown {
    pub running: bool,
    pub elapsed_ms: u32,
    pub scan_ms: u32,
}

impl BoxRow {
    /// Progress toward the preset, 0–1 (a preset of 0 is reached at once). A count-down
    /// timer has gone the way from its preset down to its current value.
    pub fn progress(&self) -> f32 {
        match (self.value, self.preset) {
            (Some(v), Some(p)) if p > 0 => {
                let done = if self.countdown.is_some() {
                    p.saturating_sub(v)
                } else {
                    v
                };
                (done as f32 / p as f32).min(1.0)
            }
            (Some(_), Some(_)) => 1.0,
            _ => 0.0,
        }
    }

    /// A count-down timer's time so far and the scans until its output turns on (None when
    /// not timing or already on): (elapsed ms, scans to go).
    pub fn elapsed(&self) -> Option<(u64, Option<u64>)> {
        let c = self.countdown?;
        let (unit, value, preset) = (u64::from(self.unit_ms?), self.value?, self.preset?);
        if !c.running {
            return Some((0, None));
        }
        // Once done the time stops at the preset (the remainder keeps turning underneath).
        let elapsed = if value == 0 {
            preset * unit
        } else {
            preset.saturating_sub(value) * unit + u64::from(c.elapsed_ms)
        };
        let left = (value * unit).saturating_sub(u64::from(c.elapsed_ms));
        let scans = (value > 0).then(|| left.div_ceil(u64::from(c.scan_ms.max(1))));
        Some((elapsed, scans))
    }

    /// A value in the box's terms: "2.9 s" for a 100 ms timer holding 29, "29" for a counter.
    pub fn amount(&self, v: u64) -> String {
        match self.unit_ms {
            Some(unit) => {
                let ms = v * u64::from(unit);
                let decimals = match unit {
                    100.. => 1,
                    10.. => 2,
                    _ => 3,
                };
                let scale = 10u64.pow(3 - decimals as u32);
                format!("{}.{:0decimals$} s", ms / 1000, (ms % 1000) / scale)
            }
            None => v.to_string(),
        }
    }

    /// What is special about the box now: at its maximum, or data not in the format.
    pub fn note(&self) -> Option<String> {
        match (self.value, self.preset) {
            (None, _) => Some(format!(
                "{} = {:X} is not BCD: not counted (SP75)",
                self.value_at, self.raw
            )),
            (_, None) => Some("the preset is not BCD (SP75)".to_string()),
            (Some(v), _) if v >= self.max && self.countdown.is_none() => {
                Some("at its maximum".to_string())
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_and_clocks() {
        let t = TimeBase { scan_ms: 10 };
        assert_eq!(t.time_ms(300), 3000);
        // A 100 ms clock: off for scans 0–4, on for 5–9.
        let late: Vec<bool> = (0..10).map(|k| t.late_half(k, 100)).collect();
        assert_eq!(
            late,
            [
                false, false, false, false, false, true, true, true, true, true
            ]
        );
        assert!(t.early_half(0, 100) && !t.early_half(5, 100));
        // With 1000 ms scans a 1 s clock aliases: always at phase 0.
        let slow = TimeBase { scan_ms: 1000 };
        assert!((0..10).all(|k| !slow.late_half(k, 1000)));
    }

    #[test]
    fn settings_give_the_scan_time() {
        let mut s = Settings::new();
        assert_eq!(TimeBase::from_settings(&s).scan_ms, 10);
        s.insert("scan_ms".into(), 25.0);
        assert_eq!(TimeBase::from_settings(&s).scan_ms, 25);
        s.insert("scan_ms".into(), 5000.0);
        assert_eq!(TimeBase::from_settings(&s).scan_ms, 1000);
    }

    #[test]
    fn edges_fire_once_per_change() {
        let mut e = Edges::new(2);
        assert!(
            e.rose(0, true),
            "an input already on fires at its first execution"
        );
        assert!(!e.rose(0, true));
        assert!(e.fell(0, false));
        assert!(!e.fell(0, false));
        assert!(!e.rose(7, true), "no such edge: nothing fires");
    }

    #[test]
    fn accumulate_carries_the_remainder() {
        // 30 ms scans toward 100 ms units: 0.3, 0.6, 0.9, then 1 unit with 20 ms left.
        let mut ms = 0;
        let mut units = 0;
        for _ in 0..4 {
            let (u, left) = accumulate(ms, 30, 100);
            units += u;
            ms = left;
        }
        assert_eq!((units, ms), (1, 20));
        assert_eq!(accumulate(0, 1000, 10), (100, 0));
    }

    #[test]
    fn box_rows_speak_time_and_progress() {
        let row = BoxRow {
            title: "TMR T1".into(),
            status: "T1".into(),
            preset_from: "K30".into(),
            preset: Some(30),
            value_at: "TA1".into(),
            value: Some(29),
            raw: 0x29,
            max: 9999,
            unit_ms: Some(100),
            done: false,
            line: 2,
            countdown: None,
        };
        assert_eq!(row.amount(29), "2.9 s");
        assert!((row.progress() - 29.0 / 30.0).abs() < 1e-6);
        assert_eq!(row.note(), None);
        let fast = BoxRow {
            unit_ms: Some(10),
            ..row.clone()
        };
        assert_eq!(fast.amount(29), "0.29 s");
        let bad = BoxRow {
            value: None,
            raw: 0xA0,
            ..row.clone()
        };
        assert!(bad.note().is_some_and(|n| n.contains("A0 is not BCD")));
        let full = BoxRow {
            value: Some(9999),
            ..row.clone()
        };
        assert_eq!(full.note().as_deref(), Some("at its maximum"));
        // OpenNet's TIM preset 50 at 30 ms scans, 12 left and 20 ms toward the next tenth:
        // 3.8 s gone (38 tenths + 20 ms), 1.2 s − 20 ms = 1180 ms to go = 40 scans (39.3 up).
        let down = BoxRow {
            preset: Some(50),
            value: Some(12),
            countdown: Some(Countdown {
                running: true,
                elapsed_ms: 20,
                scan_ms: 30,
            }),
            ..row
        };
        assert_eq!(down.elapsed(), Some((3820, Some(40))));
        let done = BoxRow {
            value: Some(0),
            done: true,
            ..down.clone()
        };
        assert_eq!(
            done.elapsed(),
            Some((5000, None)),
            "done: the preset's time"
        );
        assert!((down.progress() - 38.0 / 50.0).abs() < 1e-6);
        assert_eq!(down.note(), None);
        let ms = BoxRow {
            unit_ms: Some(1),
            ..down
        };
        assert_eq!(ms.amount(5), "0.005 s");
        assert_eq!(ms.amount(1234), "1.234 s");
    }

    #[test]
    fn counters_count_rises_only() {
        let mut c = CounterInputs::default();
        assert_eq!(c.rises(true, false), (true, false));
        assert_eq!(c.rises(true, false), (false, false));
        assert_eq!(c.rises(false, true), (false, true));
    }
}
