//! Every error path: the setups that `Simulation::new` refuses, and the numerical failures that
//! end a run with `Outcome::Failed`, keeping everything computed before them.
//!
//! Each test checks the variant, its fields, and that the message names the thing (the
//! constraint, the option, the time) and says what to do about it.

use std::f64::consts::PI;
use zenosim::models::{BallOnSine, BouncingBall, SphericalPendulum};
use zenosim::{
    Completion, Constraint, Derived, Error, EventKind, Execution, HybridLagrangian, Outcome,
    OutputGrid, Scalar, Simulation, SimulationOptions, Tolerances, Trajectory, ZenoStrategy,
};

const G: f64 = 9.81;

/// The test models: a point in `dimension` coordinates with unit masses, gravity `G` along the
/// last coordinate that has a constraint, and one twist each.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Twist {
    /// `L = Σ ½ q̇ᵢ²`, `h = q1` (any dimension, for the dimension checks).
    Plain,
    /// `L = ½ ẋ² − G x` with no kinetic term in `y`: `M` is singular everywhere.
    NoKineticTerm,
    /// `L = ½(ẋ² + ẏ²) − G y − 0.1 (3 − x)^(3/2)`, `h = y`: `L` is NaN for `x > 3`, and the
    /// force `0.15 √(3 − x)` pulls the ball there while it bounces on `y = 0`. The force stays
    /// finite up to `x = 3` (with `√(3 − x)` itself it would be singular there, and the step
    /// could underflow on the singularity before any trial met a NaN).
    NanPastThree,
    /// `L = ½(ẋ² + ẏ² + x ẋ ẏ) + x − G y`, `h = y`: `M = [[1, x/2], [x/2, 1]]` loses
    /// positive definiteness at `x = 2`, which the constant force `+1` along `x` reaches.
    MassLosesDefiniteness,
    /// `L = ½ ẋ² − G x`, `h = x` written through `.re()`: the automatic derivatives see
    /// `∂h/∂q = 0` everywhere.
    GuardWithoutDerivative,
    /// `L = ½ ẋ² − G x`, `h = x³`: `∂h/∂q = 3x² = 0` on `h = 0`.
    Cubic,
    /// `L = ½ ẋ² − G x`, `h = atan x`, with a completion map that throws `x` to 100, from where
    /// Newton's method on `atan` diverges.
    AtanWithBadMap,
}

struct Toy {
    twist: Twist,
    dimension: usize,
    constraints: Vec<Constraint>,
}

impl Toy {
    fn new(twist: Twist, dimension: usize, names: &[&str], restitution: f64) -> Self {
        Self {
            twist,
            dimension,
            constraints: names
                .iter()
                .map(|n| Constraint::new(*n, restitution))
                .collect(),
        }
    }
}

impl HybridLagrangian for Toy {
    fn dimension(&self) -> usize {
        self.dimension
    }

    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        let kinetic = |v: &[D]| v.iter().fold(D::from(0.0), |acc, &x| acc + x * x * 0.5);
        match self.twist {
            Twist::Plain => kinetic(v),
            Twist::NoKineticTerm => v[0] * v[0] * 0.5 - q[0] * G,
            Twist::NanPastThree => {
                let gap = D::from(3.0) - q[0];
                kinetic(v) - q[1] * G - gap.sqrt() * gap * 0.1
            }
            Twist::MassLosesDefiniteness => kinetic(v) + q[0] * v[0] * v[1] * 0.5 + q[0] - q[1] * G,
            Twist::GuardWithoutDerivative | Twist::Cubic | Twist::AtanWithBadMap => {
                v[0] * v[0] * 0.5 - q[0] * G
            }
        }
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        match self.twist {
            Twist::Plain | Twist::NoKineticTerm => q[0],
            Twist::NanPastThree | Twist::MassLosesDefiniteness => q[1],
            Twist::GuardWithoutDerivative => D::from(q[0].re()),
            Twist::Cubic => q[0].powi(3),
            Twist::AtanWithBadMap => q[0].atan(),
        }
    }

    fn completion_map(&self, _index: usize, q: &mut [f64], _q_dot: &mut [f64]) -> bool {
        if self.twist == Twist::AtanWithBadMap {
            q[0] = 100.0;
            true
        } else {
            false
        }
    }
}

