//! Operands: punctuation, numbers and immediates of the right width, counts, and jump targets.

use super::lex::{Context, Error, Num, Suffix, Tok, Token, err};
use super::names::{Fixup, Names, Target, predefined};
use super::unmodelled;
use crate::machine::tml::program::{Data, Operand, Ty, Value};
use crate::machine::tml::{PREDEFINED, d};

pub(super) fn punct(ts: &[Token], at: usize, p: &str) -> bool {
    matches!(ts.get(at), Some(Token { tok: Tok::Punct(q), .. }) if *q == p)
}

pub(super) fn writable(op: &Operand) -> bool {
    match op.data {
        Data::Pre(i) => PREDEFINED[i as usize].writable,
        Data::Var(_) => true,
    }
}

pub(super) fn datum_name(op: &Operand, names: &Names) -> String {
    let base = match op.data {
        Data::Pre(i) => PREDEFINED[i as usize].name.to_string(),
        Data::Var(v) => names.vars[v as usize].name.clone(),
    };
    match op.half {
        Some(true) => format!("{base}(H)"),
        Some(false) => format!("{base}(L)"),
        None => base,
    }
}

/// A possibly negative number at `at`.
pub(super) fn signed_number(ts: &[Token], at: &mut usize) -> Option<Result<Num, Error>> {
    let start = *at;
    let negative = punct(ts, *at, "-");
    let i = *at + usize::from(negative);
    let t = ts.get(i)?;
    let (v, fixed, suffix) = match &t.tok {
        Tok::Int(v, suffix) => (*v, false, *suffix),
        Tok::Fixed(v) => (*v, true, Suffix::None),
        Tok::BadNumber(w) if w.starts_with('.') => {
            return Some(err(
                t.col,
                t.len,
                format!("write 0{w}: a fixed literal has a digit before its point"),
            ));
        }
        Tok::BadNumber(w) => {
            return Some(err(t.col, t.len, format!("malformed number '{w}'")));
        }
        _ => return None,
    };
    *at = i + 1;
    let col = ts[start].col;
    Some(Ok(Num {
        value: if negative { -v } else { v },
        fixed,
        suffix,
        col,
        len: t.col + t.len - col,
    }))
}

/// A plain number (no suffix, not fixed) at `at`, for counts, time-outs and levels.
pub(super) fn count_number(ts: &[Token], at: &mut usize) -> Option<Result<Num, Error>> {
    Some(signed_number(ts, at)?.and_then(|n| n.check(Context::Count).map(|()| n)))
}

pub(super) fn shift_count(ts: &[Token], at: &mut usize) -> Result<u8, Error> {
    match count_number(ts, at) {
        Some(Ok(n)) if !n.fixed && (0..=15).contains(&n.value) => Ok(n.value as u8),
        Some(Ok(n)) => err(n.col, n.len, "shift count outside 0..15"),
        Some(Err(e)) => Err(e),
        None => {
            let (col, len) = ts.get(*at).map_or((0, 1), |t| (t.col, t.len));
            err(col, len, "expected a shift count 0..15")
        }
    }
}

/// An immediate for a destination of type `dst` (spec §1: imm16, imm32, immF), as the raw
/// value the statement stores or adds.
pub(super) fn immediate(n: Num, dst: &Operand) -> Result<i64, Error> {
    let Num {
        value: v,
        fixed: fixed_literal,
        col,
        len,
        ..
    } = n;
    n.check(if dst.is_fixed() {
        Context::Fixed
    } else if dst.bits() == 16 {
        Context::Bits16
    } else {
        Context::Bits32
    })?;
    if dst.is_fixed() {
        if fixed_literal {
            if !(i128::from(i32::MIN)..=i128::from(i32::MAX)).contains(&v) {
                return err(
                    col,
                    len,
                    "fixed value out of range (−32768.0 .. 32767.99998)",
                );
            }
            return Ok(v as i64);
        }
        if !(-32768..=32767).contains(&v) {
            return err(
                col,
                len,
                "a whole number for a fixed datum must be in −32768..32767 (write it as a fixed literal, e.g. 1.5)",
            );
        }
        return Ok((v * 65536) as i64);
    }
    if fixed_literal {
        return err(col, len, "a fixed literal needs a fixed destination");
    }
    if dst.bits() == 16 {
        if !(-32768..=65535).contains(&v) {
            return err(col, len, "16-bit value out of range (−32768..65535)");
        }
        return Ok(i64::from(v as u16 as i16));
    }
    if !(i128::from(i32::MIN)..=i128::from(u32::MAX)).contains(&v) {
        return err(
            col,
            len,
            "32-bit value out of range (−2147483648..4294967295)",
        );
    }
    Ok(i64::from(v as u32 as i32))
}

