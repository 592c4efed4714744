//! Runs one model `N` times in a loop, for instruction counts under callgrind (BENCHMARKS.md):
//! the count of `N = 101` minus that of `N = 1`, over 100, is the cost of one run, free of the
//! loading and of the process's start.
//!
//! ```sh
//! cargo build --release --locked --example runs -p zenosim-model
//! valgrind --tool=callgrind target/release/examples/runs bouncing 101
//! ```
//!
//! Models: `ball-file` (the paper's ball from `models/ball-on-sine.toml`, its settings),
//! `ball-rust` (the same ball as the Rust model `zenosim::models::BallOnSine`, the file's
//! settings), `bouncing` (the Rust `BouncingBall`, `m = 1`, `g = 9.81`, `e = 0.8`, from 1 m,
//! default options).

use std::path::PathBuf;
use std::process::ExitCode;

use zenosim::models::{BallOnSine, BouncingBall};
use zenosim::{HybridLagrangian, Simulation, SimulationOptions};
use zenosim_model::{parse_model, ModelFile};

const USAGE: &str = "usage: runs ball-file|ball-rust|bouncing N";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(which), Some(Ok(n))) = (args.first(), args.get(1).map(|n| n.parse::<u32>())) else {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    let steps = match which.as_str() {
        "ball-file" => {
            let file = paper_ball();
            repeat(
                &file.model,
                &file.initial.q,
                &file.initial.q_dot,
                file.options(),
                n,
            )
        }
        "ball-rust" => {
            let example = BallOnSine::paper();
            let options = paper_ball().options();
            repeat(&example.model, &example.q0, &example.q_dot0, options, n)
        }
        "bouncing" => {
            let ball = BouncingBall::new(1.0, 9.81, 0.8);
            repeat(&ball, &[1.0], &[0.0], SimulationOptions::default(), n)
        }
        _ => {
            eprintln!("{USAGE}");
            return ExitCode::from(2);
        }
    };
    // The steps taken, so that the runs cannot be optimised away.
    println!("{steps}");
    ExitCode::SUCCESS
}

/// `models/ball-on-sine.toml`, loaded.
fn paper_ball() -> ModelFile {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../models/ball-on-sine.toml");
    let source = std::fs::read_to_string(&path).expect("models/ball-on-sine.toml is read");
    parse_model("ball-on-sine.toml", &source, &[]).expect("the paper's ball loads")
}

/// Runs `model` `n` times; the steps of all runs.
fn repeat<M: HybridLagrangian>(
    model: &M,
    q0: &[f64],
    q_dot0: &[f64],
    options: SimulationOptions,
    n: u32,
) -> u64 {
    let simulation = Simulation::new(model, q0, q_dot0, options).expect("the model runs");
    let mut steps = 0;
    for _ in 0..n {
        steps += simulation.run(&mut ()).stats.steps;
    }
    steps
}
