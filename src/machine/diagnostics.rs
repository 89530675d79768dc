//! Assembler diagnostics, shared by every dialect.

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
        write!(f, "{}:{}: {}: {}", self.line, self.col, level, self.message)
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

/// Levenshtein distance, for "did you mean" suggestions. Inputs are short identifiers.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cost = usize::from(ca != cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// The closest candidate to `word` (case-insensitive), if it is close enough to be a likely typo.
pub fn suggest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let word = word.to_ascii_uppercase();
    let limit = (word.chars().count() / 3).clamp(1, 3);
    candidates
        .into_iter()
        .map(|c| (edit_distance(&word, &c.to_ascii_uppercase()), c))
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_counts_edits() {
        assert_eq!(edit_distance("CLC", "CLC"), 0);
        assert_eq!(edit_distance("CLK", "CLC"), 1);
        assert_eq!(edit_distance("ADDD", "ADD"), 1);
        assert_eq!(edit_distance("", "ABC"), 3);
    }

    #[test]
    fn suggests_only_close_words() {
        let ops = ["MULT_S", "MULT_U", "MULT_S64_SHR16", "ADD"];
        assert_eq!(suggest("mult_s64_shr61", ops), Some("MULT_S64_SHR16"));
        assert_eq!(suggest("ADDD", ops), Some("ADD"));
        assert_eq!(suggest("XYZZY", ops), None);
    }
}
