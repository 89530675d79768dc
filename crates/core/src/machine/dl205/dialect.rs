//! DL205's entry in the dialect registry.

use std::sync::Arc;

use super::{Dl205, assemble};
use crate::machine::Diagnostic;
use crate::machine::dialect::{AtLimit, ChannelSpec, DialectInfo, Settings, Vocabulary};
use crate::machine::project::Project;

pub static DIALECT: DialectInfo = DialectInfo {
    name: "dl205",
    display_name: "AutomationDirect DL205",
    extensions: &["dl205"],
    vocabulary: Vocabulary {
        tick: "scan",
        ticks: "scans",
        step: "instruction",
        steps: "instructions",
        location_hint: "V2000",
        watch_hint: "V2000 & 0xFF, ACC",
        condition_hint: "V2000 == 0x25 && X0",
    },
    examples: &[
        (
            "subs.dl205",
            include_str!("../../../../../assets/examples/subs.dl205"),
        ),
        (
            "totaliser.dl205",
            include_str!("../../../../../assets/examples/totaliser.dl205"),
        ),
        (
            "scaling.dl205",
            include_str!("../../../../../assets/examples/scaling.dl205"),
        ),
        (
            "latch.dl205",
            include_str!("../../../../../assets/examples/latch.dl205"),
        ),
        (
            "nonbcd.dl205",
            include_str!("../../../../../assets/examples/nonbcd.dl205"),
        ),
        (
            "traffic_light.dl205",
            include_str!("../../../../../assets/examples/traffic_light.dl205"),
        ),
        (
            "parts_counter.dl205",
            include_str!("../../../../../assets/examples/parts_counter.dl205"),
        ),
        (
            "push_on_off.dl205",
            include_str!("../../../../../assets/examples/push_on_off.dl205"),
        ),
        (
            "batch_mixer.dl205",
            include_str!("../../../../../assets/examples/batch_mixer.dl205"),
        ),
    ],
    projects: &[],
    lessons: &[
        (
            "dl205_bcd_stack_task.ron",
            include_str!("../../../../../sessions/dl205_bcd_stack_task.ron"),
        ),
        (
            "dl205_subs_walkthrough.ron",
            include_str!("../../../../../sessions/dl205_subs_walkthrough.ron"),
        ),
        (
            "dl205_timer_counter_task.ron",
            include_str!("../../../../../sessions/dl205_timer_counter_task.ron"),
        ),
    ],
    reference: include_str!("../../../../../docs/dl205.md"),
    mnemonics: &[super::assembler::MNEMONICS],
    settings: &[crate::machine::plc::SCAN_MS],
    default_channels: &[ChannelSpec {
        location: "ACC",
        label: "ACC",
        group: 0,
    }],
    default_max_ticks: 1,
    at_limit: AtLimit::Ended,
    new_program: "// A new DL205 program\nSTR X0\nOUT Y0\nEND\n",
    empty_program: "END\n",
    error_flags: "SP53 divide by zero, SP75 non-BCD data",
    decimal_literals_are_fixed: false,
    includes: None,
    classify: super::syntax::classify,
};

pub fn machine(source: &str) -> Result<Dl205, Vec<Diagnostic>> {
    Ok(Dl205::new(Arc::new(assemble(source)?)))
}

/// The program's machine with the scan time of `settings`, or every diagnostic.
pub fn open(project: &Project, settings: &Settings) -> Result<Dl205, Vec<Diagnostic>> {
    crate::machine::plc::open(project, settings)
}
