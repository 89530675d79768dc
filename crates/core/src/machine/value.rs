//! Values as people read and type them, for locations of any width from 1 to 64 bits.

use serde::{Deserialize, Serialize};

/// Why typed text is not a value.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ValueError {
    #[error("type a value: 42, -7, 0x2A, 0b101010, bcd(1234) or q16(1.5)")]
    Empty,
    #[error("'{0}' is not a number")]
    NotANumber(String),
    #[error("{0} does not fit in 64 bits")]
    Over64Bits(String),
    #[error("{text} does not fit in {width} bits ({min} ..= {max})")]
    TooWide {
        text: String,
        width: u8,
        min: i128,
        max: i128,
    },
    #[error("q16({0}) needs a decimal number, like q16(254.3467)")]
    BadQ16(String),
    #[error("q16({0}) has too many digits (at most 30)")]
    Q16TooLong(String),
    #[error(
        "q16({0}) does not fit Q16.16's range, -32768 to 32767.9999847 (65536 × the value must fit a signed 32-bit register)"
    )]
    Q16TooBig(String),
    #[error("bcd({0}) needs 1 to 16 decimal digits, like bcd(1234)")]
    BadBcd(String),
    #[error("'{text}' is not a number in {format}")]
    NotIn { text: String, format: &'static str },
}

/// How a value is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum Format {
    #[default]
    Signed,
    Unsigned,
    Hex,
    Binary,
    Octal,
    /// Binary-coded decimal: one decimal digit per nibble.
    Bcd,
    /// Q16.16 fixed point (signed, 16 fractional bits).
    Q16,
}

impl Format {
    pub const ALL: [Format; 7] = [
        Format::Signed,
        Format::Unsigned,
        Format::Hex,
        Format::Binary,
        Format::Octal,
        Format::Bcd,
        Format::Q16,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Format::Signed => "signed",
            Format::Unsigned => "unsigned",
            Format::Hex => "hex",
            Format::Binary => "binary",
            Format::Octal => "octal",
            Format::Bcd => "BCD",
            Format::Q16 => "Q16.16",
        }
    }

    /// `value` (the raw bits of a `width`-bit location) in this format.
    pub fn show(self, value: u64, width: u8) -> String {
        let value = value & mask(width);
        match self {
            Format::Signed => sign_extend(value, width).to_string(),
            Format::Unsigned => value.to_string(),
            Format::Hex => hex(value, width),
            Format::Binary => binary(value, width),
            Format::Octal => format!("0o{value:o}"),
            Format::Bcd => bcd(value),
            Format::Q16 => q16(sign_extend(value, width)),
        }
    }
}

/// All ones in the low `width` bits.
pub fn mask(width: u8) -> u64 {
    match width {
        0 => 0,
        1..=63 => (1u64 << width) - 1,
        _ => u64::MAX,
    }
}

/// The low `width` bits read as two's complement.
pub fn sign_extend(value: u64, width: u8) -> i64 {
    let width = u32::from(width.clamp(1, 64));
    let shift = 64 - width;
    ((value << shift) as i64) >> shift
}

/// Hex digits for the width, grouped by 16-bit words: `0x0000_ABCD`, `0x12`.
pub fn hex(value: u64, width: u8) -> String {
    let digits = usize::from(width.clamp(1, 64)).div_ceil(4);
    let text = format!("{value:0digits$X}");
    format!("0x{}", group_from_right(&text, 4, "_"))
}

/// Bits in nibbles, 16-bit words separated by a wider gap.
pub fn binary(value: u64, width: u8) -> String {
    let width = usize::from(width.clamp(1, 64));
    let text = format!("{value:0width$b}");
    let words: Vec<String> = chunks_from_right(&text, 16)
        .into_iter()
        .map(|w| group_from_right(&w, 4, " "))
        .collect();
    words.join("  ")
}

/// The nibbles as decimal digits; a nibble over 9 is shown in hex and the value marked.
pub fn bcd(value: u64) -> String {
    let text = format!("{value:X}");
    if text.chars().all(|c| c.is_ascii_digit()) {
        text
    } else {
        format!("{text} (not BCD)")
    }
}

/// The value read as signed Q16.16, to the six decimals a person reads.
pub fn q16(value: i64) -> String {
    let v = value as f64 / 65536.0;
    let text = format!("{v:.6}");
    let trimmed = text.trim_end_matches('0').trim_end_matches('.');
    if trimmed.is_empty() || trimmed == "-" || trimmed == "-0" {
        "0".to_string()
    } else {
        trimmed.to_string()
    }
}

