//! TML's entry in the dialect registry.

use std::sync::Arc;

use super::{Tml, assemble};
use crate::machine::Diagnostic;
use crate::machine::dialect::{AtLimit, ChannelSpec, DialectInfo, Settings, Vocabulary};
use crate::machine::project::Project;

pub static DIALECT: DialectInfo = DialectInfo {
    name: "tml",
    display_name: "Technosoft TML",
    extensions: &["tml"],
    vocabulary: Vocabulary {
        tick: "tick",
        ticks: "ticks",
        step: "statement",
        steps: "statements",
        location_hint: "APOS",
        watch_hint: "TPOS - APOS, APOS",
        condition_hint: "APOS > 1000",
    },
    examples: &[
        (
            "fixed_speed.tml",
            include_str!("../../../../../assets/examples/fixed_speed.tml"),
        ),
        (
            "shifts.tml",
            include_str!("../../../../../assets/examples/shifts.tml"),
        ),
        (
            "moves.tml",
            include_str!("../../../../../assets/examples/moves.tml"),
        ),
        (
            "wait_input.tml",
            include_str!("../../../../../assets/examples/wait_input.tml"),
        ),
    ],
    projects: &[(
        "easymotion_axis",
        &[
            (
                "motion.tml",
                include_str!("../../../../../assets/examples/easymotion_axis/motion.tml"),
            ),
            (
                "setup_interrupts.tml",
                include_str!("../../../../../assets/examples/easymotion_axis/setup_interrupts.tml"),
            ),
            (
                "setup_settings.tml",
                include_str!("../../../../../assets/examples/easymotion_axis/setup_settings.tml"),
            ),
            (
                "main.tml",
                include_str!("../../../../../assets/examples/easymotion_axis/main.tml"),
            ),
            (
                "homingmodes.tml",
                include_str!("../../../../../assets/examples/easymotion_axis/homingmodes.tml"),
            ),
            (
                "functions.tml",
                include_str!("../../../../../assets/examples/easymotion_axis/functions.tml"),
            ),
        ],
    )],
    lessons: &[
        (
            "tml_fixed_point_walkthrough.ron",
            include_str!("../../../../../sessions/tml_fixed_point_walkthrough.ron"),
        ),
        (
            "tml_product_task.ron",
            include_str!("../../../../../sessions/tml_product_task.ron"),
        ),
    ],
    reference: include_str!("../../../../../docs/tml.md"),
    mnemonics: &[super::assembler::MNEMONICS],
    settings: &[],
    default_channels: &[
        ChannelSpec {
            location: "TPOS",
            label: "target (TPOS)",
            group: 0,
        },
        ChannelSpec {
            location: "APOS",
            label: "actual (APOS)",
            group: 0,
        },
    ],
    default_max_ticks: 10_000_000,
    at_limit: AtLimit::Limit,
    new_program: "// A new TML program\nint i;\n\n        i = 1;\n        END;\n",
    empty_program: "",
    error_flags: "MER, motion error register",
    decimal_literals_are_fixed: true,
    includes: Some(super::assembler::includes),
    classify: super::syntax::classify,
};

/// A machine for `source`, or every diagnostic.
pub fn machine(source: &str) -> Result<Tml, Vec<Diagnostic>> {
    Ok(Tml::new(Arc::new(assemble(source)?)))
}

/// The project's machine (every file, `#include`s resolved), or every diagnostic.
pub fn open(project: &Project, _settings: &Settings) -> Result<Tml, Vec<Diagnostic>> {
    let program = super::assembler::assemble_project(project)?;
    Ok(Tml::new(Arc::new(program)))
}
