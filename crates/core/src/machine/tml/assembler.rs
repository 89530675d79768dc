//! TML text → [`Program`] (spec §1, §5). Every error is reported, at most one per statement
//! (a bad character: one for its line), sorted by line and column; any error means no program.
//!
//! Decided where the spec is silent: a fixed literal may have at most 25 digits after its
//! point (exact rounding needs them all, and nobody writes more).

use std::collections::HashMap;

use super::program::{AddKind, Cond, Data, EventSpec, Op, Operand, Program, Stmt, Ty, Value, Var};
use super::{PREDEFINED, d};
use crate::machine::Diagnostic;
use crate::machine::diagnostics::Suggester;
use crate::machine::project::Project;

/// The statements of the subset (spec §5), reserved as names.
pub const MNEMONICS: &[&str] = &[
    "GOTO", "CALL", "RET", "END", "MODE", "CPR", "CPA", "TUM0", "TUM1", "UPD", "STOP", "SAP",
    "AXISON", "AXISOFF", "BEGIN", "ENDINIT", "NOP", "SRB", "SRBL", "WAIT",
];

/// Real TML instructions outside the subset (spec §5.10).
pub const UNSUPPORTED: &[&str] = &[
    "CALLS",
    "RETI",
    "ABORT",
    "SEG",
    "PVTP",
    "PTP",
    "SETPT",
    "SETPVT",
    "EINT",
    "DINT",
    "HOMING",
    "FUNCTION",
    "SAVE",
    "RESET",
    "FAULTR",
    "SEND",
    "STA",
    "EXTREF",
    "TIMEOUT",
    "SETSYNC",
    "ENCAPI0",
    "ENCAPI1",
    "EN2CAPI0",
    "EN2CAPI1",
    "DISCAPI",
    "DIS2CAPI",
    "ENLSP0",
    "ENLSP1",
    "ENLSN0",
    "ENLSN1",
    "DISLSP",
    "DISLSN",
    "ENEEPROM",
    "LOCKEEPROM",
    "INITCAM",
    "ENDINITCAM",
    "SETWS",
    "MENU",
    "CHECKSUM",
    "SETMODE",
    "SGM",
    "RGM",
    "REG_ON",
    "REG_OFF",
    "STOPLOG",
    "STARTLOG",
    "GETERROR",
    "SAVEERROR",
    "CLEARERROR",
    "INITSLAVES",
    "AXISID",
    "GROUPID",
    "ADDGRID",
    "REMGRID",
    "CANBR",
    "SCIBR",
    "SPIBR",
    "SETOFFSET",
    "GETOFFSET",
    "OUT",
    "IN",
];

/// TML data servoscope does not model (spec §2.3): name, type and address. Reserved; any use is
/// an error naming them.
const UNMODELLED: &[(&str, &str, u16)] = &[
    ("CDEC", "fixed", 0x0858),
    ("TJERK", "long", 0x08D2),
    ("ERRMAX", "uint", 0x02C5),
    ("TERRMAX", "uint", 0x02C6),
    ("ASR", "uint", 0x0201),
    ("ACR", "uint", 0x0912),
    ("SCR", "uint", 0x0300),
    ("CER", "uint", 0x0301),
    ("OSR", "uint", 0x0302),
    ("PCR", "uint", 0x0303),
    ("ICR", "uint", 0x0304),
    ("DER2", "uint", 0x0305),
    ("ISR", "uint", 0x0306),
    ("MSR", "uint", 0x0308),
    ("CCR", "uint", 0x030A),
    ("CSR", "uint", 0x030B),
    ("AAR", "uint", 0x030C),
    ("CBR", "uint", 0x030D),
    ("CAPPOS", "long", 0x02BC),
    ("CAPPOS2", "long", 0x081E),
    ("IQREF", "int", 0x022F),
    ("HOMEPOS", "long", 0x0992),
    ("HOMESPD", "fixed", 0x0994),
    ("HOMECRT", "int", 0x08AC),
    ("HOMETIME", "uint", 0x08AD),
    ("HOMING_NR", "uint", 0x09B7),
    ("LSACTIVE", "int", 0x0832),
    ("QUICKSTOPS", "int", 0x082F),
    ("TRANSMISSION", "long", 0x037C),
];

/// The error for a datum of [`UNMODELLED`], if `name` is one.
fn unmodelled(name: &str) -> Option<String> {
    UNMODELLED
        .iter()
        .find(|(n, _, _)| n.eq_ignore_ascii_case(name))
        .map(|(n, ty, addr)| {
            format!("'{n}' ({ty}, 0x{addr:04X}) is a TML datum that servoscope does not model yet")
        })
}

