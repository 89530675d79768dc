//! `servoscope`: opens the debugger, or runs a program headless (`servoscope run`).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use servoscope_core::machine::Diagnostic;
use servoscope_core::machine::diagnostics::printable;
use servoscope_core::machine::project::IncludeFolders;
use servoscope_core::output::{self, Output, Refusal};
use servoscope_core::registry::{self, Dialect, Settings};
use servoscope_core::runner::{self, Report};
use servoscope_core::session::{Recorded, Session, is_session_path};

#[derive(Parser)]
#[command(
    name = "servoscope",
    version,
    about = "Debugger and simulator for servo and PLC programs"
)]
#[command(args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// A program (dialect by extension, e.g. .qsl) or a saved session (.ron) to open.
    file: Option<PathBuf>,
    /// The program's dialect when its extension does not say it.
    #[arg(long, value_name = "NAME")]
    dialect: Option<String>,
    /// Measure frame times: run FILE unlimited for N frames, print median and worst, close.
    #[arg(long, value_name = "N", hide = true)]
    frame_stats: Option<usize>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a program headless and report its final state (exit 0 ended, 1 faulted,
    /// 2 bad file or arguments, 3 tick limit, 4 --break came true).
    Run(RunArgs),
    /// Draw a PLC program (DL205, OpenNet) as a ladder diagram in SVG, with its power flow
    /// as it stands after --max-ticks scans (before the first scan without it).
    Ladder(LadderArgs),
    /// Grade a lesson: run PROGRAM (or the lesson's own program) from tick 0 with the
    /// lesson's settings and edits, then evaluate every check of every step (exit 0 all
    /// pass, 1 any fails, 2 the program does not assemble or a file cannot be read, 3 the
    /// time budget ran out).
    Check(CheckArgs),
}

#[derive(clap::Args)]
struct CheckArgs {
    /// The lesson: a session (.ron) with a lesson section.
    lesson: PathBuf,
    /// The student's program; without it, the lesson's own program.
    program: Option<PathBuf>,
    /// Stop before this tick (scans for a PLC); without it, the lesson's `max_ticks`, else the
    /// dialect's runner default.
    #[arg(long)]
    max_ticks: Option<u64>,
    /// Print exactly one JSON object on stdout (also when the program does not assemble:
    /// status "not assembled" with every diagnostic).
    #[arg(long)]
    json: bool,
    /// Stop grading after this many seconds of running (the report says so; exit 3).
    #[arg(long, value_name = "SECONDS", default_value_t = DEFAULT_CHECK_TIMEOUT_S)]
    timeout: f64,
    #[command(flatten)]
    includes: IncludeArgs,
}

/// Where included files may be read from.
#[derive(clap::Args)]
struct IncludeArgs {
    /// Also read `#include`d files from this folder (and below); without it, only from the
    /// program's own folder and its subfolders. Repeatable.
    #[arg(long = "include-dir", value_name = "DIR")]
    include_dirs: Vec<PathBuf>,
}

impl IncludeArgs {
    fn folders(&self) -> IncludeFolders {
        IncludeFolders {
            allowed: self.include_dirs.clone(),
        }
    }
}

#[derive(clap::Args)]
struct LadderArgs {
    /// The program (dialect by extension), or a saved session (.ron).
    file: PathBuf,
    /// The program's dialect when its extension does not say it.
    #[arg(long, value_name = "NAME")]
    dialect: Option<String>,
    /// Run this many scans first; without it, the diagram before the first scan.
    #[arg(long)]
    max_ticks: Option<u64>,
    /// Toggle an input at the listed scans, e.g. X0=10,20 (inputs start low). Repeatable.
    #[arg(long = "input", value_name = "NAME=T1,T2,...")]
    inputs: Vec<String>,
    /// Force a bit from a scan on, e.g. Y0=1@100 (from the start without @SCAN). Repeatable.
    #[arg(long = "force", value_name = "NAME=1|0[@SCAN]")]
    forces: Vec<String>,
    /// A setting of the dialect's model, e.g. scan_ms=20. Repeatable.
    #[arg(long = "setting", value_name = "KEY=VALUE")]
    settings: Vec<String>,
    /// Where to write the SVG (never over the program; over a file that is not a ladder
    /// diagram servoscope drew only with --overwrite).
    #[arg(long, value_name = "OUT.svg")]
    svg: PathBuf,
    /// Let --svg replace a file that is not a ladder diagram servoscope drew.
    #[arg(long)]
    overwrite: bool,
    #[command(flatten)]
    includes: IncludeArgs,
}

