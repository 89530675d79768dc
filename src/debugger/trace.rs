//! The motion trace that plots read: target (R0), actual (R1), error (R6) and velocity (R7)
//! for every tick.
//!
//! Stored as change points: a sample is kept only for a tick where one of the four values
//! changed, and holds until the next sample. An idle motor costs nothing; a moving one about
//! 24 bytes a tick. Every [`BLOCK`] samples also get a min/max summary, so the min/max of any
//! column of a plot is found from a few summaries plus the partial blocks at its edges:
//! decimating millions of samples to a plot's width takes well under a millisecond.
//!
//! Bound: at most `capacity` samples (16 M by default, about 400 MB with summaries, reached only
//! by 16 M ticks of continuous motion). Past it the oldest quarter is dropped: the trace then
//! starts later, like an oscilloscope's memory.

use std::ops::Range;

pub const BLOCK: usize = 256;
pub const DEFAULT_CAPACITY: usize = 16 << 20;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Series {
    Target,
    Actual,
    Error,
    Velocity,
}

impl Series {
    pub const ALL: [Series; 4] = [
        Series::Target,
        Series::Actual,
        Series::Error,
        Series::Velocity,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Series::Target => "target (R0)",
            Series::Actual => "actual (R1)",
            Series::Error => "error (R6)",
            Series::Velocity => "velocity (R7)",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// The four values at one tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Sample {
    pub tick: u64,
    pub values: [i32; 4],
}

impl Sample {
    pub fn get(&self, s: Series) -> i32 {
        self.values[s.index()]
    }
}

#[derive(Clone, Copy, Debug)]
struct Summary {
    min: [i32; 4],
    max: [i32; 4],
}

#[derive(Clone, Debug)]
pub struct Trace {
    ticks: Vec<u64>,
    values: [Vec<i32>; 4],
    /// Min/max of each full block of BLOCK samples.
    blocks: Vec<Summary>,
    capacity: usize,
    /// The last tick recorded, changed or not: the last sample holds until here.
    end: u64,
    /// Samples dropped from the front since the trace began (for the user: "starts at tick N").
    dropped: u64,
}

impl Default for Trace {
    fn default() -> Self {
        Trace::with_capacity(DEFAULT_CAPACITY)
    }
}

impl Trace {
    pub fn with_capacity(capacity: usize) -> Self {
        Trace {
            ticks: Vec::new(),
            values: Default::default(),
            blocks: Vec::new(),
            capacity: capacity.max(4 * BLOCK),
            end: 0,
            dropped: 0,
        }
    }

    pub fn len(&self) -> usize {
        self.ticks.len()
    }
    pub fn is_empty(&self) -> bool {
        self.ticks.is_empty()
    }
    pub fn dropped(&self) -> u64 {
        self.dropped
    }
    pub fn first_tick(&self) -> Option<u64> {
        self.ticks.first().copied()
    }
    /// The last tick the trace covers (its last sample holds until here).
    pub fn end_tick(&self) -> Option<u64> {
        (!self.is_empty()).then_some(self.end)
    }

    pub fn clear(&mut self) {
        self.ticks.clear();
        self.values.iter_mut().for_each(Vec::clear);
        self.blocks.clear();
        self.end = 0;
        self.dropped = 0;
    }

    /// Record the values after `tick`. Kept only if something changed (or it is the first).
    #[inline]
    pub fn record(&mut self, tick: u64, values: [i32; 4]) {
        self.end = self.end.max(tick);
        if let Some(last) = self.ticks.len().checked_sub(1) {
            let same = (0..4).all(|s| self.values[s][last] == values[s]);
            if same || self.ticks[last] >= tick {
                if !same && self.ticks[last] == tick {
                    // A second record of the same tick (a user edit): the newest values win.
                    for (s, v) in values.iter().enumerate() {
                        self.values[s][last] = *v;
                    }
                    self.rebuild_last_block();
                }
                return;
            }
        }
        if self.ticks.len() == self.ticks.capacity() {
            // Grow by an eighth rather than doubling: a long trace wastes at most 12 %.
            let more = (self.ticks.len() / 8).max(1 << 16);
            self.ticks.reserve_exact(more);
            self.values.iter_mut().for_each(|v| v.reserve_exact(more));
        }
        self.ticks.push(tick);
        for (s, v) in values.iter().enumerate() {
            self.values[s].push(*v);
        }
        if self.ticks.len().is_multiple_of(BLOCK) {
            let start = self.ticks.len() - BLOCK;
            self.blocks.push(self.summarise(start..self.ticks.len()));
        }
        if self.ticks.len() > self.capacity {
            self.drop_oldest_quarter();
        }
    }

