//! Colour classes of OpenNet text for the code view.

use super::assembler::{ADVANCED, BASIC, UNSUPPORTED};
use crate::machine::dialect::{TokenClass, classify_words};

/// Colour classes for every character of one line (without its newline).
pub fn classify(line: &str) -> Vec<TokenClass> {
    classify_words(
        line,
        |chars, i, _| chars[i] == ';',
        |c| c == ',',
        |word, first| {
            let base = word.split('(').next().unwrap_or("");
            let mnemonic =
                BASIC.contains(&base) || ADVANCED.contains(&base) || UNSUPPORTED.contains(&base);
            if (first && mnemonic) || word == "REP" || word == "LOD" {
                TokenClass::Mnemonic
            } else if word.starts_with(|ch: char| ch.is_ascii_digit() || ch == '-' || ch == '+') {
                TokenClass::Number
            } else if word.starts_with("M8") && word.len() == 5 {
                TokenClass::Condition
            } else if word.chars().nth(1).is_some_and(|ch| ch.is_ascii_digit()) {
                TokenClass::Location
            } else {
                TokenClass::Number
            }
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_cover_every_character() {
        let line = "ADD(W) D100(R) D0 D0 REP 4 ; total";
        let kinds = classify(line);
        assert_eq!(kinds.len(), line.chars().count());
        assert_eq!(kinds[0], TokenClass::Mnemonic);
        assert_eq!(kinds[7], TokenClass::Location);
        assert_eq!(*kinds.last().unwrap(), TokenClass::Comment);
    }
}
