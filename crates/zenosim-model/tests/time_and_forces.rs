//! Time, generalized forces and dissipation in model files: `t` in `L`, in `h` and in
//! `zeno_reset`, `[forces]` and `dissipation`, evaluated over `f64` and dual numbers against
//! values worked out by hand; which models are autonomous.

use std::path::PathBuf;

use approx::assert_relative_eq;
use num_dual::Dual64;
use zenosim::HybridLagrangian;
use zenosim_model::{parse_model, ModelFile};

/// A pendulum `theta` driven by a torque, and a mass `x` on a spring whose anchor shakes, above
/// a floor that moves; damped by a force and by a dissipation function.
const DRIVEN: &str = r#"name = "driven"
coordinates = ["theta", "x"]
lagrangian = "0.5*m*l^2*theta_dot^2 + 0.5*m*x_dot^2 + m*g*l*cos(theta) - 0.5*k*(x - a*sin(w*t))^2"
dissipation = "0.5*c*x_dot^2 + 0.25*c*x^2*theta_dot^2"

[parameters]
m = 2.0
l = 0.5
g = 9.81
c = 0.3
tau0 = 1.5
w = 2.0
k = 4.0
a = 0.1

[forces]
theta = "-c*theta_dot + tau0*sin(w*t)"

[[constraint]]
name = "floor"
h = "x + 1 - 0.05*sin(w*t)"
restitution = 0.5
zeno_reset = { x = "0.05*sin(w*t) - 1", x_dot = "0.05*w*cos(w*t)" }

[initial]
theta = 0.3
x_dot = 0.2
"#;

const C: f64 = 0.3;
const TAU0: f64 = 1.5;
const W: f64 = 2.0;
const K: f64 = 4.0;
const A: f64 = 0.1;

