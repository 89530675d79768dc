//! Tokens: the lexer of one statement, numbers and their suffixes (spec §1.3), and the
//! assembler's error.

use super::MAX_FIXED_DIGITS;

#[derive(Clone, Debug, PartialEq)]
pub(super) enum Tok {
    Ident(String),
    /// A number as written: decimal/hex integer with its suffix, or a fixed literal.
    Int(i128, Suffix),
    Fixed(i128),
    BadNumber(String),
    Punct(&'static str),
}

/// An integer literal's suffix (spec §1.3): it never changes the value, it says where the
/// literal may stand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Suffix {
    None,
    /// `U`: 0..65535.
    U,
    /// `L`: a 32-bit integer.
    L,
    /// `UL` or `LU`: 0..2^32−1.
    UL,
}

impl Suffix {
    pub(super) fn text(self) -> &'static str {
        match self {
            Suffix::None => "",
            Suffix::U => "U",
            Suffix::L => "L",
            Suffix::UL => "UL",
        }
    }
}

/// Where a number stands, for its suffix (spec §1.3's table).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Context {
    /// 16-bit data, SRB masks, the factor B of `*`: `U` allowed.
    Bits16,
    /// Long data, SAP, `!RT`: `U`, `L`, `UL`, `LU` allowed.
    Bits32,
    /// Fixed data: no suffix.
    Fixed,
    /// A shift count, a `WAIT!` time-out, an `!IN#` number or level: no suffix.
    Count,
}

/// A number read from the tokens, with where it stands in the text.
#[derive(Clone, Copy, Debug)]
pub(super) struct Num {
    pub(super) value: i128,
    pub(super) fixed: bool,
    pub(super) suffix: Suffix,
    pub(super) col: usize,
    pub(super) len: usize,
}

impl Num {
    /// Refuse a suffix the context does not take, and a value its suffix does not allow.
    pub(super) fn check(&self, context: Context) -> Result<(), Error> {
        let s = self.suffix;
        let misplaced = |what: &str| {
            err(
                self.col,
                self.len,
                format!("misplaced suffix '{}': {what}", s.text()),
            )
        };
        match (context, s) {
            (_, Suffix::None) => Ok(()),
            (Context::Count, _) => misplaced("this number takes no suffix"),
            (Context::Fixed, _) => misplaced("fixed data takes a fixed literal or a whole number"),
            (Context::Bits16, Suffix::L | Suffix::UL) => {
                misplaced("L marks a 32-bit integer, and this is 16-bit")
            }
            (_, Suffix::U) if !(0..=65535).contains(&self.value) => {
                err(self.col, self.len, "a U number is 0..65535")
            }
            (_, Suffix::UL) if !(0..=i128::from(u32::MAX)).contains(&self.value) => {
                err(self.col, self.len, "a UL number is 0..4294967295")
            }
            _ => Ok(()),
        }
    }
}

#[derive(Clone, Debug)]
pub(super) struct Token {
    pub(super) tok: Tok,
    pub(super) col: usize,
    pub(super) len: usize,
}

pub(super) struct Error {
    pub(super) col: usize,
    pub(super) len: usize,
    pub(super) message: String,
}

pub(super) fn err<T>(col: usize, len: usize, message: impl Into<String>) -> Result<T, Error> {
    Err(Error {
        col,
        len,
        message: message.into(),
    })
}

pub(super) fn allowed(c: char) -> bool {
    c.is_ascii_alphanumeric() || c.is_whitespace() || "_;:,.=+-*/<>!#()[]{}@".contains(c)
}

const PUNCTS: &[&str] = &[
    "<<=", ">>=", "+=", "-=", "/=", "<<", ">>", "=", "*", ",", "(", ")", "!", "#", "-", "[", "]",
    "{", "}", ".", "+", "/", "<", ">", ":", "@",
];

/// Tokens of one statement; `start` is the 1-based column of `text[0]`.
pub(super) fn lex(text: &[char], start: usize) -> Vec<Token> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let c = text[i];
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let col = start + i;
        if c.is_ascii_alphabetic() || c == '_' {
            let begin = i;
            while i < text.len() && (text[i].is_ascii_alphanumeric() || text[i] == '_') {
                i += 1;
            }
            out.push(Token {
                tok: Tok::Ident(text[begin..i].iter().collect()),
                col,
                len: i - begin,
            });
        } else if c.is_ascii_digit()
            || (c == '.' && text.get(i + 1).is_some_and(char::is_ascii_digit))
        {
            // `.5` too, so it is refused as a number ("write 0.5"), not as punctuation.
            let begin = i;
            i += 1;
            while i < text.len()
                && (text[i].is_ascii_alphanumeric() || text[i] == '.' || text[i] == '_')
            {
                i += 1;
            }
            let word: String = text[begin..i].iter().collect();
            out.push(Token {
                tok: number(&word),
                col,
                len: i - begin,
            });
        } else {
            let rest: String = text[i..text.len().min(i + 3)].iter().collect();
            let p = PUNCTS
                .iter()
                .find(|p| rest.starts_with(**p))
                .copied()
                .unwrap_or(".");
            out.push(Token {
                tok: Tok::Punct(p),
                col,
                len: p.len(),
            });
            i += p.len();
        }
    }
    out
}

/// A number token: decimal, `0x` hex, or a fixed literal (raw = round(x × 65536), ties away
/// from zero, exact).
fn number(word: &str) -> Tok {
    let bad = || Tok::BadNumber(word.to_string());
    let lower = word.to_ascii_lowercase();
    // An integer's suffix: UL, LU, U or L (a fixed literal takes none: `1.5L` is malformed).
    let (lower, suffix) = if lower.contains('.') {
        (lower.as_str(), Suffix::None)
    } else if let Some(body) = lower
        .strip_suffix("ul")
        .or_else(|| lower.strip_suffix("lu"))
    {
        (body, Suffix::UL)
    } else if let Some(body) = lower.strip_suffix('u') {
        (body, Suffix::U)
    } else if let Some(body) = lower.strip_suffix('l') {
        (body, Suffix::L)
    } else {
        (lower.as_str(), Suffix::None)
    };
    let int = |v: i128| Tok::Int(v, suffix);
    if let Some(hex) = lower.strip_prefix("0x") {
        if hex.is_empty() || hex.len() > 16 {
            return bad();
        }
        return i128::from_str_radix(hex, 16).map_or_else(|_| bad(), int);
    }
    if let Some((int, frac)) = word.split_once('.') {
        if int.is_empty()
            || !int.chars().all(|c| c.is_ascii_digit())
            || !frac.chars().all(|c| c.is_ascii_digit())
            || frac.len() > MAX_FIXED_DIGITS
            || int.len() > 12
        {
            return bad();
        }
        let scale = 10i128.pow(frac.len() as u32);
        let whole: i128 = int.parse().unwrap_or(0);
        let part: i128 = if frac.is_empty() {
            0
        } else {
            frac.parse().unwrap_or(0)
        };
        // Too large for i128 is far outside the fixed range: keep a value the range check refuses.
        let Some(num) = whole
            .checked_mul(scale)
            .and_then(|x| x.checked_add(part))
            .and_then(|x| x.checked_mul(65536))
        else {
            return Tok::Fixed(i128::MAX);
        };
        let (q, r) = (num / scale, num % scale);
        let raw = if 2 * r >= scale { q + 1 } else { q };
        return Tok::Fixed(raw);
    }
    if lower.is_empty() || lower.len() > 20 || !lower.chars().all(|c| c.is_ascii_digit()) {
        return bad();
    }
    lower.parse().map_or_else(|_| bad(), int)
}
