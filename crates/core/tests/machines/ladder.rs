//! The ladder model of the scanned PLCs (issue: layout in the core, one model for the panel and
//! the SVG): every example's diagram holds each of its instructions once, at its line, wired as
//! the boolean stack combines them; nested blocks and branches connect as the vendors' manuals
//! draw them; the SVG export carries the attributes tools read.

use std::collections::BTreeSet;

use servoscope_core::machine::plc::ladder::{Element, Ladder, Rung, Symbol};
use servoscope_core::registry::{self, by_name};

fn ladder_of(dialect: &str, source: &str) -> Ladder {
    let d = by_name(dialect).expect("registered");
    let engine = match d.open_text(source, &d.default_settings()) {
        Ok(e) => e,
        Err(diags) => panic!("assembles: {diags:?}"),
    };
    let ladder = engine
        .machine()
        .as_plc()
        .expect("a PLC has a ladder")
        .ladder();
    (*ladder).clone()
}

/// What feeds an element: the operands of the elements before it ("rail" for the left rail),
/// sorted.
fn feeds(r: &Rung, e: &Element) -> Vec<String> {
    let mut v: Vec<String> = r
        .before(e)
        .into_iter()
        .map(|b| b.map_or("rail".to_string(), |b| b.operand.clone()))
        .collect();
    v.sort();
    v
}

/// The element of `rung` on `line`.
fn at_line(l: &Ladder, line: usize) -> (&Rung, &Element) {
    l.rungs
        .iter()
        .find_map(|r| r.elements.iter().find(|e| e.line == line).map(|e| (r, e)))
        .unwrap_or_else(|| panic!("an element on line {line}"))
}

fn feeds_of(l: &Ladder, line: usize) -> Vec<String> {
    let (r, e) = at_line(l, line);
    feeds(r, e)
}

/// The instruction lines of a source: text before the comment, not a directive.
fn instruction_lines(source: &str, marker: &str) -> Vec<(usize, String)> {
    source
        .lines()
        .enumerate()
        .filter_map(|(i, l)| {
            let code = l.split(marker).next().unwrap_or("").trim();
            (!code.is_empty() && !code.starts_with('#')).then(|| (i + 1, code.to_string()))
        })
        .collect()
}

/// Instructions that combine blocks or move along the branch stack draw nothing themselves.
const DRAWN_AS_WIRES: [&str; 8] = [
    "ANDSTR", "ORSTR", "ANDLOD", "ORLOD", "BPS", "BRD", "BPP", "NOP",
];

fn check_structure(name: &str, source: &str, ladder: &Ladder, marker: &str) {
    let lines = instruction_lines(source, marker);
    let drawn: Vec<&(usize, String)> = lines
        .iter()
        .filter(|(_, code)| {
            let m = code
                .split_whitespace()
                .next()
                .unwrap_or("")
                .to_ascii_uppercase();
            !DRAWN_AS_WIRES.contains(&m.as_str())
        })
        .collect();
    let elements: Vec<&Element> = ladder.rungs.iter().flat_map(|r| &r.elements).collect();
    assert_eq!(
        elements.len(),
        drawn.len(),
        "{name}: one element per drawn instruction"
    );
    let element_lines: BTreeSet<usize> = elements.iter().map(|e| e.line).collect();
    let source_lines: BTreeSet<usize> = drawn.iter().map(|(l, _)| *l).collect();
    assert_eq!(element_lines, source_lines, "{name}: each at its line");
    for e in &elements {
        let code = &lines
            .iter()
            .find(|(l, _)| *l == e.line)
            .expect("its line")
            .1;
        assert!(
            code.to_ascii_uppercase()
                .contains(&e.operand.to_ascii_uppercase())
                || matches!(e.symbol, Symbol::PowerEdge(_) | Symbol::Invert),
            "{name} line {}: the operand {} is on the line '{code}'",
            e.line,
            e.operand
        );
    }
    for (k, r) in ladder.rungs.iter().enumerate() {
        // No two elements share a cell; coils and boxes end at the rung's last column; every
        // contact goes rightwards.
        let mut cells = BTreeSet::new();
        for e in &r.elements {
            let (a, b) = match e.to {
                Some(to) => (e.col, r.node_col[to as usize]),
                None => (e.from_col, r.last_col + 1),
            };
            assert!(b > a, "{name} rung {k}: line {} goes rightwards", e.line);
            for row in e.row..e.row + e.height {
                for c in a..b {
                    assert!(
                        cells.insert((row, c)),
                        "{name} rung {k}: line {} overlaps at ({row}, {c})",
                        e.line
                    );
                }
            }
            if e.to.is_none() {
                assert_eq!(e.col, r.last_col, "{name}: line {} at the right", e.line);
            }
        }
    }
}

