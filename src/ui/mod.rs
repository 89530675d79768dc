//! The debugger window. Each panel draws from the [`Debugger`] and its own view settings and
//! returns what the user asked for as [`Command`]s; [`ServoscopeApp::apply`] carries them out.
//! No run logic lives here: it is all in `debugger` and `machine`.

pub mod code;
pub mod controls;
pub mod files;
pub mod plot;
pub mod queues;
pub mod registers;
pub mod status;
pub mod theme;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::debugger::format::Format;
use crate::debugger::{Debugger, Speed};
use crate::machine::Machine;

/// Example programs built into the binary, for the Examples menu and the start screen.
pub const EXAMPLES: &[(&str, &str)] = &[
    (
        "fifo_moves.qsl",
        include_str!("../../assets/examples/fifo_moves.qsl"),
    ),
    (
        "fixed_point.qsl",
        include_str!("../../assets/examples/fixed_point.qsl"),
    ),
    (
        "homing.qsl",
        include_str!("../../assets/examples/homing.qsl"),
    ),
    (
        "lifo_undo.qsl",
        include_str!("../../assets/examples/lifo_undo.qsl"),
    ),
    (
        "call_ret.qsl",
        include_str!("../../assets/examples/call_ret.qsl"),
    ),
];

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

/// What a user asked for, from a panel, the menu or a key.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    StepCommand,
    StepTick,
    Run,
    Pause,
    Reset,
    RunToLine(usize),
    ToggleBreakpoint(usize),
    Assemble,
    EditSource(String),
    SetSpeed(Speed),
    SetInput(usize, bool),
    SetRegister(usize, u32),
    ToggleRegisterBit(usize, u8),
    SetStatusBit(&'static str, u8, bool),
    OpenDialog,
    OpenPath(PathBuf),
    ExportDialog,
    ExportCsv(PathBuf),
    LoadExample(usize),
    SetDark(bool),
}

/// Preferences kept between runs by eframe's storage (never the program state).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    pub dark: bool,
    pub recent: Vec<PathBuf>,
    pub speed: Speed,
    pub register_format: Format,
    pub only_used_registers: bool,
}

impl Default for Prefs {
    fn default() -> Self {
        Prefs {
            dark: true,
            recent: Vec::new(),
            speed: Speed::PerSecond(10.0),
            register_format: Format::Signed,
            only_used_registers: true,
        }
    }
}

pub const PREFS_KEY: &str = "servoscope-prefs";
const MAX_RECENT: usize = 10;

/// Frame-time measurement (`servoscope --frame-stats N FILE`): runs the program unlimited and
/// reports the frame interval and the time spent in `ui`, median and worst, over N frames.
pub struct FrameStats {
    frames: usize,
    warmup: usize,
    intervals: Vec<f64>,
    work: Vec<f64>,
    last: Option<Instant>,
}

impl FrameStats {
    pub fn new(frames: usize) -> Self {
        FrameStats {
            frames: frames.max(1),
            warmup: 30,
            intervals: Vec::new(),
            work: Vec::new(),
            last: None,
        }
    }

    fn record(&mut self, started: Instant, finished: Instant) -> Option<String> {
        if let Some(last) = self.last {
            if self.warmup > 0 {
                self.warmup -= 1;
            } else {
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
            format!(
                "{} frames running unlimited: frame interval median {interval_median:.2} ms, worst {interval_worst:.2} ms; time in ui (simulation + layout) median {work_median:.2} ms, worst {work_worst:.2} ms",
                self.frames
            )
        })
    }
}

pub struct ServoscopeApp {
    pub debugger: Debugger,
    pub frame_stats: Option<FrameStats>,
    pub path: Option<PathBuf>,
    pub prefs: Prefs,
    pub code: code::CodeView,
    pub registers: registers::RegisterView,
    pub plot: plot::PlotView,
    pub files: files::Files,
    /// A message for the user that is not a program diagnostic (a file that could not be read).
    pub notice: Option<String>,
    title: String,
    last_frame: Option<Instant>,
    /// Smoothed frame time not spent simulating (drawing, presenting, waiting).
    overhead: Duration,
    last_slice: Duration,
    theme_applied: Option<bool>,
}

