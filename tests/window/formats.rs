//! Issue #22 items 1–4: a value is typed, shown, watched and plotted in the format the user
//! reads it in, each format means the same in every view, and formats belong to their dialect.

use servoscope_core::debugger::Debugger;
use servoscope_core::machine::value::{Format, parse_in};
use servoscope_core::registry;
use servoscope_core::session::ViewSettings;

fn dl205() -> &'static registry::Dialect {
    registry::by_name("dl205").expect("registered")
}

#[test]
fn plain_digits_are_read_in_the_fields_format_and_written_forms_as_written() {
    let read = |text: &str, width, format| parse_in(text, width, format).map(|(v, _)| v);
    // The case: 1234 typed where BCD is shown is BCD 1234, not 0x04D2.
    assert_eq!(read("1234", 16, Format::Bcd), Ok(0x1234));
    assert_eq!(read("1A", 16, Format::Hex), Ok(0x1A));
    assert_eq!(read("0101 1111", 16, Format::Binary), Ok(0b0101_1111));
    assert_eq!(read("17", 16, Format::Octal), Ok(0o17));
    assert_eq!(read("1.5", 32, Format::Q16), Ok(98304));
    assert_eq!(read("-1", 16, Format::Signed), Ok(0xFFFF));
    assert_eq!(read("1234", 16, Format::Unsigned), Ok(1234));
    // Explicit forms win over the field's format.
    assert_eq!(read("0x10", 16, Format::Bcd), Ok(0x10));
    assert_eq!(read("bcd(99)", 16, Format::Signed), Ok(0x99));
    assert_eq!(read("q16(0.5)", 32, Format::Bcd), Ok(32768));
    assert_eq!(read("-0x1", 16, Format::Bcd), Ok(0xFFFF));
    // What the field shows reads back to the same bits in every format.
    for format in Format::ALL {
        for raw in [0u64, 1, 0x1234, 0x9999, 0x7FFF, 0x8000, 0xFFFF] {
            if format == Format::Bcd && !servoscope_core::machine::value::is_bcd(raw) {
                continue;
            }
            let text = format.show(raw, 16);
            let text = if format == Format::Q16 {
                servoscope_core::machine::value::q16_exact(raw as u16 as i16 as i64)
            } else {
                text
            };
            assert_eq!(
                read(&text, 16, format),
                Ok(raw),
                "{text} in {}",
                format.name()
            );
        }
    }
    // Digits the format has no room for are refused, naming the format.
    let e = parse_in("12A4", 16, Format::Bcd).unwrap_err().to_string();
    assert_eq!(e, "'12A4' is not a number in BCD");
    let e = parse_in("G", 16, Format::Hex).unwrap_err().to_string();
    assert!(e.contains("'G'") && e.contains("hex"), "{e}");
    let e = parse_in("70000", 16, Format::Signed)
        .unwrap_err()
        .to_string();
    assert!(e.contains("70000") && e.contains("16 bits"), "{e}");
    // The reading is said.
    let (_, reading) = parse_in("1234", 16, Format::Bcd).unwrap();
    assert_eq!(reading.describe(), "read as BCD (the field's format)");
    let (_, reading) = parse_in("0x12", 16, Format::Bcd).unwrap();
    assert_eq!(reading.describe(), "read as hex (written 0x…)");
}

#[test]
fn each_dialect_reads_its_words_its_own_way() {
    let d = Debugger::with_dialect(dl205(), "v.dl205", "STR SP1\nLD V2000\nOUT V2001\nEND\n");
    let m = d.machine();
    for name in ["V2000", "ACC", "L1"] {
        let info = m.info(m.find(name).unwrap()).unwrap();
        assert_eq!(info.reading(), Format::Bcd, "{name}");
    }
    let opennet = registry::by_name("opennet").expect("registered");
    let d = Debugger::with_dialect(
        opennet,
        "t.opennet",
        "LOD M8120\nMOV(W) 100 D0 REP 1\nMOV(I) -5 D1 REP 1\nMOV(L) -5 D2 REP 1\nEND\n",
    );
    assert!(d.diagnostics().is_empty(), "{:?}", d.diagnostics());
    let m = d.machine();
    let reading = |name: &str| m.info(m.find(name).unwrap()).unwrap().reading();
    assert_eq!(reading("D0"), Format::Unsigned, "W: unsigned (spec §2)");
    assert_eq!(reading("D1"), Format::Signed, "I: signed");
    assert_eq!(
        reading("D2"),
        Format::Signed,
        "L: its upper word carries the sign"
    );
    assert_eq!(
        reading("D3"),
        Format::Unsigned,
        "L: its lower word is plain bits"
    );
    let tml = registry::by_name("tml").expect("registered");
    let d = Debugger::with_dialect(
        tml,
        "f.tml",
        "fixed speed;\nint n;\nspeed = 1.5;\nn = 3;\nEND;\n",
    );
    assert!(d.diagnostics().is_empty(), "{:?}", d.diagnostics());
    let m = d.machine();
    assert_eq!(
        m.info(m.find("speed").unwrap()).unwrap().reading(),
        Format::Q16
    );
    assert_eq!(
        m.info(m.find("n").unwrap()).unwrap().reading(),
        Format::Signed
    );
}

