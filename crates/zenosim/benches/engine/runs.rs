//! Whole runs of the paper's examples, written as Rust models, at `rtol = atol = 1e-10`.
//!
//! Target (issue: the engine): the paper's ball to `t = 6` in under 1 ms median on a 2-core
//! machine.

use criterion::Criterion;
use std::hint::black_box;
use zenosim::models::{BallOnSine, BouncingBall, CartPendulum, Example, SphericalPendulum};
use zenosim::{HybridLagrangian, Simulation, SimulationOptions, Trajectory};

fn options<M>(example: &Example<M>) -> SimulationOptions {
    SimulationOptions {
        t_end: example.t_end,
        ..Default::default()
    }
}

fn whole_run<M: HybridLagrangian>(c: &mut Criterion, name: &str, example: &Example<M>) {
    let sim = Simulation::new(
        &example.model,
        &example.q0,
        &example.q_dot0,
        options(example),
    )
    .expect("a valid example");
    let run = sim.run(&mut ());
    eprintln!(
        "{name}: {:?}, {} steps ({} rejected), {} rhs evaluations, {} impacts",
        run.outcome,
        run.stats.steps,
        run.stats.rejected_steps,
        run.stats.rhs_evals,
        run.stats.impacts
    );
    c.bench_function(name, |b| b.iter(|| black_box(sim.run(&mut ()))));
}

pub fn paper_ball(c: &mut Criterion) {
    let paper = BallOnSine::paper();
    whole_run(c, "paper ball to t=6 (record only)", &paper);
    let sim = Simulation::new(&paper.model, &paper.q0, &paper.q_dot0, options(&paper)).unwrap();
    c.bench_function("paper ball to t=6 (with the trajectory in memory)", |b| {
        b.iter(|| {
            let mut trajectory = Trajectory::default();
            black_box(sim.run(&mut trajectory));
            trajectory
        })
    });
}

pub fn demos(c: &mut Criterion) {
    whole_run(c, "demo ball on sine to t=20", &BallOnSine::demo());
    whole_run(c, "demo cart pendulum to t=40", &CartPendulum::demo());
    whole_run(
        c,
        "demo spherical pendulum to t=35",
        &SphericalPendulum::demo(),
    );
    let ball = Example {
        model: BouncingBall::new(1.0, 9.81, 0.8),
        q0: vec![1.0],
        q_dot0: vec![0.0],
        t_end: 10.0,
    };
    whole_run(c, "bouncing ball e=0.8 to t=10", &ball);
}
