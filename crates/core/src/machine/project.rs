//! A program as a set of named source files with a top file (TML's `#include`, spec tml.md §1.1).
//!
//! Every layer above the assemblers keeps positions as a single line number: file `k`'s line
//! `l` is `k × FILE_LINES + l` ([`Project::line`]). The top file is file 0, so a one-file
//! program's lines are its own line numbers and everything that knew one file (breakpoints,
//! traces, sessions, the runner) still holds; what shows a position to a user splits it back
//! with [`Project::describe`]. The stride is fixed, not a running sum, so editing one file
//! never moves the lines of another.

use std::path::{Path, PathBuf};

/// Lines each file may have; file `k`'s lines are `k × FILE_LINES + 1 ..`.
pub const FILE_LINES: usize = 1 << 20;
/// Files a project may have.
pub const MAX_FILES: usize = 1024;
/// Nested `#include` levels below the top file (spec tml.md §1.1).
pub const MAX_INCLUDE_DEPTH: usize = 16;

/// One source file: its name (the top file's file name, an included file's path relative to
/// the top file's directory, with `/`) and its text.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SourceFile {
    pub name: String,
    pub text: String,
}

/// The files of a program: the top file first, then the included ones in order of first
/// inclusion.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Project {
    pub files: Vec<SourceFile>,
}

impl Project {
    /// A program of one file.
    pub fn single(name: impl Into<String>, text: impl Into<String>) -> Self {
        Project {
            files: vec![SourceFile {
                name: name.into(),
                text: text.into(),
            }],
        }
    }

    /// The top file (an empty one for an empty project).
    pub fn top_text(&self) -> &str {
        self.files.first().map_or("", |f| f.text.as_str())
    }

    pub fn top_name(&self) -> &str {
        self.files.first().map_or("", |f| f.name.as_str())
    }

    /// More than one file: positions then name their file.
    pub fn is_multi(&self) -> bool {
        self.files.len() > 1
    }

    /// The program line of file `file`'s 1-based line `local`.
    pub const fn line(file: usize, local: usize) -> usize {
        file * FILE_LINES + local
    }

    /// The file and the 1-based line in it of a program line.
    pub const fn split(line: usize) -> (usize, usize) {
        (line / FILE_LINES, line % FILE_LINES)
    }

    /// The name of the file holding program line `line` ("" when there is no such file).
    pub fn file_of(&self, line: usize) -> &str {
        self.files
            .get(Project::split(line).0)
            .map_or("", |f| f.name.as_str())
    }

    /// A program line as a user reads it: `7` in a one-file program, `setup.tml:7` in a
    /// project.
    pub fn describe(&self, line: usize) -> String {
        let (file, local) = Project::split(line);
        if self.is_multi() || file > 0 {
            format!(
                "{}:{local}",
                self.files.get(file).map_or("?", |f| f.name.as_str())
            )
        } else {
            local.to_string()
        }
    }

    /// The file named `name`: that exact name, or else the only one equal to it ignoring ASCII
    /// case (spec §1.1's fallback for projects made on Windows).
    pub fn index_of(&self, name: &str) -> Option<usize> {
        if let Some(i) = self.files.iter().position(|f| f.name == name) {
            return Some(i);
        }
        let mut matches = self
            .files
            .iter()
            .enumerate()
            .filter(|(_, f)| f.name.eq_ignore_ascii_case(name));
        match (matches.next(), matches.next()) {
            (Some((i, _)), None) => Some(i),
            _ => None,
        }
    }

    /// How a diagnostic names file `file` when the top file was given as `top_path`: the top
    /// path as given, an included file joined to the top file's directory.
    pub fn display_path(&self, top_path: &str, file: usize) -> String {
        if file == 0 {
            return top_path.to_string();
        }
        let name = self.files.get(file).map_or("?", |f| f.name.as_str());
        if Path::new(name).is_absolute() {
            return name.to_string();
        }
        match Path::new(top_path).parent() {
            Some(dir) if !dir.as_os_str().is_empty() => normalize(&format!(
                "{}/{name}",
                dir.to_string_lossy().replace('\\', "/")
            )),
            _ => name.to_string(),
        }
    }
}

