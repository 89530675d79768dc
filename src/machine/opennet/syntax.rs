//! Colour classes of OpenNet text for the code view.

use super::assembler::{ADVANCED, BASIC, UNSUPPORTED};
use crate::machine::registry::TokenClass;

/// Colour classes for every character of one line (without its newline).
pub fn classify(line: &str) -> Vec<TokenClass> {
    let chars: Vec<char> = line.chars().collect();
    let mut kinds = vec![TokenClass::Plain; chars.len()];
    let mut i = 0;
    let mut first = true;
    while i < chars.len() {
        let c = chars[i];
        if c == ';' {
            kinds[i..].fill(TokenClass::Comment);
            break;
        }
        if c.is_whitespace() || c == ',' {
            i += 1;
            continue;
        }
        let start = i;
        while i < chars.len() && !chars[i].is_whitespace() && chars[i] != ',' && chars[i] != ';' {
            i += 1;
        }
        let word: String = chars[start..i].iter().collect::<String>().to_ascii_uppercase();
        let base = word.split('(').next().unwrap_or("");
        let class = if (first
            && (BASIC.contains(&base) || ADVANCED.contains(&base) || UNSUPPORTED.contains(&base)))
            || word == "REP"
            || word == "LOD"
        {
            TokenClass::Mnemonic
        } else if word.starts_with(|ch: char| ch.is_ascii_digit() || ch == '-' || ch == '+') {
            TokenClass::Number
        } else if word.starts_with('M') && word.len() == 5 && word.starts_with("M8") {
            TokenClass::Condition
        } else if word.chars().skip(1).take_while(|ch| ch.is_ascii_digit()).count() > 0 {
            TokenClass::Location
        } else {
            TokenClass::Number
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
        let line = "ADD(W) D100(R) D0 D0 REP 4 ; total";
        let kinds = classify(line);
        assert_eq!(kinds.len(), line.chars().count());
        assert_eq!(kinds[0], TokenClass::Mnemonic);
        assert_eq!(kinds[7], TokenClass::Location);
        assert_eq!(*kinds.last().unwrap(), TokenClass::Comment);
    }
}
