//! TML programs as EasyMotion Studio writes them (spec `tml.md` §1.1, §2.2, §5.7, §5.11, §6.1,
//! §7, §9): projects of several files through the assembler, the debugger, sessions and the
//! runner; the drive's table B data; program memory and label addresses; the in-position rule.
//!
//! The example project's golden values (addresses, ticks, registers) were worked out by hand
//! and by an independent model from the spec's rules, not from servoscope's output.

use crate::common::{scratch_dir, write};
use std::path::{Path, PathBuf};

use servoscope_core::debugger::Debugger;
use servoscope_core::machine::project::{Project, SourceFile};
use servoscope_core::machine::tml::assembler::assemble_project;
use servoscope_core::machine::tml::dialect::machine;
use servoscope_core::machine::tml::{Tml, d};
use servoscope_core::machine::{Machine, MachineView, RunState};
use servoscope_core::registry;
use servoscope_core::session::Session;

const EXAMPLE: &str = concat!(
    concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
    "/assets/examples/easymotion_axis"
);

fn tml() -> &'static registry::Dialect {
    registry::by_name("tml").expect("TML is registered")
}

fn project(files: &[(&str, &str)]) -> Project {
    Project {
        files: files
            .iter()
            .map(|(name, text)| SourceFile {
                name: name.to_string(),
                text: text.to_string(),
            })
            .collect(),
    }
}

/// Every diagnostic as `file:line:col: error: message`.
fn errors_of(p: &Project) -> Vec<String> {
    match assemble_project(p) {
        Ok(_) => Vec::new(),
        Err(e) => e.iter().map(|d| p.diagnostic(p.top_name(), d)).collect(),
    }
}

/// Run until the debugger stops on its own (breakpoint, end, fault).
fn run_to_stop(d: &mut Debugger) {
    d.set_speed(servoscope_core::debugger::Speed::Unlimited);
    d.run();
    while d.advance(0.016, std::time::Duration::from_millis(200)) {}
}

fn run(src: &str) -> Tml {
    let mut m = machine(src).unwrap_or_else(|e| panic!("assembles: {e:?}\n{src}"));
    m.run_until(1_000_000, |_| false);
    m
}

fn var(m: &Tml, name: &str) -> i64 {
    let loc = m.find(name).unwrap_or_else(|| panic!("{name}"));
    servoscope_core::machine::value_of(m, loc)
}

// ---- §1.1 files and #include ---------------------------------------------------------------

#[test]
fn an_included_file_is_assembled_at_its_include_line_with_its_own_lines() {
    let p = project(&[
        (
            "motion.tml",
            "int a;\nBEGIN;\n#include \"setup.tml\"\na += 1;\nEND;\n",
        ),
        ("setup.tml", "// setup\na = 5;\n"),
    ]);
    let program = assemble_project(&p).expect("assembles");
    let lines: Vec<usize> = program.stmts.iter().map(|s| s.line).collect();
    assert_eq!(
        lines,
        vec![2, Project::line(1, 2), 4, 5],
        "BEGIN, then setup.tml line 2, then the top file again"
    );
    assert_eq!(p.describe(Project::line(1, 2)), "setup.tml:2");
    let mut m = Tml::new(std::sync::Arc::new(program));
    m.run_until(100, |_| false);
    assert_eq!(var(&m, "a"), 6);
}

#[test]
fn include_paths_backslashes_dots_and_letter_case() {
    // Relative to the including file; `\` as `/`; `..`; a name differing only in case.
    let p = project(&[
        ("motion.tml", "#include \"lib\\\\a.tml\"\n"),
        ("lib/a.tml", "#include \"../COMMON/B.TML\" // from lib\n"),
        ("common/b.tml", "int b; b = 7;\n"),
    ]);
    let program = assemble_project(&p).expect("assembles");
    assert_eq!(program.stmts.len(), 1);
    assert_eq!(program.stmts[0].line, Project::line(2, 1));
    // `#` with blanks around it and any case.
    let p = project(&[("m.tml", "  #  INCLUDE \"x.tml\"\n"), ("x.tml", "NOP;\n")]);
    assert!(assemble_project(&p).is_ok());
}

