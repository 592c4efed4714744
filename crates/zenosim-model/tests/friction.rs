//! Coulomb friction from model files (docs/friction.md): the shipped frictional models against
//! their closed forms, and every way a `friction` or `slip` key is refused.

use std::path::PathBuf;

use zenosim::{EventKind, Execution, Outcome, Simulation, Trajectory};
use zenosim_model::{parse_model, ModelError, ModelFile, Override};

const G: f64 = 9.81;

fn load(name: &str, overrides: &[(&str, &str)]) -> ModelFile {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../models/{name}.toml"));
    let source = std::fs::read_to_string(&path).unwrap();
    let overrides: Vec<Override> = overrides
        .iter()
        .map(|(name, value)| Override {
            name: name.to_string(),
            value: value.to_string(),
        })
        .collect();
    parse_model(&format!("{name}.toml"), &source, &overrides).unwrap()
}

fn run(file: &ModelFile) -> (Execution, Trajectory) {
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(
        &file.model,
        &file.initial.q,
        &file.initial.q_dot,
        file.options(),
    )
    .unwrap()
    .run(&mut trajectory);
    (run, trajectory)
}

fn times(run: &Execution, kind: EventKind) -> Vec<f64> {
    run.events
        .iter()
        .filter(|e| e.kind == kind)
        .map(|e| e.t)
        .collect()
}

/// models/ball-backspin.toml: it sticks at its first impact (the slip stops there), leaves
/// rolling at `(5 ẋ₀ − 2 r θ̇₀)/7`, and reaches the bouncing ball's Zeno point; with `μ = 0.02`
/// it slides through the Zeno point and rolls from `t_Z + |s_Z|/((7/2) μ g)`.
#[test]
fn the_ball_with_backspin_sticks_or_slides_through_its_zeno_point() {
    let (r, e, y0, v0, w0) = (0.1, 0.5, 1.0, 1.0, -20.0);
    let t1 = f64::sqrt(2.0 * (y0 - r) / G);
    let t_zeno = t1 * (1.0 + e) / (1.0 - e);
    let rolling = (5.0 * v0 - 2.0 * r * w0) / 7.0;

    let (sticking, _) = run(&load("ball-backspin", &[]));
    assert_eq!(sticking.outcome, Outcome::Finished, "{}", sticking.outcome);
    let first = sticking
        .events
        .iter()
        .find(|e| e.kind == EventKind::Impact)
        .unwrap();
    assert!((first.t - t1).abs() < 1e-12, "{first:?}");
    assert!((first.after.q_dot[0] - rolling).abs() < 1e-12, "{first:?}");
    assert!(
        (sticking.zeno[0].t_zeno - t_zeno).abs() < 1e-9,
        "{:?}",
        sticking.zeno
    );
    let end = &sticking.final_state;
    assert!((end.q_dot[0] - rolling).abs() < 1e-9, "{end:?}");
    assert!((end.q_dot[0] + r * end.q_dot[2]).abs() < 1e-9, "{end:?}");

    let mu = 0.02;
    let (sliding, trajectory) = run(&load("ball-backspin", &[("mu", "0.02")]));
    assert_eq!(sliding.outcome, Outcome::Finished, "{}", sliding.outcome);
    let v1 = G * t1;
    let s_zeno = v0 + r * w0 + 3.5 * mu * (1.0 + e) * v1 / (1.0 - e);
    let t_stick = t_zeno + s_zeno.abs() / (3.5 * mu * G);
    assert_eq!(times(&sliding, EventKind::Stick).len(), 1);
    let stick = times(&sliding, EventKind::Stick)[0];
    assert!((stick - t_stick).abs() < 1e-8, "{stick} against {t_stick}");
    assert!((sliding.final_state.q_dot[0] - rolling).abs() < 1e-9);
    // Friction took energy out, and the balance with its work closes.
    let last = trajectory.points.last().unwrap();
    assert!(last.work.friction < 0.0, "{:?}", last.work);
    assert!(
        trajectory.balance_residual() < 1e-8,
        "{}",
        trajectory.balance_residual()
    );
}

