//! OpenNet's memory map (spec §2): the spaces a location lives in and the names users type.

use super::program::{Area, BOXES, Bit, SPECIAL};
use crate::machine::Loc;

pub const D: u8 = 0;
pub const I: u8 = 1;
pub const Q: u8 = 2;
pub const M: u8 = 3;
pub const SPECIAL_SPACE: u8 = 4;
pub const R: u8 = 5;
/// Timer outputs, current values, presets; the same for counters.
pub const T: u8 = 6;
pub const T_CURRENT: u8 = 7;
pub const T_PRESET: u8 = 8;
pub const C: u8 = 9;
pub const C_CURRENT: u8 = 10;
pub const C_PRESET: u8 = 11;
/// RLO (0) and MC (1).
pub const LOGIC: u8 = 12;

pub(super) const SPECIAL_DESCRIPTIONS: [&str; 7] = [
    "carry (ADD) or borrow (SUB), last bit shifted out (SFTL/SFTR)",
    "user program execution error (latched)",
    "initialize pulse: on in scan 0",
    "1-s clock: on while t mod 1000 ms < 500",
    "100-ms clock: on while t mod 100 ms < 50",
    "10-ms clock: on while t mod 10 ms < 5",
    "in operation: on in every scan",
];

pub(super) fn area_of(space: u8) -> Option<Area> {
    match space {
        I => Some(Area::I),
        Q => Some(Area::Q),
        M => Some(Area::M),
        R => Some(Area::R),
        _ => None,
    }
}

pub fn area_space(area: Area) -> u8 {
    match area {
        Area::I => I,
        Area::Q => Q,
        Area::M => M,
        Area::R => R,
    }
}

pub fn bit_loc(b: Bit) -> Loc {
    match b {
        Bit::Point(area, i) => Loc::new(area_space(area), i),
        Bit::Special(s) => Loc::new(SPECIAL_SPACE, u32::from(s)),
        Bit::Timer(n) => Loc::new(T, n),
        Bit::Counter(n) => Loc::new(C, n),
    }
}

/// `D12`, `I17`, `M8003`, `R7`, `T3`, `T3.current`, `C0.preset`, `MC` → its location.
pub fn parse_name(name: &str) -> Option<Loc> {
    let name = name.trim();
    if name.eq_ignore_ascii_case("MC") {
        return Some(Loc::new(LOGIC, 1));
    }
    if name.eq_ignore_ascii_case("RLO") {
        return Some(Loc::new(LOGIC, 0));
    }
    let (name, field) = match name.split_once('.') {
        Some((n, f)) => (n, Some(f.to_ascii_lowercase())),
        None => (name, None),
    };
    let mut chars = name.chars();
    let letter = chars.next()?.to_ascii_uppercase();
    let digits = chars.as_str();
    if digits.is_empty() || digits.len() > 6 || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let n: u32 = digits.parse().ok()?;
    if let Some(field) = field {
        let space = match (letter, field.as_str()) {
            ('T', "current") => T_CURRENT,
            ('T', "preset") => T_PRESET,
            ('C', "current") => C_CURRENT,
            ('C', "preset") => C_PRESET,
            _ => return None,
        };
        return (n < BOXES).then(|| Loc::new(space, n));
    }
    match letter {
        'D' if n < super::REGISTERS as u32 => Some(Loc::new(D, n)),
        'T' if n < BOXES => Some(Loc::new(T, n)),
        'C' if n < BOXES => Some(Loc::new(C, n)),
        'R' if n < Area::R.points() => Some(Loc::new(R, n)),
        'M' if n >= 8000 => SPECIAL
            .iter()
            .position(|&s| u32::from(s) == n)
            .map(|i| Loc::new(SPECIAL_SPACE, i as u32)),
        'I' | 'Q' | 'M' => {
            let area = match letter {
                'I' => Area::I,
                'Q' => Area::Q,
                _ => Area::M,
            };
            if n % 10 >= 8 {
                return None;
            }
            let index = n / 10 * 8 + n % 10;
            (index < area.points()).then(|| Loc::new(area_space(area), index))
        }
        _ => None,
    }
}
