//! Colour classes of SilverLode program text for the code view.

use super::program::ALIASES;
use super::{ClcOp, CondBit, ExtOp};
use crate::machine::dialect::TokenClass;

use super::assembler::MNEMONICS;

fn class_of_word(word: &str, first_word: bool) -> TokenClass {
    let upper = word.to_ascii_uppercase();
    if first_word && MNEMONICS.contains(&upper.as_str()) {
        TokenClass::Mnemonic
    } else if ClcOp::parse(word).is_some() || ExtOp::parse(word).is_some() {
        TokenClass::Operation
    } else if CondBit::parse(word).is_some() {
        TokenClass::Condition
    } else if ALIASES.iter().any(|a| a.name.eq_ignore_ascii_case(word))
        || (upper.starts_with('R')
            && upper.len() > 1
            && upper[1..].chars().all(|c| c.is_ascii_digit()))
    {
        TokenClass::Location
    } else if upper == "Q16" {
        TokenClass::Number
    } else {
        TokenClass::Label
    }
}

/// Colour classes for every character of one line (without its newline).
pub fn classify(line: &str) -> Vec<TokenClass> {
    let chars: Vec<char> = line.chars().collect();
    let mut kinds = vec![TokenClass::Plain; chars.len()];
    let mut i = 0;
    let mut seen_word = false;
    while i < chars.len() {
        let c = chars[i];
        if c == ';' {
            kinds[i..].fill(TokenClass::Comment);
            break;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let is_label_def = !seen_word && chars.get(i) == Some(&':');
            let kind = if is_label_def {
                TokenClass::Label
            } else {
                let k = class_of_word(&word, !seen_word);
                seen_word = true;
                k
            };
            kinds[start..i].fill(kind);
            if is_label_def {
                kinds[i] = TokenClass::Label;
                i += 1;
            }
            continue;
        }
        if c.is_ascii_digit() || (c == '-' && chars.get(i + 1).is_some_and(char::is_ascii_digit)) {
            let start = i;
            i += 1;
            while i < chars.len()
                && (chars[i].is_ascii_alphanumeric() || chars[i] == '_' || chars[i] == '.')
            {
                i += 1;
            }
            kinds[start..i].fill(TokenClass::Number);
            continue;
        }
        if c == '!' {
            kinds[i] = TokenClass::Condition;
        }
        i += 1;
    }
    kinds
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classify_colours_each_part() {
        let kinds = classify("loop: CLD ADD, R25, 26, q16(1.5) ; hi");
        assert!(kinds[0..5].iter().all(|&k| k == TokenClass::Label));
        assert!(kinds[6..9].iter().all(|&k| k == TokenClass::Mnemonic));
        assert!(kinds[10..13].iter().all(|&k| k == TokenClass::Operation));
        assert!(kinds[15..18].iter().all(|&k| k == TokenClass::Location));
        assert!(kinds[20..22].iter().all(|&k| k == TokenClass::Number));
        assert_eq!(kinds.last(), Some(&TokenClass::Comment));
    }
}