/// models/rough-incline.toml: with `μ > tan α` the block stops at `v₀/(g (μ cos α − sin α))`
/// and stays; with `μ = 0.2 < tan α` it slides on, accelerating at `g (sin α − μ cos α)`.
#[test]
fn the_block_on_the_rough_incline_stops_or_slides_on() {
    let (alpha, v0, t_end) = (0.3_f64, 2.0, 3.0);
    let (run_stop, _) = run(&load("rough-incline", &[]));
    let decel = G * (0.5 * alpha.cos() - alpha.sin());
    let t_stop = v0 / decel;
    assert_eq!(times(&run_stop, EventKind::Stick), [run_stop.events[0].t]);
    assert!(
        (run_stop.events[0].t - t_stop).abs() < 1e-9,
        "{:?}",
        run_stop.events
    );
    let x_stop = v0 * t_stop - 0.5 * decel * t_stop * t_stop;
    assert!((run_stop.final_state.q[0] - x_stop).abs() < 1e-9);
    assert_eq!(run_stop.final_state.q_dot[0], 0.0);

    let (run_slide, _) = run(&load("rough-incline", &[("mu", "0.2")]));
    assert!(run_slide.events.is_empty(), "{:?}", run_slide.events);
    let a = G * (alpha.sin() - 0.2 * alpha.cos());
    let end = &run_slide.final_state;
    assert!(
        (end.q[0] - (v0 * t_end + 0.5 * a * t_end * t_end)).abs() < 1e-9,
        "{end:?}"
    );
    assert!((end.q_dot[0] - (v0 + a * t_end)).abs() < 1e-9, "{end:?}");
}

/// models/belt-stick-slip.toml: the first slip ends where the block's velocity is the belt's,
/// `sin ω t = v_b/(c ω)` (`c = μₖ g/k`, `ω = √k`); it sticks until `k x = μₛ g`; then slips on the
/// ellipse about `c` to `x = 2c − x_slip`; the cycle repeats.
#[test]
fn the_block_on_the_belt_sticks_and_slips() {
    let (k, v_b, mu_s, mu_k) = (4.0_f64, 0.5, 0.6, 0.4);
    let (run, trajectory) = run(&load("belt-stick-slip", &[]));
    assert_eq!(run.outcome, Outcome::Finished);
    let omega = k.sqrt();
    let c = mu_k * G / k;
    let t_stick = (v_b / (c * omega)).asin() / omega;
    let x_stick = c * (1.0 - (omega * t_stick).cos());
    let x_slip = mu_s * G / k;
    let t_slip = t_stick + (x_slip - x_stick) / v_b;
    // The slip from x_slip at v_b: x − c = a cos(ω τ + φ), back at ẋ = v_b after
    // ω τ = −π − 2 φ (mod 2π).
    let phase = (-v_b / omega).atan2(x_slip - c);
    let tau = ((-std::f64::consts::PI - 2.0 * phase) / omega)
        .rem_euclid(2.0 * std::f64::consts::PI / omega);
    let period = tau + 2.0 * (x_slip - c) / v_b;
    let sticks = times(&run, EventKind::Stick);
    let slips = times(&run, EventKind::Slip);
    assert_eq!((sticks.len(), slips.len()), (3, 2), "{:?}", run.events);
    let expected_sticks = [t_stick, t_slip + tau, t_slip + tau + period];
    let expected_slips = [t_slip, t_slip + period];
    for (t, expected) in sticks.iter().zip(expected_sticks) {
        assert!((t - expected).abs() < 1e-8, "{t} against {expected}");
    }
    for (t, expected) in slips.iter().zip(expected_slips) {
        assert!((t - expected).abs() < 1e-8, "{t} against {expected}");
    }
    // The belt does work through friction, sticking or slipping (fₜ s₀, s₀ = −v_b): the
    // balance counted only fₜ s and was 17.8 off.
    assert!(
        trajectory.balance_residual() < 1e-8,
        "{}",
        trajectory.balance_residual()
    );
}

