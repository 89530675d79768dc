//! TML text → [`Program`] (spec §1, §5). Every error is reported, at most one per statement
//! (a bad character: one for its line), sorted by line and column; any error means no program.
//!
//! Decided where the spec is silent: a fixed literal may have at most 25 digits after its
//! point (exact rounding needs them all, and nobody writes more).

mod include;
mod instructions;
mod lex;
mod names;
mod operands;
mod statement;

use std::collections::HashMap;

pub use include::includes;

use super::program::{EventSpec, Op, Program, Stmt, Value};
use crate::machine::Diagnostic;
use crate::machine::diagnostics::Suggester;
use crate::machine::project::Project;
use include::{SourceLine, expand};
use lex::{Tok, allowed, lex};
use names::{Fixup, Names, reserved};
use operands::not_supported;
use statement::{multi_axis, statement, statement_ends};

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
    let mut budget = include::Budget::default();
    if !project.files.is_empty() {
        expand(
            project,
            0,
            &mut Vec::new(),
            &mut lines,
            &mut errors,
            &mut budget,
        );
    }
    // Past the bound, the rest is not assembled: a bomb's million lines would each give
    // their diagnostics again.
    if budget.ran_out() {
        return Err(errors);
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