impl ServoscopeApp {
    /// The app on the first built-in example.
    pub fn new(prefs: Prefs) -> Self {
        let (name, text) = EXAMPLES[0];
        let mut debugger = Debugger::new(name, text);
        debugger.set_speed(prefs.speed);
        let registers = registers::RegisterView::new(&prefs);
        ServoscopeApp {
            debugger,
            path: None,
            prefs,
            code: code::CodeView::default(),
            registers,
            plot: plot::PlotView::default(),
            files: files::Files::default(),
            notice: None,
            frame_stats: None,
            title: String::new(),
            last_frame: None,
            overhead: Duration::from_millis(8),
            last_slice: Duration::ZERO,
            theme_applied: None,
        }
    }

    /// The app on a file; if it cannot be read, on the built-in example with a notice.
    pub fn with_file(prefs: Prefs, path: PathBuf) -> Self {
        let mut app = ServoscopeApp::new(prefs);
        app.open_path(path);
        app
    }

    pub fn window_title(&self) -> String {
        let edited = if self.debugger.is_edited() {
            " ●"
        } else {
            ""
        };
        format!("servoscope — {}{edited}", self.debugger.name())
    }

    /// Open a program file. On failure the current program stays and the user is told why.
    pub fn open_path(&mut self, path: PathBuf) {
        match std::fs::read_to_string(&path) {
            Ok(text) => {
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                self.debugger.load(name, text);
                self.prefs.recent.retain(|p| p != &path);
                self.prefs.recent.insert(0, path.clone());
                self.prefs.recent.truncate(MAX_RECENT);
                self.path = Some(path);
                self.notice = None;
                self.files.open.close();
                self.code.reset_view();
                self.plot.reset();
            }
            Err(e) => {
                let message = format!("Cannot open {}: {e}", path.display());
                self.files.open.error = Some(message.clone());
                self.notice = Some(message);
            }
        }
    }

    pub fn apply(&mut self, ctx: &egui::Context, command: Command) {
        let d = &mut self.debugger;
        match command {
            Command::StepCommand => d.step_command(),
            Command::StepTick => d.step_tick(),
            Command::Run => d.run(),
            Command::Pause => d.pause(),
            Command::Reset => d.reset(),
            Command::RunToLine(line) => d.run_to_line(line),
            Command::ToggleBreakpoint(line) => {
                d.toggle_breakpoint(line);
            }
            Command::Assemble => {
                d.assemble();
            }
            Command::EditSource(text) => *d.source_mut() = text,
            Command::SetSpeed(speed) => {
                d.set_speed(speed);
                self.prefs.speed = speed;
            }
            Command::SetInput(i, high) => d.set_input(i, high),
            Command::SetRegister(i, v) => d.set_register(i, v),
            Command::ToggleRegisterBit(i, bit) => d.toggle_register_bit(i, bit),
            Command::SetStatusBit(word, bit, on) => {
                d.set_status_bit(word, bit, on);
            }
            Command::OpenDialog => self.files.open.start(ctx),
            Command::OpenPath(path) => self.open_path(path),
            Command::ExportDialog => self.files.export.start(ctx),
            Command::ExportCsv(path) => match self.debugger.export_trace_csv(&path) {
                Ok(rows) => {
                    self.files.export.close();
                    self.notice = Some(format!("Exported {rows} rows to {}", path.display()));
                }
                Err(e) => {
                    let message = format!("Cannot write {}: {e}", path.display());
                    self.files.export.error = Some(message.clone());
                    self.notice = Some(message);
                }
            },
            Command::LoadExample(i) => {
                if let Some(&(name, text)) = EXAMPLES.get(i) {
                    self.debugger.load(name, text);
                    self.path = None;
                    self.code.reset_view();
                    self.plot.reset();
                }
            }
            Command::SetDark(dark) => self.prefs.dark = dark,
        }
    }

    /// One frame: keys, the run slice, then every panel. Usable without eframe (tests).
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        if self.theme_applied != Some(self.prefs.dark) {
            theme::apply(&ctx, self.prefs.dark);
            self.theme_applied = Some(self.prefs.dark);
        }

        let mut commands = Vec::new();
        controls::shortcuts(&ctx, &self.debugger, &self.code, &mut commands);
        files::dropped_files(&ctx, &mut commands);
        self.files.poll(&mut commands);
        for c in commands.drain(..) {
            self.apply(&ctx, c);
        }

