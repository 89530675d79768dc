//! DL205's memory map (spec §3): the spaces a location lives in, their numbering (octal
//! names, V-memory, the bit-mapped words) and the names users type.

use super::program::{Bit, Kind, MAPPED, SPECIAL, mapped};
use super::{LEVELS, V_WORDS};
use crate::machine::{BitInfo, Loc};

pub const ACC: u8 = 0;
pub const V: u8 = 1;
pub const X: u8 = 2;
pub const Y: u8 = 3;
pub const C: u8 = 4;
pub const SP: u8 = 5;
pub const S: u8 = 6;
pub const T: u8 = 7;
pub const CT: u8 = 8;
/// The bit-mapped words V40400–V41237, numbered densely (the regions have gaps between them).
pub const VM: u8 = 9;

pub(super) const SP_DESCRIPTIONS: [&str; 20] = [
    "on during the first scan",
    "always on",
    "always off",
    "1-minute clock (on in the second half)",
    "1-second clock (on in the second half)",
    "100 ms clock (on in the second half)",
    "50 ms clock (on in the second half)",
    "on in odd scans",
    "divide by zero; table address out of range",
    "CMP: accumulator less than the operand",
    "CMP: accumulator equal to the operand",
    "CMP: accumulator greater than the operand",
    "the result is zero",
    "borrow out of the low word",
    "borrow out of the 32-bit value",
    "carry out of the low word",
    "carry out of the 32-bit value",
    "bit 31 of ACC (negative)",
    "signed overflow of a binary add",
    "a BCD instruction met a non-BCD digit",
];

pub(super) const NO_BITS: &[BitInfo] = &[];

pub fn kind_space(kind: Kind) -> u8 {
    match kind {
        Kind::X => X,
        Kind::Y => Y,
        Kind::C => C,
        Kind::Sp => SP,
        Kind::S => S,
        Kind::T => T,
        Kind::Ct => CT,
    }
}

pub fn bit_loc(b: Bit) -> Loc {
    Loc::new(kind_space(b.kind), b.n)
}

/// The location of V address `a`: a data word, or a bit-mapped word in [`VM`].
pub fn v_loc(a: u32) -> Loc {
    if (a as usize) < V_WORDS {
        return Loc::new(V, a);
    }
    let mut dense = 0;
    for &(first, last, ..) in &MAPPED {
        if (first..=last).contains(&a) {
            return Loc::new(VM, dense + a - first);
        }
        dense += last - first + 1;
    }
    // Not an address (the assembler lets none through): a location that does not exist.
    Loc::new(VM, u32::MAX)
}

/// The V address of bit-mapped word `i` of [`VM`].
pub fn mapped_address(i: u32) -> Option<u32> {
    let mut dense = 0;
    for &(first, last, ..) in &MAPPED {
        let len = last - first + 1;
        if i < dense + len {
            return Some(first + i - dense);
        }
        dense += len;
    }
    None
}

pub(super) const MAPPED_WORDS: u32 = {
    let mut n = 0;
    let mut i = 0;
    while i < MAPPED.len() {
        n += MAPPED[i].1 - MAPPED[i].0 + 1;
        i += 1;
    }
    n
};

/// A V word an instruction wrote, and for a bit-mapped word its sixteen elements too.
pub fn word_writes(a: u32, f: &mut impl FnMut(Loc)) {
    f(v_loc(a));
    if let Some((kind, first)) = mapped(a)
        && kind != Kind::Sp
    {
        (first..first + 16).for_each(|n| f(Loc::new(kind_space(kind), n)));
    }
}

/// `V1400`, `X17`, `SP53`, `ACC`, `L3` → its location.
pub fn parse_name(name: &str) -> Option<Loc> {
    let upper = name.trim().to_ascii_uppercase();
    if upper == "ACC" {
        return Some(Loc::new(ACC, 0));
    }
    let letters: String = upper
        .chars()
        .take_while(|c| c.is_ascii_alphabetic())
        .collect();
    let digits = &upper[letters.len()..];
    if digits.is_empty() || digits.len() > 7 || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    if letters == "L" {
        let n: u32 = digits.parse().ok()?;
        return (1..=LEVELS as u32).contains(&n).then(|| Loc::new(ACC, n));
    }
    let n = u32::from_str_radix(digits, 8).ok()?;
    if let Some(&(first, last, ..)) = MAPPED.iter().find(|m| m.3 == letters) {
        let a = first + n / 16;
        return (n % 0o20 == 0 && a <= last).then_some(v_loc(a));
    }
    match letters.as_str() {
        "V" if (n as usize) < V_WORDS || mapped(n).is_some() => Some(v_loc(n)),
        "X" if n < Kind::X.count() => Some(Loc::new(X, n)),
        "Y" if n < Kind::Y.count() => Some(Loc::new(Y, n)),
        "C" if n < Kind::C.count() => Some(Loc::new(C, n)),
        "S" if n < Kind::S.count() => Some(Loc::new(S, n)),
        "T" if n < Kind::T.count() => Some(Loc::new(T, n)),
        "CT" if n < Kind::Ct.count() => Some(Loc::new(CT, n)),
        "TA" if n < Kind::T.count() => Some(Loc::new(V, n)),
        "CTA" if n < Kind::Ct.count() => Some(Loc::new(V, 0o1000 + n)),
        "SP" => SPECIAL
            .iter()
            .position(|&s| s == n)
            .map(|i| Loc::new(SP, i as u32)),
        _ => None,
    }
}