impl Project {
    /// A diagnostic as compilers print it, `file:line:col: error: message`, with the file
    /// named as reached from `top_path` (the top path as given).
    pub fn diagnostic(&self, top_path: &str, d: &crate::machine::Diagnostic) -> String {
        let (file, local) = Project::split(d.line);
        let local_diag = crate::machine::Diagnostic {
            line: local,
            ..d.clone()
        };
        local_diag
            .with_file(&self.display_path(top_path, file))
            .to_string()
    }
}

/// A one-file program of this text (its name is given where it is used).
impl From<&str> for Project {
    fn from(text: &str) -> Self {
        Project::single("", text)
    }
}

impl From<String> for Project {
    fn from(text: String) -> Self {
        Project::single("", text)
    }
}

/// The name of the file `path` names when written in the file named `includer` (spec §1.1):
/// relative to the includer's directory (an absolute path as is), `\` read as `/`, `.` and `..`
/// resolved on the text.
pub fn resolve_include(includer: &str, path: &str) -> String {
    let path = path.replace('\\', "/");
    if path.starts_with('/') || Path::new(&path).is_absolute() {
        return normalize(&path);
    }
    let dir = match includer.rfind('/') {
        Some(i) => &includer[..=i],
        None => "",
    };
    normalize(&format!("{dir}{path}"))
}

/// `.` and `..` taken out of a `/` path where they can be; leading `..` stay.
fn normalize(path: &str) -> String {
    let absolute = path.starts_with('/');
    let mut parts: Vec<&str> = Vec::new();
    for part in path.split('/') {
        match part {
            "" | "." => {}
            ".." if parts.last().is_some_and(|p| *p != "..") => {
                parts.pop();
            }
            ".." if absolute => {}
            _ => parts.push(part),
        }
    }
    let joined = parts.join("/");
    if absolute {
        format!("/{joined}")
    } else {
        joined
    }
}

/// The file at `path` on disk, taking each component as that entry or else the only entry of
/// its directory whose name equals it ignoring ASCII case.
fn find_on_disk(path: &Path) -> Option<PathBuf> {
    if path.is_file() {
        return Some(path.to_path_buf());
    }
    let mut found = PathBuf::new();
    for component in path.components() {
        use std::path::Component;
        match component {
            Component::Normal(name) => {
                let exact = found.join(name);
                if exact.exists() {
                    found = exact;
                    continue;
                }
                let dir = if found.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    found.as_path()
                };
                let wanted = name.to_string_lossy();
                let mut matches = std::fs::read_dir(dir)
                    .ok()?
                    .filter_map(Result::ok)
                    .filter(|e| {
                        e.file_name()
                            .to_string_lossy()
                            .eq_ignore_ascii_case(&wanted)
                    });
                let entry = matches.next()?;
                if matches.next().is_some() {
                    return None;
                }
                found = found.join(entry.file_name());
            }
            other => found.push(other.as_os_str()),
        }
    }
    found.is_file().then_some(found)
}

/// Read the program whose top file is `top`, with every file it includes (by `includes`, the
/// dialect's list of the paths a text includes) from the folders `folders` allows, in order
/// of first inclusion. Only the top file's own error is returned.
pub fn load(
    top: &Path,
    includes: fn(&str) -> Vec<String>,
    folders: &IncludeFolders,
) -> Result<Project, crate::text::TextError> {
    let text = crate::text::read(top)?;
    let name = top.file_name().map_or_else(
        || top.to_string_lossy().into_owned(),
        |n| n.to_string_lossy().into_owned(),
    );
    let dir = top.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut project = Project::single(name, text);
    add_new_includes(&mut project, &dir, includes, folders);
    Ok(project)
}

