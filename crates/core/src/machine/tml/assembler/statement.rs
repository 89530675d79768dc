//! Statements: where they end, the multi-axis ones refused, expressions (assignments, adds,
//! divides, shifts, multiplies) and declarations.

use super::instructions::{event, mnemonic};
use super::lex::{Error, Num, Tok, Token, err};
use super::names::{Fixup, Names, predefined, reserved};
use super::operands::{
    datum_name, expect_end, immediate, not_supported, punct, shift_count, signed_number,
    value_of_width, writable,
};
use super::{INTERRUPTS, MAX_NAME, MNEMONICS, TYPES, UNSUPPORTED, unmodelled};
use crate::machine::tml::d;
use crate::machine::tml::program::{AddKind, Data, Op, Operand, Ty, Value, Var};

/// The indices of the `;` that end statements in `body`: a `;` inside a multi-axis `{…}` group
/// does not end one (spec §5.10: the statement runs to the end of its group).
pub(super) fn statement_ends(body: &[char]) -> Vec<usize> {
    let mut depth = 0usize;
    let mut ends = Vec::new();
    for (k, &c) in body.iter().enumerate() {
        match c {
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            ';' if depth == 0 => ends.push(k),
            _ => {}
        }
    }
    ends
}

/// The one error of a multi-axis statement (`[3] X = Y`, `[G1]{CPOS=2000;}`, `[B]{STOP;}`) or
/// a bare `{…}` group, naming it and where it is sent.
pub(super) fn multi_axis(ts: &[Token], seg: &[char]) -> Error {
    let text: String = seg.iter().collect::<String>().trim().to_string();
    // The group's body is elided: `[G1] {…}`.
    let shown = match (text.find('{'), text.rfind('}')) {
        (Some(open), Some(close)) if open < close => {
            let before = text[..open].trim_end();
            let gap = if before.is_empty() { "" } else { " " };
            format!("{before}{gap}{{…}}{}", &text[close + 1..])
        }
        _ => text.clone(),
    };
    let target = text
        .strip_prefix('[')
        .and_then(|r| r.split_once(']'))
        .map(|(t, _)| t.trim().to_ascii_uppercase());
    let sent = match target.as_deref() {
        Some("B") => " (broadcast to every axis)".to_string(),
        Some(t) if t.starts_with('G') => format!(" (sent to group {})", &t[1..]),
        Some(t) => format!(" (sent to axis {t})"),
        None => String::new(),
    };
    let first = &ts[0];
    let len = ts.last().map_or(first.len, |l| l.col + l.len - first.col);
    Error {
        col: first.col,
        len,
        message: format!("multi-axis statement '{shown}'{sent} is not supported by servoscope yet"),
    }
}

