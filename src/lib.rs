//! servoscope's window: the egui app over the core crate (`servoscope_core`), which holds the
//! machines, the debugger, sessions, the runner and lessons. `main.rs` is the command line.

pub mod ui;
