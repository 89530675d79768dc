//! OpenNet instruction-list text → [`Program`] (spec §1, §4.3, §5.1). Every error is reported
//! (one per line), sorted; any error means no program.

use super::program::{
    Area, Arith, BOXES, Bit, CounterKind, Instr, Logic, Op, Program, Rel, SPECIAL, TimerKind, Ty,
    Value, Word,
};
use crate::machine::Diagnostic;
use crate::machine::diagnostics::Suggester;

pub const BASIC: &[&str] = &[
    "LOD", "LODN", "AND", "ANDN", "OR", "ORN", "ANDLOD", "ORLOD", "BPS", "BRD", "BPP", "SOTU",
    "SOTD", "OUT", "OUTN", "SET", "RST", "END", "TML", "TIM", "TMH", "TMS", "CNT", "CDP", "CUD",
    "CC=", "CC>=", "DC=", "DC>=", "SFR", "SFRN", "MCS", "MCR", "JMP", "JEND", "NOP",
];
pub const ADVANCED: &[&str] = &[
    "MOV", "ADD", "SUB", "MUL", "DIV", "INC", "DEC", "CMP=", "CMP<>", "CMP<", "CMP>", "CMP<=",
    "CMP>=", "ICMP>=", "ANDW", "ORW", "XORW", "SFTL", "SFTR", "HTOB", "BTOH",
];

/// Advanced instructions that take only W and D.
const WORD_TYPES_ONLY: &[&str] = &[
    "INC", "DEC", "ANDW", "ORW", "XORW", "SFTL", "SFTR", "HTOB", "BTOH",
];
/// Advanced instructions that may carry `REP n`.
const REPEATABLE: &[&str] = &[
    "MOV", "ADD", "SUB", "MUL", "DIV", "CMP=", "CMP<>", "CMP<", "CMP>", "CMP<=", "CMP>=", "ICMP>=",
    "ANDW", "ORW", "XORW", "HTOB", "BTOH",
];

/// Real OpenNet instructions outside the subset.
pub const UNSUPPORTED: &[&str] = &[
    "BCDLS", "WSFT", "ROTL", "ROTR", "HTOA", "ATOH", "BTOA", "ATOB", "ENCO", "DECO", "BTOD",
    "DTOB", "SWAP", "LABEL", "LJMP", "LCAL", "LRET", "IOREF", "DISP", "DGRD", "TXD", "RXD",
    "CVXTY", "CVYTX", "AVRG", "PULS", "PWM", "RAMP", "ZRN", "PID", "NEG", "ROOT", "SUM", "IMOV",
    "IMOVN", "BMOV", "NSET", "NRS", "XCHG", "TCCST", "MOVN", "WKTIM", "WKTBL", "DTML", "DTIM",
    "DTMH", "DTMS", "TTIM", "DJNZ", "DI", "EI", "CALL", "RET",
];

/// Off-delay timers of later IDEC CPUs.
const LATER_CPU: &[&str] = &["TIMO", "TMHO", "TMLO", "TMSO"];

/// Names users of other tools write, and the OpenNet instruction meant.
const OTHER_NAMES: &[(&str, &str)] = &[
    ("TMR", "TIM"),
    ("TON", "TIM"),
    ("CTU", "CNT"),
    ("CTD", "CDP"),
    ("BCD", "HTOB"),
    ("BIN", "BTOH"),
    ("MC", "MCS"),
    ("ANDD", "ANDW(D)"),
];

/// MICRO3 special relays that are ordinary relays on OpenNet: number, MICRO3 meaning, the
/// OpenNet relay to use (spec §1).
const MICRO3: &[(u32, &str, &str)] = &[
    (301, "initialize pulse", "M8120"),
    (303, "carry/borrow", "M8003"),
    (304, "execution error", "M8004"),
    (311, "1-s clock", "M8121"),
    (312, "100-ms clock", "M8122"),
    (313, "10-ms clock", "M8123"),
];

const MAX_REP: u32 = 99;
const REGISTERS: u32 = 8000;
const STACK_DEPTH: u32 = 8;

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

#[derive(Clone, Debug)]
struct Token {
    text: String,
    col: usize,
}

fn tokens(code: &[char]) -> Vec<Token> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < code.len() {
        if code[i].is_whitespace() || code[i] == ',' {
            i += 1;
            continue;
        }
        let start = i;
        while i < code.len() && !code[i].is_whitespace() && code[i] != ',' {
            i += 1;
        }
        out.push(Token {
            text: code[start..i].iter().collect(),
            col: start + 1,
        });
    }
    out
}