/// TML's interrupt instructions (spec §5.10).
const INTERRUPTS: &[&str] = &["RETI", "EINT", "DINT"];

const UNSUPPORTED_EVENTS: &[&str] = &[
    "CAP", "LSP", "LSN", "AT", "RO", "RU", "RPO", "RPU", "RMPO", "RMPU", "VO", "VU", "LSO", "LSU",
    "MSO", "MSU", "ALPO", "ALPU", "AMPO", "AMPU", "PRT", "PVT", "PT",
];

const TYPES: &[&str] = &["INT", "LONG", "FIXED"];
const MAX_NAME: usize = 32;
const MAX_FIXED_DIGITS: usize = 25;

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    /// A number as written: decimal/hex integer with its suffix, or a fixed literal.
    Int(i128, Suffix),
    Fixed(i128),
    BadNumber(String),
    Punct(&'static str),
}

/// An integer literal's suffix (spec §1.3): it never changes the value, it says where the
/// literal may stand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Suffix {
    None,
    /// `U`: 0..65535.
    U,
    /// `L`: a 32-bit integer.
    L,
    /// `UL` or `LU`: 0..2^32−1.
    UL,
}

impl Suffix {
    fn text(self) -> &'static str {
        match self {
            Suffix::None => "",
            Suffix::U => "U",
            Suffix::L => "L",
            Suffix::UL => "UL",
        }
    }
}

/// Where a number stands, for its suffix (spec §1.3's table).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Context {
    /// 16-bit data, SRB masks, the factor B of `*`: `U` allowed.
    Bits16,
    /// Long data, SAP, `!RT`: `U`, `L`, `UL`, `LU` allowed.
    Bits32,
    /// Fixed data: no suffix.
    Fixed,
    /// A shift count, a `WAIT!` time-out, an `!IN#` number or level: no suffix.
    Count,
}

/// A number read from the tokens, with where it stands in the text.
#[derive(Clone, Copy, Debug)]
struct Num {
    value: i128,
    fixed: bool,
    suffix: Suffix,
    col: usize,
    len: usize,
}

impl Num {
    /// Refuse a suffix the context does not take, and a value its suffix does not allow.
    fn check(&self, context: Context) -> Result<(), Error> {
        let s = self.suffix;
        let misplaced = |what: &str| {
            err(
                self.col,
                self.len,
                format!("misplaced suffix '{}': {what}", s.text()),
            )
        };
        match (context, s) {
            (_, Suffix::None) => Ok(()),
            (Context::Count, _) => misplaced("this number takes no suffix"),
            (Context::Fixed, _) => misplaced("fixed data takes a fixed literal or a whole number"),
            (Context::Bits16, Suffix::L | Suffix::UL) => {
                misplaced("L marks a 32-bit integer, and this is 16-bit")
            }
            (_, Suffix::U) if !(0..=65535).contains(&self.value) => {
                err(self.col, self.len, "a U number is 0..65535")
            }
            (_, Suffix::UL) if !(0..=i128::from(u32::MAX)).contains(&self.value) => {
                err(self.col, self.len, "a UL number is 0..4294967295")
            }
            _ => Ok(()),
        }
    }
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    col: usize,
    len: usize,
}

struct Error {
    col: usize,
    len: usize,
    message: String,
}

fn err<T>(col: usize, len: usize, message: impl Into<String>) -> Result<T, Error> {
    Err(Error {
        col,
        len,
        message: message.into(),
    })
}

fn allowed(c: char) -> bool {
    c.is_ascii_alphanumeric() || c.is_whitespace() || "_;:,.=+-*/<>!#()[]{}@".contains(c)
}

const PUNCTS: &[&str] = &[
    "<<=", ">>=", "+=", "-=", "/=", "<<", ">>", "=", "*", ",", "(", ")", "!", "#", "-", "[", "]",
    "{", "}", ".", "+", "/", "<", ">", ":", "@",
];

