//! Frame pacing while running unlimited, and frame-time measurement (`--frame-stats`).

use std::time::{Duration, Instant};

/// The frame time aimed at while running unlimited (under 60 fps's 16.7 ms, with room for jitter).
pub const TARGET_FRAME: Duration = Duration::from_millis(15);
/// The most [`FramePacer`] brings a frame forward to keep the cadence.
pub const MAX_LEAD: Duration = Duration::from_millis(3);
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

/// Frames every [`TARGET_FRAME`] while running unlimited, as they come and not only as they are
/// asked for. The wait before the next frame is the target less the frame's own time and less a
/// *lead*: how much earlier than the target frames must be asked for to come on time, learned
/// from the intervals measured (each moves the lead by an eighth of its difference to the
/// target, within 0..[`MAX_LEAD`]). On an idle machine the lead is the wake-up delay (a few
/// tenths of a millisecond); with another process busy on a core the scheduler delays frames
/// more and the lead grows (a fixed earlier aim would draw more frames than needed on an idle
/// machine, taking time from the simulation). With a GPU, vsync paces frames anyway. The
/// measurements are in docs/figures.md.
#[derive(Debug, Default)]
pub struct FramePacer {
    last_started: Option<Instant>,
    lead: Duration,
}

impl FramePacer {
    /// For a frame that began at `started`: how long from `now` until the next is asked for.
    pub fn wait(&mut self, started: Instant, now: Instant) -> Duration {
        if let Some(last) = self.last_started {
            let interval = started.saturating_duration_since(last);
            // A pause, a stall or the first frame of a run says nothing about the cadence.
            if interval < TARGET_FRAME * 2 {
                let lead = self.lead.as_secs_f64()
                    + (interval.as_secs_f64() - TARGET_FRAME.as_secs_f64()) / 8.0;
                self.lead = Duration::from_secs_f64(lead.clamp(0.0, MAX_LEAD.as_secs_f64()));
            }
        }
        self.last_started = Some(started);
        TARGET_FRAME
            .saturating_sub(self.lead)
            .saturating_sub(now.saturating_duration_since(started))
    }

    /// How much earlier than the target the next frame is asked for.
    pub fn lead(&self) -> Duration {
        self.lead
    }
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
    /// The threads' CPU time when measuring began (where the system tells it).
    cpu_at_start: Option<ThreadCpu>,
}

/// CPU time of this process's threads in nanoseconds: the window's own thread (the process's
/// first), the simulation thread, and the rest (without a GPU, the rasterizer's threads).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ThreadCpu {
    pub window: u64,
    pub simulation: u64,
    pub others: u64,
}

impl ThreadCpu {
    /// Read from `/proc/self/task/*/schedstat` (Linux); `None` where there is no such file.
    pub fn now() -> Option<ThreadCpu> {
        let pid = std::process::id().to_string();
        let mut cpu = ThreadCpu::default();
        for task in std::fs::read_dir("/proc/self/task").ok()?.flatten() {
            let path = task.path();
            let Some(nanos) = std::fs::read_to_string(path.join("schedstat"))
                .ok()
                .and_then(|s| schedstat_nanos(&s))
            else {
                continue;
            };
            let name = std::fs::read_to_string(path.join("comm")).unwrap_or_default();
            if task.file_name().to_str() == Some(pid.as_str()) {
                cpu.window += nanos;
            } else if name.trim_end() == "simulation" {
                cpu.simulation += nanos;
            } else {
                cpu.others += nanos;
            }
        }
        Some(cpu)
    }
}

/// The CPU each group of threads spent a frame, between two readings `frames` frames apart.
fn cpu_per_frame(before: ThreadCpu, after: ThreadCpu, frames: usize) -> String {
    let ms = |a: u64, b: u64| b.saturating_sub(a) as f64 / 1e6 / frames.max(1) as f64;
    format!(
        "; CPU a frame: window thread {:.2} ms, other threads (the renderer's, without a GPU) {:.2} ms, simulation {:.2} ms",
        ms(before.window, after.window),
        ms(before.others, after.others),
        ms(before.simulation, after.simulation)
    )
}

