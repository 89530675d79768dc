//! The trace that plots read: the values of the chosen channels (locations, at most
//! [`MAX_CHANNELS`]) for every tick.
//!
//! Stored as change points: a sample is kept only for a tick where one of the values changed,
//! and holds until the next sample. An idle motor costs nothing; a moving one about 8 bytes per
//! channel a tick. Every [`BLOCK`] samples also get a min/max summary, so the min/max of any
//! column of a plot is found from a few summaries plus the partial blocks at its edges:
//! decimating millions of samples to a plot's width takes well under a millisecond.
//!
//! Bound: at most `capacity` samples (16 M by default, about 400 MB with summaries, reached only
//! by 16 M ticks of continuous motion). Past it the oldest quarter is dropped: the trace then
//! starts later, like an oscilloscope's memory.

use std::ops::Range;

use crate::machine::Loc;
use crate::machine::value::{self, Format, sign_extend};

pub const BLOCK: usize = 256;
pub const DEFAULT_CAPACITY: usize = 16 << 20;
/// Channels a trace records at most.
pub const MAX_CHANNELS: usize = 8;
/// Stacked plots the channels are grouped into (a channel's group is below this).
pub const PLOT_GROUPS: u8 = 4;

/// One recorded location: where it is, how to read it and how the plot calls it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Channel {
    pub loc: Loc,
    /// The location's name (sessions store channels by name).
    pub name: String,
    pub label: String,
    pub width: u8,
    pub signed: bool,
    /// The location's reading: BCD words are plotted as the decimal number their digits say,
    /// Q16.16 as a real number; any other reading as the integer.
    pub reading: Format,
    /// Channels of the same group share a plot.
    pub group: u8,
    /// A watch expression plotted instead of the location (`loc` is then unused).
    pub expr: Option<crate::debugger::expr::Expr>,
}

impl Channel {
    /// The channel's number in `m`'s present state.
    #[inline]
    pub fn sample<M: crate::machine::MachineView + ?Sized>(&self, m: &M) -> i64 {
        match &self.expr {
            Some(e) => e.eval(m),
            None => self.value(m.read(self.loc)),
        }
    }

    /// The stored number for raw bits of this location.
    #[inline]
    pub fn value(&self, raw: u64) -> i64 {
        if self.signed {
            sign_extend(raw, self.width)
        } else {
            (raw & crate::machine::value::mask(self.width)) as i64
        }
    }
}

impl Channel {
    /// The name of the reading when it is not a plain integer ("BCD", "Q16.16").
    pub fn reading_name(&self) -> Option<&'static str> {
        matches!(self.reading, Format::Bcd | Format::Q16).then(|| self.reading.name())
    }

    /// The label with its reading: `ACC (BCD)`, `speed (Q16.16)`, `R1`.
    pub fn titled(&self) -> String {
        match self.reading_name() {
            Some(reading) => format!("{} ({reading})", self.label),
            None => self.label.clone(),
        }
    }

    /// Where a stored value is drawn: BCD decoded, Q16.16 as a real number.
    pub fn plotted(&self, v: i64) -> f64 {
        match self.reading {
            Format::Bcd => value::bcd_decimal(v as u64 & value::mask(self.width)) as f64,
            Format::Q16 => value::sign_extend(v as u64, self.width) as f64 / 65536.0,
            _ => v as f64,
        }
    }

    /// A stored value as the user reads it: `9750`, `1.5`, `12A4 (not BCD)`.
    pub fn value_text(&self, v: i64) -> String {
        match self.reading {
            Format::Bcd | Format::Q16 => self.reading.show(v as u64, self.width),
            _ => v.to_string(),
        }
    }
}

/// The channels' values at one tick.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Sample {
    pub tick: u64,
    pub values: Vec<i64>,
}

impl Sample {
    pub fn get(&self, channel: usize) -> i64 {
        self.values.get(channel).copied().unwrap_or(0)
    }
}

/// Min and max of every channel over one block.
#[derive(Clone, Debug)]
struct Summary {
    min: Vec<i64>,
    max: Vec<i64>,
}