/// Tokens of one statement; `start` is the 1-based column of `text[0]`.
fn lex(text: &[char], start: usize) -> Vec<Token> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let c = text[i];
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let col = start + i;
        if c.is_ascii_alphabetic() || c == '_' {
            let begin = i;
            while i < text.len() && (text[i].is_ascii_alphanumeric() || text[i] == '_') {
                i += 1;
            }
            out.push(Token {
                tok: Tok::Ident(text[begin..i].iter().collect()),
                col,
                len: i - begin,
            });
        } else if c.is_ascii_digit()
            || (c == '.' && text.get(i + 1).is_some_and(char::is_ascii_digit))
        {
            // `.5` too, so it is refused as a number ("write 0.5"), not as punctuation.
            let begin = i;
            i += 1;
            while i < text.len()
                && (text[i].is_ascii_alphanumeric() || text[i] == '.' || text[i] == '_')
            {
                i += 1;
            }
            let word: String = text[begin..i].iter().collect();
            out.push(Token {
                tok: number(&word),
                col,
                len: i - begin,
            });
        } else {
            let rest: String = text[i..text.len().min(i + 3)].iter().collect();
            let p = PUNCTS
                .iter()
                .find(|p| rest.starts_with(**p))
                .copied()
                .unwrap_or(".");
            out.push(Token {
                tok: Tok::Punct(p),
                col,
                len: p.len(),
            });
            i += p.len();
        }
    }
    out
}

/// A number token: decimal, `0x` hex, or a fixed literal (raw = round(x × 65536), ties away
/// from zero, exact).
fn number(word: &str) -> Tok {
    let bad = || Tok::BadNumber(word.to_string());
    let lower = word.to_ascii_lowercase();
    // An integer's suffix: UL, LU, U or L (a fixed literal takes none: `1.5L` is malformed).
    let (lower, suffix) = if lower.contains('.') {
        (lower.as_str(), Suffix::None)
    } else if let Some(body) = lower
        .strip_suffix("ul")
        .or_else(|| lower.strip_suffix("lu"))
    {
        (body, Suffix::UL)
    } else if let Some(body) = lower.strip_suffix('u') {
        (body, Suffix::U)
    } else if let Some(body) = lower.strip_suffix('l') {
        (body, Suffix::L)
    } else {
        (lower.as_str(), Suffix::None)
    };
    let int = |v: i128| Tok::Int(v, suffix);
    if let Some(hex) = lower.strip_prefix("0x") {
        if hex.is_empty() || hex.len() > 16 {
            return bad();
        }
        return i128::from_str_radix(hex, 16).map_or_else(|_| bad(), int);
    }
    if let Some((int, frac)) = word.split_once('.') {
        if int.is_empty()
            || !int.chars().all(|c| c.is_ascii_digit())
            || !frac.chars().all(|c| c.is_ascii_digit())
            || frac.len() > MAX_FIXED_DIGITS
            || int.len() > 12
        {
            return bad();
        }
        let scale = 10i128.pow(frac.len() as u32);
        let whole: i128 = int.parse().unwrap_or(0);
        let part: i128 = if frac.is_empty() {
            0
        } else {
            frac.parse().unwrap_or(0)
        };
        // Too large for i128 is far outside the fixed range: keep a value the range check refuses.
        let Some(num) = whole
            .checked_mul(scale)
            .and_then(|x| x.checked_add(part))
            .and_then(|x| x.checked_mul(65536))
        else {
            return Tok::Fixed(i128::MAX);
        };
        let (q, r) = (num / scale, num % scale);
        let raw = if 2 * r >= scale { q + 1 } else { q };
        return Tok::Fixed(raw);
    }
    if lower.is_empty() || lower.len() > 20 || !lower.chars().all(|c| c.is_ascii_digit()) {
        return bad();
    }
    lower.parse().map_or_else(|_| bad(), int)
}

/// A value only program memory can give: the address of a label's statement, or the statement
/// at a numeric jump address.
#[derive(Clone, Copy, Debug)]
enum Fixup {
    LabelAddress(u32),
    JumpAddress {
        address: u32,
        col: usize,
        len: usize,
    },
}

/// Where a GOTO or CALL goes.
enum Target {
    Statement(u32),
    Via(Operand),
}

/// Names the program and the drive define, while the program is read.
struct Names<'a> {
    vars: Vec<Var>,
    var_index: HashMap<String, u16>,
    labels: &'a HashMap<String, (u32, usize)>,
    /// What the statement being read leaves to be filled in once every statement's address is
    /// known (spec §5.11).
    pending: Option<Fixup>,
    used: Vec<u8>,
    used_inputs: Vec<u8>,
    uses_preg: bool,
    suggester: Suggester,
}

fn predefined(name: &str) -> Option<u8> {
    let name = super::canonical_name(name);
    PREDEFINED
        .iter()
        .position(|p| {
            p.name.eq_ignore_ascii_case(name)
                || p.alias.is_some_and(|a| a.eq_ignore_ascii_case(name))
        })
        .map(|i| i as u8)
}

