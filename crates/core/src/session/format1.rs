//! Format 1, SilverLode's sessions from before dialects: the old file's shape, and its
//! conversion to the current format.

use super::{FORMAT_1_DIALECT, FORMAT_VERSION, Session, SessionEvent, SessionMark, ViewSettings};
use crate::debugger::history::Change;
use crate::machine::Pos;
use crate::registry;

/// Format 1, as written by servoscope before dialects: SilverLode only.
pub(super) mod v1 {
    use serde::Deserialize;

    #[derive(Deserialize, Default)]
    #[serde(default)]
    pub struct Session {
        pub program_name: String,
        pub program_path: Option<std::path::PathBuf>,
        pub program: String,
        pub breakpoints: Vec<usize>,
        pub servo: Servo,
        pub events: Vec<Event>,
        pub tick: u64,
        pub furthest: u64,
        pub marks: Vec<Mark>,
        pub view: View,
    }

    /// SilverLode's servo model as format 1 stored it; each field is the setting of that key.
    #[derive(Deserialize, Default)]
    #[serde(default)]
    pub struct Servo {
        pub natural_frequency_hz: Option<f64>,
        pub damping: Option<f64>,
        pub moving_error_limit: Option<u32>,
        pub holding_error_limit: Option<u32>,
    }

    impl Servo {
        pub fn settings(&self) -> crate::registry::Settings {
            [
                ("natural_frequency_hz", self.natural_frequency_hz),
                ("damping", self.damping),
                ("moving_error_limit", self.moving_error_limit.map(f64::from)),
                (
                    "holding_error_limit",
                    self.holding_error_limit.map(f64::from),
                ),
            ]
            .into_iter()
            .filter_map(|(key, value)| Some((key.to_string(), value?)))
            .collect()
        }
    }

    #[derive(Deserialize)]
    pub struct Event {
        pub tick: u64,
        pub edit: Edit,
    }

    #[derive(Deserialize)]
    pub enum Edit {
        Input { input: usize, high: bool },
        Register { register: usize, value: u32 },
        StatusBit { word: String, bit: u8, on: bool },
    }

    #[derive(Deserialize)]
    pub struct Mark {
        pub tick: u64,
        pub fault: bool,
        pub line: usize,
    }

    #[derive(Deserialize)]
    #[serde(default)]
    pub struct View {
        pub register_format: crate::machine::Format,
        pub register_formats: Vec<(usize, crate::machine::Format)>,
        pub only_used_registers: bool,
        pub selected_register: Option<usize>,
        #[allow(dead_code)]
        pub plot_velocity: bool,
        pub speed: crate::debugger::Speed,
    }

    impl Default for View {
        fn default() -> Self {
            View {
                register_format: crate::machine::Format::Signed,
                register_formats: Vec::new(),
                only_used_registers: true,
                selected_register: None,
                plot_velocity: false,
                speed: crate::debugger::Speed::PerSecond(10.0),
            }
        }
    }
}

impl From<v1::Session> for Session {
    fn from(old: v1::Session) -> Session {
        let event = |e: v1::Event| {
            let (location, change) = match e.edit {
                v1::Edit::Input { input, high } => {
                    // Wide enough for any number a file gives: IO18446744073709551616 is then
                    // refused by name, as an input the program does not have.
                    let number = input as u128 + 1;
                    (format!("IO{number}"), Change::Set(u64::from(high)))
                }
                v1::Edit::Register { register, value } => {
                    (format!("R{register}"), Change::Set(u64::from(value)))
                }
                v1::Edit::StatusBit { word, bit, on } => (word, Change::Bit { bit, on }),
            };
            SessionEvent {
                at: Pos::at_tick(e.tick),
                location,
                change,
            }
        };
        Session {
            format: FORMAT_VERSION,
            dialect: FORMAT_1_DIALECT.to_string(),
            program_name: old.program_name,
            program_path: old.program_path,
            program: old.program,
            breakpoints: old.breakpoints,
            // Clamped and completed as the dialect's settings are when the session restores.
            settings: registry::by_name(FORMAT_1_DIALECT).map_or_else(
                || old.servo.settings(),
                |d| d.settings_from(&old.servo.settings()),
            ),
            channels: None,
            events: old.events.into_iter().map(event).collect(),
            at: Pos::at_tick(old.tick),
            furthest: Pos::at_tick(old.furthest),
            marks: old
                .marks
                .into_iter()
                .map(|m| SessionMark {
                    at: Pos::at_tick(m.tick),
                    fault: m.fault,
                    line: m.line,
                })
                .collect(),
            view: ViewSettings {
                register_format: old.view.register_format,
                formats: old
                    .view
                    .register_formats
                    .into_iter()
                    .map(|(r, f)| (format!("R{r}"), f))
                    .collect(),
                only_used_registers: old.view.only_used_registers,
                selected: old.view.selected_register.map(|r| format!("R{r}")),
                speed: old.view.speed,
                every_location_as: None,
            },
            ..Session::default()
        }
    }
}
