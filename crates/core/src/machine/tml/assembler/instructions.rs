//! The instructions of the subset (GOTO, CALL, MODE, SAP, SRB, WAIT!, …) and the events a
//! `!` statement sets (!MC, !RT, !IN#n).

use super::UNSUPPORTED_EVENTS;
use super::lex::{Context, Error, Num, Tok, Token, err};
use super::names::{Names, Target};
use super::operands::{
    count_number, datum_name, expect_end, jump_target, not_supported, punct, signed_number,
    value_of_width, writable,
};
use crate::machine::tml::program::{Cond, EventSpec, Op};

pub(super) fn mnemonic(ts: &[Token], names: &mut Names, upper: &str) -> Result<Op, Error> {
    let mut at = 1;
    let first = &ts[0];
    let op = match upper {
        "GOTO" | "CALL" => {
            let target = jump_target(ts, &mut at, names)?;
            let cond = if punct(ts, at, ",") {
                at += 1;
                if at >= ts.len() {
                    return err(ts[at - 1].col + 1, 1, "expected a variable to test");
                }
                let x = names.operand(ts, &mut at)?;
                if !punct(ts, at, ",") {
                    let (col, len) = ts
                        .get(at)
                        .map_or((ts[at - 1].col + ts[at - 1].len, 1), |t| (t.col, t.len));
                    return err(
                        col,
                        len,
                        "expected ', condition' (EQ, NEQ, LT, LEQ, GT, GEQ)",
                    );
                }
                at += 1;
                let Some(Token {
                    tok: Tok::Ident(c),
                    col,
                    len,
                }) = ts.get(at)
                else {
                    let col = ts.get(at).map_or(ts[at - 1].col + 1, |t| t.col);
                    return err(col, 1, "expected a condition: EQ, NEQ, LT, LEQ, GT or GEQ");
                };
                let Some(c) = Cond::parse(c) else {
                    return err(
                        *col,
                        *len,
                        format!("unknown condition '{c}': EQ, NEQ, LT, LEQ, GT or GEQ"),
                    );
                };
                at += 1;
                Some((x, c))
            } else {
                None
            };
            let call = upper == "CALL";
            match target {
                Target::Statement(target) => Op::Jump { target, call, cond },
                Target::Via(via) => Op::JumpVia { via, call, cond },
            }
        }
        "RET" => Op::Ret,
        "END" => Op::End,
        "MODE" => match ts.get(1) {
            Some(Token {
                tok: Tok::Ident(m), ..
            }) if m.eq_ignore_ascii_case("PP") => {
                at = 2;
                Op::ModePp
            }
            Some(t) => return not_supported(t, &format!("MODE {}", token_text(t))),
            None => return err(first.col + first.len, 1, "expected a mode: PP"),
        },
        "CPR" => Op::Relative(true),
        "CPA" => Op::Relative(false),
        "TUM0" => Op::Tum(false),
        "TUM1" => Op::Tum(true),
        "UPD" | "STOP" if punct(ts, 1, "!") => return not_supported(first, &format!("{upper}!")),
        "UPD" => Op::Upd,
        "STOP" => Op::Stop,
        "SAP" => Op::Sap(value_of_width(ts, &mut at, names, 32)?),
        "AXISON" => Op::Axis(true),
        "AXISOFF" => Op::Axis(false),
        "BEGIN" | "ENDINIT" | "NOP" => Op::Nop,
        "SRB" | "SRBL" => {
            let t = ts.get(1).cloned().ok_or(Error {
                col: first.col + first.len,
                len: 1,
                message: "expected a 16-bit datum".into(),
            })?;
            let dst = names.operand(ts, &mut at)?;
            if dst.bits() != 16 {
                return err(
                    t.col,
                    t.len,
                    format!(
                        "{upper} works on 16-bit data; {} is 32-bit (use X(L) or X(H))",
                        datum_name(&dst, names)
                    ),
                );
            }
            if !writable(&dst) {
                return err(
                    t.col,
                    t.len,
                    format!("{} is read-only", datum_name(&dst, names)),
                );
            }
            let mut masks = [0u16; 2];
            for mask in &mut masks {
                if !punct(ts, at, ",") {
                    let col = ts
                        .get(at)
                        .map_or(ts[at - 1].col + ts[at - 1].len, |t| t.col);
                    return err(col, 1, "expected ', mask' (SRB X, andmask, ormask)");
                }
                at += 1;
                match signed_number(ts, &mut at) {
                    Some(Ok(n)) if !n.fixed && (-32768..=65535).contains(&n.value) => {
                        n.check(Context::Bits16)?;
                        *mask = n.value as u16;
                    }
                    Some(Ok(n)) => {
                        return err(n.col, n.len, "a mask is a 16-bit number (−32768..65535)");
                    }
                    Some(Err(e)) => return Err(e),
                    None => {
                        let col = ts.get(at).map_or(ts[at - 1].col + 1, |t| t.col);
                        return err(col, 1, "expected a 16-bit mask");
                    }
                }
            }
            Op::Srb {
                dst,
                and: masks[0],
                or: masks[1],
            }
        }
        "WAIT" => {
            if !punct(ts, 1, "!") {
                return err(first.col, first.len, "expected WAIT! (WAIT with '!')");
            }
            at = 2;
            let limit = match count_number(ts, &mut at) {
                None => None,
                Some(Ok(n)) if !n.fixed && (0..=65535).contains(&n.value) => Some(n.value as u16),
                Some(Ok(n)) => {
                    return err(
                        n.col,
                        n.len,
                        "a WAIT! time-out is a number of ticks 0..65535",
                    );
                }
                Some(Err(e)) => return Err(e),
            };
            Op::Wait(limit)
        }
        _ => {
            return err(
                first.col,
                first.len,
                format!("unknown instruction '{upper}'"),
            );
        }
    };
    expect_end(ts, at)?;
    Ok(op)
}

