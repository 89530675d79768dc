//! The last statement in words, with its operand values (spec issue: "PREG = (Var1 4694 × 293)
//! << 12 = 0x00014FC6E000").

use super::program::{AddKind, Data, Op, Operand, Value};
use super::{PREDEFINED, Tml, d};
use crate::machine::value::{q16_exact, remainder_note, wrap_note};

fn name(m: &Tml, op: &Operand) -> String {
    let base = match op.data {
        Data::Pre(i) => PREDEFINED[i as usize].name.to_string(),
        Data::Var(v) => m.var_name(v as usize).to_string(),
    };
    match op.half {
        Some(true) => format!("{base}(H)"),
        Some(false) => format!("{base}(L)"),
        None => base,
    }
}

/// A value as its datum reads: fixed also in decimal.
/// The label a `W16 = label` statement names, if `text` is one.
fn assigned_label<'a>(m: &'a Tml, text: &str) -> Option<&'a str> {
    let rhs = text.split_once('=')?.1.trim();
    m.program
        .labels
        .iter()
        .find(|(l, _)| l.eq_ignore_ascii_case(rhs))
        .map(|(l, _)| l.as_str())
}

fn shown(op: &Operand, v: i64) -> String {
    if op.is_fixed() {
        format!("{v} = {} (fixed)", q16_exact(v))
    } else {
        v.to_string()
    }
}

fn source(m: &Tml, v: &Value, read: i64) -> String {
    match v {
        Value::Imm(_) => read.to_string(),
        Value::Var(op) => format!("{} {read}", name(m, op)),
    }
}

/// What a shift lost: bits shifted out at the top (the result wrapped) or at the bottom.
fn shift_note(value: i64, left: bool, n: u8, stored: i64) -> String {
    let n = u32::from(n.min(63));
    if left {
        wrap_note(i128::from(value) << n, stored)
    } else {
        let dropped = value & ((1i64 << n) - 1);
        if dropped == 0 {
            String::new()
        } else {
            format!(" — the low {n} bit(s) ({dropped}) were shifted out")
        }
    }
}

