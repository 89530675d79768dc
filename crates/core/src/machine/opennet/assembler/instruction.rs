//! One line's instruction: its mnemonic (with its data type and `REP`) and operands read into
//! an [`Op`], or the error, with a suggestion for an unknown mnemonic.

use super::operands::{
    Role, bit, box_operand, constant, dest_point, note_boxes, operand, point, value, word,
};
use super::{
    ADVANCED, BASIC, Error, LATER_CPU, MAX_REP, OTHER_NAMES, Pass, REGISTERS, REPEATABLE, Token,
    UNSUPPORTED, WORD_TYPES_ONLY, err,
};
use crate::machine::diagnostics::Suggester;
use crate::machine::opennet::program::{
    Area, Arith, CounterKind, Logic, Op, Rel, TimerKind, Ty, Value, Word,
};

/// The suggestion for an unknown mnemonic: `ADDW` → `ADD(W)`, `TMR` → `TIM`, else the closest
/// known one.
fn suggestion(word: &str, suggester: &Suggester) -> Option<String> {
    let upper = word.to_ascii_uppercase();
    if let Some((_, to)) = OTHER_NAMES.iter().find(|(from, _)| *from == upper) {
        return Some((*to).to_string());
    }
    for base in ADVANCED {
        if let Some(t) = upper.strip_prefix(base)
            && Ty::parse(t).is_some()
        {
            return Some(format!("{base}({t})"));
        }
    }
    suggester
        .suggest(word, BASIC.iter().chain(ADVANCED.iter()).copied())
        .map(str::to_string)
}

/// The data types an advanced instruction takes, as its message lists them.
fn types_of(mnemonic: &str) -> &'static str {
    if WORD_TYPES_ONLY.contains(&mnemonic) {
        "(W) or (D)"
    } else {
        "(W), (I), (D) or (L)"
    }
}