fn load(source: &str) -> ModelFile {
    parse_model("driven.toml", source, &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// The state the values are checked at.
const T: f64 = 0.7;
const Q: [f64; 2] = [0.4, -0.2];
const Q_DOT: [f64; 2] = [1.1, -0.6];

#[test]
fn the_formulas_are_read() {
    let file = load(DRIVEN);
    let model = &file.model;
    assert_eq!(model.time_slot(), 4);
    assert_eq!(
        model.force_formula(0).map(|f| f.source()),
        Some("-c*theta_dot + tau0*sin(w*t)")
    );
    assert!(model.force_formula(1).is_none(), "x has no force");
    assert_eq!(
        model.dissipation_formula().map(|f| f.source()),
        Some("0.5*c*x_dot^2 + 0.25*c*x^2*theta_dot^2")
    );
    assert!(model.lagrangian_formula().reads(4), "L reads t");
    assert!(model.constraint_formula(0).reads(4), "h reads t");
    assert!(!model.is_autonomous());
}

#[test]
fn generalized_forces_over_f64_and_dual_numbers() {
    let model = load(DRIVEN).model;
    // The force is added to what is there; x has none.
    let mut force = [1.0, 2.0];
    model.generalized_force(T, &Q, &Q_DOT, &mut force);
    let theta = -C * Q_DOT[0] + TAU0 * (W * T).sin();
    assert_relative_eq!(force[0], 1.0 + theta, max_relative = 1e-15);
    assert_eq!(force[1], 2.0);

    // Over dual numbers, seeded on theta_dot: ∂Q/∂θ̇ = −c.
    let q = Q.map(Dual64::from);
    let q_dot = [Dual64::new(Q_DOT[0], 1.0), Dual64::from(Q_DOT[1])];
    let mut force = [Dual64::from(0.0); 2];
    model.generalized_force(Dual64::from(T), &q, &q_dot, &mut force);
    assert_eq!(force[0].re, model_force_f64(&model));
    assert_relative_eq!(force[0].eps, -C, max_relative = 1e-15);
    assert_eq!((force[1].re, force[1].eps), (0.0, 0.0));

    // Seeded on t: ∂Q/∂t = τ0 w cos(w t).
    let mut force = [Dual64::from(0.0); 2];
    model.generalized_force(
        Dual64::new(T, 1.0),
        &Q.map(Dual64::from),
        &Q_DOT.map(Dual64::from),
        &mut force,
    );
    assert_relative_eq!(force[0].eps, TAU0 * W * (W * T).cos(), max_relative = 1e-14);
}

/// The force on theta over `f64`, from zero.
fn model_force_f64(model: &zenosim_model::FileModel) -> f64 {
    let mut force = [0.0; 2];
    model.generalized_force(T, &Q, &Q_DOT, &mut force);
    force[0]
}

#[test]
fn the_dissipation_function_over_f64_and_dual_numbers() {
    let model = load(DRIVEN).model;
    let (x, theta_dot, x_dot) = (Q[1], Q_DOT[0], Q_DOT[1]);
    let d = model.dissipation(T, &Q, &Q_DOT);
    let expected = 0.5 * C * x_dot * x_dot + 0.25 * C * x * x * theta_dot * theta_dot;
    assert_relative_eq!(d, expected, max_relative = 1e-15);

    // ∂D/∂ẋ = c ẋ and ∂D/∂θ̇ = c x² θ̇ / 2: the forces −∂D/∂q̇ the engine derives.
    let q = Q.map(Dual64::from);
    let seeded = |i: usize| {
        let mut q_dot = Q_DOT.map(Dual64::from);
        q_dot[i].eps = 1.0;
        model.dissipation(Dual64::from(T), &q, &q_dot)
    };
    let by_theta_dot = seeded(0);
    let by_x_dot = seeded(1);
    assert_eq!(by_theta_dot.re, d);
    assert_relative_eq!(
        by_theta_dot.eps,
        0.5 * C * x * x * theta_dot,
        max_relative = 1e-14
    );
    assert_relative_eq!(by_x_dot.eps, C * x_dot, max_relative = 1e-15);
    // It does not depend on t.
    let by_t = model.dissipation(Dual64::new(T, 1.0), &q, &Q_DOT.map(Dual64::from));
    assert_eq!(by_t.eps, 0.0);
}

#[test]
fn the_time_in_the_lagrangian_and_the_constraint() {
    let model = load(DRIVEN).model;
    let (theta, x) = (Q[0], Q[1]);
    let spring = x - A * (W * T).sin();
    let l = 0.5 * 2.0 * 0.25 * Q_DOT[0] * Q_DOT[0]
        + 0.5 * 2.0 * Q_DOT[1] * Q_DOT[1]
        + 2.0 * 9.81 * 0.5 * theta.cos()
        - 0.5 * K * spring * spring;
    assert_relative_eq!(model.lagrangian_at(T, &Q, &Q_DOT), l, max_relative = 1e-14);
    // ∂L/∂t = k (x − a sin(w t)) a w cos(w t).
    let dl_dt = model.lagrangian_at(
        Dual64::new(T, 1.0),
        &Q.map(Dual64::from),
        &Q_DOT.map(Dual64::from),
    );
    assert_relative_eq!(
        dl_dt.eps,
        K * spring * A * W * (W * T).cos(),
        max_relative = 1e-14
    );
    // h(t, q) = x + 1 − 0.05 sin(w t), ∂h/∂t = −0.05 w cos(w t).
    let h = model.constraint_at(0, T, &Q);
    assert_relative_eq!(h, x + 1.0 - 0.05 * (W * T).sin(), max_relative = 1e-15);
    let dh_dt = model.constraint_at(0, Dual64::new(T, 1.0), &Q.map(Dual64::from));
    assert_relative_eq!(dh_dt.eps, -0.05 * W * (W * T).cos(), max_relative = 1e-14);
    // ∂h/∂x = 1.
    let dh_dx = model.constraint_at(
        0,
        Dual64::from(T),
        &[Dual64::from(theta), Dual64::new(x, 1.0)],
    );
    assert_eq!(dh_dx.eps, 1.0);
    // Without a time, the functions are those at t = 0.
    assert_eq!(
        model.lagrangian(&Q, &Q_DOT).to_bits(),
        model.lagrangian_at(0.0, &Q, &Q_DOT).to_bits()
    );
    assert_eq!(
        model.constraint(0, &Q).to_bits(),
        model.constraint_at(0, 0.0, &Q).to_bits()
    );
}

#[test]
fn the_zeno_reset_at_a_time() {
    let model = load(DRIVEN).model;
    let (mut q, mut q_dot) = (Q, Q_DOT);
    assert!(model.completion_map_at(0, T, &mut q, &mut q_dot));
    assert_eq!(q[0], Q[0]);
    assert_relative_eq!(q[1], 0.05 * (W * T).sin() - 1.0, max_relative = 1e-15);
    assert_eq!(q_dot[0], Q_DOT[0]);
    assert_relative_eq!(q_dot[1], 0.05 * W * (W * T).cos(), max_relative = 1e-15);
    // On the moving floor.
    assert!(model.constraint_at(0, T, &q).abs() < 1e-15);
    let (mut q0, mut q_dot0) = (Q, Q_DOT);
    assert!(model.completion_map(0, &mut q0, &mut q_dot0));
    assert_eq!((q0[1], q_dot0[1]), (-1.0, 0.05 * W));
}

/// `DRIVEN` with `from` replaced by `to` (which must occur).
fn driven_with(from: &str, to: &str) -> String {
    assert!(DRIVEN.contains(from), "{from:?} is not in the model");
    DRIVEN.replacen(from, to, 1)
}

/// `DRIVEN` with every feature but `keep` removed.
fn only(keep: &str) -> String {
    let mut source = DRIVEN.to_string();
    let removals: [(&str, &str, &str); 5] = [
        ("lagrangian", " - 0.5*k*(x - a*sin(w*t))^2", " - 0.5*k*x^2"),
        ("h", "h = \"x + 1 - 0.05*sin(w*t)\"", "h = \"x + 1\""),
        (
            "zeno_reset",
            "zeno_reset = { x = \"0.05*sin(w*t) - 1\", x_dot = \"0.05*w*cos(w*t)\" }\n",
            "",
        ),
        (
            "forces",
            "[forces]\ntheta = \"-c*theta_dot + tau0*sin(w*t)\"\n",
            "",
        ),
        (
            "dissipation",
            "dissipation = \"0.5*c*x_dot^2 + 0.25*c*x^2*theta_dot^2\"\n",
            "",
        ),
    ];
    for (feature, from, to) in removals {
        assert!(source.contains(from), "{from}");
        if feature != keep {
            source = source.replacen(from, to, 1);
        }
    }
    source
}

#[test]
fn a_model_is_autonomous_without_time_forces_and_dissipation() {
    assert!(load(&only("none")).model.is_autonomous());
    for feature in ["lagrangian", "h", "zeno_reset", "forces", "dissipation"] {
        assert!(
            !load(&only(feature)).model.is_autonomous(),
            "{feature} makes the model non-autonomous"
        );
    }
    // A reset that does not read t keeps the model autonomous.
    let source = only("none").replace(
        "[initial]",
        "[[constraint]]\nname = \"stop\"\nh = \"2 - x\"\nrestitution = 0.5\nzeno_reset = { x = \"2\" }\n\n[initial]",
    );
    assert!(load(&source).model.is_autonomous());
    // An empty [forces] table gives no force.
    let source = only("none").replace("[initial]", "[forces]\n\n[initial]");
    assert!(load(&source).model.is_autonomous());
}

#[test]
fn forces_may_be_numbers_and_depend_on_anything() {
    let source = driven_with(
        "theta = \"-c*theta_dot + tau0*sin(w*t)\"",
        "theta = -1.5\nx = \"-k*x*theta + x_dot*t\"",
    );
    let model = load(&source).model;
    let mut force = [0.0; 2];
    model.generalized_force(T, &Q, &Q_DOT, &mut force);
    assert_eq!(force[0], -1.5);
    assert_relative_eq!(
        force[1],
        -K * Q[1] * Q[0] + Q_DOT[1] * T,
        max_relative = 1e-15
    );
}

#[test]
fn only_constant_forces_keep_free_flight_a_parabola() {
    let ball = |forces: &str| {
        let source = format!(
            "name = \"ball\"\ncoordinates = [\"x\", \"y\"]\nlagrangian = \"0.5*(x_dot^2 + y_dot^2)\"\n\n\
             [forces]\n{forces}\n\n[[constraint]]\nname = \"floor\"\nh = \"y\"\nrestitution = 0.5\n\n\
             [initial]\ny = 1.0\n"
        );
        load(&source).model
    };
    assert!(ball("y = -9.81").parabolic_flight());
    assert!(!ball("y = \"-9.81*cos(t)\"").parabolic_flight());
    assert!(!ball("y = \"-9.81 - x_dot\"").parabolic_flight());
}

/// The repository's `models/` folder.
fn models_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

/// The shipped models with forces, dissipation or time (docs/forces-and-time.md).
const NOT_AUTONOMOUS: [&str; 4] = [
    "damped-oscillator.toml",
    "dragged-ball.toml",
    "pd-arm.toml",
    "vibrating-table.toml",
];

#[test]
fn every_other_shipped_model_is_autonomous_and_the_same_at_every_time() {
    let mut count = 0;
    for entry in std::fs::read_dir(models_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let source = std::fs::read_to_string(&path).unwrap();
        let file = parse_model(&name, &source, &[]).unwrap_or_else(|e| panic!("{e}"));
        let model = &file.model;
        if NOT_AUTONOMOUS.contains(&name.as_str()) {
            assert!(!model.is_autonomous(), "{name}");
            continue;
        }
        count += 1;
        assert!(model.is_autonomous(), "{name}");
        assert!(model.dissipation_formula().is_none(), "{name}");
        let n = model.dimension();
        assert!((0..n).all(|i| model.force_formula(i).is_none()), "{name}");
        // `_at` is the function without time, bit for bit, at any time and over dual numbers.
        let (q, q_dot) = (&file.initial.q, &file.initial.q_dot);
        let q_dot: Vec<f64> = q_dot
            .iter()
            .enumerate()
            .map(|(i, v)| v + 0.1 * i as f64)
            .collect();
        assert_eq!(
            model.lagrangian_at(123.4, q, &q_dot).to_bits(),
            model.lagrangian(q, &q_dot).to_bits(),
            "{name}"
        );
        let qd: Vec<Dual64> = q.iter().map(|&v| Dual64::new(v, 1.0)).collect();
        let vd: Vec<Dual64> = q_dot.iter().map(|&v| Dual64::new(v, 0.5)).collect();
        let at = model.lagrangian_at(Dual64::new(7.0, 1.0), &qd, &vd);
        let plain = model.lagrangian(&qd, &vd);
        assert_eq!(
            (at.re.to_bits(), at.eps.to_bits()),
            (plain.re.to_bits(), plain.eps.to_bits()),
            "{name}"
        );
        for index in 0..model.constraints().len() {
            let at = model.constraint_at(index, Dual64::new(-3.0, 1.0), &qd);
            let plain = model.constraint(index, &qd);
            assert_eq!(
                (at.re.to_bits(), at.eps.to_bits()),
                (plain.re.to_bits(), plain.eps.to_bits()),
                "{name}: h{index}"
            );
        }
        let mut force = vec![0.0; n];
        model.generalized_force(1.0, q, &q_dot, &mut force);
        assert!(force.iter().all(|&f| f == 0.0), "{name}");
        assert_eq!(model.dissipation(1.0, q, &q_dot), 0.0, "{name}");
    }
    assert!(count >= 10, "the shipped models are there ({count})");
}
