//! `.qsl` text → [`Program`] + diagnostics (spec §1).
//!
//! Two passes: the first finds every label (labels may be used before they appear), the second
//! parses each command. Every error in the file is reported; a program is produced only when
//! there is none. DEFs are processed in source order, so a DEF must come before its first use.
//!
//! Decided where the spec is silent:
//! - DEF names are case-sensitive, like labels, and may not reuse a register alias or look like
//!   a register (`R12`). A DEF may name another DEF.
//! - A DEF of a number used where a register is expected names that register (0..=199); a DEF of
//!   a register used where a number is expected is an error (CLX takes data from a register).
//! - `DLY` takes 0 ..= 4294967295 ticks; negative delays are errors.
//! - `q16(...)` is computed exactly from its decimal text (no binary floating point), at most
//!   30 significant digits.

use std::collections::HashMap;

use super::program::{ClcOp, Cond, CondBit, ExtOp, Instr, MoveKind, Program};
use crate::machine::diagnostics::{Diagnostic, Suggester, suggest};

pub use super::program::ALIASES;

pub const MNEMONICS: &[&str] = &[
    "CLC", "CLD", "CLX", "WRP", "JMP", "CALL", "RET", "DLY", "WBS", "CER", "END", "MAV", "MRV",
    "RAV", "RRV", "ZTP", "TTP", "DEF",
];

pub const REGISTER_COUNT: usize = 200;

/// Assemble a whole file. `Err` holds every error, sorted by position.
pub fn assemble(source: &str) -> Result<Program, Vec<Diagnostic>> {
    let mut asm = Assembler::default();
    let lines: Vec<Line> = source
        .lines()
        .enumerate()
        .map(|(i, text)| split_line(i + 1, text))
        .collect();
    asm.collect_labels(&lines);
    for line in &lines {
        asm.line(line);
    }
    if asm.errors.is_empty() {
        let mut used = asm.used;
        used.sort_unstable();
        used.dedup();
        let flat = super::program::flatten(&asm.instrs);
        Ok(Program {
            flat_writes: super::program::flat_writes(&flat),
            loops: super::jit::Loops::find(&flat),
            flat,
            instrs: asm.instrs,
            lines: asm.lines,
            labels: asm.label_list,
            used_registers: used,
            register_names: asm.register_names,
            constants: asm.constants,
        })
    } else {
        asm.errors.sort_by_key(|d| (d.line, d.col));
        Err(asm.errors)
    }
}

/// A piece of a line with its 1-based column.
#[derive(Clone, Copy, Debug)]
struct Tok<'a> {
    text: &'a str,
    col: usize,
}

impl Tok<'_> {
    fn len(&self) -> usize {
        self.text.chars().count()
    }
}

struct Line<'a> {
    number: usize,
    label: Option<Tok<'a>>,
    mnemonic: Option<Tok<'a>>,
    /// Everything after the mnemonic (operands, or `name = value` for DEF).
    rest: Tok<'a>,
    /// A label-looking prefix that is not a valid identifier.
    bad_label: Option<Tok<'a>>,
}

fn column(line: &str, byte_offset: usize) -> usize {
    line[..byte_offset].chars().count() + 1
}

fn is_ident(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn trimmed<'a>(full: &'a str, start: usize, end: usize) -> Tok<'a> {
    let piece = &full[start..end];
    let lead = piece.len() - piece.trim_start().len();
    let text = piece.trim();
    Tok {
        text,
        col: column(full, start + lead),
    }
}

fn split_line(number: usize, full: &str) -> Line<'_> {
    let code_end = full.find(';').unwrap_or(full.len());
    let mut start = 0;
    let mut label = None;
    let mut bad_label = None;
    let code = &full[..code_end];
    if let Some(colon) = code.find(':') {
        let candidate = trimmed(full, 0, colon);
        if is_ident(candidate.text) {
            label = Some(candidate);
            start = colon + 1;
        } else if !candidate.text.contains(char::is_whitespace) && !candidate.text.is_empty() {
            bad_label = Some(candidate);
            start = colon + 1;
        }
    }
    let body = &code[start..];
    let lead = body.len() - body.trim_start().len();
    let body_start = start + lead;
    let word_end = code[body_start..]
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .map_or(code_end, |i| body_start + i);
    let mnemonic = if body.trim().is_empty() {
        None
    } else if word_end == body_start {
        // Starts with something that is not a word: report it as the (bad) mnemonic.
        let end = code[body_start..]
            .find(char::is_whitespace)
            .map_or(code_end, |i| body_start + i);
        Some(trimmed(full, body_start, end))
    } else {
        Some(trimmed(full, body_start, word_end))
    };
    let rest_start = mnemonic.map_or(code_end, |m| {
        let byte = full
            .char_indices()
            .nth(m.col - 1)
            .map_or(code_end, |(b, _)| b);
        byte + m.text.len()
    });
    Line {
        number,
        label,
        mnemonic,
        rest: trimmed(full, rest_start.min(code_end), code_end),
        bad_label,
    }
}

