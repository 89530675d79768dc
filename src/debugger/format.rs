//! Register values as people read and type them.

use serde::{Deserialize, Serialize};

use crate::machine::silverlode::assembler::{parse_number, parse_q16};

/// How a register value is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum Format {
    #[default]
    Signed,
    Unsigned,
    Hex,
    Binary,
    /// Q16.16 fixed point.
    Q16,
}

impl Format {
    pub const ALL: [Format; 5] = [
        Format::Signed,
        Format::Unsigned,
        Format::Hex,
        Format::Binary,
        Format::Q16,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Format::Signed => "signed",
            Format::Unsigned => "unsigned",
            Format::Hex => "hex",
            Format::Binary => "binary",
            Format::Q16 => "Q16.16",
        }
    }

    pub fn show(self, value: u32) -> String {
        match self {
            Format::Signed => (value as i32).to_string(),
            Format::Unsigned => value.to_string(),
            Format::Hex => hex(value),
            Format::Binary => binary(value),
            Format::Q16 => q16(value),
        }
    }
}

/// `0x0000_ABCD`: the 16-bit halves separated, as the vendor's texts group them.
pub fn hex(value: u32) -> String {
    format!("0x{:04X}_{:04X}", value >> 16, value & 0xFFFF)
}

/// 32 bits in nibbles, words separated by a wider gap.
pub fn binary(value: u32) -> String {
    let mut out = String::with_capacity(40);
    for nibble in (0..8).rev() {
        let bits = value >> (nibble * 4) & 0xF;
        out.push_str(&format!("{bits:04b}"));
        if nibble == 4 {
            out.push_str("  ");
        } else if nibble > 0 {
            out.push(' ');
        }
    }
    out
}

/// The value read as signed Q16.16, exact to the 16 fractional bits it has.
pub fn q16(value: u32) -> String {
    let v = f64::from(value as i32) / 65536.0;
    // 1/65536 needs up to 16 decimals to be exact; 6 is what a person reads.
    let text = format!("{v:.6}");
    let trimmed = text.trim_end_matches('0').trim_end_matches('.');
    if trimmed.is_empty() || trimmed == "-" {
        "0".to_string()
    } else {
        trimmed.to_string()
    }
}

/// A value typed by a user: decimal (signed or unsigned), `0x…`, `0b…`, `_` separators, or
/// `q16(…)`. The result is the 32-bit pattern to store.
pub fn parse_value(text: &str) -> Result<u32, String> {
    let text = text.trim();
    if text.is_empty() {
        return Err("type a value: 42, -7, 0x2A, 0b101010 or q16(1.5)".to_string());
    }
    let lower = text.to_ascii_lowercase();
    let value = if let Some(inner) = lower
        .strip_prefix("q16(")
        .and_then(|rest| rest.strip_suffix(')'))
    {
        parse_q16(inner)?
    } else {
        parse_number(text)?
    };
    if !(-(1i64 << 31)..=i64::from(u32::MAX)).contains(&value) {
        return Err(format!(
            "{text} does not fit in 32 bits (-2147483648 ..= 4294967295)"
        ));
    }
    Ok(value as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats() {
        assert_eq!(Format::Signed.show(0xFFFF_FFF1), "-15");
        assert_eq!(Format::Unsigned.show(0xFFFF_FFF1), "4294967281");
        assert_eq!(Format::Hex.show(0xABCD_893F), "0xABCD_893F");
        assert_eq!(
            Format::Binary.show(0xABCD_893F),
            "1010 1011 1100 1101  1000 1001 0011 1111"
        );
        assert_eq!(Format::Q16.show(98304), "1.5");
        assert_eq!(Format::Q16.show(16668865), "254.346695");
        assert_eq!(Format::Q16.show((-65536i32) as u32), "-1");
        assert_eq!(Format::Q16.show(0), "0");
    }

    #[test]
    fn parses_what_people_type() {
        assert_eq!(parse_value("42"), Ok(42));
        assert_eq!(parse_value(" -7 "), Ok((-7i32) as u32));
        assert_eq!(parse_value("0x2A"), Ok(42));
        assert_eq!(parse_value("0b101010"), Ok(42));
        assert_eq!(parse_value("4294967295"), Ok(u32::MAX));
        assert_eq!(parse_value("q16(1.5)"), Ok(98304));
        assert_eq!(parse_value("Q16(-1)"), Ok((-65536i32) as u32));
        assert!(parse_value("").is_err());
        assert!(parse_value("4294967296").is_err());
        assert!(parse_value("12abc").is_err());
        assert!(parse_value("q16(x)").is_err());
    }
}
