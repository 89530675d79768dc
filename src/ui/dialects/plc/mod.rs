//! The panels every scanned PLC shares: the ladder with live power flow, the I/O board, and the
//! table of timers and counters.

pub mod boxes;
pub mod io_board;
pub mod ladder;

use crate::ui::panels::DialectPanel;

/// A scanned PLC's panels: the ladder and the Timers & counters table first (they are what a
/// PLC program is about), the dialect's own `between`, the I/O board last.
pub fn panels(between: Vec<Box<dyn DialectPanel>>) -> Vec<Box<dyn DialectPanel>> {
    let mut all: Vec<Box<dyn DialectPanel>> = vec![
        Box::new(ladder::LadderPanel::default()),
        Box::new(boxes::BoxesPanel),
    ];
    all.extend(between);
    all.push(Box::new(io_board::IoBoard::default()));
    all
}