/// Operands separated by commas, each trimmed, with columns. An empty `rest` has no operands.
fn operands<'a>(rest: Tok<'a>) -> Vec<Tok<'a>> {
    if rest.text.is_empty() {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut col = rest.col;
    for piece in rest.text.split(',') {
        let lead = piece.len() - piece.trim_start().len();
        out.push(Tok {
            text: piece.trim(),
            col: col + piece[..lead].chars().count(),
        });
        col += piece.chars().count() + 1;
    }
    out
}

#[derive(Clone, Copy, Debug)]
enum DefValue {
    Number(i64),
    Register(u8),
}

type OpResult<T> = Result<T, String>;

#[derive(Default)]
struct Assembler {
    instrs: Vec<Instr>,
    lines: Vec<u32>,
    labels: HashMap<String, (u32, usize)>,
    label_list: Vec<(String, u32)>,
    defs: HashMap<String, (DefValue, usize)>,
    register_names: Vec<(String, u8)>,
    constants: Vec<(String, i64)>,
    /// "Did you mean" among the program's own names, bounded per file.
    suggester: Suggester,
    /// DEF names and the line that defines them, to explain "used before definition".
    all_defs: HashMap<String, usize>,
    used: Vec<u8>,
    errors: Vec<Diagnostic>,
}

impl Assembler {
    fn error(&mut self, line: usize, tok: Tok<'_>, message: impl Into<String>) {
        self.errors
            .push(Diagnostic::error(line, tok.col, tok.len(), message));
    }