/// models/painleve-rod.toml: `1 + 3 cos²θ − 3 μ sin θ cos θ < 0` while it slides towards its
/// lower end: the run fails at once, naming the contact; with little friction it slides.
#[test]
fn the_rod_at_painleves_paradox_fails_and_names_the_contact() {
    let (run_paradox, _) = run(&load("painleve-rod", &[]));
    match &run_paradox.outcome {
        Outcome::Failed(zenosim::Error::Painleve { constraints, .. }) => {
            assert_eq!(constraints, &["end".to_string()])
        }
        other => panic!("expected Painlevé's paradox, got {other:?}"),
    }
    let (run_slide, _) = run(&load("painleve-rod", &[("mu", "0.1")]));
    assert_eq!(
        run_slide.outcome,
        Outcome::Finished,
        "{}",
        run_slide.outcome
    );
}

/// models/housner-block.toml against `models/references/housner-block.json`
/// (`bench/references/housner.py`: the energy integral about each corner by quadrature and
/// Housner's ratio, summed to the Zeno point in 50 digits): every corner impact sticks and
/// scales the angular velocity by `1 − (3/2) sin²α`; the impact times follow the reference,
/// and the block comes to rest flat on both corners at the Zeno point, without slipping.
#[test]
fn housners_rocking_block_comes_to_rest_at_its_zeno_point() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../models/references/housner-block.json");
    let reference: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let number = |v: &serde_json::Value| v.as_str().unwrap().parse::<f64>().unwrap();
    let ratio = number(&reference["ratio"]);
    let (b, c) = (0.2_f64, 0.5_f64);
    assert!((ratio - (1.0 - 1.5 * (b / c).atan().sin().powi(2))).abs() < 1e-15);
    let (run, trajectory) = run(&load("housner-block", &[]));
    assert_eq!(run.outcome, Outcome::Finished, "{}", run.outcome);
    let impacts: Vec<_> = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Impact)
        .collect();
    let times = reference["impacts"].as_array().unwrap();
    assert!(impacts.len() >= 50, "{}", impacts.len());
    for (k, (impact, t_ref)) in impacts.iter().zip(times).enumerate() {
        let t_ref = number(t_ref);
        let (before, after) = (impact.before.q_dot[2], impact.after.q_dot[2]);
        // The integration's error, which accumulates over the flights (1e-10 relative, the
        // default tolerance, each), plus the rounding of the gap (64 ε of its terms, about
        // 1 m) over the speed the corner strikes at, `2b |θ̇|` (it is 2b from the pivot).
        let bound = 2e-9 + 64.0 * f64::EPSILON / (2.0 * b * before.abs());
        assert!(
            (impact.t - t_ref).abs() < bound,
            "impact {k}: {} against {t_ref}",
            impact.t
        );
        assert!(
            (after / before - ratio).abs() < 1e-12,
            "impact {k}: {}",
            after / before
        );
    }
    let zeno = &run.zeno[0];
    let t_zeno = number(&reference["t_zeno"]);
    // τ∞ extrapolates the tail as geometric, which it is only in the limit.
    assert!(
        (zeno.t_zeno - t_zeno).abs() < 1e-8,
        "{zeno:?} against {t_zeno}"
    );
    assert_eq!(run.zeno.len(), 1, "{:?}", run.zeno);
    let end = &run.final_state;
    assert!(
        end.q[2].abs() < 1e-12 && end.q_dot.iter().all(|v| v.abs() < 1e-12),
        "{end:?}"
    );
    assert_eq!(
        run.final_mode,
        zenosim::Mode::Constrained(zenosim::ActiveSet::single(0).with(1))
    );
    let last = trajectory.points.last().unwrap();
    assert_eq!(last.grips.stick, zenosim::ActiveSet::single(0).with(1));
    assert_eq!(last.work.friction, 0.0);
    assert!(
        trajectory.balance_residual() < 1e-9,
        "{}",
        trajectory.balance_residual()
    );
}

