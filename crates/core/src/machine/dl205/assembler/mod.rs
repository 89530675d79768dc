//! DirectSOFT mnemonic text → [`Program`] (spec §1, §2, §6.8). Every faulty line is reported
//! once; the rung-structure checks run only when every line is valid.

mod control;
mod instruction;
mod operands;
mod rungs;

use super::program::{ElementDoc, Instr, Program};
use crate::machine::Diagnostic;
use crate::machine::diagnostics::Suggester;
use control::control;
use instruction::instruction;
use rungs::rungs;

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

/// One record of an ELEMENT_DOC block, as DirectSOFT writes it (Host Engineering's
/// description: double-quoted fields "element", "nickname", "wiring info", "description", a
/// quote inside doubled). A line that is not such a record is passed over, as the rest of a
/// `#BEGIN` block is.
fn element_doc(line: &str) -> Option<ElementDoc> {
    let mut fields = Vec::new();
    let mut chars = line.trim().chars().peekable();
    loop {
        while chars.peek().is_some_and(|c| c.is_whitespace()) {
            chars.next();
        }
        let mut field = String::new();
        if chars.peek() == Some(&'"') {
            chars.next();
            loop {
                match chars.next()? {
                    '"' if chars.peek() == Some(&'"') => {
                        chars.next();
                        field.push('"');
                    }
                    '"' => break,
                    c => field.push(c),
                }
            }
            while chars.peek().is_some_and(|&c| c != ',') {
                chars.next();
            }
        } else {
            while let Some(&c) = chars.peek().filter(|&&c| c != ',') {
                field.push(c);
                chars.next();
            }
        }
        fields.push(field.trim().to_string());
        if chars.next().is_none() {
            break;
        }
    }
    let element = fields.first()?.to_ascii_uppercase();
    if element.is_empty() || !element.starts_with(|c: char| c.is_ascii_alphabetic()) {
        return None;
    }
    Some(ElementDoc {
        element,
        nickname: fields.get(1).cloned().unwrap_or_default(),
        description: fields.get(3).cloned().unwrap_or_default(),
    })
}

pub fn assemble(source: &str) -> Result<Program, Vec<Diagnostic>> {
    let text = crate::text::normalize(source);
    let mut program = Program::default();
    let mut errors = Vec::new();
    let suggester = Suggester::default();
    let mut block_start: Option<usize> = None;
    let mut in_element_doc = false;
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let trimmed = line.trim_start().to_ascii_uppercase();
        if block_start.is_some() {
            if trimmed.starts_with("#END") {
                block_start = None;
            } else if in_element_doc && let Some(doc) = element_doc(line) {
                program.docs.push(doc);
            }
            continue;
        }
        if trimmed.starts_with("#BEGIN") {
            block_start = Some(line_no);
            in_element_doc = trimmed.split_whitespace().nth(1) == Some("ELEMENT_DOC");
            continue;
        }
        let mut code = line.find("//").map_or(line, |k| &line[..k]);
        // The code before it is still read, so the rungs after it are checked as written.
        if let Some(k) = code.find(';') {
            let col = code[..k].chars().count() + 1;
            errors.push(Diagnostic::error(
                line_no,
                col,
                1,
                "DL205 comments start with // (';' starts a comment in OpenNet, not here)",
            ));
            code = &code[..k];
        }
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
        // `OR STR` for ORSTR: the second word would be read as a bit and refused.
        if let [first, second, ..] = ts.as_slice()
            && second.text.eq_ignore_ascii_case("STR")
            && ["AND", "OR"].contains(&first.text.to_ascii_uppercase().as_str())
        {
            let word = format!("{}STR", first.text.to_ascii_uppercase());
            errors.push(Diagnostic::error(
                line_no,
                first.col,
                first.text.len() + 4,
                format!("write {word} as one word: it joins the last two branches"),
            ));
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
