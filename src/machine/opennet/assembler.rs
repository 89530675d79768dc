//! OpenNet instruction-list text → [`Program`] (spec §1, §4.3, §5.1). Every error is reported
//! (one per line), sorted; any error means no program.

use super::program::{Area, Arith, Bit, Instr, Op, Program, SPECIAL, Ty, Word};
use crate::machine::Diagnostic;
use crate::machine::diagnostics::Suggester;

pub const BASIC: &[&str] = &[
    "LOD", "LODN", "AND", "ANDN", "OR", "ORN", "ANDLOD", "ORLOD", "BPS", "BRD", "BPP", "SOTU",
    "SOTD", "OUT", "OUTN", "SET", "RST", "END",
];
pub const ADVANCED: &[&str] = &["MOV", "ADD", "SUB", "MUL", "DIV", "INC", "DEC"];

/// Real OpenNet instructions outside the subset.
pub const UNSUPPORTED: &[&str] = &[
    "TML", "TIM", "TMH", "TMS", "CNT", "CDP", "CUD", "CC=", "CC>=", "DC=", "DC>=", "SFR", "SFRN",
    "JMP", "JEND", "MCS", "MCR", "NOP", "CMP=", "CMP<>", "CMP<", "CMP>", "CMP<=", "CMP>=",
    "ICMP>=", "ANDW", "ORW", "XORW", "SFTL", "SFTR", "BCDLS", "WSFT", "ROTL", "ROTR", "HTOB",
    "BTOH", "HTOA", "ATOH", "BTOA", "ATOB", "ENCO", "DECO", "BTOD", "DTOB", "SWAP", "LABEL",
    "LJMP", "LCAL", "LRET", "IOREF", "DISP", "DGRD", "TXD", "RXD", "CVXTY", "CVYTX", "AVRG",
    "PULS", "PWM", "RAMP", "ZRN", "PID", "NEG", "ROOT", "SUM", "IMOV", "IMOVN", "BMOV", "NSET",
    "NRS", "XCHG", "TCCST", "MOVN", "WKTIM", "WKTBL", "DTML", "DTIM", "DTMH", "DTMS", "TTIM",
    "DJNZ", "DI", "EI", "CALL", "RET",
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
    Load,
    Logic,
    AndOrLod,
    Bps,
    Brd,
    Bpp,
    Output,
    End,
}

