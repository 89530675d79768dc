//! A TML project of several files in the window (spec `tml.md` §10): one tab per file, the top
//! file first; the tab of the statement about to run comes forward; breakpoints belong to a
//! file and a line; the Drive data and Labels panels.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use servoscope::ui::{Command, Prefs, ServoscopeApp};
use servoscope_core::debugger::Action;
use servoscope_core::machine::project::Project;

const TOP: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/examples/easymotion_axis/motion.tml"
);

fn harness(app: ServoscopeApp) -> Harness<'static, ServoscopeApp> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(2);
    h
}

fn apply(h: &mut Harness<'static, ServoscopeApp>, command: Command) {
    let ctx = h.ctx.clone();
    h.state_mut().apply(&ctx, command);
    h.run_steps(3);
}

/// A folder holding `motion.tml` (`int a;`, the include of `part.tml`, `END;`) and `part.tml`.
fn two_file_project(name: &str, part: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("servoscope-gui-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(
        dir.join("motion.tml"),
        "int a;\n#include \"part.tml\"\nEND;\n",
    )
    .expect("w");
    std::fs::write(dir.join("part.tml"), part).expect("w");
    dir
}

fn project_app() -> ServoscopeApp {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(TOP.into());
    assert!(app.notice.is_none(), "{:?}", app.notice);
    app
}

#[test]
fn the_top_file_opens_the_whole_project_one_tab_per_file() {
    let mut h = harness(project_app());
    let names = [
        "motion.tml",
        "setup_interrupts.tml",
        "setup_settings.tml",
        "main.tml",
        "homingmodes.tml",
        "functions.tml",
    ];
    for name in names {
        h.get_by_label(&format!("File {name}"));
    }
    assert_eq!(h.state().code.file, 0, "the top file is shown first");
    assert!(!h.state().debugger.has_errors());
    // The first step runs BEGIN; the next statement is in setup_interrupts.tml: its tab comes
    // forward.
    apply(&mut h, Command::Debug(Action::StepCommand));
    assert_eq!(h.state().code.file, 1);
    // The user looks at another file: it stays while nothing runs; the next step brings the
    // statement about to run back into view.
    h.get_by_label("File functions.tml").click();
    h.run_steps(2);
    assert_eq!(h.state().code.file, 5);
    h.run_steps(3);
    assert_eq!(h.state().code.file, 5, "nothing ran: the chosen tab stays");
    apply(&mut h, Command::Debug(Action::StepCommand));
    assert_eq!(
        h.state().code.file,
        1,
        "a step shows setup_interrupts.tml:5 again"
    );
    apply(&mut h, Command::Debug(Action::StepCommand));
    assert_eq!(
        h.state().code.file,
        2,
        "entering setup_settings.tml brings it forward"
    );
}

#[test]
fn a_breakpoint_set_in_an_included_file_stops_there() {
    let mut h = harness(project_app());
    h.get_by_label("File main.tml").click();
    h.run_steps(2);
    h.get_by_label("Breakpoint line 15").click();
    h.run_steps(2);
    let main = h
        .state()
        .debugger
        .project()
        .index_of("main.tml")
        .expect("main.tml");
    let line = Project::line(main, 15);
    assert_eq!(h.state().debugger.breakpoints(), [line].into());
    apply(
        &mut h,
        Command::Debug(Action::SetSpeed(
            servoscope_core::debugger::Speed::Unlimited,
        )),
    );
    apply(&mut h, Command::Debug(Action::Run));
    for _ in 0..200 {
        h.run_steps(1);
        if !h.state().debugger.is_running() {
            break;
        }
    }
    assert_eq!(h.state().debugger.machine().pc_line(), Some(line));
    // The breakpoint list names the file.
    let list = servoscope::ui::layout::Pane::Breakpoints;
    apply(&mut h, Command::ShowPane(list.clone(), true));
    h.state_mut().layout.focus(&list);
    h.run_steps(2);
    h.get_by_label("Line main.tml:15");
}

#[test]
fn a_jump_to_a_line_of_another_file_shows_that_file() {
    let mut h = harness(project_app());
    let functions = h
        .state()
        .debugger
        .project()
        .index_of("functions.tml")
        .expect("functions.tml");
    apply(&mut h, Command::ShowLine(Project::line(functions, 5)));
    assert_eq!(h.state().code.file, functions);
    assert_eq!(
        h.state().code.cursor_line,
        Some(Project::line(functions, 5))
    );
}

