//! DirectSOFT mnemonic text → [`Program`] (spec §1, §2, §6.8). Every faulty line is reported
//! once; the rung-structure checks run only when every line is valid.

use super::program::{
    Bit, BoxDecl, Cmp, CounterKind, D, Edge, Instr, Kind, Logic, MAPPED, Math, Op, Preset, Program,
    SPECIAL, ShiftKind, Src, Table, Test, TimerKind, W, box_shape, current_word, mapped,
    writable_word,
};
use crate::machine::Diagnostic;
use crate::machine::diagnostics::Suggester;

pub const MNEMONICS: &[&str] = &[
    "STR", "STRN", "AND", "ANDN", "OR", "ORN", "STRE", "STRNE", "ANDE", "ANDNE", "ORE", "ORNE",
    "ANDSTR", "ORSTR", "OUT", "SET", "RST", "END", "NOP", "LD", "LDD", "LDA", "LDF", "OUTD",
    "OUTF", "POP", "ADD", "SUB", "ADDD", "SUBD", "ADDS", "SUBS", "MUL", "MULS", "MULD", "DIV",
    "DIVD", "DIVS", "ADDB", "ADDBD", "ADDBS", "SUBB", "SUBBD", "SUBBS", "MULB", "MULBS", "DIVB",
    "DIVBS", "INCB", "DECB", "BIN", "BCD", "XOR", "ANDD", "ORD", "XORD", "ANDS", "ORS", "XORS",
    "SHFL", "SHFR", "ROTL", "ROTR", "NOT", "STRPD", "STRND", "ANDPD", "ANDND", "ORPD", "ORND",
    "PD", "OROUT", "INV", "CMP", "CMPD", "TMR", "TMRF", "TMRA", "TMRAF", "CNT", "SGCNT", "UDC",
    "GOTO", "LBL", "FOR", "NEXT", "GTS", "SBR", "RT", "RTC", "MLS", "MLR", "SG", "ISG", "JMP",
    "NJMP", "MOV", "SETBIT", "RSTBIT",
];

pub const UNSUPPORTED: &[&str] = &[
    "DRUM", "EDRUM", "MDRMD", "MDRMW", "SR", "OROUTN", "MOVW", "FILL", "FIND", "FDGT", "FDGTHS",
    "TSHFL", "TSHFR", "STRI", "STRNI", "ANDI", "ANDNI", "ORI", "ORNI", "OUTI", "SETI", "RSTI",
    "LDI", "LDIF", "OUTIF", "CMPS", "CMPR", "CMPF", "ENCO", "DECO", "SUM", "LDX", "LDSX", "OUTX",
    "OUTL", "LDR", "ADDR", "SUBR", "MULR", "DIVR", "ADDF", "SUBF", "MULF", "DIVF", "ANDF", "ORF",
    "XORF", "SQRTR", "MOVMC", "LDLBL", "BCDCPL", "BTOR", "RTOB", "ATH", "HTA", "SEG", "GRAY",
    "SFLDGT", "SWAP", "TTD", "RTD", "CV", "CVJMP", "BCALL", "BEND", "BREAK", "INT", "IRT", "IRTC",
    "ENI", "DISI", "STOP", "PAUSE", "RD", "WT", "RX", "WX", "PRINT", "DLBL", "NCON", "ACON",
    "FAULT",
];

const V_WORDS: u32 = 0o40000;
const STACK_LEVELS: usize = 8;

struct Error {
    col: usize,
    message: String,
}

fn err<T>(col: usize, message: impl Into<String>) -> Result<T, Error> {
    Err(Error {
        col,
        message: message.into(),
    })
}

#[derive(Clone, Debug)]
struct Tok {
    text: String,
    col: usize,
}

