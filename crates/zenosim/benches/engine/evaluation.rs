//! One evaluation of each Rust model's equations of motion (free, and constrained at its Zeno
//! point), and event location on one step's dense output.

use std::hint::black_box;

use criterion::Criterion;
use zenosim::events::first_crossing;
use zenosim::integrator::{Method, OdeSystem, Stepper};
use zenosim::models::{BallOnSine, BouncingBall, CartPendulum, Example, SphericalPendulum};
use zenosim::{Derived, HybridLagrangian, Simulation, SimulationOptions, Tolerances};

pub fn benches(c: &mut Criterion) {
    equations_of_motion(c, "paper ball", &BallOnSine::paper());
    equations_of_motion(c, "bouncing ball", &bouncing_ball());
    equations_of_motion(c, "cart pendulum", &CartPendulum::demo());
    equations_of_motion(c, "spherical pendulum", &SphericalPendulum::demo());
    event_location(c);
}

/// The classic ball, dropped from 1 m with e = 0.8.
fn bouncing_ball() -> Example<BouncingBall> {
    Example {
        model: BouncingBall::new(1.0, 9.81, 0.8),
        q0: vec![1.0],
        q_dot0: vec![0.0],
        t_end: 10.0,
    }
}

/// `q̈` at the initial state (free) and at the state after the first Zeno point (constrained),
/// through the same code the engine calls at every stage of a step.
fn equations_of_motion<M: HybridLagrangian>(c: &mut Criterion, name: &str, example: &Example<M>) {
    let derived = Derived::new(&example.model).expect("a valid example");
    let mut q_ddot = vec![0.0; example.q0.len()];
    c.bench_function(&format!("equations of motion, free: {name}"), |b| {
        b.iter(|| {
            derived.write_acceleration(
                None,
                black_box(&example.q0),
                black_box(&example.q_dot0),
                &mut q_ddot,
            )
        })
    });
    let options = SimulationOptions {
        t_end: example.t_end,
        ..Default::default()
    };
    let run = Simulation::new(&example.model, &example.q0, &example.q_dot0, options)
        .expect("a valid example")
        .run(&mut ());
    let zeno = run.zeno.first().expect("the example reaches a Zeno point");
    let (q, q_dot) = (&zeno.point.q, &zeno.point.q_dot);
    c.bench_function(&format!("equations of motion, constrained: {name}"), |b| {
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

/// The paper's ball as a first-order system `y = (q, q̇)`.
struct Free<'a> {
    derived: Derived<'a, BallOnSine>,
}

impl OdeSystem for Free<'_> {
    type Error = ();

    fn dimension(&self) -> usize {
        6
    }

    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
        dy[..3].copy_from_slice(&y[3..]);
        let (q, q_dot) = y.split_at(3);
        self.derived
            .write_acceleration(None, q, q_dot, &mut dy[3..])
            .map(|_| ())
            .ok_or(())
    }
}

/// Locating an impact on one step: on a closed-form parabola (the locator alone), a whole
/// flight inside one step (found from the samples' slopes), and the paper ball's first fall
/// on a DOP853 step's dense output (the guard `h = x3 − sin x2` and `ḣ` from the
/// interpolated state, as the engine evaluates them).
fn event_location(c: &mut Criterion) {
    let g = 9.81;
    // Dropped from 1 m: the floor at t = √(2/g) ≈ 0.45 inside a step of 1 s.
    c.bench_function("event location: parabola, crossing inside the step", |b| {
        b.iter(|| {
            first_crossing(0.0, black_box(1.0), |t| {
                (1.0 - 0.5 * g * t * t, Some(-g * t))
            })
        })
    });
    // Thrown up at 0.1 m/s from the floor: back at t ≈ 0.02, no sign change at the samples.
    c.bench_function("event location: a whole flight inside the step", |b| {
        b.iter(|| {
            first_crossing(0.0, black_box(1.0), |t| {
                (0.1 * t - 0.5 * g * t * t, Some(0.1 - g * t))
            })
        })
    });

    let example = BallOnSine::paper();
    let derived = Derived::new(&example.model).expect("a valid example");
    let mut system = Free { derived };
    let mut stepper = Stepper::new(Method::Dop853, 6, Tolerances::default());
    let y0: Vec<f64> = example.q0.iter().chain(&example.q_dot0).copied().collect();
    stepper
        .start(&mut system, 0.0, &y0, Some(1.0))
        .expect("the start is regular");
    stepper.step(&mut system, 1.0, 1.0).expect("a step");
    stepper.prepare_dense(&mut system).expect("dense output");
    let (t0, t1) = (stepper.t_previous(), stepper.t());
    let mut y = [0.0; 6];
    let mut guard = |t: f64| {
        stepper.interpolate(t, &mut y);
        let (x2, x3, v2, v3) = (y[1], y[2], y[4], y[5]);
        (x3 - x2.sin(), Some(v3 - x2.cos() * v2))
    };
    let crossing = first_crossing(t0, t1, &mut guard).expect("the ball lands in this step");
    eprintln!(
        "paper ball's first step: [{t0}, {t1}], impact at t = {}",
        crossing.t_admissible
    );
    c.bench_function("event location: paper ball, DOP853 dense output", |b| {
        b.iter(|| first_crossing(black_box(t0), t1, &mut guard))
    });
}