#[test]
fn editing_an_included_file_assembles_the_project_and_save_writes_the_changed_file() {
    let dir = two_file_project("proj", "a = 1;\n");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(dir.join("motion.tml"));
    let mut h = harness(app);
    apply(&mut h, Command::EditFile(1, "a = 2;\n".into()));
    assert!(h.state().debugger.is_file_edited(1));
    assert!(h.state().program_modified());
    apply(&mut h, Command::Debug(Action::Assemble));
    assert!(!h.state().debugger.has_errors());
    assert_eq!(
        h.state().code.unsaved,
        [false, true],
        "assembled, still unsaved"
    );
    apply(&mut h, Command::SaveProgram);
    assert_eq!(
        std::fs::read_to_string(dir.join("part.tml")).expect("read"),
        "a = 2;\n"
    );
    assert!(!h.state().program_modified());
    // An `#include` typed in reads its file from beside the top file.
    std::fs::write(dir.join("extra.tml"), "a += 40;\n").expect("w");
    apply(
        &mut h,
        Command::EditFile(
            0,
            "int a;\n#include \"part.tml\"\n#include \"extra.tml\"\nEND;\n".into(),
        ),
    );
    apply(&mut h, Command::Debug(Action::Assemble));
    assert!(
        !h.state().debugger.has_errors(),
        "{:?}",
        h.state().debugger.diagnostics()
    );
    assert_eq!(h.state().debugger.project().files.len(), 3);
    h.get_by_label("File extra.tml");
}

#[test]
fn the_drive_data_and_labels_panels_list_tables_a_and_b_and_the_addresses() {
    let mut h = harness(project_app());
    let show = |h: &mut Harness<'static, ServoscopeApp>, title: &str| {
        let pane = servoscope::ui::layout::Pane::Dialect(title.into());
        apply(h, Command::ShowPane(pane.clone(), true));
        h.state_mut().layout.focus(&pane);
        h.run_steps(2);
        assert!(h.state().layout.is_shown(&pane), "{title}");
    };
    show(&mut h, "Drive data");
    h.get_by_label("0x036A");
    h.get_by_label("0x03B2");
    show(&mut h, "Labels");
    h.get_by_label("MainStartAddress");
    h.get_by_label("0x4011");
    h.get_by_label("setup_settings.tml:20");
}

#[test]
fn ctrl_click_on_an_include_line_opens_the_file_it_names() {
    let mut h = harness(project_app());
    // The middle of motion.tml is its `#include "setup_settings.tml"` / `"main.tml"` lines.
    h.get_by_label("motion.tml")
        .click_modifiers(egui::Modifiers::COMMAND);
    h.run_steps(3);
    let shown = h.state().code.file;
    let name = h.state().debugger.project().files[shown].name.clone();
    assert!(
        name == "setup_settings.tml" || name == "main.tml",
        "opened {name}"
    );
    // A plain click only moves the caret.
    h.get_by_label("File motion.tml").click();
    h.run_steps(2);
    h.get_by_label("motion.tml").click();
    h.run_steps(2);
    assert_eq!(h.state().code.file, 0);
}

#[test]
fn a_session_whose_files_changed_on_disk_says_so_and_runs_its_own_copies() {
    let dir = two_file_project("sess", "a = 1;\n");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(dir.join("motion.tml"));
    let mut h = harness(app);
    apply(&mut h, Command::SaveSessionTo(dir.join("s.ron")));
    std::fs::write(dir.join("part.tml"), "a = 99;\n").expect("w");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(dir.join("s.ron"));
    let notice = app.notice.clone().unwrap_or_default();
    assert!(notice.contains("part.tml changed on disk"), "{notice}");
    assert_eq!(app.debugger.project().files[1].text, "a = 1;\n");
    // The session's copy is unsaved: its tab says so, and Save program writes it back (the
    // top file, unchanged, is left alone).
    let mut h = harness(app);
    assert_eq!(h.state().code.unsaved, [false, true]);
    let top_written = std::fs::metadata(dir.join("motion.tml"))
        .and_then(|m| m.modified())
        .ok();
    apply(&mut h, Command::SaveProgram);
    assert_eq!(
        std::fs::read_to_string(dir.join("part.tml")).expect("r"),
        "a = 1;\n"
    );
    assert_eq!(
        std::fs::metadata(dir.join("motion.tml"))
            .and_then(|m| m.modified())
            .ok(),
        top_written
    );
    assert!(!h.state().program_modified());
    assert_eq!(h.state().code.unsaved, [false, false]);
}

