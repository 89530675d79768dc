//! Colour classes of DL205 mnemonic text for the code view.

use super::assembler::{MNEMONICS, UNSUPPORTED};
use crate::machine::registry::TokenClass;

/// Colour classes for every character of one line (without its newline).
pub fn classify(line: &str) -> Vec<TokenClass> {
    let chars: Vec<char> = line.chars().collect();
    let mut kinds = vec![TokenClass::Plain; chars.len()];
    let mut i = 0;
    let mut first = true;
    while i < chars.len() {
        if chars[i] == '/' && chars.get(i + 1) == Some(&'/') || (first && chars[i] == '#') {
            kinds[i..].fill(TokenClass::Comment);
            break;
        }
        if chars[i].is_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        while i < chars.len() && !chars[i].is_whitespace() {
            i += 1;
        }
        let word: String = chars[start..i].iter().collect::<String>().to_ascii_uppercase();
        let class = if first && (MNEMONICS.contains(&word.as_str()) || UNSUPPORTED.contains(&word.as_str())) {
            TokenClass::Mnemonic
        } else if word.starts_with('K') || word.starts_with('O') {
            TokenClass::Number
        } else if word.starts_with("SP") {
            TokenClass::Condition
        } else {
            TokenClass::Location
        };
        kinds[start..i].fill(class);
        first = false;
    }
    kinds
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