/// models/rimless-wheel.toml: each spoke strikes plastically and sticks, scaling the angular
/// velocity by `r = (I + m l² cos 2a)/(I + m l²)`; each stance gains `K = 4 m g l sin a sin γ/
/// (I + m l²)` in `ω²`; so `ω₊² − ω*²` shrinks by exactly `r²` a step towards the limit cycle
/// `ω*² = r² K/(1 − r²)` (McGeer's rimless wheel, with a hub of inertia `I`).
#[test]
fn the_rimless_wheel_rolls_onto_its_limit_cycle() {
    let (m, inertia, g, l, gamma) = (1.0_f64, 0.1, G, 1.0, 0.1_f64);
    let a = std::f64::consts::PI / 10.0;
    let r = (inertia + m * l * l * (2.0 * a).cos()) / (inertia + m * l * l);
    let k = 4.0 * m * g * l * a.sin() * gamma.sin() / (inertia + m * l * l);
    let limit = r * r * k / (1.0 - r * r);
    let (run, _) = run(&load("rimless-wheel", &[]));
    assert_eq!(run.outcome, Outcome::Finished, "{}", run.outcome);
    let impacts: Vec<_> = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Impact)
        .collect();
    assert!(impacts.len() >= 20, "{}", impacts.len());
    for (i, impact) in impacts.iter().enumerate() {
        let (before, after) = (impact.before.q_dot[2], impact.after.q_dot[2]);
        assert!(
            (after / before - r).abs() < 1e-12,
            "impact {i}: {}",
            after / before
        );
        // The contact point does not slip.
        assert_eq!(impact.contacts.len(), 2, "{impact:?}");
        if let Some(next) = impacts.get(i + 1) {
            // The stance's gain, to the integration's tolerance.
            let gain = next.before.q_dot[2].powi(2) - after.powi(2);
            assert!(
                (gain - k).abs() < 1e-8 * k,
                "stance {i}: {gain} against {k}"
            );
            // (The gain's error, 1e-8 of K at most, over the distance to the cycle.)
            let distance = after.powi(2) - limit;
            let shrink = (next.after.q_dot[2].powi(2) - limit) / distance;
            assert!(
                (shrink - r * r).abs() < 1e-8 * k / distance.abs(),
                "step {i}: {shrink} against {}",
                r * r
            );
        }
    }
    let last = impacts.last().unwrap().after.q_dot[2].abs();
    assert!(
        (last - limit.sqrt()).abs() < 2e-4,
        "{last} against {}",
        limit.sqrt()
    );
}

