//! Writing files users keep: write a temporary file beside the target, flush it to disk, then
//! rename it over the target, so a crash mid-save leaves the old file intact.
//!
//! Only regular files are replaced: a symbolic link is followed and its target written (the
//! link stays), a device, directory or other special file is refused (`/dev/null` stays a
//! device), and the replaced file keeps its permissions and, where allowed, its owner. The
//! temporary file has a fixed name per target, so one left behind by a killed save is reused
//! and replaced by the next save, never piled up.

use std::io::Write;
use std::path::{Path, PathBuf};

/// The path a save really writes: `target`, or the file its symbolic links lead to.
pub fn resolve(target: &Path) -> std::io::Result<PathBuf> {
    let mut path = target.to_path_buf();
    // A bounded walk: a loop of links is an error, as the system reports it elsewhere.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&path) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = std::fs::read_link(&path)?;
                path = match path.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            Ok(meta) if !meta.is_file() => {
                return Err(std::io::Error::other(format!(
                    "{} is not a regular file; servoscope saves only to regular files",
                    path.display()
                )));
            }
            // A regular file, or nothing yet: either is fine to write.
            _ => return Ok(path),
        }
    }
    Err(std::io::Error::other(format!(
        "{} is a loop of symbolic links",
        target.display()
    )))
}

/// How the temporary files of our saves end.
const TEMP_SUFFIX: &str = ".servoscope-tmp";
/// A temporary file untouched this long belongs to a save that was killed, not to one under
/// way (a save writes its file in well under a second).
const STALE_AFTER: std::time::Duration = std::time::Duration::from_secs(60);

/// Remove the temporary files killed saves left in `dir` (ours only: `.NAME.servoscope-tmp`,
/// untouched for a minute). Called on every save, and on start for the folders of recent
/// files. Errors are ignored: this is tidying, never a reason for a save to fail.
pub fn remove_stale_temporaries(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let now = std::time::SystemTime::now();
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if !(name.starts_with('.') && name.ends_with(TEMP_SUFFIX)) {
            continue;
        }
        let stale = entry
            .metadata()
            .ok()
            .filter(std::fs::Metadata::is_file)
            .and_then(|m| m.modified().ok())
            .and_then(|modified| now.duration_since(modified).ok())
            .is_some_and(|age| age >= STALE_AFTER);
        if stale {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

fn temp_path(target: &Path) -> PathBuf {
    let name = target
        .file_name()
        .map_or_else(|| "servoscope".into(), |n| n.to_string_lossy().into_owned());
    target.with_file_name(format!(".{name}{TEMP_SUFFIX}"))
}

/// Give the new file the old one's permissions and owner (the owner only where allowed).
#[cfg(unix)]
fn keep_attributes(old: &std::fs::Metadata, new: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::MetadataExt;
    std::fs::set_permissions(new, old.permissions())?;
    // Only a privileged saver can give the file away; anyone else keeps their own.
    let _ = std::os::unix::fs::chown(new, Some(old.uid()), Some(old.gid()));
    Ok(())
}

#[cfg(not(unix))]
fn keep_attributes(old: &std::fs::Metadata, new: &Path) -> std::io::Result<()> {
    std::fs::set_permissions(new, old.permissions())
}

/// Write `target` through `fill`, atomically. On any error the target is untouched and the
/// temporary file is removed.
pub fn write_atomically(
    target: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let target = resolve(target)?;
    let temp = temp_path(&target);
    let result = (|| {
        let file = std::fs::File::create(&temp)?;
        let mut writer = std::io::BufWriter::new(file);
        fill(&mut writer)?;
        let file = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        if let Ok(old) = std::fs::metadata(&target) {
            keep_attributes(&old, &temp)?;
        }
        std::fs::rename(&temp, &target)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    if let Some(dir) = target.parent() {
        remove_stale_temporaries(if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        });
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("servoscope-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn replaces_the_target_only_when_complete() {
        let dir = dir("complete");
        let target = dir.join("out.txt");
        std::fs::write(&target, "old").unwrap();
        let failed = write_atomically(&target, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("disk full"))
        });
        assert!(failed.is_err());
        assert_eq!(
            std::fs::read_to_string(&target).unwrap(),
            "old",
            "old file intact"
        );
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "no temporary file left"
        );
        write_atomically(&target, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_save_anywhere_in_a_folder_removes_what_killed_saves_left_there() {
        let dir = dir("stale");
        let old = dir.join(".killed.ron.servoscope-tmp");
        let fresh = dir.join(".busy.ron.servoscope-tmp");
        let theirs = dir.join(".notes.txt.swp");
        for path in [&old, &fresh, &theirs] {
            std::fs::write(path, "half").unwrap();
        }
        let an_hour_ago = std::time::SystemTime::now() - std::time::Duration::from_secs(3600);
        for path in [&old, &theirs] {
            let file = std::fs::File::options().write(true).open(path).unwrap();
            file.set_modified(an_hour_ago).unwrap();
        }
        write_atomically(&dir.join("other.ron"), |w| w.write_all(b"x")).unwrap();
        assert!(!old.exists(), "a killed save's leftover goes");
        assert!(fresh.exists(), "a save that may be under way stays");
        assert!(theirs.exists(), "other programs' files stay");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_temporary_file_left_by_a_killed_save_is_reused() {
        let dir = dir("leftover");
        let target = dir.join("s.ron");
        std::fs::write(temp_path(&target), "half of an old save").unwrap();
        write_atomically(&target, |w| w.write_all(b"whole")).unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "whole");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "nothing left over"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[cfg(unix)]
    #[test]
    fn links_are_followed_and_special_files_refused() {
        use std::os::unix::fs::PermissionsExt;
        let dir = dir("links");
        let real = dir.join("real.ron");
        std::fs::write(&real, "old").unwrap();
        std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o600)).unwrap();
        let link = dir.join("link.ron");
        std::os::unix::fs::symlink("real.ron", &link).unwrap();
        write_atomically(&link, |w| w.write_all(b"through the link")).unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink(),
            "the link stays a link"
        );
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "through the link");
        let mode = std::fs::metadata(&real).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600, "the file keeps its permissions");

        let null = write_atomically(Path::new("/dev/null"), |w| w.write_all(b"x"));
        assert!(null.is_err(), "a device is not replaced");
        assert!(
            !std::fs::metadata("/dev/null")
                .unwrap()
                .file_type()
                .is_file(),
            "/dev/null is still a device"
        );
        let into_dir = write_atomically(&dir, |w| w.write_all(b"x"));
        assert!(into_dir.is_err(), "nor is a directory");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