fn kind_of(mnemonic: &str) -> Kind {
    match mnemonic {
        "LOD" | "LODN" => Kind::Load,
        "AND" | "ANDN" | "OR" | "ORN" | "SOTU" | "SOTD" => Kind::Logic,
        "ANDLOD" | "ORLOD" => Kind::AndOrLod,
        "BPS" => Kind::Bps,
        "BRD" => Kind::Brd,
        "BPP" => Kind::Bpp,
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

/// An I/Q/M point number in IDEC numbering → its index.
fn point(area: Area, n: u32, t: &Token) -> Result<u32, Error> {
    if n % 10 >= 8 {
        return err(t.col, t.text.len(), format!("{}: the last digit of an {} number is octal (0–7)", t.text, area.letter()));
    }
    let index = n / 10 * 8 + n % 10;
    if index >= area.points() {
        let last = super::program::point_name(area, area.points() - 1);
        return err(t.col, t.text.len(), format!("{} is out of range ({}0–{last})", t.text, area.letter()));
    }
    Ok(index)
}

fn unsupported_operand(letter: char, t: &Token) -> Error {
    let what = match letter {
        'T' => "a timer (T)",
        'C' => "a counter (C)",
        'R' => "a shift register bit (R)",
        'L' => "a link register (L)",
        _ => "this operand",
    };
    Error {
        col: t.col,
        len: t.text.len(),
        message: format!("{} is {what}, not supported by servoscope yet", t.text),
    }
}

/// A bit operand; `output`: OUT/OUTN/SET/RST (no input, no read-only special relay).
fn bit(t: &Token, output: bool, program: &mut Program) -> Result<Bit, Error> {
    let Some((letter, n, repeat)) = operand(&t.text) else {
        return err(t.col, t.text.len(), format!("'{}' is not a bit operand (I, Q or M)", t.text));
    };
    if repeat {
        return err(t.col, t.text.len(), "(R) belongs to advanced instructions with REP");
    }
    let b = match letter {
        'I' if output => return err(t.col, t.text.len(), format!("{} is an input: a program cannot write it", t.text)),
        'I' => Bit::Point(Area::I, point(Area::I, n, t)?),
        'Q' => Bit::Point(Area::Q, point(Area::Q, n, t)?),
        'M' if n >= 8000 => {
            let Some(i) = SPECIAL.iter().position(|&s| u32::from(s) == n) else {
                return err(t.col, t.text.len(), format!("{} is a special relay not supported by servoscope yet (M8003, M8004, M8120–M8122 are)", t.text));
            };
            if output && i >= 2 {
                return err(t.col, t.text.len(), format!("{} is read-only", t.text));
            }
            Bit::Special(i as u8)
        }
        'M' => Bit::Point(Area::M, point(Area::M, n, t)?),
        'D' => return err(t.col, t.text.len(), format!("{} is a data register: a bit instruction needs I, Q or M", t.text)),
        'T' | 'C' | 'R' | 'L' => return Err(unsupported_operand(letter, t)),
        _ => return err(t.col, t.text.len(), format!("'{}' is not an operand", t.text)),
    };
    if let Bit::Point(area, index) = b {
        program.used_bits.push((area, index));
    }
    Ok(b)
}

/// A word operand: `dest` for D1; `words` its block size; `rep` the repeat count.
fn word(t: &Token, ty: Ty, dest: bool, words: u32, rep: u32, program: &mut Program) -> Result<Word, Error> {
    let len = t.text.len();
    if let Some((letter, n, repeat)) = operand(&t.text) {
        let span = words * if repeat { rep } else { 1 };
        return match letter {
            'D' => {
                if (8000..8500).contains(&n) {
                    return err(t.col, len, format!("{} is a special data register, not supported by servoscope yet", t.text));
                }
                if n >= REGISTERS {
                    return err(t.col, len, format!("{} is out of range (D0–D7999)", t.text));
                }
                if n + span > REGISTERS {
                    return err(t.col, len, format!("{} with its {span} word(s) runs past D7999", t.text));
                }
                program.used_regs.extend(n..n + span);
                if ty.signed() {
                    // Each item's first word: an I word, or the upper (sign) word of an L pair.
                    program.signed_regs.extend((n..n + span).step_by(words.max(1) as usize));
                }
                Ok(Word::Reg { n, repeat })
            }
            'I' | 'Q' | 'M' => {
                let area = match letter {
                    'I' if dest => return err(t.col, len, format!("{} is an input: it cannot be a destination", t.text)),
                    'I' => Area::I,
                    'Q' => Area::Q,
                    _ => Area::M,
                };
                if area == Area::M && n >= 8000 {
                    return err(t.col, len, format!("{}: special relays are never word operands", t.text));
                }
                let index = point(area, n, t)?;
                if index + span * 16 > area.points() {
                    let last = super::program::point_name(area, area.points() - 1);
                    return err(t.col, len, format!("{} with its {} points runs past {last}", t.text, span * 16));
                }
                program.used_bits.extend((index..index + span * 16).map(|i| (area, i)));
                Ok(Word::Bits { area, index, repeat })
            }
            'T' | 'C' | 'R' | 'L' => Err(unsupported_operand(letter, t)),
            _ => err(t.col, len, format!("'{}' is not an operand (D, I, Q, M or a constant)", t.text)),
        };
    }
    if t.text.to_ascii_uppercase().ends_with("(R)") {
        return err(t.col, len, "(R) cannot follow a constant");
    }
    let Some((v, hex)) = constant(&t.text) else {
        return err(t.col, len, format!("malformed operand or constant '{}'", t.text));
    };
    if dest {
        return err(t.col, len, "a constant cannot be a destination");
    }
    let pattern = if hex {
        if v >> ty.bits() != 0 {
            return err(t.col, len, format!("{} does not fit {} bits", t.text, ty.bits()));
        }
        v as u32
    } else {
        if v < ty.min() || v > ty.max() {
            return err(t.col, len, format!("{} is out of range for type {} ({} … {})", t.text, ty.letter(), ty.min(), ty.max()));
        }
        v as u32 & if ty.words() == 1 { 0xFFFF } else { u32::MAX }
    };
    Ok(Word::Const(pattern))
}

/// The suggestion for an unknown mnemonic: `ADDW` → `ADD(W)`, else the closest known one.
fn suggestion(word: &str, suggester: &Suggester) -> Option<String> {
    let upper = word.to_ascii_uppercase();
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

/// One line's instruction: its mnemonic (for the rung check) and the result.
fn instruction(ts: &[Token], program: &mut Program, suggester: &Suggester) -> (Option<&'static str>, Result<Op, Error>) {
    let first = &ts[0];
    let raw = first.text.to_ascii_uppercase();
    let (base, ty_text) = match raw.split_once('(') {
        Some((b, rest)) => (b.to_string(), Some(rest.trim_end_matches(')').to_string())),
        None => (raw.clone(), None),
    };
    let mut rest: Vec<Token> = ts[1..].to_vec();
    // `AND LOD` / `OR LOD`.
    let base = if (base == "AND" || base == "OR") && ty_text.is_none() && rest.first().is_some_and(|t| t.text.eq_ignore_ascii_case("LOD")) {
        rest.remove(0);
        format!("{base}LOD")
    } else {
        base
    };
    let known = BASIC.iter().chain(ADVANCED.iter()).find(|m| **m == base).copied();
    let Some(mnemonic) = known else {
        if UNSUPPORTED.contains(&base.as_str()) {
            return (None, err(first.col, first.text.len(), format!("{base} is an OpenNet instruction not supported by servoscope yet")));
        }
        let hint = suggestion(&first.text, suggester).map(|s| format!(" (did you mean {s}?)")).unwrap_or_default();
        return (None, err(first.col, first.text.len(), format!("unknown mnemonic '{}'{hint}", first.text)));
    };
    let result = (|| {
        let advanced = ADVANCED.contains(&mnemonic);
        let ty = match (&ty_text, advanced) {
            (Some(_), false) => return err(first.col, first.text.len(), format!("{mnemonic} is a basic instruction: it takes no data type")),
            (None, true) => {
                let types = if matches!(mnemonic, "INC" | "DEC") { "(W) or (D)" } else { "(W), (I), (D) or (L)" };
                return err(first.col, first.text.len(), format!("{mnemonic} needs a data type: {mnemonic}{types}"));
            }
            (Some(t), true) => match Ty::parse(t) {
                Some(ty) if matches!(mnemonic, "INC" | "DEC") && ty.signed() => {
                    return err(first.col, first.text.len(), format!("{mnemonic} takes type W or D, not {t}"));
                }
                Some(ty) => Some(ty),
                None => return err(first.col, first.text.len(), format!("invalid data type '{t}': W, I, D or L")),
            },
            (None, false) => None,
        };
        // REP n at the end.
        let mut rep: u32 = 1;
        let mut has_rep = false;
        if let Some(k) = rest.iter().position(|t| t.text.eq_ignore_ascii_case("REP")) {
            let rep_tok = rest[k].clone();
            if !matches!(mnemonic, "MOV" | "ADD" | "SUB" | "MUL" | "DIV") {
                return err(rep_tok.col, 3, format!("{mnemonic} cannot repeat (REP is for MOV, ADD, SUB, MUL, DIV)"));
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
                return err(extra.col, extra.text.len(), "unexpected text after the REP count");
            }
            rest.truncate(k);
            has_rep = true;
        }
        let want = match mnemonic {
            "ANDLOD" | "ORLOD" | "BPS" | "BRD" | "BPP" | "SOTU" | "SOTD" | "END" => 0,
            "MOV" => 2,
            "ADD" | "SUB" | "MUL" | "DIV" => 3,
            _ => 1,
        };
        if rest.len() != want {
            let (col, len) = rest.get(want).map_or((first.col, first.text.len()), |t| (t.col, t.text.len()));
            return err(col, len, format!("{mnemonic} takes {want} operand(s), found {}", rest.len()));
        }
        if !has_rep && let Some(t) = rest.iter().find(|t| t.text.to_ascii_uppercase().ends_with("(R)")) {
            return err(t.col, t.text.len(), "(R) without REP: add REP n after the operands");
        }
        Ok(match mnemonic {
            "LOD" | "LODN" => Op::Lod(bit(&rest[0], false, program)?, mnemonic == "LODN"),
            "AND" | "ANDN" => Op::And(bit(&rest[0], false, program)?, mnemonic == "ANDN"),
            "OR" | "ORN" => Op::Or(bit(&rest[0], false, program)?, mnemonic == "ORN"),
            "ANDLOD" => Op::AndLod,
            "ORLOD" => Op::OrLod,
            "BPS" => Op::Bps,
            "BRD" => Op::Brd,
            "BPP" => Op::Bpp,
            "SOTU" | "SOTD" => {
                let m = program.edges;
                program.edges += 1;
                if mnemonic == "SOTU" { Op::Sotu(m) } else { Op::Sotd(m) }
            }
            "OUT" | "OUTN" => Op::Out(bit(&rest[0], true, program)?, mnemonic == "OUTN"),
            "SET" => Op::Set(bit(&rest[0], true, program)?),
            "RST" => Op::Rst(bit(&rest[0], true, program)?),
            "END" => Op::End,
            "INC" | "DEC" => {
                let ty = ty.unwrap_or(Ty::W);
                let t = &rest[0];
                match word(t, ty, true, ty.words(), 1, program)? {
                    Word::Reg { n, .. } => Op::Step { up: mnemonic == "INC", ty, reg: n },
                    _ => return err(t.col, t.text.len(), format!("{mnemonic} works on a data register (D)")),
                }
            }
            "MOV" => {
                let ty = ty.unwrap_or(Ty::W);
                let src = word(&rest[0], ty, false, ty.words(), rep, program)?;
                let dst = word(&rest[1], ty, true, ty.words(), rep, program)?;
                Op::Mov { ty, src, dst, rep: rep as u8 }
            }
            _ => {
                let ty = ty.unwrap_or(Ty::W);
                let op = match mnemonic {
                    "ADD" => Arith::Add,
                    "SUB" => Arith::Sub,
                    "MUL" => Arith::Mul,
                    _ => Arith::Div,
                };
                let dst_words = match op {
                    Arith::Add | Arith::Sub => ty.words(),
                    Arith::Mul => 2,
                    Arith::Div => 2 * ty.words(),
                };
                let a = word(&rest[0], ty, false, ty.words(), rep, program)?;
                let b = word(&rest[1], ty, false, ty.words(), rep, program)?;
                let dst = word(&rest[2], ty, true, dst_words, rep, program)?;
                Op::Arith { op, ty, a, b, dst, rep: rep as u8 }
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
    let mut previous: Option<Kind> = None;
    // The first logic instruction since the last output (logic that drives nothing).
    let mut dangling: Option<usize> = None;
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
        let mut error = None;
        if previous.is_none() && kind != Kind::Load {
            error = Some("a program starts with LOD or LODN".to_string());
        }
        match kind {
            Kind::Load => {
                let rung_start = matches!(previous, None | Some(Kind::Output));
                if rung_start {
                    if branches > 0 {
                        error.get_or_insert_with(|| "a new rung starts while BPS is not closed by BPP".into());
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
            Kind::Output => {
                if blocks > 0 {
                    error.get_or_insert_with(|| "an output while LOD blocks are not combined (ANDLOD/ORLOD)".into());
                }
                dangling = None;
            }
            Kind::End => {}
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
    errors
}

pub fn assemble(source: &str) -> Result<Program, Vec<Diagnostic>> {
    let text = crate::text::normalize(source);
    let mut program = Program::default();
    let mut errors = Vec::new();
    let mut seq: Vec<(usize, &'static str)> = Vec::new();
    let mut end_line = None;
    let suggester = Suggester::default();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let chars: Vec<char> = line.chars().collect();
        let code_end = chars.iter().position(|&c| c == ';').unwrap_or(chars.len());
        let ts = tokens(&chars[..code_end]);
        if ts.is_empty() {
            continue;
        }
        if end_line.is_some() {
            errors.push(Diagnostic::error(line_no, ts[0].col, ts[0].text.len(), "an instruction after END"));
            continue;
        }
        let (mnemonic, result) = instruction(&ts, &mut program, &suggester);
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
            Ok(op) => program.instrs.push(Instr {
                op,
                line: line_no,
                text: chars[..code_end].iter().collect::<String>().trim().to_string(),
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
    program.used_regs.sort_unstable();
    program.used_regs.dedup();
    program.signed_regs.sort_unstable();
    program.signed_regs.dedup();
    program.used_bits.sort_unstable();
    program.used_bits.dedup();
    program.flat = super::fast::flatten(&program.instrs);
    program.scan_writes = super::fast::scan_writes(&program.instrs);
    Ok(program)
}
