//! The expression language of conditions, watches, log points and the runner's `--break`:
//! integer arithmetic over a machine's locations.
//!
//! ```text
//! R4 > 1000 && IO3        ACC == 0x00222970        M8004        TPOS - APOS > 50
//! PSW.12                  (V1400 & 0xFF) != 0      !X0 || -R5 >= 2
//! ```
//!
//! - Names are the dialect's location names and aliases (case-insensitive) and the program's
//!   own names (DEF names, TML variables), resolved once when the expression is compiled, so
//!   evaluation is a few array reads. `NAME.N` reads bit N of a word.
//! - Values are 64-bit signed integers: a location reads as its number (signed locations
//!   sign-extended, a TML `fixed` as its raw Q16.16 bits), a relay or input as 0 or 1.
//!   Literals are decimal, `0x` hex or `0b` binary. `bcd(x)` is x's decimal digits as BCD
//!   (`V2000 == bcd(1250)` holds when V2000 holds 0x1250); `q16(1.5)` is a decimal number's
//!   Q16.16 pattern (98304).
//! - Operators, loosest first: `||`, `&&`, comparisons `== != < <= > >=`, `|`, `^`, `&`,
//!   shifts `<< >>`, `+ -`, `* / %`, unary `! - ~`. Comparisons and logic give 0 or 1; a
//!   value is true when it is not 0. Arithmetic wraps; a division or remainder by 0 gives 0
//!   (a condition must never stop the debugger with an error of its own).
//! - A malformed expression is an [`ExprError`] with the 1-based column, never a panic.

use std::fmt::Write as _;

use crate::machine::{Loc, MachineView, value};

/// Why text is not an expression, with the 1-based column (in characters) of the problem.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("column {col}: {message}")]
pub struct ExprError {
    pub col: usize,
    pub message: String,
}

/// Nesting deeper than this is refused (it keeps parsing and evaluation off the call stack).
const MAX_DEPTH: usize = 48;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    Or,
    And,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    BitOr,
    BitXor,
    BitAnd,
    Shl,
    Shr,
    Add,
    Sub,
    Mul,
    Div,
    Rem,
}

impl Op {
    fn apply(self, a: i64, b: i64) -> i64 {
        match self {
            Op::Or => i64::from(a != 0 || b != 0),
            Op::And => i64::from(a != 0 && b != 0),
            Op::Eq => i64::from(a == b),
            Op::Ne => i64::from(a != b),
            Op::Lt => i64::from(a < b),
            Op::Le => i64::from(a <= b),
            Op::Gt => i64::from(a > b),
            Op::Ge => i64::from(a >= b),
            Op::BitOr => a | b,
            Op::BitXor => a ^ b,
            Op::BitAnd => a & b,
            Op::Shl => a.wrapping_shl((b & 63) as u32),
            Op::Shr => a.wrapping_shr((b & 63) as u32),
            Op::Add => a.wrapping_add(b),
            Op::Sub => a.wrapping_sub(b),
            Op::Mul => a.wrapping_mul(b),
            Op::Div => a.checked_div(b).unwrap_or(0),
            Op::Rem => a.checked_rem(b).unwrap_or(0),
        }
    }
}

/// One step of the compiled expression, evaluated on a small stack (postfix order).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Node {
    Const(i64),
    Read {
        loc: Loc,
        width: u8,
        signed: bool,
    },
    Bit {
        loc: Loc,
        bit: u8,
    },
    Not,
    Neg,
    Invert,
    /// `bcd(x)`: x's decimal digits as BCD nibbles (1250 → 0x1250).
    Bcd,
    Binary(Op),
}

/// A compiled expression.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Expr {
    text: String,
    nodes: Vec<Node>,
}

impl Expr {
    /// Compile `text` against the locations of `m`.
    pub fn compile(text: &str, m: &(impl MachineView + ?Sized)) -> Result<Expr, ExprError> {
        let tokens = lex(text)?;
        let mut p = Parser {
            tokens: &tokens,
            at: 0,
            end_col: text.chars().count() + 1,
            nodes: Vec::new(),
            depth: 0,
            m: &resolve_in(m),
            constants: m.program_constants(),
        };
        if tokens.is_empty() {
            return Err(ExprError {
                col: 1,
                message: "type an expression, like R4 > 1000".to_string(),
            });
        }
        p.expr(0)?;
        if let Some(t) = tokens.get(p.at) {
            return Err(ExprError {
                col: t.col,
                message: format!("unexpected '{}'", t.text),
            });
        }
        Ok(Expr {
            text: text.trim().to_string(),
            nodes: p.nodes,
        })
    }