fn options(t_end: f64) -> SimulationOptions {
    SimulationOptions {
        t_end,
        ..Default::default()
    }
}

fn refused<L: HybridLagrangian>(
    model: &L,
    q0: &[f64],
    q_dot0: &[f64],
    options: SimulationOptions,
) -> Error {
    match Simulation::new(model, q0, q_dot0, options) {
        Ok(_) => panic!("the setup q0 = {q0:?}, q_dot0 = {q_dot0:?}, {options:?} was accepted"),
        Err(e) => e,
    }
}

fn run<L: HybridLagrangian>(
    model: &L,
    q0: &[f64],
    q_dot0: &[f64],
    options: SimulationOptions,
) -> (Execution, Trajectory) {
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(model, q0, q_dot0, options)
        .expect("a valid setup")
        .run(&mut trajectory);
    (run, trajectory)
}

fn failure(run: &Execution) -> &Error {
    match &run.outcome {
        Outcome::Failed(e) => e,
        other => panic!(
            "expected a failure, the run ended {other:?} at t = {}",
            run.t_final
        ),
    }
}

/// The time a run-time error names.
fn error_time(e: &Error) -> f64 {
    match e {
        Error::SingularMassMatrix { t, .. }
        | Error::DegenerateConstraint { t, .. }
        | Error::NonFinite { t }
        | Error::StepSizeUnderflow { t, .. }
        | Error::ContactProblem { t, .. }
        | Error::ContactSolver { t, .. }
        | Error::Projection { t, .. }
        | Error::Limit { t, .. } => *t,
        other => panic!("not a run-time error: {other:?}"),
    }
}

fn assert_says(e: &Error, parts: &[&str]) {
    let message = e.to_string();
    for part in parts {
        assert!(
            message.contains(part),
            "the message lacks {part:?}: {message}"
        );
    }
}

/// Everything up to the failure is kept: the record ends at the failure time, the hybrid time
/// domain is contiguous up to it, every event is before it, and the observer saw the state the
/// record ends with. The message says when.
fn assert_kept_up_to_failure(run: &Execution, trajectory: &Trajectory) -> f64 {
    let e = failure(run);
    let t = error_time(e);
    assert_says(e, &[&format!("at t = {t}")]);
    assert!(
        (run.t_final - t).abs() <= 1e-12 * (1.0 + t.abs()),
        "the record ends at t_final = {} but the failure is at t = {t} ({e})",
        run.t_final
    );
    let last = run.intervals.last().expect("at least one interval");
    assert_eq!(last.end, run.t_final);
    assert_eq!(run.intervals[0].start, 0.0);
    for pair in run.intervals.windows(2) {
        assert_eq!(
            pair[0].end, pair[1].start,
            "the hybrid time domain has a gap"
        );
    }
    assert_eq!(run.intervals.len(), run.events.len() + 1);
    assert!(run.events.iter().all(|ev| ev.t <= t));
    let seen = trajectory.points.last().expect("samples");
    assert_eq!(seen.t, run.t_final, "the observer's last sample");
    assert_eq!(
        (&seen.q, &seen.q_dot),
        (&run.final_state.q, &run.final_state.q_dot)
    );
    t
}

// ----- setup errors ----------------------------------------------------------------------

#[test]
fn restitution_outside_zero_one_is_refused() {
    for e in [-0.1, 1.5, f64::NAN] {
        let ball = BouncingBall::new(1.0, G, e);
        let err = refused(&ball, &[1.0], &[0.0], options(1.0));
        match &err {
            Error::Restitution { constraint, value } => {
                assert_eq!(constraint, "floor");
                assert!(value == &e || (e.is_nan() && value.is_nan()));
            }
            other => panic!("e = {e}: {other:?}"),
        }
        assert_says(&err, &["'floor'", &format!("{e}"), "must lie in [0, 1]"]);
    }
    // The bounds themselves are allowed.
    for e in [0.0, 1.0] {
        assert!(
            Simulation::new(&BouncingBall::new(1.0, G, e), &[1.0], &[0.0], options(1.0)).is_ok()
        );
    }
}

