//! The debugger window. Each panel draws from the [`Debugger`] and its own view settings and
//! returns what the user asked for as [`Command`]s; [`ServoscopeApp::apply`] carries them out.
//! No run logic lives here: it is all in `debugger` and `machine`.

pub mod code;
pub mod controls;
pub mod files;
pub mod registers;
pub mod status;
pub mod theme;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::debugger::format::Format;
use crate::debugger::{Debugger, Speed};

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

/// Simulation time allowed per frame while running unlimited: the rest of a 16 ms frame is
/// left for drawing.
pub const RUN_BUDGET: Duration = Duration::from_millis(8);

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
    pub registers_width: f32,
}

impl Default for Prefs {
    fn default() -> Self {
        Prefs {
            dark: true,
            recent: Vec::new(),
            speed: Speed::PerSecond(10.0),
            register_format: Format::Signed,
            only_used_registers: true,
            registers_width: 570.0,
        }
    }
}

pub const PREFS_KEY: &str = "servoscope-prefs";
const MAX_RECENT: usize = 10;

pub struct ServoscopeApp {
    pub debugger: Debugger,
    pub path: Option<PathBuf>,
    pub prefs: Prefs,
    pub code: code::CodeView,
    pub registers: registers::RegisterView,
    pub files: files::Files,
    /// A message for the user that is not a program diagnostic (a file that could not be read).
    pub notice: Option<String>,
    title: String,
    last_frame: Option<Instant>,
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
            files: files::Files::default(),
            notice: None,
            title: String::new(),
            last_frame: None,
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
                self.files.close();
                self.code.reset_view();
            }
            Err(e) => {
                let message = format!("Cannot open {}: {e}", path.display());
                self.files.error = Some(message.clone());
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
            Command::OpenDialog => self.files.open_dialog(ctx),
            Command::OpenPath(path) => self.open_path(path),
            Command::LoadExample(i) => {
                if let Some(&(name, text)) = EXAMPLES.get(i) {
                    self.debugger.load(name, text);
                    self.path = None;
                    self.code.reset_view();
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
        if let Some(path) = self.files.poll() {
            commands.push(Command::OpenPath(path));
        }
        for c in commands.drain(..) {
            self.apply(&ctx, c);
        }

        let now = Instant::now();
        let dt = self
            .last_frame
            .map_or(0.0, |t| now.duration_since(t).as_secs_f64());
        self.last_frame = Some(now);
        if self.debugger.advance(dt, RUN_BUDGET) {
            ctx.request_repaint();
        }

        egui::Panel::top("menu").show(ui, |ui| {
            controls::menu_bar(ui, self, &mut commands);
            controls::toolbar(ui, &self.debugger, &mut commands);
        });
        egui::Panel::bottom("status_bar").show(ui, |ui| {
            status::status_bar(ui, &self.debugger);
        });
        let width = self.prefs.registers_width;
        let panel = egui::Panel::right("registers")
            .resizable(true)
            .default_size(width)
            .min_size(380.0)
            .show(ui, |ui| {
                registers::show(ui, &self.debugger, &mut self.registers, &mut commands);
            });
        self.prefs.registers_width = panel.response.rect.width();
        egui::CentralPanel::default().show(ui, |ui| {
            if let Some(notice) = self.notice.clone()
                && status::notice_banner(ui, &notice)
            {
                self.notice = None;
            }
            status::fault_banner(ui, &self.debugger);
            code::show(ui, &self.debugger, &mut self.code, &mut commands);
        });
        files::open_window(&ctx, &mut self.files, &self.prefs, &mut commands);

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
        self.show(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, PREFS_KEY, &self.prefs);
    }
}

/// Start the window. `file`: a program to open instead of the built-in example.
pub fn run_gui(file: Option<PathBuf>) -> eframe::Result {
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
            Ok(Box::new(match file {
                Some(path) => ServoscopeApp::with_file(prefs, path),
                None => ServoscopeApp::new(prefs),
            }))
        }),
    )
}