/// The value read as signed Q16.16, exactly: every digit of raw / 65536 (at most 16 after
/// the point), e.g. 1747626 → `26.6667022705078125`.
pub fn q16_exact(value: i64) -> String {
    let negative = value < 0;
    let magnitude = value.unsigned_abs();
    let whole = magnitude >> 16;
    // 10^16 / 2^16 = 5^16: the fraction in sixteen decimal digits, exactly.
    let fraction = u128::from(magnitude & 0xFFFF) * 5u128.pow(16);
    let sign = if negative { "-" } else { "" };
    if fraction == 0 {
        return format!("{sign}{whole}");
    }
    let digits = format!("{fraction:016}");
    format!("{sign}{whole}.{}", digits.trim_end_matches('0'))
}

/// What a decimal number typed as Q16.16 (`q16(0.00001)`, a TML fixed literal) really stores:
/// the raw pattern, the value that pattern stands for, and the quantization error.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Quantized {
    pub raw: i64,
    /// raw / 65536, every digit.
    pub stands_for: String,
    /// stored − typed, every digit, signed (`+0.0000052587890625`).
    pub error: String,
    /// The error relative to the typed value, to two decimals (`+52.59 %`); `None` for 0.
    pub relative: Option<String>,
}

/// Quantize `text` (a decimal number, optional sign) to Q16.16 as the assemblers do (round
/// half away from zero, exactly from the digits).
pub fn quantize_q16(text: &str) -> Result<Quantized, ValueError> {
    let raw = parse_q16(text)?;
    let body = text.trim().trim_start_matches(['+', '-']);
    let negative = text.trim().starts_with('-');
    let (int_part, frac_part) = body.split_once('.').unwrap_or((body, ""));
    let digits: String = format!("{int_part}{frac_part}")
        .chars()
        .filter(|&c| c != '_')
        .collect();
    let frac_len = frac_part.chars().filter(|&c| c != '_').count() as u32;
    let mantissa: i128 = digits.parse::<i128>().unwrap_or(0) * if negative { -1 } else { 1 };
    // stored − typed = (raw × 10^k − mantissa × 2^16) / (10^k × 2^16); × 5^16 makes the
    // denominator 10^(k+16), so the difference is a finite decimal.
    let scale = 10i128.pow(frac_len);
    let exact = i128::from(raw)
        .checked_mul(scale)
        .and_then(|a| a.checked_sub(mantissa.checked_mul(65536)?))
        .and_then(|d| d.checked_mul(5i128.pow(16)));
    let error = match exact {
        Some(0) => "0".to_string(),
        Some(num) => {
            let places = (frac_len + 16) as usize;
            let digits = format!("{:0>width$}", num.unsigned_abs(), width = places + 1);
            let (whole, fraction) = digits.split_at(digits.len() - places);
            let sign = if num < 0 { "-" } else { "+" };
            let fraction = fraction.trim_end_matches('0');
            if fraction.is_empty() {
                format!("{sign}{whole}")
            } else {
                format!("{sign}{whole}.{fraction}")
            }
        }
        None => "(too many digits to show)".to_string(),
    };
    // A ratio for people to read, not a stored value: floating point is fine here.
    let typed = mantissa as f64 / scale as f64;
    let relative = (typed != 0.0).then(|| {
        let percent = (raw as f64 / 65536.0 - typed) / typed.abs() * 100.0;
        format!("{percent:+.2} %")
    });
    Ok(Quantized {
        raw,
        stands_for: q16_exact(raw),
        error,
        relative,
    })
}

fn chunks_from_right(text: &str, size: usize) -> Vec<String> {
    let chars: Vec<char> = text.chars().collect();
    let first = chars.len() % size;
    let mut out = Vec::new();
    if first > 0 {
        out.push(chars[..first].iter().collect());
    }
    out.extend(chars[first..].chunks(size).map(|c| c.iter().collect()));
    out
}

fn group_from_right(text: &str, size: usize, separator: &str) -> String {
    chunks_from_right(text, size).join(separator)
}

/// `1234567` as `1,234,567`.
pub fn group_thousands(n: u64) -> String {
    group_from_right(&n.to_string(), 3, ",")
}