#[test]
fn every_example_draws_each_instruction_once_at_its_line() {
    let mut seen = 0;
    for (dialect, name, source) in registry::examples() {
        let marker = match dialect.name {
            "dl205" => "//",
            "opennet" => ";",
            _ => continue,
        };
        let ladder = ladder_of(dialect.name, source);
        check_structure(name, source, &ladder, marker);
        seen += 1;
    }
    assert!(seen >= 15, "the DL205 and OpenNet examples ({seen})");
}

#[test]
fn dl205_examples_wire_as_written() {
    let source = include_str!("../../../../assets/examples/latch.dl205");
    let l = ladder_of("dl205", source);
    // STR X0; OR C0; ANDN X1; OUT C0 — the seal-in.
    assert_eq!(feeds_of(&l, 3), ["rail"]);
    assert_eq!(feeds_of(&l, 4), ["rail"], "OR C0 beside X0");
    assert_eq!(feeds_of(&l, 5), ["C0", "X0"], "X1 after both");
    assert_eq!(feeds_of(&l, 6), ["X1"]);
    // STR C0; ANDN C2; OUT C1.
    assert_eq!(feeds_of(&l, 8), ["C0"]);
    assert_eq!(feeds_of(&l, 9), ["C2"]);
    // STR C0; OUT C2; OUT Y0: two coils on one contact.
    assert_eq!(feeds_of(&l, 11), ["C0"]);
    assert_eq!(feeds_of(&l, 12), ["C0"]);
    assert_eq!(l.rungs.len(), 5, "four rungs and END");

    // The counter's two legs: count (X0) on top, reset (X1) below.
    let source = include_str!("../../../../assets/examples/parts_counter.dl205");
    let l = ladder_of("dl205", source);
    let cnt = source
        .lines()
        .position(|s| s.starts_with("CNT"))
        .expect("a CNT")
        + 1;
    let (r, e) = at_line(&l, cnt);
    assert_eq!(e.symbol, Symbol::Box);
    assert_eq!(e.from.len(), 2);
    let legs: Vec<String> = e
        .from
        .iter()
        .map(|&n| r.into_node(n).map(|x| x.operand.clone()).collect())
        .collect();
    assert_eq!(legs, ["X0", "X1"]);
    assert!(e.values.contains(&"CTA0".to_string()), "shows its count");

    // Stages stand alone as their own rungs; the JMP is an output of its condition.
    let source = include_str!("../../../../assets/examples/batch_mixer.dl205");
    let l = ladder_of("dl205", source);
    let sg = at_line(&l, 9).1;
    assert_eq!((sg.operand.as_str(), sg.from.len()), ("SG", 0));
    assert_eq!(feeds_of(&l, 8), ["X0"], "JMP S1 on X0");
    assert_eq!(feeds_of(&l, 13), ["X1"], "JMP S2 on X1");
}