#[derive(clap::Args)]
struct RunArgs {
    /// The program (dialect by extension, e.g. .qsl), or a saved session (.ron) to resume.
    file: PathBuf,
    /// The program's dialect when its extension does not say it.
    #[arg(long, value_name = "NAME")]
    dialect: Option<String>,
    /// Stop before this tick (scans for a PLC); the dialect's default when not given.
    #[arg(long)]
    max_ticks: Option<u64>,
    /// Toggle an input at the listed ticks, e.g. IO1=100,250 (inputs start low). Repeatable.
    #[arg(long = "input", value_name = "NAME=T1,T2,...")]
    inputs: Vec<String>,
    /// Give a location an initial value before the first tick, e.g. R26=-5. Repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
    /// A setting of the dialect's model, e.g. scan_ms=20 (PLCs) or a servo model key.
    /// Repeatable.
    #[arg(long = "setting", value_name = "KEY=VALUE")]
    settings: Vec<String>,
    /// Print exactly one JSON object on stdout (also when the program does not assemble:
    /// status "not assembled" with every diagnostic).
    #[arg(long)]
    json: bool,
    /// When the run stops, save a session that reproduces this exact state.
    #[arg(long, value_name = "OUT.ron")]
    save_session: Option<PathBuf>,
    /// Let --save-session and --trace replace a file of another kind (never the program).
    #[arg(long)]
    overwrite: bool,
    /// Force a bit (PLC inputs, outputs, relays) from a scan on, e.g. Y0=1@100 or X1=0 (from
    /// the start without @SCAN); it keeps that level whatever the program writes. Repeatable.
    #[arg(long = "force", value_name = "NAME=1|0[@SCAN]")]
    forces: Vec<String>,
    /// Write one JSON object per executed instruction to this file (JSON Lines): position,
    /// line, mnemonic, and the locations it wrote with their new values.
    #[arg(long, value_name = "FILE.jsonl")]
    trace: Option<PathBuf>,
    /// Stop when this expression holds before an instruction, e.g. "R4 > 1000 && IO3"
    /// (exit code 4; the report says where).
    #[arg(long = "break", value_name = "EXPR")]
    break_when: Option<String>,
    #[command(flatten)]
    includes: IncludeArgs,
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return argument_error(&e),
    };
    match cli.command {
        Some(Command::Run(args)) => ExitCode::from(match run(&args) {
            Ok(code) => code,
            Err(message) => {
                say(&format!("servoscope: {message}"));
                2
            }
        }),
        Some(Command::Ladder(args)) => ExitCode::from(match ladder(&args) {
            Ok(()) => 0,
            Err(message) => {
                say(&format!("servoscope: {message}"));
                2
            }
        }),
        Some(Command::Check(args)) => ExitCode::from(match check(&args) {
            Ok(code) => code,
            Err(message) => {
                say(&format!("servoscope: {message}"));
                2
            }
        }),
        None => open_window(cli.file, cli.dialect, cli.frame_stats),
    }
}

fn open_window(
    file: Option<PathBuf>,
    dialect: Option<String>,
    frame_stats: Option<usize>,
) -> ExitCode {
    if let Some(name) = &dialect
        && registry::by_name(name).is_none()
    {
        say(&format!(
            "servoscope: {}",
            registry::ChooseError::UnknownName(name.clone())
        ));
        return ExitCode::from(2);
    }
    match servoscope::ui::run_gui(file, dialect, frame_stats) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            say(&format!("servoscope: cannot open the window: {e}"));
            say("(no display? `servoscope run FILE` works without one)");
            ExitCode::from(2)
        }
    }
}