#[test]
fn an_initial_state_below_a_constraint_is_refused() {
    let err = refused(
        &BouncingBall::new(1.0, G, 0.5),
        &[-0.1],
        &[0.0],
        options(1.0),
    );
    assert_eq!(
        err,
        Error::Inadmissible {
            constraint: "floor".into(),
            h: -0.1
        }
    );
    assert_says(
        &err,
        &[
            "'floor'",
            "h = -1e-1",
            "start on the admissible side h >= 0",
        ],
    );

    // The paper's ball half a unit below the sinusoid: h = 0.5 − sin(π/2) = −0.5.
    let ball = BallOnSine::paper().model;
    let err = refused(&ball, &[0.0, PI / 2.0, 0.5], &[0.0; 3], options(1.0));
    assert!(
        matches!(&err, Error::Inadmissible { constraint, h } if constraint == "surface" && (h + 0.5).abs() < 1e-15),
        "{err:?}"
    );
    assert_says(&err, &["'surface'", "admissible side"]);
}

#[test]
fn a_lagrangian_without_kinetic_term_in_a_coordinate_is_refused() {
    let model = Toy::new(Twist::NoKineticTerm, 2, &["floor"], 0.5);
    let err = refused(&model, &[1.0, 0.0], &[0.0, 0.3], options(1.0));
    assert_eq!(
        err,
        Error::SingularMassMatrix {
            t: 0.0,
            q: vec![1.0, 0.0],
            q_dot: vec![0.0, 0.3]
        }
    );
    assert_says(
        &err,
        &[
            "at t = 0",
            "not positive definite",
            "every coordinate needs a kinetic term",
        ],
    );

    // The spherical pendulum started on its pole θ = 0 (M = m l² diag(1, sin²θ)).
    let pendulum = SphericalPendulum::demo().model;
    let err = refused(&pendulum, &[0.0, 0.0], &[0.1, 1.0], options(1.0));
    assert!(
        matches!(err, Error::SingularMassMatrix { t: 0.0, .. }),
        "{err:?}"
    );
    assert_says(&err, &["coordinate singularities"]);
}

#[test]
fn initial_vectors_of_the_wrong_length_are_refused() {
    let ball = BallOnSine::paper().model;
    let err = refused(&ball, &[0.0, 1.0], &[0.0; 3], options(1.0));
    assert_eq!(
        err,
        Error::Length {
            what: "q0",
            got: 2,
            expected: 3
        }
    );
    assert_says(
        &err,
        &[
            "q0 has 2 entries",
            "3 coordinates",
            "give one value per coordinate",
        ],
    );

    let err = refused(&ball, &[0.0, 1.0, 2.0], &[0.0; 4], options(1.0));
    assert_eq!(
        err,
        Error::Length {
            what: "q_dot0",
            got: 4,
            expected: 3
        }
    );
    assert_says(
        &err,
        &["q_dot0 has 4 entries", "give one value per coordinate"],
    );
}

#[test]
fn a_non_finite_initial_state_is_refused() {
    let ball = BallOnSine::paper().model;
    for (q0, q_dot0, what, index, shown) in [
        ([0.0, f64::NAN, 2.0], [0.0; 3], "q0", 1, "q0[1] is NaN"),
        (
            [0.0, 1.0, 2.0],
            [0.0, f64::INFINITY, 0.0],
            "q_dot0",
            1,
            "q_dot0[1] is inf",
        ),
        (
            [f64::NEG_INFINITY, 1.0, 2.0],
            [0.0; 3],
            "q0",
            0,
            "q0[0] is -inf",
        ),
    ] {
        let err = refused(&ball, &q0, &q_dot0, options(1.0));
        assert!(
            matches!(err, Error::NonFiniteInitialState { what: w, index: i, .. } if w == what && i == index),
            "{err:?} for {q0:?} {q_dot0:?}"
        );
        // The message names the entry and says what to do.
        assert_says(&err, &[shown, "give finite initial values"]);
    }
}