/// Item 4: a BCD word is plotted, read and exported as the number its digits say.
#[test]
fn a_bcd_channel_is_plotted_and_exported_decoded() {
    let mut d = Debugger::with_dialect(
        dl205(),
        "acc.dl205",
        "STR SP1\nLDD K00222970\nOUTD V2000\nEND\n",
    );
    d.step_tick();
    d.step_tick();
    let acc = d
        .channels()
        .iter()
        .find(|c| c.name == "ACC")
        .expect("ACC is plotted");
    assert_eq!(acc.reading, Format::Bcd);
    assert_eq!(acc.plotted(0x0022_2970), 222970.0);
    assert_eq!(acc.value_text(0x0022_2970), "222970");
    assert_eq!(acc.titled(), "ACC (BCD)");
    let path = std::env::temp_dir().join(format!("servoscope-bcd-{}.csv", std::process::id()));
    d.export_trace_csv(&path).expect("export");
    let csv = std::fs::read_to_string(&path).expect("read back");
    let _ = std::fs::remove_file(&path);
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("tick,time_ms,ACC (BCD)"));
    assert!(
        csv.lines().any(|l| l.ends_with(",222970")),
        "the decoded count, not 2238832: {csv}"
    );
    assert!(!csv.contains("2238832"));
}

#[test]
fn session_view_formats_keep_their_meaning_across_versions() {
    // Before `every_location_as`, `Signed` meant each location in its own reading.
    let old = ViewSettings {
        register_format: Format::Signed,
        every_location_as: None,
        ..ViewSettings::default()
    };
    assert_eq!(old.column(), None);
    let old_q16 = ViewSettings {
        register_format: Format::Q16,
        every_location_as: None,
        ..ViewSettings::default()
    };
    assert_eq!(old_q16.column(), Some(Format::Q16));
    for column in [None, Some(Format::Signed), Some(Format::Bcd)] {
        let saved = ViewSettings::default().with_column(column);
        let text = ron::to_string(&saved).expect("serialise");
        let back: ViewSettings = ron::from_str(&text).expect("read back");
        assert_eq!(back.column(), column, "{text}");
    }
}

mod window {
    use egui::{Key, Modifiers};
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;
    use servoscope::ui::{Prefs, ServoscopeApp};
    use servoscope_core::machine::value::Format;
    use servoscope_core::registry;