fn inline(source: &str) -> ModelFile {
    parse_model("case.toml", source, &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// A block resting flat on two rough corners was "Painlevé's paradox" at once: with both
/// sticking, their slips have the same row, and the forces' system is singular. The forces of
/// least norm hold it: it stays at rest, with or without friction.
#[test]
fn a_block_resting_on_two_rough_corners_stays_at_rest() {
    for mu in ["0.5", "0.0"] {
        let file = inline(&HOUSNER_FLAT.replace("MU", mu));
        let (run, trajectory) = run(&file);
        assert_eq!(run.outcome, Outcome::Finished, "μ = {mu}: {}", run.outcome);
        assert!(run.events.is_empty(), "μ = {mu}: {:?}", run.events);
        let end = &run.final_state;
        assert!(
            end.q_dot.iter().all(|v| v.abs() < 1e-12),
            "μ = {mu}: {end:?}"
        );
        let last = trajectory.points.last().unwrap();
        // Each corner carries half the weight.
        assert!((last.lambda[0] - last.lambda[1]).abs() < 1e-12, "{last:?}");
        assert!((last.lambda[0].abs() - 0.5 * G).abs() < 1e-9, "{last:?}");
    }
}

const HOUSNER_FLAT: &str = r#"name = "flat"
coordinates = ["x", "y", "th"]
lagrangian = "0.5*(x_dot^2 + y_dot^2) + 0.5*((b^2 + c^2)/3)*th_dot^2 - 9.81*y"

[parameters]
b = 0.2
c = 0.5

[[constraint]]
name = "left"
h = "y - b*sin(th) - c*cos(th)"
restitution = 0.5
friction = MU
slip = ["x_dot + (b*sin(th) + c*cos(th))*th_dot"]

[[constraint]]
name = "right"
h = "y + b*sin(th) - c*cos(th)"
restitution = 0.5
friction = MU
slip = ["x_dot + (c*cos(th) - b*sin(th))*th_dot"]

[initial]
y = "c"

[simulation]
t_end = 1.0
"#;

/// A ball dropped on a moving belt did not bounce: the energy cap on the impact law compared
/// the kinetic energies, and the belt's friction impulse adds energy that is the belt's, not
/// the law's; the cap took the restitution to 0. The cap now tests the law's own loss. For a
/// ball the normal and tangential directions are decoupled: `ẏ⁺ = −e ẏ⁻` exactly, and the
/// contact point takes the belt's velocity if the cone allows; the energy balance closes with
/// the belt's work.
#[test]
fn a_ball_dropped_on_a_moving_belt_bounces() {
    let file = inline(
        r#"name = "ball-on-belt"
coordinates = ["x", "y", "th"]
lagrangian = "0.5*(x_dot^2 + y_dot^2) + 0.5*(0.4*r^2)*th_dot^2 - 9.81*y"

[parameters]
r = 0.1
vb = 0.5

[[constraint]]
name = "belt"
h = "y - r"
restitution = 0.8
friction = 0.5
slip = ["x_dot + r*th_dot - vb"]

[initial]
y = 0.5

[simulation]
t_end = 0.5
"#,
    );
    let (run, trajectory) = run(&file);
    assert_eq!(run.outcome, Outcome::Finished, "{}", run.outcome);
    let impact = run
        .events
        .iter()
        .find(|e| e.kind == EventKind::Impact)
        .unwrap();
    let (before, after) = (&impact.before.q_dot, &impact.after.q_dot);
    assert!((after[1] + 0.8 * before[1]).abs() < 1e-12, "{impact:?}");
    // It sticks: the contact point leaves at the belt's speed, ẋ⁺ = (2/7) v_b.
    assert!(
        (after[0] + 0.1 * after[2] - 0.5).abs() < 1e-12,
        "{impact:?}"
    );
    assert!((after[0] - 2.0 / 7.0 * 0.5).abs() < 1e-12, "{impact:?}");
    assert!(
        trajectory.balance_residual() < 1e-9,
        "{}",
        trajectory.balance_residual()
    );
    let last = trajectory.points.last().unwrap();
    assert!(
        last.work.constraints > 0.0,
        "the belt works: {:?}",
        last.work
    );
}

const GOOD: &str = r#"name = "block"
coordinates = ["x", "y"]
lagrangian = "0.5*(x_dot^2 + y_dot^2) - 9.81*y"

[parameters]
mu = 0.5

[[constraint]]
name = "floor"
h = "y"
restitution = 0.0
friction = "mu"
slip = ["x_dot"]

[initial]
x_dot = 1.0
"#;

fn refused(from: &str, to: &str, fragment: &str) -> ModelError {
    assert!(GOOD.contains(from), "{from:?}");
    let source = GOOD.replacen(from, to, 1);
    let error = match parse_model("case.toml", &source, &[]) {
        Ok(_) => panic!("accepted:\n{source}"),
        Err(error) => error,
    };
    let text = error.to_string();
    assert!(text.starts_with("case.toml:"), "{text}");
    assert!(text.contains(fragment), "expected {fragment:?} in:\n{text}");
    assert!(text.contains("= help: "), "{text}");
    error
}

#[test]
fn friction_and_slip_keys_are_checked() {
    parse_model("case.toml", GOOD, &[]).unwrap();
    parse_model(
        "case.toml",
        &GOOD.replace(
            "friction = \"mu\"",
            "friction = { static = 0.6, kinetic = 0.5 }",
        ),
        &[],
    )
    .unwrap();
    refused("slip = [\"x_dot\"]\n", "", "has friction but no slip");
    refused("friction = \"mu\"\n", "", "has a slip but no friction");
    refused("friction = \"mu\"", "friction = -0.1", "below 0");
    refused(
        "friction = \"mu\"",
        "friction = { static = 0.4, kinetic = 0.5 }",
        "is above its static friction",
    );
    refused(
        "friction = \"mu\"",
        "friction = { static = 0.4 }",
        "no kinetic coefficient",
    );
    refused("friction = \"mu\"", "friction = \"x\"", "x");
    // Two formulas: a contact in space.
    parse_model(
        "case.toml",
        &GOOD.replace("slip = [\"x_dot\"]", "slip = [\"x_dot\", \"y_dot\"]"),
        &[],
    )
    .unwrap();
    refused(
        "slip = [\"x_dot\"]",
        "slip = [\"x_dot\", \"y_dot\", \"x_dot\"]",
        "has 3 formulas",
    );
    let e = refused(
        "slip = [\"x_dot\"]",
        "slip = [\"x_dot\", \"x_dot*y_dot\"]",
        "component 2 of the slip of `floor` is not affine",
    );
    assert_eq!(e.key(), Some("constraint[1].slip[2]"), "{e}");
    refused("slip = [\"x_dot\"]", "slip = \"x_dot\"", "must be a list");
    refused(
        "slip = [\"x_dot\"]",
        "slip = [\"x\"]",
        "does not depend on any velocity",
    );
    let e = refused(
        "slip = [\"x_dot\"]",
        "slip = [\"x_dot + 0.1*x_dot*y_dot\"]",
        "is not affine in the velocities",
    );
    assert_eq!(e.key(), Some("constraint[1].slip[1]"), "{e}");
    refused(
        "slip = [\"x_dot\"]",
        "slip = [\"sin(x_dot)\"]",
        "not affine",
    );
    // Affine with coefficients of the coordinates and the time: accepted.
    parse_model(
        "case.toml",
        &GOOD.replace(
            "slip = [\"x_dot\"]",
            "slip = [\"cos(x)*x_dot + t*y_dot - 2\"]",
        ),
        &[],
    )
    .unwrap();
}

/// A coordinate may not take the name of a constraint's column `f_<name>` in trajectory.csv
/// (its tangential force), which only a constraint with friction has.
#[test]
fn a_coordinate_named_as_a_friction_column_is_refused() {
    let source = GOOD
        .replace("\"x\", \"y\"", "\"f_floor\", \"y\"")
        .replace("x_dot", "f_floor_dot");
    let error = parse_model("case.toml", &source, &[])
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("coordinate `f_floor` has the name of constraint `floor`'s column"),
        "{error}"
    );
    // A contact in space has a second column, f2_<name>.
    let source_in_space = GOOD
        .replace("\"x\", \"y\"", "\"f2_floor\", \"y\"")
        .replace("x_dot", "f2_floor_dot")
        .replace(
            "slip = [\"f2_floor_dot\"]",
            "slip = [\"f2_floor_dot\", \"y_dot\"]",
        );
    let error = parse_model("case.toml", &source_in_space, &[])
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("coordinate `f2_floor` has the name of constraint `floor`'s column"),
        "{error}"
    );
    // Frictionless (a coefficient of 0): no such column, so the name is free.
    let frictionless = Override {
        name: "mu".to_string(),
        value: "0".to_string(),
    };
    parse_model("case.toml", &source, &[frictionless]).unwrap();
}