/// `round(x × 65536)`, ties away from zero, computed exactly from the decimal text; the result
/// must fit a signed 32-bit word.
pub fn parse_q16(inner: &str) -> Result<i64, ValueError> {
    let text = inner.trim();
    let malformed = || ValueError::BadQ16(text.to_string());
    let (negative, body) = match text.as_bytes().first() {
        Some(b'-') => (true, &text[1..]),
        Some(b'+') => (false, &text[1..]),
        _ => (false, text),
    };
    let (int_part, frac_part) = body.split_once('.').unwrap_or((body, ""));
    let int_digits: String = int_part.chars().filter(|&c| c != '_').collect();
    let frac_digits: String = frac_part.chars().filter(|&c| c != '_').collect();
    if int_digits.is_empty() && frac_digits.is_empty()
        || !int_digits.chars().all(|c| c.is_ascii_digit())
        || !frac_digits.chars().all(|c| c.is_ascii_digit())
    {
        return Err(malformed());
    }
    let significant = int_digits.trim_start_matches('0').len() + frac_digits.len();
    if significant > 30 {
        return Err(ValueError::Q16TooLong(text.to_string()));
    }
    let mantissa: u128 = format!("{int_digits}{frac_digits}")
        .parse::<u128>()
        .unwrap_or(0);
    let scale = 10u128.pow(frac_digits.len() as u32);
    let scaled = mantissa * 65536;
    let mut q = scaled / scale;
    if (scaled % scale) * 2 >= scale {
        q += 1;
    }
    let value = if negative { -(q as i128) } else { q as i128 };
    if !(i128::from(i32::MIN)..=i128::from(i32::MAX)).contains(&value) {
        return Err(ValueError::Q16TooBig(text.to_string()));
    }
    Ok(value as i64)
}

/// An integer as typed: optional sign, decimal, `0x`, `0b` or `0o`, `_` separators.
pub fn parse_integer(text: &str) -> Result<i128, ValueError> {
    let malformed = || ValueError::NotANumber(text.to_string());
    let (negative, body) = match text.as_bytes().first() {
        Some(b'-') => (true, &text[1..]),
        Some(b'+') => (false, &text[1..]),
        _ => (false, text),
    };
    let lower = body.to_ascii_lowercase();
    let (radix, digits) = if let Some(d) = lower.strip_prefix("0x") {
        (16, d)
    } else if let Some(d) = lower.strip_prefix("0b") {
        (2, d)
    } else if let Some(d) = lower.strip_prefix("0o") {
        (8, d)
    } else {
        (10, lower.as_str())
    };
    if !digits.chars().any(|c| c.is_digit(radix)) {
        return Err(malformed());
    }
    let mut value: i128 = 0;
    for c in digits.chars() {
        if c == '_' {
            continue;
        }
        let d = c.to_digit(radix).ok_or_else(malformed)?;
        value = value * i128::from(radix) + i128::from(d);
        if value > i128::from(u64::MAX) {
            return Err(ValueError::Over64Bits(text.to_string()));
        }
    }
    Ok(if negative { -value } else { value })
}

/// A value typed by a user for a `width`-bit location: decimal (signed or unsigned), `0x…`,
/// `0b…`, `0o…`, `_` separators, `q16(…)` or `bcd(…)`. The result is the bit pattern to store.
pub fn parse_value(text: &str, width: u8) -> Result<u64, ValueError> {
    let text = text.trim();
    if text.is_empty() {
        return Err(ValueError::Empty);
    }
    let lower = text.to_ascii_lowercase();
    let call = |name: &str| {
        lower
            .strip_prefix(name)
            .and_then(|rest| rest.strip_prefix('('))
            .and_then(|rest| rest.strip_suffix(')'))
            .map(str::trim)
    };
    let value: i128 = if let Some(inner) = call("q16") {
        i128::from(parse_q16(inner)?)
    } else if let Some(inner) = call("bcd") {
        parse_bcd(inner)?
    } else {
        parse_integer(text)?
    };
    let width = width.clamp(1, 64);
    let min = -(1i128 << (width - 1));
    let max = (1i128 << width) - 1;
    if !(min..=max).contains(&value) {
        return Err(ValueError::TooWide {
            text: text.to_string(),
            width,
            min,
            max,
        });
    }
    Ok((value as u64) & mask(width))
}

/// How a typed value was read: in the field's format, or in the form the text itself names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reading {
    pub format: Format,
    /// The text named its form (`0x…`, `0b…`, `0o…`, `bcd(…)`, `q16(…)`).
    pub written: bool,
}

impl Reading {
    /// "read as BCD (the field's format)", "read as hex (written 0x…)".
    pub fn describe(self) -> String {
        let name = match self.format {
            Format::Signed | Format::Unsigned => "decimal",
            f => f.name(),
        };
        if self.written {
            let form = match self.format {
                Format::Hex => "0x…",
                Format::Binary => "0b…",
                Format::Octal => "0o…",
                Format::Bcd => "bcd(…)",
                Format::Q16 => "q16(…)",
                Format::Signed | Format::Unsigned => "a decimal number",
            };
            format!("read as {name} (written {form})")
        } else {
            format!("read as {name} (the field's format)")
        }
    }
}