/// A [`Toy`] whose type declares two coordinates, whatever it has.
struct DeclaresTwo(Toy);

impl HybridLagrangian for DeclaresTwo {
    const DIMENSION: Option<usize> = Some(2);

    fn dimension(&self) -> usize {
        self.0.dimension()
    }

    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        self.0.lagrangian(q, v)
    }

    fn constraints(&self) -> &[Constraint] {
        self.0.constraints()
    }

    fn constraint<D: Scalar>(&self, index: usize, q: &[D]) -> D {
        self.0.constraint(index, q)
    }
}

#[test]
fn a_declared_dimension_must_be_the_model_s() {
    // The mechanics of `DeclaresTwo` are compiled for two coordinates only: three are refused
    // at setup, never run into code that was not compiled.
    let model = DeclaresTwo(Toy::new(Twist::Plain, 3, &["floor"], 0.5));
    let q = [1.0; 3];
    let err = refused(&model, &q, &q, options(1.0));
    assert_eq!(
        err,
        Error::DeclaredDimension {
            declared: 2,
            dimension: 3
        }
    );
    assert_says(
        &err,
        &["DIMENSION = Some(2)", "dimension() is 3", "make them agree"],
    );
    assert!(matches!(
        Derived::new(&model),
        Err(Error::DeclaredDimension {
            declared: 2,
            dimension: 3
        })
    ));
    assert_eq!(zenosim::Compiled::trace(&model).coverage().0, 0);
    // Two: a free fall onto the floor q1 = 0 and on, past its Zeno point.
    let model = DeclaresTwo(Toy::new(Twist::Plain, 2, &["floor"], 0.5));
    let compiled = zenosim::Compiled::trace(&model);
    assert_eq!(compiled.coverage().0, compiled.coverage().1);
    let sim = Simulation::new(&model, &[1.0, 0.0], &[-1.0, 0.5], options(3.0)).unwrap();
    let run = sim.run(&mut ());
    assert!(run.stats.impacts >= 1, "{:?}", run.outcome);
}

#[test]
fn dimensions_outside_one_to_max_dimension_are_refused() {
    let max = zenosim::MAX_DIMENSION;
    for n in [0, max + 1] {
        let model = Toy::new(Twist::Plain, n, &["floor"], 0.5);
        let q = vec![1.0; n];
        let err = refused(&model, &q, &q, options(1.0));
        assert_eq!(err, Error::Dimension { dimension: n, max });
        assert_says(
            &err,
            &[
                &format!("{n} coordinates"),
                &format!("1 to {max}"),
                "reduce the model",
            ],
        );
        // The derived quantities refuse it too.
        assert!(
            matches!(Derived::new(&model), Err(Error::Dimension { dimension, max: m }) if dimension == n && m == max)
        );
    }
    // 1 and MAX_DIMENSION are fine.
    for n in [1, max] {
        let model = Toy::new(Twist::Plain, n, &["floor"], 0.5);
        assert!(Simulation::new(&model, &vec![1.0; n], &vec![0.0; n], options(1.0)).is_ok());
    }
}

#[test]
fn a_model_without_constraints_or_with_too_many_is_refused() {
    let none = Toy::new(Twist::Plain, 1, &[], 0.5);
    let err = refused(&none, &[1.0], &[0.0], options(1.0));
    assert_eq!(err, Error::ConstraintCount { count: 0, max: 64 });
    assert_says(&err, &["0 constraints", "needs 1 to 64"]);

    let names: Vec<String> = (0..65).map(|i| format!("c{i}")).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let many = Toy::new(Twist::Plain, 1, &names, 0.5);
    let err = refused(&many, &[1.0], &[0.0], options(1.0));
    assert_eq!(err, Error::ConstraintCount { count: 65, max: 64 });
    assert_says(&err, &["65 constraints", "needs 1 to 64"]);
}

