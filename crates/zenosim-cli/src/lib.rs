//! The `zenosim` command: simulate a hybrid Lagrangian written in a model file (`zenosim run`),
//! check one and print what zenosim derives from it (`zenosim check`), draw the plots of a
//! run (`zenosim plot`, or `zenosim run --plot`) or write its interactive report (`zenosim
//! report`, or `zenosim run --report`); run a model over a grid of parameters or
//! initial values (`zenosim sweep`, its shards joined by `zenosim merge`); time a model's runs
//! (`zenosim bench`) and draw work–precision diagrams (`zenosim work-precision`).
//!
//! Exit status: 0 finished (or a valid model, or plots drawn), 1 the simulation failed or the
//! output could not be written, 2 a bad model, a bad run directory or bad arguments, 3 stopped
//! at a Zeno point (`--zeno off`).
//! Every error is printed on stderr as `error: …`; reports go to stdout.
//!
//! This library is the command itself, minus its `main` (`src/main.rs`, which calls [`main`]):
//! it is a library so that the fuzz target of `zenosim plot` (`fuzz/fuzz_targets/plot.rs`) and
//! the tests can call [`draw`] on a folder without running the binary. It is no API.

mod bench;
mod check;
mod cli;
mod input;
mod merge;
mod output;
mod plot;
mod progress;
mod report;
mod run;
mod signals;
mod size;
mod sweep;
mod sweep_file;
mod trajectory;

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

use crate::cli::{Cli, Command};

pub use plot::{draw, draw_scaled, Format, Plane, PlaneScale, FRICTION, PLOTS};

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

/// The `zenosim` command: parses the command line, runs the command and prints its error. For
/// the binary's `main` to call first thing: it sets the process's signal dispositions.
pub fn main() -> ExitCode {
    // A write past a file-size limit (RLIMIT_FSIZE) fails with EFBIG, reported as a write error
    // that stops the run at once, like a full disk, instead of killing the process with SIGXFSZ
    // and losing what was computed.
    #[cfg(unix)]
    // SAFETY: `signal` with SIG_IGN installs no handler; it runs before any other thread exists.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => run::run(&args),
        Command::Sweep(args) => sweep::sweep(&args),
        Command::Merge(args) => merge::merge(&args),
        Command::Check(args) => check::check(&args),
        Command::Plot(args) => plot::plot(&args),
        Command::Report(args) => report::report(&args),
        Command::Animate(args) => plot::animate(&args),
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

/// Prints `error: <message>` on stderr (ignoring a closed stderr: there is nowhere else to say it),
/// its control characters escaped ([`terminal_safe`]).
pub fn print_error(message: &str) {
    let message = terminal_safe(message);
    let _ = writeln!(std::io::stderr().lock(), "error: {message}");
}

/// Prints a report on stdout (ignoring a closed pipe, as in `zenosim check m.toml | head -1`),
/// its control characters escaped ([`terminal_safe`]).
pub fn print_report(report: &str) {
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(terminal_safe(report).as_bytes());
    let _ = stdout.flush();
}

/// `text` with every control character but the newline and the tab written as a Rust escape
/// (`\u{1b}`): a model's name, a constraint's name or a line of a file quoted in a message
/// cannot clear the screen, retitle the window or hide text from the reader. The bidirectional
/// overrides and isolates (U+202A–U+202E, U+2066–U+2069), which reorder what is shown, are
/// escaped too.
pub fn terminal_safe(text: &str) -> std::borrow::Cow<'_, str> {
    let unsafe_char = |c: char| {
        (c.is_control() && c != '\n' && c != '\t')
            || ('\u{202a}'..='\u{202e}').contains(&c)
            || ('\u{2066}'..='\u{2069}').contains(&c)
    };
    if !text.chars().any(unsafe_char) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut safe = String::with_capacity(text.len() + 16);
    for c in text.chars() {
        if unsafe_char(c) {
            safe.extend(c.escape_unicode());
        } else {
            safe.push(c);
        }
    }
    std::borrow::Cow::Owned(safe)
}
