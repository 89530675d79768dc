//! `servoscope`: opens the debugger, or runs a program headless (`servoscope run`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use servoscope::runner::{self, DEFAULT_MAX_TICKS, Report};

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
    /// A program (.qsl) to open in the debugger.
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
        /// The program (.qsl).
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
        }) => ExitCode::from(run(&file, max_ticks, &inputs, json)),
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

fn run(file: &Path, max_ticks: u64, inputs: &[String], json: bool) -> u8 {
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
    let source = match std::fs::read_to_string(file) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("servoscope: cannot read {name}: {e}");
            return 2;
        }
    };
    let mut machine = match runner::load(&source) {
        Ok(m) => m,
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
    runner::run_with_inputs(&mut machine, &toggles, max_ticks);
    let report = Report::of(&machine);
    if json {
        println!("{}", report.to_json());
    } else {
        print!("{}", report.to_text());
    }
    report.exit_code() as u8
}