    /// The text it was compiled from.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The locations it reads.
    pub fn locations(&self) -> impl Iterator<Item = Loc> + '_ {
        self.nodes.iter().filter_map(|n| match *n {
            Node::Read { loc, .. } | Node::Bit { loc, .. } => Some(loc),
            _ => None,
        })
    }

    /// Its value in `m`'s present state.
    #[inline]
    pub fn eval<M: MachineView + ?Sized>(&self, m: &M) -> i64 {
        // The parser bounds the depth, so the stack never needs more than MAX_DEPTH + 2 slots.
        let mut stack = [0i64; MAX_DEPTH * 2 + 4];
        let mut top = 0usize;
        for node in &self.nodes {
            match *node {
                Node::Const(v) => {
                    stack[top] = v;
                    top += 1;
                }
                Node::Read { loc, width, signed } => {
                    let raw = m.read(loc);
                    stack[top] = if signed {
                        value::sign_extend(raw, width)
                    } else {
                        raw as i64
                    };
                    top += 1;
                }
                Node::Bit { loc, bit } => {
                    stack[top] = (m.read(loc) >> bit & 1) as i64;
                    top += 1;
                }
                Node::Not => stack[top - 1] = i64::from(stack[top - 1] == 0),
                Node::Neg => stack[top - 1] = stack[top - 1].wrapping_neg(),
                Node::Invert => stack[top - 1] = !stack[top - 1],
                Node::Bcd => stack[top - 1] = to_bcd(stack[top - 1]),
                Node::Binary(op) => {
                    top -= 1;
                    stack[top - 1] = op.apply(stack[top - 1], stack[top]);
                }
            }
        }
        stack[0]
    }

    /// Whether it holds (is not 0) in `m`'s present state.
    #[inline]
    pub fn holds<M: MachineView + ?Sized>(&self, m: &M) -> bool {
        self.eval(m) != 0
    }
}

/// `value`'s decimal digits as BCD nibbles: 1250 → 0x1250. A negative value gives the negated
/// pattern of its magnitude, so `bcd(-5) == -bcd(5)`; digits past the sixteenth are dropped.
fn to_bcd(value: i64) -> i64 {
    let mut magnitude = value.unsigned_abs();
    let mut pattern = 0u64;
    for nibble in 0..16 {
        pattern |= (magnitude % 10) << (4 * nibble);
        magnitude /= 10;
        if magnitude == 0 {
            break;
        }
    }
    let pattern = pattern as i64;
    if value < 0 {
        pattern.wrapping_neg()
    } else {
        pattern
    }
}