/// One line's instruction: its mnemonic (for the rung check) and the result.
pub(super) fn instruction(
    ts: &[Token],
    pass: &mut Pass,
    suggester: &Suggester,
) -> (Option<&'static str>, Result<Op, Error>) {
    let first = &ts[0];
    let raw = first.text.to_ascii_uppercase();
    let (base, ty_text) = match raw.split_once('(') {
        Some((b, rest)) => (b.to_string(), Some(rest.trim_end_matches(')').to_string())),
        None => (raw.clone(), None),
    };
    let mut rest: Vec<Token> = ts[1..].to_vec();
    // `AND LOD` / `OR LOD`.
    let base = if (base == "AND" || base == "OR")
        && ty_text.is_none()
        && rest
            .first()
            .is_some_and(|t| t.text.eq_ignore_ascii_case("LOD"))
    {
        rest.remove(0);
        format!("{base}LOD")
    } else {
        base
    };
    let known = BASIC
        .iter()
        .chain(ADVANCED.iter())
        .find(|m| **m == base)
        .copied();
    let Some(mnemonic) = known else {
        if UNSUPPORTED.contains(&base.as_str()) {
            return (
                None,
                err(
                    first.col,
                    first.text.len(),
                    format!("{base} is an OpenNet instruction not supported by servoscope yet"),
                ),
            );
        }
        if LATER_CPU.contains(&base.as_str()) {
            return (
                None,
                err(
                    first.col,
                    first.text.len(),
                    format!(
                        "{base} is an off-delay timer of later IDEC CPUs (FC5A/FC6A), not an OpenNet instruction"
                    ),
                ),
            );
        }
        let hint = suggestion(&first.text, suggester)
            .map(|s| format!(" (did you mean {s}?)"))
            .unwrap_or_default();
        return (
            None,
            err(
                first.col,
                first.text.len(),
                format!("unknown mnemonic '{}'{hint}", first.text),
            ),
        );
    };
    let result = (|| {
        let advanced = ADVANCED.contains(&mnemonic);
        let ty = match (&ty_text, advanced) {
            (Some(_), false) => {
                return err(
                    first.col,
                    first.text.len(),
                    format!("{mnemonic} is a basic instruction: it takes no data type"),
                );
            }
            (None, true) => {
                let micro3 = if matches!(mnemonic, "MOV" | "ADD" | "SUB" | "MUL" | "DIV") {
                    format!(" (a MICRO3 program's untyped {mnemonic} is the W type: {mnemonic}(W))")
                } else {
                    String::new()
                };
                return err(
                    first.col,
                    first.text.len(),
                    format!(
                        "{mnemonic} needs a data type: {mnemonic}{}{micro3}",
                        types_of(mnemonic)
                    ),
                );
            }
            (Some(t), true) => match Ty::parse(t) {
                Some(ty) if WORD_TYPES_ONLY.contains(&mnemonic) && ty.signed() => {
                    return err(
                        first.col,
                        first.text.len(),
                        format!("{mnemonic} takes type W or D, not {t}"),
                    );
                }
                Some(ty) => ty,
                None => {
                    return err(
                        first.col,
                        first.text.len(),
                        format!("invalid data type '{t}': {}", types_of(mnemonic)),
                    );
                }
            },
            (None, false) => Ty::W,
        };
        // REP n at the end.
        let mut rep: u32 = 1;
        let mut has_rep = false;
        if let Some(k) = rest.iter().position(|t| t.text.eq_ignore_ascii_case("REP")) {
            let rep_tok = rest[k].clone();
            if !REPEATABLE.contains(&mnemonic) {
                return err(
                    rep_tok.col,
                    3,
                    format!(
                        "{mnemonic} cannot repeat (REP is for MOV, ADD, SUB, MUL, DIV, the comparisons, ANDW, ORW, XORW, HTOB and BTOH)"
                    ),
                );
            }
            let Some(n) = rest.get(k + 1) else {
                return err(rep_tok.col, 3, "REP needs a count 1–99");
            };
            match n.text.parse::<u32>() {
                Ok(v) if (1..=MAX_REP).contains(&v) => rep = v,
                _ => return err(n.col, n.text.len(), "REP count outside 1–99"),
            }
            if rest.len() > k + 2 {
                let extra = &rest[k + 2];
                return err(
                    extra.col,
                    extra.text.len(),
                    "unexpected text after the REP count",
                );
            }
            rest.truncate(k);
            has_rep = true;
        }
        let want = match mnemonic {
            "ANDLOD" | "ORLOD" | "BPS" | "BRD" | "BPP" | "SOTU" | "SOTD" | "END" | "MCS"
            | "MCR" | "JMP" | "JEND" | "NOP" => 0,
            "MOV" | "TML" | "TIM" | "TMH" | "TMS" | "CNT" | "CDP" | "CUD" | "CC=" | "CC>="
            | "DC=" | "DC>=" | "SFR" | "SFRN" | "SFTL" | "SFTR" | "HTOB" | "BTOH" => 2,
            "ICMP>=" => 4,
            m if advanced && !matches!(m, "INC" | "DEC") => 3,
            _ => 1,
        };
        if rest.len() != want {
            let (col, len) = rest
                .get(want)
                .map_or((first.col, first.text.len()), |t| (t.col, t.text.len()));
            return err(
                col,
                len,
                format!("{mnemonic} takes {want} operand(s), found {}", rest.len()),
            );
        }
        if !has_rep
            && let Some(t) = rest
                .iter()
                .find(|t| t.text.to_ascii_uppercase().ends_with("(R)"))
        {
            return err(
                t.col,
                t.text.len(),
                "(R) without REP: add REP n after the operands",
            );
        }
        let w = ty.words();
        Ok(match mnemonic {
            "LOD" | "LODN" => Op::Lod(bit(&rest[0], false, pass)?, mnemonic == "LODN"),
            "AND" | "ANDN" => Op::And(bit(&rest[0], false, pass)?, mnemonic == "ANDN"),
            "OR" | "ORN" => Op::Or(bit(&rest[0], false, pass)?, mnemonic == "ORN"),
            "ANDLOD" => Op::AndLod,
            "ORLOD" => Op::OrLod,
            "BPS" => Op::Bps,
            "BRD" => Op::Brd,
            "BPP" => Op::Bpp,
            "SOTU" | "SOTD" => {
                let m = pass.program.edges;
                pass.program.edges += 1;
                if mnemonic == "SOTU" {
                    Op::Sotu(m)
                } else {
                    Op::Sotd(m)
                }
            }
            "OUT" | "OUTN" => Op::Out(bit(&rest[0], true, pass)?, mnemonic == "OUTN"),
            "SET" => Op::Set(bit(&rest[0], true, pass)?),
            "RST" => Op::Rst(bit(&rest[0], true, pass)?),
            "END" => Op::End,
            "NOP" => Op::Nop,
            // The MCR is found once every line is read.
            "MCS" => Op::Mcs(u32::MAX),
            "MCR" => Op::Mcr,
            // The target is resolved once every line is read.
            "JMP" => Op::Jmp(u32::MAX),
            "JEND" => Op::Jend,
            "TML" | "TIM" | "TMH" | "TMS" => {
                let kind = match mnemonic {
                    "TML" => TimerKind::Tml,
                    "TIM" => TimerKind::Tim,
                    "TMH" => TimerKind::Tmh,
                    _ => TimerKind::Tms,
                };
                let n = box_operand(&rest[0], 'T', mnemonic)?;
                let preset = value(&rest[1], pass)?;
                if let Some(line) = pass.timer_lines.insert(n, pass.line) {
                    pass.timer_lines.insert(n, line);
                    return err(
                        rest[0].col,
                        rest[0].text.len(),
                        format!(
                            "T{n} already has its timer instruction on line {line}: each timer number has one"
                        ),
                    );
                }
                note_boxes(&mut pass.program.used_timers, n, 1);
                if let Value::Const(p) = preset {
                    pass.program.timer_presets.push((n, p));
                }
                Op::Timer { kind, n, preset }
            }
            "CNT" | "CDP" | "CUD" => {
                let kind = match mnemonic {
                    "CNT" => CounterKind::Cnt,
                    "CDP" => CounterKind::Cdp,
                    _ => CounterKind::Cud,
                };
                let n = box_operand(&rest[0], 'C', mnemonic)?;
                let preset = value(&rest[1], pass)?;
                if let Some(line) = pass.counter_lines.insert(n, pass.line) {
                    pass.counter_lines.insert(n, line);
                    return err(
                        rest[0].col,
                        rest[0].text.len(),
                        format!(
                            "C{n} already has its counter instruction on line {line}: each counter number has one"
                        ),
                    );
                }
                note_boxes(&mut pass.program.used_counters, n, 1);
                if let Value::Const(p) = preset {
                    pass.program.counter_presets.push((n, p));
                }
                let pulses = pass.program.pulses;
                pass.program.pulses += if kind == CounterKind::Cdp { 2 } else { 1 };
                Op::Counter {
                    kind,
                    n,
                    preset,
                    pulses,
                }
            }
            "CC=" | "CC>=" => {
                let n = box_operand(&rest[0], 'C', mnemonic)?;
                note_boxes(&mut pass.program.used_counters, n, 1);
                Op::Compare {
                    counter: true,
                    n,
                    value: value(&rest[1], pass)?,
                    at_least: mnemonic == "CC>=",
                }
            }
            "DC=" | "DC>=" => {
                let t = &rest[0];
                let n = match operand(&t.text) {
                    Some(('D', n, false)) if n < REGISTERS => n,
                    _ => {
                        return err(
                            t.col,
                            t.text.len(),
                            format!(
                                "{mnemonic} needs a data register D0–D7999, not '{}'",
                                t.text
                            ),
                        );
                    }
                };
                pass.program.used_regs.push(n);
                Op::Compare {
                    counter: false,
                    n,
                    value: value(&rest[1], pass)?,
                    at_least: mnemonic == "DC>=",
                }
            }
            "SFR" | "SFRN" => {
                let t = &rest[0];
                let first_bit = match operand(&t.text) {
                    Some(('R', n, false)) => point(Area::R, n, t)?,
                    _ => {
                        return err(
                            t.col,
                            t.text.len(),
                            format!("{mnemonic} needs its first bit R0–R255, not '{}'", t.text),
                        );
                    }
                };
                let k = &rest[1];
                let len = match constant(&k.text) {
                    Some((v, _)) if (1..=256).contains(&v) => v as u32,
                    _ => {
                        return err(
                            k.col,
                            k.text.len(),
                            format!(
                                "{mnemonic}: the number of bits is a constant 1–256, not '{}'",
                                k.text
                            ),
                        );
                    }
                };
                if first_bit + len > Area::R.points() {
                    return err(
                        k.col,
                        k.text.len(),
                        format!("R{first_bit} with {len} bits runs past R255"),
                    );
                }
                pass.program
                    .used_bits
                    .extend((first_bit..first_bit + len).map(|i| (Area::R, i)));
                let pulses = pass.program.pulses;
                pass.program.pulses += 1;
                Op::ShiftRegister {
                    down: mnemonic == "SFRN",
                    first: first_bit,
                    len,
                    pulses,
                }
            }
            "INC" | "DEC" => {
                let t = &rest[0];
                match word(t, ty, Role::Destination, w, 1, pass)? {
                    Word::Reg { n, .. } => Op::Step {
                        up: mnemonic == "INC",
                        ty,
                        reg: n,
                    },
                    _ => {
                        return err(
                            t.col,
                            t.text.len(),
                            format!("{mnemonic} works on a data register (D)"),
                        );
                    }
                }
            }
            "MOV" => {
                let src = word(&rest[0], ty, Role::Source, w, rep, pass)?;
                let dst = word(&rest[1], ty, Role::Destination, w, rep, pass)?;
                Op::Mov {
                    ty,
                    src,
                    dst,
                    rep: rep as u8,
                }
            }
            "CMP=" | "CMP<>" | "CMP<" | "CMP>" | "CMP<=" | "CMP>=" | "ICMP>=" => {
                let rel = match mnemonic {
                    "CMP=" => Rel::Eq,
                    "CMP<>" => Rel::Ne,
                    "CMP<" => Rel::Lt,
                    "CMP>" => Rel::Gt,
                    "CMP<=" => Rel::Le,
                    "CMP>=" => Rel::Ge,
                    _ => Rel::Between,
                };
                let a = word(&rest[0], ty, Role::Source, w, rep, pass)?;
                let b = word(&rest[1], ty, Role::Source, w, rep, pass)?;
                let c = if rel == Rel::Between {
                    word(&rest[2], ty, Role::Source, w, rep, pass)?
                } else {
                    Word::Const(0)
                };
                let (dst, dst_repeat) = dest_point(rest.last().unwrap_or(first), rep, pass)?;
                Op::WordCompare {
                    rel,
                    ty,
                    a,
                    b,
                    c,
                    dst,
                    dst_repeat,
                    rep: rep as u8,
                }
            }
            "ANDW" | "ORW" | "XORW" => {
                let op = match mnemonic {
                    "ANDW" => Logic::And,
                    "ORW" => Logic::Or,
                    _ => Logic::Xor,
                };
                let a = word(&rest[0], ty, Role::Source, w, rep, pass)?;
                let b = word(&rest[1], ty, Role::Source, w, rep, pass)?;
                let dst = word(&rest[2], ty, Role::Destination, w, rep, pass)?;
                Op::WordLogic {
                    op,
                    ty,
                    a,
                    b,
                    dst,
                    rep: rep as u8,
                }
            }
            "SFTL" | "SFTR" => {
                let target = word(&rest[0], ty, Role::InPlace, w, 1, pass)?;
                let k = &rest[1];
                let most = ty.bits() - 1;
                let by = match constant(&k.text) {
                    Some((v, _)) if (1..=i64::from(most)).contains(&v) => v as u8,
                    _ => {
                        return err(
                            k.col,
                            k.text.len(),
                            format!(
                                "{mnemonic}({}): the shift is a constant 1–{most}, not '{}'",
                                ty.letter(),
                                k.text
                            ),
                        );
                    }
                };
                Op::Shift {
                    left: mnemonic == "SFTL",
                    ty,
                    word: target,
                    by,
                }
            }
            "HTOB" | "BTOH" => {
                let src = word(&rest[0], ty, Role::Source, w, rep, pass)?;
                let dst = word(&rest[1], ty, Role::Destination, w, rep, pass)?;
                Op::Convert {
                    to_bcd: mnemonic == "HTOB",
                    ty,
                    src,
                    dst,
                    rep: rep as u8,
                }
            }
            _ => {
                let op = match mnemonic {
                    "ADD" => Arith::Add,
                    "SUB" => Arith::Sub,
                    "MUL" => Arith::Mul,
                    _ => Arith::Div,
                };
                let dst_words = match op {
                    Arith::Add | Arith::Sub => w,
                    Arith::Mul => 2,
                    Arith::Div => 2 * w,
                };
                let a = word(&rest[0], ty, Role::Source, w, rep, pass)?;
                let b = word(&rest[1], ty, Role::Source, w, rep, pass)?;
                // A T or C destination of MUL and DIV takes two (four) timers: still W or I.
                let dst = word(&rest[2], ty, Role::Destination, dst_words, rep, pass)?;
                Op::Arith {
                    op,
                    ty,
                    a,
                    b,
                    dst,
                    rep: rep as u8,
                }
            }
        })
    })();
    (Some(mnemonic), result)
}