/// What the rung check needs of an instruction.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    /// LOD, LODN and the compare contacts.
    Load,
    Logic,
    AndOrLod,
    Bps,
    Brd,
    Bpp,
    Output,
    /// A counter or shift register: it takes this many LOD blocks and ends its rung.
    Boxed(u32),
    /// MCS or JMP: an output that ends its rung.
    Opener,
    /// MCR or JEND: alone between rungs.
    Closer,
    Nop,
    End,
}

fn kind_of(mnemonic: &str) -> Kind {
    match mnemonic {
        "LOD" | "LODN" | "CC=" | "CC>=" | "DC=" | "DC>=" => Kind::Load,
        "AND" | "ANDN" | "OR" | "ORN" | "SOTU" | "SOTD" => Kind::Logic,
        "ANDLOD" | "ORLOD" => Kind::AndOrLod,
        "BPS" => Kind::Bps,
        "BRD" => Kind::Brd,
        "BPP" => Kind::Bpp,
        "CNT" => Kind::Boxed(2),
        "CDP" | "CUD" | "SFR" | "SFRN" => Kind::Boxed(3),
        "MCS" | "JMP" => Kind::Opener,
        "MCR" | "JEND" => Kind::Closer,
        "NOP" => Kind::Nop,
        "END" => Kind::End,
        _ => Kind::Output,
    }
}

/// A number as written: decimal with sign, or hex digits then `h`. Returns (value, is hex).
fn constant(text: &str) -> Option<(i64, bool)> {
    let lower = text.to_ascii_lowercase();
    if let Some(hex) = lower.strip_suffix('h') {
        if hex.is_empty() || hex.len() > 16 || !hex.chars().all(|c| c.is_ascii_hexdigit()) {
            return None;
        }
        return i64::from_str_radix(hex, 16).ok().map(|v| (v, true));
    }
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty() || digits.len() > 18 || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    text.parse::<i64>().ok().map(|v| (v, false))
}

/// An operand token (a letter then digits, maybe `(R)`): (letter, number, repeat).
fn operand(text: &str) -> Option<(char, u32, bool)> {
    let (body, repeat) = match text.len().checked_sub(3) {
        Some(cut) if text.is_char_boundary(cut) && text[cut..].eq_ignore_ascii_case("(R)") => {
            (&text[..cut], true)
        }
        _ => (text, false),
    };
    let mut chars = body.chars();
    let letter = chars.next()?.to_ascii_uppercase();
    let digits = chars.as_str();
    if !letter.is_ascii_alphabetic()
        || digits.is_empty()
        || digits.len() > 6
        || !digits.chars().all(|c| c.is_ascii_digit())
    {
        return None;
    }
    Some((letter, digits.parse().ok()?, repeat))
}

/// The assembler's state while it reads a file.
#[derive(Default)]
struct Pass {
    program: Program,
    line: usize,
    /// Timer and counter numbers already given to an instruction, with its line.
    timer_lines: std::collections::HashMap<u32, usize>,
    counter_lines: std::collections::HashMap<u32, usize>,
    /// The first read of each MICRO3 relay (number, line, col, len), and the M points written.
    micro3_reads: Vec<(u32, usize, usize, usize)>,
    m_written: Vec<(u32, u32)>,
}

impl Pass {
    fn note_m_write(&mut self, area: Area, index: u32, points: u32) {
        if area == Area::M {
            self.m_written.push((index, points));
        }
    }
}

/// An I/Q/M/R point number → its index (IDEC numbering: the last digit of I/Q/M is octal).
fn point(area: Area, n: u32, t: &Token) -> Result<u32, Error> {
    if area.octal() && n % 10 >= 8 {
        return err(
            t.col,
            t.text.len(),
            format!(
                "{}: the last digit of an {} number is octal (0–7)",
                t.text,
                area.letter()
            ),
        );
    }
    let index = if area.octal() { n / 10 * 8 + n % 10 } else { n };
    if index >= area.points() {
        let last = super::program::point_name(area, area.points() - 1);
        return err(
            t.col,
            t.text.len(),
            format!("{} is out of range ({}0–{last})", t.text, area.letter()),
        );
    }
    Ok(index)
}