#[test]
fn clicking_a_problem_shows_its_file_and_line() {
    let dir = two_file_project("prob", "a = 1;\nCPRX;\n");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(dir.join("motion.tml"));
    let mut h = harness(app);
    assert_eq!(h.state().code.file, 0);
    h.get_by_label_contains("part.tml:2:1").click();
    h.run_steps(3);
    assert_eq!(h.state().code.file, 1, "the problem's file is shown");
    assert_eq!(h.state().code.cursor_line, Some(Project::line(1, 2)));
}

#[test]
fn save_program_never_writes_outside_the_programs_folder() {
    let dir = two_file_project("outside", "a = 1;\n");
    let above = dir
        .parent()
        .expect("a parent")
        .join(format!("servoscope-evil-{}.tml", std::process::id()));
    let _ = std::fs::remove_file(&above);
    let name = format!("../{}", above.file_name().unwrap().to_string_lossy());
    let session = format!(
        "(format: 3, dialect: \"tml\", program_name: \"motion.tml\", program_path: Some({:?}), \
         program: \"int a;\\n#include \\\"{name}\\\"\\nEND;\\n\", files: [(name: \"{name}\", text: \"a = 6;\\n\")])",
        dir.join("motion.tml")
    );
    std::fs::write(dir.join("s.ron"), session).expect("w");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(dir.join("s.ron"));
    assert!(
        !app.debugger.has_errors(),
        "{:?}",
        app.debugger.diagnostics()
    );
    let mut h = harness(app);
    apply(&mut h, Command::SaveProgram);
    assert!(
        !above.exists(),
        "nothing written above the program's folder"
    );
    let notice = h.state().notice.clone().unwrap_or_default();
    assert!(notice.contains("Not written"), "{notice}");
}

#[test]
fn an_include_outside_the_folder_is_read_only_from_a_folder_the_user_allows() {
    let root = std::env::temp_dir().join(format!("servoscope-gui-incdir-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let (shared, axis) = (root.join("shared"), root.join("axis"));
    std::fs::create_dir_all(&shared).expect("dir");
    std::fs::create_dir_all(&axis).expect("dir");
    std::fs::write(shared.join("setup.tml"), "int a;\n").expect("w");
    let top = axis.join("motion.tml");
    std::fs::write(&top, "#include \"../shared/setup.tml\"\na = 5;\nEND;\n").expect("w");

    let mut h = harness(ServoscopeApp::new(Prefs::default()));
    apply(&mut h, Command::OpenPath(top.clone()));
    assert_eq!(h.state().debugger.project().files.len(), 1, "not read");
    assert!(h.state().debugger.has_errors());
    // View → Include folders…, type the folder, Allow.
    apply(&mut h, Command::OpenIncludeFolders);
    h.get_by_label("Folder to allow").focus();
    h.step();
    h.get_by_label("Folder to allow")
        .type_text(shared.to_str().expect("utf-8"));
    h.run_steps(2);
    h.get_by_label("Allow").click();
    h.run_steps(3);
    assert_eq!(
        h.state().prefs.include_folders,
        std::slice::from_ref(&shared)
    );
    // The file is read at once and the program assembles.
    let names: Vec<String> = (h.state().debugger.project().files.iter())
        .map(|f| f.name.clone())
        .collect();
    assert_eq!(names, ["motion.tml", "../shared/setup.tml"]);
    assert!(!h.state().debugger.has_errors());
    // Removed, it is not read any more.
    h.get_by_label("Remove").click();
    h.run_steps(2);
    assert!(h.state().prefs.include_folders.is_empty());
    apply(&mut h, Command::OpenPath(top));
    assert_eq!(h.state().debugger.project().files.len(), 1);
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn an_export_never_replaces_the_programs_files() {
    let dir = two_file_project("export", "a = 1;\n");
    let mut h = harness(ServoscopeApp::new(Prefs::default()));
    apply(&mut h, Command::OpenPath(dir.join("motion.tml")));
    let part = std::fs::read_to_string(dir.join("part.tml")).expect("r");
    // The plot's and the log's exports, onto the included file: refused, the file intact.
    apply(&mut h, Command::ExportCsv(dir.join("part.tml")));
    apply(&mut h, Command::ExportLog(dir.join("part.tml")));
    assert_eq!(
        std::fs::read_to_string(dir.join("part.tml")).expect("r"),
        part
    );
    let notice = h.state().notice.clone().unwrap_or_default();
    assert!(
        notice.contains("never writes over a file it read"),
        "{notice}"
    );
    // A new file is written.
    apply(&mut h, Command::ExportCsv(dir.join("plot.csv")));
    assert!(
        std::fs::read_to_string(dir.join("plot.csv"))
            .expect("r")
            .starts_with("tick,time_ms")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