#[test]
fn include_errors_are_at_the_include_line_and_the_rest_is_still_assembled() {
    let p = project(&[(
        "motion.tml",
        "#include \"missing.tml\"\n#define X 1\n#include missing\n#include \"\"\nBOGUS;\n",
    )]);
    assert_eq!(
        errors_of(&p),
        vec![
            "motion.tml:1:10: error: cannot open included file 'missing.tml'",
            "motion.tml:2:1: error: #define is not supported by servoscope yet (only #include)",
            "motion.tml:3:1: error: malformed #include: write #include \"path\"",
            "motion.tml:4:2: error: empty #include path",
            "motion.tml:5:1: error: unknown instruction 'BOGUS'",
        ]
    );
}

#[test]
fn a_cycle_and_too_deep_a_chain_are_errors_not_endless_assembly() {
    let p = project(&[
        ("a.tml", "#include \"b.tml\"\n"),
        ("b.tml", "NOP;\n#include \"a.tml\"\n"),
    ]);
    assert_eq!(
        errors_of(&p),
        vec!["b.tml:2:10: error: 'a.tml' includes itself (a.tml -> b.tml -> a.tml)"],
        "at the include line that closes the cycle"
    );
    // 17 nested levels below the top file: the 17th include is refused.
    let mut files = vec![("f0.tml".to_string(), "#include \"f1.tml\"\n".to_string())];
    for k in 1..=17 {
        files.push((
            format!("f{k}.tml"),
            format!("#include \"f{}.tml\"\n", k + 1),
        ));
    }
    files.push(("f18.tml".to_string(), "NOP;\n".to_string()));
    let p = Project {
        files: files
            .into_iter()
            .map(|(name, text)| SourceFile { name, text })
            .collect(),
    };
    let errors = errors_of(&p);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with("f16.tml:1:10: error: more than 16 nested #include levels"),
        "{errors:?}"
    );
}

#[test]
fn a_file_included_twice_is_assembled_twice_and_its_errors_reported_once() {
    let p = project(&[
        ("m.tml", "#include \"x.tml\"\n#include \"x.tml\"\n"),
        ("x.tml", "int n;\nhere: NOP;\n"),
    ]);
    assert_eq!(
        errors_of(&p),
        vec![
            "x.tml:1:5: error: duplicate variable 'n'",
            "x.tml:2:1: error: duplicate label 'here' (first at x.tml:2)",
        ]
    );
    let p = project(&[
        ("m.tml", "int n;\n#include \"x.tml\"\n#include \"x.tml\"\n"),
        ("x.tml", "n += 1;\n"),
    ]);
    let program = assemble_project(&p).expect("assembles");
    assert_eq!(program.stmts.len(), 2);
}

#[test]
fn errors_are_sorted_by_file_in_order_of_first_inclusion() {
    let p = project(&[
        ("m.tml", "#include \"b.tml\"\n#include \"a.tml\"\nBAD1;\n"),
        ("b.tml", "BAD2;\n"),
        ("a.tml", "BAD3;\n"),
    ]);
    let errors = errors_of(&p);
    let files: Vec<&str> = errors
        .iter()
        .map(|e| e.split(':').next().unwrap())
        .collect();
    assert_eq!(files, ["m.tml", "b.tml", "a.tml"], "{errors:?}");
}

#[test]
fn declared_before_use_follows_inclusion_order_and_labels_may_come_later() {
    let p = project(&[
        ("m.tml", "#include \"use.tml\"\n#include \"decl.tml\"\n"),
        ("use.tml", "x = 1;\nGOTO later;\n"),
        ("decl.tml", "int x;\nlater: END;\n"),
    ]);
    assert_eq!(
        errors_of(&p),
        vec!["use.tml:1:1: error: undeclared variable 'x'"]
    );
}

