//! Text files as other editors write them: a UTF-8 byte-order mark is skipped, and CR LF and
//! lone CR line endings (old Mac editors, some PLC tools) become LF, for programs and sessions
//! alike. A file that is not UTF-8 is refused with the offset of the first bad byte.

use std::borrow::Cow;
use std::path::Path;

#[derive(Debug, thiserror::Error)]
pub enum TextError {
    #[error("cannot read {path}: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    #[error(
        "{path} is not UTF-8 text: the byte at offset {offset} (0x{byte:02X}) does not belong there; save the file as UTF-8"
    )]
    NotUtf8 {
        path: String,
        offset: usize,
        byte: u8,
    },
    #[error("{path} is not a regular file; servoscope opens programs and sessions from files")]
    NotAFile { path: String },
    #[error(
        "{path} has {bytes} bytes; servoscope opens files of at most {MAX_FILE_BYTES} bytes (16 MiB)"
    )]
    TooLarge { path: String, bytes: u64 },
}

/// The largest program or session file servoscope reads: far beyond any real program (the
/// largest vendor examples are a few kilobytes), small enough that reading cannot exhaust
/// memory.
pub const MAX_FILE_BYTES: usize = 16 << 20;

/// `text` without a leading byte-order mark and with every line ending as LF.
pub fn normalize(text: &str) -> Cow<'_, str> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.contains('\r') {
        Cow::Owned(text.replace("\r\n", "\n").replace('\r', "\n"))
    } else {
        Cow::Borrowed(text)
    }
}

/// Bytes read from `path` as normalized text.
pub fn decode(bytes: Vec<u8>, path: &str) -> Result<String, TextError> {
    match String::from_utf8(bytes) {
        Ok(text) => Ok(normalize(&text).into_owned()),
        Err(e) => {
            let offset = e.utf8_error().valid_up_to();
            Err(TextError::NotUtf8 {
                path: path.to_string(),
                offset,
                byte: e.as_bytes()[offset],
            })
        }
    }
}

/// Read a text file, normalized.
/// Only regular files (or links to one) of at most [`MAX_FILE_BYTES`] are read: a device such
/// as `/dev/zero`, a pipe or a directory is refused, and so is a file that grows past the limit
/// while it is read.
pub fn read(path: &Path) -> Result<String, TextError> {
    use std::io::Read as _;
    let name = path.display().to_string();
    let failed = |source| TextError::Read {
        path: name.clone(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(failed)?;
    if !meta.is_file() {
        return Err(TextError::NotAFile { path: name });
    }
    let too_large = |bytes: u64| TextError::TooLarge {
        path: name.clone(),
        bytes,
    };
    if meta.len() > MAX_FILE_BYTES as u64 {
        return Err(too_large(meta.len()));
    }
    let file = std::fs::File::open(path).map_err(failed)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(MAX_FILE_BYTES as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(failed)?;
    if bytes.len() > MAX_FILE_BYTES {
        return Err(too_large(bytes.len() as u64));
    }
    decode(bytes, &name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_directories_and_huge_files_are_refused_before_reading() {
        let zero = read(Path::new("/dev/zero"));
        assert!(matches!(zero, Err(TextError::NotAFile { .. })), "{zero:?}");
        let dir = std::env::temp_dir();
        assert!(matches!(read(&dir), Err(TextError::NotAFile { .. })));
        let big = dir.join(format!("servoscope-big-{}.qsl", std::process::id()));
        let file = std::fs::File::create(&big).expect("a temp file");
        // Sparse: no disk used, but the length says 16 MiB + 1.
        file.set_len(MAX_FILE_BYTES as u64 + 1).expect("sized");
        let result = read(&big);
        let _ = std::fs::remove_file(&big);
        match result {
            Err(TextError::TooLarge { bytes, .. }) => assert_eq!(bytes, MAX_FILE_BYTES as u64 + 1),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn line_endings_and_marks_from_other_editors() {
        assert_eq!(normalize("a\r\nb\r\n"), "a\nb\n");
        assert_eq!(normalize("a\rb\rc"), "a\nb\nc");
        assert_eq!(normalize("a\r\rb"), "a\n\nb", "two lone CRs are two lines");
        assert_eq!(normalize("\u{feff}WRP 11, 1\n"), "WRP 11, 1\n");
        assert!(matches!(normalize("plain\n"), Cow::Borrowed(_)));
    }

    #[test]
    fn bytes_that_are_not_utf8_are_refused_with_their_offset() {
        let e = decode(b"WRP 11, 1\n\xffEND".to_vec(), "p.qsl").unwrap_err();
        assert!(
            matches!(
                e,
                TextError::NotUtf8 {
                    offset: 10,
                    byte: 0xFF,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("offset 10"), "{e}");
        assert_eq!(decode(b"\xef\xbb\xbfEND\r".to_vec(), "p").unwrap(), "END\n");
    }
}
