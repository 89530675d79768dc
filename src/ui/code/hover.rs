//! What hovering a word tells: a mnemonic's reference entry, a location's value in every
//! format, what a fixed-point or BCD literal stores.

/// What hovering a mnemonic tells: its reference entry's first paragraph (syntax, effect,
/// flags), from the dialect's document.
pub fn mnemonic_hover(dialect: &servoscope_core::registry::Dialect, token: &str) -> Option<String> {
    let mnemonic = mnemonic_in(dialect, token)?;
    let entry = dialect.reference_entry(&mnemonic)?;
    Some(format!(
        "{} — {}\n{}\nF1: the whole entry in the Help panel",
        entry.names.join(", "),
        entry.title,
        entry.summary.replace('`', "")
    ))
}

/// `token` as one of `dialect`'s mnemonics: `ADD(W)` is ADD, `WAIT!` is WAIT, `loop:CLC` is CLC.
pub fn mnemonic_in(dialect: &servoscope_core::registry::Dialect, token: &str) -> Option<String> {
    let token = token.rsplit(':').next().unwrap_or(token);
    let token = token.split('(').next().unwrap_or(token);
    let token = token.trim_end_matches([';', '!', ',']);
    dialect
        .is_mnemonic(token)
        .then(|| token.to_ascii_uppercase())
}

/// What hovering `word` in the code tells: a location's value in every format, or what a
/// `q16(…)`/`bcd(…)` literal stores.
pub fn hover_value(m: &dyn servoscope_core::machine::MachineView, word: &str) -> Option<String> {
    use servoscope_core::machine::Format;
    use servoscope_core::machine::value::parse_value;
    let loc = m.find(word).or_else(|| {
        m.program_names()
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(word))
            .map(|(_, l)| *l)
    });
    if let Some(loc) = loc {
        let info = m.info(loc)?;
        let raw = m.read(loc);
        let mut lines = vec![match info.alias {
            Some(alias) => format!("{} ({alias})", info.name),
            None => info.name.clone(),
        }];
        if let Some(doc) = m.location_doc(loc) {
            lines.push(doc);
        }
        if info.width == 1 {
            // A relay or an input is on or off: "signed −1" or "Q16.16 −0.000015" would be
            // readings of a number it is not.
            lines.push(if raw != 0 { "ON" } else { "OFF" }.to_string());
            if let Some(on) = m.forced(loc) {
                let level = if on { "ON" } else { "OFF" };
                lines.push(format!(
                    "FORCED {level}: the program reads {level} whatever it writes or the switch says"
                ));
            }
        } else {
            lines.extend(
                Format::ALL
                    .iter()
                    .map(|f| format!("{:>8}  {}", f.name(), f.show(raw, info.width))),
            );
        }
        lines.push(if m.can_force(loc) {
            "Right-click: who wrote it, break on it, watch it, force it".to_string()
        } else {
            "Right-click: who wrote it, break on it, watch it".to_string()
        });
        return Some(lines.join("\n"));
    }
    if let Some((name, value)) = m.program_constants().into_iter().find(|(n, _)| n == word) {
        // A constant is a 32-bit data value: every reading of it, like a register's.
        let raw = value as u64 & 0xFFFF_FFFF;
        let mut lines = vec![format!(
            "{name} (a constant; watches and conditions may use it)"
        )];
        lines.extend(
            Format::ALL
                .iter()
                .map(|f| format!("{:>8}  {}", f.name(), f.show(raw, 32))),
        );
        return Some(lines.join("\n"));
    }
    let lower = word.to_ascii_lowercase();
    // A Q16.16 literal, or a TML fixed literal (digits, a point, digits): what it really stores.
    let fixed_literal = (servoscope_core::registry::by_name(m.dialect())
        .is_some_and(|d| d.decimal_literals_are_fixed)
        && word.contains('.')
        && word.chars().all(|c| c.is_ascii_digit() || c == '.'))
    .then_some(word);
    let q16_inner = lower
        .strip_prefix("q16(")
        .and_then(|r| r.strip_suffix(')'))
        .map(|inner| &word[4..4 + inner.len()]);
    if let Some(typed) = q16_inner.or(fixed_literal)
        && let Ok(q) = servoscope_core::machine::value::quantize_q16(typed)
    {
        let raw = q.raw as u64 & 0xFFFF_FFFF;
        let mut lines = vec![
            format!("{word} stores {} ({})", q.raw, Format::Hex.show(raw, 32)),
            format!("   binary  {}", Format::Binary.show(raw, 32)),
            format!("which is {} (= {} / 65536)", q.stands_for, q.raw),
        ];
        lines.push(match &q.relative {
            Some(relative) => format!("quantization error {} ({relative})", q.error),
            None => format!("quantization error {}", q.error),
        });
        return Some(lines.join("\n"));
    }
    if lower.starts_with("q16(") || lower.starts_with("bcd(") {
        let raw = parse_value(word, 32).ok()?;
        let mut lines = vec![format!("{word} stores")];
        lines.extend(
            [Format::Signed, Format::Hex, Format::Binary]
                .iter()
                .map(|f| format!("{:>8}  {}", f.name(), f.show(raw, 32))),
        );
        return Some(lines.join("\n"));
    }
    None
}