#[test]
fn invalid_options_are_refused_by_name() {
    let ball = BouncingBall::new(1.0, G, 0.5);
    let base = options(1.0);
    let tol = |rtol: f64, atol: f64| SimulationOptions {
        tolerances: Tolerances { rtol, atol },
        ..base
    };
    let cases: Vec<(SimulationOptions, &str, f64, &str)> = vec![
        (options(0.0), "t_end", 0.0, "stop time > 0"),
        (options(-1.0), "t_end", -1.0, "stop time > 0"),
        (options(f64::NAN), "t_end", f64::NAN, "finite stop time"),
        (
            options(f64::INFINITY),
            "t_end",
            f64::INFINITY,
            "finite stop time",
        ),
        (tol(-1e-10, 1e-10), "rtol", -1e-10, "relative tolerance > 0"),
        (
            tol(f64::NAN, 1e-10),
            "rtol",
            f64::NAN,
            "relative tolerance > 0",
        ),
        (tol(1e-10, -1e-10), "atol", -1e-10, "absolute tolerance > 0"),
        (tol(1e-10, 0.0), "atol", 0.0, "absolute tolerance > 0"),
        (tol(1e-16, 1e-10), "rtol", 1e-16, "at least 1e-15"),
        (
            SimulationOptions {
                zeno: ZenoStrategy::Epsilon(0.0),
                ..base
            },
            "zeno epsilon",
            0.0,
            "threshold ε > 0",
        ),
        (
            SimulationOptions {
                zeno: ZenoStrategy::Epsilon(-1e-3),
                ..base
            },
            "zeno epsilon",
            -1e-3,
            "threshold ε > 0",
        ),
        (
            SimulationOptions {
                zeno: ZenoStrategy::Epsilon(f64::NAN),
                ..base
            },
            "zeno epsilon",
            f64::NAN,
            "threshold ε > 0",
        ),
        (
            SimulationOptions {
                output: OutputGrid::Uniform(0.0),
                ..base
            },
            "dt",
            0.0,
            "sampling interval > 0",
        ),
        (
            SimulationOptions {
                output: OutputGrid::Uniform(-0.1),
                ..base
            },
            "dt",
            -0.1,
            "sampling interval > 0",
        ),
        (
            SimulationOptions {
                output: OutputGrid::Uniform(f64::NAN),
                ..base
            },
            "dt",
            f64::NAN,
            "finite sampling interval",
        ),
        // 10⁹ samples over t_end = 1, more than the default 10⁷ steps allow.
        (
            SimulationOptions {
                output: OutputGrid::Uniform(1e-9),
                ..base
            },
            "dt",
            1e-9,
            "t_end / dt ≤ max_steps",
        ),
        (
            SimulationOptions {
                max_step: 0.0,
                ..base
            },
            "max_step",
            0.0,
            "largest step > 0",
        ),
        (
            SimulationOptions {
                max_step: f64::NAN,
                ..base
            },
            "max_step",
            f64::NAN,
            "largest step > 0",
        ),
    ];
    for (opts, name, value, expected) in cases {
        // The options are checked before anything else (here with a valid model and state).
        assert!(matches!(opts.validate(), Err(Error::Option { option, .. }) if option == name));
        let err = refused(&ball, &[1.0], &[0.0], opts);
        match &err {
            Error::Option {
                option, value: v, ..
            } => {
                assert_eq!(*option, name, "{err}");
                assert!(v == &value || (v.is_nan() && value.is_nan()), "{err}");
            }
            other => panic!("{name} = {value}: {other:?}"),
        }
        assert_says(
            &err,
            &[
                &format!("option {name} = {}", zenosim::Readable(value)),
                "invalid",
                expected,
            ],
        );
    }
    // The smallest relative tolerance is allowed.
    assert!(tol(1e-15, 1e-15).validate().is_ok());
}

// ----- failures during a run -------------------------------------------------------------