/// models/sphere-slide-spin.toml, a contact in space: the slip `u` keeps its direction and
/// shrinks at `μ g (1 + m r²/I) = (7/2) μ g`, so the sphere rolls from `t* = |u₀|/((7/2) μ g)`
/// at `v₀ − μ g t* û₀ = v₀ − (2/7) u₀` (closed form), its spin about the vertical untouched,
/// and rolls on with no force.
#[test]
fn the_sphere_in_space_slides_in_one_direction_until_it_rolls() {
    let (r, mu): (f64, f64) = (0.1, 0.3);
    let (vx, vy, wx, wy, wz): (f64, f64, f64, f64, f64) = (2.0, 0.5, 10.0, -15.0, 7.0);
    let u0 = [vx - r * wy, vy + r * wx];
    let t_roll = u0[0].hypot(u0[1]) / (3.5 * mu * G);
    let v_roll = [vx - 2.0 / 7.0 * u0[0], vy - 2.0 / 7.0 * u0[1]];

    let (run, trajectory) = run(&load("sphere-slide-spin", &[]));
    assert_eq!(run.outcome, Outcome::Finished, "{}", run.outcome);
    let sticks = times(&run, EventKind::Stick);
    assert_eq!(sticks.len(), 1, "{:?}", run.events);
    assert!(
        (sticks[0] - t_roll).abs() < 1e-9,
        "{} against {t_roll}",
        sticks[0]
    );
    // While it slides, the slip points along u₀.
    for point in trajectory.points.iter().filter(|p| p.t < t_roll) {
        let v = &point.q_dot;
        let u = [v[0] - r * v[4], v[1] + r * v[3]];
        // The slip's part across û₀, to the rounding of the velocities.
        let across = (u[0] * u0[1] - u[1] * u0[0]) / u0[0].hypot(u0[1]);
        assert!(across.abs() < 1e-13, "at t = {}: {across}", point.t);
    }
    let end = &run.final_state;
    assert!((end.q_dot[0] - v_roll[0]).abs() < 1e-9, "{end:?}");
    assert!((end.q_dot[1] - v_roll[1]).abs() < 1e-9, "{end:?}");
    assert!((end.q_dot[5] - wz).abs() < 1e-12, "{end:?}");
    assert!((end.q_dot[0] - r * end.q_dot[4]).abs() < 1e-9, "{end:?}");
    assert!((end.q_dot[1] + r * end.q_dot[3]).abs() < 1e-9, "{end:?}");
    let last = trajectory.points.last().unwrap();
    assert!(last.work.friction < 0.0, "{:?}", last.work);
    assert!(
        trajectory.balance_residual() < 1e-8,
        "{}",
        trajectory.balance_residual()
    );
}