/// A timer or counter number 0–255, with `span` numbers from it.
fn box_number(n: u32, span: u32, t: &Token) -> Result<u32, Error> {
    let letter = t.text.chars().next().unwrap_or('T').to_ascii_uppercase();
    if n >= BOXES {
        return err(
            t.col,
            t.text.len(),
            format!("{} is out of range ({letter}0–{letter}255)", t.text),
        );
    }
    if n + span > BOXES {
        return err(
            t.col,
            t.text.len(),
            format!("{} with its {span} word(s) runs past {letter}255", t.text),
        );
    }
    Ok(n)
}

fn note_boxes(list: &mut Vec<u32>, n: u32, span: u32) {
    list.extend(n..n + span);
}

/// A bit operand; `output`: OUT/OUTN/SET/RST (no input, read-only special relay, T or C).
fn bit(t: &Token, output: bool, pass: &mut Pass) -> Result<Bit, Error> {
    let Some((letter, n, repeat)) = operand(&t.text) else {
        return err(
            t.col,
            t.text.len(),
            format!("'{}' is not a bit operand (I, Q, M, R, T or C)", t.text),
        );
    };
    if repeat {
        return err(
            t.col,
            t.text.len(),
            "(R) belongs to advanced instructions with REP",
        );
    }
    let b = match letter {
        'I' if output => {
            return err(
                t.col,
                t.text.len(),
                format!("{} is an input: a program cannot write it", t.text),
            );
        }
        'I' => Bit::Point(Area::I, point(Area::I, n, t)?),
        'Q' => Bit::Point(Area::Q, point(Area::Q, n, t)?),
        'R' => Bit::Point(Area::R, point(Area::R, n, t)?),
        'M' if n >= 8000 => {
            let Some(i) = SPECIAL.iter().position(|&s| u32::from(s) == n) else {
                return err(
                    t.col,
                    t.text.len(),
                    format!(
                        "{} is a special relay not supported by servoscope yet (M8003, M8004, M8120–M8123 and M8125 are)",
                        t.text
                    ),
                );
            };
            if output && i >= 2 {
                return err(t.col, t.text.len(), format!("{} is read-only", t.text));
            }
            Bit::Special(i as u8)
        }
        'M' => {
            let index = point(Area::M, n, t)?;
            if output {
                pass.note_m_write(Area::M, index, 1);
            } else if MICRO3.iter().any(|&(m, ..)| m == n)
                && !pass.micro3_reads.iter().any(|r| r.0 == n)
            {
                pass.micro3_reads.push((n, pass.line, t.col, t.text.len()));
            }
            Bit::Point(Area::M, index)
        }
        'T' | 'C' if output => {
            let what = if letter == 'T' {
                "a timer's output: its timer"
            } else {
                "a counter's output: its counter"
            };
            return err(
                t.col,
                t.text.len(),
                format!("{} is {what} instruction sets it", t.text),
            );
        }
        'T' => {
            let n = box_number(n, 1, t)?;
            note_boxes(&mut pass.program.used_timers, n, 1);
            Bit::Timer(n)
        }
        'C' => {
            let n = box_number(n, 1, t)?;
            note_boxes(&mut pass.program.used_counters, n, 1);
            Bit::Counter(n)
        }
        'D' => {
            return err(
                t.col,
                t.text.len(),
                format!(
                    "{} is a data register: a bit instruction needs I, Q, M, R, T or C",
                    t.text
                ),
            );
        }
        'L' => {
            return err(
                t.col,
                t.text.len(),
                format!(
                    "{} is a link register (L), not supported by servoscope yet",
                    t.text
                ),
            );
        }
        _ => {
            return err(
                t.col,
                t.text.len(),
                format!("'{}' is not an operand", t.text),
            );
        }
    };
    if let Bit::Point(area, index) = b {
        pass.program.used_bits.push((area, index));
    }
    Ok(b)
}

/// What a word operand is for (spec §4.3).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Source,
    Destination,
    /// SFTL/SFTR's S1: read and written, a D register or Q, M, R points.
    InPlace,
}

