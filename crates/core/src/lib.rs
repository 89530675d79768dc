//! servoscope's core: the machines, the debugger, sessions, the headless runner and lessons,
//! without the window (the app crate, at the workspace's root, draws them).
//!
//! Layers import downward only (`tests/layers.rs` checks it):
//! - [`machine`]: the interpreters, one folder per dialect, no I/O.
//! - [`debugger`]: run control, time travel and traces over any machine.
//! - [`registry`]: the composition root: the list of dialects, each opened as a debugger engine.
//!   Below it no file names a dialect outside the dialect's own folder.
//! - [`session`], [`runner`], [`lesson`], [`output`]: saved sessions, the headless runner,
//!   lessons, and what a command may write over.

pub mod atomic;
pub mod debugger;
pub mod lesson;
pub mod machine;
pub mod output;
pub mod registry;
pub mod runner;
pub mod session;
pub mod text;
