//! `#include` (spec §1.1): the directive on a line, and a project's files expanded into the
//! program's lines.

use crate::machine::Diagnostic;
use crate::machine::project::Project;

/// One line of the program in inclusion order: its program line (file and line, see
/// [`Project`]) and its characters.
pub(super) struct SourceLine {
    pub(super) line: usize,
    pub(super) chars: Vec<char>,
}

/// What a line starting with `#` holds (spec §1.1).
enum Directive {
    Include(String),
    /// A malformed or unsupported directive: column, length, message.
    Bad(usize, usize, String),
}

/// The directive on `chars`, if its first non-blank character is `#`.
fn directive(chars: &[char]) -> Option<Directive> {
    let hash = chars.iter().position(|c| !c.is_whitespace())?;
    if chars[hash] != '#' {
        return None;
    }
    // A trailing `//` comment is allowed, but not inside the quoted path.
    let mut end = chars.len();
    let mut quoted = false;
    for k in hash..chars.len() {
        match chars[k] {
            '"' => quoted = !quoted,
            '/' if !quoted && chars.get(k + 1) == Some(&'/') => {
                end = k;
                break;
            }
            _ => {}
        }
    }
    let after_hash: String = chars[hash + 1..end].iter().collect();
    let lead = after_hash.len() - after_hash.trim_start().len();
    let word: String = after_hash
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect();
    let word_col = hash + 2 + lead;
    if !word.eq_ignore_ascii_case("include") {
        let shown = if word.is_empty() {
            "#".to_string()
        } else {
            format!("#{word}")
        };
        return Some(Directive::Bad(
            hash + 1,
            1 + lead + word.len(),
            format!("{shown} is not supported by servoscope yet (only #include)"),
        ));
    }
    let malformed = || {
        Directive::Bad(
            hash + 1,
            end.saturating_sub(hash).max(1),
            "malformed #include: write #include \"path\"".into(),
        )
    };
    let rest = after_hash.trim_start()[word.len()..].trim();
    let Some(inner) = rest.strip_prefix('"').and_then(|r| r.strip_suffix('"')) else {
        return Some(malformed());
    };
    if inner.contains('"') {
        return Some(malformed());
    }
    if inner.trim().is_empty() {
        return Some(Directive::Bad(
            word_col,
            word.len(),
            "empty #include path".into(),
        ));
    }
    Some(Directive::Include(inner.to_string()))
}

/// The paths `text` includes with well-formed `#include` lines, in order: what a loader reads
/// from disk before assembling.
pub fn includes(text: &str) -> Vec<String> {
    crate::text::normalize(text)
        .lines()
        .filter_map(|l| match directive(&l.chars().collect::<Vec<_>>()) {
            Some(Directive::Include(path)) => Some(path),
            _ => None,
        })
        .collect()
}

/// The most characters a program may have with its includes expanded: as many as the largest
/// file servoscope opens, so a tree of small files that include each other many times (4
/// includes a level, 15 levels: 4^15 copies) stops with an error instead of filling memory.
pub const MAX_EXPANDED_CHARS: usize = crate::text::MAX_FILE_BYTES;
/// The most lines (and diagnostics, which a repeated file repeats too) of an expanded program.
pub const MAX_EXPANDED_LINES: usize = crate::machine::project::FILE_LINES - 1;

/// What is left of the expanded program's size, and whether it ran out.
pub(super) struct Budget {
    chars: usize,
    lines: usize,
    /// Ran out: nothing more is expanded; `reported` once the error is at its `#include`.
    exhausted: bool,
    reported: bool,
}

impl Default for Budget {
    fn default() -> Self {
        Budget {
            chars: MAX_EXPANDED_CHARS,
            lines: MAX_EXPANDED_LINES,
            exhausted: false,
            reported: false,
        }
    }
}

impl Budget {
    /// Whether the program grew past the bound: it is not assembled any further.
    pub(super) fn ran_out(&self) -> bool {
        self.exhausted
    }

