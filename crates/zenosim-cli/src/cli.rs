//! The command line: what `zenosim` accepts, parsed and checked by clap (bad arguments exit 2).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use zenosim::ZenoStrategy;
use zenosim_model::Override;

/// Simulate a Lagrangian hybrid system with impacts, written in a model file, through its Zeno
/// points and on past them.
#[derive(Debug, Parser)]
#[command(
    name = "zenosim",
    version,
    after_help = "Exit status: 0 finished; 1 the simulation failed (what was computed is kept) or \
                  the output could not be written; 2 a bad model or bad arguments; 3 the run \
                  stopped at a Zeno point (--zeno off)."
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a model and write its trajectory (trajectory.csv) and record (summary.json).
    #[command(
        after_help = "Output, in DIR (default: out/<model name>, relative to the current \
directory; characters of the name other than letters, digits, '-', '_' and '.' become '_'):
  trajectory.csv  t,mode,<q...>,<q_dot...>,h_<constraint>...,lambda_<constraint>...,energy: a row at
                  every accepted step (or every --dt) and the states just before and just after
                  every event; numbers in shortest round-trip form
  summary.json    the outcome, the final state, the Zeno points, the events, the hybrid time
                  domain and the work counters (non-finite numbers are written as null)
Each file is written to a temporary name (.<file>.partial) and renamed when complete;
summary.json is written last (an old one is removed first), so its presence means the files
are complete and belong together.

Exit status: 0 finished; 1 the simulation failed (the files are still completed, status
\"failed\") or the output could not be written; 2 a bad model or bad arguments (nothing is
written); 3 the run stopped at a Zeno point (--zeno off)."
    )]
    Run(RunArgs),
    /// Check a model and print what zenosim derives from it at the initial state.
    #[command(after_help = "Exit status: 0 the model is valid; 2 it is not (or bad arguments).")]
    Check(CheckArgs),
}

/// `zenosim run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The model file (TOML).
    #[arg(value_name = "MODEL.toml")]
    pub model: PathBuf,

    /// The output directory [default: out/<model name>].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Set a parameter or an initial value (a number or a formula of the parameters); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_override)]
    pub sets: Vec<Override>,

    /// The stop time [default: the file's simulation.t_end, else 10].
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = positive)]
    pub t_end: Option<f64>,

    /// How to pass Zeno points: "auto" (switch once the remaining bounces are below the
    /// integration tolerance), "off" (stop at the Zeno point, exit 3) or a number ε (the paper's
    /// rule: switch when |h| ≤ ε and |A q̇| ≤ ε) [default: the file's simulation.zeno, else auto].
    #[arg(long, value_name = "auto|off|EPS", allow_negative_numbers = true, value_parser = zeno)]
    pub zeno: Option<ZenoStrategy>,

    /// The relative tolerance [default: the file's simulation.rtol, else 1e-10].
    #[arg(long, value_name = "R", allow_negative_numbers = true, value_parser = positive)]
    pub rtol: Option<f64>,

    /// The absolute tolerance [default: the file's simulation.atol, else 1e-10].
    #[arg(long, value_name = "A", allow_negative_numbers = true, value_parser = positive)]
    pub atol: Option<f64>,

    /// Sample the trajectory every DT from the dense output instead of at every step
    /// [default: the file's simulation.dt, else every step].
    #[arg(long, value_name = "DT", allow_negative_numbers = true, value_parser = positive)]
    pub dt: Option<f64>,
}

/// `zenosim check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The model file (TOML).
    #[arg(value_name = "MODEL.toml")]
    pub model: PathBuf,

    /// Set a parameter or an initial value (a number or a formula of the parameters); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_override)]
    pub sets: Vec<Override>,
}

fn parse_override(text: &str) -> Result<Override, String> {
    text.parse()
}

fn positive(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(_) => Err("must be a finite number > 0".to_string()),
        Err(_) => Err("not a number: write e.g. 6, 0.01 or 1e-10".to_string()),
    }
}

fn zeno(text: &str) -> Result<ZenoStrategy, String> {
    zenosim_model::parse_zeno(text.trim()).ok_or_else(|| {
        "expected auto, off or a threshold ε > 0 (the paper's rule, e.g. 1e-3)".to_string()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn values_are_checked() {
        assert_eq!(positive("1e-3"), Ok(1e-3));
        assert!(positive("-1").is_err());
        assert!(positive("0").is_err());
        assert!(positive("inf").is_err());
        assert!(positive("NaN").is_err());
        assert!(positive("x").is_err());
        assert_eq!(zeno("off"), Ok(ZenoStrategy::Off));
        assert_eq!(zeno("1e-3"), Ok(ZenoStrategy::Epsilon(1e-3)));
        assert!(zeno("banana").is_err());
        assert!(zeno("-1").is_err());
        assert!(parse_override("x").is_err());
    }
}
