//! The window, driven without a display by egui_kittest: every panel, the editor, the layout at
//! each size, lessons, and every dialect through the app.

#[path = "../../crates/core/tests/common/mod.rs"]
mod common;

mod debugger_panels;
mod dialects;
mod drawing;
mod editor;
mod formats;
mod gui;
mod gui_project;
mod gui_teaching;
mod layout;
