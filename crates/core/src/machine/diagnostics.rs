//! Assembler diagnostics, shared by every dialect.

use std::cell::Cell;
use std::fmt;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Severity {
    Error,
    Warning,
}

/// One problem in a program's text, located at the exact token that is wrong.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    pub severity: Severity,
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub col: usize,
    /// Length of the offending token in characters (at least 1), for underlining.
    pub len: usize,
    pub message: String,
}

impl Diagnostic {
    pub fn error(line: usize, col: usize, len: usize, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Error,
            line,
            col,
            len: len.max(1),
            message: message.into(),
        }
    }

    /// `file:line:col: error: message`, the form compilers use and editors can jump to.
    pub fn with_file<'a>(&'a self, file: &'a str) -> impl fmt::Display + 'a {
        WithFile { file, diag: self }
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let level = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        write!(
            f,
            "{}:{}: {}: {}",
            self.line,
            self.col,
            level,
            printable(&self.message)
        )
    }
}

/// `text` with control characters escaped (`\u{1b}`), so a crafted file cannot send
/// terminal escape sequences through a message that quotes it.
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    if text.chars().any(char::is_control) {
        text.chars()
            .map(|c| {
                if c.is_control() {
                    c.escape_default().to_string()
                } else {
                    c.to_string()
                }
            })
            .collect::<String>()
            .into()
    } else {
        text.into()
    }
}

struct WithFile<'a> {
    file: &'a str,
    diag: &'a Diagnostic,
}

impl fmt::Display for WithFile<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file, self.diag)
    }
}

/// The closest candidate to `word` (case-insensitive), if it is close enough to be a likely typo.
/// "Did you mean" over names a program defines (labels, DEFs), with a bounded amount of work
/// per file: every candidate compared spends one unit of the budget, and once it is spent
/// suggestions stop. A file of 100,000 undefined names then fails in time linear in its size.
pub struct Suggester {
    budget: Cell<usize>,
}

/// Candidates compared per file at most (a few tens of milliseconds).
pub const SUGGESTION_BUDGET: usize = 200_000;

impl Default for Suggester {
    fn default() -> Self {
        Suggester {
            budget: Cell::new(SUGGESTION_BUDGET),
        }
    }
}

impl Suggester {
    pub fn suggest<'a>(
        &self,
        word: &str,
        candidates: impl IntoIterator<Item = &'a str>,
    ) -> Option<&'a str> {
        let left = self.budget.get();
        if left == 0 {
            return None;
        }
        let mut spent = 0;
        let counted = candidates.into_iter().take(left).inspect(|_| spent += 1);
        let found = suggest(word, counted);
        self.budget.set(left - spent);
        found
    }
}

/// Words longer than this get no suggestion: nobody mistypes a 65-character name by one
/// letter, and the distance would cost time proportional to both lengths.
const MAX_SUGGESTED_LEN: usize = 64;

pub fn suggest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let len = word.chars().count();
    if len > MAX_SUGGESTED_LEN {
        return None;
    }
    let word = word.to_ascii_uppercase();
    let limit = (len / 3).clamp(1, 3);
    candidates
        .into_iter()
        // Lengths further apart than the limit cannot be within it: skip the distance.
        .filter(|c| c.len().abs_diff(word.len()) <= limit)
        .map(|c| (strsim::levenshtein(&word, &c.to_ascii_uppercase()), c))
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_only_close_words() {
        let ops = ["MULT_S", "MULT_U", "MULT_S64_SHR16", "ADD"];
        assert_eq!(suggest("mult_s64_shr61", ops), Some("MULT_S64_SHR16"));
        assert_eq!(suggest("ADDD", ops), Some("ADD"));
        assert_eq!(suggest("XYZZY", ops), None);
        assert_eq!(suggest("clk", ["CLC"]), Some("CLC"), "case-insensitive");
        assert_eq!(
            suggest(&"A".repeat(100_000), ops),
            None,
            "very long words get none"
        );
    }
}