fn reserved(upper: &str) -> bool {
    predefined(upper).is_some()
        || upper == "PREG"
        || TYPES.contains(&upper)
        || MNEMONICS.contains(&upper)
        || UNSUPPORTED.contains(&upper)
        || unmodelled(upper).is_some()
}

impl Names<'_> {
    fn suggestion(&self, word: &str) -> String {
        let candidates = PREDEFINED
            .iter()
            .map(|p| p.name)
            .chain(self.vars.iter().map(|v| v.name.as_str()));
        match self.suggester.suggest(word, candidates) {
            Some(s) => format!(" (did you mean '{s}'?)"),
            None => String::new(),
        }
    }

    /// A datum by name, at `t` (with `(H)`/`(L)` following it in `ts`).
    fn operand(&mut self, ts: &[Token], at: &mut usize) -> Result<Operand, Error> {
        let t = &ts[*at];
        let Tok::Ident(name) = &t.tok else {
            return err(t.col, t.len, "expected a variable or TML data name");
        };
        let upper = name.to_ascii_uppercase();
        let (data, ty) = if let Some(i) = predefined(name) {
            if !self.used.contains(&i) {
                self.used.push(i);
            }
            (Data::Pre(i), PREDEFINED[i as usize].ty)
        } else if let Some(&v) = self.var_index.get(&upper) {
            (Data::Var(v), self.vars[v as usize].ty)
        } else if upper == "PREG" {
            return err(
                t.col,
                t.len,
                "PREG is not a TML name: read it through PROD (bits 31..0) and PRODH (47..16)",
            );
        } else if self.labels.contains_key(&upper) {
            return err(
                t.col,
                t.len,
                format!(
                    "'{name}' is a label: a label's address can only be assigned to 16-bit data ('W16 = {name};') or be a jump target"
                ),
            );
        } else if let Some(message) = unmodelled(name) {
            return err(t.col, t.len, message);
        } else {
            let hint = self.suggestion(name);
            return err(t.col, t.len, format!("undeclared variable '{name}'{hint}"));
        };
        *at += 1;
        let mut op = Operand {
            data,
            half: None,
            ty,
        };
        if punct(ts, *at, "(") {
            let (which, col) = match ts.get(*at + 1) {
                Some(Token {
                    tok: Tok::Ident(w),
                    col,
                    ..
                }) => (w.to_ascii_uppercase(), *col),
                other => {
                    let col = other.map_or(t.col, |o| o.col);
                    return err(col, 1, "expected H or L inside the parentheses");
                }
            };
            if !punct(ts, *at + 2, ")") {
                return err(col, 1, "expected ')'");
            }
            let high = match which.as_str() {
                "H" => true,
                "L" => false,
                _ => return err(col, which.len(), "expected H or L inside the parentheses"),
            };
            if data == Data::Pre(d::PROD) && high {
                // `PROD(H)` is the vendor's spelling of PRODH.
                op = Operand {
                    data: Data::Pre(d::PRODH),
                    half: None,
                    ty: Ty::Long,
                };
                if !self.used.contains(&d::PRODH) {
                    self.used.push(d::PRODH);
                }
            } else if matches!(data, Data::Pre(d::PROD) | Data::Pre(d::PRODH)) {
                return err(
                    t.col,
                    t.len,
                    "PROD and PRODH have no other halves (PROD(H) is PRODH)",
                );
            } else if ty.bits() != 32 {
                return err(
                    t.col,
                    t.len,
                    format!("'{name}' is 16-bit: only 32-bit data have (H) and (L) halves"),
                );
            } else {
                op.half = Some(high);
                op.ty = Ty::Int;
            }
            *at += 3;
        }
        if matches!(op.data, Data::Pre(d::PROD) | Data::Pre(d::PRODH)) {
            self.uses_preg = true;
        }
        Ok(op)
    }
}

fn punct(ts: &[Token], at: usize, p: &str) -> bool {
    matches!(ts.get(at), Some(Token { tok: Tok::Punct(q), .. }) if *q == p)
}

fn writable(op: &Operand) -> bool {
    match op.data {
        Data::Pre(i) => PREDEFINED[i as usize].writable,
        Data::Var(_) => true,
    }
}