fn octal(digits: &str, t: &Tok) -> Result<u32, Error> {
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
fn split(t: &Tok) -> (String, &str) {
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

fn bit(t: &Tok, program: &mut Program) -> Result<Bit, Error> {
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

fn v_addr(t: &Tok, pair: bool, program: &mut Program) -> Result<u32, Error> {
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
fn v_dest(t: &Tok, pair: bool, program: &mut Program) -> Result<u32, Error> {
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
fn k_hex(t: &Tok) -> Option<u32> {
    let (letters, digits) = (t.text.get(..1)?, t.text.get(1..)?);
    if !letters.eq_ignore_ascii_case("K") || digits.is_empty() || digits.len() > 8 {
        return None;
    }
    u32::from_str_radix(digits, 16).ok()
}

fn is_bcd(v: u32) -> bool {
    (0..8).all(|i| v >> (4 * i) & 0xF <= 9)
}

/// Whether a token names a V word (Vn, TAn, CTAn) rather than a constant.
fn is_word(t: &Tok) -> bool {
    let (letters, _) = split(t);
    matches!(letters.as_str(), "V" | "TA" | "CTA") || MAPPED.iter().any(|m| m.3 == letters)
}

/// A 16-bit source: V, or K up to `max` (BCD-checked when `bcd`).
fn word(
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

fn double(t: &Tok, allow_k: bool, bcd: bool, program: &mut Program) -> Result<D, Error> {
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
fn count(t: &Tok) -> Result<u8, Error> {
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
    } else if let Some(bare) = args.iter().find(|t| digits(t) && t.text.len() >= 3) {
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

/// A label or subroutine number: K0–KFFFF (hex digits, as DirectSOFT writes them).
fn label(t: &Tok) -> Result<u16, Error> {
    match k_hex(t) {
        Some(k) if k <= 0xFFFF => Ok(k as u16),
        _ => err(
            t.col,
            format!("'{}' is not a label number K0–KFFFF", t.text),
        ),
    }
}

/// The bit a coil (OUT, PD, OROUT) writes: Y, C or S.
fn coil(t: &Tok, mnemonic: &str, program: &mut Program) -> Result<Bit, Error> {
    let b = bit(t, program)?;
    if !matches!(b.kind, Kind::Y | Kind::C | Kind::S) {
        return err(
            t.col,
            format!("{} cannot be written: {mnemonic} needs Y, C or S", t.text),
        );
    }
    Ok(b)
}

fn instruction(ts: &[Tok], program: &mut Program, suggester: &Suggester) -> Result<Op, Error> {
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
                    return err(
                        p.col,
                        format!("'{}': the preset is a K constant or a V word", p.text),
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

/// The blocks of spec §2 (main part, stages, subroutines after END) and the program-control
/// instructions checked against them; on success their targets are resolved to instruction
/// indices: GOTO → its LBL, GTS → its SBR, FOR ↔ NEXT, SG → the next SG/ISG/END, JMP → the
/// enclosing stage.
fn control(instrs: &mut [Instr]) -> Vec<(usize, String)> {
    use std::collections::HashMap;
    let mut errors = Vec::new();
    let n = instrs.len();
    let Some(end) = instrs.iter().position(|i| i.op == Op::End) else {
        return errors;
    };
    // Which block each instruction is in: 0 the main part, 1 + i the stage whose SG/ISG is at
    // i, n + 1 + i the subroutine whose SBR is at i; None: outside any (after END).
    let mut block: Vec<Option<usize>> = vec![None; n];
    let mut labels: HashMap<u16, usize> = HashMap::new();
    let mut subroutines: HashMap<u16, usize> = HashMap::new();
    let mut stages: HashMap<u32, usize> = HashMap::new();
    let mut stage = None;
    let mut sub: Option<usize> = None;
    for i in 0..n {
        let ins = &instrs[i];
        if i <= end {
            match ins.op {
                Op::Sg { stage: s, .. } => {
                    if let Some(&first) = stages.get(&s) {
                        errors.push((
                            ins.line,
                            format!(
                                "stage S{s:o} already has its SG/ISG on line {}",
                                instrs[first].line
                            ),
                        ));
                    }
                    stages.insert(s, i);
                    stage = Some(i);
                }
                Op::Rt | Op::Rtc => errors.push((
                    ins.line,
                    format!(
                        "{} outside a subroutine: subroutines come after END, SBR … RT",
                        ins.mnemonic
                    ),
                )),
                Op::Sbr(_) => errors.push((
                    ins.line,
                    "SBR before END: subroutines come after the main program's END".into(),
                )),
                _ => {}
            }
            block[i] = Some(stage.map_or(0, |s| 1 + s));
            continue;
        }
        match ins.op {
            Op::Sbr(k) => {
                if sub.is_some() {
                    errors.push((
                        ins.line,
                        "SBR inside a subroutine: end the one before with RT".into(),
                    ));
                }
                if let Some(&first) = subroutines.get(&k) {
                    errors.push((
                        ins.line,
                        format!(
                            "SBR K{k:X} is already defined on line {}",
                            instrs[first].line
                        ),
                    ));
                }
                subroutines.insert(k, i);
                sub = Some(i);
            }
            Op::End => errors.push((
                ins.line,
                "END in a subroutine: a subroutine ends with RT".into(),
            )),
            Op::Sg { .. } => errors.push((
                ins.line,
                format!(
                    "{} in a subroutine: stages belong to the main program",
                    ins.mnemonic
                ),
            )),
            _ if sub.is_none() => {
                errors.push((
                    ins.line,
                    format!(
                        "{} after END: only subroutines (SBR … RT) may follow END",
                        ins.mnemonic
                    ),
                ));
            }
            _ => {}
        }
        block[i] = sub.map(|s| n + 1 + s);
        if ins.op == Op::Rt {
            sub = None;
        }
    }
    if let Some(open) = sub {
        errors.push((instrs[open].line, "SBR without RT".into()));
    }

    // Labels, FOR … NEXT and master-line levels, block by block in program order.
    let mut open_for: Option<usize> = None;
    let mut in_loop: Vec<Option<usize>> = vec![None; n];
    let mut level = 0u8;
    for i in 0..n {
        let starts_block = i == 0 || block[i] != block[i - 1];
        if starts_block {
            if let Some(f) = open_for.take() {
                errors.push((instrs[f].line, "FOR without NEXT in its block".into()));
            }
            level = 0;
        }
        let ins = &instrs[i];
        match ins.op {
            Op::Lbl(k) => {
                if let Some(&first) = labels.get(&k) {
                    errors.push((
                        ins.line,
                        format!(
                            "LBL K{k:X} is already defined on line {}",
                            instrs[first].line
                        ),
                    ));
                }
                labels.insert(k, i);
            }
            Op::For(..) => {
                if open_for.is_some() {
                    errors.push((ins.line, "FOR inside a FOR loop: loops do not nest".into()));
                } else {
                    open_for = Some(i);
                }
            }
            Op::Next(_) => match open_for.take() {
                Some(f) => {
                    in_loop[f] = Some(f);
                    in_loop[i] = Some(f);
                    if let Op::For(c, _) = instrs[f].op {
                        instrs[f].op = Op::For(c, i as u32);
                    }
                    instrs[i].op = Op::Next(f as u32);
                    continue;
                }
                None => errors.push((ins.line, "NEXT without FOR".into())),
            },
            Op::Sbr(_) | Op::Sg { .. } => level = 0,
            Op::Mls(k) => {
                if k != level + 1 {
                    errors.push((
                        ins.line,
                        format!(
                            "MLS K{k} must follow level {}: the current level is {level}",
                            k - 1
                        ),
                    ));
                }
                level = k;
            }
            Op::Mlr(k) => {
                if k >= level {
                    errors.push((
                        ins.line,
                        format!("MLR K{k} must be below the current level {level}"),
                    ));
                }
                level = k.min(level);
            }
            _ => {}
        }
        in_loop[i] = open_for;
    }
    if let Some(f) = open_for {
        errors.push((instrs[f].line, "FOR without NEXT in its block".into()));
    }

    // Jumps, calls and stage jumps.
    let mut calls: HashMap<usize, Vec<(usize, usize)>> = HashMap::new();
    for i in 0..n {
        let ins = &instrs[i];
        match ins.op {
            Op::Goto(k) => match labels.get(&(k as u16)) {
                None => errors.push((ins.line, format!("GOTO K{k:X}: no LBL K{k:X}"))),
                Some(&to) if to <= i => errors.push((
                    ins.line,
                    format!(
                        "GOTO K{k:X} jumps backwards (to line {}): GOTO only jumps forward",
                        instrs[to].line
                    ),
                )),
                Some(&to) if block[to] != block[i] || in_loop[to] != in_loop[i] => {
                    errors.push((ins.line, format!("GOTO K{k:X} leaves its block (stage, subroutine or FOR loop): LBL K{k:X} is on line {}", instrs[to].line)));
                }
                Some(&to) => instrs[i].op = Op::Goto(to as u32),
            },
            Op::Gts(k) => match subroutines.get(&(k as u16)) {
                None => errors.push((ins.line, format!("GTS K{k:X}: no SBR K{k:X}"))),
                Some(&to) => {
                    let caller = block[i]
                        .filter(|&b| b > n)
                        .map_or(usize::MAX, |b| b - n - 1);
                    calls.entry(caller).or_default().push((to, i));
                    instrs[i].op = Op::Gts(to as u32);
                }
            },
            Op::Jmp { to, .. } | Op::Njmp { to, .. } => {
                let own = match block[i] {
                    Some(b) if b >= 1 && b <= n => match instrs[b - 1].op {
                        Op::Sg { stage, .. } => Some(stage),
                        _ => None,
                    },
                    _ => None,
                };
                match own {
                    None => errors.push((
                        ins.line,
                        format!(
                            "{} outside a stage: it belongs after an SG or ISG",
                            ins.mnemonic
                        ),
                    )),
                    Some(_) if !stages.contains_key(&to) => errors.push((
                        ins.line,
                        format!("{} S{to:o}: no SG or ISG S{to:o}", ins.mnemonic),
                    )),
                    Some(own) => {
                        instrs[i].op = if matches!(ins.op, Op::Jmp { .. }) {
                            Op::Jmp { to, own }
                        } else {
                            Op::Njmp { to, own }
                        };
                    }
                }
            }
            Op::Sg { stage, initial, .. } => {
                let next = (i + 1..n)
                    .find(|&j| matches!(instrs[j].op, Op::Sg { .. } | Op::End))
                    .unwrap_or(end);
                instrs[i].op = Op::Sg {
                    stage,
                    initial,
                    next: next as u32,
                };
            }
            _ => {}
        }
    }
    // Calls: no recursion, at most 8 deep (so a run never faults).
    fn depth(
        sub: usize,
        calls: &std::collections::HashMap<usize, Vec<(usize, usize)>>,
        path: &mut Vec<usize>,
    ) -> Result<usize, usize> {
        if path.contains(&sub) {
            return Err(sub);
        }
        path.push(sub);
        let mut deepest = 0;
        for &(callee, _) in calls.get(&sub).map_or(&[][..], |v| v.as_slice()) {
            deepest = deepest.max(depth(callee, calls, path)? + 1);
        }
        path.pop();
        Ok(deepest)
    }
    for (&caller, list) in &calls {
        for &(callee, at) in list {
            let line = instrs[at].line;
            let mut path = if caller == usize::MAX {
                Vec::new()
            } else {
                vec![caller]
            };
            match depth(callee, &calls, &mut path) {
                Err(_) => errors.push((
                    line,
                    format!(
                        "{}: recursion: a subroutine may not call itself, directly or not",
                        instrs[at].text
                    ),
                )),
                Ok(d) if caller == usize::MAX && d + 1 > super::CALL_DEPTH => {
                    errors.push((
                        line,
                        format!(
                            "{}: calls nested {} deep (at most {})",
                            instrs[at].text,
                            d + 1,
                            super::CALL_DEPTH
                        ),
                    ));
                }
                Ok(_) => {}
            }
        }
    }
    errors.sort();
    errors.dedup();
    errors
}

/// One box per timer or counter number; a two-word box takes n and n + 1 (spec §2).
fn boxes_once(instrs: &[Instr], errors: &mut Vec<(usize, String)>) {
    let mut owner: std::collections::HashMap<Bit, usize> = std::collections::HashMap::new();
    for ins in instrs {
        let (kind, n) = match ins.op {
            Op::Timer(_, n, _) => (Kind::T, n),
            Op::Counter(_, n, _) => (Kind::Ct, n),
            _ => continue,
        };
        let words = box_shape(&ins.op).map_or(1, |(w, _)| w);
        for k in n..n + words {
            let b = Bit { kind, n: k };
            if let Some(&line) = owner.get(&b) {
                let name = super::program::bit_name(b);
                errors.push((
                    ins.line,
                    format!("{name} is already used by the box on line {line}: one box per number"),
                ));
                break;
            }
            owner.insert(b, ins.line);
        }
    }
}

/// The rung checks of spec §2: (line, message).
fn rungs(instrs: &[Instr]) -> Vec<(usize, String)> {
    let mut errors = Vec::new();
    let mut levels: usize = 0;
    let mut in_rung = false;
    let mut has_output = false;
    let mut end_line = None;
    // The multi-input box that ended the rung: only a new rung, NOP or END may follow.
    let mut after_box: Option<String> = None;
    for ins in instrs {
        match ins.op {
            Op::Nop => continue,
            op if op.is_standalone() => {
                if in_rung && !has_output {
                    errors.push((
                        ins.line,
                        format!("a rung with no output before {}", ins.mnemonic),
                    ));
                }
                in_rung = false;
                if op == Op::End && end_line.is_none() {
                    end_line = Some(ins.line);
                }
            }
            Op::Str(_) => {
                // A new rung when there is none or this one has its output; a branch otherwise.
                if !in_rung || has_output {
                    in_rung = true;
                    has_output = false;
                    levels = 0;
                }
                levels += 1;
                if levels > STACK_LEVELS {
                    errors.push((ins.line, "more than 8 levels on the boolean stack".into()));
                }
            }
            Op::And(_) | Op::Or(_) | Op::Not => {
                if after_box.is_some() {
                    errors.push((
                        ins.line,
                        format!(
                            "{} after {}: it ends its rung; start a new rung with STR",
                            ins.mnemonic,
                            after_box.unwrap_or_default()
                        ),
                    ));
                } else if !in_rung {
                    errors.push((
                        ins.line,
                        format!("{} needs a rung: start it with STR", ins.mnemonic),
                    ));
                }
            }
            Op::AndStr | Op::OrStr => {
                if !in_rung {
                    errors.push((
                        ins.line,
                        format!("{} needs a rung: start it with STR", ins.mnemonic),
                    ));
                } else if levels < 2 {
                    errors.push((
                        ins.line,
                        format!("{} needs two levels on the boolean stack", ins.mnemonic),
                    ));
                } else {
                    levels -= 1;
                }
            }
            op => {
                let legs = box_shape(&op).map_or(1, |(_, legs)| legs);
                if !in_rung {
                    errors.push((
                        ins.line,
                        "needs a rung condition: start the rung with a contact, e.g. STR SP1"
                            .into(),
                    ));
                } else if let Some(boxed) = &after_box {
                    errors.push((
                        ins.line,
                        format!(
                            "{} after {boxed}: it ends its rung; start a new rung with STR",
                            ins.mnemonic
                        ),
                    ));
                } else if legs > 1 {
                    // Each leg is its own STR, first leg first, and the box is the rung's
                    // first output (spec §2).
                    if has_output {
                        errors.push((
                            ins.line,
                            format!("{} must be the first output of its rung", ins.mnemonic),
                        ));
                    } else if levels != legs {
                        let names = match op {
                            Op::Counter(CounterKind::Udc, ..) => "up, down and reset",
                            Op::Counter(..) => "count and reset",
                            _ => "enable and reset",
                        };
                        errors.push((ins.line, format!("{} takes {legs} inputs ({names}), each started by its own STR; found {levels}", ins.mnemonic)));
                    }
                    has_output = true;
                } else {
                    if levels != 1 {
                        errors.push((
                            ins.line,
                            "branches are not merged (ANDSTR/ORSTR) before this output".into(),
                        ));
                    }
                    has_output = true;
                }
                // A multi-input box, like FOR (whose body starts with a rung), ends its rung.
                if legs > 1 || matches!(op, Op::For(..)) {
                    after_box = Some(ins.mnemonic.clone());
                }
                continue;
            }
        }
        after_box = None;
    }
    boxes_once(instrs, &mut errors);
    if end_line.is_none() {
        let line = instrs.last().map_or(1, |i| i.line);
        errors.push((line, "no END: a DL205 program ends with END".into()));
    }
    errors
}

pub fn assemble(source: &str) -> Result<Program, Vec<Diagnostic>> {
    let text = crate::text::normalize(source);
    let mut program = Program::default();
    let mut errors = Vec::new();
    let suggester = Suggester::default();
    let mut block_start: Option<usize> = None;
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let trimmed = line.trim_start().to_ascii_uppercase();
        if block_start.is_some() {
            if trimmed.starts_with("#END") {
                block_start = None;
            }
            continue;
        }
        if trimmed.starts_with("#BEGIN") {
            block_start = Some(line_no);
            continue;
        }
        let code = line.find("//").map_or(line, |k| &line[..k]);
        let mut ts = Vec::new();
        let mut col = 0;
        for part in code.split([' ', '\t']) {
            if !part.is_empty() {
                ts.push(Tok {
                    text: part.to_string(),
                    col: code[..col].chars().count() + 1,
                });
            }
            col += part.len() + 1;
        }
        if ts.is_empty() {
            continue;
        }
        match instruction(&ts, &mut program, &suggester) {
            Ok(op) => program.instrs.push(Instr {
                op,
                line: line_no,
                text: code.trim().to_string(),
                mnemonic: ts[0].text.to_ascii_uppercase(),
            }),
            Err(e) => errors.push(Diagnostic::error(line_no, e.col, 1, e.message)),
        }
    }
    if let Some(l) = block_start {
        errors.push(Diagnostic::error(l, 1, 6, "#BEGIN without #END"));
    }
    if errors.is_empty() {
        for (line, message) in rungs(&program.instrs)
            .into_iter()
            .chain(control(&mut program.instrs))
        {
            errors.push(Diagnostic::error(line, 1, 1, message));
        }
    }
    if !errors.is_empty() {
        errors.sort_by_key(|e| (e.line, e.col));
        return Err(errors);
    }
    program.used_v.sort_unstable();
    program.used_v.dedup();
    program.used_bits.sort_unstable();
    program.used_bits.dedup();
    program.flat = super::fast::flatten(&program.instrs);
    program.scan_writes = super::fast::scan_writes(&program.instrs);
    program.ladder = std::sync::Arc::new(super::ladder::build(&program.instrs));
    Ok(program)
}