/// One statement (without its `;`).
pub(super) fn statement(ts: &[Token], names: &mut Names, line: usize) -> Result<Option<Op>, Error> {
    let first = &ts[0];
    match &first.tok {
        Tok::Punct("!") => return event(ts, names).map(Some),
        Tok::Punct("(") => return not_supported(first, "addressing through a variable ((var),dm)"),
        Tok::Ident(word) => {
            let upper = word.to_ascii_uppercase();
            if TYPES.contains(&upper.as_str()) {
                declare(ts, names, line, &upper)?;
                return Ok(None);
            }
            let next_is_operator = matches!(ts.get(1), Some(Token { tok: Tok::Punct(p), .. }) if ["=", "+=", "-=", "/=", "<<=", ">>=", "<<", ">>", "*", "(", ","].contains(p));
            if INTERRUPTS.contains(&upper.as_str()) {
                return err(
                    first.col,
                    first.len,
                    format!("{upper}: servoscope does not model TML interrupts yet"),
                );
            }
            if UNSUPPORTED.contains(&upper.as_str()) && !names.var_index.contains_key(&upper) {
                return not_supported(first, &format!("the TML instruction {upper}"));
            }
            if MNEMONICS.contains(&upper.as_str()) {
                return mnemonic(ts, names, &upper).map(Some);
            }
            if !next_is_operator
                && predefined(word).is_none()
                && !names.var_index.contains_key(&upper)
            {
                let candidates = MNEMONICS.iter().copied().chain(UNSUPPORTED.iter().copied());
                if ts.len() == 1
                    || matches!(
                        ts.get(1),
                        Some(Token {
                            tok: Tok::Ident(_) | Tok::Int(..),
                            ..
                        })
                    )
                {
                    let hint = names
                        .suggester
                        .suggest(word, candidates)
                        .map(|s| format!(" (did you mean '{s}'?)"))
                        .unwrap_or_default();
                    return err(
                        first.col,
                        first.len,
                        format!("unknown instruction '{word}'{hint}"),
                    );
                }
            }
        }
        _ => return err(first.col, first.len, "expected a statement"),
    }
    // An expression statement: it starts with a datum.
    let mut at = 0;
    let lhs_tok = ts[0].clone();
    let lhs = names.operand(ts, &mut at)?;
    let Some(op_tok) = ts.get(at).cloned() else {
        return err(
            lhs_tok.col,
            lhs_tok.len,
            "expected an operator after the name (=, +=, -=, *, /=, <<, >>)",
        );
    };
    let Tok::Punct(op) = op_tok.tok else {
        return err(
            op_tok.col,
            op_tok.len,
            "expected an operator (=, +=, -=, *, /=, <<, >>)",
        );
    };
    at += 1;
    let is_prod = lhs.data == Data::Pre(d::PROD) && lhs.half.is_none();
    let check_writable = |names: &Names| -> Result<(), Error> {
        if writable(&lhs) {
            Ok(())
        } else {
            err(
                lhs_tok.col,
                lhs_tok.len,
                format!("{} is read-only", datum_name(&lhs, names)),
            )
        }
    };
    let result = match op {
        "," => return not_supported(&op_tok, "the address form X,dm"),
        "=" => {
            check_writable(names)?;
            assignment(ts, &mut at, names, lhs, &lhs_tok)?
        }
        "+=" | "-=" => {
            check_writable(names)?;
            let subtract = op == "-=";
            let (src, kind) = if let Some(n) = signed_number(ts, &mut at) {
                // An immediate added to a long is 32-bit (spec §8).
                (Value::Imm(immediate(n?, &lhs)?), AddKind::Plain)
            } else {
                if at >= ts.len() {
                    return err(op_tok.col + op_tok.len, 1, "expected a value");
                }
                let t = ts[at].clone();
                let r = names.operand(ts, &mut at)?;
                let kind = match (lhs.bits(), r.bits()) {
                    (16, 32) => {
                        return err(
                            t.col,
                            t.len,
                            "16/32-bit width mismatch: a 32-bit value cannot be added to 16-bit data (use X(L) or X(H))",
                        );
                    }
                    (32, 16) if lhs.is_fixed() => AddKind::IntegerPart,
                    _ => AddKind::Plain,
                };
                (Value::Var(r), kind)
            };
            Op::Add {
                dst: lhs,
                src,
                kind,
                subtract,
            }
        }
        "/=" => {
            check_writable(names)?;
            if lhs.bits() != 32 {
                return err(
                    lhs_tok.col,
                    lhs_tok.len,
                    "the dividend must be 32-bit (long or fixed)",
                );
            }
            if let Some(Ok(Num { col, len, .. })) = signed_number(ts, &mut at.clone()) {
                return err(
                    col,
                    len,
                    "the divisor must be a 16-bit datum, not an immediate",
                );
            }
            if at >= ts.len() {
                return err(op_tok.col + op_tok.len, 1, "expected a divisor");
            }
            let t = ts[at].clone();
            let r = names.operand(ts, &mut at)?;
            if r.bits() != 16 {
                return err(
                    t.col,
                    t.len,
                    "16/32-bit width mismatch: the divisor must be 16-bit",
                );
            }
            Op::Divide(lhs, r)
        }
        "<<=" | ">>=" | "<<" | ">>" => {
            let left = op.starts_with('<');
            let n = shift_count(ts, &mut at)?;
            if is_prod {
                names.uses_preg = true;
                Op::ShiftProduct { left, n }
            } else {
                check_writable(names)?;
                Op::Shift { dst: lhs, left, n }
            }
        }
        "*" => {
            let b = value_of_width(ts, &mut at, names, 16)?;
            let (left, n) = if punct(ts, at, "<<") || punct(ts, at, ">>") {
                let left = punct(ts, at, "<<");
                at += 1;
                (left, shift_count(ts, &mut at)?)
            } else {
                (true, 0)
            };
            names.uses_preg = true;
            Op::Multiply { a: lhs, b, left, n }
        }
        _ => {
            return err(
                op_tok.col,
                op_tok.len,
                format!("unexpected '{op}': expected =, +=, -=, *, /=, << or >>"),
            );
        }
    };
    expect_end(ts, at)?;
    Ok(Some(result))
}