/// The ball with backspin of models/ball-backspin.toml thrown along a line at 30° in space
/// (two slip components) is the planar ball on that line: the same impacts, Zeno point and
/// rolling speed, sticking (`μ = 0.5`) or sliding through the Zeno point (`μ = 0.02`).
#[test]
fn the_ball_with_backspin_in_space_is_the_planar_ball_on_its_line() {
    let space = r#"
name = "ball-backspin-space"
coordinates = ["x", "y", "z", "a", "b", "c"]
lagrangian = "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2) + 0.5*(0.4*m*r^2)*(a_dot^2 + b_dot^2 + c_dot^2) - m*g*z"
[parameters]
m = 1.0
g = 9.81
r = 0.1
e = 0.5
mu = 0.5
phi = 0.5235987755982988
[[constraint]]
name = "floor"
h = "z - r"
restitution = "e"
friction = "mu"
slip = ["x_dot - r*b_dot", "y_dot + r*a_dot"]
[initial]
z = 1.0
x_dot = "cos(phi)"
y_dot = "sin(phi)"
a_dot = "-20*sin(phi)"
b_dot = "20*cos(phi)"
[simulation]
t_end = 3.0
"#;
    for mu in ["0.5", "0.02"] {
        let plane = run(&load("ball-backspin", &[("mu", mu)])).0;
        let source = space.replace("mu = 0.5", &format!("mu = {mu}"));
        let spatial = run(&inline(&source)).0;
        assert_eq!(spatial.outcome, Outcome::Finished, "{}", spatial.outcome);
        let kinds = |r: &Execution| r.events.iter().map(|e| e.kind).collect::<Vec<_>>();
        assert_eq!(kinds(&spatial), kinds(&plane), "μ = {mu}");
        for (a, b) in spatial.events.iter().zip(&plane.events) {
            assert!(
                (a.t - b.t).abs() < 1e-7,
                "μ = {mu}: {} against {}",
                a.t,
                b.t
            );
            // The tangential impulse is the planar one, along the line (cos φ, sin φ).
            if a.kind == EventKind::Impact {
                let planar = b.tangential[0];
                let along = [a.tangential[0], a.tangential_across[0]];
                let expected = [planar * 0.75_f64.sqrt(), planar * 0.5];
                let size = 1e-9 * (1.0 + planar.abs());
                assert!((along[0] - expected[0]).abs() < size, "μ = {mu}: {a:?}");
                assert!((along[1] - expected[1]).abs() < size, "μ = {mu}: {a:?}");
            }
        }
        let (v, w) = (&spatial.final_state.q_dot, &plane.final_state.q_dot);
        assert!(
            (v[0].hypot(v[1]) - w[0]).abs() < 1e-9,
            "μ = {mu}: {v:?} {w:?}"
        );
        assert!(
            (v[1] / v[0] - 1.0 / 3.0_f64.sqrt()).abs() < 1e-9,
            "μ = {mu}: {v:?}"
        );
    }
}

