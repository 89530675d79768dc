//! The debugger: breakpoints, stepping, time travel, traces and the worker thread, over every dialect.

#[path = "../common/mod.rs"]
mod common;

mod breakpoints;
mod faults_and_flow;
mod long_runs;
mod messages;
mod opennet_debugger;
mod readings;
mod threaded;
mod time_travel;
mod trace;
