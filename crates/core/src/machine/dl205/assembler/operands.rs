//! Operands: bits, V-memory words and pairs, K constants, counts, labels and coils.

use super::{Error, Tok, V_WORDS, err};
use crate::machine::dl205::program::{
    Bit, D, Kind, MAPPED, Program, SPECIAL, W, current_word, mapped, writable_word,
};

pub(super) fn octal(digits: &str, t: &Tok) -> Result<u32, Error> {
    if digits.is_empty() || digits.len() > 7 || !digits.chars().all(|c| c.is_ascii_digit()) {
        return err(t.col, format!("malformed element '{}'", t.text));
    }
    if digits.contains(['8', '9']) {
        return err(
            t.col,
            format!("{}: element numbers are octal (digits 0–7)", t.text),
        );
    }
    u32::from_str_radix(digits, 8)
        .or_else(|_| err(t.col, format!("malformed element '{}'", t.text)))
}

/// Element letters of a token: `SP`, `CT`, `TA`, … then digits.
pub(super) fn split(t: &Tok) -> (String, &str) {
    let upper_len = t
        .text
        .chars()
        .take_while(|c| c.is_ascii_alphabetic())
        .count();
    (
        t.text[..upper_len].to_ascii_uppercase(),
        &t.text[upper_len..],
    )
}

fn unsupported_element(letters: &str) -> Option<&'static str> {
    Some(match letters {
        "GX" | "GY" => "remote I/O bits",
        "P" => "pointers",
        _ => return None,
    })
}

pub(super) fn bit(t: &Tok, program: &mut Program) -> Result<Bit, Error> {
    let (letters, digits) = split(t);
    let kind = match letters.as_str() {
        "X" => Kind::X,
        "Y" => Kind::Y,
        "C" => Kind::C,
        "SP" => Kind::Sp,
        "S" => Kind::S,
        "T" => Kind::T,
        "CT" => Kind::Ct,
        other => {
            if let Some(what) = unsupported_element(other) {
                return err(
                    t.col,
                    format!(
                        "{} is one of the {what}, not supported by servoscope yet",
                        t.text
                    ),
                );
            }
            return err(
                t.col,
                format!(
                    "'{}' is not a bit element (X, Y, C, S, T, CT or SP)",
                    t.text
                ),
            );
        }
    };
    let n = octal(digits, t)?;
    if kind == Kind::Sp {
        let Some(i) = SPECIAL.iter().position(|&s| s == n) else {
            return err(
                t.col,
                format!(
                    "{} is a special relay not supported by servoscope yet",
                    t.text
                ),
            );
        };
        return Ok(Bit { kind, n: i as u32 });
    }
    if n >= kind.count() {
        return err(
            t.col,
            format!(
                "{} is out of range ({}0–{}{:o})",
                t.text,
                kind.letter(),
                kind.letter(),
                kind.count() - 1
            ),
        );
    }
    let b = Bit { kind, n };
    program.used_bits.push(b);
    Ok(b)
}

pub(super) fn v_addr(t: &Tok, pair: bool, program: &mut Program) -> Result<u32, Error> {
    let (letters, digits) = split(t);
    let n = match letters.as_str() {
        "V" => octal(digits, t)?,
        // Timer and counter current values by their DirectSOFT names.
        "TA" | "CTA" => {
            let n = octal(digits, t)?;
            if n >= Kind::T.count() {
                return err(
                    t.col,
                    format!("{} is out of range ({letters}0–{letters}377)", t.text),
                );
            }
            current_word(if letters == "TA" { Kind::T } else { Kind::Ct }, n)
        }
        // A bit-mapped word by its elements: VX20 holds X20–X37.
        name => match MAPPED.iter().find(|m| m.3 == name) {
            Some(&(first, last, kind, _)) => {
                let n = octal(digits, t)?;
                if n % 0o20 != 0 {
                    return err(
                        t.col,
                        format!(
                            "{}: a bit-mapped word starts at a multiple of 20 ({name}0, {name}20, …)",
                            t.text
                        ),
                    );
                }
                let a = first + n / 16;
                if a > last {
                    return err(
                        t.col,
                        format!(
                            "{} is out of range ({name}0–{name}{:o}, the {} elements)",
                            t.text,
                            (last - first) * 16,
                            kind.letter()
                        ),
                    );
                }
                a
            }
            None => return err(t.col, format!("'{}' is not a V-memory word", t.text)),
        },
    };
    if (0o40000..0o40400).contains(&n) {
        return err(
            t.col,
            format!(
                "{} is a GX/GY remote I/O word, not supported by servoscope yet",
                t.text
            ),
        );
    }
    if n >= V_WORDS && mapped(n).is_none() {
        return err(
            t.col,
            format!(
                "{} does not exist (V0–V37777 data, V40400–V41237 bit-mapped words)",
                t.text
            ),
        );
    }
    if pair && n + 1 >= V_WORDS && mapped(n + 1).is_none() {
        let what = if n < V_WORDS {
            "V37777"
        } else {
            "its bit-mapped region"
        };
        return err(
            t.col,
            format!("{} and the next word run past {what}", t.text),
        );
    }
    program.used_v.push(n);
    if pair {
        program.used_v.push(n + 1);
    }
    Ok(n)
}