/// A word operand: `words` its block size; `rep` the repeat count.
fn word(
    t: &Token,
    ty: Ty,
    role: Role,
    words: u32,
    rep: u32,
    pass: &mut Pass,
) -> Result<Word, Error> {
    let len = t.text.len();
    let writes = role != Role::Source;
    if let Some((letter, n, repeat)) = operand(&t.text) {
        let span = words * if repeat { rep } else { 1 };
        return match letter {
            'D' => {
                if (8000..8500).contains(&n) {
                    return err(
                        t.col,
                        len,
                        format!(
                            "{} is a special data register, not supported by servoscope yet",
                            t.text
                        ),
                    );
                }
                if n >= REGISTERS {
                    return err(t.col, len, format!("{} is out of range (D0–D7999)", t.text));
                }
                if n + span > REGISTERS {
                    return err(
                        t.col,
                        len,
                        format!("{} with its {span} word(s) runs past D7999", t.text),
                    );
                }
                pass.program.used_regs.extend(n..n + span);
                if ty.signed() {
                    // Each item's first word: an I word, or the upper (sign) word of an L pair.
                    pass.program
                        .signed_regs
                        .extend((n..n + span).step_by(words.max(1) as usize));
                }
                Ok(Word::Reg { n, repeat })
            }
            'I' | 'Q' | 'M' | 'R' => {
                let area = match letter {
                    'I' if writes => {
                        return err(
                            t.col,
                            len,
                            format!("{} is an input: it cannot be a destination", t.text),
                        );
                    }
                    'I' => Area::I,
                    'Q' => Area::Q,
                    'R' => Area::R,
                    _ => Area::M,
                };
                if area == Area::M && n >= 8000 {
                    return err(
                        t.col,
                        len,
                        format!("{}: special relays are never word operands", t.text),
                    );
                }
                let index = point(area, n, t)?;
                if index + span * 16 > area.points() {
                    let last = super::program::point_name(area, area.points() - 1);
                    return err(
                        t.col,
                        len,
                        format!("{} with its {} points runs past {last}", t.text, span * 16),
                    );
                }
                pass.program
                    .used_bits
                    .extend((index..index + span * 16).map(|i| (area, i)));
                if writes {
                    pass.note_m_write(area, index, span * 16);
                }
                Ok(Word::Bits {
                    area,
                    index,
                    repeat,
                })
            }
            'T' | 'C' => {
                let what = if letter == 'T' { "timer" } else { "counter" };
                if role == Role::InPlace {
                    return err(
                        t.col,
                        len,
                        format!("{} is a {what}: this operand takes D, Q, M or R", t.text),
                    );
                }
                if ty.words() != 1 {
                    return err(
                        t.col,
                        len,
                        format!(
                            "{} is a {what}: T and C words go with type W or I, not {}",
                            t.text,
                            ty.letter()
                        ),
                    );
                }
                let n = box_number(n, span, t)?;
                if letter == 'T' {
                    note_boxes(&mut pass.program.used_timers, n, span);
                    Ok(Word::Timer { n, repeat })
                } else {
                    note_boxes(&mut pass.program.used_counters, n, span);
                    Ok(Word::Counter { n, repeat })
                }
            }
            'L' => err(
                t.col,
                len,
                format!(
                    "{} is a link register (L), not supported by servoscope yet",
                    t.text
                ),
            ),
            _ => err(
                t.col,
                len,
                format!(
                    "'{}' is not an operand (D, I, Q, M, R, T, C or a constant)",
                    t.text
                ),
            ),
        };
    }
    if t.text.to_ascii_uppercase().ends_with("(R)") {
        return err(t.col, len, "(R) cannot follow a constant");
    }
    let Some((v, hex)) = constant(&t.text) else {
        return err(
            t.col,
            len,
            format!("malformed operand or constant '{}'", t.text),
        );
    };
    if writes {
        return err(t.col, len, "a constant cannot be a destination");
    }
    let pattern = if hex {
        if v >> ty.bits() != 0 {
            return err(
                t.col,
                len,
                format!("{} does not fit {} bits", t.text, ty.bits()),
            );
        }
        v as u32
    } else {
        if v < ty.min() || v > ty.max() {
            return err(
                t.col,
                len,
                format!(
                    "{} is out of range for type {} ({} … {})",
                    t.text,
                    ty.letter(),
                    ty.min(),
                    ty.max()
                ),
            );
        }
        v as u32 & if ty.words() == 1 { 0xFFFF } else { u32::MAX }
    };
    Ok(Word::Const(pattern))
}