/// A mass matrix that stops being positive definite where the run goes:
/// `M = [[1, x/2], [x/2, 1]]` with `det M = 1 − x²/4`, and a force pulling `x` to 2.
#[test]
fn a_mass_matrix_that_loses_definiteness_during_the_run() {
    let model = Toy::new(Twist::MassLosesDefiniteness, 2, &["floor"], 0.9);
    let (run, trajectory) = run(&model, &[0.0, 1.0], &[0.5, 0.0], options(20.0));
    let t = assert_kept_up_to_failure(&run, &trajectory);
    let err = failure(&run);
    match err {
        Error::SingularMassMatrix { q, .. } => {
            // Where it fails, det M = 1 − x²/4 is (close to) 0.
            assert!((q[0] - 2.0).abs() < 1e-6, "{err}");
        }
        other => panic!("{other:?}"),
    }
    assert_says(
        err,
        &[
            "not positive definite",
            "q = ",
            "every coordinate needs a kinetic term",
        ],
    );
    // The impacts before it are kept.
    assert!(run.events.iter().any(|e| e.kind == EventKind::Impact));
    assert!(
        t > 1.0,
        "the failure comes after the ball has moved towards x = 2: t = {t}"
    );
}

/// The spherical pendulum driven through its pole `θ = 0`, where `M = m l² diag(1, sin²θ)` is
/// singular. With `φ̇ = 0` the motion is a planar pendulum: the coordinates go on through the
/// pole to `θ < 0` (`L` and `h = cos θ` are even in `θ`, and `M` is singular at `θ = 0` only),
/// so the run must carry on with its energy conserved — or, if a stage lands on the pole, fail
/// with a message that says when. With a small `φ̇` the bob passes near the axis instead,
/// conserving `p_φ = m l² sin²θ φ̇`.
#[test]
fn the_spherical_pendulum_through_its_pole() {
    let ex = SphericalPendulum::demo();
    let model = &ex.model;
    let d = Derived::new(model).unwrap();
    for phi_dot in [0.0, 1e-3] {
        let (run, trajectory) = run(model, &[0.3, 0.0], &[-2.0, phi_dot], options(10.0));
        // The pole is a singularity of the coordinates, not of the motion: with φ̇ = 0 the
        // motion is planar and passes it; with a little φ̇ it swings round it.
        assert_eq!(run.outcome, Outcome::Finished, "φ̇0 = {phi_dot}");
        // It got to (or through) the pole: θ = 0.3 with θ̇ = −2 has energy to spare over the top
        // (½ θ̇² = 2 > (g/l)(1 − cos 0.3) = 0.043).
        let theta_min = trajectory
            .points
            .iter()
            .map(|p| p.q[0])
            .fold(f64::INFINITY, f64::min);
        if phi_dot == 0.0 {
            assert!(theta_min < 0.0, "passed the pole: min θ = {theta_min}");
            assert!(
                trajectory.points.iter().all(|p| p.q_dot[1] == 0.0),
                "planar motion"
            );
        } else {
            assert!(theta_min.abs() < 0.05, "near the pole: min θ = {theta_min}");
        }
        // Energy conserved between events (free flight, default tolerances).
        let mut e_start = d.energy(&[0.3, 0.0], &[-2.0, phi_dot]);
        let mut events = run.events.iter().peekable();
        for p in &trajectory.points {
            if let Some(ev) = events.peek() {
                if p.t == ev.t && p.q_dot == ev.after.q_dot {
                    e_start = d.energy(&ev.after.q, &ev.after.q_dot);
                    events.next();
                    continue;
                }
            }
            let e = d.energy(&p.q, &p.q_dot);
            assert!(
                (e - e_start).abs() <= 1e-6 * (1.0 + e_start.abs()),
                "φ̇0 = {phi_dot}: energy {e} at t = {} (θ = {}) vs {e_start}",
                p.t,
                p.q[0]
            );
        }
        // p_φ conserved (φ is cyclic).
        let p0 = model.momentum_phi(&[0.3, 0.0], &[-2.0, phi_dot]);
        for p in &trajectory.points {
            let pp = model.momentum_phi(&p.q, &p.q_dot);
            assert!(
                (pp - p0).abs() <= 1e-7 * (1.0 + p0.abs()),
                "p_φ {pp} vs {p0} at t = {}",
                p.t
            );
        }
    }
}

