//! servoscope: a debugger and simulator for the programs that run inside servo motors and PLCs.
//!
//! Layers, each usable without the ones above it:
//! - [`machine`]: the interpreter core, one module per dialect, no I/O.
//! - [`debugger`]: run control, time travel and traces over any machine.
//! - [`session`]: saved debug sessions.
//! - [`runner`]: the headless runner (`servoscope run`).
//! - `ui` (feature `gui`, on by default): the egui window.

pub mod atomic;
pub mod debugger;
pub mod lesson;
pub mod machine;
pub mod runner;
pub mod session;
pub mod text;
#[cfg(feature = "gui")]
pub mod ui;