#[test]
fn the_loader_reads_included_files_from_disk_with_the_case_fallback() {
    let dir = scratch_dir("load");
    write(
        &dir,
        "motion.tml",
        "#include \"Setup.TML\"\n#include \"lib\\\\x.tml\"\nEND;\n",
    );
    write(&dir, "setup.tml", "int s; s = 3;\n");
    write(&dir, "lib/x.tml", "s += 1;\n");
    let p = tml().load(&dir.join("motion.tml")).expect("loads");
    let names: Vec<&str> = p.files.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["motion.tml", "setup.tml", "lib/x.tml"]);
    let program = assemble_project(&p).expect("assembles");
    assert_eq!(program.stmts.len(), 3);
    // An included file that is not UTF-8 reads with U+FFFD and says where.
    write(&dir, "setup.tml", "int s; s = 3; \u{0}\n");
    std::fs::write(dir.join("setup.tml"), b"int s;\ns = 3;\n\xff\n").expect("write");
    let p = tml().load(&dir.join("motion.tml")).expect("loads");
    assert_eq!(
        errors_of(&p),
        vec!["setup.tml:3:1: error: unexpected character '\\u{fffd}'"]
    );
}

// ---- §2.2 table B ----------------------------------------------------------------------------

#[test]
fn table_b_behaviours_tacc_rtime_and_mcr() {
    // TACC: the change of TSPD in the last tick; accelerating at 0.5 it is 0.5 (raw 32768).
    let m = run(
        "long t; fixed a; CACC = 0.5; CSPD = 10.; CPOS = 1000; MODE PP; UPD; !RT 3; WAIT!; a = TACC; t = RTIME; END;",
    );
    assert_eq!(var(&m, "a"), 32768);
    assert_eq!(var(&m, "t"), 3, "RTIME counts from TIME0 of the last !RT");
    // Before any !RT, RTIME is ATIME (TIME0 = 0).
    let m = run("long t; !MC; WAIT!; WAIT!; t = RTIME; END;");
    assert_eq!(var(&m, "t"), 1);
    // MCR: 0 at first; 0x8701 after MODE PP, +0x2000 with CPA, +0x4000 with TUM1.
    let m = run(
        "int m0; int m1; int m2; m0 = MCR; MODE PP; CPA; TUM1; m1 = MCR; CPR; TUM0; m2 = MCR; END;",
    );
    assert_eq!(var(&m, "m0"), 0);
    assert_eq!(var(&m, "m1") as u16, 0x8701 + 0x2000 + 0x4000);
    assert_eq!(var(&m, "m2") as u16, 0x8701);
    // Storage only: written and read back, nothing else changes.
    let m = run("DoTMLInitializations = 1; VAR_LF = 70000; ExecuteMain = 5; VAR_I3 = -2; END;");
    assert_eq!(var(&m, "DoTMLInitializations"), 1);
    assert_eq!(var(&m, "VAR_LF"), 70000);
    assert_eq!(var(&m, "ExecuteMain"), 5);
    assert_eq!(var(&m, "VAR_I3"), -2);
}

#[test]
fn table_b_read_only_data_unknown_names_and_unmodelled_ones() {
    let errs = |src: &str| match machine(src) {
        Ok(_) => Vec::new(),
        Err(e) => e.iter().map(ToString::to_string).collect::<Vec<_>>(),
    };
    assert_eq!(errs("TACC = 1;"), ["1:1: error: TACC is read-only"]);
    assert_eq!(errs("MCR = 1;"), ["1:1: error: MCR is read-only"]);
    assert_eq!(errs("RTIME = 1;"), ["1:1: error: RTIME is read-only"]);
    assert_eq!(
        errs("POSOKLM = 1;"),
        ["1:1: error: undeclared variable 'POSOKLM' (did you mean 'POSOKLIM'?)"]
    );
    assert_eq!(
        errs("int posoklim;"),
        ["1:5: error: 'posoklim' is a TML name and cannot be a variable"]
    );
    assert_eq!(
        errs("CDEC = 1.;"),
        ["1:1: error: 'CDEC' (fixed, 0x0858) is a TML datum that servoscope does not model yet"]
    );
}

// ---- §6.1 motion complete and the in-position rule -------------------------------------------

