//! The instruction reference of a dialect, read from its user document `docs/<dialect>.md`
//! (embedded in the build), so the window's hover text, its Help panel and the document never
//! disagree.
//!
//! The document's section `## Instruction reference` holds one entry per instruction or family:
//! a heading `### NAME — what it does` or `### NAME1, NAME2 — what they do`, then a first
//! paragraph of up to three lines (syntax, effect, flags) that is the hover text, then whatever
//! more the entry needs.

/// One entry of the reference.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// The mnemonics it covers, upper case, as the heading lists them.
    pub names: Vec<String>,
    /// What the heading says after the dash.
    pub title: String,
    /// The first paragraph: the hover text.
    pub summary: String,
    /// The whole entry as Markdown, heading included.
    pub markdown: String,
}

impl Entry {
    pub fn covers(&self, mnemonic: &str) -> bool {
        self.names.iter().any(|n| n.eq_ignore_ascii_case(mnemonic))
    }
}

/// The heading that starts the reference section.
pub const SECTION: &str = "## Instruction reference";

/// Every entry of `document`'s reference section, in document order; none when it has no
/// such section.
pub fn entries(document: &str) -> Vec<Entry> {
    let Some(start) = document.find(SECTION) else {
        return Vec::new();
    };
    let section = &document[start + SECTION.len()..];
    // The section ends at the next level-2 heading.
    let section = match section.find("\n## ") {
        Some(end) => &section[..end],
        None => section,
    };
    let mut out: Vec<Entry> = Vec::new();
    for block in section.split("\n### ").skip(1) {
        let (heading, body) = block.split_once('\n').unwrap_or((block, ""));
        let (names, title) = match heading.split_once(" — ") {
            Some((names, title)) => (names, title.trim()),
            None => (heading, ""),
        };
        let names: Vec<String> = names
            .split(',')
            .map(|n| n.trim().trim_matches('`').to_ascii_uppercase())
            .filter(|n| !n.is_empty())
            .collect();
        let summary = body
            .trim_start_matches('\n')
            .split("\n\n")
            .next()
            .unwrap_or("")
            .trim()
            .to_string();
        // The summary's lines (syntax, effect, flags) stay lines when rendered: hard breaks.
        let body = body.trim_end();
        let body = match body.find(&summary) {
            Some(at) if !summary.is_empty() => format!(
                "{}{}{}",
                &body[..at],
                summary.replace('\n', "  \n"),
                &body[at + summary.len()..]
            ),
            _ => body.to_string(),
        };
        out.push(Entry {
            names,
            title: title.to_string(),
            summary,
            markdown: format!("### {heading}\n{body}"),
        });
    }
    out
}

/// The entry that covers `mnemonic` (case-insensitive).
pub fn entry_for(document: &str, mnemonic: &str) -> Option<Entry> {
    entries(document).into_iter().find(|e| e.covers(mnemonic))
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = "# X\n\n## Writing\ntext\n\n## Instruction reference\n\nIntro.\n\n\
        ### ADD, ADDD — add to the accumulator\n\n`ADD V2000`\nAdds.\nFlags: SP63.\n\nMore.\n\n\
        ### END — end of the scan\n\n`END`\nEnds the scan.\n\n## After\n### NOT — not an entry\n";

    #[test]
    fn entries_are_the_level_three_headings_of_the_section_only() {
        let all = entries(DOC);
        let names: Vec<&[String]> = all.iter().map(|e| e.names.as_slice()).collect();
        assert_eq!(
            names,
            [
                &["ADD".to_string(), "ADDD".to_string()][..],
                &["END".to_string()][..]
            ]
        );
        assert_eq!(all[0].title, "add to the accumulator");
        assert_eq!(all[0].summary, "`ADD V2000`\nAdds.\nFlags: SP63.");
        assert!(all[0].markdown.ends_with("More."));
        assert!(
            all[0]
                .markdown
                .contains("`ADD V2000`  \nAdds.  \nFlags: SP63."),
            "the summary's lines stay lines: {}",
            all[0].markdown
        );
        assert_eq!(entry_for(DOC, "addd").map(|e| e.names.len()), Some(2));
        assert!(
            entry_for(DOC, "NOT").is_none(),
            "a heading after the section"
        );
        assert!(entries("# no reference\n### ADD — x\n").is_empty());
    }
}