/// The first field of a `schedstat` line: nanoseconds spent running.
fn schedstat_nanos(line: &str) -> Option<u64> {
    line.split_whitespace().next()?.parse().ok()
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
            cpu_at_start: None,
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
                if self.start.is_none() {
                    self.start = Some((started, tick));
                    self.cpu_at_start = ThreadCpu::now();
                }
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
            // From the first measured frame's end to the last's: one interval fewer.
            let cpu = match (self.cpu_at_start, ThreadCpu::now()) {
                (Some(before), Some(after)) => cpu_per_frame(before, after, self.frames - 1),
                _ => String::new(),
            };
            format!(
                "{} frames running unlimited: frame interval median {interval_median:.2} ms, worst {interval_worst:.2} ms; time in ui (simulation + layout) median {work_median:.2} ms, worst {work_worst:.2} ms; {:.2} M ticks/s (×{real_time:.0} real time){cpu}",
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
    fn cpu_a_frame_is_each_threads_time_over_the_frames() {
        assert_eq!(
            schedstat_nanos("528977072 115586285 1221\n"),
            Some(528_977_072)
        );
        assert_eq!(schedstat_nanos(""), None);
        let before = ThreadCpu {
            window: 1_000_000,
            simulation: 0,
            others: 5_000_000,
        };
        let after = ThreadCpu {
            window: 11_000_000,
            simulation: 150_000_000,
            others: 95_000_000,
        };
        assert_eq!(
            cpu_per_frame(before, after, 10),
            "; CPU a frame: window thread 1.00 ms, other threads (the renderer's, without a GPU) 9.00 ms, simulation 15.00 ms"
        );
    }

    #[test]
    fn this_process_reads_its_threads_cpu_where_linux_tells_it() {
        if cfg!(target_os = "linux") {
            let first = ThreadCpu::now().expect("/proc/self/task on Linux");
            // Spin until the clock the scheduler keeps moves on.
            let t = Instant::now();
            let mut x = 0u64;
            while t.elapsed() < Duration::from_millis(20) {
                x = std::hint::black_box(x.wrapping_add(1));
            }
            let second = ThreadCpu::now().expect("/proc/self/task on Linux");
            let total = |c: ThreadCpu| c.window + c.simulation + c.others;
            assert!(total(second) > total(first), "{first:?} then {second:?}");
        }
    }

    #[test]
    fn frames_asked_for_earlier_as_long_as_they_come_late() {
        let ms = Duration::from_millis;
        let t0 = Instant::now();
        let mut pacer = FramePacer::default();
        // The first frame of a run: the target less its own 4 ms.
        assert_eq!(pacer.wait(t0, t0 + ms(4)), TARGET_FRAME - ms(4));
        // Frames that keep coming 2 ms late are asked for earlier, an eighth of the delay at a
        // time, up to the limit.
        let mut started = t0;
        let mut waits = Vec::new();
        for _ in 0..40 {
            started += TARGET_FRAME + ms(2);
            waits.push(pacer.wait(started, started + ms(4)));
        }
        assert_eq!(waits[0], TARGET_FRAME - ms(4) - ms(2) / 8);
        assert!(waits.windows(2).all(|w| w[1] <= w[0]), "{waits:?}");
        assert_eq!(pacer.lead(), MAX_LEAD);
        assert_eq!(waits[39], TARGET_FRAME - ms(4) - MAX_LEAD);
        // Frames on time from then on: the lead settles where they come every TARGET_FRAME,
        // which is no lead at all once nothing delays them.
        for _ in 0..200 {
            let due = started + TARGET_FRAME - pacer.lead();
            started = due;
            pacer.wait(started, started + ms(4));
        }
        assert!(pacer.lead() < ms(1) / 10, "{:?}", pacer.lead());
        // A pause of a second is not a late frame.
        let lead = pacer.lead();
        pacer.wait(started + ms(1000), started + ms(1004));
        assert_eq!(pacer.lead(), lead);
        // A frame that takes longer than the target asks for the next at once.
        let slow = started + ms(1000) + TARGET_FRAME;
        assert_eq!(pacer.wait(slow, slow + ms(20)), Duration::ZERO);
    }

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
