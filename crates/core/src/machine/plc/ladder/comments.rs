//! The source's comments on the diagram: each element's trailing comment and the comment
//! lines above each rung.

use super::Ladder;

impl Ladder {
    /// Attach each element's trailing comment and each rung's comment lines from the source;
    /// `comment_of(line)` is the comment part of one line ("" when none).
    pub fn attach_comments(&mut self, source: &str, comment_of: impl Fn(&str) -> String) {
        let lines: Vec<&str> = source.lines().collect();
        let comment = |line: usize| -> String {
            lines
                .get(line.wrapping_sub(1))
                .map(|l| comment_of(l))
                .unwrap_or_default()
        };
        let mut taken = 0usize;
        for rung in &mut self.rungs {
            for e in &mut rung.elements {
                e.comment = comment(e.line);
            }
            // Comment-only lines right above the rung, after the previous rung's last line.
            let first = rung.first_line();
            let mut above = Vec::new();
            let mut l = first.saturating_sub(1);
            while l > taken {
                let text = lines.get(l - 1).map_or("", |s| s.trim());
                let c = comment(l);
                // A comment-only line: before its comment there is only the marker.
                let only = text
                    .strip_suffix(c.as_str())
                    .is_some_and(|code| !code.chars().any(char::is_alphanumeric));
                if c.is_empty() || !only {
                    break;
                }
                above.push(c);
                l -= 1;
            }
            above.reverse();
            rung.comment = above.join("\n");
            taken = rung
                .elements
                .iter()
                .map(|e| e.line)
                .max()
                .unwrap_or(taken)
                .max(taken);
        }
    }
}

/// The comment part of one source line as the dialect's highlighter classes it, without its
/// marker (`//`, `;`): what the diagram writes under an element or above a rung.
pub fn comment_of(
    classify: fn(&str) -> Vec<crate::machine::dialect::TokenClass>,
    line: &str,
) -> String {
    let classes = classify(line);
    let text: String = line
        .chars()
        .zip(classes.iter().chain(std::iter::repeat(
            &crate::machine::dialect::TokenClass::Plain,
        )))
        .filter(|(_, c)| **c == crate::machine::dialect::TokenClass::Comment)
        .map(|(ch, _)| ch)
        .collect();
    text.trim()
        .trim_start_matches("//")
        .trim_start_matches(';')
        .trim()
        .to_string()
}

/// The machine's diagram with the comments of `source` attached (None: not a ladder dialect).
pub fn with_comments(
    m: &dyn crate::machine::MachineView,
    source: &str,
    classify: fn(&str) -> Vec<crate::machine::dialect::TokenClass>,
) -> Option<Ladder> {
    commented((*m.as_plc()?.ladder()).clone(), m, source, classify)
}

/// The machine's rungs, not laid out, with the comments of `source` attached: for what reads
/// comments without drawing.
pub fn wiring_with_comments(
    m: &dyn crate::machine::MachineView,
    source: &str,
    classify: fn(&str) -> Vec<crate::machine::dialect::TokenClass>,
) -> Option<Ladder> {
    commented((*m.as_plc()?.wiring()).clone(), m, source, classify)
}

fn commented(
    mut ladder: Ladder,
    m: &dyn crate::machine::MachineView,
    source: &str,
    classify: fn(&str) -> Vec<crate::machine::dialect::TokenClass>,
) -> Option<Ladder> {
    ladder.attach_comments(source, |line| comment_of(classify, line));
    // An element without a comment of its own shows the program's documentation of its bit
    // (a DirectSOFT nickname).
    for e in ladder.rungs.iter_mut().flat_map(|r| r.elements.iter_mut()) {
        if e.comment.is_empty()
            && let Some(doc) = m.find(&e.operand).and_then(|loc| m.location_doc(loc))
        {
            e.comment = doc;
        }
    }
    Some(ladder)
}