        let now = Instant::now();
        let interval = self.last_frame.map(|t| now.duration_since(t));
        self.last_frame = Some(now);
        if let Some(interval) = interval
            && self.debugger.is_running()
        {
            let overhead = interval.saturating_sub(self.last_slice);
            self.overhead = (self.overhead * 7 + overhead) / 8;
        }
        let slice = run_slice(self.overhead);
        let dt = interval.map_or(0.0, |d| d.as_secs_f64());
        let sim_start = Instant::now();
        if self.debugger.advance(dt, slice) {
            ctx.request_repaint();
        }
        self.last_slice = sim_start.elapsed();

        egui::Panel::top("menu").show(ui, |ui| {
            controls::menu_bar(ui, self, &mut commands);
            controls::toolbar(ui, &self.debugger, &mut commands);
        });
        egui::Panel::bottom("status_bar").show(ui, |ui| {
            status::status_bar(ui, &self.debugger);
        });
        // Panel sizes are remembered by egui's own memory, which eframe persists.
        egui::Panel::right("registers")
            .resizable(true)
            .default_size(560.0)
            .min_size(380.0)
            .show(ui, |ui| {
                registers::show(ui, &self.debugger, &mut self.registers, &mut commands);
            });
        egui::CentralPanel::default().show(ui, |ui| {
            if let Some(notice) = self.notice.clone()
                && status::notice_banner(ui, &notice)
            {
                self.notice = None;
            }
            status::fault_banner(ui, &self.debugger);
            egui::Panel::bottom("queues_and_plot")
                .resizable(true)
                .default_size(310.0)
                .min_size(160.0)
                .show(ui, |ui| {
                    // Content sizes itself to the panel, never the reverse.
                    let height = ui.available_height();
                    ui.set_min_height(height);
                    if self.debugger.machine().queues().is_empty() {
                        // No queue to draw: the plot takes the whole width.
                        queues::show(ui, &self.debugger, height);
                        let rest = ui.available_height();
                        plot::show(ui, &self.debugger, &mut self.plot, rest, &mut commands);
                    } else {
                        ui.columns(2, |columns| {
                            queues::show(&mut columns[0], &self.debugger, height);
                            plot::show(
                                &mut columns[1],
                                &self.debugger,
                                &mut self.plot,
                                height,
                                &mut commands,
                            );
                        });
                    }
                });
            code::show(ui, &self.debugger, &mut self.code, &mut commands);
        });
        self.files.windows(&ctx, &self.prefs, &mut commands);

        for c in commands {
            self.apply(&ctx, c);
        }
        self.prefs.register_format = self.registers.format;
        self.prefs.only_used_registers = self.registers.only_used;

        let title = self.window_title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        if self.debugger.is_running() || self.files.is_waiting() {
            ctx.request_repaint();
        }
    }
}

impl eframe::App for ServoscopeApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let started = Instant::now();
        self.show(ui);
        if let Some(stats) = &mut self.frame_stats {
            if let Some(report) = stats.record(started, Instant::now()) {
                eprintln!("{report}");
                ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
                self.frame_stats = None;
            }
            ui.ctx().request_repaint();
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, PREFS_KEY, &self.prefs);
    }
}

/// Start the window. `file`: a program to open instead of the built-in example.
/// `frame_stats`: run it unlimited and report frame times over that many frames, then close.
pub fn run_gui(file: Option<PathBuf>, frame_stats: Option<usize>) -> eframe::Result {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("servoscope")
            .with_inner_size([1280.0, 800.0])
            .with_min_inner_size([800.0, 500.0])
            .with_drag_and_drop(true),
        ..Default::default()
    };
    eframe::run_native(
        "servoscope",
        options,
        Box::new(move |cc| {
            let prefs: Prefs = cc
                .storage
                .and_then(|s| eframe::get_value(s, PREFS_KEY))
                .unwrap_or_default();
            let mut app = match file {
                Some(path) => ServoscopeApp::with_file(prefs, path),
                None => ServoscopeApp::new(prefs),
            };
            if let Some(frames) = frame_stats {
                app.frame_stats = Some(FrameStats::new(frames));
                app.debugger.set_speed(Speed::Unlimited);
                app.debugger.run();
            }
            Ok(Box::new(app))
        }),
    )
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
