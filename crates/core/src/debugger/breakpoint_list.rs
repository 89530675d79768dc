//! The debugger's breakpoints: toggling, adding, changing and removing them, and what the
//! compiled checker knows of each (its error, hit count and the log).

use std::cell::RefCell;
use std::collections::BTreeSet;

use super::breakpoints::Checker;
use super::{BreakError, Breakpoint, Debugger, LogMessage};

impl Debugger {
    // ---- breakpoints -----------------------------------------------------------------------

    /// Toggle a plain breakpoint on a 1-based line: removes every breakpoint of the line when
    /// there is one. Returns whether the line now has one.
    pub fn toggle_breakpoint(&mut self, line: usize) -> bool {
        if line == 0 {
            return false;
        }
        let before = self.breaks.len();
        self.breaks.retain(|b| b.line_number() != Some(line));
        let set = self.breaks.len() == before;
        if set {
            self.breaks.push(Breakpoint::line(line));
        }
        self.rebuild_checker(true);
        set
    }

    /// Plain breakpoints on these lines, replacing every breakpoint.
    pub fn set_breakpoints(&mut self, lines: impl IntoIterator<Item = usize>) {
        let lines: BTreeSet<usize> = lines.into_iter().filter(|&l| l > 0).collect();
        self.set_breakpoint_list(lines.into_iter().map(Breakpoint::line).collect());
    }

    /// Every breakpoint, in the order of the list panel.
    pub fn breakpoint_list(&self) -> &[Breakpoint] {
        &self.breaks
    }

    /// Replace every breakpoint (a session loading); hit counts start at 0.
    pub fn set_breakpoint_list(&mut self, list: Vec<Breakpoint>) {
        self.breaks = list
            .into_iter()
            .filter(|b| b.line_number() != Some(0))
            .collect();
        self.rebuild_checker(false);
    }

    /// Add a breakpoint; returns its index in the list. The problem with its condition,
    /// message or location, if any, is [`Debugger::breakpoint_error`].
    pub fn add_breakpoint(&mut self, b: Breakpoint) -> usize {
        self.breaks.push(b);
        self.rebuild_checker(true);
        self.breaks.len() - 1
    }

    /// Change a breakpoint (its hit count so far stays).
    pub fn update_breakpoint(&mut self, index: usize, b: Breakpoint) {
        if let Some(slot) = self.breaks.get_mut(index) {
            *slot = b;
            self.rebuild_checker(true);
        }
    }

    pub fn remove_breakpoint(&mut self, index: usize) {
        if index < self.breaks.len() {
            self.breaks.remove(index);
            let old =
                self.checker
                    .replace(Checker::new(&self.breaks, self.machine(), &self.lines()));
            let mut hits: Vec<u64> = (0..=self.breaks.len()).map(|i| old.hits(i)).collect();
            hits.remove(index);
            let new = self.checker.get_mut();
            new.set_hits(&hits);
            new.log = old.log;
            new.rebuild_logged();
        }
    }

    /// Source lines of each file of the program that runs (breakpoints past them can never
    /// stop).
    pub(super) fn lines(&self) -> Vec<usize> {
        self.assembled
            .files
            .iter()
            .map(|f| f.text.lines().count())
            .collect()
    }

    /// Why a breakpoint cannot work in the current program (a condition that does not parse,
    /// a location that does not exist); it is inactive until fixed.
    pub fn breakpoint_error(&self, index: usize) -> Option<BreakError> {
        self.checker.borrow().errors.get(index).cloned().flatten()
    }

    /// How many times a forward run passed the breakpoint with its condition holding.
    /// Put back the hits of a saved session, in the list's order (missing ones stay 0).
    pub fn set_breakpoint_hits(&mut self, hits: &[u64]) {
        self.checker.borrow_mut().set_hits(hits);
    }

    pub fn breakpoint_hits(&self, index: usize) -> u64 {
        self.checker.borrow().hits(index)
    }

    /// The messages log points wrote, oldest first.
    pub fn log_messages(&self) -> std::cell::Ref<'_, [LogMessage]> {
        std::cell::Ref::map(self.checker.borrow(), |c| c.log.as_slice())
    }

    /// Compile the breakpoints against the current program, keeping the hit counts and log
    /// (`keep`) or starting both afresh.
    pub(super) fn rebuild_checker(&mut self, keep: bool) {
        let mut new = Checker::new(&self.breaks, self.engine.machine(), &self.lines());
        if keep {
            let old = self.checker.borrow();
            new.keep_hits(&old);
            new.log = old.log.clone();
        }
        new.rebuild_logged();
        self.checker = RefCell::new(new);
    }
}