/// A name resolver over a machine: location names, aliases and the program's own names.
fn resolve_in<M: MachineView + ?Sized>(m: &M) -> impl Fn(&str) -> Option<(Loc, u8, bool)> + '_ {
    move |name: &str| {
        let loc = m.find(name)?;
        let info = m.info(loc)?;
        Some((loc, info.width, info.signed))
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(i64),
    /// A number with a decimal point, for `q16(…)` alone.
    Decimal(String),
    Name(String),
    /// `.N` after a name: a bit of the word.
    Bit(u8),
    Sym(&'static str),
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    col: usize,
    text: String,
}

const SYMBOLS: [&str; 24] = [
    "||", "&&", "==", "!=", "<=", ">=", "<<", ">>", "<", ">", "|", "^", "&", "+", "-", "*", "/",
    "%", "!", "~", "(", ")", "=", ",",
];

fn lex(text: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let col = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let word_end = |mut j: usize| {
            while j < chars.len() && (chars[j].is_ascii_alphanumeric() || chars[j] == '_') {
                j += 1;
            }
            j
        };
        if c.is_ascii_digit() && {
            let j = word_end(i);
            chars.get(j) == Some(&'.') && chars[i..j].iter().all(char::is_ascii_digit)
        } {
            // `1.5`, `10.`: a decimal number, read only inside q16(…).
            let point = word_end(i);
            let j = (point + 1..=chars.len())
                .find(|&j| chars.get(j).is_none_or(|c| !c.is_ascii_digit()))
                .unwrap_or(chars.len());
            let word: String = chars[i..j].iter().collect();
            out.push(Token {
                tok: Tok::Decimal(word.clone()),
                col,
                text: word,
            });
            i = j;
        } else if c.is_ascii_digit() {
            let j = word_end(i);
            let word: String = chars[i..j].iter().collect();
            let value = value::parse_integer(&word)
                .ok()
                .and_then(|v| {
                    i64::try_from(v)
                        .ok()
                        .or_else(|| u64::try_from(v).ok().map(|u| u as i64))
                })
                .ok_or_else(|| ExprError {
                    col,
                    message: format!("'{word}' is not a number (write 42, 0x2A or 0b101010)"),
                })?;
            out.push(Token {
                tok: Tok::Num(value),
                col,
                text: word,
            });
            i = j;
        } else if c.is_ascii_alphabetic() || c == '_' {
            // Names are ASCII, like every dialect's; any other letter is refused below, so
            // the lexer always moves past what it looked at.
            let j = word_end(i);
            let word: String = chars[i..j].iter().collect();
            out.push(Token {
                tok: Tok::Name(word.clone()),
                col,
                text: word,
            });
            i = j;
        } else if c == '.'
            && chars.get(i + 1).is_some_and(|n| n.is_ascii_alphabetic())
            && let Some(Token {
                tok: Tok::Name(name),
                text,
                ..
            }) = out.last_mut()
        {
            // A field of a named thing: OpenNet's `T3.current`, `C0.preset`.
            let j = word_end(i + 1);
            let field: String = chars[i + 1..j].iter().collect();
            name.push('.');
            name.push_str(&field);
            *text = name.clone();
            i = j;
        } else if c == '.'
            && matches!(
                out.last(),
                Some(Token {
                    tok: Tok::Name(_),
                    ..
                })
            )
        {
            let j = word_end(i + 1);
            let digits: String = chars[i + 1..j].iter().collect();
            let bit = digits
                .parse::<u8>()
                .ok()
                .filter(|&b| b < 64)
                .ok_or_else(|| ExprError {
                    col,
                    message: "after '.', a bit number 0 to 63 (PSW.12)".to_string(),
                })?;
            out.push(Token {
                tok: Tok::Bit(bit),
                col,
                text: format!(".{digits}"),
            });
            i = j;
        } else {
            let rest: String = chars[i..chars.len().min(i + 2)].iter().collect();
            let Some(sym) = SYMBOLS.iter().find(|s| rest.starts_with(**s)) else {
                let message = if c.is_alphanumeric() {
                    format!("'{c}': names use the letters A to Z, digits and _")
                } else {
                    format!("'{c}' is not part of an expression")
                };
                return Err(ExprError { col, message });
            };
            i += sym.chars().count();
            out.push(Token {
                tok: Tok::Sym(sym),
                col,
                text: sym.to_string(),
            });
        }
    }
    Ok(out)
}

type Resolve<'a> = dyn Fn(&str) -> Option<(Loc, u8, bool)> + 'a;

struct Parser<'a> {
    tokens: &'a [Token],
    at: usize,
    end_col: usize,
    nodes: Vec<Node>,
    depth: usize,
    m: &'a Resolve<'a>,
    /// The program's named constants (they are values, not locations).
    constants: Vec<(String, i64)>,
}

/// Binary operators by binding power (higher binds tighter).
fn binary(sym: &str) -> Option<(Op, u8)> {
    Some(match sym {
        "||" => (Op::Or, 1),
        "&&" => (Op::And, 2),
        "==" => (Op::Eq, 3),
        "!=" => (Op::Ne, 3),
        "<" => (Op::Lt, 3),
        "<=" => (Op::Le, 3),
        ">" => (Op::Gt, 3),
        ">=" => (Op::Ge, 3),
        "|" => (Op::BitOr, 4),
        "^" => (Op::BitXor, 5),
        "&" => (Op::BitAnd, 6),
        "<<" => (Op::Shl, 7),
        ">>" => (Op::Shr, 7),
        "+" => (Op::Add, 8),
        "-" => (Op::Sub, 8),
        "*" => (Op::Mul, 9),
        "/" => (Op::Div, 9),
        "%" => (Op::Rem, 9),
        _ => return None,
    })
}

