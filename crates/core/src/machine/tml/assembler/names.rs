//! The names a program reads: declared variables, labels and the drive's predefined data, and
//! the operand a name stands for.

use std::collections::HashMap;

use super::lex::{Error, Tok, Token, err};
use super::operands::punct;
use super::{MNEMONICS, TYPES, UNSUPPORTED, unmodelled};
use crate::machine::diagnostics::Suggester;
use crate::machine::tml::program::{Data, Operand, Ty, Var};
use crate::machine::tml::{PREDEFINED, d};

/// A value only program memory can give: the address of a label's statement, or the statement
/// at a numeric jump address.
#[derive(Clone, Copy, Debug)]
pub(super) enum Fixup {
    LabelAddress(u32),
    JumpAddress {
        address: u32,
        col: usize,
        len: usize,
    },
}

/// Where a GOTO or CALL goes.
pub(super) enum Target {
    Statement(u32),
    Via(Operand),
}

/// Names the program and the drive define, while the program is read.
pub(super) struct Names<'a> {
    pub(super) vars: Vec<Var>,
    pub(super) var_index: HashMap<String, u16>,
    pub(super) labels: &'a HashMap<String, (u32, usize)>,
    /// What the statement being read leaves to be filled in once every statement's address is
    /// known (spec §5.11).
    pub(super) pending: Option<Fixup>,
    pub(super) used: Vec<u8>,
    pub(super) used_inputs: Vec<u8>,
    pub(super) uses_preg: bool,
    pub(super) suggester: Suggester,
}

pub(super) fn predefined(name: &str) -> Option<u8> {
    let name = crate::machine::tml::canonical_name(name);
    PREDEFINED
        .iter()
        .position(|p| {
            p.name.eq_ignore_ascii_case(name)
                || p.alias.is_some_and(|a| a.eq_ignore_ascii_case(name))
        })
        .map(|i| i as u8)
}

pub(super) fn reserved(upper: &str) -> bool {
    predefined(upper).is_some()
        || upper == "PREG"
        || TYPES.contains(&upper)
        || MNEMONICS.contains(&upper)
        || UNSUPPORTED.contains(&upper)
        || unmodelled(upper).is_some()
}

impl Names<'_> {
    pub(super) fn suggestion(&self, word: &str) -> String {
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
    pub(super) fn operand(&mut self, ts: &[Token], at: &mut usize) -> Result<Operand, Error> {
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