impl Start {
    /// The files this start was read from (`file`, and the program's files when `file` is a
    /// program): what no output may replace.
    fn inputs(&self, file: &Path) -> Vec<output::Input> {
        if self.session.is_some() {
            vec![output::Input::new(file, "the session")]
        } else {
            output::program_inputs(file, &self.project)
        }
    }
}

/// What a run starts from: the program, its dialect and settings, and the recorded events.
struct Start {
    dialect: &'static Dialect,
    name: String,
    path: Option<PathBuf>,
    /// The program's files, the top file first.
    project: servoscope_core::machine::project::Project,
    settings: Settings,
    /// Session events by name (resolved once the program is assembled).
    session: Option<Session>,
}

fn read_start(
    file: &Path,
    dialect: Option<&str>,
    folders: &IncludeFolders,
) -> Result<Start, String> {
    if is_session_path(file) {
        let session = Session::load(file).map_err(|e| e.to_string())?;
        if let Some(d) = dialect
            && registry::by_name(d) != Some(session.dialect())
        {
            return Err(format!(
                "--dialect {d} does not match the session's dialect '{}'",
                session.dialect
            ));
        }
        return Ok(Start {
            dialect: session.dialect(),
            name: session.program_name.clone(),
            path: session.program_path.clone(),
            project: session.project(),
            settings: session.settings.clone(),
            session: Some(session),
        });
    }
    let dialect = registry::choose(file, dialect).map_err(|e| e.to_string())?;
    let project = dialect
        .load_with(file, folders)
        .map_err(|e| e.to_string())?;
    let short = project.top_name().to_string();
    Ok(Start {
        dialect,
        name: short,
        path: Some(file.to_path_buf()),
        project,
        settings: dialect.default_settings(),
        session: None,
    })
}

