//! Rows of bits as the panels draw them (the Product panels of SilverLode and TML): a value's
//! bits with the binary point and which of them a result keeps.

/// One row of bits: `value`'s low `width` bits, most significant first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BitRow {
    pub label: String,
    pub value: u64,
    pub width: u8,
    /// Bits below this many are the fraction (the binary point is drawn left of bit `point-1`).
    pub point: Option<u8>,
    pub keep: Keep,
}

/// Which bits of a row end up in the result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keep {
    /// An operand: shown whole.
    Operand,
    /// Bits high..=low are stored, highlighted; the rest are lost, greyed.
    Bits(u8, u8),
    /// Computed and thrown away (the quotient of a MOD, the remainder of a DIV).
    Nothing,
}

impl Keep {
    /// Whether `bit` of the row is stored.
    pub fn keeps(self, bit: u8) -> bool {
        match self {
            Keep::Operand => true,
            Keep::Bits(high, low) => (low..=high).contains(&bit),
            Keep::Nothing => false,
        }
    }
}

/// What one arithmetic command does to the bits, for a Product panel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Breakdown {
    /// The command's 1-based source line.
    pub line: usize,
    /// The command as the panel names it (`CLD MULT_S64_SHR16, R21, R20, 1665`).
    pub command: String,
    pub rows: Vec<BitRow>,
    /// What is kept and lost, in words.
    pub notes: Vec<String>,
    /// The real-number arithmetic and the error of what is stored.
    pub real: Option<String>,
}

// The numbers of the panels' real-number lines: text for people, so floating point is fine.

/// A decimal for people: up to `places` decimals, trailing zeros dropped.
pub fn decimal(value: f64, places: usize) -> String {
    let text = format!("{value:.places$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// `stored` against `exact`, relative: `−0.023 %`.
pub fn relative_error(stored: f64, exact: f64) -> String {
    if exact == 0.0 {
        return if stored == 0.0 {
            "0 %".into()
        } else {
            "∞ %".into()
        };
    }
    let percent = (stored - exact) / exact.abs() * 100.0;
    let text = format!("{percent:+.3} %").replace('-', "−");
    if text == "+0.000 %" || text == "−0.000 %" {
        "0 %".to_string()
    } else {
        text
    }
}