#[test]
fn opennet_examples_wire_as_written() {
    let source = include_str!("../../../../assets/examples/conveyor.opennet");
    let l = ladder_of("opennet", source);
    let line = |text: &str| {
        source
            .lines()
            .position(|s| s.starts_with(text))
            .unwrap_or_else(|| panic!("{text}"))
            + 1
    };
    assert_eq!(feeds_of(&l, line("LOD I0")), ["rail"]);
    assert_eq!(feeds_of(&l, line("OR M0")), ["rail"]);
    assert_eq!(feeds_of(&l, line("ANDN I1")), ["I0", "M0"]);
    assert_eq!(feeds_of(&l, line("OUT M0")), ["I1"]);
    assert_eq!(feeds_of(&l, line("MCS")), ["M0"]);
    // CNT: the reset leg, then the pulse leg.
    let (r, e) = at_line(&l, line("CNT"));
    let legs: Vec<String> = e
        .from
        .iter()
        .map(|&n| r.into_node(n).map(|x| x.operand.clone()).collect())
        .collect();
    assert_eq!(legs, ["I3", "I2"]);
}

#[test]
fn nested_blocks_connect_as_the_stack_combines_them() {
    // ((X0·X1)·(X2+X3)) + (X4·X5) → Y0
    let dl = "STR X0\nAND X1\nSTR X2\nOR X3\nANDSTR\nSTR X4\nAND X5\nORSTR\nOUT Y0\nEND\n";
    let l = ladder_of("dl205", dl);
    assert_eq!(feeds_of(&l, 1), ["rail"]);
    assert_eq!(feeds_of(&l, 2), ["X0"]);
    assert_eq!(feeds_of(&l, 3), ["X1"]);
    assert_eq!(feeds_of(&l, 4), ["X1"]);
    assert_eq!(feeds_of(&l, 6), ["rail"]);
    assert_eq!(feeds_of(&l, 7), ["X4"]);
    assert_eq!(feeds_of(&l, 9), ["X2", "X3", "X5"]);
    check_structure("nested", dl, &l, "//");

    // OpenNet: (I0 · (I1 + I2)) then two branches from the same point (BPS/BPP).
    let on = "LOD I0\nLOD I1\nOR I2\nANDLOD\nBPS\nAND I3\nOUT Q0\nBPP\nANDN I4\nOUT Q1\nEND\n";
    let l = ladder_of("opennet", on);
    assert_eq!(feeds_of(&l, 2), ["I0"]);
    assert_eq!(feeds_of(&l, 3), ["I0"]);
    assert_eq!(feeds_of(&l, 6), ["I1", "I2"]);
    assert_eq!(feeds_of(&l, 7), ["I3"]);
    assert_eq!(
        feeds_of(&l, 9),
        ["I1", "I2"],
        "BPP: back at the saved point"
    );
    assert_eq!(feeds_of(&l, 10), ["I4"]);
    check_structure("branches", on, &l, ";");

    // DL205 outputs stacked with more conditions: STR X0; OUT Y0; AND X1; OUT Y1.
    let l = ladder_of("dl205", "STR X0\nOUT Y0\nAND X1\nOUT Y1\nEND\n");
    assert_eq!(feeds_of(&l, 3), ["X0"]);
    assert_eq!(feeds_of(&l, 4), ["X1"]);
    let (_, y0) = at_line(&l, 2);
    let (_, y1) = at_line(&l, 4);
    assert_eq!(y0.col, y1.col, "coils line up at the right rail");
    assert!(y1.row > y0.row);
}

/// #43 item 7: before the first scan no rung has been evaluated, so no wire has power (a
/// normally closed contact's rung reached Y1 in green while Y1 was off); after one scan the
/// same rung conducts and its coil is on.
#[test]
fn no_power_flows_before_the_first_scan() {
    use servoscope_core::machine::plc::ladder::{RungState, power_of};
    for (dialect, source, coil) in [
        ("dl205", "STRN X0\nOUT Y1\nEND\n", "Y1"),
        ("opennet", "LODN I0\nOUT Q1\nEND\n", "Q1"),
    ] {
        let d = by_name(dialect).expect("registered");
        let mut engine = match d.open_text(source, &d.default_settings()) {
            Ok(e) => e,
            Err(diags) => panic!("assembles: {diags:?}"),
        };
        let ladder = engine.machine().as_plc().expect("a PLC").ladder();
        let before = power_of(&ladder, engine.machine());
        assert!(
            before.iter().all(|r| r.state == RungState::NotYet
                && r.node.iter().all(|n| !n)
                && (r.element.iter().zip(&ladder.rungs[0].elements))
                    .all(|(on, e)| !on || matches!(e.symbol, Symbol::Contact { .. }))),
            "{dialect}: {before:?}"
        );
        engine.run_headless(&[], 1);
        let loc = engine.machine().find(coil).expect("the coil");
        assert_eq!(
            engine.machine().read(loc),
            1,
            "{dialect}: {coil} on after a scan"
        );
        let after = power_of(&ladder, engine.machine());
        assert_eq!(after[0].state, RungState::Done, "{dialect}");
        assert!(
            after[0].element.iter().all(|&on| on),
            "{dialect}: {after:?}"
        );
    }
}

