//! A model read from a file against the same model written in Rust, over whole runs.
//!
//! Target (issue: model files): the paper's ball to `t = 6` at `rtol = atol = 1e-10` at most
//! 2× slower from its file than as the engine's Rust model. "interpreted" is the file model
//! without its compiled derivatives, for comparison. Run with
//! `cargo bench -p zenosim-model --bench file_vs_rust`.
//!
//! Also, for every shipped model file: one evaluation of its equations of motion and its whole
//! run to its stop time.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use zenosim::models::{BallOnSine, CartPendulum, Example, SphericalPendulum};
use zenosim::{Derived, HybridLagrangian, Simulation, SimulationOptions};
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

/// Every shipped model file: one evaluation of its equations of motion (free at the initial
/// state; constrained at its first Zeno point, if it reaches one), and its whole run to its
/// stop time (those of `pair` are already run there).
fn every_model(c: &mut Criterion) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../models");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("the models directory is readable")
        .filter_map(|entry| entry.ok()?.file_name().into_string().ok())
        .filter(|name| name.ends_with(".toml"))
        .collect();
    names.sort();
    for name in names {
        let file = load(&name);
        let label = &file.name;
        let derived = Derived::new(&file.model).expect("a valid model");
        let (q, q_dot) = (&file.initial.q, &file.initial.q_dot);
        let mut q_ddot = vec![0.0; q.len()];
        c.bench_function(&format!("equations of motion, free: {label} (file)"), |b| {
            b.iter(|| derived.write_acceleration(None, black_box(q), black_box(q_dot), &mut q_ddot))
        });
        let sim = Simulation::new(&file.model, q, q_dot, file.options()).expect("a valid model");
        let run = sim.run(&mut ());
        if let Some(zeno) = run.zeno.first() {
            let (q, q_dot) = (&zeno.point.q, &zeno.point.q_dot);
            let name = format!("equations of motion, constrained: {label} (file)");
            c.bench_function(&name, |b| {
                b.iter(|| {
                    derived.write_acceleration(
                        Some(zeno.constraint),
                        black_box(q),
                        black_box(q_dot),
                        &mut q_ddot,
                    )
                })
            });
        }
        if !PAIRED.contains(&name.as_str()) {
            bench_run(
                c,
                &format!("{label} (file)"),
                &file.model,
                q,
                q_dot,
                file.options(),
            );
        }
    }
}

/// The files run beside their Rust models in [`pair`].
const PAIRED: [&str; 3] = [
    "ball-on-sine.toml",
    "cart-pendulum.toml",
    "spherical-pendulum.toml",
];

fn paper_ball(c: &mut Criterion) {
    pair(c, "ball-on-sine.toml", &BallOnSine::paper());
}

fn demos(c: &mut Criterion) {
    pair(c, "cart-pendulum.toml", &CartPendulum::demo());
    pair(c, "spherical-pendulum.toml", &SphericalPendulum::demo());
}

criterion_group!(benches, paper_ball, demos, every_model);
criterion_main!(benches);
