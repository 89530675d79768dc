//! The diagram drawn as a standalone SVG document, with its power flow, live values and
//! forces.

use std::fmt::Write as _;

use super::{CoilKind, EdgeKind, Ladder, NodeId, RungPower, RungState, Symbol, power_of};

/// A live value a box shows, in the location's own reading: `TA1 = 29` (BCD on a DL205).
pub fn value_text(m: &dyn crate::machine::MachineView, name: &str) -> String {
    match m.find(name).and_then(|loc| Some((loc, m.info(loc)?))) {
        Some((loc, info)) => format!("{name} = {}", info.reading().show(m.read(loc), info.width)),
        None => name.to_string(),
    }
}

/// The comment every ladder SVG carries after its `<svg>` tag: how a later export knows the
/// file is ours to replace (`crate::output`).
pub const SVG_MARK: &str = "<!-- servoscope ladder diagram -->";

/// The whole diagram of `m` as SVG with its power flow now.
pub fn svg_of(m: &dyn crate::machine::MachineView, ladder: &Ladder, title: &str) -> String {
    let power = power_of(ladder, m);
    let forced = |name: &str| m.find(name).and_then(|loc| m.forced(loc));
    svg(ladder, &power, title, &|name| value_text(m, name), &forced)
}

/// Cell size of the SVG drawing, in px.
const CELL_W: u32 = 110;
const CELL_H: u32 = 76;
const RUNG_GAP: u32 = 26;
/// Lines of a rung's comment a drawing shows (a file's opening paragraph can be long).
pub const RUNG_COMMENT_LINES: usize = 3;

/// Text for an SVG (XML 1.0) document: markup escaped, and the characters XML cannot hold at
/// all (C0 controls but tab and line breaks, U+FFFE, U+FFFF) shown as their control pictures
/// (ESC as ␛) or U+FFFD, so a comment with a terminal colour code still gives a valid file.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\t' | '\n' | '\r' => out.push(c),
            '\u{0}'..='\u{1f}' => {
                out.push(char::from_u32(0x2400 + c as u32).unwrap_or('\u{fffd}'));
            }
            '\u{fffe}' | '\u{ffff}' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// Stroke attributes of a wire or symbol, lit or not (attributes, not CSS: every SVG reader
/// honours them).
fn stroke(lit: bool) -> &'static str {
    if lit {
        r##"stroke="#1a9c3a" stroke-width="3""##
    } else {
        r##"stroke="#555555" stroke-width="2""##
    }
}

/// `text` cut to `max` characters with an ellipsis.
pub fn fit(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_string()
    } else {
        let mut t: String = text.chars().take(max.saturating_sub(1)).collect();
        t.push('…');
        t
    }
}

/// The drawn symbol of a coil: `( )`, `(S)`.
pub fn coil_letters(kind: CoilKind) -> &'static str {
    match kind {
        CoilKind::Out => " ",
        CoilKind::OutNot => "/",
        CoilKind::Set => "S",
        CoilKind::Reset => "R",
        CoilKind::Pulse => "PD",
        CoilKind::OrOut => "OR",
        CoilKind::Jump => "JMP",
    }
}