    fn harness(app: ServoscopeApp) -> Harness<'static, ServoscopeApp> {
        let mut h = Harness::builder()
            .with_size(egui::vec2(1400.0, 900.0))
            .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
        h.run_steps(2);
        h
    }

    fn app_in(dialect: &str, name: &str, text: &str) -> ServoscopeApp {
        let mut app = ServoscopeApp::new(Prefs::default());
        app.load_program_as(registry::by_name(dialect).expect("registered"), name, text);
        app
    }

    fn read(h: &Harness<'static, ServoscopeApp>, name: &str) -> u64 {
        let m = h.state().debugger.machine();
        m.read(m.find(name).unwrap())
    }

    fn type_into(h: &mut Harness<'static, ServoscopeApp>, label: &str, text: &str) {
        h.get_by_label(label).focus();
        h.step();
        h.key_press_modifiers(Modifiers::COMMAND, Key::A);
        h.get_by_label(label).type_text(text);
        h.run_steps(2);
    }

    /// Item 1: 1234 typed into a DL205 word shown in BCD stores BCD 1234, and the field says
    /// which reading it used before Set.
    #[test]
    fn a_value_typed_where_bcd_is_shown_is_stored_as_bcd() {
        let mut h = harness(app_in(
            "dl205",
            "v.dl205",
            "STR SP1\nLD V2000\nOUT V2001\nEND\n",
        ));
        h.get_by_label("V2000").click();
        h.run_steps(2);
        h.get_by_label("in BCD");
        type_into(&mut h, "Value of V2000", "1234");
        h.get_by_label("Set stores 0x1234: read as BCD (the field's format)");
        h.get_by_label("Set").click();
        h.run_steps(2);
        assert_eq!(read(&h, "V2000"), 0x1234, "not 0x04D2");
        assert!(h.query_by_label("4D2 (not BCD)").is_none());
        // A written form is read as written, and says so.
        type_into(&mut h, "Value of V2000", "0x42");
        h.get_by_label("Set stores 0x0042: read as hex (written 0x…)");
        h.key_press(Key::Enter);
        h.get_by_label("Set").click();
        h.run_steps(2);
        assert_eq!(read(&h, "V2000"), 0x42);
    }

    /// Item 2: "signed" means signed decimal for a DL205 word, in the table and in a watch.
    #[test]
    fn signed_means_signed_in_the_table_and_in_a_watch() {
        let mut h = harness(app_in(
            "dl205",
            "v.dl205",
            "STR SP1\nLD V2000\nOUT V2001\nEND\n",
        ));
        h.state_mut().debugger.set_text("V2000", "0x8001").unwrap();
        h.run_steps(2);
        assert_eq!(read(&h, "V2000"), 0x8001);
        h.get_by_label("8001");
        h.get_by_label("Format").click();
        h.run_steps(2);
        h.get_by_label("signed").click();
        h.run_steps(2);
        assert_eq!(h.state().registers.column(), Some(Format::Signed));
        h.get_by_label("-32767");
        assert!(
            h.query_by_label("0x8001").is_some(),
            "the Hex column stays hex"
        );
        // A watch of the same word: starts in its own reading (BCD), signed means the same.
        h.state_mut().apply(
            &egui::Context::default(),
            servoscope::ui::Command::AddWatch("V2000".into()),
        );
        h.run_steps(2);
        assert_eq!(h.state().debugger.watches()[0].format, Format::Bcd);
        h.get_by_label("Value of watch 1: 8001");
        let mut w = h.state().debugger.watches()[0].clone();
        w.format = Format::Signed;
        h.state_mut().debugger.update_watch(0, w);
        h.run_steps(2);
        h.get_by_label("Value of watch 1: -32767");
    }

    /// Item 3: BCD chosen in a DL205 program does not follow into OpenNet; each dialect keeps
    /// its own choice, and the fixed-point lesson shows integers as integers.
    #[test]
    fn a_format_chosen_in_one_dialect_stays_with_it() {
        let mut h = harness(app_in(
            "dl205",
            "v.dl205",
            "STR SP1\nLD V2000\nOUT V2001\nEND\n",
        ));
        h.get_by_label("Format").click();
        h.run_steps(2);
        // The popup's entry (the stack panel has a "BCD" heading too).
        h.get_all_by_label("BCD")
            .last()
            .expect("the BCD entry")
            .click();
        h.run_steps(2);
        assert_eq!(h.state().registers.column(), Some(Format::Bcd));
        let opennet = registry::by_name("opennet").unwrap();
        h.state_mut().load_program_as(
            opennet,
            "mov.opennet",
            "LOD M8120\nMOV(W) 100 D0 REP 1\nMOV(I) -5 D1 REP 1\nEND\n",
        );
        h.run_steps(2);
        h.state_mut().debugger.step_tick();
        h.run_steps(3);
        assert_eq!(read(&h, "D0"), 100);
        assert_eq!(
            h.state().registers.column(),
            None,
            "OpenNet has no choice of its own"
        );
        assert!(h.query_all_by_label("100").count() > 0);
        assert!(h.query_by_label("64").is_none(), "100 is not read as BCD");
        let app = h.state();
        let m = app.debugger.machine();
        let d1 = m.find("D1").unwrap();
        assert_eq!(
            app.registers.format_of(d1, &m.info(d1).unwrap()),
            Format::Signed
        );
        assert!(
            h.query_all_by_label("-5").count() > 0,
            "D1 (type I) reads signed"
        );
        // Back in DL205, its choice is still there.
        h.state_mut()
            .load_program_as(registry::by_name("dl205").unwrap(), "b.dl205", "END\n");
        h.run_steps(2);
        assert_eq!(h.state().registers.column(), Some(Format::Bcd));
        assert_eq!(
            h.state().prefs.register_formats.get("dl205"),
            Some(&Format::Bcd),
            "kept between runs, per dialect"
        );
    }

    #[test]
    fn the_fixed_point_lesson_shows_integers_as_integers() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/sessions/fixed_point_walkthrough.ron"
        );
        let mut app = ServoscopeApp::new(Prefs::default());
        app.open_path(path.into());
        let mut h = harness(app);
        for _ in 0..50 {
            h.run_steps(1);
            if h.state().loading.is_none() {
                break;
            }
        }
        h.state_mut().debugger.goto_tick(2);
        h.run_steps(3);
        let app = h.state();
        assert_eq!(app.registers.column(), None);
        let m = app.debugger.machine();
        let counts = m.find("R20").unwrap();
        assert_eq!(m.read(counts), 40000);
        assert_eq!(
            app.registers.format_of(counts, &m.info(counts).unwrap()),
            Format::Signed
        );
        h.get_by_label("40000");
        assert!(h.query_by_label("0.610352").is_none());
    }
}
