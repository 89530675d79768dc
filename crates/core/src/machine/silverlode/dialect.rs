//! SilverLode's entry in the dialect registry.

use std::sync::Arc;

use super::motion::ServoSettings;
use super::{SilverLode, assemble};
use crate::machine::Diagnostic;
use crate::machine::dialect::{
    AtLimit, ChannelSpec, DialectInfo, SettingInfo, Settings, Vocabulary,
};
use crate::machine::project::Project;

pub static DIALECT: DialectInfo = DialectInfo {
    name: "silverlode",
    display_name: "QuickSilver SilverLode",
    extensions: &["qsl"],
    vocabulary: Vocabulary {
        tick: "tick",
        ticks: "ticks",
        step: "command",
        steps: "commands",
        location_hint: "R4",
        watch_hint: "R4 + R5, PSW.12, R0 - R1",
        condition_hint: "R4 > 1000 && IO3",
    },
    examples: &[
        (
            "fifo_moves.qsl",
            include_str!("../../../../../assets/examples/fifo_moves.qsl"),
        ),
        (
            "fixed_point.qsl",
            include_str!("../../../../../assets/examples/fixed_point.qsl"),
        ),
        (
            "homing.qsl",
            include_str!("../../../../../assets/examples/homing.qsl"),
        ),
        (
            "lifo_undo.qsl",
            include_str!("../../../../../assets/examples/lifo_undo.qsl"),
        ),
        (
            "call_ret.qsl",
            include_str!("../../../../../assets/examples/call_ret.qsl"),
        ),
    ],
    projects: &[],
    lessons: &[
        (
            "fifo_lifo_task.ron",
            include_str!("../../../../../sessions/fifo_lifo_task.ron"),
        ),
        (
            "fifo_queue_walkthrough.ron",
            include_str!("../../../../../sessions/fifo_queue_walkthrough.ron"),
        ),
        (
            "fixed_point_walkthrough.ron",
            include_str!("../../../../../sessions/fixed_point_walkthrough.ron"),
        ),
        (
            "homing_on_input.ron",
            include_str!("../../../../../sessions/homing_on_input.ron"),
        ),
        (
            "q16_scaling_task.ron",
            include_str!("../../../../../sessions/q16_scaling_task.ron"),
        ),
    ],
    reference: include_str!("../../../../../docs/silverlode.md"),
    mnemonics: &[super::assembler::MNEMONICS],
    settings: &[
        SettingInfo {
            key: "natural_frequency_hz",
            label: "Natural frequency (Hz)",
            help: "How stiff the position loop is: higher follows the target more closely.",
            min: 0.5,
            max: 200.0,
            default: 25.0,
            integer: false,
        },
        SettingInfo {
            key: "damping",
            label: "Damping ratio",
            help: "Below 1 the actual position overshoots; 1 is critically damped.",
            min: 0.05,
            max: 2.0,
            default: 0.7,
            integer: false,
        },
        SettingInfo {
            key: "moving_error_limit",
            label: "Moving error limit (counts)",
            help: "ISW bit 8 is set while |R6| exceeds this during a move.",
            min: 0.0,
            max: 2_147_483_647.0,
            default: 2000.0,
            integer: true,
        },
        SettingInfo {
            key: "holding_error_limit",
            label: "Holding error limit (counts)",
            help: "ISW bit 9 is set while |R6| exceeds this with no move running.",
            min: 0.0,
            max: 2_147_483_647.0,
            default: 2000.0,
            integer: true,
        },
    ],
    default_channels: &[
        ChannelSpec {
            location: "R0",
            label: "target (R0)",
            group: 0,
        },
        ChannelSpec {
            location: "R1",
            label: "actual (R1)",
            group: 0,
        },
        ChannelSpec {
            location: "R6",
            label: "error (R6)",
            group: 1,
        },
    ],
    default_max_ticks: 10_000_000,
    at_limit: AtLimit::Limit,
    new_program: "; A new SilverLode program\nWRP 11, 1\nEND\n",
    empty_program: "",
    error_flags: "PSW bit 12, command error",
    decimal_literals_are_fixed: false,
    includes: None,
    classify: super::syntax::classify,
};

/// The servo model from the dialect's settings (missing keys take their defaults).
pub fn servo_settings(settings: &Settings) -> ServoSettings {
    let s = DIALECT.settings_from(settings);
    let d = ServoSettings::default();
    ServoSettings {
        natural_frequency_hz: s
            .get("natural_frequency_hz")
            .copied()
            .unwrap_or(d.natural_frequency_hz),
        damping: s.get("damping").copied().unwrap_or(d.damping),
        moving_error_limit: s
            .get("moving_error_limit")
            .map_or(d.moving_error_limit, |&v| v as u32),
        holding_error_limit: s
            .get("holding_error_limit")
            .map_or(d.holding_error_limit, |&v| v as u32),
    }
    .clamped()
}

/// The dialect's settings from a servo model (sessions of format 1 store it this way).
pub fn settings_of(servo: ServoSettings) -> Settings {
    let servo = servo.clamped();
    DIALECT.settings_from(&Settings::from([
        (
            "natural_frequency_hz".to_string(),
            servo.natural_frequency_hz,
        ),
        ("damping".to_string(), servo.damping),
        (
            "moving_error_limit".to_string(),
            f64::from(servo.moving_error_limit),
        ),
        (
            "holding_error_limit".to_string(),
            f64::from(servo.holding_error_limit),
        ),
    ]))
}

/// A machine for `source`, or every diagnostic.
pub fn machine(source: &str, settings: &Settings) -> Result<SilverLode, Vec<Diagnostic>> {
    let program = assemble(source)?;
    Ok(SilverLode::with_settings(
        Arc::new(program),
        servo_settings(settings),
    ))
}

/// The program's machine, or every diagnostic.
pub fn open(project: &Project, settings: &Settings) -> Result<SilverLode, Vec<Diagnostic>> {
    machine(project.top_text(), settings)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn servo_settings_round_trip_through_the_registry_form() {
        let servo = ServoSettings {
            natural_frequency_hz: 40.0,
            damping: 1.0,
            moving_error_limit: 123,
            holding_error_limit: 45,
        };
        assert_eq!(servo_settings(&settings_of(servo)), servo);
        assert_eq!(
            servo_settings(&Settings::new()),
            ServoSettings::default(),
            "missing keys are the defaults of spec §6"
        );
    }
}
