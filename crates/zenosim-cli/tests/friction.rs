//! Friction in the run's files (docs/friction.md, "Outputs"; docs/output.md): `trajectory.csv`
//! has the tangential force `f_<constraint>` of each constraint with friction and the contacts'
//! stick/slip states in `mode`, `summary.json` lists those constraints in `friction`, and the
//! plots, the report and the animation read such a run back. A frictionless model's files are
//! as they were.

mod common;

use std::path::Path;

use common::*;

const G: f64 = 9.81;
/// The belt model's coefficients (models/belt-stick-slip.toml): static 0.6, kinetic 0.4, on a
/// block of unit mass whose normal force is its weight.
const MU_STATIC: f64 = 0.6;
const MU_KINETIC: f64 = 0.4;

/// The shipped model `name`'s text.
fn shipped(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../models/{name}.toml"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The friction states a `mode` lists after the held constraints: (stick, slip).
fn grips(mode: &str) -> (Vec<&str>, Vec<&str>) {
    let (mut stick, mut slip) = (Vec::new(), Vec::new());
    for part in mode.split(';').skip(1) {
        let (label, names) = part.split_once(':').expect("`label:names`");
        let names = names.split('+');
        match label {
            "stick" => stick.extend(names),
            "slip" => slip.extend(names),
            _ => panic!("`{label}` in the mode {mode}"),
        }
    }
    (stick, slip)
}

#[test]
fn the_belt_writes_its_tangential_force_and_its_stick_and_slip() {
    let scratch = Scratch::new(&shipped("belt-stick-slip"));
    assert_exit(&scratch.run(&[]), 0);
    let out = scratch.path("out");

    let csv = Csv::read(&out.join("trajectory.csv"));
    assert_eq!(
        csv.header.join(","),
        "t,mode,x,y,x_dot,y_dot,h_belt,lambda_belt,f_belt,energy"
    );
    let f = csv.column("f_belt");
    let lambda = csv.column("lambda_belt");
    let (mut sticking, mut slipping) = (0, 0);
    for row in &csv.rows {
        let (held, _) = row.mode.split_once(';').unwrap_or((&row.mode, ""));
        assert_eq!(held, "constrained:belt", "t = {}", row.t);
        let force = row.values[f];
        // The normal force is the weight throughout: λ = −m g.
        assert!((row.values[lambda] + G).abs() < 1e-9, "t = {}", row.t);
        match grips(&row.mode) {
            (stick, slip) if stick == ["belt"] && slip.is_empty() => {
                sticking += 1;
                // Within the static cone; a stick → slip event's row is on its edge, to
                // rounding.
                assert!(
                    force.abs() <= MU_STATIC * G * (1.0 + 1e-12),
                    "t = {}: f = {force}",
                    row.t
                );
            }
            (stick, slip) if stick.is_empty() && slip == ["belt"] => {
                slipping += 1;
                assert!(
                    (force.abs() - MU_KINETIC * G).abs() <= 1e-9,
                    "t = {}: f = {force}",
                    row.t
                );
            }
            other => panic!("t = {}: the mode {} lists {other:?}", row.t, row.mode),
        }
    }
    // Stick-slip: both states, over and over (docs: a period of 4.0042 s in 10 s).
    assert!(sticking >= 4 && slipping >= 4, "{sticking} and {slipping}");

    let s = summary(&out);
    assert_eq!(s["friction"], serde_json::json!(["belt"]));
    // Each stick or slip event has its two rows, the contact's state before and after it.
    let mut events = 0;
    for event in s["events"].as_array().unwrap() {
        let t = event["t"].as_f64().unwrap();
        let modes: Vec<&str> = csv
            .rows
            .iter()
            .filter(|r| r.t == t)
            .map(|r| r.mode.as_str())
            .collect();
        let (before, after) = match event["kind"].as_str().unwrap() {
            "stick" => ("slip", "stick"),
            "slip" => ("stick", "slip"),
            other => panic!("a {other} event on the belt"),
        };
        assert_eq!(
            modes,
            [
                format!("constrained:belt;{before}:belt"),
                format!("constrained:belt;{after}:belt")
            ],
            "t = {t}"
        );
        events += 1;
    }
    assert!(events >= 4, "{events} events");

    // What reads the files back takes them.
    assert_exit(&scratch.zenosim(&["plot", "out"]), 0);
    assert!(out.join("figure.svg").exists());
    assert_exit(&scratch.zenosim(&["report", "out"]), 0);
    assert!(out.join("report.html").exists());
    assert_exit(
        &scratch.zenosim(&["animate", "out", "--out", "belt.gif", "--max-frames", "20"]),
        0,
    );
}

#[test]
fn a_frictionless_model_keeps_its_columns_modes_and_summary() {
    let scratch = Scratch::new(BALL_ON_SINE);
    assert_exit(&scratch.run(&[]), 0);
    let out = scratch.path("out");
    let csv = Csv::read(&out.join("trajectory.csv"));
    // The header tests/run.rs expects.
    assert_eq!(
        csv.header.join(","),
        "t,mode,x1,x2,x3,x1_dot,x2_dot,x3_dot,h_surface,lambda_surface,energy"
    );
    assert!(csv
        .rows
        .iter()
        .all(|r| r.mode == "free" || r.mode == "constrained:surface"));
    let s = summary(&out);
    assert!(s.get("friction").is_none(), "{}", s["friction"]);
}

#[test]
fn a_coefficient_of_0_is_frictionless() {
    let source = shipped("belt-stick-slip")
        .replace("friction = { static = 0.6, kinetic = 0.4 }", "friction = 0");
    assert!(source.contains("friction = 0\n"));
    let scratch = Scratch::new(&source);
    assert_exit(&scratch.run(&["--t-end", "1"]), 0);
    let out = scratch.path("out");
    let csv = Csv::read(&out.join("trajectory.csv"));
    assert_eq!(
        csv.header.join(","),
        "t,mode,x,y,x_dot,y_dot,h_belt,lambda_belt,energy"
    );
    assert!(csv.rows.iter().all(|r| r.mode == "constrained:belt"));
    assert!(summary(&out).get("friction").is_none());
    assert_exit(&scratch.zenosim(&["plot", "out"]), 0);
}

/// A contact in space (models/sphere-slide-spin.toml, two slip components): `trajectory.csv`
/// has its force's second component `f2_plane` right after `f_plane`, `summary.json` lists it
/// under `friction_in_space`, and the plots and the report read the run back. While the
/// sphere slides, the force is `μ m g` against the slip `u₀ = (3.5, 1.5)` (closed form: the
/// slip keeps its direction); once it rolls, 0.
#[test]
fn a_contact_in_space_writes_both_components_of_its_force() {
    let scratch = Scratch::new(&shipped("sphere-slide-spin"));
    assert_exit(&scratch.run(&[]), 0);
    let out = scratch.path("out");
    let csv = Csv::read(&out.join("trajectory.csv"));
    assert_eq!(
        csv.header.join(","),
        "t,mode,x,y,z,a,b,c,x_dot,y_dot,z_dot,a_dot,b_dot,c_dot,h_plane,lambda_plane,\
         f_plane,f2_plane,energy"
    );
    let (f1, f2) = (csv.column("f_plane"), csv.column("f2_plane"));
    let size = 0.3 * G;
    let u = [3.5 / 3.5_f64.hypot(1.5), 1.5 / 3.5_f64.hypot(1.5)];
    let (mut slipping, mut sticking) = (0, 0);
    for row in &csv.rows {
        let f = [row.values[f1], row.values[f2]];
        match grips(&row.mode) {
            (stick, _) if stick == ["plane"] => {
                sticking += 1;
                assert!(
                    f[0].abs() < 1e-12 && f[1].abs() < 1e-12,
                    "t = {}: {f:?}",
                    row.t
                );
            }
            (_, slip) if slip == ["plane"] => {
                slipping += 1;
                // μ m g exactly, against u₀: its direction is the slip's, whose error (about
                // 1e-13, the integration's) turns it by that over the slip's size.
                assert!(
                    (f[0].hypot(f[1]) - size).abs() < 1e-12,
                    "t = {}: {f:?}",
                    row.t
                );
                assert!(f[0] * u[0] + f[1] * u[1] < 0.0, "t = {}: {f:?}", row.t);
                let v = |name: &str| row.values[csv.column(name)];
                let slip = (v("x_dot") - 0.1 * v("b_dot")).hypot(v("y_dot") + 0.1 * v("a_dot"));
                let across = f[0] * u[1] - f[1] * u[0];
                assert!(
                    across.abs() < size * (1e-12 + 1e-13 / slip),
                    "t = {}: {f:?}, slip {slip}",
                    row.t
                );
            }
            other => panic!("t = {}: {other:?}", row.t),
        }
    }
    assert!(slipping > 0 && sticking > 0, "{slipping} {sticking}");
    let s = summary(&out);
    assert_eq!(s["friction"], serde_json::json!(["plane"]));
    assert_eq!(s["friction_in_space"], serde_json::json!(["plane"]));
    assert_exit(&scratch.zenosim(&["plot", "out"]), 0);
    assert_exit(&scratch.zenosim(&["report", "out"]), 0);
    assert!(out.join("report.html").exists());
}