fn run(args: &RunArgs) -> Result<u8, String> {
    let RunArgs {
        file,
        dialect,
        max_ticks,
        inputs,
        sets,
        settings: given_settings,
        json,
        save_session,
        overwrite,
        forces,
        trace,
        break_when,
        includes,
    } = args;
    let (dialect, max_ticks, json) = (dialect.as_deref(), *max_ticks, *json);
    let start = read_start(file, dialect, &includes.folders())?;
    let read_files = start.inputs(file);
    let streamed = trace.as_deref().is_some_and(is_stream);
    if let Some(path) = trace
        && !streamed
    {
        output::may_write(path, Output::Trace, &read_files, *overwrite).map_err(refused)?;
    }
    if let Some(path) = save_session {
        // The session rule itself (a session, or --overwrite) is the session's own save.
        output::may_write(path, Output::Session, &read_files, true).map_err(refused)?;
    }
    let name = file.display().to_string();
    if start.session.is_some() && !(inputs.is_empty() && sets.is_empty() && forces.is_empty()) {
        return Err(
            "--input, --set and --force cannot be combined with a session (its edits are in it)"
                .to_string(),
        );
    }
    if start.session.is_some() && !given_settings.is_empty() {
        return Err(
            "--setting cannot be combined with a session (its settings are in it)".to_string(),
        );
    }
    let mut settings = start.settings.clone();
    for text in given_settings {
        let (key, value) = start.dialect.parse_setting(text)?;
        settings.insert(key, value);
    }
    let settings = start.dialect.settings_from(&settings);
    let engine = open_engine(&start, &settings, &name).map_err(|diagnostics| {
        if json {
            print_json(runner::not_assembled_json(
                start.dialect,
                &start.project,
                &name,
                &diagnostics,
            ));
        }
        nothing_run(&name, &diagnostics)
    })?;
    let m = engine.machine();
    let events = match &start.session {
        // A session resumes at its saved tick; the events decide everything, so running on
        // from the start with them gives exactly the straight run's result.
        Some(session) => session.user_events(m, &name).map_err(|e| e.to_string())?,
        None => {
            let mut events = Vec::new();
            for spec in sets {
                events.push(runner::parse_set_spec(m, spec).map_err(|e| e.to_string())?);
            }
            let mut toggles = Vec::new();
            for spec in inputs {
                toggles.extend(runner::parse_input_spec(m, spec).map_err(|e| e.to_string())?);
            }
            events.extend(runner::toggles_to_events(&toggles));
            for spec in forces {
                events.push(runner::parse_force_spec(m, spec).map_err(|e| e.to_string())?);
            }
            events
        }
    };
    let max_ticks = max_ticks.unwrap_or(start.dialect.default_max_ticks);
    let until = match break_when {
        Some(text) => Some(
            servoscope_core::debugger::expr::Expr::compile(text, m)
                .map_err(|e| format!("--break '{text}': {e}"))?,
        ),
        None => None,
    };
    let (done, broke) = if trace.is_none() && until.is_none() {
        (
            runner::run_engine(engine.as_ref(), &events, max_ticks),
            None,
        )
    } else {
        let run_probed = |trace: Option<&mut dyn std::io::Write>| {
            let probe = runner::Probe { trace, until };
            runner::run_engine_probed(engine.as_ref(), &events, max_ticks, &start.project, probe)
        };
        match trace {
            // A pipe or a terminal (`--trace /dev/stdout`, `>(jq …)`) is written as the run
            // goes: there is nothing there to keep.
            Some(path) if streamed => {
                let file = std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
                let mut writer = std::io::BufWriter::new(file);
                let (done, broke, error) = run_probed(Some(&mut writer));
                error
                    .map_or_else(|| writer.flush(), Err)
                    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
                (done, broke)
            }
            // Written atomically: a failed run or write leaves whatever was there before.
            Some(path) => {
                let mut ran = None;
                servoscope_core::atomic::write_atomically(path, |w| {
                    let (done, broke, error) = run_probed(Some(w));
                    ran = Some((done, broke));
                    error.map_or(Ok(()), Err)
                })
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
                ran.ok_or_else(|| format!("cannot write {}", path.display()))?
            }
            None => {
                let (done, broke, _) = run_probed(None);
                (done, broke)
            }
        }
    };
    let report = Report {
        dialect: start.dialect,
        machine: done.machine(),
        project: Some(&start.project),
        broke,
    };
    if let Some(out) = save_session {
        let session = Session::of_run(Recorded {
            dialect: start.dialect,
            program_name: &start.name,
            program_path: start.path.clone(),
            program: start.project.top_text(),
            files: start.project.files.get(1..).unwrap_or_default(),
            settings: &settings,
            machine: done.machine(),
            events: &events,
        });
        let saved = if *overwrite {
            session.save_over(out)
        } else {
            session.save(out)
        };
        saved.map_err(|e| match e {
            servoscope_core::session::SessionError::WouldReplace { .. } => {
                format!("{e}; pass --overwrite to replace it")
            }
            other => other.to_string(),
        })?;
    }
    let text = if json {
        report.to_json() + "\n"
    } else {
        report.to_text()
    };
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(report.exit_code()),
        // The reader went away (`| head`): nothing to tell anyone, as Unix tools do.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(2),
        Err(e) => Err(format!("cannot write the report to standard output: {e}")),
    }
}

/// Assemble the start's program, printing its errors (and warnings, which never stop a run:
/// OpenNet's MICRO3 relays) on stderr.
fn open_engine(
    start: &Start,
    settings: &Settings,
    name: &str,
) -> Result<Box<dyn servoscope_core::debugger::Engine>, Vec<Diagnostic>> {
    match start.dialect.open_program(&start.project, settings) {
        Ok(engine) => {
            for d in engine
                .machine()
                .warnings()
                .iter()
                .take(MAX_DIAGNOSTICS_SHOWN)
            {
                say(&start.project.diagnostic(name, d));
            }
            Ok(engine)
        }
        Err(diagnostics) => {
            for d in diagnostics.iter().take(MAX_DIAGNOSTICS_SHOWN) {
                say(&start.project.diagnostic(name, d));
            }
            if diagnostics.len() > MAX_DIAGNOSTICS_SHOWN {
                let more = diagnostics.len() - MAX_DIAGNOSTICS_SHOWN;
                say(&format!("... and {more} more error(s)"));
            }
            Err(diagnostics)
        }
    }
}

