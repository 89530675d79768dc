//! What a command may write over. `servoscope ladder prog.dl205 --svg prog.dl205` used to
//! replace the program with its drawing. Every output file (a ladder SVG, a trace, a log, a
//! session) follows one rule: never a file the command read; and an existing file that is not
//! this kind of output (a program, a session, anything else) only when the user says so
//! (`--overwrite`; the window's exports refuse and keep their dialog open). Symbolic links are
//! followed first, so a link cannot smuggle a write past the rule, and a link to nothing is
//! refused (it would create a file wherever it points). The write itself is atomic
//! ([`crate::atomic`]).

use std::io::Read;
use std::path::{Path, PathBuf};

/// The kinds of file servoscope writes, each recognisable from its first bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// `ladder --svg`, Export ladder: an SVG carrying the ladder's mark.
    LadderSvg,
    /// `run --trace`: JSON Lines, one object per instruction.
    Trace,
    /// Export log: CSV under [`LOG_CSV_HEADER`].
    LogCsv,
    /// The plot's export: CSV whose header starts `tick,time_ms`.
    PlotCsv,
    /// A saved session.
    Session,
}

use crate::machine::plc::ladder::SVG_MARK as LADDER_SVG_MARK;
/// The first line of an exported log.
pub const LOG_CSV_HEADER: &str = "tick,step,instruction,line,explanation,written";

impl Output {
    fn describe(self) -> &'static str {
        match self {
            Output::LadderSvg => "a ladder diagram servoscope drew",
            Output::Trace => "a servoscope trace",
            Output::LogCsv => "a log servoscope exported",
            Output::PlotCsv => "a plot servoscope exported",
            Output::Session => "a session",
        }
    }

    /// Whether `head` (the file's first bytes) is this kind of output.
    fn recognises(self, head: &str, path: &Path) -> bool {
        match self {
            Output::LadderSvg => {
                head.trim_start().starts_with("<svg") && head.contains(LADDER_SVG_MARK)
            }
            // Each line an object whose first key is the instruction count (a first line may
            // be longer than the head read, so its start is what counts).
            Output::Trace => head.starts_with("{\"n\":") && head.contains("\"mnemonic\":"),
            Output::LogCsv => head.lines().next() == Some(LOG_CSV_HEADER),
            Output::PlotCsv => head.starts_with("tick,time_ms"),
            Output::Session => crate::session::not_a_session(path).is_none(),
        }
    }
}

#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum Refusal {
    #[error("{path} is {what}, and servoscope never writes over a file it read")]
    Input { path: String, what: String },
    #[error("{path} exists and is not {kind} ({found}), so it was not replaced")]
    NotOurs {
        path: String,
        kind: &'static str,
        found: String,
    },
    #[error("cannot write {path}: {reason}")]
    Unwritable { path: String, reason: String },
}

/// One file a command read, named for the message that refuses to write over it.
#[derive(Clone, Debug)]
pub struct Input {
    pub path: PathBuf,
    /// "the program", "an included file", "the lesson" …
    pub what: String,
}

impl Input {
    pub fn new(path: impl Into<PathBuf>, what: impl Into<String>) -> Self {
        Input {
            path: path.into(),
            what: what.into(),
        }
    }
}

/// The bytes of a file's head read to recognise it.
const HEAD_BYTES: u64 = 64 << 10;

/// Whether `kind` may be written to `target`, given the files the command read (`inputs`) and
/// whether the user allowed replacing a file of another kind (`overwrite`). A missing or empty
/// target is always fine, the command's input never is.
pub fn may_write(
    target: &Path,
    kind: Output,
    inputs: &[Input],
    overwrite: bool,
) -> Result<(), Refusal> {
    let shown = target.display().to_string();
    let real = crate::atomic::resolve(target).map_err(|e| Refusal::Unwritable {
        path: shown.clone(),
        reason: e.to_string(),
    })?;
    let Ok(meta) = std::fs::metadata(&real) else {
        if std::fs::symlink_metadata(target).is_ok_and(|m| m.file_type().is_symlink()) {
            return Err(Refusal::Unwritable {
                path: shown,
                reason: "it is a link to a file that does not exist; servoscope creates no file through a link".to_string(),
            });
        }
        return Ok(());
    };
    if let Some(input) = inputs.iter().find(|i| same_file(&real, &i.path)) {
        return Err(Refusal::Input {
            path: shown,
            what: input.what.clone(),
        });
    }
    if meta.len() == 0 || overwrite {
        return Ok(());
    }
    let head = read_head(&real);
    if crate::registry::by_path(&real).is_none() && kind.recognises(&head, &real) {
        return Ok(());
    }
    let found = if let Some(dialect) = crate::registry::by_path(&real) {
        format!("it is a {} program", dialect.display_name)
    } else if crate::session::is_session_path(&real) {
        "it is a session".to_string()
    } else {
        "servoscope did not write it".to_string()
    };
    Err(Refusal::NotOurs {
        path: shown,
        kind: kind.describe(),
        found,
    })
}