impl Parser<'_> {
    /// Whether the next token is `(`: a name before it is a function (`bcd(…)`, `q16(…)`).
    fn opens_call(&self) -> bool {
        matches!(
            self.tokens.get(self.at),
            Some(Token {
                tok: Tok::Sym("("),
                ..
            })
        )
    }

    fn error<T>(&self, message: impl Into<String>) -> Result<T, ExprError> {
        let col = self.tokens.get(self.at).map_or(self.end_col, |t| t.col);
        Err(ExprError {
            col,
            message: message.into(),
        })
    }

    /// Operators binding tighter than `min` (precedence climbing).
    fn expr(&mut self, min: u8) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return self.error("nested too deeply");
        }
        self.unary()?;
        while let Some(Token {
            tok: Tok::Sym(sym), ..
        }) = self.tokens.get(self.at)
        {
            if *sym == "=" {
                return self.error("'=' stores a value; compare with '=='");
            }
            let Some((op, power)) = binary(sym) else {
                break;
            };
            if power <= min {
                break;
            }
            self.at += 1;
            self.expr(power)?;
            self.nodes.push(Node::Binary(op));
        }
        self.depth -= 1;
        Ok(())
    }

    fn unary(&mut self) -> Result<(), ExprError> {
        let Some(token) = self.tokens.get(self.at) else {
            return self.error("the expression ends too soon: a value or name is missing");
        };
        self.at += 1;
        match &token.tok {
            Tok::Sym(s @ ("!" | "-" | "~")) => {
                self.depth += 1;
                if self.depth > MAX_DEPTH {
                    return self.error("nested too deeply");
                }
                self.unary()?;
                self.depth -= 1;
                self.nodes.push(match *s {
                    "!" => Node::Not,
                    "-" => Node::Neg,
                    _ => Node::Invert,
                });
            }
            Tok::Sym("(") => {
                self.expr(0)?;
                match self.tokens.get(self.at) {
                    Some(Token {
                        tok: Tok::Sym(")"), ..
                    }) => self.at += 1,
                    _ => return self.error("')' is missing"),
                }
            }
            Tok::Num(v) => self.nodes.push(Node::Const(*v)),
            Tok::Name(name) if name.eq_ignore_ascii_case("bcd") && self.opens_call() => {
                self.at += 1;
                self.expr(0)?;
                match self.tokens.get(self.at) {
                    Some(Token {
                        tok: Tok::Sym(")"), ..
                    }) => self.at += 1,
                    _ => return self.error("')' is missing after bcd(…"),
                }
                self.nodes.push(Node::Bcd);
            }
            Tok::Name(name) if name.eq_ignore_ascii_case("q16") && self.opens_call() => {
                // A number as Q16.16, rounded as the assemblers round it: `q16(1.5)` is 98304.
                self.at += 1;
                let mut text = String::new();
                while let Some(t) = self.tokens.get(self.at) {
                    match &t.tok {
                        Tok::Sym(")") => break,
                        Tok::Sym("-") | Tok::Num(_) | Tok::Decimal(_) => text.push_str(&t.text),
                        _ => return self.error("q16(…) takes a number, like q16(1.5)"),
                    }
                    self.at += 1;
                }
                if self.tokens.get(self.at).is_none() {
                    return self.error("')' is missing after q16(…");
                }
                let value = match value::parse_q16(&text) {
                    Ok(v) => v,
                    Err(e) => return self.error(e.to_string()),
                };
                self.at += 1;
                self.nodes.push(Node::Const(value));
            }
            Tok::Name(name) => {
                let Some((loc, width, signed)) = (self.m)(name) else {
                    // A constant the program names (DEF names are case-sensitive).
                    if let Some(&(_, value)) = self.constants.iter().find(|(n, _)| n == name) {
                        if let Some(Token {
                            tok: Tok::Bit(bit), ..
                        }) = self.tokens.get(self.at)
                        {
                            self.at += 1;
                            self.nodes.push(Node::Const(value >> (*bit).min(63) & 1));
                        } else {
                            self.nodes.push(Node::Const(value));
                        }
                        return Ok(());
                    }
                    self.at -= 1;
                    // A DL205 K constant (`K50`) is a number in a program's text, not a
                    // location: say what to write in an expression.
                    if let Some(digits) = name.strip_prefix(['K', 'k'])
                        && !digits.is_empty()
                        && digits.chars().all(|c| c.is_ascii_hexdigit())
                    {
                        return self.error(format!(
                            "'{name}' is a K constant of a program's text; here write {digits}, \
                             or bcd({digits}) to compare with a BCD word"
                        ));
                    }
                    return self.error(format!("there is no location named '{name}'"));
                };
                if let Some(Token {
                    tok: Tok::Bit(bit), ..
                }) = self.tokens.get(self.at)
                {
                    self.at += 1;
                    if *bit >= width {
                        self.at -= 1;
                        return self.error(format!("{name} has {width} bit(s)"));
                    }
                    self.nodes.push(Node::Bit { loc, bit: *bit });
                } else {
                    self.nodes.push(Node::Read { loc, width, signed });
                }
            }
            Tok::Decimal(text) => {
                self.at -= 1;
                return self.error(format!(
                    "{text} is not a whole number: write q16({text}) for its Q16.16 pattern"
                ));
            }
            _ => {
                self.at -= 1;
                return self.error(format!("'{}' cannot start a value", token.text));
            }
        }
        Ok(())
    }
}