/// Whether `path` is a pipe or a character device (a terminal, `/dev/stdout`): written as a
/// stream, not replaced.
fn is_stream(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        std::fs::metadata(path).is_ok_and(|m| {
            let kind = m.file_type();
            kind.is_fifo() || kind.is_char_device()
        })
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        false
    }
}

/// Why an output file was not written, with what the user can do about it.
fn refused(e: Refusal) -> String {
    match e {
        Refusal::NotOurs { .. } => format!("{e}; pass --overwrite to replace it"),
        other => other.to_string(),
    }
}

/// Why nothing ran, for the exit with code 2.
fn nothing_run(name: &str, diagnostics: &[Diagnostic]) -> String {
    format!("{name}: {} error(s), nothing run", diagnostics.len())
}

/// `--json`'s one object for a program that did not assemble, on standard output.
fn print_json(value: impl std::fmt::Display) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{value}").and_then(|()| out.flush());
}

/// `servoscope ladder`: the diagram with its power flow after the scans asked for, as SVG.
fn ladder(args: &LadderArgs) -> Result<(), String> {
    let start = read_start(
        &args.file,
        args.dialect.as_deref(),
        &args.includes.folders(),
    )?;
    let name = args.file.display().to_string();
    output::may_write(
        &args.svg,
        Output::LadderSvg,
        &start.inputs(&args.file),
        args.overwrite,
    )
    .map_err(refused)?;
    let mut settings = start.settings.clone();
    for text in &args.settings {
        let (key, value) = start.dialect.parse_setting(text)?;
        settings.insert(key, value);
    }
    let settings = start.dialect.settings_from(&settings);
    let engine = open_engine(&start, &settings, &name).map_err(|d| nothing_run(&name, &d))?;
    let m = engine.machine();
    if !m.is_plc() {
        return Err(format!(
            "{name}: a {} program has no ladder diagram (DL205 and OpenNet programs have)",
            start.dialect.display_name
        ));
    }
    let mut events = match &start.session {
        Some(session) => session.user_events(m, &name).map_err(|e| e.to_string())?,
        None => Vec::new(),
    };
    let mut toggles = Vec::new();
    for spec in &args.inputs {
        toggles.extend(runner::parse_input_spec(m, spec).map_err(|e| e.to_string())?);
    }
    events.extend(runner::toggles_to_events(&toggles));
    for spec in &args.forces {
        events.push(runner::parse_force_spec(m, spec).map_err(|e| e.to_string())?);
    }
    let done = runner::run_engine(engine.as_ref(), &events, args.max_ticks.unwrap_or(0));
    let m = done.machine();
    let diagram = servoscope_core::machine::plc::ladder::with_comments(
        m,
        start.project.top_text(),
        start.dialect.classify,
    )
    .ok_or_else(|| format!("{name}: no ladder diagram"))?;
    let title = format!("{} — after {} scan(s)", start.name, m.ticks());
    let svg = servoscope_core::machine::plc::ladder::svg_of(m, &diagram, &title);
    servoscope_core::atomic::write_atomically(&args.svg, |w| w.write_all(svg.as_bytes()))
        .map_err(|e| format!("cannot write {}: {e}", args.svg.display()))
}