/// A value typed in a field that shows `format`: plain digits are read in that format (`1234`
/// in a BCD field is 0x1234, `1A` in a hex field is 26, `1.5` in a Q16.16 field is 98304);
/// text that names its form (`0x…`, `0b…`, `0o…`, `bcd(…)`, `q16(…)`) is read as written.
pub fn parse_in(text: &str, width: u8, format: Format) -> Result<(u64, Reading), ValueError> {
    let trimmed = text.trim();
    let lower = trimmed.to_ascii_lowercase();
    let unsigned = lower.trim_start_matches(['-', '+']);
    let named = [
        ("0x", Format::Hex),
        ("0b", Format::Binary),
        ("0o", Format::Octal),
    ]
    .into_iter()
    .find(|(prefix, _)| unsigned.starts_with(prefix))
    .map(|(_, f)| f)
    .or_else(|| {
        [("bcd(", Format::Bcd), ("q16(", Format::Q16)]
            .into_iter()
            .find(|(prefix, _)| lower.starts_with(prefix))
            .map(|(_, f)| f)
    });
    if let Some(written) = named {
        let reading = Reading {
            format: written,
            written: true,
        };
        return parse_value(trimmed, width).map(|v| (v, reading));
    }
    let reading = Reading {
        format,
        written: false,
    };
    if trimmed.is_empty() {
        return Err(ValueError::Empty);
    }
    // Spaces group digits in the binary and hex readings (`0000 0101`), as they are shown.
    let digits: String = trimmed.chars().filter(|c| !c.is_whitespace()).collect();
    let as_text = match format {
        Format::Signed | Format::Unsigned => trimmed.to_string(),
        Format::Hex => format!("0x{digits}"),
        Format::Binary => format!("0b{digits}"),
        Format::Octal => format!("0o{digits}"),
        Format::Bcd => format!("bcd({digits})"),
        Format::Q16 => format!("q16({trimmed})"),
    };
    match parse_value(&as_text, width) {
        Ok(v) => Ok((v, reading)),
        // Report the text as the user typed it, not as rewritten here.
        Err(ValueError::NotANumber(_) | ValueError::BadBcd(_) | ValueError::BadQ16(_)) => {
            Err(ValueError::NotIn {
                text: trimmed.to_string(),
                format: format.name(),
            })
        }
        Err(ValueError::Q16TooLong(_)) => Err(ValueError::Q16TooLong(trimmed.to_string())),
        Err(ValueError::Q16TooBig(_)) => Err(ValueError::Q16TooBig(trimmed.to_string())),
        Err(ValueError::TooWide {
            width, min, max, ..
        }) => Err(ValueError::TooWide {
            text: trimmed.to_string(),
            width,
            min,
            max,
        }),
        Err(e) => Err(e),
    }
}

/// What an explanation adds when a stored result is not the exact one: `""` when it is, else
/// `" — overflow: the exact result 2147483648 does not fit, it wrapped to -2147483648"`.
pub fn wrap_note(exact: i128, stored: i64) -> String {
    if exact == i128::from(stored) {
        String::new()
    } else {
        format!(" — overflow: the exact result {exact} does not fit, it wrapped to {stored}")
    }
}

/// `" — remainder 3 discarded"` when a division was not exact.
pub fn remainder_note(remainder: i128) -> String {
    if remainder == 0 {
        String::new()
    } else {
        format!(" — remainder {remainder} discarded")
    }
}

/// The decimal number BCD digits stand for (`0x9750` → 9750); a nibble over 9 counts as its
/// value, so a non-BCD pattern still orders sensibly (callers mark it with [`is_bcd`]).
pub fn bcd_decimal(value: u64) -> u64 {
    let mut out: u64 = 0;
    for nibble in (0..16).rev() {
        out = out
            .wrapping_mul(10)
            .wrapping_add(value >> (nibble * 4) & 0xF);
    }
    out
}

/// Every nibble of `value` is a decimal digit.
pub fn is_bcd(value: u64) -> bool {
    (0..16).all(|n| value >> (n * 4) & 0xF <= 9)
}

