//! OpenNet's entry in the dialect registry.

use std::sync::Arc;

use super::{OpenNet, assemble};
use crate::machine::Diagnostic;
use crate::machine::dialect::{AtLimit, ChannelSpec, DialectInfo, Settings, Vocabulary};
use crate::machine::project::Project;

pub static DIALECT: DialectInfo = DialectInfo {
    name: "opennet",
    display_name: "IDEC OpenNet",
    extensions: &["opennet"],
    vocabulary: Vocabulary {
        tick: "scan",
        ticks: "scans",
        step: "instruction",
        steps: "instructions",
        location_hint: "D0",
        watch_hint: "D0 + D1, T0.current",
        condition_hint: "D0 > 100 && I0",
    },
    examples: &[
        (
            "totaliser.opennet",
            include_str!("../../../../../assets/examples/totaliser.opennet"),
        ),
        (
            "signed_overflow.opennet",
            include_str!("../../../../../assets/examples/signed_overflow.opennet"),
        ),
        (
            "mul_div.opennet",
            include_str!("../../../../../assets/examples/mul_div.opennet"),
        ),
        (
            "batch_sotu.opennet",
            include_str!("../../../../../assets/examples/batch_sotu.opennet"),
        ),
        (
            "exec_error.opennet",
            include_str!("../../../../../assets/examples/exec_error.opennet"),
        ),
        (
            "traffic_light.opennet",
            include_str!("../../../../../assets/examples/traffic_light.opennet"),
        ),
        (
            "parts_counter.opennet",
            include_str!("../../../../../assets/examples/parts_counter.opennet"),
        ),
        (
            "conveyor.opennet",
            include_str!("../../../../../assets/examples/conveyor.opennet"),
        ),
        (
            "alarm.opennet",
            include_str!("../../../../../assets/examples/alarm.opennet"),
        ),
    ],
    projects: &[],
    lessons: &[
        (
            "opennet_overflow_walkthrough.ron",
            include_str!("../../../../../sessions/opennet_overflow_walkthrough.ron"),
        ),
        (
            "opennet_overflow_task.ron",
            include_str!("../../../../../sessions/opennet_overflow_task.ron"),
        ),
        (
            "opennet_timer_counter_task.ron",
            include_str!("../../../../../sessions/opennet_timer_counter_task.ron"),
        ),
    ],
    reference: include_str!("../../../../../docs/opennet.md"),
    mnemonics: &[super::assembler::BASIC, super::assembler::ADVANCED],
    settings: &[crate::machine::plc::SCAN_MS],
    default_channels: &[ChannelSpec {
        location: "D0",
        label: "D0",
        group: 0,
    }],
    default_max_ticks: 1,
    at_limit: AtLimit::Ended,
    new_program: "; A new OpenNet program\nLOD I0\nOUT Q0\nEND\n",
    empty_program: "",
    error_flags: "M8004, execution error",
    decimal_literals_are_fixed: false,
    includes: None,
    classify: super::syntax::classify,
};

pub fn machine(source: &str) -> Result<OpenNet, Vec<Diagnostic>> {
    Ok(OpenNet::new(Arc::new(assemble(source)?)))
}

/// The program's machine with the scan time of `settings`, or every diagnostic.
pub fn open(project: &Project, settings: &Settings) -> Result<OpenNet, Vec<Diagnostic>> {
    crate::machine::plc::open(project, settings)
}
