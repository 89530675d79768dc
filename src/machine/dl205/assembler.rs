//! DirectSOFT mnemonic text → [`Program`] (spec §1, §2, §6.8). Every faulty line is reported
//! once; the rung-structure checks run only when every line is valid.

use super::program::{
    Bit, BoxDecl, Cmp, CounterKind, D, Edge, Instr, Kind, Logic, Math, Op, Preset, Program,
    SPECIAL, ShiftKind, Src, Test, TimerKind, W, box_shape, current_word,
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
];

pub const UNSUPPORTED: &[&str] = &[
    "DRUM", "EDRUM", "MDRMD", "MDRMW", "OROUTN", "STRI", "STRNI",
    "ANDI", "ANDNI", "ORI", "ORNI", "OUTI", "SETI", "RSTI", "LDI", "LDIF", "OUTIF",
    "CMPS", "CMPR", "CMPF", "ENCO", "DECO", "SUM", "LDX", "LDSX", "OUTX", "OUTL", "LDR",
    "ADDR", "SUBR", "MULR", "DIVR", "ADDF", "SUBF", "MULF", "DIVF", "ANDF", "ORF", "XORF", "SQRTR",
    "MOV", "MOVMC", "LDLBL", "BCDCPL", "BTOR", "RTOB", "ATH", "HTA", "SEG", "GRAY", "SFLDGT",
    "SWAP", "TTD", "RTD", "SBR", "RT", "RTC", "GTS", "GOTO", "LBL", "FOR", "NEXT", "MLS", "MLR",
    "ISG", "SG", "JMP", "NJMP", "CV", "CVJMP", "BCALL", "BEND", "BREAK", "INT", "IRT", "IRTC",
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
        return err(t.col, format!("{}: element numbers are octal (digits 0–7)", t.text));
    }
    u32::from_str_radix(digits, 8).or_else(|_| err(t.col, format!("malformed element '{}'", t.text)))
}

/// Element letters of a token: `SP`, `CT`, `TA`, … then digits.
fn split(t: &Tok) -> (String, &str) {
    let upper_len = t.text.chars().take_while(|c| c.is_ascii_alphabetic()).count();
    (t.text[..upper_len].to_ascii_uppercase(), &t.text[upper_len..])
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
                return err(t.col, format!("{} is one of the {what}, not supported by servoscope yet", t.text));
            }
            return err(t.col, format!("'{}' is not a bit element (X, Y, C, S, T, CT or SP)", t.text));
        }
    };
    let n = octal(digits, t)?;
    if kind == Kind::Sp {
        let Some(i) = SPECIAL.iter().position(|&s| s == n) else {
            return err(t.col, format!("{} is a special relay not supported by servoscope yet", t.text));
        };
        return Ok(Bit { kind, n: i as u32 });
    }
    if n >= kind.count() {
        return err(t.col, format!("{} is out of range ({}0–{}{:o})", t.text, kind.letter(), kind.letter(), kind.count() - 1));
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
                return err(t.col, format!("{} is out of range ({letters}0–{letters}377)", t.text));
            }
            current_word(if letters == "TA" { Kind::T } else { Kind::Ct }, n)
        }
        _ => return err(t.col, format!("'{}' is not a V-memory word", t.text)),
    };
    if (0o40000..=0o41237).contains(&n) {
        return err(t.col, format!("{} is a bit-mapped/system word, not supported by servoscope yet", t.text));
    }
    if n >= V_WORDS {
        return err(t.col, format!("{} is out of range (V0–V37777)", t.text));
    }
    if pair && n + 1 >= V_WORDS {
        return err(t.col, format!("{} and the next word run past V37777", t.text));
    }
    program.used_v.push(n);
    if pair {
        program.used_v.push(n + 1);
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
    matches!(letters.as_str(), "V" | "TA" | "CTA")
}

