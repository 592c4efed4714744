//! Regressions found by the random initial states of `zenosim-model`'s `tests/random_states.rs`
//! (issue 5); each test is named after what went wrong.

use zenosim::models::BallOnSine;
use zenosim::{
    Constraint, EventKind, HybridLagrangian, Mode, Observer, Outcome, OutputGrid, Sample, Scalar,
    Simulation, SimulationOptions,
};

/// A particle outside a fixed circle of radius `R` centred at the origin, under gravity `−y`:
/// `L = ½ (ẋ² + ẏ²) − g y`, `h = √(x² + y²) − R` (the shipped ball-off-cylinder without its
/// floor).
struct OutsideACircle {
    radius: f64,
    gravity: f64,
    constraints: [Constraint; 1],
}

impl OutsideACircle {
    /// The unit circle under `g = 9.81`, restitution 0.5, and the options of a run to `t = 4`
    /// sampled every `dt` (inside the steps, where a pass through the circle would show).
    fn unit(dt: f64) -> (Self, SimulationOptions) {
        let model = Self {
            radius: 1.0,
            gravity: 9.81,
            constraints: [Constraint::new("circle", 0.5)],
        };
        let options = SimulationOptions {
            t_end: 4.0,
            output: OutputGrid::Uniform(dt),
            ..Default::default()
        };
        (model, options)
    }
}

impl HybridLagrangian for OutsideACircle {
    const DIMENSION: Option<usize> = Some(2);
    fn dimension(&self) -> usize {
        2
    }
    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * self.gravity
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    #[inline]
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        (q[0] * q[0] + q[1] * q[1]).sqrt() - self.radius
    }
}

/// The lowest `h` of the samples.
#[derive(Default)]
struct Lowest {
    h: f64,
}

impl Observer for Lowest {
    fn sample(&mut self, s: &Sample<'_>) {
        self.h = self.h.min(s.h[0]);
    }
}

/// The random states found that a particle started on the circle, moving along it where the
/// circle has to push (gravity's normal part above the centripetal `v²/R`), fell straight
/// through the circle whenever the rounding of `A q̇` came out positive (`+1e-16`): the start
/// was taken for a crossing of a body moving away, the integrator restarted with a longer step,
/// and that step's samples of the dense output all lay outside the circle, before and after
/// the body's pass through it. A normal velocity at its rounding is no direction: with the free
/// motion pressing in, it is a contact (a chattering Zeno point at `t = 0`).
#[test]
fn a_start_on_a_surface_that_presses_is_a_contact_whatever_the_sign_of_the_rounding() {
    let (model, options) = OutsideACircle::unit(1e-3);
    let (radius, speed) = (model.radius, 1.5);
    let mut positive_rounding = 0;
    for degrees in 5..=60 {
        // On the circle, `alpha` from the top, moving along it away from the top: the circle
        // pushes while g cos α > v²/R (cos α ≥ 0.5 > 0.23).
        let alpha = f64::from(degrees).to_radians();
        let q = [-radius * alpha.sin(), radius * alpha.cos()];
        let v = [-speed * alpha.cos(), -speed * alpha.sin()];
        let normal = (q[0] * v[0] + q[1] * v[1]) / radius;
        if normal > 0.0 {
            positive_rounding += 1;
        }
        let mut lowest = Lowest::default();
        let run = Simulation::new(&model, &q, &v, options)
            .unwrap()
            .run(&mut lowest);
        assert_eq!(run.outcome, Outcome::Finished, "α = {degrees}°");
        assert!(
            lowest.h >= -1e-12,
            "α = {degrees}°: h = {:e} inside the circle",
            lowest.h
        );
        // The circle carries it from the start: held from t = 0 (issue 24), or, where the
        // rounding of A q̇ is beyond its bound, a chattering Zeno point at t = 0.
        assert!(
            run.zeno.iter().all(|z| z.t_switch < 1e-9),
            "α = {degrees}° (A q̇ = {normal:e}): {:?}",
            run.zeno
        );
        assert!(run
            .intervals
            .iter()
            .any(|i| matches!(i.mode, Mode::Constrained(_)) && i.start < 1e-9 && i.end > i.start));
    }
    // The rounding of A q̇ = 0 comes out positive for some of these starts.
    assert!(positive_rounding > 0);
}