/// #43 item 15: a bit driven by OUT in two rungs is a warning (as DirectSOFT's program check
/// and WindLDR's give), naming both lines; SET/RST of one bit is not, nor one OUT in each of
/// two stages (the shipped push-on/push-off example drives its lamp so).
#[test]
fn a_duplicate_coil_is_a_warning_naming_both_lines() {
    for (dialect, source, bit) in [
        (
            "dl205",
            "STR X0\nOUT Y0\nSTR X1\nOUT Y0\nSTR X2\nSET Y1\nSTR X3\nRST Y1\nEND\n",
            "Y0",
        ),
        (
            "opennet",
            "LOD I0\nOUT Q0\nLOD I1\nOUT Q0\nLOD I2\nSET Q1\nLOD I3\nRST Q1\nEND\n",
            "Q0",
        ),
    ] {
        let d = by_name(dialect).expect("registered");
        let engine = match d.open_text(source, &d.default_settings()) {
            Ok(e) => e,
            Err(diags) => panic!("assembles: {diags:?}"),
        };
        let warnings = engine.machine().warnings();
        assert_eq!(warnings.len(), 1, "{dialect}: {warnings:?}");
        let w = &warnings[0];
        assert_eq!(w.line, 4, "{dialect}: on the second OUT");
        assert!(
            w.message
                .starts_with(&format!("{bit} is already an output coil on line 2")),
            "{dialect}: {}",
            w.message
        );
    }
    let d = by_name("dl205").expect("registered");
    let staged = include_str!("../../../../assets/examples/push_on_off.dl205");
    let engine = d
        .open_text(staged, &d.default_settings())
        .expect("assembles");
    assert_eq!(engine.machine().warnings(), []);
}

/// #43 item 14: a DirectSOFT export's `#BEGIN ELEMENT_DOC` records ("element", "nickname",
/// "wiring info", "description"; a quote doubled) name their elements: the nickname works in
/// expressions, the documentation shows on the diagram and in views.
#[test]
fn directsoft_element_documentation_names_the_elements() {
    let source = "#BEGIN ELEMENT_DOC\n\
        \"X0\",\"START_PB\",\"TB1-3\",\"Start push button\"\n\
        \"Y0\",\"MOTOR\",\"\",\"Motor \"\"M1\"\" contactor\"\n\
        #END\n\
        STR X0\nOUT Y0\nEND\n";
    let d = by_name("dl205").expect("registered");
    let mut engine = d
        .open_text(source, &d.default_settings())
        .expect("assembles");
    let m = engine.machine();
    let x0 = m.find("X0").expect("X0");
    let y0 = m.find("Y0").expect("Y0");
    assert_eq!(
        m.location_doc(x0).as_deref(),
        Some("START_PB — Start push button")
    );
    assert_eq!(
        m.location_doc(y0).as_deref(),
        Some("MOTOR — Motor \"M1\" contactor")
    );
    let names = m.program_names();
    assert!(names.contains(&("START_PB".to_string(), x0)), "{names:?}");
    // On the diagram, under the contact and the coil.
    let ladder = servoscope_core::machine::plc::ladder::with_comments(m, source, d.classify)
        .expect("a ladder");
    let comments: Vec<&str> = ladder.rungs[0]
        .elements
        .iter()
        .map(|e| e.comment.as_str())
        .collect();
    assert_eq!(
        comments,
        [
            "START_PB — Start push button",
            "MOTOR — Motor \"M1\" contactor"
        ]
    );
    // In an expression: the nickname reads X0.
    engine
        .edit(x0, servoscope_core::debugger::history::Change::Set(1))
        .expect("X0 takes 1");
    engine.run_headless(&[], 1);
    let expr =
        servoscope_core::debugger::expr::Expr::compile("START_PB && MOTOR", engine.machine())
            .expect("compiles");
    assert_eq!(expr.eval(engine.machine()), 1);
}