/// The tick in which the statement after `WAIT!` starts (the WAIT! completes then).
fn wait_completes(src: &str) -> u64 {
    let m = run(&format!("long t; {src} t = ATIME; END;"));
    var(&m, "t") as u64
}

#[test]
fn the_spec_example_of_the_in_position_rule() {
    assert_eq!(
        wait_completes("CACC = 1; CSPD = 1; CPOS = 3; MODE PP; UPD; !MC; WAIT!;"),
        4,
        "bit 11 clear: motion complete follows the reference, which ends in tick 3"
    );
    assert_eq!(
        wait_completes(
            "SRB UPGRADE, 0xFFFF, 0x0800; POSOKLIM = 0; TONPOSOK = 50; CACC = 1; CSPD = 1; CPOS = 3; MODE PP; UPD; !MC; WAIT!;"
        ),
        53,
        "n reaches 50 in tick 52"
    );
    // TONPOSOK 0 counts as 1: n = 1 at the end of tick 3, where the profile ends (APOS is
    // on TPOS); a band that APOS never enters keeps motion incomplete.
    assert_eq!(
        wait_completes(
            "SRB UPGRADE, 0xFFFF, 0x0800; TONPOSOK = 0; CACC = 1; CSPD = 1; CPOS = 3; MODE PP; UPD; !MC; WAIT!;"
        ),
        4
    );
    // A move whose APOS still lags when the reference stops (worked by hand from §6): speeds
    // 4, 4, 0 put TPOS at 4, 8, 8 and APOS at 2, 5, 7, 8 in ticks 0..3.
    let mv = "CACC = 4; CSPD = 4; CPOS = 8; MODE PP; UPD; !MC; WAIT!;";
    assert_eq!(wait_completes(mv), 3, "the reference ends in tick 2");
    assert_eq!(
        wait_completes(&format!(
            "SRB UPGRADE, 0xFFFF, 0x0800; POSOKLIM = 0; TONPOSOK = 1; {mv}"
        )),
        4,
        "APOS reaches 8 in tick 3"
    );
    assert_eq!(
        wait_completes(&format!(
            "SRB UPGRADE, 0xFFFF, 0x0800; POSOKLIM = 1; TONPOSOK = 1; {mv}"
        )),
        3,
        "|8 − 7| ≤ 1 in tick 2"
    );
}

// ---- §5.11 program memory and label addresses ------------------------------------------------

#[test]
fn the_spec_example_puts_the_labels_where_the_vendors_linker_map_has_them() {
    let src = "BEGIN;
ExecuteMain = MainStartAddress;
ExecuteAutotuning = ContinueWithEndinit;
GOTO ContinueWithEndinit, DoTMLInitializations, EQ;
RET;
ContinueWithEndinit: SRB UPGRADE, 0xFFFF, 0x8000;
ENDINIT;
wait_VDC: GOTO wait_VDC, FLAGUV, NEQ;
AXISON;
MainStartAddress:
";
    let m = machine(src).expect("assembles");
    let address = |name: &str| {
        let (_, index) = m
            .program
            .labels
            .iter()
            .find(|(n, _)| n == name)
            .expect(name);
        m.program.address_of(*index as usize)
    };
    assert_eq!(address("ContinueWithEndinit"), 0x4009);
    assert_eq!(address("wait_VDC"), 0x400D);
    assert_eq!(
        address("MainStartAddress"),
        0x4011,
        "a last label is the end address"
    );
    assert_eq!(m.program.end_address, 0x4011);
    let m = run(src);
    assert_eq!(var(&m, "ExecuteMain"), 0x4011);
    assert_eq!(var(&m, "ExecuteAutotuning"), 0x4009);
}