/// A Lagrangian that is NaN past `x = 3`, reached at `t ≈ 2.39` while the ball bounces.
#[test]
fn a_lagrangian_that_turns_nan_during_the_run() {
    let model = Toy::new(Twist::NanPastThree, 2, &["floor"], 0.9);
    let (run, trajectory) = run(&model, &[0.0, 1.0], &[1.0, 0.0], options(10.0));
    let t = assert_kept_up_to_failure(&run, &trajectory);
    let err = failure(&run);
    assert!(matches!(err, Error::NonFinite { .. }), "{err:?}");
    // The failure is where x reaches 3: before t = 3 (ẋ ≥ 1, the pull only speeds it up), and
    // after t = 2 (the pull's work 0.1·3^(3/2) from x = 0 raises ẋ to at most √(1 + 1.04) < 1.5).
    assert!(
        (run.final_state.q[0] - 3.0).abs() < 1e-6,
        "x = {} at the failure",
        run.final_state.q[0]
    );
    assert!(t > 2.0 && t < 3.0, "t = {t}");
    // The impacts before it are kept (first at √(2/g) = 0.45, the next 2e·√(2g)/g later).
    let impacts = run.impact_times(0);
    assert!(impacts.len() >= 3, "{impacts:?}");
    assert!(
        (impacts[0] - (2.0 / G).sqrt()).abs() < 1e-9,
        "first impact at {} (closed form √(2/g))",
        impacts[0]
    );
    assert_says(err, &["not finite", "check the model"]);
}