/// The diagram as a standalone SVG document with the power flow of `power` (one per rung);
/// `values(name)` gives the text a box shows for a live value (`TA1 = 29`). Every element is a
/// `<g class="element">` with `data-line`, `data-operand` and `data-powered`; every rung a
/// `<g class="rung" data-rung="K">`.
pub fn svg(
    ladder: &Ladder,
    power: &[RungPower],
    title: &str,
    values: &dyn Fn(&str) -> String,
    forced: &dyn Fn(&str) -> Option<bool>,
) -> String {
    let cols = u32::from(ladder.last_col) + 1;
    let left = 40u32;
    // Room right of the right rail for a rung's state.
    let width = left * 2 + cols * CELL_W + 120;
    let mut y = 50u32;
    let mut body = String::new();
    for (k, rung) in ladder.rungs.iter().enumerate() {
        let pw = power.get(k);
        let comment: Vec<&str> = rung.comment.lines().take(RUNG_COMMENT_LINES).collect();
        let comment_lines = comment.len() as u32;
        let top = y + comment_lines * 14 + if comment_lines > 0 { 8 } else { 0 };
        let height = u32::from(rung.rows) * CELL_H;
        let _ = writeln!(
            body,
            r#"<g class="rung" data-rung="{k}" data-line="{}">"#,
            rung.first_line()
        );
        for (i, line) in comment.iter().enumerate() {
            let _ = writeln!(
                body,
                r##"<text class="comment" x="{left}" y="{}" fill="#2a7a2a" font-style="italic">{}</text>"##,
                y + 12 + i as u32 * 14,
                escape(&fit(line, (width as usize - left as usize) / 6))
            );
        }
        if let Some(why) = &rung.oversized {
            let _ = writeln!(
                body,
                r##"<text class="oversized" x="{left}" y="{}" fill="#aa5500">{}</text>"##,
                top + CELL_H / 2,
                escape(why)
            );
            body.push_str("</g>\n");
            y = top + height + RUNG_GAP;
            continue;
        }
        let on = |node: NodeId| pw.is_some_and(|p| p.node.get(node as usize) == Some(&true));
        let wire = |body: &mut String, x1: u32, y1: u32, x2: u32, y2: u32, lit: bool| {
            let _ = writeln!(
                body,
                r#"<line class="wire{}" x1="{x1}" y1="{y1}" x2="{x2}" y2="{y2}" {}/>"#,
                if lit { " on" } else { "" },
                stroke(lit)
            );
        };
        let x_of = |c: u32| left + c * CELL_W;
        let y_of = |r: u32| top + r * CELL_H + CELL_H / 2;
        let state = pw.map_or(RungState::Done, |p| p.state);
        // Rails.
        wire(
            &mut body,
            left,
            top,
            left,
            top + height,
            state == RungState::Done,
        );
        let right = x_of(cols);
        let note = match state {
            RungState::Done => None,
            RungState::NotYet => Some("not yet this scan"),
            RungState::NotRun => Some("not run this scan"),
            RungState::MasterOff => Some("MC off: outputs off"),
        };
        if let Some(note) = note {
            let _ = writeln!(
                body,
                r##"<text class="state" x="{}" y="{}" fill="#888888" font-style="italic">{note}</text>"##,
                right + 6,
                top + 14
            );
        }
        wire(&mut body, right, top, right, top + height, false);
        for f in &rung.fillers {
            wire(
                &mut body,
                x_of(u32::from(f.from_col)),
                y_of(u32::from(f.row)),
                x_of(u32::from(f.to_col)),
                y_of(u32::from(f.row)),
                on(f.node),
            );
        }
        for v in &rung.verticals {
            wire(
                &mut body,
                x_of(u32::from(v.col)),
                y_of(u32::from(v.top)),
                x_of(u32::from(v.col)),
                y_of(u32::from(v.bottom)),
                on(v.node),
            );
        }
        for (i, e) in rung.elements.iter().enumerate() {
            let powered = pw.is_some_and(|p| p.element.get(i) == Some(&true));
            let col = if e.to.is_none() {
                cols - 1
            } else {
                u32::from(e.col)
            };
            let (x, yc) = (x_of(col), y_of(u32::from(e.row)));
            let force = forced(&e.operand);
            let _ = writeln!(
                body,
                r#"<g class="element{}" data-line="{}" data-operand="{}" data-powered="{}"{}>"#,
                if powered { " on" } else { "" },
                e.line,
                escape(&e.operand),
                u8::from(powered),
                match force {
                    Some(on) => format!(r#" data-forced="{}""#, u8::from(on)),
                    None => String::new(),
                }
            );
            if let Some(on) = force {
                let _ = writeln!(
                    body,
                    r##"<rect x="{}" y="{}" width="20" height="13" rx="3" fill="#e67814"/><text x="{}" y="{}" fill="#ffffff" font-size="9" text-anchor="middle">F{}</text>"##,
                    x + CELL_W / 2 + 14,
                    yc + 8,
                    x + CELL_W / 2 + 24,
                    yc + 18,
                    u8::from(on)
                );
            }
            let input_lit = e.from.first().is_some_and(|&f| on(f));
            // A coil's or box's input wires run from their nodes to its column.
            if e.to.is_none() {
                for (&f, &row) in e.from.iter().zip(&e.leg_rows) {
                    let from = u32::from(rung.node_col.get(f as usize).copied().unwrap_or(0));
                    let yk = y_of(u32::from(row));
                    if from < col {
                        wire(&mut body, x_of(from), yk, x, yk, on(f));
                    }
                }
            }
            let mid = x + CELL_W / 2;
            match e.symbol {
                Symbol::Box => {
                    let h = u32::from(e.height) * CELL_H - 16;
                    for (&f, &row) in e.from.iter().zip(&e.leg_rows) {
                        let yk = y_of(u32::from(row));
                        wire(&mut body, x, yk, x + 8, yk, on(f));
                    }
                    let _ = writeln!(
                        body,
                        r##"<rect x="{}" y="{}" width="{}" height="{h}" rx="3" fill="#ffffff" {}/>"##,
                        x + 8,
                        yc - CELL_H / 2 + 8,
                        CELL_W - 16,
                        stroke(powered)
                    );
                    let mut lines = vec![e.text.clone()];
                    lines.extend(e.values.iter().map(|v| values(v)));
                    for (j, l) in lines.iter().enumerate() {
                        let _ = writeln!(
                            body,
                            r#"<text class="box" x="{mid}" y="{}" text-anchor="middle">{}</text>"#,
                            yc - CELL_H / 2 + 24 + j as u32 * 14,
                            escape(&fit(l, 16))
                        );
                    }
                    if !e.comment.is_empty() {
                        let _ = writeln!(
                            body,
                            r##"<text class="note" x="{mid}" y="{}" text-anchor="middle" fill="#2a7a2a" font-size="9"><title>{}</title>{}</text>"##,
                            // Inside the box, along its bottom edge.
                            yc - CELL_H / 2 + 8 + h - 5,
                            escape(&e.comment),
                            escape(&fit(&e.comment, 22))
                        );
                    }
                }
                _ => {
                    let (l, r) = (mid - 12, mid + 12);
                    wire(&mut body, x, yc, l, yc, input_lit);
                    let out_lit = match e.to {
                        Some(to) => on(to),
                        None => false,
                    };
                    wire(&mut body, r, yc, x + CELL_W, yc, out_lit);
                    match e.symbol {
                        Symbol::Coil(kind) => {
                            let _ = writeln!(
                                body,
                                r#"<path class="coil" d="M{} {} a 14 14 0 0 0 0 28 M{} {} a 14 14 0 0 1 0 28" fill="none" {}/><text class="sym" x="{mid}" y="{}" text-anchor="middle" font-weight="bold">{}</text>"#,
                                l + 6,
                                yc - 14,
                                r - 6,
                                yc - 14,
                                stroke(powered),
                                yc + 4,
                                coil_letters(kind)
                            );
                        }
                        _ => {
                            let mark = match e.symbol {
                                Symbol::Contact { closed: true, .. } => "/",
                                Symbol::Contact {
                                    edge: Some(EdgeKind::Rising),
                                    ..
                                }
                                | Symbol::PowerEdge(EdgeKind::Rising) => "↑",
                                Symbol::Contact {
                                    edge: Some(EdgeKind::Falling),
                                    ..
                                }
                                | Symbol::PowerEdge(EdgeKind::Falling) => "↓",
                                Symbol::Invert => "NOT",
                                Symbol::Compare => "CMP",
                                _ => "",
                            };
                            let _ = writeln!(
                                body,
                                r#"<line class="contact" x1="{l}" y1="{}" x2="{l}" y2="{}" {}/><line class="contact" x1="{r}" y1="{}" x2="{r}" y2="{}" {}/><text class="sym" x="{mid}" y="{}" text-anchor="middle" font-weight="bold">{}</text>"#,
                                yc - 14,
                                yc + 14,
                                stroke(powered),
                                yc - 14,
                                yc + 14,
                                stroke(powered),
                                yc + 4,
                                mark
                            );
                        }
                    }
                    let _ = writeln!(
                        body,
                        r#"<text class="name" x="{mid}" y="{}" text-anchor="middle">{}</text>"#,
                        yc - 18,
                        escape(&fit(&e.text, 18))
                    );
                    if !e.comment.is_empty() {
                        let _ = writeln!(
                            body,
                            r##"<text class="note" x="{mid}" y="{}" text-anchor="middle" fill="#2a7a2a" font-size="9"><title>{}</title>{}</text>"##,
                            yc - 31,
                            escape(&e.comment),
                            escape(&fit(&e.comment, 22))
                        );
                    }
                }
            }
            body.push_str("</g>\n");
        }
        body.push_str("</g>\n");
        y = top + height + RUNG_GAP;
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{y}" viewBox="0 0 {width} {y}" font-family="sans-serif" font-size="11">"#
    );
    out.push_str(SVG_MARK);
    out.push('\n');
    let _ = writeln!(
        out,
        r#"<text x="{}" y="24" font-size="14">{}</text>"#,
        left,
        escape(title)
    );
    out.push_str(&body);
    out.push_str("</svg>\n");
    out
}
