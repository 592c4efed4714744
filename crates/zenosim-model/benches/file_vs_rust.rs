//! A model read from a file against the same model written in Rust, over whole runs.
//!
//! Target (issue: model files): the paper's ball to `t = 6` at `rtol = atol = 1e-10` at most
//! 2× slower from its file than as the engine's Rust model. "interpreted" is the file model
//! without its compiled derivatives, for comparison. Run with
//! `cargo bench -p zenosim-model --bench file_vs_rust`.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use zenosim::models::{BallOnSine, CartPendulum, Example, SphericalPendulum};
use zenosim::{HybridLagrangian, Simulation, SimulationOptions};
use zenosim_model::{parse_model, ModelFile};

fn load(name: &str) -> ModelFile {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../models")
        .join(name);
    let source = std::fs::read_to_string(&path).expect("the model file is readable");
    parse_model(name, &source, &[]).unwrap_or_else(|e| panic!("{e}"))
}

fn bench_run<L: HybridLagrangian>(
    c: &mut Criterion,
    name: &str,
    model: &L,
    q0: &[f64],
    q_dot0: &[f64],
    options: SimulationOptions,
) {
    let sim = Simulation::new(model, q0, q_dot0, options).expect("a valid model");
    let run = sim.run(&mut ());
    eprintln!(
        "{name}: {:?}, {} steps, {} rhs evaluations, {} impacts",
        run.outcome, run.stats.steps, run.stats.rhs_evals, run.stats.impacts
    );
    c.bench_function(name, |b| b.iter(|| black_box(sim.run(&mut ()))));
}

/// The file (with its compiled derivatives, as zenosim runs it, and interpreted: differentiated
/// through the formula interpreter at every step) and the Rust model, with the file's options
/// (the same as the Rust example's).
fn pair<M: HybridLagrangian>(c: &mut Criterion, file: &str, rust: &Example<M>) {
    let file = load(file);
    let options = file.options();
    let label = &file.name;
    bench_run(
        c,
        &format!("{label} (file)"),
        &file.model,
        &file.initial.q,
        &file.initial.q_dot,
        options,
    );
    bench_run(
        c,
        &format!("{label} (file, interpreted)"),
        &file.model.clone().interpreted(),
        &file.initial.q,
        &file.initial.q_dot,
        options,
    );
    bench_run(
        c,
        &format!("{label} (Rust)"),
        &rust.model,
        &rust.q0,
        &rust.q_dot0,
        options,
    );
}

fn paper_ball(c: &mut Criterion) {
    pair(c, "ball-on-sine.toml", &BallOnSine::paper());
}

fn demos(c: &mut Criterion) {
    pair(c, "cart-pendulum.toml", &CartPendulum::demo());
    pair(c, "spherical-pendulum.toml", &SphericalPendulum::demo());
}

criterion_group!(benches, paper_ball, demos);
criterion_main!(benches);
