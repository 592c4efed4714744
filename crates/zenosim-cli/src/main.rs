//! The `zenosim` command: simulate a hybrid Lagrangian written in a model file (`zenosim run`),
//! check one and print what zenosim derives from it (`zenosim check`), or draw the plots of a
//! run (`zenosim plot`, or `zenosim run --plot`); time a model's runs (`zenosim bench`) and draw
//! work–precision diagrams (`zenosim work-precision`).
//!
//! Exit status: 0 finished (or a valid model, or plots drawn), 1 the simulation failed or the
//! output could not be written, 2 a bad model, a bad run directory or bad arguments, 3 stopped
//! at a Zeno point (`--zeno off`).
//! Every error is printed on stderr as `error: …`; reports go to stdout.

mod bench;
mod check;
mod cli;
mod input;
mod output;
mod plot;
mod progress;
mod run;
mod trajectory;

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

use crate::cli::{Cli, Command};

/// Exit status of a successful run or check.
pub const EXIT_OK: u8 = 0;
/// Exit status of a failed simulation or of output that could not be written.
pub const EXIT_FAILED: u8 = 1;
/// Exit status of a bad model or bad arguments (as clap's own).
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit status of a run stopped at a Zeno point (`--zeno off`).
pub const EXIT_ZENO_STALLED: u8 = 3;

/// Why a command stopped early, and so its exit status.
#[derive(Debug)]
pub enum Failure {
    /// A bad model, model file or argument: exit 2, nothing written.
    BadInput(anyhow::Error),
    /// The output could not be written: exit 1.
    Output(anyhow::Error),
}

/// Sorting errors into [`Failure`]s.
pub trait Classify<T> {
    /// A bad input.
    fn bad_input(self) -> Result<T, Failure>;
    /// An output error.
    fn output(self) -> Result<T, Failure>;
}

impl<T> Classify<T> for anyhow::Result<T> {
    fn bad_input(self) -> Result<T, Failure> {
        self.map_err(Failure::BadInput)
    }
    fn output(self) -> Result<T, Failure> {
        self.map_err(Failure::Output)
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => run::run(&args),
        Command::Check(args) => check::check(&args),
        Command::Plot(args) => plot::plot(&args),
        Command::Bench(args) => bench::bench(&args),
        Command::WorkPrecision(args) => plot::work_precision(&args),
    };
    match result {
        Ok(code) => ExitCode::from(code),
        Err(Failure::BadInput(error)) => {
            print_error(&format!("{error:#}"));
            ExitCode::from(EXIT_BAD_INPUT)
        }
        Err(Failure::Output(error)) => {
            print_error(&format!("{error:#}"));
            ExitCode::from(EXIT_FAILED)
        }
    }
}

/// Prints `error: <message>` on stderr (ignoring a closed stderr: there is nowhere else to say it).
pub fn print_error(message: &str) {
    let _ = writeln!(std::io::stderr().lock(), "error: {message}");
}

/// Prints a report on stdout (ignoring a closed pipe, as in `zenosim check m.toml | head -1`).
pub fn print_report(report: &str) {
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(report.as_bytes());
    let _ = stdout.flush();
}
