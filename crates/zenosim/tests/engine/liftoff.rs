//! Lift-off: the constraint lets go when its force would have to pull (`λ` reaches 0), and
//! impacts resume when the body lands again (docs/contact-laws.md, law 1).

use zenosim::models::BallOnSine;
use zenosim::{
    Constraint, Derived, EventKind, HybridLagrangian, Mode, Outcome, Scalar, Simulation,
    SimulationOptions, Trajectory,
};

/// A particle on the outside of a frictionless circle of radius `R` centred at the origin:
/// `L = ½ m (ẋ² + ẏ²) − m g y`, `h = √(x² + y²) − R`.
struct ParticleOnCircle {
    radius: f64,
    gravity: f64,
    constraints: [Constraint; 1],
}

impl HybridLagrangian for ParticleOnCircle {
    const DIMENSION: Option<usize> = Some(2);
    fn dimension(&self) -> usize {
        2
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * self.gravity
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        (q[0] * q[0] + q[1] * q[1]).sqrt() - self.radius
    }
}

#[test]
fn a_particle_sliding_off_a_circle_leaves_where_the_closed_form_says() {
    let (radius, gravity, v0) = (1.0, 9.81, 1.0);
    let model = ParticleOnCircle {
        radius,
        gravity,
        constraints: [Constraint::new("circle", 0.5)],
    };
    // At rest on the top but for a push v0 along the surface: the circle carries it from the
    // start (held from t = 0, no impact and no Zeno point: issue 24), it slides, and it lets
    // go.
    let options = SimulationOptions {
        t_end: 1.5,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&model, &[0.0, radius], &[v0, 0.0], options)
        .unwrap()
        .run(&mut trajectory);
    assert_eq!(run.outcome, Outcome::Finished);
    assert!(run.zeno.is_empty(), "{:?}", run.zeno);
    assert!(matches!(run.intervals[0].mode, Mode::Constrained(_)));
    assert_eq!(run.intervals[0].start, 0.0);
    let kinds: Vec<_> = run.events.iter().map(|e| e.kind).collect();
    assert_eq!(kinds, [EventKind::Liftoff]);

    // Closed form: energy v² = v0² + 2 g R (1 − cos θ) and zero normal force
    // g cos θ = v²/R give cos θ* = 2/3 + v0²/(3 g R), v*² = g R cos θ*.
    let cos_star = 2.0 / 3.0 + v0 * v0 / (3.0 * gravity * radius);
    let liftoff = &run.events[0];
    let (q, q_dot) = (&liftoff.after.q, &liftoff.after.q_dot);
    let cos_theta = q[1] / radius;
    let speed2 = q_dot[0] * q_dot[0] + q_dot[1] * q_dot[1];
    assert!(
        (cos_theta - cos_star).abs() < 1e-9,
        "{cos_theta} vs {cos_star}"
    );
    assert!(
        (speed2 - gravity * radius * cos_star).abs() < 1e-8,
        "{speed2}"
    );
    // On the surface at the moment it leaves, moving along it.
    let derived = Derived::new(&model).unwrap();
    assert!(derived.constraint(0, q).0.abs() < 1e-12);
    assert!(derived.normal_velocity(0, q, q_dot).abs() < 1e-12);
    // Before lift-off the circle pushes (λ ≤ 0); after it, free flight clear of the circle.
    for p in &trajectory.points {
        if p.t < liftoff.t && matches!(p.mode, Mode::Constrained(_)) {
            assert!(p.lambda[0] <= 0.0, "{p:?}");
        }
        if p.t > liftoff.t {
            assert_eq!(p.mode, Mode::Free);
            assert!(p.h[0] > 0.0, "{p:?}");
        }
    }
}

#[test]
fn a_ball_that_flies_off_a_crest_lands_and_bounces_again() {
    let model = BallOnSine::new(1.0, 9.81, 0.6);
    // On the surface in a trough, fast along it: it slides up, leaves the surface before the
    // crest (there sin(x2) ẋ2² > g), flies, lands on the far side and settles again.
    let (x2, x2_dot) = (-std::f64::consts::FRAC_PI_2, 8.0);
    let q0 = [0.0, x2, x2.sin()];
    let q_dot0 = [0.0, x2_dot, x2.cos() * x2_dot];
    let options = SimulationOptions {
        t_end: 6.0,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&model, &q0, &q_dot0, options)
        .unwrap()
        .run(&mut trajectory);
    assert_eq!(run.outcome, Outcome::Finished);
    let first_liftoff = run
        .events
        .iter()
        .position(|e| e.kind == EventKind::Liftoff)
        .expect("the ball must lift off");
    let after: Vec<_> = run.events[first_liftoff + 1..]
        .iter()
        .map(|e| e.kind)
        .collect();
    assert_eq!(after.first(), Some(&EventKind::Impact), "{after:?}");
    assert!(
        after.contains(&EventKind::Zeno),
        "it settles again: {after:?}"
    );
    // Never through the surface, never gaining energy.
    let e0 = trajectory.points[0].energy;
    for p in &trajectory.points {
        assert!(p.h[0] >= -1e-9, "{p:?}");
        assert!(p.energy <= e0 + 1e-8, "{p:?}");
    }
}

/// A body resting on a floor `z ≥ 0` whose load a rotor modulates: `L = ½ ż² + ½ φ̇² − g z +
/// a z sin φ`. On the floor the rotor turns uniformly (`φ̈ = a z cos φ = 0`), and the floor
/// carries `g − a sin φ`: with `a = 2 g` it lets go where `sin φ` first reaches ½ (closed form).
struct RotorOnFloor {
    constraints: [Constraint; 1],
}

impl HybridLagrangian for RotorOnFloor {
    const DIMENSION: Option<usize> = Some(2);
    fn dimension(&self) -> usize {
        2
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[0] * 9.81 + q[0] * q[1].sin() * 19.62
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0]
    }
}

/// Regression: a lift-off was searched inside a held step only where the margins at its ends
/// did not rule one out, and those of an autonomous model were never sampled inside it. The
/// rotor's angle is linear in time, so the held steps grew to many turns, and the load's dips
/// between two ends that held were missed: from φ0 = 4.0 at 1 rad/s the body lifted off at
/// t = 9.09 instead of 2.81, from φ0 = 3.2 at 2 rad/s never. The margin is now sampled at
/// every held step's middle and the next step bounded by its curvature, as for models that
/// depend on time.
#[test]
fn a_lift_off_inside_a_long_held_step_was_missed() {
    use std::f64::consts::PI;
    for (phi0, omega) in [(4.0, 1.0), (3.2, 2.0), (3.2, 0.5), (4.6, 1.0), (3.6, 2.0)] {
        let model = RotorOnFloor {
            constraints: [Constraint::new("floor", 0.5)],
        };
        let options = SimulationOptions {
            t_end: 60.0,
            ..Default::default()
        };
        let run = Simulation::new(&model, &[0.0, phi0], &[0.0, omega], options)
            .unwrap()
            .run(&mut ());
        // The first angle past φ0 where sin φ = ½ on its way up: π/6 + 2πk.
        let k = ((phi0 - PI / 6.0) / (2.0 * PI)).ceil();
        let expected = (PI / 6.0 + 2.0 * PI * k - phi0) / omega;
        let lift = run.events.iter().find(|e| e.kind == EventKind::Liftoff);
        let t = lift.map(|e| e.t);
        assert!(
            t.is_some_and(|t| (t - expected).abs() < 1e-8),
            "φ0 = {phi0}, ω = {omega}: lifted off at {t:?}, expected {expected}"
        );
    }
}