    fn summarise(&self, range: Range<usize>) -> Summary {
        let mut s = Summary {
            min: [i32::MAX; 4],
            max: [i32::MIN; 4],
        };
        for series in 0..4 {
            for &v in &self.values[series][range.clone()] {
                s.min[series] = s.min[series].min(v);
                s.max[series] = s.max[series].max(v);
            }
        }
        s
    }

    fn rebuild_last_block(&mut self) {
        let full = self.ticks.len() / BLOCK;
        if full == self.blocks.len() && full > 0 {
            let start = (full - 1) * BLOCK;
            self.blocks[full - 1] = self.summarise(start..start + BLOCK);
        }
    }

    fn drop_oldest_quarter(&mut self) {
        // Whole blocks, so the summaries stay aligned.
        let drop = (self.ticks.len() / 4 / BLOCK).max(1) * BLOCK;
        self.ticks.drain(..drop);
        for v in &mut self.values {
            v.drain(..drop);
        }
        self.blocks.drain(..drop / BLOCK);
        self.dropped += drop as u64;
    }

    /// Forget everything after `tick` (time travel rewrites the future).
    pub fn truncate_after(&mut self, tick: u64) {
        let keep = self.ticks.partition_point(|&t| t <= tick);
        self.end = self.end.min(tick);
        self.ticks.truncate(keep);
        for v in &mut self.values {
            v.truncate(keep);
        }
        self.blocks.truncate(keep / BLOCK);
    }

    /// Index of the sample in effect at `tick` (the last one at or before it).
    fn index_at(&self, tick: u64) -> Option<usize> {
        self.ticks.partition_point(|&t| t <= tick).checked_sub(1)
    }

    /// The values in effect at `tick`, if the trace covers it.
    pub fn at(&self, tick: u64) -> Option<Sample> {
        let i = self.index_at(tick)?;
        Some(self.sample(i))
    }

    pub fn sample(&self, i: usize) -> Sample {
        Sample {
            tick: self.ticks[i],
            values: [0, 1, 2, 3].map(|s| self.values[s][i]),
        }
    }

    /// Every change point, oldest first (for export and comparisons).
    pub fn samples(&self) -> impl Iterator<Item = Sample> + '_ {
        (0..self.len()).map(|i| self.sample(i))
    }

    /// Min and max of `series` over sample indices `range` (non-empty).
    fn min_max(&self, series: Series, range: Range<usize>) -> (i32, i32) {
        let s = series.index();
        let data = &self.values[s];
        let scan = |r: Range<usize>, (lo, hi): (i32, i32)| {
            data[r]
                .iter()
                .fold((lo, hi), |(lo, hi), &v| (lo.min(v), hi.max(v)))
        };
        let first_block = range.start.div_ceil(BLOCK);
        let last_block = range.end / BLOCK;
        let (mut lo, mut hi) = (i32::MAX, i32::MIN);
        if first_block < last_block && last_block <= self.blocks.len() {
            (lo, hi) = scan(range.start..first_block * BLOCK, (lo, hi));
            for b in &self.blocks[first_block..last_block] {
                lo = lo.min(b.min[s]);
                hi = hi.max(b.max[s]);
            }
            (lo, hi) = scan(last_block * BLOCK..range.end, (lo, hi));
        } else {
            (lo, hi) = scan(range, (lo, hi));
        }
        (lo, hi)
    }