/// A sphere set down rolling across a plane tilted by `α` (contact in space): with
/// `μ < (2/7) tan α` it slips from rest straight down the slope at `g (sin α − μ cos α)`, its
/// sideways rolling untouched; with more friction it rolls down at `(5/7) g sin α`, held by
/// `(2/7) m g sin α` up the slope (closed forms).
#[test]
fn the_sphere_on_a_tilted_plane_slips_from_rest_down_the_slope_or_rolls() {
    let source = r#"
name = "sphere-tilted"
coordinates = ["x", "y", "z", "a", "b", "c"]
lagrangian = "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2) + 0.5*(0.4*m*r^2)*(a_dot^2 + b_dot^2 + c_dot^2) - m*g*z"
[parameters]
m = 1.0
g = 9.81
r = 0.1
mu = 0.05
al = 0.3
vx = 1.0
[[constraint]]
name = "slope"
h = "z*cos(al) - y*sin(al) - r"
restitution = 0.0
friction = "mu"
slip = ["x_dot - r*(b_dot*cos(al) + c_dot*sin(al))", "cos(al)*y_dot + sin(al)*z_dot + r*a_dot"]
[initial]
z = "r/cos(al)"
x_dot = "vx"
b_dot = "vx/(r*cos(al))"
[simulation]
t_end = 1.0
"#;
    let al: f64 = 0.3;
    let down = |v: &[f64]| -(al.cos() * v[1] + al.sin() * v[2]);
    for (mu, slips, rate) in [
        (0.05, true, G * (al.sin() - 0.05 * al.cos())),
        (0.1, false, 5.0 / 7.0 * G * al.sin()),
    ] {
        let file = inline(&source.replace("mu = 0.05", &format!("mu = {mu}")));
        let (run, trajectory) = run(&file);
        assert_eq!(run.outcome, Outcome::Finished, "{}", run.outcome);
        assert!(run.events.is_empty(), "{:?}", run.events);
        let end = &run.final_state;
        assert!((down(&end.q_dot) - rate).abs() < 1e-9, "μ = {mu}: {end:?}");
        assert!((end.q_dot[0] - 1.0).abs() < 1e-12, "μ = {mu}: {end:?}");
        let point = trajectory.points.last().unwrap();
        assert_eq!(point.grips.stick.is_empty(), slips, "μ = {mu}");
        // The tangential force: up the slope (the second component, negative down it).
        let force = if slips {
            mu * G * al.cos()
        } else {
            2.0 / 7.0 * G * al.sin()
        };
        assert!(point.friction[0].abs() < 1e-12, "{:?}", point.friction);
        assert!(
            (point.friction_across[0] - force).abs() < 1e-9,
            "μ = {mu}: {} against {force}",
            point.friction_across[0]
        );
    }
}
