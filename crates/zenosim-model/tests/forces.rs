//! The shipped examples with forces, dissipation or a moving surface (docs/forces-and-time.md),
//! each against its reference: the closed forms of `zenosim::models` with the file's own
//! parameters, and the energy balance.

use std::path::PathBuf;

use zenosim::models::{DampedOscillator, DraggedBall, VibratingTable};
use zenosim::{EventKind, Execution, HybridLagrangian, Mode, Outcome, Trajectory};
use zenosim_model::{parse_model, ModelFile, Override};

fn load(name: &str, overrides: &[Override]) -> ModelFile {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../models")
        .join(name);
    let source = std::fs::read_to_string(&path).unwrap();
    parse_model(name, &source, overrides).unwrap_or_else(|e| panic!("{e}"))
}

fn parameter(file: &ModelFile, name: &str) -> f64 {
    file.parameters
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no parameter {name}"))
        .1
}

/// Runs the file with its own options; it must finish, cross no constraint by more than 1e-9,
/// and keep its energy balance to 1e-8 (relative to the energies and works involved).
fn run(file: &ModelFile) -> (Execution, Trajectory) {
    assert!(!file.model.is_autonomous(), "{}", file.name);
    let (run, trajectory) = file.run_keeping().unwrap();
    assert_eq!(run.outcome, Outcome::Finished, "{}", file.name);
    for p in &trajectory.points {
        assert!(p.h.iter().all(|&h| h >= -1e-9), "{}: {p:?}", file.name);
    }
    let balance = trajectory.balance_residual();
    assert!(balance <= 1e-8, "{}: balance off by {balance:e}", file.name);
    (run, trajectory)
}

/// The impact times to 1e-9 and the Zeno time to 1e-8, relative.
fn closed_form(run: &Execution, exact: &[f64], t_zeno: f64) {
    let times = run.impact_times(0);
    assert!(times.len() >= 20, "{} impacts", times.len());
    for (k, (t, x)) in times.iter().zip(exact).enumerate() {
        assert!((t - x).abs() <= 1e-9 * x, "impact {k}: {t} against {x}");
    }
    assert_eq!(run.zeno.len(), 1);
    let t = run.zeno[0].t_zeno;
    assert!(
        (t - t_zeno).abs() <= 1e-8 * t_zeno,
        "Zeno time {t} against {t_zeno}"
    );
}

#[test]
fn the_dragged_ball_file_bounces_at_the_closed_form_times() {
    let file = load("dragged-ball.toml", &[]);
    let p = |name| parameter(&file, name);
    let reference = DraggedBall::new(p("m"), p("g"), p("c"), p("e"));
    let (exact, t_zeno) = reference.impacts(p("h0"));
    let (run, _) = run(&file);
    closed_form(&run, &exact, t_zeno);
    assert!(run.work.forces < 0.0);
}

#[test]
fn the_damped_oscillator_file_hits_the_wall_at_the_closed_form_times() {
    let file = load("damped-oscillator.toml", &[]);
    let p = |name| parameter(&file, name);
    let reference = DampedOscillator::new(p("m"), p("k"), p("c"), p("x_eq"), p("e"));
    let (exact, t_zeno) = reference.impacts(p("x0"));
    let (run, _) = run(&file);
    closed_form(&run, &exact, t_zeno);
    // At rest on the wall after its Zeno point, held by the spring.
    assert!(matches!(run.final_mode, Mode::Constrained(_)));
}

#[test]
fn the_vibrating_table_file_lets_go_where_the_table_decelerates_at_g() {
    let file = load("vibrating-table.toml", &[]);
    let p = |name| parameter(&file, name);
    let reference = VibratingTable::new(p("m"), p("g"), p("a"), p("w"), p("e"));
    let phase = reference.liftoff_phase().expect("a w² > g");
    let (run, _) = run(&file);
    let liftoffs: Vec<f64> = run.times_of(EventKind::Liftoff);
    assert!(liftoffs.len() >= 20, "{} lift-offs", liftoffs.len());
    for t in liftoffs {
        let theta = (p("w") * t).rem_euclid(std::f64::consts::TAU);
        assert!(
            (theta - phase).abs() <= 1e-9,
            "lift-off at {t}: phase {theta}, not {phase}"
        );
    }
    // Moved by the table, the constraint did work on the ball.
    assert!(run.work.constraints != 0.0);
}

#[test]
fn on_a_gently_vibrating_table_the_ball_stays_after_its_zeno_point() {
    let file = load("vibrating-table.toml", &["a=0.002".parse().unwrap()]);
    let p = |name| parameter(&file, name);
    assert!(p("a") * p("w") * p("w") < p("g"));
    let (run, trajectory) = run(&file);
    assert_eq!(run.zeno.len(), 1);
    assert!(run.times_of(EventKind::Liftoff).is_empty());
    let t_zeno = run.zeno[0].t_switch;
    for s in trajectory.points.iter().filter(|s| s.t > t_zeno) {
        let table = p("a") * (p("w") * s.t).sin();
        assert!(
            (s.q[0] - table).abs() <= 1e-9,
            "t = {}: {} vs {table}",
            s.t,
            s.q[0]
        );
    }
}

/// The arm is driven into its stop, reaches a Zeno point and is held there by its controller;
/// it leaves the stop where the stop's force `kp (r1 − stop)` vanishes, the set point crossing
/// the stop at `t1` (link 2 then at rest at its set point, the arm at rest on the stop).
#[test]
fn the_pd_arm_is_held_on_its_stop_and_leaves_it_when_its_set_point_crosses_it() {
    let file = load("pd-arm.toml", &[]);
    let t1 = parameter(&file, "t1");
    let (run, trajectory) = run(&file);
    assert_eq!(run.zeno.len(), 1, "{:?}", run.zeno);
    assert!(run.zeno[0].t_zeno < t1);
    let liftoffs: Vec<f64> = run.times_of(EventKind::Liftoff);
    assert_eq!(liftoffs.len(), 1, "{liftoffs:?}");
    let error = (liftoffs[0] - t1).abs();
    eprintln!(
        "pd arm: lift-off at {} (t1 = {t1}, off by {error:e})",
        liftoffs[0]
    );
    assert!(error <= 1e-8, "lift-off at {} against {t1}", liftoffs[0]);
    // Held in between: on the stop, pushed by it.
    let held = trajectory
        .points
        .iter()
        .filter(|p| p.t > run.zeno[0].t_switch + 0.1 && p.t < t1 - 0.1);
    for p in held {
        assert!(p.h[0].abs() <= 1e-9 && p.lambda[0] < 0.0, "{p:?}");
    }
    // The controller did the work: the arm ends away from the stop, free.
    assert_eq!(run.final_mode, Mode::Free);
}