/// A 16-bit source: V, or K up to `max` (BCD-checked when `bcd`).
fn word(t: &Tok, allow_k: bool, bcd: bool, min: u32, max: u32, program: &mut Program) -> Result<W, Error> {
    if is_word(t) {
        return v_addr(t, false, program).map(W::V);
    }
    if !allow_k {
        return err(t.col, format!("'{}': this instruction takes a V-memory word", t.text));
    }
    let Some(k) = k_hex(t) else {
        return err(t.col, format!("'{}' is not a V word or a K constant", t.text));
    };
    if bcd && !is_bcd(k) {
        return err(t.col, format!("{} is not BCD: this instruction needs BCD digits 0–9", t.text));
    }
    if k < min || k > max {
        return err(t.col, format!("{} is out of range (K{min:X}–K{max:X})", t.text));
    }
    Ok(W::K(k as u16))
}

fn double(t: &Tok, allow_k: bool, bcd: bool, program: &mut Program) -> Result<D, Error> {
    if is_word(t) {
        return v_addr(t, true, program).map(D::V);
    }
    if !allow_k {
        return err(t.col, format!("'{}': this instruction takes a V-memory pair", t.text));
    }
    let Some(k) = k_hex(t) else {
        return err(t.col, format!("'{}' is not a V pair or a K constant", t.text));
    };
    if bcd && !is_bcd(k) {
        return err(t.col, format!("{} is not BCD: this instruction needs BCD digits 0–9", t.text));
    }
    Ok(D::K(k))
}

/// A count: K + decimal 1–32.
fn count(t: &Tok) -> Result<u8, Error> {
    let digits = t.text.get(1..).unwrap_or("");
    if !t.text.to_ascii_uppercase().starts_with('K') || !digits.chars().all(|c| c.is_ascii_digit()) {
        return err(t.col, format!("'{}' is not a count K1–K32", t.text));
    }
    match digits.parse::<u8>() {
        Ok(n) if (1..=32).contains(&n) => Ok(n),
        _ => err(t.col, format!("{} is out of range (K1–K32)", t.text)),
    }
}

/// The bit a coil (OUT, PD, OROUT) writes: Y, C or S.
fn coil(t: &Tok, mnemonic: &str, program: &mut Program) -> Result<Bit, Error> {
    let b = bit(t, program)?;
    if !matches!(b.kind, Kind::Y | Kind::C | Kind::S) {
        return err(t.col, format!("{} cannot be written: {mnemonic} needs Y, C or S", t.text));
    }
    Ok(b)
}