    /// Take one line of `chars` characters; false (and exhausted) when it does not fit.
    fn take(&mut self, chars: usize) -> bool {
        if self.exhausted || self.lines == 0 || self.chars < chars {
            self.exhausted = true;
            return false;
        }
        self.lines -= 1;
        self.chars -= chars;
        true
    }

    fn too_large(line: usize, col: usize, len: usize) -> Diagnostic {
        Diagnostic::error(
            line,
            col,
            len,
            format!(
                "with its included files the program grows past {MAX_EXPANDED_LINES} lines or {MAX_EXPANDED_CHARS} characters here (do files include each other many times?); servoscope assembles at most that"
            ),
        )
    }
}

/// The lines of file `file` with its includes expanded in place (spec §1.1), appended to `out`,
/// within `budget`: the `#include` whose expansion crosses it gets the error and expansion stops.
pub(super) fn expand(
    project: &Project,
    file: usize,
    chain: &mut Vec<usize>,
    out: &mut Vec<SourceLine>,
    errors: &mut Vec<Diagnostic>,
    budget: &mut Budget,
) {
    let text = crate::text::normalize(&project.files[file].text);
    chain.push(file);
    for (i, l) in text.lines().enumerate() {
        let line = Project::line(file, i + 1);
        if budget.exhausted {
            break;
        }
        if i + 1 >= crate::machine::project::FILE_LINES {
            errors.push(Diagnostic::error(
                line,
                1,
                1,
                "file too long: servoscope reads at most 1048575 lines of a file",
            ));
            break;
        }
        // A line, and a diagnostic too (a file included many times repeats its errors), takes
        // from the budget; the `#include` being expanded reports running out, or else the top
        // file's own line does.
        if !budget.take(l.len()) {
            if chain.len() == 1 && !budget.reported {
                budget.reported = true;
                errors.push(Budget::too_large(line, 1, l.chars().count().max(1)));
            }
            break;
        }
        let chars: Vec<char> = l.chars().collect();
        match directive(&chars) {
            None => out.push(SourceLine { line, chars }),
            Some(Directive::Bad(col, len, message)) => {
                errors.push(Diagnostic::error(line, col, len, message))
            }
            Some(Directive::Include(path)) => {
                let col = chars.iter().position(|&c| c == '"').map_or(1, |k| k + 1);
                let len = path.chars().count() + 2;
                let name =
                    crate::machine::project::resolve_include(&project.files[file].name, &path);
                let Some(target) = project.index_of(&name) else {
                    errors.push(Diagnostic::error(
                        line,
                        col,
                        len,
                        if crate::machine::project::outside_top_folder(&name) {
                            format!(
                                "cannot open included file '{path}': it is outside the program's folder, and servoscope reads included files only from the top file's folder and its subfolders unless you allow another folder (--include-dir DIR, or View → Include folders… in the window)"
                            )
                        } else {
                            format!("cannot open included file '{path}'")
                        },
                    ));
                    continue;
                };
                if chain.contains(&target) {
                    let names: Vec<&str> = chain
                        .iter()
                        .skip_while(|&&f| f != target)
                        .map(|&f| project.files[f].name.as_str())
                        .chain([project.files[target].name.as_str()])
                        .collect();
                    errors.push(Diagnostic::error(
                        line,
                        col,
                        len,
                        format!("'{path}' includes itself ({})", names.join(" -> ")),
                    ));
                    continue;
                }
                if chain.len() > crate::machine::project::MAX_INCLUDE_DEPTH {
                    errors.push(Diagnostic::error(
                        line,
                        col,
                        len,
                        format!(
                            "more than {} nested #include levels below the top file",
                            crate::machine::project::MAX_INCLUDE_DEPTH
                        ),
                    ));
                    continue;
                }
                expand(project, target, chain, out, errors, budget);
                if budget.exhausted && !budget.reported {
                    budget.reported = true;
                    errors.push(Budget::too_large(line, col, len));
                }
            }
        }
    }
    chain.pop();
}
