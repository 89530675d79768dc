//! Colour classes of DL205 mnemonic text for the code view.

use super::assembler::{MNEMONICS, UNSUPPORTED};
use crate::machine::dialect::{TokenClass, classify_words};

/// Colour classes for every character of one line (without its newline).
pub fn classify(line: &str) -> Vec<TokenClass> {
    classify_words(
        line,
        |chars, i, first| {
            (chars[i] == '/' && chars.get(i + 1) == Some(&'/')) || (first && chars[i] == '#')
        },
        |_| false,
        |word, first| {
            if first && (MNEMONICS.contains(&word) || UNSUPPORTED.contains(&word)) {
                TokenClass::Mnemonic
            } else if word.starts_with('K') || word.starts_with('O') {
                TokenClass::Number
            } else if word.starts_with("SP") {
                TokenClass::Condition
            } else {
                TokenClass::Location
            }
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_cover_every_character() {
        let line = "STRE V1400 K1234 // equal";
        let kinds = classify(line);
        assert_eq!(kinds.len(), line.chars().count());
        assert_eq!(kinds[0], TokenClass::Mnemonic);
        assert_eq!(kinds[5], TokenClass::Location);
        assert_eq!(kinds[11], TokenClass::Number);
        assert_eq!(*kinds.last().unwrap(), TokenClass::Comment);
    }
}
