//! Colour classes of TML text for the code view.

use super::PREDEFINED;
use super::assembler::{MNEMONICS, UNSUPPORTED};
use super::program::Cond;
use crate::machine::dialect::TokenClass;

fn class_of_word(word: &str) -> TokenClass {
    let upper = word.to_ascii_uppercase();
    if MNEMONICS.contains(&upper.as_str())
        || UNSUPPORTED.contains(&upper.as_str())
        || ["INT", "LONG", "FIXED", "PP", "MC", "RT"].contains(&upper.as_str())
    {
        TokenClass::Mnemonic
    } else if Cond::parse(word).is_some() {
        TokenClass::Condition
    } else if upper == "PREG"
        || PREDEFINED.iter().any(|p| {
            let name = super::canonical_name(&upper);
            p.name == name || p.alias == Some(name)
        })
    {
        TokenClass::Location
    } else {
        TokenClass::Label
    }
}

/// Colour classes for every character of one line (without its newline).
pub fn classify(line: &str) -> Vec<TokenClass> {
    let chars: Vec<char> = line.chars().collect();
    let mut kinds = vec![TokenClass::Plain; chars.len()];
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            kinds[i..].fill(TokenClass::Comment);
            break;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let class = if chars.get(i) == Some(&':') && start == 0 {
                TokenClass::Label
            } else {
                class_of_word(&word)
            };
            kinds[start..i].fill(class);
            continue;
        }
        if c.is_ascii_digit() {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '.') {
                i += 1;
            }
            kinds[start..i].fill(TokenClass::Number);
            continue;
        }
        if "=+-*/<>!#".contains(c) {
            kinds[i] = TokenClass::Operation;
        }
        i += 1;
    }
    kinds
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_cover_every_character() {
        let line = "loop: CPOS = 0x10; GOTO loop, x, GT; // done";
        let kinds = classify(line);
        assert_eq!(kinds.len(), line.chars().count());
        assert_eq!(kinds[0], TokenClass::Label);
        assert_eq!(kinds[6], TokenClass::Location);
        assert_eq!(kinds[13], TokenClass::Number);
        assert_eq!(*kinds.last().unwrap(), TokenClass::Comment);
    }
}
