//! The composition root: the list of dialects servoscope knows, and the glue that turns a
//! dialect's assembled machine into a debugger engine. It stands above the machines and the
//! debugger (machine ← debugger ← registry ← session, runner, lesson), so neither names a
//! dialect; sessions, the runner and everything above the core (the window, `main`) find the
//! dialects here.
//!
//! Adding a dialect: its folder under `machine/` (with `dialect::DIALECT` and `dialect::open`),
//! `pub mod` in `machine/mod.rs`, and one word in [`dialects!`] below.

use std::path::Path;

pub use crate::debugger::dialect::{Dialect, OpenResult};
use crate::debugger::{Debugger, engine};
pub use crate::machine::dialect::*;
use crate::machine::project::Project;

/// Lists each dialect's description with the function that opens its programs as an engine.
macro_rules! dialects {
    ($($name:ident),+ $(,)?) => {
        /// Every registered dialect. The first one is the default (the built-in example at
        /// start-up).
        pub static DIALECTS: &[&Dialect] = &[$(&Dialect {
            info: &crate::machine::$name::dialect::DIALECT,
            open: |project, settings| {
                crate::machine::$name::dialect::open(project, settings).map(engine)
            },
        }),+];
    };
}

dialects!(silverlode, tml, opennet, dl205);

impl Debugger {
    /// A debugger on `source` in the default dialect (SilverLode).
    pub fn new(name: impl Into<String>, source: impl Into<String>) -> Self {
        Debugger::with_dialect(default_dialect(), name, source)
    }
}

/// The default dialect.
pub fn default_dialect() -> &'static Dialect {
    DIALECTS[0]
}

/// A dialect by its name (case-insensitive).
pub fn by_name(name: &str) -> Option<&'static Dialect> {
    DIALECTS
        .iter()
        .copied()
        .find(|d| d.name.eq_ignore_ascii_case(name.trim()))
}

/// The dialect whose extension `path` has.
pub fn by_path(path: &Path) -> Option<&'static Dialect> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    DIALECTS
        .iter()
        .copied()
        .find(|d| d.extensions.contains(&ext.as_str()))
}

/// `silverlode (.qsl), ...`: for messages that list the choices.
pub fn list() -> String {
    DIALECTS
        .iter()
        .map(|d| format!("{} (.{})", d.name, d.extensions.join(", .")))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Why no dialect could be chosen for a file.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ChooseError {
    #[error("unknown dialect '{0}'; servoscope knows {list}", list = list())]
    UnknownName(String),
    #[error(
        "{0}: no dialect uses this file's extension; pass --dialect NAME (servoscope knows {list})",
        list = list()
    )]
    UnknownExtension(String),
}

/// The dialect for a program file: `--dialect NAME` if given, else the file's extension.
pub fn choose(path: &Path, name: Option<&str>) -> Result<&'static Dialect, ChooseError> {
    match name {
        Some(n) => by_name(n).ok_or_else(|| ChooseError::UnknownName(n.to_string())),
        None => {
            by_path(path).ok_or_else(|| ChooseError::UnknownExtension(path.display().to_string()))
        }
    }
}

/// Every lesson session of every dialect, with its dialect.
pub fn lessons() -> impl Iterator<Item = (&'static Dialect, &'static str, &'static str)> {
    DIALECTS
        .iter()
        .flat_map(|d| d.lessons.iter().map(move |&(n, t)| (*d, n, t)))
}

/// Every built-in example of several files: its dialect, title and files.
pub fn example_projects() -> impl Iterator<Item = (&'static Dialect, &'static str, Project)> {
    DIALECTS.iter().flat_map(|d| {
        d.projects.iter().map(move |(title, files)| {
            let files = files
                .iter()
                .map(|&(name, text)| crate::machine::project::SourceFile {
                    name: name.to_string(),
                    text: text.to_string(),
                })
                .collect();
            (*d, *title, Project { files })
        })
    })
}

/// Every example of every dialect, with its dialect.
pub fn examples() -> impl Iterator<Item = (&'static Dialect, &'static str, &'static str)> {
    DIALECTS
        .iter()
        .flat_map(|d| d.examples.iter().map(move |&(n, t)| (*d, n, t)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_extensions_are_unique() {
        let mut names: Vec<&str> = DIALECTS.iter().map(|d| d.name).collect();
        let mut exts: Vec<&str> = DIALECTS
            .iter()
            .flat_map(|d| d.extensions.iter().copied())
            .collect();
        let (n, e) = (names.len(), exts.len());
        names.sort_unstable();
        names.dedup();
        exts.sort_unstable();
        exts.dedup();
        assert_eq!(names.len(), n, "two dialects share a name");
        assert_eq!(exts.len(), e, "two dialects share an extension");
        assert!(!exts.contains(&"ron"), ".ron is for sessions");
    }

    #[test]
    fn choosing_by_extension_and_by_name() {
        let sl = by_name("silverlode").expect("registered");
        assert_eq!(choose(Path::new("a/b.QSL"), None), Ok(sl));
        assert_eq!(choose(Path::new("prog.txt"), Some("SilverLode")), Ok(sl));
        let unknown = choose(Path::new("prog.txt"), None).unwrap_err();
        assert!(
            unknown.to_string().contains("silverlode (.qsl)"),
            "{unknown}"
        );
        assert!(matches!(
            choose(Path::new("a.qsl"), Some("cobol")),
            Err(ChooseError::UnknownName(_))
        ));
    }

    #[test]
    fn settings_are_clamped_and_completed() {
        let sl = by_name("silverlode").expect("registered");
        let mut given = Settings::new();
        given.insert("natural_frequency_hz".into(), 1e9);
        given.insert("unknown".into(), 3.0);
        let s = sl.settings_from(&given);
        assert_eq!(s.len(), sl.settings.len());
        assert_eq!(s["natural_frequency_hz"], 200.0);
        assert!(!s.contains_key("unknown"));
    }
}