/// `max_events = 5` on the bouncing ball dropped from 1 (e = 0.5): the 6th impact, at
/// `τ_6` of the closed form, is refused.
#[test]
fn the_event_limit_stops_the_run_after_exactly_that_many_events() {
    let ball = BouncingBall::new(1.0, G, 0.5);
    let opts = SimulationOptions {
        max_events: 5,
        ..options(10.0)
    };
    let (run, trajectory) = run(&ball, &[1.0], &[0.0], opts);
    let err = failure(&run).clone();
    match &err {
        Error::Limit {
            t,
            what,
            limit,
            recent,
        } => {
            assert_eq!((*what, *limit), ("events", 5));
            let tau6 = ball.impact_time(1.0, 6);
            assert!(
                (t - tau6).abs() < 1e-9,
                "refused at {t}, closed-form 6th impact {tau6}"
            );
            // The five events kept came between the first impact and the refused sixth.
            let (count, span) = recent.expect("the event limit says how quickly events came");
            assert_eq!(count, 5);
            assert!(
                (span - (tau6 - ball.impact_time(1.0, 1))).abs() < 1e-9,
                "{span}"
            );
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(run.events.len(), 5);
    // The refused impact is not counted.
    assert_eq!(run.stats.impacts, 5);
    for (k, ev) in run.events.iter().enumerate() {
        assert_eq!(ev.kind, EventKind::Impact);
        assert!((ev.t - ball.impact_time(1.0, k as u32 + 1)).abs() < 1e-9);
    }
    assert_says(
        &err,
        &[
            "limit of 5 events",
            "the last 5 of them within",
            "raise max_events",
        ],
    );
    assert_kept_up_to_failure(&run, &trajectory);
}

/// `max_steps = N` stops the run after exactly `N` accepted steps, whether or not the last of
/// them ended at an event (swept over `N = 1..=30` on the bouncing ball: every other limit
/// falls on a step that contains an impact).
#[test]
fn the_step_limit_stops_the_run() {
    let ball = BouncingBall::new(1.0, G, 0.5);
    for limit in 1..=30u64 {
        let opts = SimulationOptions {
            max_steps: limit,
            ..options(10.0)
        };
        let (run, trajectory) = run(&ball, &[1.0], &[0.0], opts);
        let err = failure(&run).clone();
        assert!(
            matches!(err, Error::Limit { what: "steps", limit: l, .. } if l == limit),
            "{err:?}"
        );
        assert_says(
            &err,
            &[&format!("limit of {limit} steps"), "raise max_steps"],
        );
        assert_kept_up_to_failure(&run, &trajectory);
        assert!(run.t_final > 0.0 && run.t_final < 10.0);
        assert_eq!(
            run.stats.steps,
            limit,
            "accepted steps against max_steps = {limit} ({} events, t_final = {})",
            run.events.len(),
            run.t_final
        );
    }
}

#[test]
fn a_constraint_with_zero_gradient_is_degenerate() {
    let model = Toy::new(Twist::GuardWithoutDerivative, 1, &["flat"], 0.5);
    let (run, trajectory) = run(&model, &[1.0], &[0.0], options(5.0));
    let err = failure(&run).clone();
    match &err {
        Error::DegenerateConstraint { t, constraint } => {
            assert_eq!(constraint, "flat");
            // At the first contact, √(2 h0/g) (closed form).
            assert!((t - (2.0 / G).sqrt()).abs() < 1e-9, "t = {t}");
        }
        other => panic!("{other:?}"),
    }
    assert_says(
        &err,
        &[
            "'flat'",
            "∂h/∂q = 0",
            "write h so that its gradient does not vanish",
        ],
    );
    assert!(run.events.is_empty());
    assert_kept_up_to_failure(&run, &trajectory);
}

/// `h = x³`: `∂h/∂q = 3x² = 0` on `h = 0`, where the constraint has to act. The engine must say
/// so (`DegenerateConstraint`) at the first contact, `t = √(2/g)`, rather than go on with
/// multipliers and Zeno predictions computed from a vanishing gradient.
#[test]
fn a_constraint_whose_gradient_vanishes_on_its_surface_is_degenerate() {
    let model = Toy::new(Twist::Cubic, 1, &["cubic"], 0.5);
    let (run, trajectory) = run(&model, &[1.0], &[0.0], options(3.0));
    let err = match &run.outcome {
        Outcome::Failed(e) => e.clone(),
        other => panic!(
            "h = x³ ran to {other:?} with events {:?}",
            run.events
                .iter()
                .map(|e| (e.kind.name(), e.t))
                .collect::<Vec<_>>()
        ),
    };
    assert!(
        matches!(&err, Error::DegenerateConstraint { constraint, t } if constraint == "cubic" && (t - (2.0 / G).sqrt()).abs() < 1e-9),
        "{err:?}; events before it: {:?}",
        run.events
            .iter()
            .map(|e| (e.kind.name(), e.t, e.after.q_dot[0]))
            .collect::<Vec<_>>()
    );
    assert_says(
        &err,
        &["'cubic'", "write h so that its gradient does not vanish"],
    );
    assert_kept_up_to_failure(&run, &trajectory);
}

/// The model's completion map throws `x` to 100, where Newton's method on `h = atan x`
/// diverges: the switch to the constrained motion cannot put the state on `h = 0`.
#[test]
fn a_projection_that_does_not_converge() {
    let model = Toy::new(Twist::AtanWithBadMap, 1, &["atan"], 0.5);
    let opts = SimulationOptions {
        completion: Completion::ModelMap,
        ..options(5.0)
    };
    let (run, trajectory) = run(&model, &[1.0], &[0.0], opts);
    let err = failure(&run).clone();
    match &err {
        Error::Projection {
            constraint,
            residual,
            t,
        } => {
            assert_eq!(constraint, "atan");
            assert!(*residual > 1e-12, "{residual}");
            // At the switch, just before τ∞ = √(2/g)·3 (closed form, e = 0.5).
            let tau = (2.0 / G).sqrt() * 3.0;
            assert!(*t <= tau && tau - t < 1e-6, "t = {t}, τ∞ = {tau}");
        }
        other => panic!("{other:?}"),
    }
    assert_says(&err, &["'atan'", "left |h| ="]);
    assert!(
        run.events
            .iter()
            .filter(|e| e.kind == EventKind::Impact)
            .count()
            >= 10
    );
    assert_kept_up_to_failure(&run, &trajectory);
}
