//! One line's instruction: its mnemonic and operands read into an [`Op`], and the notation of
//! other controllers named with what DirectSOFT writes instead.

use super::operands::{
    bit, coil, count, double, is_bcd, is_word, k_hex, label, octal, split, v_addr, v_dest, word,
};
use super::{Error, MNEMONICS, Tok, UNSUPPORTED, err};
use crate::machine::diagnostics::Suggester;
use crate::machine::dl205::program::{
    Bit, BoxDecl, Cmp, CounterKind, Edge, Kind, Logic, Math, Op, Preset, Program, SPECIAL,
    ShiftKind, Src, Table, Test, TimerKind, W, current_word,
};

/// Other controllers' notation, named with what DirectSOFT writes instead (spec §1): line
/// numbers and bare element numbers of DL305/handheld listings, `OR NOT`, `LD X1` for a
/// contact, and the mnemonics of IDEC, Omron, IEC 61131-3 and Allen-Bradley.
fn other_notation(m: &str, ts: &[Tok]) -> Option<Error> {
    let first = &ts[0];
    let args = &ts[1..];
    let digits = |t: &Tok| !t.text.is_empty() && t.text.chars().all(|c| c.is_ascii_digit());
    let message = if digits(first) {
        format!(
            "'{}' is a line number in DL305/handheld notation: DirectSOFT mnemonic text has none, start the line with the mnemonic",
            first.text
        )
    } else if let Some(bare) = (args.iter().enumerate())
        // A timer's or counter's preset is a K constant: its own message says so.
        .filter(|(k, _)| {
            !(*k == 1
                && ["TMR", "TMRF", "TMRA", "TMRAF", "CNT", "SGCNT", "UDC"]
                    .contains(&first.text.to_ascii_uppercase().as_str()))
        })
        .map(|(_, t)| t)
        .find(|t| digits(t) && t.text.len() >= 3)
    {
        return Some(Error {
            col: bare.col,
            message: format!(
                "'{}' is a bare element number in DL305/handheld notation: name the element (X{}, Y{}, C{} …)",
                bare.text,
                bare.text.trim_start_matches('0'),
                bare.text.trim_start_matches('0'),
                bare.text.trim_start_matches('0')
            ),
        });
    } else if let Some(preset) = args.iter().find(|t| {
        t.text.contains('.') && t.text.replace('.', "").chars().all(|c| c.is_ascii_digit())
    }) {
        return Some(Error {
            col: preset.col,
            message: format!(
                "'{}' is a decimal preset in DL305/handheld notation: write K and the digits, e.g. K30 for 3.0 s",
                preset.text
            ),
        });
    } else if matches!(m, "OR" | "AND" | "STR")
        && args
            .first()
            .is_some_and(|t| t.text.eq_ignore_ascii_case("NOT"))
    {
        format!("{m} NOT: DirectSOFT writes {m}N")
    } else if m == "LD"
        && args.first().is_some_and(|t| {
            let (letters, _) = split(t);
            matches!(letters.as_str(), "X" | "Y" | "C" | "S" | "T" | "CT" | "SP")
        })
    {
        format!(
            "LD loads the accumulator: a contact on {} is STR {}",
            args[0].text, args[0].text
        )
    } else {
        let (origin, instead) = match m {
            "LOD" | "LODN" => ("IDEC", "STR / STRN"),
            "TIM" | "TIMH" | "CNTR" => ("Omron", "TMR / CNT"),
            "TON" | "TOF" | "TP" => ("IEC 61131-3", "TMR"),
            "CTU" | "CTD" | "CTUD" => ("IEC 61131-3", "CNT / UDC"),
            "XIC" | "XIO" => ("Allen-Bradley", "STR / STRN"),
            "OTE" | "OTL" | "OTU" => ("Allen-Bradley", "OUT / SET / RST"),
            _ => return None,
        };
        format!("{m} is {origin} notation: DirectSOFT writes {instead}")
    };
    Some(Error {
        col: first.col,
        message,
    })
}

