//! How the cost of a run grows (issue: speed and accuracy, "Scaling"):
//! - `scaling/t_end`: with the stop time (the paper's ball, most of it on the surface);
//! - `scaling/impacts`: with the number of impacts before the Zeno point (the bouncing ball,
//!   `e` from 0.1 to 0.95: about `log(tolerance)/log(e)` impacts);
//! - `scaling/coordinates`: with the number of coordinates (a chain of `n` pendulums on a wall),
//!   one evaluation of the equations of motion and a whole run;
//! - `scaling/tolerance`: with the tolerance, the bouncing ball to just past its Zeno point
//!   (the target: the cost grows with `log(1/tolerance)`, not with `1/tolerance`; the
//!   deterministic check of it counts evaluations in `tests/engine/zeno_cost.rs`).
//!
//! Every case prints its impacts, steps and right-hand-side evaluations once, so the counts
//! appear with the times. The slow cases take few samples, to keep the whole binary's default
//! run short.

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, BenchmarkId, Criterion, SamplingMode};
use std::hint::black_box;
use std::time::Duration;
use zenosim::models::{BallOnSine, BouncingBall, PendulumChain};
use zenosim::{Derived, HybridLagrangian, Simulation, SimulationOptions, Tolerances};

/// The bouncing ball's drop height, for the cases that use it.
const H0: f64 = 1.0;

/// A group with few samples and short warm-up and measurement (criterion stretches the
/// measurement to fit 10 samples where a run is longer: the chain of 20 links takes seconds).
fn short_group<'a>(c: &'a mut Criterion, name: &str) -> BenchmarkGroup<'a, WallTime> {
    let mut group = c.benchmark_group(name);
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    group
}

/// Benchmarks a whole run of `sim` as `parameter` in `group` (named `name`), after printing
/// its counts once.
fn bench_run<L: HybridLagrangian>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    parameter: String,
    sim: &Simulation<'_, L>,
) {
    let run = sim.run(&mut ());
    eprintln!(
        "{name}/{parameter}: {}, {} impacts, {} Zeno points, {} steps ({} rejected), \
         {} rhs evaluations",
        run.outcome,
        run.stats.impacts,
        run.zeno.len(),
        run.stats.steps,
        run.stats.rejected_steps,
        run.stats.rhs_evals
    );
    group.bench_function(BenchmarkId::from_parameter(parameter), |b| {
        b.iter(|| black_box(sim.run(&mut ())))
    });
}

/// The paper's ball to `t_end` ∈ {3, 6, 12, 24, 48}: the Zeno point comes at about 2.04, and
/// the rest is constrained motion along the surface.
fn t_end(c: &mut Criterion) {
    let paper = BallOnSine::paper();
    const NAME: &str = "scaling/t_end";
    let mut group = short_group(c, NAME);
    for t_end in [3.0, 6.0, 12.0, 24.0, 48.0] {
        let options = SimulationOptions {
            t_end,
            ..Default::default()
        };
        let sim = Simulation::new(&paper.model, &paper.q0, &paper.q_dot0, options)
            .expect("a valid example");
        bench_run(&mut group, NAME, format!("{t_end}"), &sim);
    }
    group.finish();
}

/// The bouncing ball dropped from 1 m with `e` ∈ {0.1, …, 0.95}, to 0.5 s past its Zeno point.
fn impacts(c: &mut Criterion) {
    const NAME: &str = "scaling/impacts";
    let mut group = short_group(c, NAME);
    for e in [0.1, 0.3, 0.5, 0.7, 0.9, 0.95] {
        let ball = BouncingBall::new(1.0, 9.81, e);
        let options = SimulationOptions {
            t_end: ball.zeno_time(H0) + 0.5,
            ..Default::default()
        };
        let sim = Simulation::new(&ball, &[H0], &[0.0], options).expect("a valid ball");
        bench_run(&mut group, NAME, format!("e={e}"), &sim);
    }
    group.finish();
}

/// The chain of `n` pendulums on a wall ([`PendulumChain::example`]): one evaluation of the
/// free equations of motion (`M`, the force, the Cholesky solve) and a whole run to its stop
/// time.
fn coordinates(c: &mut Criterion) {
    const LINKS: [usize; 7] = [1, 2, 3, 5, 10, 15, 20];
    let chains: Vec<_> = LINKS.iter().map(|&n| PendulumChain::example(n)).collect();

    let mut group = short_group(c, "scaling/coordinates/acceleration");
    for chain in &chains {
        let derived = Derived::new(&chain.model).expect("n ≤ MAX_DIMENSION");
        // A moving state, so that no velocity term vanishes.
        let q_dot: Vec<f64> = (0..chain.model.links)
            .map(|i| 0.5 - 0.1 * i as f64)
            .collect();
        assert!(derived.acceleration(&chain.q0, &q_dot).is_some());
        group.bench_function(
            BenchmarkId::from_parameter(format!("n={}", chain.model.links)),
            |b| b.iter(|| derived.acceleration(black_box(&chain.q0), black_box(&q_dot))),
        );
    }
    group.finish();

    const NAME: &str = "scaling/coordinates/run";
    let mut group = short_group(c, NAME);
    // One run per iteration, the same number in every sample: the long runs are not repeated
    // in growing batches.
    group.sampling_mode(SamplingMode::Flat);
    for chain in &chains {
        let options = SimulationOptions {
            t_end: chain.t_end,
            ..Default::default()
        };
        let sim = Simulation::new(&chain.model, &chain.q0, &chain.q_dot0, options)
            .expect("a valid example");
        bench_run(&mut group, NAME, format!("n={}", chain.model.links), &sim);
    }
    group.finish();
}

/// The bouncing ball (`e = 0.5`, dropped from 1 m) to 0.01 s past its Zeno point at
/// `rtol = atol` ∈ {1e-4, …, 1e-12}.
fn tolerance(c: &mut Criterion) {
    let ball = BouncingBall::new(1.0, 9.81, 0.5);
    const NAME: &str = "scaling/tolerance";
    let mut group = short_group(c, NAME);
    for tol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        let options = SimulationOptions {
            t_end: ball.zeno_time(H0) + 0.01,
            tolerances: Tolerances {
                rtol: tol,
                atol: tol,
            },
            ..Default::default()
        };
        let sim = Simulation::new(&ball, &[H0], &[0.0], options).expect("a valid ball");
        bench_run(&mut group, NAME, format!("tol={tol:e}"), &sim);
    }
    group.finish();
}

pub fn benches(c: &mut Criterion) {
    t_end(c);
    impacts(c);
    coordinates(c);
    tolerance(c);
}