/// A message with `{EXPR}` holes, for log points: "R4 = {R4}, sum {R4 + R5}".
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Message {
    parts: Vec<Part>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Part {
    Text(String),
    Value(Expr),
}

impl Message {
    /// Compile the holes of `text`; `{{` and `}}` are literal braces. An error's column counts
    /// from the start of the whole message.
    pub fn compile(text: &str, m: &(impl MachineView + ?Sized)) -> Result<Message, ExprError> {
        let mut parts = Vec::new();
        let mut literal = String::new();
        let chars: Vec<char> = text.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            match chars[i] {
                '{' if chars.get(i + 1) == Some(&'{') => {
                    literal.push('{');
                    i += 2;
                }
                '}' if chars.get(i + 1) == Some(&'}') => {
                    literal.push('}');
                    i += 2;
                }
                '{' => {
                    let close = chars[i..].iter().position(|&c| c == '}').ok_or(ExprError {
                        col: i + 1,
                        message: "'{' has no closing '}'".to_string(),
                    })?;
                    let inner: String = chars[i + 1..i + close].iter().collect();
                    let expr = Expr::compile(&inner, m).map_err(|e| ExprError {
                        col: e.col + i + 1,
                        message: e.message,
                    })?;
                    if !literal.is_empty() {
                        parts.push(Part::Text(std::mem::take(&mut literal)));
                    }
                    parts.push(Part::Value(expr));
                    i += close + 1;
                }
                c => {
                    literal.push(c);
                    i += 1;
                }
            }
        }
        if !literal.is_empty() {
            parts.push(Part::Text(literal));
        }
        Ok(Message { parts })
    }

    /// The message with each hole's value in `m`'s present state.
    pub fn render<M: MachineView + ?Sized>(&self, m: &M) -> String {
        let mut out = String::new();
        for part in &self.parts {
            match part {
                Part::Text(t) => out.push_str(t),
                Part::Value(e) => {
                    let _ = write!(out, "{}", e.eval(m));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::debugger::Debugger;

    fn machine(source: &str) -> Debugger {
        Debugger::new("t", source)
    }

    fn eval(d: &Debugger, text: &str) -> i64 {
        Expr::compile(text, d.machine())
            .unwrap_or_else(|e| panic!("{text}: {e}"))
            .eval(d.machine())
    }

    #[test]
    fn arithmetic_follows_the_usual_precedence() {
        let d = machine("END");
        assert_eq!(eval(&d, "1 + 2 * 3"), 7);
        assert_eq!(eval(&d, "(1 + 2) * 3"), 9);
        assert_eq!(eval(&d, "10 - 4 - 3"), 3, "left to right");
        assert_eq!(eval(&d, "-7 / 2"), -3);
        assert_eq!(eval(&d, "7 % 0"), 0, "no error from a condition");
        assert_eq!(eval(&d, "1 << 4 | 1"), 17);
        assert_eq!(eval(&d, "0x10 & 0b11000"), 16);
        assert_eq!(eval(&d, "1 < 2 && 3 >= 3 || 0"), 1);
        assert_eq!(eval(&d, "!0 + ~0"), 0);
        assert_eq!(eval(&d, "2 == 2 == 1"), 1);
        assert_eq!(
            eval(&d, "0xFFFFFFFFFFFFFFFF"),
            -1,
            "64-bit patterns read as signed"
        );
    }

    #[test]
    fn names_read_the_machine() {
        let mut d = machine("END");
        d.set_text("R4", "-1500").expect("a register");
        d.set_text("R5", "20").expect("a register");
        let io3 = d.find("IO3").expect("an input");
        d.set_input(io3, true).expect("switched");
        assert_eq!(eval(&d, "R4"), -1500, "registers are signed");
        assert_eq!(eval(&d, "r4 < -1000 && IO3"), 1, "names ignore case");
        assert_eq!(eval(&d, "R5 - R4 > 50"), 1);
        assert_eq!(eval(&d, "R5.2"), 1, "bit 2 of 20");
        assert_eq!(eval(&d, "R5.0"), 0);
    }

    #[test]
    fn errors_say_where() {
        let d = machine("END");
        let err = |text: &str| Expr::compile(text, d.machine()).expect_err(text);
        assert_eq!(err("R4 >").col, 5, "missing operand at the end");
        assert_eq!(err("R4 > BANANA").col, 6);
        assert!(err("R4 > BANANA").message.contains("BANANA"));
        assert_eq!(err("(R4 + 1").col, 8);
        assert_eq!(err("R4 = 3").col, 4);
        assert!(err("R4 = 3").message.contains("=="));
        assert_eq!(err("R4 $ 3").col, 4);
        assert_eq!(err("").col, 1);
        assert_eq!(err("R4 R5").col, 4);
        assert_eq!(err("R4.40").col, 3, "R4 has 32 bits");
        assert_eq!(err("99999999999999999999").col, 1);
        let deep = "(".repeat(10_000) + "1" + &")".repeat(10_000);
        assert!(err(&deep).message.contains("deeply"));
        let deep_unary = "-".repeat(10_000) + "1";
        assert!(err(&deep_unary).message.contains("deeply"));
    }

    #[test]
    fn messages_fill_their_holes() {
        let mut d = machine("END");
        d.set_text("R4", "12").expect("a register");
        let m = Message::compile("R4 is {R4}, twice {R4 * 2} {{literal}}", d.machine())
            .expect("compiles");
        assert_eq!(m.render(d.machine()), "R4 is 12, twice 24 {literal}");
        let e = Message::compile("x {R4 +} y", d.machine()).expect_err("bad hole");
        assert_eq!(e.col, 8, "the closing brace, counted in the whole message");
        assert!(Message::compile("x {R4", d.machine()).is_err());
    }

    #[test]
    fn letters_outside_ascii_are_an_error_at_their_column() {
        let d = machine("END");
        for (text, col) in [
            ("é", 1),
            ("R4 > é", 6),
            ("Ré4", 2),
            ("R4 == ٣", 7),
            ("ÉTAT", 1),
        ] {
            let e = Expr::compile(text, d.machine()).expect_err(text);
            assert_eq!(e.col, col, "{text}: {e}");
            assert!(e.message.contains("A to Z"), "{text}: {e}");
        }
        let e = Message::compile("pos {é}", d.machine()).expect_err("a hole with é");
        assert_eq!(e.col, 6);
    }

    proptest::proptest! {
        /// Any text at all compiles or is refused with a column inside it (or just past its
        /// end), in bounded time: conditions, watches, channels and `--break` all come here.
        #[test]
        fn any_text_is_an_expression_or_an_error_with_its_column(text in "\\PC{0,40}") {
            let d = machine("END");
            let chars = text.chars().count();
            match Expr::compile(&text, d.machine()) {
                Ok(e) => { e.eval(d.machine()); }
                Err(e) => proptest::prop_assert!((1..=chars + 1).contains(&e.col), "{e}"),
            }
            match Message::compile(&text, d.machine()) {
                Ok(m) => { m.render(d.machine()); }
                Err(e) => proptest::prop_assert!((1..=chars + 1).contains(&e.col), "{e}"),
            }
        }
    }
}