/// A preset or compared value: a constant 0–65535 (`0h`–`FFFFh`) or a data register.
fn value(t: &Token, pass: &mut Pass) -> Result<Value, Error> {
    let len = t.text.len();
    if let Some((letter, n, repeat)) = operand(&t.text) {
        if repeat {
            return err(t.col, len, "(R) belongs to advanced instructions with REP");
        }
        if letter != 'D' {
            return err(
                t.col,
                len,
                format!(
                    "{}: a value is a constant 0–65535 or a data register (D)",
                    t.text
                ),
            );
        }
        if (8000..8500).contains(&n) {
            return err(
                t.col,
                len,
                format!(
                    "{} is a special data register, not supported by servoscope yet",
                    t.text
                ),
            );
        }
        if n >= REGISTERS {
            return err(t.col, len, format!("{} is out of range (D0–D7999)", t.text));
        }
        pass.program.used_regs.push(n);
        return Ok(Value::Reg(n));
    }
    match constant(&t.text) {
        Some((v, _)) if (0..=0xFFFF).contains(&v) => Ok(Value::Const(v as u16)),
        Some(_) => err(
            t.col,
            len,
            format!("{} is out of range for a value (0–65535)", t.text),
        ),
        None => err(
            t.col,
            len,
            format!(
                "malformed value '{}': a constant 0–65535 or a data register",
                t.text
            ),
        ),
    }
}

/// The timer or counter operand of a timer, counter or CC instruction.
fn box_operand(t: &Token, want: char, mnemonic: &str) -> Result<u32, Error> {
    match operand(&t.text) {
        Some((letter, n, false)) if letter == want => box_number(n, 1, t),
        _ => {
            let what = if want == 'T' {
                "a timer T0–T255"
            } else {
                "a counter C0–C255"
            };
            err(
                t.col,
                t.text.len(),
                format!("{mnemonic} needs {what}, not '{}'", t.text),
            )
        }
    }
}

