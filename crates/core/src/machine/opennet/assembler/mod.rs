//! OpenNet instruction-list text → [`Program`] (spec §1, §4.3, §5.1). Every error is reported
//! (one per line), sorted; any error means no program.

mod instruction;
mod operands;
mod rungs;

use super::program::{Area, Instr, Program};
use crate::machine::Diagnostic;
use crate::machine::diagnostics::Suggester;
use instruction::instruction;
use rungs::{NOT_ASSEMBLED, resolve, rungs};

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
        let mut code_end = chars.iter().position(|&c| c == ';').unwrap_or(chars.len());
        // The code before it is still read, so the rungs after it are checked as written.
        if let Some(k) = chars[..code_end].windows(2).position(|w| w == ['/', '/']) {
            errors.push(Diagnostic::error(
                line_no,
                k + 1,
                2,
                "OpenNet comments start with ; ('//' starts a comment in DL205, not here)",
            ));
            code_end = k;
        }
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