    /// At most two points per column for `columns` columns over ticks `[t0, t1)`: the min and
    /// max of the step function in each column, in tick order. Columns the trace does not
    /// cover are left out.
    pub fn decimate(&self, series: Series, t0: f64, t1: f64, columns: usize) -> Vec<[f64; 2]> {
        let mut out = Vec::with_capacity(columns * 2);
        if self.is_empty() || columns == 0 || t0.is_nan() || t1.is_nan() || t1 <= t0 {
            return out;
        }
        let end = self.end as f64;
        let width = (t1 - t0) / columns as f64;
        for c in 0..columns {
            let c0 = t0 + width * c as f64;
            let c1 = c0 + width;
            if c1 <= self.ticks[0] as f64 || c0 > end {
                continue;
            }
            // Samples in effect somewhere in [c0, c1): the one holding at c0, then every
            // sample that starts before c1.
            let start_tick = c0.max(0.0).floor() as u64;
            let first = self.index_at(start_tick).unwrap_or(0);
            let end = self
                .ticks
                .partition_point(|&t| (t as f64) < c1)
                .max(first + 1);
            let (lo, hi) = self.min_max(series, first..end);
            let x = c0 + width / 2.0;
            out.push([x, f64::from(lo)]);
            if hi != lo {
                out.push([x, f64::from(hi)]);
            }
        }
        out
    }

    /// Bytes held, for the memory figures.
    pub fn memory_bytes(&self) -> usize {
        self.ticks.capacity() * 8
            + self.values.iter().map(|v| v.capacity() * 4).sum::<usize>()
            + self.blocks.capacity() * std::mem::size_of::<Summary>()
    }

    /// CSV of every change point: `tick,time_ms,target,actual,error,velocity`. A row holds
    /// until the next one.
    pub fn write_csv(&self, out: &mut dyn std::io::Write, tick_micros: u32) -> std::io::Result<()> {
        writeln!(out, "tick,time_ms,target,actual,error,velocity")?;
        for s in self.samples() {
            let ms = s.tick as f64 * f64::from(tick_micros) / 1000.0;
            writeln!(
                out,
                "{},{ms:.3},{},{},{},{}",
                s.tick, s.values[0], s.values[1], s.values[2], s.values[3]
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_only_changes() {
        let mut t = Trace::default();
        t.record(0, [0, 0, 0, 0]);
        t.record(1, [0, 0, 0, 0]);
        t.record(2, [5, 0, 5, 0]);
        t.record(3, [5, 0, 5, 0]);
        assert_eq!(t.len(), 2);
        assert_eq!(t.at(1).unwrap().values, [0, 0, 0, 0]);
        assert_eq!(t.at(3).unwrap().values, [5, 0, 5, 0]);
        assert_eq!(t.at(3).unwrap().tick, 2);
    }

    #[test]
    fn drops_the_oldest_quarter_past_capacity() {
        let mut t = Trace::with_capacity(4 * BLOCK);
        for i in 0..(4 * BLOCK + 1) as u64 {
            t.record(i, [i as i32, 0, 0, 0]);
        }
        assert_eq!(t.len(), 3 * BLOCK + 1);
        assert_eq!(t.first_tick(), Some(BLOCK as u64));
        assert_eq!(t.dropped(), BLOCK as u64);
        // Summaries still match the data after the drop.
        let d = t.decimate(Series::Target, BLOCK as f64, (4 * BLOCK + 1) as f64, 1);
        assert_eq!(
            d,
            vec![[d[0][0], BLOCK as f64], [d[0][0], (4 * BLOCK) as f64]]
        );
    }

    #[test]
    fn truncation_forgets_the_future() {
        let mut t = Trace::default();
        for i in 0..1000u64 {
            t.record(i, [i as i32, 0, 0, 0]);
        }
        t.truncate_after(499);
        assert_eq!(t.end_tick(), Some(499));
        t.record(500, [7, 0, 0, 0]);
        assert_eq!(t.at(600).unwrap().values[0], 7);
    }
}
