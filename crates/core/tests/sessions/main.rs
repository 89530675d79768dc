//! Sessions, lessons and the runner's inputs: saving, reopening and grading, and hostile files.

#[path = "../common/mod.rs"]
mod common;

mod hostile;
mod lessons;
mod sessions;