#[test]
fn every_row_of_the_word_table() {
    let rows: &[(&str, u32)] = &[
        (
            "BEGIN; END; ENDINIT; NOP; RET; UPD; STOP; AXISON; AXISOFF; WAIT!; !MC; PROD << 2; SAP l;",
            13,
        ),
        (
            "i = 5; i = here; i = j; i = -j; i += 3; i -= 3; l += m; i <<= 2; l >>= 1; GOTO here; CALL here; !IN#3 1;",
            24,
        ),
        (
            "l = 70000; f = 1.5; l += 5; f -= 0.5; i = j << 2; l = m >> 1; i * j; l /= i; SRB i, 1, 2; CPR; CPA; TUM0; TUM1; MODE PP; GOTO here, i, EQ; CALL here, l, GT; SAP 5; WAIT! 10; !RT l;",
            57,
        ),
        ("SRBL i, 1, 2; !RT 100;", 8),
    ];
    for (statements, words) in rows {
        let src = format!("int i; int j; long l; long m; fixed f;\nhere: {statements}\n");
        let m = machine(&src).unwrap_or_else(|e| panic!("{e:?}"));
        assert_eq!(m.program.end_address - 0x4000, *words, "{statements}");
    }
}

#[test]
fn jumps_to_numbers_and_through_variables() {
    // 0x4000 GOTO (2 words), 0x4002 i = 9 (2 words), 0x4004 END: a jump to 0x4004 skips the
    // assignment.
    let m = run("int i; GOTO 0x4004; i = 9; END;");
    assert_eq!(var(&m, "i"), 0);
    assert_eq!(
        machine("GOTO 0x4001; NOP; NOP;")
            .err()
            .map(|e| e[0].to_string()),
        Some("1:6: error: no statement starts at 0x4001".to_string())
    );
    assert_eq!(
        machine("GOTO 5L;").err().map(|e| e[0].message.clone()),
        Some("misplaced suffix 'L': this number takes no suffix".to_string())
    );
    // Through a variable: the address it holds, read unsigned.
    let m = run("int p; int i; p = there; GOTO p; i = 1;\nthere: i += 10; END;");
    assert_eq!(var(&m, "i"), 10);
    // The end address ends the program after the jump.
    let m = run("int p; int i; p = last; GOTO p; i = 1;\nlast:");
    assert_eq!(m.run_state(), RunState::Ended);
    assert_eq!(var(&m, "i"), 0);
    // A label's address needs 16-bit data, and a label is no other operand.
    let errs = machine("long l; l = here;\nhere: NOP;").expect_err("errors");
    assert!(
        errs[0].message.contains("a label's address is 16-bit"),
        "{errs:?}"
    );
    let errs = machine("int i; i += here;\nhere: NOP;").expect_err("errors");
    assert!(errs[0].message.contains("'here' is a label"), "{errs:?}");
    let errs = machine("long l; GOTO l;").expect_err("errors");
    assert!(errs[0].message.contains("16-bit datum"), "{errs:?}");
}

#[test]
fn a_jump_through_a_variable_to_no_statement_faults_with_bad_address() {
    let m = run("int p; int i; p = 0x4001; i = 4; CALL p; i = 5;");
    assert_eq!(m.run_state(), RunState::Faulted);
    let fault = m.fault().expect("a fault");
    assert_eq!(fault.kind, "bad_address");
    assert_eq!(fault.line, 1);
    assert!(fault.message.contains("0x4001"), "{}", fault.message);
    assert!(m.stack.is_empty(), "CALL pushed nothing");
    assert_eq!(var(&m, "i"), 4, "nothing after the fault ran");
    assert_eq!(m.data[d::MER as usize], 0, "no error bits: decided");
    // Not taken: no fault.
    let m = run("int p; int i; p = 1; CALL p, i, NEQ; END;");
    assert_eq!(m.run_state(), RunState::Ended);
    // The address is checked before the stack: a full stack still faults bad_address.
    let calls = "CALL f;\n".repeat(11);
    let m = run(&format!("int p; p = 3;\n{calls}END;\nf: CALL p;\n"));
    assert_eq!(m.fault().map(|f| f.kind), Some("bad_address"));
}

// ---- the example project through the runner, the debugger, sessions and the window -----------

fn example_top() -> PathBuf {
    Path::new(EXAMPLE).join("motion.tml")
}