/// The folders besides the top file's own (and its subfolders) that a program's included
/// files may be read from: none unless the user names them (`--include-dir`, the window's
/// setting). Graders run students' files; an `#include "/etc/passwd"` must not read it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct IncludeFolders {
    pub allowed: Vec<PathBuf>,
}

impl IncludeFolders {
    /// Whether the file `path` lies in `dir` (the top file's folder) or an allowed folder, or
    /// below one, once its symbolic links are followed (a link in the folder to a file outside
    /// it is outside).
    pub fn permit(&self, dir: &Path, path: &Path) -> bool {
        let Ok(real) = path.canonicalize() else {
            return false;
        };
        std::iter::once(dir)
            .chain(self.allowed.iter().map(PathBuf::as_path))
            .any(|root| {
                let root = if root.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    root
                };
                root.canonicalize().is_ok_and(|r| real.starts_with(r))
            })
    }

    /// Where the program file named `name` (a name of [`resolve_include`]) of a program whose
    /// top file is in `dir` is on disk, if the rule lets servoscope read or write it there.
    pub fn path_of(&self, dir: &Path, name: &str) -> Option<PathBuf> {
        let name = name.replace('\\', "/");
        let on_disk = if Path::new(&name).is_absolute() {
            PathBuf::from(&name)
        } else {
            dir.join(&name)
        };
        // A file not there yet (Save program writes it): its nearest folder that exists must
        // be allowed, links followed, and what is below it plain names, never `..`.
        let mut existing = on_disk.as_path();
        while !existing.exists() {
            existing.file_name()?;
            existing = existing.parent()?;
        }
        let existing = if existing.as_os_str().is_empty() {
            Path::new(".")
        } else {
            existing
        };
        self.permit(dir, existing).then_some(on_disk)
    }
}

/// Whether an included file's name (of [`resolve_include`]) leaves the top file's folder: an
/// absolute path or one that starts with `..`.
pub fn outside_top_folder(name: &str) -> bool {
    Path::new(name).is_absolute()
        || name.starts_with('/')
        || name == ".."
        || name.starts_with("../")
}

/// The file named `wanted` (a name of [`resolve_include`]) of a program whose top file is in
/// `dir`, read from disk and named as it is found there (so a case-folded include still names
/// the real file); `None` when there is no such readable file or `folders` does not allow it.
pub fn read_included(dir: &Path, wanted: &str, folders: &IncludeFolders) -> Option<SourceFile> {
    let on_disk = if Path::new(wanted).is_absolute() {
        PathBuf::from(wanted)
    } else {
        dir.join(wanted)
    };
    // A path that climbs out of the folder is refused by its text too, even one that comes
    // back in (`../prog/x.tml` would load a second copy of `x.tml` under another name).
    if outside_top_folder(wanted) && folders.allowed.is_empty() {
        return None;
    }
    let found = find_on_disk(&on_disk)?;
    if !folders.permit(dir, &found) {
        return None;
    }
    let text = read_lossy(&found)?;
    let name = if Path::new(wanted).is_absolute() {
        found.to_string_lossy().replace('\\', "/")
    } else {
        found.strip_prefix(dir).map_or(wanted.to_string(), |p| {
            p.to_string_lossy().replace('\\', "/")
        })
    };
    Some(SourceFile { name, text })
}

