//! The command line as users and scripts run it: `run`, `check`, `ladder` and sessions through
//! the built binary, exit codes and JSON, for every dialect.

#[path = "../../crates/core/tests/common/mod.rs"]
mod core_common;

/// The core's test helpers and the binary.
mod common {
    pub use super::core_common::*;

    /// The built binary, run with `args`.
    pub fn servoscope(args: &[&str]) -> std::process::Output {
        command().args(args).output().expect("run servoscope")
    }

    /// The built binary, with a home of its own.
    pub fn command() -> std::process::Command {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_servoscope"));
        with_scratch_home(&mut command);
        command
    }
}

mod breakpoints;
mod cli;
mod dl205;
mod dl205_boxes;
mod forcing;
mod hostile;
mod ladder_svg;
mod lessons;
mod opennet;
mod opennet_examples;
mod opennet_plc;
mod overflow_words;
mod sessions;
mod tml;
mod tml_projects;