#[test]
fn stepping_and_breakpoints_go_into_the_included_files() {
    let project = tml().load(&example_top()).expect("loads");
    let main = project.index_of("main.tml").expect("main.tml");
    let mut d = Debugger::with_project(tml(), project);
    assert!(!d.has_errors(), "{:?}", d.diagnostics());
    // motion.tml:4 BEGIN, then setup_interrupts.tml:4.
    assert_eq!(d.machine().pc_line(), Some(4));
    d.step_command();
    while d.advance(0.016, std::time::Duration::from_millis(200)) {}
    assert_eq!(
        d.describe_line(d.machine().pc_line().unwrap()),
        "setup_interrupts.tml:4"
    );
    // A breakpoint on main.tml:15 (CACC = 0.5;) stops the run there, after the homing.
    let line = Project::line(main, 15);
    assert!(d.toggle_breakpoint(line));
    run_to_stop(&mut d);
    assert_eq!(d.machine().pc_line(), Some(line));
    assert_eq!(
        d.machine().ticks(),
        2031,
        "the homing's WAIT! completes in tick 2031"
    );
    // Edits in an included file move its own breakpoints only.
    let text = d.project().files[main].text.clone();
    *d.file_text_mut(main) = format!("// a new first line\n{text}");
    assert!(d.assemble());
    assert_eq!(
        d.breakpoint_list()[0].line_number(),
        Some(Project::line(main, 16))
    );
}

#[test]
fn a_session_of_a_project_keeps_every_file_and_breakpoints_by_file() {
    let project = tml().load(&example_top()).expect("loads");
    let main = project.index_of("main.tml").expect("main.tml");
    let mut d = Debugger::with_project(tml(), project.clone());
    d.toggle_breakpoint(Project::line(main, 15));
    d.toggle_breakpoint(4);
    run_to_stop(&mut d);
    let at = d.pos();
    let session = Session::capture(&d, Some(example_top()), Default::default());
    let text = session.to_ron().expect("encodes");
    assert!(text.contains("format: 3"), "several files: format 3");
    assert!(
        text.contains("(\"main.tml\", 15)"),
        "breakpoints by file and line: {text}"
    );
    let back = Session::from_ron(&text, "p.ron").expect("reads");
    assert_eq!(back.project(), project, "every file's text and name");
    let restored = back.restore("p.ron").expect("restores");
    assert_eq!(restored.pos(), at);
    assert_eq!(restored.machine().pc_line(), Some(Project::line(main, 15)));
    let mut lines: Vec<usize> = restored
        .breakpoint_list()
        .iter()
        .filter_map(|b| b.line_number())
        .collect();
    lines.sort_unstable();
    assert_eq!(lines, [4, Project::line(main, 15)]);
    assert!(
        back.changed_on_disk(&Default::default()).is_empty(),
        "the files on disk are the same"
    );
    // A file changed on disk: said, and the session's copy is used.
    let dir = scratch_dir("changed");
    for f in &project.files {
        write(&dir, &f.name, &f.text);
    }
    write(&dir, "main.tml", "// changed\n");
    let mut moved = back.clone();
    moved.program_path = Some(dir.join("motion.tml"));
    assert_eq!(moved.changed_on_disk(&Default::default()), ["main.tml"]);
    assert_eq!(moved.restore("p.ron").expect("restores").pos(), at);
    // One file: still format 2, which older builds read.
    let single = Debugger::with_dialect(tml(), "a.tml", "int a; a = 1; END;");
    let text = Session::capture(&single, None, Default::default())
        .to_ron()
        .expect("encodes");
    assert!(
        text.contains("format: 2") && !text.contains("files"),
        "{text}"
    );
}

#[test]
fn an_older_tml_session_still_opens() {
    let text = "(format: 2, dialect: \"tml\", program_name: \"a.tml\", program: \"int a;\\na += 1;\\nEND;\\n\", breakpoints: [2], at: (tick: 0, step: 1))";
    let s = Session::from_ron(text, "old.ron").expect("reads");
    let d = s.restore("old.ron").expect("restores");
    assert_eq!(
        d.machine().pc_line(),
        Some(3),
        "one statement run: END is next"
    );
    assert_eq!(d.breakpoints(), [2].into());
}