#[test]
fn a_rung_too_long_to_draw_runs_and_shows_a_note_in_its_place() {
    // 200,000 series contacts (DL205) and 200,000 boxes on one rung (OpenNet), each followed
    // by an ordinary rung that still draws as usual.
    let contacts = format!(
        "STR X0\n{}OUT Y0\nSTR X2\nOUT Y1\nEND\n",
        "AND X1\n".repeat(200_000)
    );
    let boxes = format!(
        "LOD I0\n{}LOD I1\nOUT Q1\nEND\n",
        "ADD(W) D0 1 D1\n".repeat(200_000)
    );
    for (dialect, source, elements, next_line) in [
        ("dl205", contacts, 200_002, 200_003),
        ("opennet", boxes, 200_001, 200_002),
    ] {
        let (dialect, source) = (dialect.to_string(), source);
        let (ladder, svg) = crate::common::within(120, move || {
            let d = by_name(&dialect).expect("registered");
            let engine = d
                .open_text(&source, &d.default_settings())
                .unwrap_or_else(|e| panic!("{dialect} assembles: {:?}", e.first()));
            let mut run = engine.restarted(Vec::new(), Vec::new());
            run.run_headless(&[], 1);
            assert_eq!(run.machine().ticks(), 1, "{dialect}: a scan ran");
            let m = run.machine();
            let ladder =
                servoscope_core::machine::plc::ladder::with_comments(m, &source, d.classify)
                    .expect("a diagram");
            let svg = servoscope_core::machine::plc::ladder::svg_of(m, &ladder, "long");
            (ladder, svg)
        });
        let long = &ladder.rungs[0];
        assert_eq!(long.elements.len(), elements);
        let note = long.oversized.as_deref().expect("too large to draw");
        assert!(note.contains("lines 1–"), "{note}");
        assert!(note.contains("at most 512 columns and 1024 rows"), "{note}");
        assert!(
            long.rows <= 2,
            "a note's rows, not the rung's {}",
            long.rows
        );
        // The next rung is laid out as ever, its coil in the last column of the drawn rungs.
        let (rung, coil) = at_line(&ladder, next_line + 1);
        assert!(rung.oversized.is_none());
        assert_eq!(coil.col, ladder.last_col);
        assert!(
            ladder.last_col < 10,
            "the long rung does not widen the others"
        );
        assert!(svg.contains("class=\"oversized\""));
        assert!(svg.len() < 1 << 20, "{} bytes", svg.len());
    }
}

#[test]
fn the_widest_and_tallest_rungs_that_fit_are_drawn() {
    // 510 contacts and a coil: 512 columns, the most drawn; one more contact is too many.
    for (contacts, drawn) in [(510, true), (511, false)] {
        let source = format!("STR X0\n{}OUT Y0\nEND\n", "AND X1\n".repeat(contacts));
        let ladder = ladder_of("dl205", &source);
        assert_eq!(
            ladder.rungs[0].oversized.is_none(),
            drawn,
            "{contacts} contacts"
        );
        if drawn {
            assert_eq!(usize::from(ladder.last_col) + 1, 512);
        }
    }
    // 1024 coils on one condition: 1024 rows; 1025 are too many.
    for (coils, drawn) in [(1024, true), (1025, false)] {
        let outs: String = (0..coils).map(|k| format!("OUT C{k:o}\n")).collect();
        let source = format!("STR X0\n{outs}END\n");
        let ladder = ladder_of("dl205", &source);
        assert_eq!(ladder.rungs[0].oversized.is_none(), drawn, "{coils} coils");
        if drawn {
            assert_eq!(ladder.rungs[0].rows, 1024);
        }
    }
}
