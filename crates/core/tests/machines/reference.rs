//! The instruction reference inside the window comes from `docs/<dialect>.md`: every mnemonic
//! each assembler accepts has an entry there, with a short first paragraph for the hover.

use servoscope_core::machine::reference;
use servoscope_core::registry::DIALECTS;

#[test]
fn every_mnemonic_the_assemblers_accept_has_a_reference_entry() {
    for d in DIALECTS {
        let entries = reference::entries(d.reference);
        assert!(
            !entries.is_empty(),
            "docs/{}.md has no instruction reference",
            d.name
        );
        let missing: Vec<&str> = d
            .mnemonics
            .iter()
            .flat_map(|list| list.iter().copied())
            .filter(|m| !entries.iter().any(|e| e.covers(m)))
            .collect();
        assert!(
            missing.is_empty(),
            "docs/{}.md lacks entries for {missing:?}",
            d.name
        );
    }
}

#[test]
fn every_entry_names_real_mnemonics_and_opens_with_a_short_summary() {
    for d in DIALECTS {
        for e in reference::entries(d.reference) {
            let names = e.names.join(", ");
            assert!(
                !e.names.is_empty(),
                "docs/{}.md: an entry without names",
                d.name
            );
            for name in &e.names {
                assert!(
                    d.is_mnemonic(name),
                    "docs/{}.md: '{name}' is not a mnemonic the assembler accepts",
                    d.name
                );
            }
            assert!(
                !e.title.is_empty(),
                "docs/{}.md: {names} has no title",
                d.name
            );
            let lines = e.summary.lines().count();
            assert!(
                (1..=3).contains(&lines),
                "docs/{}.md: {names}: the hover text has {lines} lines",
                d.name
            );
            assert!(
                e.summary.starts_with('`'),
                "docs/{}.md: {names}: the first line is the syntax, in backticks",
                d.name
            );
        }
    }
}

#[test]
fn an_entry_is_found_by_any_of_its_names_in_any_case() {
    for d in DIALECTS {
        for m in d.mnemonics.iter().flat_map(|list| list.iter()) {
            let entry = d.reference_entry(&m.to_ascii_lowercase());
            assert!(entry.is_some_and(|e| e.covers(m)), "{}: {m}", d.name);
        }
        assert!(d.reference_entry("NOT_A_MNEMONIC").is_none());
    }
}