/// `bcd(1234)` = 0x1234: decimal digits as nibbles.
fn parse_bcd(digits: &str) -> Result<i128, ValueError> {
    let digits: String = digits.chars().filter(|&c| c != '_').collect();
    if digits.is_empty() || digits.len() > 16 || !digits.chars().all(|c| c.is_ascii_digit()) {
        return Err(ValueError::BadBcd(digits));
    }
    i128::from_str_radix(&digits, 16).map_err(|_| ValueError::BadBcd(digits))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_at_32_bits_read_as_before() {
        let w = 32;
        assert_eq!(Format::Signed.show(0xFFFF_FFF1, w), "-15");
        assert_eq!(Format::Unsigned.show(0xFFFF_FFF1, w), "4294967281");
        assert_eq!(Format::Hex.show(0xABCD_893F, w), "0xABCD_893F");
        assert_eq!(
            Format::Binary.show(0xABCD_893F, w),
            "1010 1011 1100 1101  1000 1001 0011 1111"
        );
        assert_eq!(Format::Q16.show(98304, w), "1.5");
        assert_eq!(Format::Q16.show(16668865, w), "254.346695");
        assert_eq!(Format::Q16.show((-65536i32) as u32 as u64, w), "-1");
        assert_eq!(Format::Q16.show(0, w), "0");
    }

    #[test]
    fn formats_follow_the_width() {
        assert_eq!(Format::Signed.show(0xFFFF, 16), "-1");
        assert_eq!(Format::Unsigned.show(0xFFFF, 16), "65535");
        assert_eq!(Format::Hex.show(0x1234, 16), "0x1234");
        assert_eq!(Format::Hex.show(0x8000_0000_0000, 48), "0x8000_0000_0000");
        assert_eq!(
            Format::Signed.show(0x8000_0000_0000, 48),
            "-140737488355328"
        );
        assert_eq!(Format::Binary.show(5, 4), "0101");
        assert_eq!(Format::Binary.show(1, 1), "1");
        assert_eq!(Format::Octal.show(0o1400, 16), "0o1400");
        assert_eq!(Format::Bcd.show(0x0017_2056, 32), "172056");
        assert_eq!(Format::Bcd.show(0x12A4, 16), "12A4 (not BCD)");
        assert_eq!(Format::Bcd.show(0x28D, 32), "28D (not BCD)");
        assert_eq!(Format::Bcd.show(0, 16), "0");
        assert_eq!(Format::Signed.show(u64::MAX, 64), "-1");
    }

    #[test]
    fn parses_what_people_type() {
        assert_eq!(parse_value("42", 32), Ok(42));
        assert_eq!(parse_value(" -7 ", 32), Ok(0xFFFF_FFF9));
        assert_eq!(parse_value("-7", 16), Ok(0xFFF9));
        assert_eq!(parse_value("0x2A", 32), Ok(42));
        assert_eq!(parse_value("0b101010", 32), Ok(42));
        assert_eq!(parse_value("0o1400", 16), Ok(0o1400));
        assert_eq!(parse_value("4294967295", 32), Ok(u64::from(u32::MAX)));
        assert_eq!(parse_value("q16(1.5)", 32), Ok(98304));
        assert_eq!(parse_value("Q16(-1)", 32), Ok(0xFFFF_0000));
        assert_eq!(parse_value("bcd(2056)", 16), Ok(0x2056));
        assert_eq!(parse_value("1", 1), Ok(1));
        assert!(parse_value("2", 1).is_err());
        assert!(parse_value("65536", 16).is_err());
        assert!(parse_value("", 32).is_err());
        assert!(parse_value("4294967296", 32).is_err());
        assert!(parse_value("12abc", 32).is_err());
        assert!(parse_value("q16(x)", 32).is_err());
        assert!(parse_value("bcd(12a)", 16).is_err());
        assert_eq!(parse_value("-1", 64), Ok(u64::MAX));
        assert!(parse_value("0x1_0000_0000_0000_0000", 64).is_err());
    }

    #[test]
    fn q16_is_exact_from_decimal_text() {
        // The vendor's worked value.
        assert_eq!(parse_q16("254.3467"), Ok(16668865));
        assert_eq!(parse_q16("1"), Ok(65536));
        assert_eq!(parse_q16("-1.5"), Ok(-98304));
        // 1/131072 is exactly half a unit: ties go away from zero.
        assert_eq!(parse_q16("0.00000762939453125"), Ok(1));
        assert_eq!(parse_q16("-0.00000762939453125"), Ok(-1));
        assert!(parse_q16("32768").is_err());
        assert_eq!(parse_q16("-32768"), Ok(i64::from(i32::MIN)));
        assert!(parse_q16("abc").is_err());
        assert!(parse_q16("").is_err());
    }
}
