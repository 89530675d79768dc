//! `servoscope`: opens the debugger, or runs a program headless (`servoscope run`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use std::sync::Arc;

use servoscope::machine::silverlode::{ServoSettings, SilverLode, assemble};
use servoscope::runner::{self, DEFAULT_MAX_TICKS, Report};
use servoscope::session::Session;

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
    /// A program (.qsl) or a saved session (.ron) to open in the debugger.
    file: Option<PathBuf>,
    /// Measure frame times: run FILE unlimited for N frames, print median and worst, close.
    #[arg(long, value_name = "N", hide = true)]
    frame_stats: Option<usize>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a program headless and report its final state (exit 0 ended, 1 faulted,
    /// 2 bad file or arguments, 3 tick limit).
    Run {
        /// The program (.qsl), or a saved session (.ron) to resume.
        file: PathBuf,
        /// Stop after this many ticks (120 µs each).
        #[arg(long, default_value_t = DEFAULT_MAX_TICKS)]
        max_ticks: u64,
        /// Toggle an input at the listed ticks, e.g. IO1=100,250 (inputs start low). Repeatable.
        #[arg(long = "input", value_name = "IOk=T1,T2,...")]
        inputs: Vec<String>,
        /// Print exactly one JSON object on stdout.
        #[arg(long)]
        json: bool,
        /// When the run stops, save a session that reproduces this exact state.
        #[arg(long, value_name = "OUT.ron")]
        save_session: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Some(Command::Run {
            file,
            max_ticks,
            inputs,
            json,
            save_session,
        }) => ExitCode::from(run(
            &file,
            max_ticks,
            &inputs,
            json,
            save_session.as_deref(),
        )),
        None => match servoscope::ui::run_gui(cli.file, cli.frame_stats) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("servoscope: cannot open the window: {e}");
                eprintln!("(no display? `servoscope run FILE` works without one)");
                ExitCode::from(2)
            }
        },
    }
}

/// A `.ron` file is a saved session; anything else a program.
fn is_session(file: &Path) -> bool {
    file.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ron"))
}

fn run(file: &Path, max_ticks: u64, inputs: &[String], json: bool, save: Option<&Path>) -> u8 {
    let mut toggles = Vec::new();
    for spec in inputs {
        match runner::parse_input_spec(spec) {
            Ok(t) => toggles.extend(t),
            Err(e) => {
                eprintln!("servoscope: {e}");
                return 2;
            }
        }
    }
    let name = file.display().to_string();
    let (program_name, program_path, source, events, settings) = if is_session(file) {
        if !toggles.is_empty() {
            eprintln!(
                "servoscope: --input cannot be combined with a session (its inputs are in it)"
            );
            return 2;
        }
        let session = match Session::load(file) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("servoscope: {e}");
                return 2;
            }
        };
        (
            session.program_name,
            session.program_path,
            session.program,
            session.events,
            session.servo,
        )
    } else {
        match std::fs::read_to_string(file) {
            Ok(text) => {
                let short = file
                    .file_name()
                    .map_or(name.clone(), |n| n.to_string_lossy().into_owned());
                (
                    short,
                    Some(file.to_path_buf()),
                    text,
                    runner::toggles_to_events(&toggles),
                    ServoSettings::default(),
                )
            }
            Err(e) => {
                eprintln!("servoscope: cannot read {name}: {e}");
                return 2;
            }
        }
    };
    let program = match assemble(&source) {
        Ok(p) => p,
        Err(diagnostics) => {
            for d in &diagnostics {
                eprintln!("{}", d.with_file(&name));
            }
            eprintln!(
                "servoscope: {name}: {} error(s), nothing run",
                diagnostics.len()
            );
            return 2;
        }
    };
    let mut machine = SilverLode::with_settings(Arc::new(program), settings);
    // A session resumes at its saved tick; the events decide everything, so running on from
    // tick 0 with them gives exactly the straight run's result.
    runner::run_events(&mut machine, &events, max_ticks);
    let report = Report::of(&machine);
    if let Some(out) = save {
        let session = runner::session_of_run(
            &program_name,
            program_path.as_deref(),
            &source,
            &machine,
            events,
        );
        if let Err(e) = session.save(out) {
            eprintln!("servoscope: {e}");
            return 2;
        }
    }
    if json {
        println!("{}", report.to_json());
    } else {
        print!("{}", report.to_text());
    }
    report.exit_code() as u8
}