fn datum_name(op: &Operand, names: &Names) -> String {
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
fn signed_number(ts: &[Token], at: &mut usize) -> Option<Result<Num, Error>> {
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
fn count_number(ts: &[Token], at: &mut usize) -> Option<Result<Num, Error>> {
    Some(signed_number(ts, at)?.and_then(|n| n.check(Context::Count).map(|()| n)))
}

fn shift_count(ts: &[Token], at: &mut usize) -> Result<u8, Error> {
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
fn immediate(n: Num, dst: &Operand) -> Result<i64, Error> {
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

fn expect_end(ts: &[Token], at: usize) -> Result<(), Error> {
    match ts.get(at) {
        None => Ok(()),
        Some(t) => err(t.col, t.len, "unexpected text: expected ';'"),
    }
}

fn not_supported<T>(t: &Token, what: &str) -> Result<T, Error> {
    err(
        t.col,
        t.len,
        format!("{what} is not supported by servoscope yet"),
    )
}

/// The target of a GOTO or CALL (spec §5.7): a label, a 16-bit datum holding a program address
/// (a variable known at this point is the variable, else a label), or a number that must be a
/// statement's address.
fn jump_target(ts: &[Token], at: &mut usize, names: &mut Names) -> Result<Target, Error> {
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
fn value_of_width(
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

/// The indices of the `;` that end statements in `body`: a `;` inside a multi-axis `{…}` group
/// does not end one (spec §5.10: the statement runs to the end of its group).
fn statement_ends(body: &[char]) -> Vec<usize> {
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
fn multi_axis(ts: &[Token], seg: &[char]) -> Error {
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
fn statement(ts: &[Token], names: &mut Names, line: usize) -> Result<Option<Op>, Error> {
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

fn mnemonic(ts: &[Token], names: &mut Names, upper: &str) -> Result<Op, Error> {
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

fn event(ts: &[Token], names: &mut Names) -> Result<Op, Error> {
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

/// One line of the program in inclusion order: its program line (file and line, see
/// [`Project`]) and its characters.
struct SourceLine {
    line: usize,
    chars: Vec<char>,
}

/// What a line starting with `#` holds (spec §1.1).
enum Directive {
    Include(String),
    /// A malformed or unsupported directive: column, length, message.
    Bad(usize, usize, String),
}

/// The directive on `chars`, if its first non-blank character is `#`.
fn directive(chars: &[char]) -> Option<Directive> {
    let hash = chars.iter().position(|c| !c.is_whitespace())?;
    if chars[hash] != '#' {
        return None;
    }
    // A trailing `//` comment is allowed, but not inside the quoted path.
    let mut end = chars.len();
    let mut quoted = false;
    for k in hash..chars.len() {
        match chars[k] {
            '"' => quoted = !quoted,
            '/' if !quoted && chars.get(k + 1) == Some(&'/') => {
                end = k;
                break;
            }
            _ => {}
        }
    }
    let after_hash: String = chars[hash + 1..end].iter().collect();
    let lead = after_hash.len() - after_hash.trim_start().len();
    let word: String = after_hash
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect();
    let word_col = hash + 2 + lead;
    if !word.eq_ignore_ascii_case("include") {
        let shown = if word.is_empty() {
            "#".to_string()
        } else {
            format!("#{word}")
        };
        return Some(Directive::Bad(
            hash + 1,
            1 + lead + word.len(),
            format!("{shown} is not supported by servoscope yet (only #include)"),
        ));
    }
    let malformed = || {
        Directive::Bad(
            hash + 1,
            end.saturating_sub(hash).max(1),
            "malformed #include: write #include \"path\"".into(),
        )
    };
    let rest = after_hash.trim_start()[word.len()..].trim();
    let Some(inner) = rest.strip_prefix('"').and_then(|r| r.strip_suffix('"')) else {
        return Some(malformed());
    };
    if inner.contains('"') {
        return Some(malformed());
    }
    if inner.trim().is_empty() {
        return Some(Directive::Bad(
            word_col,
            word.len(),
            "empty #include path".into(),
        ));
    }
    Some(Directive::Include(inner.to_string()))
}

/// The paths `text` includes with well-formed `#include` lines, in order: what a loader reads
/// from disk before assembling.
pub fn includes(text: &str) -> Vec<String> {
    crate::text::normalize(text)
        .lines()
        .filter_map(|l| match directive(&l.chars().collect::<Vec<_>>()) {
            Some(Directive::Include(path)) => Some(path),
            _ => None,
        })
        .collect()
}

/// The lines of file `file` with its includes expanded in place (spec §1.1), appended to `out`.
fn expand(
    project: &Project,
    file: usize,
    chain: &mut Vec<usize>,
    out: &mut Vec<SourceLine>,
    errors: &mut Vec<Diagnostic>,
) {
    let text = crate::text::normalize(&project.files[file].text);
    chain.push(file);
    for (i, l) in text.lines().enumerate() {
        let line = Project::line(file, i + 1);
        if i + 1 >= crate::machine::project::FILE_LINES {
            errors.push(Diagnostic::error(
                line,
                1,
                1,
                "file too long: servoscope reads at most 1048575 lines of a file",
            ));
            break;
        }
        let chars: Vec<char> = l.chars().collect();
        match directive(&chars) {
            None => out.push(SourceLine { line, chars }),
            Some(Directive::Bad(col, len, message)) => {
                errors.push(Diagnostic::error(line, col, len, message))
            }
            Some(Directive::Include(path)) => {
                let col = chars.iter().position(|&c| c == '"').map_or(1, |k| k + 1);
                let len = path.chars().count() + 2;
                let name =
                    crate::machine::project::resolve_include(&project.files[file].name, &path);
                let Some(target) = project.index_of(&name) else {
                    errors.push(Diagnostic::error(
                        line,
                        col,
                        len,
                        format!("cannot open included file '{path}'"),
                    ));
                    continue;
                };
                if chain.contains(&target) {
                    let names: Vec<&str> = chain
                        .iter()
                        .skip_while(|&&f| f != target)
                        .map(|&f| project.files[f].name.as_str())
                        .chain([project.files[target].name.as_str()])
                        .collect();
                    errors.push(Diagnostic::error(
                        line,
                        col,
                        len,
                        format!("'{path}' includes itself ({})", names.join(" -> ")),
                    ));
                    continue;
                }
                if chain.len() > crate::machine::project::MAX_INCLUDE_DEPTH {
                    errors.push(Diagnostic::error(
                        line,
                        col,
                        len,
                        format!(
                            "more than {} nested #include levels below the top file",
                            crate::machine::project::MAX_INCLUDE_DEPTH
                        ),
                    ));
                    continue;
                }
                expand(project, target, chain, out, errors);
            }
        }
    }
    chain.pop();
}

/// Program-memory words of a statement (spec §5.11); `srbl` when it was written `SRBL`.
fn words_of(op: &Op, srbl: bool) -> u8 {
    match op {
        Op::Nop
        | Op::End
        | Op::Ret
        | Op::Upd
        | Op::Stop
        | Op::Axis(_)
        | Op::ShiftProduct { .. } => 1,
        Op::Wait(None) | Op::SetEvent(EventSpec::MotionComplete) | Op::Sap(Value::Var(_)) => 1,
        Op::Wait(Some(_))
        | Op::SetEvent(EventSpec::Time(Value::Var(_)))
        | Op::Sap(Value::Imm(_)) => 3,
        Op::SetEvent(EventSpec::Time(Value::Imm(_))) => 4,
        Op::SetEvent(EventSpec::Input(..)) => 2,
        Op::Assign(dst, Value::Imm(_))
        | Op::Add {
            dst,
            src: Value::Imm(_),
            ..
        } => {
            if dst.bits() == 16 {
                2
            } else {
                3
            }
        }
        Op::Assign(_, Value::Var(_)) | Op::Negate(..) | Op::Add { .. } | Op::Shift { .. } => 2,
        Op::AssignShift { .. } | Op::Multiply { .. } | Op::Divide(..) => 3,
        Op::Srb { .. } => {
            if srbl {
                4
            } else {
                3
            }
        }
        Op::ModePp | Op::Relative(_) | Op::Tum(_) => 3,
        Op::Jump { cond: None, .. } | Op::JumpVia { cond: None, .. } => 2,
        Op::Jump { .. } | Op::JumpVia { .. } => 3,
    }
}

/// Assemble the TML text of a one-file program.
pub fn assemble(source: &str) -> Result<Program, Vec<Diagnostic>> {
    assemble_project(&Project::single("", source))
}

/// Assemble a program of several files: the top file with its `#include` files expanded.
pub fn assemble_project(project: &Project) -> Result<Program, Vec<Diagnostic>> {
    let mut errors: Vec<Diagnostic> = Vec::new();
    let mut lines: Vec<SourceLine> = Vec::new();
    if !project.files.is_empty() {
        expand(project, 0, &mut Vec::new(), &mut lines, &mut errors);
    }
    let describe = |line: usize| {
        if project.is_multi() {
            format!("at {}", project.describe(line))
        } else {
            format!("on line {line}")
        }
    };

    // Pass 1: where each line's statements begin (comments and labels taken off), and labels.
    struct Line {
        /// (statement chars, column of its first char)
        body: Vec<char>,
        body_col: usize,
    }
    let mut bodies = Vec::with_capacity(lines.len());
    let mut labels: HashMap<String, (u32, usize)> = HashMap::new();
    // (name, line, index into `lines`)
    let mut label_list: Vec<(String, usize, usize)> = Vec::new();
    let mut stmt_count_before: Vec<u32> = Vec::with_capacity(lines.len());
    let mut count: u32 = 0;
    for (idx, source_line) in lines.iter().enumerate() {
        let line_no = source_line.line;
        let chars = &source_line.chars;
        let mut end = chars.len();
        for k in 0..chars.len().saturating_sub(1) {
            if chars[k] == '/' && chars[k + 1] == '/' {
                end = k;
                break;
            }
        }
        let code = &chars[..end];
        stmt_count_before.push(count);
        if let Some(k) = code.iter().position(|&c| !allowed(c)) {
            errors.push(Diagnostic::error(
                line_no,
                k + 1,
                1,
                format!("unexpected character '{}'", code[k].escape_default()),
            ));
            bodies.push(None);
            continue;
        }
        let mut body_col = 1;
        let mut body: &[char] = code;
        // A label: a name and ':' at column 1.
        if let Some(colon) = code.iter().position(|&c| c == ':') {
            let before: String = code[..colon].iter().collect();
            let name = before.trim();
            let valid = !name.is_empty()
                && name
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !valid {
                let col = code
                    .iter()
                    .position(|c| !c.is_whitespace())
                    .unwrap_or(colon)
                    + 1;
                errors.push(Diagnostic::error(
                    line_no,
                    col,
                    colon + 2 - col,
                    "expected a label name before ':'",
                ));
                bodies.push(None);
                continue;
            }
            let indent = code.iter().take_while(|c| c.is_whitespace()).count();
            if indent > 0 {
                errors.push(Diagnostic::error(
                    line_no,
                    indent + 1,
                    name.len(),
                    format!("label '{name}' must start in column 1"),
                ));
                bodies.push(None);
                continue;
            }
            let upper = name.to_ascii_uppercase();
            if name.len() > MAX_NAME {
                errors.push(Diagnostic::error(
                    line_no,
                    1,
                    name.len(),
                    format!("name longer than {MAX_NAME} characters"),
                ));
            } else if reserved(&upper) {
                errors.push(Diagnostic::error(
                    line_no,
                    1,
                    name.len(),
                    format!("'{name}' is a TML name and cannot be a label"),
                ));
            } else if let Some(&(_, first)) = labels.get(&upper) {
                errors.push(Diagnostic::error(
                    line_no,
                    1,
                    name.len(),
                    format!("duplicate label '{name}' (first {})", describe(first)),
                ));
            } else {
                // Its statement index is fixed once this line's statements are counted.
                labels.insert(upper, (u32::MAX, line_no));
                label_list.push((name.to_string(), line_no, idx));
            }
            body = &code[colon + 1..];
            body_col = colon + 2;
        }
        // Statements that are empty (`;;`) are not counted.
        let mut nonempty = 0;
        let mut start = 0;
        for k in statement_ends(body) {
            // Declarations are not statements: labels count only what runs.
            let seg: String = body[start..k].iter().collect();
            let first = seg
                .split_whitespace()
                .next()
                .unwrap_or("")
                .to_ascii_uppercase();
            if !seg.trim().is_empty() && !TYPES.contains(&first.as_str()) {
                nonempty += 1;
            }
            start = k + 1;
        }
        count += nonempty;
        bodies.push(Some(Line {
            body: body.to_vec(),
            body_col,
        }));
    }
    // Labels point at the first statement at or after their line.
    for (name, _, idx) in &label_list {
        let index = stmt_count_before[*idx];
        if let Some(entry) = labels.get_mut(&name.to_ascii_uppercase()) {
            entry.0 = index;
        }
    }

    // Pass 2: the statements, in order (variables are declared before use).
    let mut names = Names {
        vars: Vec::new(),
        var_index: HashMap::new(),
        labels: &labels,
        pending: None,
        used: Vec::new(),
        used_inputs: Vec::new(),
        uses_preg: false,
        suggester: Suggester::default(),
    };
    let mut stmts = Vec::new();
    let mut fixups: Vec<(usize, Fixup)> = Vec::new();
    for (idx, line) in bodies.iter().enumerate() {
        let Some(line) = line else { continue };
        let line_no = lines[idx].line;
        let mut start = 0;
        for k in statement_ends(&line.body) {
            let seg = &line.body[start..k];
            let seg_col = line.body_col + start;
            start = k + 1;
            if seg.iter().all(|c| c.is_whitespace()) {
                continue;
            }
            let ts = lex(seg, seg_col);
            let lead = seg.iter().take_while(|c| c.is_whitespace()).count();
            names.pending = None;
            let parsed = match ts.first().map(|t| &t.tok) {
                Some(Tok::Punct("[" | "{")) => Err(multi_axis(&ts, seg)),
                Some(Tok::Punct("@")) => not_supported(
                    &ts[0],
                    "a data word '@ …' (EasyMotion's homing and function tables)",
                ),
                _ => statement(&ts, &mut names, line_no),
            };
            match parsed {
                Ok(Some(op)) => {
                    let srbl = matches!(ts.first().map(|t| &t.tok), Some(Tok::Ident(w)) if w.eq_ignore_ascii_case("SRBL"));
                    if let Some(fixup) = names.pending.take() {
                        fixups.push((stmts.len(), fixup));
                    }
                    stmts.push(Stmt {
                        words: words_of(&op, srbl),
                        op,
                        line: line_no,
                        col: seg_col + lead,
                        text: seg.iter().collect::<String>().trim().to_string(),
                    });
                }
                Ok(None) => {}
                Err(e) => errors.push(Diagnostic::error(line_no, e.col.max(1), e.len, e.message)),
            }
        }
        let rest = &line.body[start..];
        if rest.iter().any(|c| !c.is_whitespace()) {
            let trailing = rest.len() - rest.iter().rev().take_while(|c| c.is_whitespace()).count();
            let col = line.body_col + start + trailing;
            errors.push(Diagnostic::error(
                line_no,
                col,
                1,
                "expected ';' at the end of the statement",
            ));
        }
    }

    // Program memory (spec §5.11): each statement's address, then what needed them.
    let mut addresses = Vec::with_capacity(stmts.len());
    let mut next = super::PROGRAM_BASE;
    for stmt in &stmts {
        addresses.push(next);
        next += u32::from(stmt.words);
    }
    let end_address = next;
    let address_of = |index: u32| {
        addresses
            .get(index as usize)
            .copied()
            .unwrap_or(end_address)
    };
    for (at, fixup) in fixups {
        let line = stmts[at].line;
        match fixup {
            Fixup::LabelAddress(target) => {
                if let Op::Assign(_, Value::Imm(v)) = &mut stmts[at].op {
                    *v = i64::from(address_of(target));
                }
            }
            Fixup::JumpAddress { address, col, len } => {
                let index = if address == end_address {
                    Some(stmts.len() as u32)
                } else {
                    addresses.binary_search(&address).ok().map(|i| i as u32)
                };
                match (index, &mut stmts[at].op) {
                    (Some(i), Op::Jump { target, .. }) => *target = i,
                    _ => errors.push(Diagnostic::error(
                        line,
                        col,
                        len,
                        format!("no statement starts at 0x{address:04X}"),
                    )),
                }
            }
        }
    }
    if end_address > 0x1_0000 {
        let line = stmts.last().map_or(1, |s| s.line);
        errors.push(Diagnostic::error(line, 1, 1, format!(
            "the program needs {} words from 0x4000: more than program memory's 16-bit addresses reach",
            end_address - super::PROGRAM_BASE
        )));
    }
    if !errors.is_empty() {
        // A file included twice repeats its diagnostics: each is reported once.
        errors.sort_by(|a, b| (a.line, a.col, &a.message).cmp(&(b.line, b.col, &b.message)));
        errors.dedup();
        return Err(errors);
    }
    let mut label_entries: Vec<(String, u32, usize)> = label_list
        .iter()
        .map(|(name, line, _)| {
            (
                name.clone(),
                names.labels[&name.to_ascii_uppercase()].0,
                *line,
            )
        })
        .collect();
    label_entries.sort_by_key(|(_, at, _)| *at);
    let mut used = names.used;
    used.sort_unstable();
    let mut used_inputs = names.used_inputs;
    used_inputs.sort_unstable();
    let flat = super::program::flatten(&stmts);
    Ok(Program {
        flat_writes: super::exec::flat_writes(&flat),
        flat,
        stmts,
        vars: names.vars,
        files: if project.is_multi() {
            project.files.iter().map(|f| f.name.clone()).collect()
        } else {
            Vec::new()
        },
        label_lines: label_entries.iter().map(|(_, _, line)| *line).collect(),
        labels: label_entries
            .into_iter()
            .map(|(name, at, _)| (name, at))
            .collect(),
        addresses,
        end_address,
        used,
        uses_preg: names.uses_preg,
        used_inputs,
    })
}