/// The first bytes of `path` as text (invalid UTF-8 replaced); empty when it cannot be read.
fn read_head(path: &Path) -> String {
    let mut bytes = Vec::new();
    if let Ok(file) = std::fs::File::open(path) {
        let _ = file.take(HEAD_BYTES).read_to_end(&mut bytes);
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Whether `a` and `b` name one file (links followed; on Unix the same inode, so a hard link
/// counts too).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// The files a program was read from: the top file at `top` and its included files, as the
/// loader found them next to it.
pub fn program_inputs(top: &Path, project: &crate::machine::project::Project) -> Vec<Input> {
    let dir = top.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut inputs = vec![Input::new(top, "the program")];
    for file in project.files.iter().skip(1) {
        let path = if Path::new(&file.name).is_absolute() {
            PathBuf::from(&file.name)
        } else {
            dir.join(&file.name)
        };
        inputs.push(Input::new(path, format!("the included file {}", file.name)));
    }
    inputs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("servoscope-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp folder");
        dir
    }

    #[test]
    fn the_input_is_never_replaced_even_with_overwrite() {
        let dir = folder("input");
        let program = dir.join("prog.dl205");
        std::fs::write(&program, "STR X0\nOUT Y0\nEND\n").expect("written");
        let inputs = [Input::new(&program, "the program")];
        let refused = may_write(&program, Output::LadderSvg, &inputs, true);
        assert!(matches!(refused, Err(Refusal::Input { .. })), "{refused:?}");
        #[cfg(unix)]
        {
            let link = dir.join("link.svg");
            std::os::unix::fs::symlink(&program, &link).expect("link");
            let refused = may_write(&link, Output::LadderSvg, &inputs, true);
            assert!(matches!(refused, Err(Refusal::Input { .. })), "{refused:?}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_file_of_another_kind_needs_overwrite() {
        let dir = folder("kind");
        let other = dir.join("notes.txt");
        std::fs::write(&other, "my notes").expect("written");
        let program = dir.join("other.dl205");
        std::fs::write(&program, "STR X0\n").expect("written");
        for target in [&other, &program] {
            let refused = may_write(target, Output::Trace, &[], false);
            assert!(
                matches!(refused, Err(Refusal::NotOurs { .. })),
                "{refused:?}"
            );
            assert_eq!(may_write(target, Output::Trace, &[], true), Ok(()));
        }
        let message = may_write(&program, Output::LadderSvg, &[], false)
            .expect_err("refused")
            .to_string();
        assert!(message.contains("DL205 program"), "{message}");
        // Our own earlier output, a missing file and an empty one are fine.
        let trace = dir.join("t.jsonl");
        std::fs::write(
            &trace,
            "{\"n\":1,\"tick\":0,\"step\":0,\"line\":1,\"mnemonic\":\"STR\",\"written\":{}}\n",
        )
        .expect("written");
        assert_eq!(may_write(&trace, Output::Trace, &[], false), Ok(()));
        assert!(may_write(&trace, Output::LadderSvg, &[], false).is_err());
        let svg = dir.join("l.svg");
        std::fs::write(
            &svg,
            format!("<svg xmlns=\"x\">\n{LADDER_SVG_MARK}\n</svg>\n"),
        )
        .expect("written");
        assert_eq!(may_write(&svg, Output::LadderSvg, &[], false), Ok(()));
        assert_eq!(
            may_write(&dir.join("new.svg"), Output::LadderSvg, &[], false),
            Ok(())
        );
        std::fs::write(dir.join("empty.svg"), "").expect("written");
        assert_eq!(
            may_write(&dir.join("empty.svg"), Output::LadderSvg, &[], false),
            Ok(())
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