/// The random states found that a particle started on the underside of the circle, moving into
/// it slowly while gravity pulls it away hard, passed through the circle's rim: it dips in
/// (`5.9e-6` deep for 2.4 ms here) and out again before the first sample of the first step's
/// dense output, and the search for dips took the start (`h = 0`) as no dip's beginning. A start
/// on the surface moving into it is an impact at `t = 0`.
#[test]
fn a_start_on_a_surface_moving_into_it_is_an_impact_however_soon_it_would_leave() {
    // Samples finer than the dips.
    let (model, options) = OutsideACircle::unit(1e-4);
    let radius = model.radius;
    for degrees in [30, 45, 60, 75] {
        for normal_speed in [1e-3, 1e-2, 1e-1] {
            // On the circle `beta` below the horizontal, moving along it at 0.4 and into it at
            // `normal_speed`; gravity pulls it off at g sin β.
            let beta = f64::from(degrees).to_radians();
            let (normal, tangent) = ([beta.cos(), -beta.sin()], [beta.sin(), beta.cos()]);
            let q = [radius * normal[0], radius * normal[1]];
            let v = [
                0.4 * tangent[0] - normal_speed * normal[0],
                0.4 * tangent[1] - normal_speed * normal[1],
            ];
            let mut lowest = Lowest::default();
            let run = Simulation::new(&model, &q, &v, options)
                .unwrap()
                .run(&mut lowest);
            let case = format!("β = {degrees}°, A q̇ = −{normal_speed}");
            assert_eq!(run.outcome, Outcome::Finished, "{case}");
            assert!(
                lowest.h >= -1e-12,
                "{case}: h = {:e} inside the circle",
                lowest.h
            );
            let first = &run.events[0];
            assert_eq!((first.kind, first.t), (EventKind::Impact, 0.0), "{case}");
            // Then it flies off: A q̇⁺ = e·normal_speed, and no further contact.
            let after = &first.after;
            let a_q_dot = (after.q[0] * after.q_dot[0] + after.q[1] * after.q_dot[1]) / radius;
            assert!(
                (a_q_dot - 0.5 * normal_speed).abs() < 1e-12 * (1.0 + normal_speed),
                "{case}: {a_q_dot}"
            );
            assert_eq!(run.events.len(), 1, "{case}");
        }
    }
}

/// The random states found the ball on the sine (the authors' demo, e = 0.9) passing through a
/// crest: after its second bounce it flies over the crest at x2 = −3π/2, sinks into the surface
/// beyond it (0.02 deep) and comes out again before landing further down the slope at t = 3.35,
/// all between two samples of one long step (a free flight is a polynomial, which the
/// integrator takes in long steps) whose slopes `ġ` are both negative: no sign change of `g` or
/// `ġ` showed it. The cubic through the samples' values and slopes, checked at the midpoint,
/// does.
#[test]
fn a_flight_over_a_crest_does_not_pass_through_the_slope_beyond_it() {
    let ex = BallOnSine::demo();
    // To the demo's own stop time: the steps' length depends on it.
    let options = SimulationOptions {
        t_end: ex.t_end,
        output: OutputGrid::Uniform(1e-3),
        ..Default::default()
    };
    let q = [-1.0, 3.8759625913093543, 2.2761942403230035];
    let v = [-3.0, -2.8419899111854883, 2.262383238664377];
    let mut lowest = Lowest::default();
    let run = Simulation::new(&ex.model, &q, &v, options)
        .unwrap()
        .run(&mut lowest);
    assert_eq!(run.outcome, Outcome::Finished);
    assert!(lowest.h >= -1e-12, "h = {:e} inside the surface", lowest.h);
    // It lands just past the crest instead, at t ≈ 2.93 (x2 ≈ −4.8), not at t = 3.35.
    let impacts = run.impact_times(0);
    assert!(impacts[2] > 2.9 && impacts[2] < 2.95, "{impacts:?}");
}
