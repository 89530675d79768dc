//! Tests of the ladder model: wiring, layout, power flow and the SVG.

use super::*;

fn c(i: usize, name: &str) -> Element {
    Element::new(
        Symbol::Contact {
            closed: false,
            edge: None,
        },
        i,
        i + 1,
        name,
    )
}

fn coil(i: usize, name: &str) -> Element {
    Element::new(Symbol::Coil(CoilKind::Out), i, i + 1, name)
}

fn named<'a>(r: &'a Rung, name: &str) -> &'a Element {
    r.elements.iter().find(|e| e.operand == name).expect(name)
}

fn before(r: &Rung, name: &str) -> Vec<String> {
    let mut v: Vec<String> = r
        .before(named(r, name))
        .into_iter()
        .map(|e| e.map_or("rail".to_string(), |e| e.operand.clone()))
        .collect();
    v.sort();
    v
}

#[test]
fn series_parallel_and_blocks_wire_as_the_stack_combines() {
    // (A·B + C) · (D + E) → Y
    let ladder = Ladder::build([
        Step::Load(c(0, "A")),
        Step::And(c(1, "B")),
        Step::Or(c(2, "C")),
        Step::Load(c(3, "D")),
        Step::Or(c(4, "E")),
        Step::AndBlock,
        Step::Output(coil(5, "Y")),
    ]);
    assert_eq!(ladder.rungs.len(), 1);
    let r = &ladder.rungs[0];
    assert_eq!(before(r, "A"), ["rail"]);
    assert_eq!(before(r, "B"), ["A"]);
    assert_eq!(before(r, "C"), ["rail"]);
    assert_eq!(before(r, "D"), ["B", "C"]);
    assert_eq!(before(r, "E"), ["B", "C"]);
    assert_eq!(before(r, "Y"), ["D", "E"]);
    // Power: A off, C on, E on → Y powered; D's wire lit through C.
    let p = RungPower::of(r, RungState::Done, |i| [false, true, true, false, true][i]);
    let y = r.elements.iter().position(|e| e.operand == "Y").unwrap();
    assert!(p.element[y]);
    let p = RungPower::of(r, RungState::Done, |i| [false, true, false, true, true][i]);
    assert!(!p.element[y], "A·B + C is off");
}

#[test]
fn outputs_after_more_conditions_branch_at_the_fork() {
    // STR X1; OUT Y1; AND X2; OUT Y2 — then a new rung at STR.
    let ladder = Ladder::build([
        Step::Load(c(0, "X1")),
        Step::Output(coil(1, "Y1")),
        Step::And(c(2, "X2")),
        Step::Output(coil(3, "Y2")),
        Step::Load(c(4, "X3")),
        Step::Output(coil(5, "Y3")),
    ]);
    assert_eq!(ladder.rungs.len(), 2);
    let r = &ladder.rungs[0];
    assert_eq!(before(r, "Y1"), ["X1"]);
    assert_eq!(before(r, "X2"), ["X1"]);
    assert_eq!(before(r, "Y2"), ["X2"]);
    assert_eq!(named(r, "Y1").col, named(r, "Y2").col, "coils line up");
    assert_ne!(named(r, "Y1").row, named(r, "Y2").row);
}

#[test]
fn branch_stack_and_boxes_with_legs() {
    // LOD A; BPS; AND B; OUT Q1; BPP; AND C; OUT Q2
    let ladder = Ladder::build([
        Step::Load(c(0, "A")),
        Step::Push,
        Step::And(c(1, "B")),
        Step::Output(coil(2, "Q1")),
        Step::Pop,
        Step::And(c(3, "C")),
        Step::Output(coil(4, "Q2")),
        // Reset leg, pulse leg, CNT.
        Step::Load(c(5, "R")),
        Step::Load(c(6, "P")),
        Step::Boxed(Element::new(Symbol::Box, 7, 8, "CNT"), 2),
    ]);
    let r = &ladder.rungs[0];
    assert_eq!(before(r, "B"), ["A"]);
    assert_eq!(before(r, "C"), ["A"]);
    assert_eq!(before(r, "Q2"), ["C"]);
    let cnt = &ladder.rungs[1];
    let b = named(cnt, "CNT");
    assert_eq!(b.from.len(), 2);
    assert_eq!(b.height, 2);
    assert_eq!(before(cnt, "CNT"), ["P", "R"]);
    assert_eq!(
        named(cnt, "R").row,
        b.row,
        "the first leg enters at the top"
    );
    assert_eq!(named(cnt, "P").row, b.row + 1);
}

#[test]
fn only_an_evaluated_rung_has_power() {
    let ladder = Ladder::build([Step::Load(c(0, "X1")), Step::Output(coil(1, "Y1"))]);
    let r = &ladder.rungs[0];
    for state in [RungState::NotYet, RungState::NotRun, RungState::MasterOff] {
        let p = RungPower::of(r, state, |_| true);
        assert_eq!(
            p.element,
            [true, false],
            "{state:?}: the contact shows its bit"
        );
        assert!(!p.node[1], "{state:?}: no power past it");
    }
    let p = RungPower::of(r, RungState::Done, |_| true);
    assert_eq!(p.element, [true, true]);
}

#[test]
fn svg_carries_the_attributes() {
    let ladder = Ladder::build([Step::Load(c(0, "X<1")), Step::Output(coil(1, "Y1"))]);
    let power = vec![RungPower::of(&ladder.rungs[0], RungState::Done, |_| true)];
    let s = svg(&ladder, &power, "t", &|v| v.to_string(), &|_| None);
    assert!(s.contains(r#"data-rung="0""#));
    assert!(s.contains(r#"data-line="1" data-operand="X&lt;1" data-powered="1""#));
    assert!(s.contains(r#"data-line="2" data-operand="Y1" data-powered="1""#));
}
