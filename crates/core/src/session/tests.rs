//! Tests of reading sessions: refused, damaged, old and absurd files.

use super::*;

#[test]
fn newer_foreign_and_broken_files_are_refused_clearly() {
    let newer = Session::from_ron("(format: 99, dialect: \"silverlode\")", "s.ron");
    assert!(matches!(newer, Err(SessionError::Newer { found: 99, .. })));
    let foreign = Session::from_ron("(name: \"x\")", "s.ron");
    assert!(matches!(foreign, Err(SessionError::Foreign { .. })));
    let other = Session::from_ron("(format: 2, dialect: \"cobol\")", "s.ron");
    assert!(matches!(other, Err(SessionError::Foreign { .. })));
    let v1_other = Session::from_ron("(format: 1, dialect: \"tml\")", "s.ron");
    assert!(
        matches!(v1_other, Err(SessionError::Foreign { .. })),
        "format 1 was SilverLode only"
    );
    let broken = Session::from_ron("(format: 2, dialect: \"silverlode\", at: ", "s.ron");
    match broken {
        Err(SessionError::Malformed { line, .. }) => assert_eq!(line, 1),
        other => panic!("{other:?}"),
    }
    assert!(Session::from_ron("not ron at all {", "s.ron").is_err());
}

#[test]
fn sessions_from_other_editors_and_damaged_ones() {
    let lf = "(format: 2, dialect: \"silverlode\", program: \"WRP 11, 1\\nEND\", at: (tick: 1))";
    let want = Session::from_ron(lf, "s.ron").expect("loads");
    let bom = format!("\u{feff}{}", lf.replace('\n', "\r\n"));
    assert_eq!(
        Session::from_ron(&bom, "s.ron").expect("a BOM is skipped"),
        want
    );
    let cr = "(format: 2,\rdialect: \"silverlode\",\rprogram: \"WRP 11, 1\\nEND\",\rat: (tick: 1))";
    assert_eq!(Session::from_ron(cr, "s.ron").expect("CR line ends"), want);
    let deep = format!(
        "(format: 2, dialect: \"silverlode\", view: {}",
        "(".repeat(10_000)
    );
    match Session::from_ron(&deep, "deep.ron") {
        Err(SessionError::Malformed { message, .. }) => {
            assert!(!message.contains("recursion_limit"), "{message}");
            assert!(message.contains("damaged"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn an_absurd_tick_is_refused_instead_of_replayed_forever() {
    let text =
        "(format: 1, dialect: \"silverlode\", program: \"l: JMP l\", tick: 18446744073709551615)";
    let s = Session::from_ron(text, "huge.ron").expect("parses");
    assert!(matches!(
        s.restore("huge.ron"),
        Err(SessionError::TooLong { .. })
    ));
    let text =
        "(format: 2, dialect: \"silverlode\", program: \"l: JMP l\", at: (tick: 2000000000))";
    let s = Session::from_ron(text, "huge.ron").expect("parses");
    assert!(matches!(
        s.restore("huge.ron"),
        Err(SessionError::TooLong { .. })
    ));
}

#[test]
fn an_older_file_with_missing_fields_still_loads() {
    let s = Session::from_ron(
        "(format: 1, dialect: \"silverlode\", program: \"WRP 11, 1\\nEND\")",
        "old.ron",
    )
    .expect("loads");
    assert_eq!(s.at, Pos::default());
    assert_eq!(s.view, ViewSettings::default());
    let d = s.restore("old.ron").expect("restores");
    assert_eq!(d.machine().ticks(), 0);
}

#[test]
fn a_format_1_input_number_at_the_edge_of_its_type_is_refused_by_name() {
    let text = "(format: 1, dialect: \"silverlode\", program: \"END\", \
                events: [(tick: 0, edit: Input(input: 18446744073709551615, high: true))])";
    let s = Session::from_ron(text, "old.ron").expect("parses");
    match s.restore("old.ron") {
        Err(SessionError::UnknownLocation { location, .. }) => {
            assert_eq!(location, "IO18446744073709551616")
        }
        other => panic!("{:?}", other.map(|_| ())),
    }
}

#[test]
fn an_edit_of_a_location_the_program_lacks_is_refused() {
    let text = "(format: 2, dialect: \"silverlode\", program: \"END\", \
                events: [(at: (tick: 0), location: \"V1400\", change: Set(1))])";
    let s = Session::from_ron(text, "s.ron").expect("parses");
    match s.restore("s.ron") {
        Err(SessionError::UnknownLocation { location, .. }) => assert_eq!(location, "V1400"),
        other => panic!("{:?}", other.map(|_| ())),
    }
}