    fn collect_labels(&mut self, lines: &[Line<'_>]) {
        let mut index = 0u32;
        for line in lines {
            if let Some(label) = line.label {
                if let Some(&(_, first)) = self.labels.get(label.text) {
                    self.error(
                        line.number,
                        label,
                        format!(
                            "duplicate label '{}' (first defined on line {first})",
                            label.text
                        ),
                    );
                } else {
                    self.labels
                        .insert(label.text.to_string(), (index, line.number));
                    self.label_list.push((label.text.to_string(), index));
                }
            }
            if let Some(m) = line.mnemonic {
                if m.text.eq_ignore_ascii_case("DEF") {
                    let name = line.rest.text.split('=').next().unwrap_or("").trim();
                    self.all_defs.entry(name.to_string()).or_insert(line.number);
                } else {
                    index += 1;
                }
            }
        }
    }

    fn line(&mut self, line: &Line<'_>) {
        if let Some(bad) = line.bad_label {
            self.error(
                line.number,
                bad,
                format!(
                    "'{}' is not a valid label (letters, digits and _, not starting with a digit)",
                    bad.text
                ),
            );
        }
        let Some(mnemonic) = line.mnemonic else {
            return;
        };
        let upper = mnemonic.text.to_ascii_uppercase();
        if upper == "DEF" {
            self.def(line.number, line.rest);
            return;
        }
        let ops = operands(line.rest);
        let result = self.command(line.number, mnemonic, &upper, &ops);
        self.lines.push(line.number as u32);
        // A placeholder keeps command indices (and so labels) right while errors are collected.
        self.instrs.push(result.unwrap_or(Instr::End));
    }

    fn def(&mut self, line: usize, rest: Tok<'_>) {
        let Some(eq) = rest.text.find('=') else {
            self.error(line, rest, "DEF needs the form 'DEF name = value'");
            return;
        };
        let name = trimmed(rest.text, 0, eq);
        let name = Tok {
            text: name.text,
            col: rest.col + name.col - 1,
        };
        let value = trimmed(rest.text, eq + 1, rest.text.len());
        let value = Tok {
            text: value.text,
            col: rest.col + value.col - 1,
        };
        if !is_ident(name.text) {
            self.error(
                line,
                name,
                format!("'{}' is not a valid DEF name", name.text),
            );
            return;
        }
        if alias(name.text).is_some() || register_number(name.text).is_some() {
            self.error(
                line,
                name,
                format!("'{}' is a register name and cannot be redefined", name.text),
            );
            return;
        }
        if let Some(&(_, first)) = self.defs.get(name.text) {
            self.error(
                line,
                name,
                format!("'{}' is already defined on line {first}", name.text),
            );
            return;
        }
        if value.text.is_empty() {
            self.error(line, value, "DEF needs a value after '='");
            return;
        }
        let parsed = if let Some(reg) = register_number(value.text).or_else(|| alias(value.text)) {
            Ok(DefValue::Register(reg))
        } else if let Some(&(v, _)) = self.defs.get(value.text) {
            Ok(v)
        } else {
            self.data_value(value).map(DefValue::Number)
        };
        match parsed {
            Ok(v) => {
                match v {
                    DefValue::Register(r) => self.register_names.push((name.text.to_string(), r)),
                    DefValue::Number(n) => self.constants.push((name.text.to_string(), n)),
                }
                self.defs.insert(name.text.to_string(), (v, line));
            }
            Err(message) => self.error(line, value, message),
        }
    }

    fn command(
        &mut self,
        line: usize,
        mnemonic: Tok<'_>,
        upper: &str,
        ops: &[Tok<'_>],
    ) -> Option<Instr> {
        let arity: (usize, usize, &str) = match upper {
            "CLC" => (2, 2, "operation, register"),
            "CLD" => (4, 4, "operation, result, reg1, data"),
            "CLX" => (4, 4, "operation, result, reg1, reg2"),
            "WRP" => (2, 2, "register, value"),
            "JMP" => (1, 2, "label [, condition]"),
            "CALL" => (1, 1, "label"),
            "RET" | "END" | "ZTP" | "TTP" => (0, 0, "nothing"),
            "DLY" => (1, 1, "ticks"),
            "WBS" => (1, 1, "condition"),
            "CER" => (1, 1, "label or 0"),
            "MAV" | "MRV" => (3, 4, "position, accel, vel [, condition]"),
            "RAV" | "RRV" => (3, 4, "register, accel, vel [, condition]"),
            _ => {
                let hint = suggest(mnemonic.text, MNEMONICS.iter().copied())
                    .map(|s| format!("; did you mean {s}?"))
                    .unwrap_or_default();
                self.error(
                    line,
                    mnemonic,
                    format!("unknown command '{}'{hint}", mnemonic.text),
                );
                return None;
            }
        };
        let (min, max, shape) = arity;
        if ops.len() < min || ops.len() > max {
            let expected = if min == max {
                format!("{min}")
            } else {
                format!("{min} or {max}")
            };
            let plural = if max == 1 { "" } else { "s" };
            let at = if ops.len() > max { ops[max] } else { mnemonic };
            self.error(
                line,
                at,
                format!(
                    "{upper} takes {expected} operand{plural} ({shape}), found {}",
                    ops.len()
                ),
            );
            return None;
        }
        // Parse every operand even after one fails, so all errors of the line are reported.
        let instr = match upper {
            "CLC" => {
                let (op, reg) = (self.clc_op(line, ops[0]), self.register(line, ops[1]));
                Instr::Clc { op: op?, reg: reg? }
            }
            "CLD" | "CLX" => {
                let (op, res, reg1) = (
                    self.ext_op(line, ops[0], upper),
                    self.register(line, ops[1]),
                    self.register(line, ops[2]),
                );
                if upper == "CLD" {
                    let data = self.data(line, ops[3], true);
                    let (op, res, reg1, data) = (op?, res?, reg1?, data?);
                    self.note_ext_registers(op, res, reg1, Some(data));
                    Instr::Cld {
                        op,
                        res,
                        reg1,
                        data,
                    }
                } else {
                    let reg2 = self.register(line, ops[3]);
                    let (op, res, reg1, reg2) = (op?, res?, reg1?, reg2?);
                    self.note_ext_registers(op, res, reg1, None);
                    Instr::Clx {
                        op,
                        res,
                        reg1,
                        reg2,
                    }
                }
            }
            "WRP" => {
                let (reg, value) = (self.register(line, ops[0]), self.data(line, ops[1], false));
                Instr::Wrp {
                    reg: reg?,
                    value: value?,
                }
            }
            "JMP" => {
                let target = self.label(line, ops[0]);
                let cond = ops.get(1).map(|&c| self.cond(line, c));
                Instr::Jmp {
                    target: target?,
                    cond: match cond {
                        Some(c) => Some(c?),
                        None => None,
                    },
                }
            }
            "CALL" => Instr::Call {
                target: self.label(line, ops[0])?,
            },
            "RET" => Instr::Ret,
            "END" => Instr::End,
            "ZTP" => Instr::Ztp,
            "TTP" => Instr::Ttp,
            "DLY" => {
                let value = self.number(line, ops[0])?;
                if value < 0 {
                    self.error(line, ops[0], "a delay cannot be negative");
                    return None;
                }
                Instr::Dly {
                    ticks: value as u32,
                }
            }
            "WBS" => Instr::Wbs {
                cond: self.cond(line, ops[0])?,
            },
            "CER" => {
                if ops[0].text == "0" {
                    Instr::Cer { target: None }
                } else {
                    Instr::Cer {
                        target: Some(self.label(line, ops[0])?),
                    }
                }
            }
            _ => {
                let kind = match upper {
                    "MAV" => MoveKind::Mav,
                    "MRV" => MoveKind::Mrv,
                    "RAV" => MoveKind::Rav,
                    _ => MoveKind::Rrv,
                };
                let pos = if kind.takes_register() {
                    self.register(line, ops[0]).map(i32::from)
                } else {
                    self.data(line, ops[0], false)
                };
                let (accel, vel) = (
                    self.data(line, ops[1], false),
                    self.data(line, ops[2], false),
                );
                let cond = ops.get(3).map(|&c| self.cond(line, c));
                self.used.extend([0, 1, 6, 7]);
                Instr::Move {
                    kind,
                    pos: pos?,
                    accel: accel?,
                    vel: vel?,
                    cond: match cond {
                        Some(c) => Some(c?),
                        None => None,
                    },
                }
            }
        };
        if let Instr::Clc { op, .. } = instr {
            self.used.push(10);
            if op == ClcOp::SubTarget {
                self.used.extend([0, 1]);
            }
        }
        Some(instr)
    }

    /// Registers an extended op touches beyond its operands, for the "used registers" filter.
    fn note_ext_registers(&mut self, op: ExtOp, res: u8, reg1: u8, data: Option<i32>) {
        match op {
            ExtOp::MultU64 if res < 199 => self.used.push(res + 1),
            ExtOp::DivU64 if reg1 < 199 => self.used.push(reg1 + 1),
            ExtOp::QInit => {
                let size = data.unwrap_or(0).max(0) as usize;
                let end = (reg1 as usize + 1 + size).min(REGISTER_COUNT - 1);
                self.used.extend((reg1..=end as u8).collect::<Vec<_>>());
            }
            _ if op.is_queue() && reg1 < 199 => self.used.push(reg1 + 1),
            _ => {}
        }
    }

    fn clc_op(&mut self, line: usize, tok: Tok<'_>) -> Option<ClcOp> {
        if let Some(op) = ClcOp::parse(tok.text) {
            return Some(op);
        }
        let message = if ExtOp::parse(tok.text).is_some() {
            format!(
                "{} is a CLD/CLX operation, not a CLC one",
                tok.text.to_ascii_uppercase()
            )
        } else {
            unknown("CLC operation", tok.text, ClcOp::NAMES)
        };
        self.error(line, tok, message);
        None
    }

    fn ext_op(&mut self, line: usize, tok: Tok<'_>, mnemonic: &str) -> Option<ExtOp> {
        if let Some(op) = ExtOp::parse(tok.text) {
            return Some(op);
        }
        let message = if ClcOp::parse(tok.text).is_some() {
            format!(
                "{} is a CLC operation, not a {mnemonic} one",
                tok.text.to_ascii_uppercase()
            )
        } else {
            unknown(&format!("{mnemonic} operation"), tok.text, ExtOp::NAMES)
        };
        self.error(line, tok, message);
        None
    }

    fn cond(&mut self, line: usize, tok: Tok<'_>) -> Option<Cond> {
        let (negated, name) = match tok.text.strip_prefix('!') {
            Some(rest) => (true, rest.trim()),
            None => (false, tok.text),
        };
        match CondBit::parse(name) {
            Some(bit) => Some(Cond { bit, negated }),
            None => {
                let message = if name.is_empty() {
                    "missing condition".to_string()
                } else {
                    unknown("condition", name, CondBit::NAMES)
                };
                self.error(line, tok, message);
                None
            }
        }
    }

    fn label(&mut self, line: usize, tok: Tok<'_>) -> Option<u32> {
        if let Some(&(index, _)) = self.labels.get(tok.text) {
            return Some(index);
        }
        let message = if tok.text.is_empty() {
            "missing label".to_string()
        } else if !is_ident(tok.text) {
            format!("'{}' is not a label name", tok.text)
        } else {
            let hint = self
                .suggester
                .suggest(tok.text, self.labels.keys().map(String::as_str))
                .map(|s| format!("; did you mean '{s}'?"))
                .unwrap_or_default();
            format!("undefined label '{}'{hint}", tok.text)
        };
        self.error(line, tok, message);
        None
    }

    fn register(&mut self, line: usize, tok: Tok<'_>) -> Option<u8> {
        let result = self.register_value(tok);
        match result {
            Ok(r) => {
                self.used.push(r);
                Some(r)
            }
            Err(message) => {
                self.error(line, tok, message);
                None
            }
        }
    }

    fn register_value(&self, tok: Tok<'_>) -> OpResult<u8> {
        let text = tok.text;
        if text.is_empty() {
            return Err("missing register".into());
        }
        if let Some(r) = alias(text) {
            return Ok(r);
        }
        if let Some(digits) = text.strip_prefix(['R', 'r'])
            && !digits.is_empty()
            && digits.chars().all(|c| c.is_ascii_digit())
        {
            return register_in_range(digits.parse::<i64>().unwrap_or(i64::MAX), text);
        }
        if is_ident(text) {
            return match self.lookup_def(text)? {
                DefValue::Register(r) => Ok(r),
                DefValue::Number(n) => register_in_range(n, text),
            };
        }
        if text.to_ascii_lowercase().starts_with("q16(") {
            return Err("a q16(...) literal is a number, not a register".into());
        }
        let n = parse_number(text)?;
        register_in_range(n, text)
    }

    fn lookup_def(&self, name: &str) -> OpResult<DefValue> {
        if let Some(&(value, _)) = self.defs.get(name) {
            return Ok(value);
        }
        if let Some(&defined) = self.all_defs.get(name) {
            return Err(format!("'{name}' is used before its DEF on line {defined}"));
        }
        if let Some(digits) = name.strip_prefix(['R', 'r'])
            && !digits.is_empty()
            && digits.chars().all(|c| c.is_ascii_digit())
        {
            // A register by its number, past the last one: say so, not "unknown name".
            return Err(format!("register {name} is outside R0–R199"));
        }
        let candidates = self
            .defs
            .keys()
            .map(String::as_str)
            .chain(ALIASES.iter().map(|a| a.name));
        let hint = self
            .suggester
            .suggest(name, candidates)
            .map(|s| format!("; did you mean '{s}'?"))
            .unwrap_or_default();
        Err(format!("unknown name '{name}'{hint}"))
    }

    /// A 32-bit data operand (stored as its low 32 bits).
    fn data(&mut self, line: usize, tok: Tok<'_>, cld: bool) -> Option<i32> {
        match self.data_value(tok) {
            Ok(v) => Some(v as u32 as i32),
            Err(mut message) => {
                if cld && register_number(tok.text).is_some() {
                    message.push_str(" (CLX takes its data from a register)");
                }
                self.error(line, tok, message);
                None
            }
        }
    }

    /// A data operand as written, before truncation to 32 bits.
    fn number(&mut self, line: usize, tok: Tok<'_>) -> Option<i64> {
        match self.data_value(tok) {
            Ok(v) => Some(v),
            Err(message) => {
                self.error(line, tok, message);
                None
            }
        }
    }

    fn data_value(&self, tok: Tok<'_>) -> OpResult<i64> {
        let text = tok.text;
        if text.is_empty() {
            return Err("missing value".into());
        }
        if let Some(inner) = strip_call(text, "q16") {
            return parse_q16(inner).map_err(|e| e.to_string());
        }
        if let Some(r) = register_number(text).or_else(|| alias(text)) {
            return Err(format!("expected a number, found register R{r}"));
        }
        if is_ident(text) {
            return match self.lookup_def(text)? {
                DefValue::Number(n) => Ok(n),
                DefValue::Register(r) => Err(format!(
                    "'{text}' names register R{r}, but a number is expected here"
                )),
            };
        }
        let n = parse_number(text)?;
        if !(-(1i64 << 31)..=u32::MAX as i64).contains(&n) {
            return Err(format!(
                "{text} does not fit in 32 bits (-2147483648 ..= 4294967295)"
            ));
        }
        Ok(n)
    }
}

fn unknown(what: &str, text: &str, names: &[&str]) -> String {
    let hint = suggest(text, names.iter().copied())
        .map(|s| format!("; did you mean {s}?"))
        .unwrap_or_default();
    format!("unknown {what} '{text}'{hint}")
}

fn alias(text: &str) -> Option<u8> {
    ALIASES
        .iter()
        .find(|a| a.name.eq_ignore_ascii_case(text))
        .map(|a| a.register)
}

/// `R26` / `r26` → 26 when in range.
fn register_number(text: &str) -> Option<u8> {
    let digits = text.strip_prefix(['R', 'r'])?;
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    digits
        .parse::<u8>()
        .ok()
        .filter(|&r| (r as usize) < REGISTER_COUNT)
}

fn register_in_range(n: i64, text: &str) -> OpResult<u8> {
    if (0..REGISTER_COUNT as i64).contains(&n) {
        Ok(n as u8)
    } else {
        Err(format!("register {text} is outside R0–R199"))
    }
}

fn strip_call<'a>(text: &'a str, name: &str) -> Option<&'a str> {
    let open = text.find('(')?;
    if !text[..open].trim().eq_ignore_ascii_case(name) {
        return None;
    }
    text[open + 1..].strip_suffix(')')
}