/// One point a comparison writes: a Q, M or R bit, with `span` points from it.
fn dest_point(t: &Token, span: u32, pass: &mut Pass) -> Result<((Area, u32), bool), Error> {
    let len = t.text.len();
    let Some((letter, n, repeat)) = operand(&t.text) else {
        return err(
            t.col,
            len,
            format!(
                "'{}': a comparison's result goes to a Q, M or R bit",
                t.text
            ),
        );
    };
    let area = match letter {
        'Q' => Area::Q,
        'M' if n < 8000 => Area::M,
        'R' => Area::R,
        _ => {
            return err(
                t.col,
                len,
                format!("{}: a comparison's result goes to a Q, M or R bit", t.text),
            );
        }
    };
    let index = point(area, n, t)?;
    let span = if repeat { span } else { 1 };
    if index + span > area.points() {
        let last = super::program::point_name(area, area.points() - 1);
        return err(
            t.col,
            len,
            format!("{} with its {span} points runs past {last}", t.text),
        );
    }
    pass.program
        .used_bits
        .extend((index..index + span).map(|i| (area, i)));
    pass.note_m_write(area, index, span);
    Ok(((area, index), repeat))
}

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
fn instruction(
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

/// Stands in `seq` for a line that did not assemble: what it would have done to the rung is
/// unknown, so the rung checks start afresh after it rather than report what follows from it.
const NOT_ASSEMBLED: &str = "?";

/// The rung-structure check of spec §5.1 over the known instructions: (line, mnemonic).
fn rungs(seq: &[(usize, &'static str)], end_line: Option<usize>) -> Vec<(usize, String)> {
    let mut errors = Vec::new();
    let (mut blocks, mut branches) = (0u32, 0u32);
    // The kind of the last instruction other than NOP (NOP may stand anywhere).
    let mut previous: Option<Kind> = None;
    // The first logic instruction since the last output (logic that drives nothing).
    let mut dangling: Option<usize> = None;
    // MCS and JMP not yet closed: the first of each since its last closer.
    let (mut open_mcs, mut open_jmp): (Option<usize>, Option<usize>) = (None, None);
    for &(line, mnemonic) in seq {
        if mnemonic == NOT_ASSEMBLED {
            (blocks, branches, dangling) = (0, 0, None);
            previous = Some(Kind::Output);
            continue;
        }
        let kind = kind_of(mnemonic);
        if kind == Kind::End {
            break;
        }
        if kind == Kind::Nop {
            continue;
        }
        let mut error = None;
        if previous.is_none() && kind != Kind::Load {
            error = Some("a program starts with LOD or LODN".to_string());
        }
        let rung_open = matches!(
            previous,
            Some(Kind::Load | Kind::Logic | Kind::AndOrLod | Kind::Bps | Kind::Brd | Kind::Bpp)
        );
        if matches!(previous, Some(Kind::Boxed(_) | Kind::Opener))
            && !matches!(kind, Kind::Load | Kind::Closer)
        {
            error.get_or_insert_with(|| "after a counter, shift register, MCS or JMP a new rung starts (LOD), or MCR, JEND, NOP or END follows".into());
        }
        match kind {
            Kind::Load => {
                let rung_start = !rung_open;
                if rung_start {
                    if branches > 0 {
                        error.get_or_insert_with(|| {
                            "a new rung starts while BPS is not closed by BPP".into()
                        });
                    }
                    blocks = 0;
                    branches = 0;
                } else {
                    blocks += 1;
                    if blocks > STACK_DEPTH {
                        error.get_or_insert_with(|| "more than 8 LOD blocks open".into());
                    }
                }
                dangling.get_or_insert(line);
            }
            Kind::Logic => {
                dangling.get_or_insert(line);
            }
            Kind::AndOrLod => {
                if blocks == 0 {
                    error.get_or_insert_with(|| format!("{mnemonic} with no LOD block to combine"));
                } else {
                    blocks -= 1;
                }
                dangling.get_or_insert(line);
            }
            Kind::Bps => {
                branches += 1;
                if branches > STACK_DEPTH {
                    error.get_or_insert_with(|| "more than 8 BPS open".into());
                }
                dangling.get_or_insert(line);
            }
            Kind::Brd | Kind::Bpp => {
                if branches == 0 {
                    error.get_or_insert_with(|| format!("{mnemonic} without BPS"));
                } else if kind == Kind::Bpp {
                    branches -= 1;
                }
                dangling.get_or_insert(line);
            }
            Kind::Output | Kind::Opener => {
                if blocks > 0 {
                    error.get_or_insert_with(|| {
                        "an output while LOD blocks are not combined (ANDLOD/ORLOD)".into()
                    });
                }
                if mnemonic == "MCS" {
                    open_mcs.get_or_insert(line);
                } else if mnemonic == "JMP" {
                    open_jmp.get_or_insert(line);
                }
                dangling = None;
            }
            Kind::Boxed(inputs) => {
                if blocks + 1 != inputs {
                    error.get_or_insert_with(|| {
                        format!(
                            "{mnemonic} takes {inputs} inputs, one LOD block each; it has {}",
                            blocks + 1
                        )
                    });
                }
                blocks = 0;
                dangling = None;
            }
            Kind::Closer => {
                if rung_open {
                    error.get_or_insert_with(|| {
                        format!(
                            "{mnemonic} while a rung's logic is open: it stands alone between rungs"
                        )
                    });
                } else if branches > 0 {
                    error.get_or_insert_with(|| {
                        format!("{mnemonic} while BPS is not closed by BPP")
                    });
                }
                let opener = if mnemonic == "MCR" {
                    &mut open_mcs
                } else {
                    &mut open_jmp
                };
                if opener.take().is_none() {
                    let what = if mnemonic == "MCR" {
                        "MCR with no MCS since the previous MCR"
                    } else {
                        "JEND with no JMP since the previous JEND"
                    };
                    error.get_or_insert_with(|| what.into());
                }
                (blocks, branches) = (0, 0);
                dangling = None;
            }
            Kind::Nop | Kind::End => {}
        }
        if let Some(e) = error {
            errors.push((line, e));
        }
        previous = Some(kind);
    }
    let last_line = end_line.or(seq.last().map(|(l, _)| *l));
    if branches > 0
        && let Some(l) = last_line
    {
        errors.push((l, "the program ends with BPS not closed by BPP".into()));
    }
    if let Some(l) = dangling {
        errors.push((l, "logic that drives nothing: no output follows".into()));
    }
    if let Some(l) = open_mcs {
        errors.push((l, "MCS not closed by a later MCR".into()));
    }
    if let Some(l) = open_jmp {
        errors.push((l, "JMP not closed by a later JEND".into()));
    }
    errors
}

/// Each JMP's JEND and each MCS's MCR (the first after it), and whether each LOD starts a
/// rung.
fn resolve(program: &mut Program) {
    let n = program.instrs.len();
    let (mut next_jend, mut next_mcr) = (u32::MAX, u32::MAX);
    for i in (0..n).rev() {
        match program.instrs[i].op {
            Op::Jend => next_jend = i as u32,
            Op::Mcr => next_mcr = i as u32,
            Op::Jmp(_) => program.instrs[i].op = Op::Jmp(next_jend),
            Op::Mcs(_) => program.instrs[i].op = Op::Mcs(next_mcr),
            _ => {}
        }
    }
    let mut opens = Vec::with_capacity(n);
    let mut after_output = true;
    for instr in &program.instrs {
        opens.push(after_output);
        match instr.op {
            Op::Nop => {}
            op => after_output = op.is_output() || matches!(op, Op::Mcr | Op::Jend),
        }
    }
    program.opens = opens;
    program.marks_code = program
        .instrs
        .iter()
        .any(|i| matches!(i.op, Op::Mcs(_) | Op::Jmp(_)));
}

/// One warning per MICRO3 relay read and never written (spec §1).
fn micro3_warnings(pass: &Pass) -> Vec<Diagnostic> {
    pass.micro3_reads
        .iter()
        .filter(|&&(n, ..)| {
            let index = n / 10 * 8 + n % 10;
            !pass.m_written.iter().any(|&(from, len)| (from..from + len).contains(&index))
        })
        .filter_map(|&(n, line, col, len)| {
            let (_, meaning, relay) = MICRO3.iter().find(|m| m.0 == n)?;
            Some(Diagnostic {
                severity: crate::machine::Severity::Warning,
                line,
                col,
                len: len.max(1),
                message: format!("M{n} is the MICRO3 {meaning} relay; on OpenNet it is an ordinary relay this program never writes, so it stays 0: use {relay}"),
            })
        })
        .collect()
}

pub fn assemble(source: &str) -> Result<Program, Vec<Diagnostic>> {
    let text = crate::text::normalize(source);
    let mut pass = Pass::default();
    let mut errors = Vec::new();
    let mut seq: Vec<(usize, &'static str)> = Vec::new();
    let mut end_line = None;
    let suggester = Suggester::default();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        pass.line = line_no;
        let chars: Vec<char> = line.chars().collect();
        let code_end = chars.iter().position(|&c| c == ';').unwrap_or(chars.len());
        let ts = tokens(&chars[..code_end]);
        if ts.is_empty() {
            continue;
        }
        if end_line.is_some() {
            errors.push(Diagnostic::error(
                line_no,
                ts[0].col,
                ts[0].text.len(),
                "an instruction after END",
            ));
            continue;
        }
        let (mnemonic, result) = instruction(&ts, &mut pass, &suggester);
        match mnemonic {
            Some(m) if result.is_ok() => {
                seq.push((line_no, m));
                if m == "END" {
                    end_line = Some(line_no);
                }
            }
            _ => seq.push((line_no, NOT_ASSEMBLED)),
        }
        match result {
            Ok(op) => pass.program.instrs.push(Instr {
                op,
                line: line_no,
                text: chars[..code_end]
                    .iter()
                    .collect::<String>()
                    .trim()
                    .to_string(),
            }),
            Err(e) => errors.push(Diagnostic::error(line_no, e.col, e.len, e.message)),
        }
    }
    for (line, message) in rungs(&seq, end_line) {
        // One error per line: a line that already has one keeps it.
        if !errors.iter().any(|d: &Diagnostic| d.line == line) {
            let col = text
                .lines()
                .nth(line - 1)
                .and_then(|l| l.chars().position(|c| !c.is_whitespace()))
                .map_or(1, |c| c + 1);
            errors.push(Diagnostic::error(line, col, 1, message));
        }
    }
    if !errors.is_empty() {
        errors.sort_by_key(|e| (e.line, e.col));
        return Err(errors);
    }
    let warnings = micro3_warnings(&pass);
    let mut program = pass.program;
    program.warnings = warnings;
    for list in [
        &mut program.used_regs,
        &mut program.signed_regs,
        &mut program.used_timers,
        &mut program.used_counters,
    ] {
        list.sort_unstable();
        list.dedup();
    }
    program.used_bits.sort_unstable();
    program.used_bits.dedup();
    resolve(&mut program);
    program.flat = super::fast::flatten(&program.instrs, &program.opens);
    program.scan_writes = super::fast::scan_writes(&program.instrs);
    program.ladder = std::sync::Arc::new(super::ladder::build(&program.instrs));
    Ok(program)
}