#[derive(Clone, Debug)]
pub struct Trace {
    ticks: Vec<u64>,
    /// One column per channel.
    values: Vec<Vec<i64>>,
    /// Min/max of each full block of BLOCK samples.
    blocks: Vec<Summary>,
    capacity: usize,
    /// The last tick recorded, changed or not: the last sample holds until here.
    end: u64,
    /// Samples dropped from the front since the trace began (for the user: "starts at tick N").
    dropped: u64,
}

impl Trace {
    pub fn new(channels: usize) -> Self {
        Trace::with_capacity(channels, DEFAULT_CAPACITY)
    }

    pub fn with_capacity(channels: usize, capacity: usize) -> Self {
        Trace {
            ticks: Vec::new(),
            values: vec![Vec::new(); channels.min(MAX_CHANNELS)],
            blocks: Vec::new(),
            capacity: capacity.max(4 * BLOCK),
            end: 0,
            dropped: 0,
        }
    }

    pub fn len(&self) -> usize {
        self.ticks.len()
    }
    pub fn channels(&self) -> usize {
        self.values.len()
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

    /// The values held until `tick` (nothing changed): what `record` does with the values of
    /// the last sample, without comparing them.
    #[inline]
    pub fn extend_to(&mut self, tick: u64) {
        self.end = self.end.max(tick);
    }

    /// Record the values after `tick`. Kept only if something changed (or it is the first).
    /// Returns whether the newest sample now holds `values` (false only for a tick older than
    /// the newest sample, which changes nothing).
    #[inline]
    pub fn record(&mut self, tick: u64, values: &[i64]) -> bool {
        self.end = self.end.max(tick);
        if let Some(last) = self.ticks.len().checked_sub(1) {
            let same = self
                .values
                .iter()
                .zip(values)
                .all(|(column, v)| column[last] == *v);
            if same || self.ticks[last] >= tick {
                if !same && self.ticks[last] == tick {
                    // A second record of the same tick (a user edit): the newest values win.
                    for (column, v) in self.values.iter_mut().zip(values) {
                        column[last] = *v;
                    }
                    self.rebuild_last_block();
                    return true;
                }
                return same;
            }
        }
        if self.ticks.len() == self.ticks.capacity() {
            // Grow by an eighth rather than doubling: a long trace wastes at most 12 %.
            let more = (self.ticks.len() / 8).max(1 << 16);
            self.ticks.reserve_exact(more);
            self.values.iter_mut().for_each(|v| v.reserve_exact(more));
        }
        self.ticks.push(tick);
        for (column, v) in self.values.iter_mut().zip(values) {
            column.push(*v);
        }
        if self.ticks.len().is_multiple_of(BLOCK) {
            let start = self.ticks.len() - BLOCK;
            self.blocks.push(self.summarise(start..self.ticks.len()));
        }
        if self.ticks.len() > self.capacity {
            self.drop_oldest_quarter();
        }
        true
    }

    fn summarise(&self, range: Range<usize>) -> Summary {
        let n = self.values.len();
        let mut s = Summary {
            min: vec![i64::MAX; n],
            max: vec![i64::MIN; n],
        };
        for (c, column) in self.values.iter().enumerate() {
            for &v in &column[range.clone()] {
                s.min[c] = s.min[c].min(v);
                s.max[c] = s.max[c].max(v);
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
            values: self.values.iter().map(|column| column[i]).collect(),
        }
    }

    /// Every change point, oldest first (for export and comparisons).
    pub fn samples(&self) -> impl Iterator<Item = Sample> + '_ {
        (0..self.len()).map(|i| self.sample(i))
    }

    /// Min and max of channel `s` over sample indices `range` (non-empty).
    fn min_max(&self, s: usize, range: Range<usize>) -> (i64, i64) {
        let data = &self.values[s];
        let scan = |r: Range<usize>, (lo, hi): (i64, i64)| {
            data[r]
                .iter()
                .fold((lo, hi), |(lo, hi), &v| (lo.min(v), hi.max(v)))
        };
        let first_block = range.start.div_ceil(BLOCK);
        let last_block = range.end / BLOCK;
        let (mut lo, mut hi) = (i64::MAX, i64::MIN);
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
    pub fn decimate(&self, channel: usize, t0: f64, t1: f64, columns: usize) -> Vec<[f64; 2]> {
        let mut out = Vec::with_capacity(columns * 2);
        if self.is_empty()
            || channel >= self.values.len()
            || columns == 0
            || t0.is_nan()
            || t1.is_nan()
            || t1 <= t0
        {
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
            let (lo, hi) = self.min_max(channel, first..end);
            let x = c0 + width / 2.0;
            out.push([x, lo as f64]);
            if hi != lo {
                out.push([x, hi as f64]);
            }
        }
        out
    }

    /// Bytes held, for the memory figures.
    pub fn memory_bytes(&self) -> usize {
        self.ticks.capacity() * 8
            + self.values.iter().map(|v| v.capacity() * 8).sum::<usize>()
            + self.blocks.capacity() * (std::mem::size_of::<Summary>() + 16 * self.values.len())
    }

    /// CSV of every change point: `tick,time_ms,` then one column per channel, headed by its
    /// label and reading (`ACC (BCD)`) and holding what the plot draws (BCD decoded, Q16.16 as
    /// a decimal number). A row holds until the next one.
    pub fn write_csv(
        &self,
        out: &mut dyn std::io::Write,
        tick_micros: u32,
        channels: &[Channel],
    ) -> std::io::Result<()> {
        let header: Vec<String> = channels.iter().map(|c| csv_field(&c.titled())).collect();
        writeln!(out, "tick,time_ms,{}", header.join(","))?;
        for s in self.samples() {
            let ms = s.tick as f64 * f64::from(tick_micros) / 1000.0;
            let values: Vec<String> = s
                .values
                .iter()
                .zip(channels)
                .map(|(&v, c)| match c.reading {
                    Format::Bcd => value::bcd_decimal(v as u64 & value::mask(c.width)).to_string(),
                    Format::Q16 => value::q16_exact(sign_extend(v as u64, c.width)),
                    _ => v.to_string(),
                })
                .collect();
            writeln!(out, "{},{ms:.3},{}", s.tick, values.join(","))?;
        }
        Ok(())
    }
}

/// A CSV field, quoted when it holds a separator or a quote.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_only_changes() {
        let mut t = Trace::new(4);
        t.record(0, &[0, 0, 0, 0]);
        t.record(1, &[0, 0, 0, 0]);
        t.record(2, &[5, 0, 5, 0]);
        t.record(3, &[5, 0, 5, 0]);
        assert_eq!(t.len(), 2);
        assert_eq!(t.at(1).unwrap().values, [0, 0, 0, 0]);
        assert_eq!(t.at(3).unwrap().values, [5, 0, 5, 0]);
        assert_eq!(t.at(3).unwrap().tick, 2);
    }

    #[test]
    fn drops_the_oldest_quarter_past_capacity() {
        let mut t = Trace::with_capacity(4, 4 * BLOCK);
        for i in 0..(4 * BLOCK + 1) as u64 {
            t.record(i, &[i as i64, 0, 0, 0]);
        }
        assert_eq!(t.len(), 3 * BLOCK + 1);
        assert_eq!(t.first_tick(), Some(BLOCK as u64));
        assert_eq!(t.dropped(), BLOCK as u64);
        // Summaries still match the data after the drop.
        let d = t.decimate(0, BLOCK as f64, (4 * BLOCK + 1) as f64, 1);
        assert_eq!(
            d,
            vec![[d[0][0], BLOCK as f64], [d[0][0], (4 * BLOCK) as f64]]
        );
    }

    #[test]
    fn truncation_forgets_the_future() {
        let mut t = Trace::new(4);
        for i in 0..1000u64 {
            t.record(i, &[i as i64, 0, 0, 0]);
        }
        t.truncate_after(499);
        assert_eq!(t.end_tick(), Some(499));
        t.record(500, &[7, 0, 0, 0]);
        assert_eq!(t.at(600).unwrap().values[0], 7);
    }
}
