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
}

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
pub fn read(path: &Path) -> Result<String, TextError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| TextError::Read {
        path: name.clone(),
        source,
    })?;
    decode(bytes, &name)
}

#[cfg(test)]
mod tests {
    use super::*;

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
