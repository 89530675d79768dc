//! A dialect as the debugger uses it: the machine layer's description, and how to open a
//! program of it as an [`Engine`]. The list of dialects is the composition root's
//! (`crate::registry`): the debugger is handed a dialect, it never picks one.

use std::ops::Deref;

use super::Engine;
use crate::machine::Diagnostic;
use crate::machine::dialect::{DialectInfo, Settings};
use crate::machine::project::Project;

/// A program assembled into a debuggable machine, or every diagnostic.
pub type OpenResult = Result<Box<dyn Engine>, Vec<Diagnostic>>;

pub struct Dialect {
    pub info: &'static DialectInfo,
    /// Assemble a program of one or more files (the top file first) with these settings.
    pub open: fn(project: &Project, settings: &Settings) -> OpenResult,
}

impl Dialect {
    /// Assemble a program of one or more files.
    pub fn open_program(&self, project: &Project, settings: &Settings) -> OpenResult {
        (self.open)(project, settings)
    }

    /// Assemble one file's text.
    pub fn open_text(&self, source: &str, settings: &Settings) -> OpenResult {
        let name = format!("program.{}", self.extensions[0]);
        (self.open)(&Project::single(name, source.to_string()), settings)
    }
}

impl Deref for Dialect {
    type Target = DialectInfo;
    fn deref(&self) -> &DialectInfo {
        self.info
    }
}

impl std::fmt::Debug for Dialect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.info.fmt(f)
    }
}

impl PartialEq for Dialect {
    fn eq(&self, other: &Self) -> bool {
        self.info == other.info
    }
}
