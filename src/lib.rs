//! servoscope: a debugger and simulator for the programs that run inside servo motors and PLCs.
//!
//! Layers, each usable without the ones above it:
//! - [`machine`]: the interpreter core, one module per dialect, no I/O.
//! - [`runner`]: the headless runner of spec §8 (`servoscope run`).

pub mod atomic;
pub mod debugger;
pub mod machine;
pub mod runner;
pub mod session;
pub mod ui;