fn token_text(t: &Token) -> String {
    match &t.tok {
        Tok::Ident(s) | Tok::BadNumber(s) => s.clone(),
        Tok::Int(v, suffix) => format!("{v}{}", suffix.text()),
        Tok::Fixed(v) => v.to_string(),
        Tok::Punct(p) => (*p).to_string(),
    }
}

pub(super) fn event(ts: &[Token], names: &mut Names) -> Result<Op, Error> {
    let Some(t) = ts.get(1) else {
        return err(ts[0].col, 1, "expected an event after '!': MC, RT or IN#n");
    };
    let Tok::Ident(word) = &t.tok else {
        return err(t.col, t.len, "expected an event after '!': MC, RT or IN#n");
    };
    let upper = word.to_ascii_uppercase();
    let mut at = 2;
    let spec = match upper.as_str() {
        "MC" => EventSpec::MotionComplete,
        "RT" => EventSpec::Time(value_of_width(ts, &mut at, names, 32)?),
        "IN" => {
            if !punct(ts, 2, "#") {
                return err(t.col, t.len, "expected IN#n (an input 0..15)");
            }
            at = 3;
            let n = match count_number(ts, &mut at) {
                Some(Ok(n)) if !n.fixed && (0..=15).contains(&n.value) => n.value as u8,
                Some(Ok(n)) => return err(n.col, n.len, "inputs are IN#0..IN#15"),
                Some(Err(e)) => return Err(e),
                None => return err(t.col, t.len, "expected IN#n (an input 0..15)"),
            };
            let level = match count_number(ts, &mut at) {
                Some(Ok(Num {
                    value: 0,
                    fixed: false,
                    ..
                })) => false,
                Some(Ok(Num {
                    value: 1,
                    fixed: false,
                    ..
                })) => true,
                Some(Ok(n)) => return err(n.col, n.len, "an input event waits for level 0 or 1"),
                Some(Err(e)) => return Err(e),
                None => {
                    let col = ts.last().map_or(t.col, |l| l.col + l.len);
                    return err(col, 1, "expected the level to wait for: 0 or 1");
                }
            };
            if !names.used_inputs.contains(&n) {
                names.used_inputs.push(n);
            }
            EventSpec::Input(n, level)
        }
        _ if UNSUPPORTED_EVENTS.contains(&upper.as_str()) => {
            return not_supported(t, &format!("the event !{upper}"));
        }
        _ => {
            return err(
                t.col,
                t.len,
                format!("unknown event '!{word}': !MC, !RT t or !IN#n 0|1"),
            );
        }
    };
    expect_end(ts, at)?;
    Ok(Op::SetEvent(spec))
}