/// Decimal, `0x` hex or `0b` binary, optional sign, `_` separators. Range is checked by callers.
pub fn parse_number(text: &str) -> OpResult<i64> {
    let body = text.trim_start_matches(['-', '+']).to_ascii_lowercase();
    if body.starts_with("0o") {
        // Octal is not SilverLode syntax.
        return Err(format!("'{text}' is not a number"));
    }
    let too_big = || format!("{text} does not fit in 32 bits");
    match crate::machine::value::parse_integer(text) {
        Ok(v) if v.unsigned_abs() > 1 << 40 => Err(too_big()),
        Ok(v) => Ok(v as i64),
        Err(crate::machine::value::ValueError::Over64Bits(_)) => Err(too_big()),
        Err(e) => Err(e.to_string()),
    }
}

use crate::machine::value::parse_q16;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_every_base() {
        assert_eq!(parse_number("-15"), Ok(-15));
        assert_eq!(parse_number("0x2BCD"), Ok(0x2BCD));
        assert_eq!(parse_number("0b1010"), Ok(10));
        assert_eq!(parse_number("0xABCD_893F"), Ok(0xABCD_893F));
        assert_eq!(parse_number("1_000_000"), Ok(1_000_000));
        assert!(parse_number("12z").is_err());
        assert!(parse_number("0x").is_err());
        assert!(parse_number("-").is_err());
    }

    #[test]
    fn line_splitting_keeps_columns() {
        let line = split_line(3, "  loop: CLD ADD, 25, 26 ; comment");
        assert_eq!(line.label.map(|t| (t.text, t.col)), Some(("loop", 3)));
        assert_eq!(line.mnemonic.map(|t| (t.text, t.col)), Some(("CLD", 9)));
        let ops = operands(line.rest);
        let got: Vec<_> = ops.iter().map(|t| (t.text, t.col)).collect();
        assert_eq!(got, vec![("ADD", 13), ("25", 18), ("26", 22)]);
    }
}