pub(super) fn instruction(
    ts: &[Tok],
    program: &mut Program,
    suggester: &Suggester,
) -> Result<Op, Error> {
    let first = &ts[0];
    let m = first.text.to_ascii_uppercase();
    let args = &ts[1..];
    if let Some(e) = other_notation(&m, ts) {
        return Err(e);
    }
    if !MNEMONICS.contains(&m.as_str()) {
        if UNSUPPORTED.contains(&m.as_str()) {
            return err(
                first.col,
                format!("{m} is a DL205 instruction not supported by servoscope yet"),
            );
        }
        let hint = match m.as_str() {
            "INC" => Some("INCB"),
            "DEC" => Some("DECB"),
            _ => suggester.suggest(&m, MNEMONICS.iter().copied()),
        };
        let hint = hint
            .map(|s| format!(" (did you mean {s}?)"))
            .unwrap_or_default();
        return err(
            first.col,
            format!("unknown mnemonic '{}'{hint}", first.text),
        );
    }
    let want = |n: usize| -> Result<(), Error> {
        if args.len() == n {
            Ok(())
        } else {
            let col = args.get(n).or(args.first()).map_or(first.col, |t| t.col);
            err(
                col,
                format!("{m} takes {n} operand(s), found {}", args.len()),
            )
        }
    };
    let contact = |program: &mut Program, neg_bit: bool, cmp: Option<Cmp>| -> Result<Test, Error> {
        match (args.len(), cmp) {
            (1, None) => Ok(Test::Bit(bit(&args[0], program)?, neg_bit)),
            (2, c) => {
                let a = v_addr(&args[0], false, program)?;
                let b = word(&args[1], true, false, 0, 0xFFFF, program)?;
                let kind = c.unwrap_or(if neg_bit { Cmp::Lt } else { Cmp::Ge });
                Ok(Test::Compare(a, b, kind))
            }
            _ => {
                let col = args.get(2).or(args.first()).map_or(first.col, |t| t.col);
                err(
                    col,
                    format!(
                        "{m} takes a bit, or a V word and a value to compare, found {} operand(s)",
                        args.len()
                    ),
                )
            }
        }
    };
    Ok(match m.as_str() {
        "STR" | "STRN" => Op::Str(contact(program, m == "STRN", None)?),
        "AND" | "OR" | "XOR" if args.len() == 1 && is_word(&args[0]) => {
            let logic = match m.as_str() {
                "AND" => Logic::And,
                "OR" => Logic::Or,
                _ => Logic::Xor,
            };
            Op::LogicV(logic, v_addr(&args[0], false, program)?)
        }
        "XOR" => {
            want(1)?;
            return err(args[0].col, "XOR takes a V-memory word");
        }
        "AND" | "ANDN" => Op::And(contact(program, m == "ANDN", None)?),
        "OR" | "ORN" => Op::Or(contact(program, m == "ORN", None)?),
        "STRE" | "STRNE" | "ANDE" | "ANDNE" | "ORE" | "ORNE" => {
            want(2)?;
            let c = if m.contains("NE") { Cmp::Ne } else { Cmp::Eq };
            let t = contact(program, false, Some(c))?;
            match &m[..2] {
                "ST" => Op::Str(t),
                "AN" => Op::And(t),
                _ => Op::Or(t),
            }
        }
        "ANDSTR" => {
            want(0)?;
            Op::AndStr
        }
        "ORSTR" => {
            want(0)?;
            Op::OrStr
        }
        "OUT" => {
            want(1)?;
            let t = &args[0];
            if is_word(t) {
                Op::OutV(v_dest(t, false, program)?)
            } else {
                Op::Coil(coil(t, "OUT", program)?)
            }
        }
        "SET" | "RST" => {
            if args.is_empty() || args.len() > 2 {
                let col = args.get(2).or(args.first()).map_or(first.col, |t| t.col);
                return err(col, format!("{m} takes one element or a range of two"));
            }
            let a = bit(&args[0], program)?;
            let resets_box = m == "RST" && matches!(a.kind, Kind::T | Kind::Ct);
            if !resets_box && !matches!(a.kind, Kind::Y | Kind::C | Kind::S) {
                let kinds = if m == "RST" {
                    "Y, C, S, T or CT"
                } else {
                    "Y, C or S"
                };
                return err(
                    args[0].col,
                    format!("{} cannot be written: {m} needs {kinds}", args[0].text),
                );
            }
            let b = match args.get(1) {
                Some(t) => {
                    let b = bit(t, program)?;
                    if b.kind != a.kind || b.n < a.n {
                        return err(
                            t.col,
                            format!(
                                "{m} range {}–{} must stay in one kind and run upwards",
                                args[0].text, t.text
                            ),
                        );
                    }
                    b
                }
                None => a,
            };
            if m == "SET" {
                Op::Set(a, b)
            } else {
                Op::Rst(a, b)
            }
        }
        "STRPD" | "STRND" | "ANDPD" | "ANDND" | "ORPD" | "ORND" => {
            want(1)?;
            let edge = if m.ends_with("PD") {
                Edge::Rising
            } else {
                Edge::Falling
            };
            let t = Test::Edge(bit(&args[0], program)?, edge, program.edges);
            program.edges += 1;
            match &m[..2] {
                "ST" => Op::Str(t),
                "AN" => Op::And(t),
                _ => Op::Or(t),
            }
        }
        "NOT" | "INV" => {
            want(0)?;
            if m == "NOT" { Op::Not } else { Op::Inv }
        }
        "PD" => {
            want(1)?;
            let b = coil(&args[0], "PD", program)?;
            program.edges += 1;
            Op::Pd(b, program.edges - 1)
        }
        "OROUT" => {
            want(1)?;
            let b = coil(&args[0], "OROUT", program)?;
            let mark = match program.orout_bits.iter().position(|&o| o == b) {
                Some(i) => i,
                None => {
                    program.orout_bits.push(b);
                    program.orout_bits.len() - 1
                }
            };
            Op::OrOut(b, mark as u32)
        }
        "CMP" => {
            want(1)?;
            Op::Cmp(word(&args[0], true, false, 0, 0xFFFF, program)?)
        }
        "CMPD" => {
            want(1)?;
            Op::CmpD(double(&args[0], true, false, program)?)
        }
        "TMR" | "TMRF" | "TMRA" | "TMRAF" | "CNT" | "SGCNT" | "UDC" => {
            want(2)?;
            let timer = m.starts_with("TMR");
            let kind = if timer { Kind::T } else { Kind::Ct };
            let (letters, digits) = split(&args[0]);
            if letters != kind.letter() {
                let what = if timer {
                    "a timer number T0–T377"
                } else {
                    "a counter number CT0–CT377"
                };
                return err(
                    args[0].col,
                    format!("{m} needs {what}, found '{}'", args[0].text),
                );
            }
            let n = octal(digits, &args[0])?;
            let wide = matches!(m.as_str(), "TMRA" | "TMRAF" | "UDC");
            let last = kind.count() - 1 - u32::from(wide);
            if n > last {
                let also = if wide {
                    " (it also takes the next number)"
                } else {
                    ""
                };
                return err(
                    args[0].col,
                    format!(
                        "{} is out of range ({}0–{}{last:o}){also}",
                        args[0].text,
                        kind.letter(),
                        kind.letter()
                    ),
                );
            }
            let p = &args[1];
            let preset = if is_word(p) {
                let a = v_addr(p, wide, program)?;
                if wide {
                    Preset::Pair(a)
                } else {
                    Preset::Word(a)
                }
            } else {
                let Some(k) = k_hex(p) else {
                    // A bare number is the commonest slip: say what K it means in this box.
                    let hint = match p.text.parse::<u32>() {
                        Ok(n) if timer => {
                            let (unit, per_second) = if m.ends_with('F') {
                                ("hundredths", 100)
                            } else {
                                ("tenths", 10)
                            };
                            format!(
                                ": write K{n} (= {}.{:0width$} s, in {unit} of a second)",
                                n / per_second,
                                n % per_second,
                                width = if per_second == 100 { 2 } else { 1 }
                            )
                        }
                        Ok(n) => format!(": write K{n} ({n} counts)"),
                        Err(_) => String::new(),
                    };
                    return err(
                        p.col,
                        format!("'{}': the preset is a K constant or a V word{hint}", p.text),
                    );
                };
                if !is_bcd(k) {
                    return err(
                        p.col,
                        format!("{} is not BCD: presets are BCD digits 0–9", p.text),
                    );
                }
                if !wide && k > 0x9999 {
                    return err(p.col, format!("{} is out of range (K0–K9999)", p.text));
                }
                Preset::K(k)
            };
            let status = Bit { kind, n };
            program.used_bits.push(status);
            let words = 1 + u32::from(wide);
            let value = current_word(kind, n);
            program.used_v.extend(value..value + words);
            let op = match m.as_str() {
                "TMR" => Op::Timer(TimerKind::Tmr, n, preset),
                "TMRF" => Op::Timer(TimerKind::Tmrf, n, preset),
                "TMRA" => Op::Timer(TimerKind::Tmra, n, preset),
                "TMRAF" => Op::Timer(TimerKind::Tmraf, n, preset),
                "CNT" => Op::Counter(CounterKind::Cnt, n, preset),
                "SGCNT" => Op::Counter(CounterKind::Sgcnt, n, preset),
                _ => Op::Counter(CounterKind::Udc, n, preset),
            };
            program.boxes.push(BoxDecl {
                status,
                words,
                preset,
                instr: program.instrs.len(),
            });
            op
        }
        "GOTO" | "GTS" | "LBL" | "SBR" => {
            want(1)?;
            let k = label(&args[0])?;
            match m.as_str() {
                // Targets hold the label until `control` resolves them.
                "GOTO" => Op::Goto(u32::from(k)),
                "GTS" => Op::Gts(u32::from(k)),
                "LBL" => Op::Lbl(k),
                _ => Op::Sbr(k),
            }
        }
        "FOR" => {
            want(1)?;
            Op::For(word(&args[0], true, true, 1, 0x9999, program)?, 0)
        }
        "NEXT" | "RT" | "RTC" => {
            want(0)?;
            match m.as_str() {
                "NEXT" => Op::Next(0),
                "RT" => Op::Rt,
                _ => Op::Rtc,
            }
        }
        "MLS" | "MLR" => {
            want(1)?;
            let (lo, hi) = if m == "MLS" { (1, 7) } else { (0, 6) };
            let n = match k_hex(&args[0]) {
                Some(n) if (lo..=hi).contains(&n) => n as u8,
                _ => {
                    return err(
                        args[0].col,
                        format!("'{}': {m} takes a level K{lo}–K{hi}", args[0].text),
                    );
                }
            };
            if m == "MLS" { Op::Mls(n) } else { Op::Mlr(n) }
        }
        "SG" | "ISG" | "JMP" | "NJMP" => {
            want(1)?;
            let b = bit(&args[0], program)?;
            if b.kind != Kind::S {
                return err(
                    args[0].col,
                    format!("{m} takes a stage S0–S1777, found '{}'", args[0].text),
                );
            }
            match m.as_str() {
                "SG" | "ISG" => Op::Sg {
                    stage: b.n,
                    initial: m == "ISG",
                    next: 0,
                },
                // The enclosing stage is found by `control`.
                "JMP" => Op::Jmp { to: b.n, own: 0 },
                _ => Op::Njmp { to: b.n, own: 0 },
            }
        }
        "MOV" => {
            want(1)?;
            Op::Table(Table::Mov, v_dest(&args[0], false, program)?)
        }
        "SETBIT" | "RSTBIT" => {
            want(1)?;
            let (letters, digits) = split(&args[0]);
            if letters != "O" {
                return err(
                    args[0].col,
                    format!(
                        "'{}': {m} takes a bit number as an octal constant On",
                        args[0].text
                    ),
                );
            }
            let n = octal(digits, &args[0])?;
            if n > 0o177777 {
                return err(
                    args[0].col,
                    format!("{} is out of range (O0–O177777)", args[0].text),
                );
            }
            Op::Table(
                if m == "SETBIT" {
                    Table::SetBit
                } else {
                    Table::RstBit
                },
                n,
            )
        }
        "END" => {
            want(0)?;
            Op::End
        }
        "NOP" => {
            want(0)?;
            Op::Nop
        }
        "POP" | "ADDS" | "SUBS" | "MULS" | "DIVS" | "ADDBS" | "SUBBS" | "MULBS" | "DIVBS"
        | "BIN" | "BCD" | "ANDS" | "ORS" | "XORS" => {
            want(0)?;
            match m.as_str() {
                "POP" => Op::Pop,
                "ADDS" => Op::Bcd(Math::Add, Src::Stack),
                "SUBS" => Op::Bcd(Math::Sub, Src::Stack),
                "MULS" => Op::Bcd(Math::Mul, Src::Stack),
                "DIVS" => Op::Bcd(Math::Div, Src::Stack),
                "ADDBS" => Op::Binary(Math::Add, Src::Stack),
                "SUBBS" => Op::Binary(Math::Sub, Src::Stack),
                "MULBS" => Op::Binary(Math::Mul, Src::Stack),
                "DIVBS" => Op::Binary(Math::Div, Src::Stack),
                "BIN" => Op::ToBin,
                "BCD" => Op::ToBcd,
                "ANDS" => Op::LogicS(Logic::And),
                "ORS" => Op::LogicS(Logic::Or),
                _ => Op::LogicS(Logic::Xor),
            }
        }
        _ => {
            want(if matches!(m.as_str(), "LDF" | "OUTF") {
                2
            } else {
                1
            })?;
            let t = &args[0];
            match m.as_str() {
                "LD" => Op::Ld(word(t, true, false, 0, 0xFFFF, program)?),
                "LDD" => Op::Ldd(double(t, true, false, program)?),
                "LDA" => {
                    let (letters, digits) = split(t);
                    if letters != "O" {
                        return err(
                            t.col,
                            format!("'{}': LDA takes an octal constant On", t.text),
                        );
                    }
                    let n = octal(digits, t)?;
                    if n > 0o177777 {
                        return err(t.col, format!("{} is out of range (O0–O177777)", t.text));
                    }
                    Op::Lda(n)
                }
                "LDF" | "OUTF" => {
                    let e = bit(t, program)?;
                    let n = count(&args[1])?;
                    // Spec §6.2: OUTF writes Y, C or S; X, SP, T and CT bits are not the program's.
                    if m == "OUTF" && matches!(e.kind, Kind::X | Kind::Sp | Kind::T | Kind::Ct) {
                        return err(
                            t.col,
                            format!("{} cannot be written: OUTF needs Y, C or S", t.text),
                        );
                    }
                    if e.kind == Kind::Sp {
                        // Every relay in the range must be modelled.
                        let start = SPECIAL[e.n as usize];
                        if (start..start + u32::from(n)).any(|s| !SPECIAL.contains(&s)) {
                            return err(
                                t.col,
                                format!(
                                    "{} with K{n} covers special relays not supported by servoscope yet",
                                    t.text
                                ),
                            );
                        }
                    } else if e.n + u32::from(n) > e.kind.count() {
                        return err(
                            args[1].col,
                            format!(
                                "{} with {} runs past the last {} element",
                                t.text,
                                args[1].text,
                                e.kind.letter()
                            ),
                        );
                    } else {
                        program
                            .used_bits
                            .extend((e.n..e.n + u32::from(n)).map(|i| Bit { kind: e.kind, n: i }));
                    }
                    if m == "LDF" {
                        Op::Ldf(e, n)
                    } else {
                        Op::OutF(e, n)
                    }
                }
                "OUTD" => Op::OutD(v_dest(t, true, program)?),
                "ADD" => Op::Bcd(
                    Math::Add,
                    Src::Word(word(t, false, true, 0, 0x9999, program)?),
                ),
                "SUB" => Op::Bcd(
                    Math::Sub,
                    Src::Word(word(t, false, true, 0, 0x9999, program)?),
                ),
                "ADDD" => Op::Bcd(Math::Add, Src::Double(double(t, true, true, program)?)),
                "SUBD" => Op::Bcd(Math::Sub, Src::Double(double(t, true, true, program)?)),
                "MUL" => Op::Bcd(
                    Math::Mul,
                    Src::Word(word(t, true, true, 0, 0x9999, program)?),
                ),
                "MULD" => Op::Bcd(Math::Mul, Src::Double(double(t, false, true, program)?)),
                "DIV" => Op::Bcd(
                    Math::Div,
                    Src::Word(word(t, true, true, 1, 0x9999, program)?),
                ),
                "DIVD" => Op::Bcd(Math::Div, Src::Double(double(t, false, true, program)?)),
                "ADDB" => Op::Binary(
                    Math::Add,
                    Src::Word(word(t, true, false, 0, 0xFFFF, program)?),
                ),
                "SUBB" => Op::Binary(
                    Math::Sub,
                    Src::Word(word(t, true, false, 0, 0xFFFF, program)?),
                ),
                "ADDBD" => Op::Binary(Math::Add, Src::Double(double(t, true, false, program)?)),
                "SUBBD" => Op::Binary(Math::Sub, Src::Double(double(t, true, false, program)?)),
                "MULB" => Op::Binary(
                    Math::Mul,
                    Src::Word(word(t, true, false, 0, 0xFFFF, program)?),
                ),
                "DIVB" => Op::Binary(
                    Math::Div,
                    Src::Word(word(t, true, false, 1, 0xFFFF, program)?),
                ),
                "INCB" => Op::IncB(v_dest(t, false, program)?),
                "DECB" => Op::DecB(v_dest(t, false, program)?),
                "ANDD" => Op::LogicD(Logic::And, double(t, true, false, program)?),
                "ORD" => Op::LogicD(Logic::Or, double(t, true, false, program)?),
                "XORD" => Op::LogicD(Logic::Xor, double(t, true, false, program)?),
                _ => {
                    let kind = match m.as_str() {
                        "SHFL" => ShiftKind::Shfl,
                        "SHFR" => ShiftKind::Shfr,
                        "ROTL" => ShiftKind::Rotl,
                        _ => ShiftKind::Rotr,
                    };
                    let n = if t.text.to_ascii_uppercase().starts_with('V') {
                        W::V(v_addr(t, false, program)?)
                    } else {
                        W::K(u16::from(count(t)?))
                    };
                    Op::Shift(kind, n)
                }
            }
        }
    })
}