#[test]
fn an_included_file_from_another_editor_reads_the_same() {
    // A byte-order mark and CR LF line ends change nothing, positions included.
    let p = project(&[
        ("m.tml", "int a;\r\n#include \"w.tml\"\r\nEND;\r\n"),
        ("w.tml", "\u{feff}// from Windows\r\na = 3;\r\nBAD;\r\n"),
    ]);
    assert_eq!(
        errors_of(&p),
        ["w.tml:3:1: error: unknown instruction 'BAD'"]
    );
}

#[test]
fn tables_a_and_b_have_the_specs_types_addresses_and_access() {
    use servoscope_core::machine::tml::{PREDEFINED, Ty};
    // Spec §2.1 and §2.2, row by row.
    let spec: &[(&str, Ty, u16, bool, bool)] = &[
        ("CPOS", Ty::Long, 0x029E, true, false),
        ("CSPD", Ty::Fixed, 0x02A0, true, false),
        ("CACC", Ty::Fixed, 0x02A2, true, false),
        ("TPOS", Ty::Long, 0x02B2, false, false),
        ("TSPD", Ty::Fixed, 0x02B4, false, false),
        ("APOS", Ty::Long, 0x0228, false, false),
        ("ASPD", Ty::Fixed, 0x022C, false, false),
        ("POSERR", Ty::Int, 0x022A, false, false),
        ("ATIME", Ty::Long, 0x02C0, false, false),
        ("SRL", Ty::Uint, 0x090E, false, false),
        ("SRH", Ty::Uint, 0x090F, false, false),
        ("MER", Ty::Uint, 0x08FC, false, false),
        ("DER", Ty::Uint, 0x03AD, false, false),
        ("UPGRADE", Ty::Int, 0x0857, true, false),
        ("FLAGUV", Ty::Int, 0x02FB, false, false),
        ("PROD", Ty::Long, 0x030E, false, false),
        ("PRODH", Ty::Long, 0x030F, false, false),
        ("TACC", Ty::Fixed, 0x02B6, false, true),
        ("RTIME", Ty::Long, 0x02C2, false, true),
        ("MCR", Ty::Uint, 0x0309, false, true),
        ("POSOKLIM", Ty::Uint, 0x036A, true, true),
        ("TONPOSOK", Ty::Uint, 0x036B, true, true),
        ("VAR_I1", Ty::Int, 0x0366, true, true),
        ("VAR_I2", Ty::Int, 0x0367, true, true),
        ("VAR_I3", Ty::Int, 0x0979, true, true),
        ("VAR_LF", Ty::Long, 0x0368, true, true),
        ("DoTMLInitializations", Ty::Int, 0x09C0, true, true),
        ("ExecuteMain", Ty::Uint, 0x09BF, true, true),
        ("ExecuteAutotuning", Ty::Uint, 0x0998, true, true),
        ("HOMINGTABLE_POINTER", Ty::Uint, 0x09C1, true, true),
        ("FUNCTIONTABLE_POINTER", Ty::Uint, 0x09C9, true, true),
    ];
    assert_eq!(PREDEFINED.len(), spec.len());
    for (p, &(name, ty, address, writable, table_b)) in PREDEFINED.iter().zip(spec) {
        assert_eq!(
            (p.name, p.ty, p.address, p.writable, p.table_b),
            (name, ty, address, writable, table_b)
        );
    }
    // All start at 0 but SRL (0x8400: axis on, motion complete).
    let m = machine("").expect("empty");
    for (i, p) in PREDEFINED.iter().enumerate() {
        let raw = m.raw(servoscope_core::machine::tml::program::Data::Pre(i as u8));
        assert_eq!(raw, if p.name == "SRL" { 0x8400 } else { 0 }, "{}", p.name);
    }
    // User variables from 0x03B0: an int one word, a long or fixed two at an even address.
    let m = machine("int a; long b; int c; fixed d; int e;").expect("declares");
    assert_eq!(
        m.program.var_addresses(),
        [0x03B0, 0x03B2, 0x03B4, 0x03B6, 0x03B8]
    );
}