/// A V word (or pair) an instruction writes: data words, VY, VC and VS; the X, T, CT and SP
/// words belong to the scan and the boxes (spec §1, §9.24).
pub(super) fn v_dest(t: &Tok, pair: bool, program: &mut Program) -> Result<u32, Error> {
    let n = v_addr(t, pair, program)?;
    if !writable_word(n) || (pair && !writable_word(n + 1)) {
        return err(
            t.col,
            format!(
                "{} is read-only: the X, T, CT and SP bit-mapped words cannot be written",
                t.text
            ),
        );
    }
    Ok(n)
}

/// `K` + 1–8 hex digits, the raw pattern.
pub(super) fn k_hex(t: &Tok) -> Option<u32> {
    let (letters, digits) = (t.text.get(..1)?, t.text.get(1..)?);
    if !letters.eq_ignore_ascii_case("K") || digits.is_empty() || digits.len() > 8 {
        return None;
    }
    u32::from_str_radix(digits, 16).ok()
}

pub(super) fn is_bcd(v: u32) -> bool {
    (0..8).all(|i| v >> (4 * i) & 0xF <= 9)
}

/// Whether a token names a V word (Vn, TAn, CTAn) rather than a constant.
pub(super) fn is_word(t: &Tok) -> bool {
    let (letters, _) = split(t);
    matches!(letters.as_str(), "V" | "TA" | "CTA") || MAPPED.iter().any(|m| m.3 == letters)
}

/// A 16-bit source: V, or K up to `max` (BCD-checked when `bcd`).
pub(super) fn word(
    t: &Tok,
    allow_k: bool,
    bcd: bool,
    min: u32,
    max: u32,
    program: &mut Program,
) -> Result<W, Error> {
    if is_word(t) {
        return v_addr(t, false, program).map(W::V);
    }
    if !allow_k {
        return err(
            t.col,
            format!("'{}': this instruction takes a V-memory word", t.text),
        );
    }
    let Some(k) = k_hex(t) else {
        return err(
            t.col,
            format!("'{}' is not a V word or a K constant", t.text),
        );
    };
    if bcd && !is_bcd(k) {
        return err(
            t.col,
            format!(
                "{} is not BCD: this instruction needs BCD digits 0–9",
                t.text
            ),
        );
    }
    if k < min || k > max {
        return err(
            t.col,
            format!("{} is out of range (K{min:X}–K{max:X})", t.text),
        );
    }
    Ok(W::K(k as u16))
}

pub(super) fn double(t: &Tok, allow_k: bool, bcd: bool, program: &mut Program) -> Result<D, Error> {
    if is_word(t) {
        return v_addr(t, true, program).map(D::V);
    }
    if !allow_k {
        return err(
            t.col,
            format!("'{}': this instruction takes a V-memory pair", t.text),
        );
    }
    let Some(k) = k_hex(t) else {
        return err(
            t.col,
            format!("'{}' is not a V pair or a K constant", t.text),
        );
    };
    if bcd && !is_bcd(k) {
        return err(
            t.col,
            format!(
                "{} is not BCD: this instruction needs BCD digits 0–9",
                t.text
            ),
        );
    }
    Ok(D::K(k))
}

/// A count: K + decimal 1–32.
pub(super) fn count(t: &Tok) -> Result<u8, Error> {
    let digits = t.text.get(1..).unwrap_or("");
    if !t.text.to_ascii_uppercase().starts_with('K') || !digits.chars().all(|c| c.is_ascii_digit())
    {
        return err(t.col, format!("'{}' is not a count K1–K32", t.text));
    }
    match digits.parse::<u8>() {
        Ok(n) if (1..=32).contains(&n) => Ok(n),
        _ => err(t.col, format!("{} is out of range (K1–K32)", t.text)),
    }
}

/// A label or subroutine number: K0–KFFFF (hex digits, as DirectSOFT writes them).
pub(super) fn label(t: &Tok) -> Result<u16, Error> {
    match k_hex(t) {
        Some(k) if k <= 0xFFFF => Ok(k as u16),
        _ => err(
            t.col,
            format!("'{}' is not a label number K0–KFFFF", t.text),
        ),
    }
}

/// The bit a coil (OUT, PD, OROUT) writes: Y, C or S.
pub(super) fn coil(t: &Tok, mnemonic: &str, program: &mut Program) -> Result<Bit, Error> {
    let b = bit(t, program)?;
    if !matches!(b.kind, Kind::Y | Kind::C | Kind::S) {
        return err(
            t.col,
            format!("{} cannot be written: {mnemonic} needs Y, C or S", t.text),
        );
    }
    Ok(b)
}