fn instruction(ts: &[Tok], program: &mut Program, suggester: &Suggester) -> Result<Op, Error> {
    let first = &ts[0];
    let m = first.text.to_ascii_uppercase();
    let args = &ts[1..];
    if !MNEMONICS.contains(&m.as_str()) {
        if UNSUPPORTED.contains(&m.as_str()) {
            return err(first.col, format!("{m} is a DL205 instruction not supported by servoscope yet"));
        }
        let hint = match m.as_str() {
            "INC" => Some("INCB"),
            "DEC" => Some("DECB"),
            _ => suggester.suggest(&m, MNEMONICS.iter().copied()),
        };
        let hint = hint.map(|s| format!(" (did you mean {s}?)")).unwrap_or_default();
        return err(first.col, format!("unknown mnemonic '{}'{hint}", first.text));
    }
    let want = |n: usize| -> Result<(), Error> {
        if args.len() == n {
            Ok(())
        } else {
            let col = args.get(n).or(args.first()).map_or(first.col, |t| t.col);
            err(col, format!("{m} takes {n} operand(s), found {}", args.len()))
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
                err(col, format!("{m} takes a bit, or a V word and a value to compare, found {} operand(s)", args.len()))
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
            let (letters, _) = split(t);
            match letters.as_str() {
                "V" | "TA" | "CTA" => Op::OutV(v_addr(t, false, program)?),
                _ => Op::Coil(coil(t, "OUT", program)?),
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
                let kinds = if m == "RST" { "Y, C, S, T or CT" } else { "Y, C or S" };
                return err(args[0].col, format!("{} cannot be written: {m} needs {kinds}", args[0].text));
            }
            let b = match args.get(1) {
                Some(t) => {
                    let b = bit(t, program)?;
                    if b.kind != a.kind || b.n < a.n {
                        return err(t.col, format!("{m} range {}–{} must stay in one kind and run upwards", args[0].text, t.text));
                    }
                    b
                }
                None => a,
            };
            if m == "SET" { Op::Set(a, b) } else { Op::Rst(a, b) }
        }
        "STRPD" | "STRND" | "ANDPD" | "ANDND" | "ORPD" | "ORND" => {
            want(1)?;
            let edge = if m.ends_with("PD") { Edge::Rising } else { Edge::Falling };
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
                let what = if timer { "a timer number T0–T377" } else { "a counter number CT0–CT377" };
                return err(args[0].col, format!("{m} needs {what}, found '{}'", args[0].text));
            }
            let n = octal(digits, &args[0])?;
            let wide = matches!(m.as_str(), "TMRA" | "TMRAF" | "UDC");
            let last = kind.count() - 1 - u32::from(wide);
            if n > last {
                let also = if wide { " (it also takes the next number)" } else { "" };
                return err(args[0].col, format!("{} is out of range ({}0–{}{last:o}){also}", args[0].text, kind.letter(), kind.letter()));
            }
            let p = &args[1];
            let preset = if is_word(p) {
                let a = v_addr(p, wide, program)?;
                if wide { Preset::Pair(a) } else { Preset::Word(a) }
            } else {
                let Some(k) = k_hex(p) else {
                    return err(p.col, format!("'{}': the preset is a K constant or a V word", p.text));
                };
                if !is_bcd(k) {
                    return err(p.col, format!("{} is not BCD: presets are BCD digits 0–9", p.text));
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
            program.boxes.push(BoxDecl { status, words, preset, instr: program.instrs.len() });
            op
        }
        "END" => {
            want(0)?;
            Op::End
        }
        "NOP" => {
            want(0)?;
            Op::Nop
        }
        "POP" | "ADDS" | "SUBS" | "MULS" | "DIVS" | "ADDBS" | "SUBBS" | "MULBS" | "DIVBS" | "BIN" | "BCD" | "ANDS" | "ORS" | "XORS" => {
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
            want(if matches!(m.as_str(), "LDF" | "OUTF") { 2 } else { 1 })?;
            let t = &args[0];
            match m.as_str() {
                "LD" => Op::Ld(word(t, true, false, 0, 0xFFFF, program)?),
                "LDD" => Op::Ldd(double(t, true, false, program)?),
                "LDA" => {
                    let (letters, digits) = split(t);
                    if letters != "O" {
                        return err(t.col, format!("'{}': LDA takes an octal constant On", t.text));
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
                    if m == "OUTF" && matches!(e.kind, Kind::X | Kind::Sp) {
                        return err(t.col, format!("{} cannot be written: OUTF needs Y or C", t.text));
                    }
                    if e.kind == Kind::Sp {
                        // Every relay in the range must be modelled.
                        let start = SPECIAL[e.n as usize];
                        if (start..start + u32::from(n)).any(|s| !SPECIAL.contains(&s)) {
                            return err(t.col, format!("{} with K{n} covers special relays not supported by servoscope yet", t.text));
                        }
                    } else if e.n + u32::from(n) > e.kind.count() {
                        return err(args[1].col, format!("{} with {} runs past the last {} element", t.text, args[1].text, e.kind.letter()));
                    } else {
                        program.used_bits.extend((e.n..e.n + u32::from(n)).map(|i| Bit { kind: e.kind, n: i }));
                    }
                    if m == "LDF" { Op::Ldf(e, n) } else { Op::OutF(e, n) }
                }
                "OUTD" => Op::OutD(v_addr(t, true, program)?),
                "ADD" => Op::Bcd(Math::Add, Src::Word(word(t, false, true, 0, 0x9999, program)?)),
                "SUB" => Op::Bcd(Math::Sub, Src::Word(word(t, false, true, 0, 0x9999, program)?)),
                "ADDD" => Op::Bcd(Math::Add, Src::Double(double(t, true, true, program)?)),
                "SUBD" => Op::Bcd(Math::Sub, Src::Double(double(t, true, true, program)?)),
                "MUL" => Op::Bcd(Math::Mul, Src::Word(word(t, true, true, 0, 0x9999, program)?)),
                "MULD" => Op::Bcd(Math::Mul, Src::Double(double(t, false, true, program)?)),
                "DIV" => Op::Bcd(Math::Div, Src::Word(word(t, true, true, 1, 0x9999, program)?)),
                "DIVD" => Op::Bcd(Math::Div, Src::Double(double(t, false, true, program)?)),
                "ADDB" => Op::Binary(Math::Add, Src::Word(word(t, true, false, 0, 0xFFFF, program)?)),
                "SUBB" => Op::Binary(Math::Sub, Src::Word(word(t, true, false, 0, 0xFFFF, program)?)),
                "ADDBD" => Op::Binary(Math::Add, Src::Double(double(t, true, false, program)?)),
                "SUBBD" => Op::Binary(Math::Sub, Src::Double(double(t, true, false, program)?)),
                "MULB" => Op::Binary(Math::Mul, Src::Word(word(t, true, false, 0, 0xFFFF, program)?)),
                "DIVB" => Op::Binary(Math::Div, Src::Word(word(t, true, false, 1, 0xFFFF, program)?)),
                "INCB" => Op::IncB(v_addr(t, false, program)?),
                "DECB" => Op::DecB(v_addr(t, false, program)?),
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
                errors.push((ins.line, format!("{name} is already used by the box on line {line}: one box per number")));
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
        if end_line.is_some() {
            errors.push((ins.line, format!("{} after END: END must be the last instruction", ins.mnemonic)));
            continue;
        }
        match ins.op {
            Op::End => {
                if in_rung && !has_output {
                    errors.push((ins.line, "a rung with no output before END".into()));
                }
                end_line = Some(ins.line);
            }
            Op::Nop => continue,
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
                    errors.push((ins.line, format!("{} after {}: a multi-input box ends its rung; start a new rung with STR", ins.mnemonic, after_box.unwrap_or_default())));
                } else if !in_rung {
                    errors.push((ins.line, format!("{} needs a rung: start it with STR", ins.mnemonic)));
                }
            }
            Op::AndStr | Op::OrStr => {
                if !in_rung {
                    errors.push((ins.line, format!("{} needs a rung: start it with STR", ins.mnemonic)));
                } else if levels < 2 {
                    errors.push((ins.line, format!("{} needs two levels on the boolean stack", ins.mnemonic)));
                } else {
                    levels -= 1;
                }
            }
            op => {
                let legs = box_shape(&op).map_or(1, |(_, legs)| legs);
                if !in_rung {
                    errors.push((ins.line, "needs a rung condition: start the rung with a contact, e.g. STR SP1".into()));
                } else if let Some(boxed) = &after_box {
                    errors.push((ins.line, format!("{} after {boxed}: a multi-input box ends its rung; start a new rung with STR", ins.mnemonic)));
                } else if legs > 1 {
                    // Each leg is its own STR, first leg first, and the box is the rung's
                    // first output (spec §2).
                    if has_output {
                        errors.push((ins.line, format!("{} must be the first output of its rung", ins.mnemonic)));
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
                        errors.push((ins.line, "branches are not merged (ANDSTR/ORSTR) before this output".into()));
                    }
                    has_output = true;
                }
                if legs > 1 {
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
        for (line, message) in rungs(&program.instrs) {
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
    Ok(program)
}