fn assignment(
    ts: &[Token],
    at: &mut usize,
    names: &mut Names,
    lhs: Operand,
    lhs_tok: &Token,
) -> Result<Op, Error> {
    if let Some(n) = signed_number(ts, at) {
        return Ok(Op::Assign(lhs, Value::Imm(immediate(n?, &lhs)?)));
    }
    let negate = punct(ts, *at, "-");
    if negate {
        *at += 1;
    }
    let Some(t) = ts.get(*at).cloned() else {
        // Point just past the '=' (or the '-'), where the value is missing.
        let before = at.checked_sub(1).and_then(|i| ts.get(i)).unwrap_or(lhs_tok);
        return err(before.col + before.len, 1, "expected a value after '='");
    };
    if let Tok::Ident(name) = &t.tok
        && let Some(&(target, _)) = names.labels.get(&name.to_ascii_uppercase())
        && !names.var_index.contains_key(&name.to_ascii_uppercase())
    {
        // `W16 = label` stores the label's program address (spec §5.11).
        if negate {
            return err(
                t.col,
                t.len,
                format!("'{name}' is a label: its address cannot be negated"),
            );
        }
        if lhs.bits() != 16 {
            return err(
                t.col,
                t.len,
                format!(
                    "a label's address is 16-bit: {} is 32-bit (assign it to an int, or to X(L))",
                    datum_name(&lhs, names)
                ),
            );
        }
        *at += 1;
        names.pending = Some(Fixup::LabelAddress(target));
        return Ok(Op::Assign(lhs, Value::Imm(0)));
    }
    if matches!(t.tok, Tok::Punct("(")) {
        return not_supported(&t, "addressing through a variable ((var),dm)");
    }
    // Into 16-bit data an unknown name may be a label of a file not included (a part run
    // alone): say both.
    if let Tok::Ident(name) = &t.tok
        && lhs.bits() == 16
        && !negate
        && predefined(name).is_none()
        && unmodelled(name).is_none()
        && !name.eq_ignore_ascii_case("PREG")
        && !name.eq_ignore_ascii_case("IN")
        && !names.var_index.contains_key(&name.to_ascii_uppercase())
    {
        let hint = names.suggestion(name);
        return err(
            t.col,
            t.len,
            format!("undeclared variable or undefined label '{name}'{hint}"),
        );
    }
    if let Tok::Ident(name) = &t.tok
        && name.eq_ignore_ascii_case("IN")
        && punct(ts, *at + 1, "(")
    {
        return not_supported(&t, "reading inputs with IN(…)");
    }
    let src = names.operand(ts, at)?;
    if punct(ts, *at, ",")
        && matches!(ts.get(*at + 1), Some(Token { tok: Tok::Ident(dm), .. }) if dm.eq_ignore_ascii_case("dm"))
    {
        return not_supported(&t, "addressing through a variable (X,dm)");
    }
    if src.bits() != lhs.bits() {
        return err(
            t.col,
            t.len,
            format!(
                "16/32-bit width mismatch: {} is {}-bit, {} is {}-bit (use X(L) or X(H))",
                datum_name(&lhs, names),
                lhs.bits(),
                datum_name(&src, names),
                src.bits()
            ),
        );
    }
    if negate {
        return Ok(Op::Negate(lhs, src));
    }
    if punct(ts, *at, "<<") || punct(ts, *at, ">>") {
        let left = punct(ts, *at, "<<");
        *at += 1;
        let n = shift_count(ts, at)?;
        return Ok(Op::AssignShift {
            dst: lhs,
            src,
            left,
            n,
        });
    }
    Ok(Op::Assign(lhs, Value::Var(src)))
}

fn declare(ts: &[Token], names: &mut Names, line: usize, ty_word: &str) -> Result<(), Error> {
    let ty = match ty_word {
        "INT" => Ty::Int,
        "LONG" => Ty::Long,
        _ => Ty::Fixed,
    };
    let mut at = 1;
    loop {
        let Some(t) = ts.get(at) else {
            let col = ts.last().map_or(1, |t| t.col + t.len);
            return err(col, 1, "expected a variable name");
        };
        let Tok::Ident(name) = &t.tok else {
            return err(t.col, t.len, "expected a variable name");
        };
        let upper = name.to_ascii_uppercase();
        if name.len() > MAX_NAME {
            return err(
                t.col,
                t.len,
                format!("name longer than {MAX_NAME} characters"),
            );
        }
        if reserved(&upper) {
            return err(
                t.col,
                t.len,
                format!("'{name}' is a TML name and cannot be a variable"),
            );
        }
        if names.var_index.contains_key(&upper) {
            return err(t.col, t.len, format!("duplicate variable '{name}'"));
        }
        if names.labels.contains_key(&upper) {
            return err(t.col, t.len, format!("'{name}' is already a label"));
        }
        let index = names.vars.len() as u16;
        names.var_index.insert(upper, index);
        names.vars.push(Var {
            name: name.clone(),
            ty,
            line,
        });
        at += 1;
        match ts.get(at) {
            None => return Ok(()),
            Some(t) if t.tok == Tok::Punct(",") => at += 1,
            Some(t) => return err(t.col, t.len, "expected ',' or ';'"),
        }
    }
}