/// `servoscope check`: run the program as the lesson says and grade it by the lesson's checks.
fn check(args: &CheckArgs) -> Result<u8, String> {
    let lesson_name = args.lesson.display().to_string();
    if let Some(asked) = args.max_ticks
        && asked > servoscope_core::lesson::MAX_LESSON_TICKS
    {
        return Err(format!(
            "--max-ticks {asked}: servoscope grades at most {} ticks",
            servoscope_core::lesson::MAX_LESSON_TICKS
        ));
    }
    let budget = std::time::Duration::try_from_secs_f64(args.timeout)
        .ok()
        .filter(|d| !d.is_zero())
        .ok_or_else(|| {
            format!(
                "--timeout {}: give a number of seconds above 0",
                args.timeout
            )
        })?;
    let session = Session::load(&args.lesson).map_err(|e| e.to_string())?;
    for warning in &session.warnings {
        say(&format!("servoscope: {lesson_name}: {warning}"));
    }
    let Some(lesson) = session.lesson.clone() else {
        return Err(format!(
            "{lesson_name} is a session without a lesson section (lesson: Some((title: …, steps: […])))"
        ));
    };
    let dialect = session.dialect();
    let (name, project) = match &args.program {
        Some(path) => {
            if let Some(by_extension) = registry::by_path(path)
                && by_extension != dialect
            {
                return Err(format!(
                    "{} is a program for {}; the lesson is for {}",
                    path.display(),
                    by_extension.display_name,
                    dialect.display_name
                ));
            }
            let project = dialect
                .load_with(path, &args.includes.folders())
                .map_err(|e| e.to_string())?;
            (path.display().to_string(), project)
        }
        None => (session.program_name.clone(), session.project()),
    };
    let start = Start {
        dialect,
        name: name.clone(),
        path: args.program.clone(),
        project,
        settings: session.settings.clone(),
        session: None,
    };
    let settings = dialect.settings_from(&session.settings);
    let engine = open_engine(&start, &settings, &name).map_err(|diagnostics| {
        if args.json {
            let outcomes =
                servoscope_core::lesson::unevaluated(&lesson, "the program did not assemble");
            let mut run = runner::not_assembled_json(dialect, &start.project, &name, &diagnostics);
            run["program"] = serde_json::json!(name);
            print_json(servoscope_core::lesson::report_json(
                &lesson.title,
                &outcomes,
                run,
            ));
        }
        nothing_run(&name, &diagnostics)
    })?;
    let max_ticks = servoscope_core::lesson::grading_ticks(&lesson, args.max_ticks, dialect);
    let graded = servoscope_core::lesson::grading_run(
        engine.as_ref(),
        &session,
        &lesson,
        max_ticks,
        &lesson_name,
        budget,
    )
    .map_err(|e| e.to_string())?;
    let (done, outcomes) = (graded.run, graded.outcomes);
    let report = Report {
        dialect,
        machine: done.machine(),
        project: Some(&start.project),
        broke: None,
    };
    let status = if graded.finished {
        report.status().to_string()
    } else {
        "timed out".to_string()
    };
    let unit = if done.machine().is_plc() {
        "scan(s)"
    } else {
        "tick(s)"
    };
    let text = if args.json {
        let run = serde_json::json!({
            "program": name,
            "status": status,
            "ticks": done.machine().ticks(),
        });
        servoscope_core::lesson::report_json(&lesson.title, &outcomes, run) + "\n"
    } else {
        let run = format!("{name}: {status} after {} {unit}", done.machine().ticks());
        servoscope_core::lesson::report_text(&lesson.title, &outcomes, &run)
    };
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) if !graded.finished => Ok(3),
        Ok(()) => Ok(u8::from(outcomes.iter().any(|o| !o.pass))),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(2),
        Err(e) => Err(format!("cannot write the report to standard output: {e}")),
    }
}

/// What clap found instead of a command: help, the version, or a mistake. With `--json` among
/// the arguments, help and the version are one JSON object on stdout too, as `--json`
/// promises; without it, clap's own text.
fn argument_error(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    let json = std::env::args_os()
        .skip(1)
        .take_while(|a| a != "--")
        .any(|a| a == "--json");
    let shown = matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion);
    if json && shown {
        let value = if e.kind() == ErrorKind::DisplayVersion {
            serde_json::json!({ "version": env!("CARGO_PKG_VERSION") })
        } else {
            serde_json::json!({ "help": e.render().to_string() })
        };
        print_json(value);
        return ExitCode::SUCCESS;
    }
    let _ = e.print();
    ExitCode::from(if e.use_stderr() { 2 } else { 0 })
}

/// `check --timeout`'s default, in seconds.
const DEFAULT_CHECK_TIMEOUT_S: f64 = servoscope_core::lesson::DEFAULT_GRADING_SECONDS;

/// Diagnostics printed at most; the rest are counted.
const MAX_DIAGNOSTICS_SHOWN: usize = 100;

/// A line on standard error, control characters escaped. A failing stderr has nowhere to be
/// reported: it is ignored rather than allowed to panic.
fn say(line: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{}", printable(line));
}