pub fn explain(m: &Tml) -> Option<String> {
    let index = m.last? as usize;
    let stmt = m.program.stmts.get(index)?;
    let [a, b, r] = m.last_vals;
    let text = match stmt.op {
        // `W16 = label`: the address, in hex as program memory is read, and whose it is.
        Op::Assign(dst, Value::Imm(_)) if let Some(label) = assigned_label(m, &stmt.text) => {
            format!(
                "{} = 0x{:04X}, the address of {label}",
                name(m, &dst),
                r as u16
            )
        }
        Op::Assign(dst, src) => format!(
            "{} = {}{}",
            name(m, &dst),
            match src {
                Value::Imm(_) => shown(&dst, r),
                Value::Var(s) => format!("{} = {}", name(m, &s), shown(&dst, r)),
            },
            wrap_note(i128::from(a), r)
        ),
        Op::Negate(dst, src) => format!(
            "{} = −({} {a}) = {}{}",
            name(m, &dst),
            name(m, &src),
            shown(&dst, r),
            wrap_note(-i128::from(a), r)
        ),
        Op::AssignShift { dst, src, left, n } => format!(
            "{} = {} {a} {} {n} = {}{}",
            name(m, &dst),
            name(m, &src),
            if left { "<<" } else { ">>" },
            shown(&dst, r),
            shift_note(a, left, n, r)
        ),
        Op::Add {
            dst,
            src,
            kind,
            subtract,
        } => {
            let sign = if subtract { "−" } else { "+" };
            let what = match (src, kind) {
                (Value::Var(s), AddKind::IntegerPart) => {
                    format!("{} {} × 65536", name(m, &s), b / 65536)
                }
                (s, _) => source(m, &s, b),
            };
            let exact = if subtract {
                i128::from(a) - i128::from(b)
            } else {
                i128::from(a) + i128::from(b)
            };
            format!(
                "{} = {a} {sign} {what} = {}{}",
                name(m, &dst),
                shown(&dst, r),
                wrap_note(exact, r)
            )
        }
        Op::Multiply {
            a: x,
            b: y,
            left,
            n,
        } => {
            let mult = m.last_multiply?;
            let by = match y {
                Value::Imm(_) => mult.b.to_string(),
                Value::Var(op) => format!("{} {}", name(m, &op), mult.b),
            };
            // Said only when a set bit was dropped, with what was dropped.
            let (low, high) = super::arith::multiply_losses(m, &mult);
            let lost = match (low, high) {
                (0, false) => String::new(),
                (0, true) => " (high bits beyond 48 lost)".to_string(),
                (low, false) => format!(" (low bits {low} of 2^{n} lost)"),
                (low, true) => {
                    format!(" (low bits {low} of 2^{n} and high bits beyond 48 lost)")
                }
            };
            format!(
                "PREG = ({} {} × {by}) {} {n} = 0x{:012X}{lost}; product {}",
                name(m, &x),
                mult.a,
                if left { "<<" } else { ">>" },
                m.preg,
                mult.product
            )
        }
        Op::Divide(dst, divisor) => {
            let num = if dst.is_fixed() {
                format!("{a}")
            } else {
                format!("({a} × 65536)")
            };
            let n = if dst.is_fixed() {
                i128::from(a)
            } else {
                i128::from(a) * 65536
            };
            let note = if b == 0 {
                " — ÷0: saturated".to_string()
            } else if n / i128::from(b) != i128::from(r) {
                format!(
                    " — saturated: the exact quotient {} does not fit 32 bits",
                    n / i128::from(b)
                )
            } else {
                remainder_note(n % i128::from(b))
            };
            format!(
                "{} /= {}: {num} / {b} = {r} = {} (fixed){note}",
                name(m, &dst),
                name(m, &divisor),
                q16_exact(r)
            )
        }
        Op::Shift { dst, left, n } => format!(
            "{} {}= {n}: {a} → {}{}",
            name(m, &dst),
            if left { "<<" } else { ">>" },
            shown(&dst, r),
            shift_note(a, left, n, r)
        ),
        Op::ShiftProduct { left, n } => format!(
            "PREG {}= {n}: {a} → {} (0x{:012X})",
            if left { "<<" } else { ">>" },
            r,
            m.preg
        ),
        Op::Srb { dst, and, or } => format!(
            "SRB {}: ({} AND 0x{and:04X}) OR 0x{or:04X} = {}",
            name(m, &dst),
            a,
            r
        ),
        Op::Jump { call, cond, .. } => {
            let verb = if call { "CALL" } else { "GOTO" };
            match cond {
                Some((x, c)) => format!(
                    "{verb}: {} = {a} {} {}",
                    name(m, &x),
                    c.symbol(),
                    if b != 0 {
                        "holds: jumped"
                    } else {
                        "does not hold: went on"
                    }
                ),
                None => format!("{verb}: jumped"),
            }
        }
        Op::JumpVia { via, call, cond } => {
            let verb = if call { "CALL" } else { "GOTO" };
            let address = r as u16;
            let whither = match m.program.statement_at(u32::from(address)) {
                Some(i) if i < m.program.stmts.len() => {
                    format!("0x{address:04X} ('{}')", m.program.stmts[i].text)
                }
                Some(_) => format!("0x{address:04X}, the end of the program"),
                None => format!("0x{address:04X}"),
            };
            let through = format!("through {} = {whither}", name(m, &via));
            match cond {
                Some((x, c)) if b == 0 => format!(
                    "{verb} {through}: {} = {a} {} does not hold: went on",
                    name(m, &x),
                    c.symbol()
                ),
                Some((x, c)) => format!(
                    "{verb} {through}: {} = {a} {} holds: jumped",
                    name(m, &x),
                    c.symbol()
                ),
                None => format!("{verb} {through}: jumped"),
            }
        }
        Op::Ret => "RET: back after the CALL".into(),
        Op::End => "END: the program ended".into(),
        Op::ModePp => "MODE PP: trapezoidal position profile (TUM0)".into(),
        Op::Relative(true) => "CPR: CPOS is relative".into(),
        Op::Relative(false) => "CPA: CPOS is absolute".into(),
        Op::Tum(t) => format!(
            "TUM{}: the next UPD starts from the {}",
            u8::from(t),
            if t {
                "reference"
            } else {
                "actual position and speed"
            }
        ),
        Op::Upd => {
            let p = &m.profile;
            let why = m.last_vals[0] as u8;
            if why == 0 {
                format!(
                    "UPD: move to {} at speed {} and acceleration {} (counts/tick)",
                    p.end,
                    q16_exact(p.speed),
                    q16_exact(p.accel)
                )
            } else {
                use super::upd_ignored as u;
                let cspd = q16_exact(i64::from(m.data[d::CSPD as usize] as i32));
                let cacc = q16_exact(i64::from(m.data[d::CACC as usize] as i32));
                let reasons: Vec<String> = [
                    (u::NO_MODE_PP, "no MODE PP was given".to_string()),
                    (u::AXIS_OFF, "the axis is off (AXISON first)".to_string()),
                    (u::CSPD, format!("CSPD is {cspd}, not positive")),
                    (u::CACC, format!("CACC is {cacc}, not positive")),
                ]
                .into_iter()
                .filter(|(bit, _)| why & bit != 0)
                .map(|(_, text)| text)
                .collect();
                format!(
                    "UPD: ignored (MER bit 14, DER bit 4): {}",
                    reasons.join("; ")
                )
            }
        }
        Op::Stop => "STOP: decelerate to standstill at CACC".into(),
        Op::Sap(_) => format!("SAP: APOS = {a} (shifted by {b}; the motor does not move)"),
        Op::Axis(on) => format!(
            "{}: power stage {}",
            if on { "AXISON" } else { "AXISOFF" },
            if on { "on" } else { "off" }
        ),
        Op::Nop => format!("{}: no effect", stmt.text),
        Op::SetEvent(_) => format!("{}: event programmed, SRL bit 14 cleared", stmt.text),
        Op::Wait(_) => {
            if a != 0 {
                format!("WAIT!: the event occurred after {b} ticks")
            } else {
                format!("WAIT!: timed out after {b} ticks")
            }
        }
    };
    Some(text)
}