/// Add the files `project`'s texts include that it does not hold yet and that can be read from
/// disk (the top file is in `dir`), in order of first inclusion: when a project is loaded, and
/// when an `#include` is typed in the window. A file that cannot be read is left out: the
/// assembler reports it at its `#include` line. Returns how many were added.
pub fn add_new_includes(
    project: &mut Project,
    dir: &Path,
    includes: fn(&str) -> Vec<String>,
    folders: &IncludeFolders,
) -> usize {
    let before = project.files.len();
    let mut next = 0;
    while next < project.files.len() && project.files.len() < MAX_FILES {
        let includer = project.files[next].name.clone();
        for path in includes(&project.files[next].text) {
            let wanted = resolve_include(&includer, &path);
            if project.index_of(&wanted).is_none()
                && let Some(file) = read_included(dir, &wanted, folders)
                && project.index_of(&file.name).is_none()
            {
                project.files.push(file);
            }
        }
        next += 1;
    }
    project.files.len() - before
}

/// An included file's text: UTF-8 with an invalid byte read as U+FFFD (spec §1.1), within the
/// size limit every file read has.
fn read_lossy(path: &Path) -> Option<String> {
    let meta = std::fs::metadata(path).ok()?;
    if !meta.is_file() || meta.len() > crate::text::MAX_FILE_BYTES as u64 {
        return None;
    }
    let bytes = std::fs::read(path).ok()?;
    Some(crate::text::normalize(&String::from_utf8_lossy(&bytes)).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn include_paths_resolve_relative_to_the_including_file() {
        assert_eq!(resolve_include("motion.tml", "setup.tml"), "setup.tml");
        assert_eq!(resolve_include("motion.tml", "lib\\a.tml"), "lib/a.tml");
        assert_eq!(resolve_include("lib/a.tml", "b.tml"), "lib/b.tml");
        assert_eq!(resolve_include("lib/a.tml", "../b.tml"), "b.tml");
        assert_eq!(resolve_include("lib/a.tml", "./x/../c.tml"), "lib/c.tml");
        assert_eq!(
            resolve_include("main.tml", "../common/x.tml"),
            "../common/x.tml"
        );
        assert_eq!(resolve_include("main.tml", "/abs/p.tml"), "/abs/p.tml");
    }

    #[test]
    fn a_file_is_written_only_inside_the_top_folder_whatever_its_name() {
        let root = std::env::temp_dir().join(format!("servoscope-path-of-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let dir = root.join("prog");
        std::fs::create_dir_all(dir.join("lib")).expect("folders");
        std::fs::write(dir.join("lib/a.tml"), "").expect("a file");
        let none = IncludeFolders::default();
        // Inside, there or not yet.
        assert!(none.path_of(&dir, "lib/a.tml").is_some());
        assert!(none.path_of(&dir, "lib/new.tml").is_some());
        assert!(none.path_of(&dir, "new/deeper/b.tml").is_some());
        // Out, however spelled (a crafted session names the files Save program writes).
        for name in [
            "../evil.tml",
            "./../evil.tml",
            "x/../../evil.tml",
            "lib/../../evil.tml",
            "..\\evil.tml",
            "/tmp/evil.tml",
        ] {
            assert_eq!(none.path_of(&dir, name), None, "{name}");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&root, dir.join("out")).expect("a link");
            assert_eq!(none.path_of(&dir, "out/new.tml"), None, "through a link");
        }
        // An allowed folder is as good as the top one.
        let shared = IncludeFolders {
            allowed: vec![root.clone()],
        };
        assert!(shared.path_of(&dir, "../evil.tml").is_some());
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn lines_name_their_file() {
        let mut p = Project::single("motion.tml", "BEGIN;");
        assert_eq!(p.describe(7), "7");
        p.files.push(SourceFile {
            name: "setup.tml".into(),
            text: String::new(),
        });
        let line = Project::line(1, 12);
        assert_eq!(Project::split(line), (1, 12));
        assert_eq!(p.describe(line), "setup.tml:12");
        assert_eq!(p.describe(3), "motion.tml:3");
        assert_eq!(p.index_of("SETUP.TML"), Some(1));
        assert_eq!(p.display_path("proj/motion.tml", 1), "proj/setup.tml");
        assert_eq!(p.display_path("proj/motion.tml", 0), "proj/motion.tml");
    }
}