pub(super) fn expect_end(ts: &[Token], at: usize) -> Result<(), Error> {
    match ts.get(at) {
        None => Ok(()),
        Some(t) => err(t.col, t.len, "unexpected text: expected ';'"),
    }
}

pub(super) fn not_supported<T>(t: &Token, what: &str) -> Result<T, Error> {
    err(
        t.col,
        t.len,
        format!("{what} is not supported by servoscope yet"),
    )
}

/// The target of a GOTO or CALL (spec §5.7): a label, a 16-bit datum holding a program address
/// (a variable known at this point is the variable, else a label), or a number that must be a
/// statement's address.
pub(super) fn jump_target(
    ts: &[Token],
    at: &mut usize,
    names: &mut Names,
) -> Result<Target, Error> {
    let Some(t) = ts.get(*at).cloned() else {
        let col = ts.last().map_or(1, |t| t.col + t.len);
        return err(col, 1, "expected a label");
    };
    match &t.tok {
        Tok::Ident(name) => {
            let upper = name.to_ascii_uppercase();
            if names.var_index.contains_key(&upper) || predefined(name).is_some() {
                let via = names.operand(ts, at)?;
                if via.bits() != 16 {
                    return err(
                        t.col,
                        t.len,
                        format!(
                            "{} is 32-bit: a jump through data needs a 16-bit datum holding a program address",
                            datum_name(&via, names)
                        ),
                    );
                }
                return Ok(Target::Via(via));
            }
            match names.labels.get(&upper) {
                Some(&(target, _)) => {
                    *at += 1;
                    Ok(Target::Statement(target))
                }
                None => {
                    if let Some(message) = unmodelled(name) {
                        return err(t.col, t.len, message);
                    }
                    let hint = names
                        .suggester
                        .suggest(name, names.labels.keys().map(String::as_str))
                        .map(|s| format!(" (did you mean '{}'?)", s.to_ascii_lowercase()))
                        .unwrap_or_default();
                    err(t.col, t.len, format!("undefined label '{name}'{hint}"))
                }
            }
        }
        Tok::Int(..) | Tok::Punct("-") | Tok::BadNumber(_) | Tok::Fixed(_) => {
            match count_number(ts, at) {
                Some(Ok(n)) if !n.fixed && (0..=0xFFFF).contains(&n.value) => {
                    names.pending = Some(Fixup::JumpAddress {
                        address: n.value as u32,
                        col: n.col,
                        len: n.len,
                    });
                    Ok(Target::Statement(0))
                }
                Some(Ok(n)) => err(n.col, n.len, "a jump address is a number 0..0xFFFF"),
                Some(Err(e)) => Err(e),
                None => err(t.col, t.len, "expected a label"),
            }
        }
        _ => err(t.col, t.len, "expected a label"),
    }
}

/// A readable operand or an immediate of `bits` bits: 16 for a multiply's right side, 32 for
/// SAP and `!RT`.
pub(super) fn value_of_width(
    ts: &[Token],
    at: &mut usize,
    names: &mut Names,
    bits: u8,
) -> Result<Value, Error> {
    if let Some(n) = signed_number(ts, at) {
        let as_integer = Operand {
            data: Data::Pre(d::UPGRADE),
            half: None,
            ty: if bits == 16 { Ty::Int } else { Ty::Long },
        };
        return immediate(n?, &as_integer).map(Value::Imm);
    }
    if *at >= ts.len() {
        let col = ts.last().map_or(1, |t| t.col + t.len);
        return err(col, 1, "expected a value");
    }
    let t = ts[*at].clone();
    let op = names.operand(ts, at)?;
    if op.bits() != bits {
        let hint = if bits == 16 {
            " (use X(L) or X(H))"
        } else {
            ""
        };
        return err(
            t.col,
            t.len,
            format!("16/32-bit width mismatch: a {bits}-bit operand is needed here{hint}"),
        );
    }
    Ok(Value::Var(op))
}
