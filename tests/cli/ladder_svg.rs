//! `servoscope ladder --svg`: the drawing a user exports carries each element's line, operand
//! and power.

use crate::common;

use common::servoscope;

/// Each `<g class="element…">` of an SVG as (line, operand, powered).
fn svg_elements(svg: &str) -> Vec<(usize, String, bool)> {
    let attr = |tag: &str, name: &str| -> String {
        let key = format!("{name}=\"");
        let start = tag.find(&key).expect(name) + key.len();
        tag[start..].split('"').next().unwrap_or("").to_string()
    };
    svg.lines()
        .filter(|l| l.starts_with("<g class=\"element"))
        .map(|tag| {
            (
                attr(tag, "data-line").parse().expect("a line number"),
                attr(tag, "data-operand"),
                attr(tag, "data-powered") == "1",
            )
        })
        .collect()
}

#[test]
fn the_svg_export_carries_line_operand_and_power() {
    let dir = std::env::temp_dir().join(format!("servoscope_ladder_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temp dir");
    let out = dir.join("latch.svg");
    let program = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/examples/latch.dl205");
    // Start pressed in scans 1–2: the latch holds C0 and Y0 on after it is released.
    let run = servoscope(&[
        "ladder",
        program,
        "--max-ticks",
        "5",
        "--input",
        "X0=1,3",
        "--svg",
        out.to_str().expect("utf-8"),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let svg = std::fs::read_to_string(&out).expect("written");
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    for k in 0..5 {
        assert!(svg.contains(&format!("<g class=\"rung\" data-rung=\"{k}\"")));
    }
    let elements = svg_elements(&svg);
    assert_eq!(elements.len(), 13, "every drawn instruction of latch.dl205");
    let powered = |line: usize| {
        elements
            .iter()
            .find(|(l, ..)| *l == line)
            .unwrap_or_else(|| panic!("line {line}"))
            .2
    };
    assert!(!powered(3), "X0 released: its contact is open");
    assert!(powered(4), "C0 sealed in: its contact conducts");
    assert!(powered(5), "ANDN X1 with X1 off conducts");
    assert!(powered(6), "the C0 coil has power");
    assert!(powered(12), "the Y0 coil has power");
    assert!(
        !powered(9),
        "C1 (the start pulse) has no power after the pulse"
    );
    assert!(
        elements.iter().any(|(l, op, _)| *l == 12 && op == "Y0"),
        "data-operand names the bit"
    );

    // Without --max-ticks: before the first scan nothing is latched.
    let before = dir.join("before.svg");
    let run = servoscope(&["ladder", program, "--svg", before.to_str().expect("utf-8")]);
    assert!(run.status.success());
    let elements = svg_elements(&std::fs::read_to_string(&before).expect("written"));
    assert!(!elements.iter().find(|(l, ..)| *l == 4).expect("C0").2);

    // A force shows in the power flow: C0 forced off opens every C0 contact.
    let forced = dir.join("forced.svg");
    let run = servoscope(&[
        "ladder",
        program,
        "--max-ticks",
        "5",
        "--input",
        "X0=1,3",
        "--force",
        "C0=0@4",
        "--svg",
        forced.to_str().expect("utf-8"),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let elements = svg_elements(&std::fs::read_to_string(&forced).expect("written"));
    let powered = |line: usize| elements.iter().find(|(l, ..)| *l == line).expect("line").2;
    assert!(!powered(4) && !powered(10), "C0 contacts open");
    assert!(!powered(12), "Y0's coil has no power");

    // OpenNet's conveyor with the line stopped (M0 off): the MCS area gets no power, so its
    // coils and boxes have none at their input, and a force is marked on its element.
    let conveyor = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/examples/conveyor.opennet"
    );
    let source = include_str!("../../assets/examples/conveyor.opennet");
    let line = |text: &str| {
        source
            .lines()
            .position(|s| s.starts_with(text))
            .expect(text)
            + 1
    };
    let mc = dir.join("mc.svg");
    let run = servoscope(&[
        "ladder",
        conveyor,
        "--max-ticks",
        "3",
        "--force",
        "Q0=0",
        "--svg",
        mc.to_str().expect("utf-8"),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let svg = std::fs::read_to_string(&mc).expect("written");
    let elements = svg_elements(&svg);
    let at = |l: usize| elements.iter().find(|(x, ..)| *x == l).expect("element").2;
    assert!(at(line("LOD M8125")), "M8125 is on: its contact conducts");
    assert!(!at(line("OUT Q0")), "MC off: the coil has no power");
    assert!(!at(line("TIM T0")), "MC off: the timer has no power");
    assert!(
        at(line("LODN M0")),
        "outside the area: the stopped lamp's contact"
    );
    assert!(svg.contains("MC off"));
    assert!(
        svg.lines()
            .any(|l| l.contains("data-operand=\"Q0\"") && l.contains("data-forced=\"0\"")),
        "the forced coil says so"
    );

    // A dialect without a ladder is told so.
    let qsl = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/examples/homing.qsl");
    let run = servoscope(&[
        "ladder",
        qsl,
        "--svg",
        dir.join("x.svg").to_str().expect("utf-8"),
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("no ladder diagram"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// #44 item 7: a control character in a comment (a terminal colour code) is shown as its
/// control picture, so the SVG stays well-formed XML (it wrote a raw ESC, which no XML reader
/// takes).
#[test]
fn a_control_character_in_a_comment_keeps_the_svg_valid() {
    let program = common::scratch_file("escape.dl205", "STR X0 // \u{1b}[31mred\nOUT Y0\nEND\n");
    let out = common::scratch_file("escape.svg", "");
    let _ = std::fs::remove_file(&out);
    let (program_path, out_path) = (
        program.to_str().expect("utf-8"),
        out.to_str().expect("utf-8"),
    );
    let run = servoscope(&["ladder", program_path, "--svg", out_path]);
    assert!(run.status.success(), "{run:?}");
    let svg = std::fs::read_to_string(&out).expect("written");
    // XML 1.0's characters: no C0 control but tab, line feed and carriage return.
    let bad: Vec<char> = svg
        .chars()
        .filter(|&c| c < ' ' && !matches!(c, '\t' | '\n' | '\r'))
        .collect();
    assert!(bad.is_empty(), "{bad:?}");
    assert!(svg.contains("␛[31mred"), "the comment, its ESC shown as ␛");
    let _ = std::fs::remove_file(out);
    let _ = std::fs::remove_file(program);
}
