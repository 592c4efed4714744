//! Lift-off: the constraint lets go when its force would have to pull (`λ` reaches 0), and
//! impacts resume when the body lands again (REFERENCE §2).

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