#[test]
fn an_include_bomb_stops_at_the_include_that_crosses_the_bound() {
    // 16 small files, each including the next four times: 4^15 copies of the last one.
    let dir = scratch_dir("bomb");
    for k in 0..16 {
        let text = if k == 15 {
            "int a;\na = 1;\n".to_string()
        } else {
            format!("#include \"f{}.tml\"\n", k + 1).repeat(4)
        };
        write(&dir, &format!("f{k}.tml"), &text);
    }
    write(&dir, "top.tml", "#include \"f0.tml\"\nEND;\n");
    let top = dir.join("top.tml");
    let errors = crate::common::within(120, move || {
        let project = tml().load(&top).expect("reads");
        assert_eq!(project.files.len(), 17, "each file read once");
        match assemble_project(&project) {
            Ok(_) => panic!("assembled 4^15 copies"),
            Err(errors) => (project, errors),
        }
    });
    let (project, errors) = errors;
    let grows: Vec<_> = errors
        .iter()
        .filter(|d| d.message.contains("grows past"))
        .collect();
    assert_eq!(grows.len(), 1, "{errors:?}");
    // At an `#include` line: the innermost one whose expansion crossed the bound.
    let (file, line) = Project::split(grows[0].line);
    let text = &project.files[file].text;
    let at = text.lines().nth(line - 1).expect("the line");
    assert!(at.starts_with("#include"), "{at}");
    assert!(
        grows[0].message.contains("1048575 lines"),
        "{}",
        grows[0].message
    );
    assert!(errors.len() < 100, "{} diagnostics", errors.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn includes_outside_the_programs_folder_are_not_read_and_never_quoted() {
    let root = scratch_dir("outside");
    write(&root, "secret.txt", "hunter2 is the password\n");
    write(&root, "common/shared.tml", "int shared;\n");
    let dir = root.join("student");
    write(&dir, "lib/ok.tml", "int a;\n");
    let secret = root.join("secret.txt");
    let absolute = secret.display().to_string();
    write(
        &dir,
        "top.tml",
        &format!(
            "#include \"lib/ok.tml\"\n#include \"../secret.txt\"\n#include \"{absolute}\"\n#include \"../common/shared.tml\"\nEND;\n"
        ),
    );
    #[cfg(unix)]
    std::os::unix::fs::symlink(&secret, dir.join("lib/link.tml")).expect("a link");
    #[cfg(unix)]
    write(&dir, "linked.tml", "#include \"lib/link.tml\"\nEND;\n");

    let project = tml().load(&dir.join("top.tml")).expect("reads");
    let names: Vec<&str> = project.files.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(
        names,
        ["top.tml", "lib/ok.tml"],
        "only the folder's own files"
    );
    let errors = assemble_project(&project).expect_err("three includes refused");
    let text: Vec<String> = errors.iter().map(|d| d.message.clone()).collect();
    assert_eq!(
        text.iter()
            .filter(|m| m.contains("outside the program's folder"))
            .count(),
        3,
        "{text:?}"
    );
    assert!(text.iter().all(|m| !m.contains("hunter2")), "{text:?}");
    #[cfg(unix)]
    {
        // A link in the folder to a file outside it is outside.
        let linked = tml().load(&dir.join("linked.tml")).expect("reads");
        assert_eq!(linked.files.len(), 1);
        let errors = assemble_project(&linked).expect_err("refused");
        assert!(errors.iter().all(|d| !d.message.contains("hunter2")));
    }
    // A folder the user allows is read.
    let allowed = servoscope_core::machine::project::IncludeFolders {
        allowed: vec![root.join("common")],
    };
    let project = tml()
        .load_with(&dir.join("top.tml"), &allowed)
        .expect("reads");
    assert!(
        project
            .files
            .iter()
            .any(|f| f.name == "../common/shared.tml")
    );
    assert!(!project.files.iter().any(|f| f.text.contains("hunter2")));
    let _ = std::fs::remove_dir_all(&root);
}
