//! Frame pacing while running unlimited, and frame-time measurement (`--frame-stats`).

use std::time::{Duration, Instant};

/// The frame time aimed at while running unlimited (under 60 fps's 16.7 ms, with room for jitter).
pub const TARGET_FRAME: Duration = Duration::from_millis(15);
/// Bounds of the simulation slice per frame: always some progress, never a sluggish window.
pub const MIN_RUN_SLICE: Duration = Duration::from_millis(2);
pub const MAX_RUN_SLICE: Duration = Duration::from_millis(12);

/// The run slice for the next frame: what the target frame leaves after drawing, where
/// `overhead` is the smoothed part of recent frames not spent simulating.
pub fn run_slice(overhead: Duration) -> Duration {
    TARGET_FRAME
        .saturating_sub(overhead)
        .clamp(MIN_RUN_SLICE, MAX_RUN_SLICE)
}

/// Frame-time measurement (`servoscope --frame-stats N FILE`): runs the program unlimited and
/// reports the frame interval and the time spent in `ui`, median and worst, over N frames, and
/// the simulation rate they achieved.
pub struct FrameStats {
    frames: usize,
    warmup: usize,
    intervals: Vec<f64>,
    work: Vec<f64>,
    last: Option<Instant>,
    /// When measuring began, and the tick the machine was at.
    start: Option<(Instant, u64)>,
}

impl FrameStats {
    pub fn new(frames: usize) -> Self {
        FrameStats {
            frames: frames.max(1),
            warmup: 30,
            intervals: Vec::new(),
            work: Vec::new(),
            last: None,
            start: None,
        }
    }

    /// One frame that began at `started` and ended at `finished` with the machine at `tick`
    /// (ticks of `tick_micros`). The report, once N frames are measured.
    pub fn record(
        &mut self,
        started: Instant,
        finished: Instant,
        tick: u64,
        tick_micros: u32,
    ) -> Option<String> {
        if let Some(last) = self.last {
            if self.warmup > 0 {
                self.warmup -= 1;
            } else {
                self.start.get_or_insert((started, tick));
                self.intervals
                    .push(started.duration_since(last).as_secs_f64() * 1e3);
                self.work
                    .push(finished.duration_since(started).as_secs_f64() * 1e3);
            }
        }
        self.last = Some(started);
        (self.intervals.len() >= self.frames).then(|| {
            let stats = |v: &mut Vec<f64>| {
                v.sort_by(f64::total_cmp);
                (v[v.len() / 2], v[v.len() - 1])
            };
            let (interval_median, interval_worst) = stats(&mut self.intervals);
            let (work_median, work_worst) = stats(&mut self.work);
            let (t0, tick0) = self.start.unwrap_or((started, tick));
            let seconds = finished.duration_since(t0).as_secs_f64().max(1e-9);
            let rate = tick.saturating_sub(tick0) as f64 / seconds;
            let real_time = rate * f64::from(tick_micros) / 1e6;
            format!(
                "{} frames running unlimited: frame interval median {interval_median:.2} ms, worst {interval_worst:.2} ms; time in ui (simulation + layout) median {work_median:.2} ms, worst {work_worst:.2} ms; {:.2} M ticks/s (×{real_time:.0} real time)",
                self.frames,
                rate / 1e6
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_run_slice_is_what_the_frame_leaves() {
        let ms = Duration::from_millis;
        assert_eq!(run_slice(ms(11)), ms(4));
        assert_eq!(
            run_slice(ms(40)),
            MIN_RUN_SLICE,
            "slow drawing still makes progress"
        );
        assert_eq!(
            run_slice(ms(0)),
            MAX_RUN_SLICE,
            "fast drawing does not starve the frame"
        );
    }
}
