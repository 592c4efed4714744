//! The ports of Siconos's frictional examples (`models/siconos/`, README there) against their
//! independent references (`models/siconos/references/<name>.json`, written by
//! `bench/siconos/references/<name>.py`: closed forms, or event-driven computations of their own
//! in mpmath). Each model runs at the default tolerance (`rtol = atol = 1e-10`) and is compared
//! impact by impact, friction event by friction event (stick, slip, reversal), at its Zeno
//! point and at its final state; every port must finish at tolerances 1e-6 to 1e-12.

use std::path::PathBuf;

use serde_json::Value;
use zenosim::{
    ActiveSet, Derived, EventKind, Execution, HybridLagrangian, Mode, Outcome, SimulationOptions,
    Tolerances, Trajectory,
};
use zenosim_model::{parse_model, ModelFile};

/// The default tolerance of a run (`rtol = atol`), the README's `[simulation]` default.
const DEFAULT_TOLERANCE: f64 = 1e-10;

fn model(name: &str) -> ModelFile {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../models/siconos/{name}.toml"));
    let source = std::fs::read_to_string(&path).unwrap();
    parse_model(name, &source, &[]).unwrap_or_else(|e| panic!("{e}"))
}

fn reference(name: &str) -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../../models/siconos/references/{name}.json"));
    let value: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(value["model"], format!("models/siconos/{name}.toml"));
    assert_eq!(value["commit"], "b6c9bfd1940a69dae512a3e39cf5f1a951e3eebe");
    value
}

fn parameter(file: &ModelFile, name: &str) -> f64 {
    file.parameters
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no parameter {name}"))
        .1
}

fn number(value: &Value) -> f64 {
    value
        .as_f64()
        .unwrap_or_else(|| panic!("not a number: {value}"))
}

fn numbers(value: &Value) -> Vec<f64> {
    value.as_array().unwrap().iter().map(number).collect()
}

/// Runs the model with its own options, the tolerance changed where given, keeping the
/// trajectory.
fn run_with(file: &ModelFile, tolerance: Option<f64>) -> (Execution, Trajectory) {
    let defaults = file.options();
    let options = SimulationOptions {
        tolerances: tolerance.map_or(defaults.tolerances, |tol| Tolerances {
            rtol: tol,
            atol: tol,
        }),
        ..defaults
    };
    let mut trajectory = Trajectory::default();
    let simulation =
        zenosim::Simulation::new(&file.model, &file.initial.q, &file.initial.q_dot, options)
            .unwrap();
    let run = simulation.run(&mut trajectory);
    (run, trajectory)
}

/// The constraints a mode holds.
fn held(mode: Mode) -> ActiveSet {
    match mode {
        Mode::Free => ActiveSet::empty(),
        Mode::Constrained(set) => set,
    }
}

fn events(run: &Execution, kind: EventKind) -> Vec<&zenosim::Event> {
    run.events.iter().filter(|e| e.kind == kind).collect()
}

/// No sample below a constraint by more than `crossing`, no impulse that pulls, and no
/// frictional impact that gains kinetic energy (`T + V`, `V` the same on both sides;
/// docs/friction.md: zenosim's law never creates energy), to rounding.
fn check_physics(file: &ModelFile, run: &Execution, trajectory: &Trajectory, crossing: f64) {
    for p in &trajectory.points {
        assert!(
            p.h.iter().all(|&h| h >= -crossing),
            "{}: a constraint crossed at t = {}: h = {:?}",
            file.name,
            p.t,
            p.h
        );
    }
    let derived = Derived::new(&file.model).unwrap();
    for e in events(run, EventKind::Impact) {
        assert!(
            e.impulses.iter().all(|&l| l >= -1e-12 * l.abs().max(1.0)),
            "{}: a pulling impulse at t = {}: {:?}",
            file.name,
            e.t,
            e.impulses
        );
        let before = derived.energy(&e.before.q, &e.before.q_dot);
        let after = derived.energy(&e.after.q, &e.after.q_dot);
        assert!(
            after <= before + 1e-12 * before.abs().max(1.0),
            "{}: the impact at t = {} gains {:e}",
            file.name,
            e.t,
            after - before
        );
    }
}

/// The run's final state against the reference's, every component within `bound[i]`
/// (positions, then velocities); returns the largest error.
fn compare_final(file: &ModelFile, run: &Execution, reference: &Value, bound: &[f64]) -> f64 {
    let expected = &reference["final"];
    assert_eq!(run.t_final, number(&expected["t"]), "{}", file.name);
    let want: Vec<f64> = numbers(&expected["q"])
        .into_iter()
        .chain(numbers(&expected["q_dot"]))
        .collect();
    let got: Vec<f64> = run
        .final_state
        .q
        .iter()
        .chain(&run.final_state.q_dot)
        .copied()
        .collect();
    assert_eq!(got.len(), want.len());
    let mut worst: f64 = 0.0;
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        let error = (g - w).abs();
        worst = worst.max(error);
        assert!(
            error <= bound[i],
            "{}: final component {i}: {g} against {w} (error {error:e}, bound {:e})",
            file.name,
            bound[i]
        );
    }
    worst
}

/// The run's impacts against the reference's list `impacts`, one by one: the same count (all
/// of them, or, before a Zeno point, the first ones), on the named contact, at times within
/// `bound(k)`. Returns the largest time error.
fn compare_impacts(
    file: &ModelFile,
    run: &Execution,
    impacts: &Value,
    all: bool,
    bound: impl Fn(usize) -> f64,
) -> f64 {
    let expected = impacts.as_array().unwrap();
    let got = events(run, EventKind::Impact);
    if all {
        assert_eq!(got.len(), expected.len(), "{}: impacts", file.name);
    } else {
        assert!(got.len() <= expected.len(), "{}: impacts", file.name);
    }
    let mut worst: f64 = 0.0;
    for (k, (event, reference)) in got.iter().zip(expected).enumerate() {
        let t_ref = number(&reference["t"]);
        let error = (event.t - t_ref).abs();
        worst = worst.max(error);
        assert!(
            error <= bound(k),
            "{}: impact {k} at {} against {t_ref} (error {error:e}, bound {:e})",
            file.name,
            event.t,
            bound(k)
        );
        let contacts: Vec<&str> = event
            .contacts
            .iter()
            .map(|i| file.model.constraints()[i].name.as_str())
            .collect();
        let want: Vec<&str> = reference["contacts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_str().unwrap())
            .collect();
        assert_eq!(contacts, want, "{}: impact {k}", file.name);
    }
    worst
}

/// The run's friction events (stick and slip) against the reference's `friction_events`, in
/// order: a reference "stick" is zenosim's stick event, a "slip" (from sticking) and a
/// "reversal" (the slip changing sign) are its slip events (docs/friction.md); times within
/// `bound(t)`. Returns the largest time error.
fn compare_friction_events(
    file: &ModelFile,
    run: &Execution,
    reference: &Value,
    bound: impl Fn(f64) -> f64,
) -> f64 {
    let expected = reference["friction_events"].as_array().unwrap();
    let got: Vec<&zenosim::Event> = run
        .events
        .iter()
        .filter(|e| matches!(e.kind, EventKind::Stick | EventKind::Slip))
        .collect();
    assert_eq!(got.len(), expected.len(), "{}: friction events", file.name);
    let mut worst: f64 = 0.0;
    for (k, (event, reference)) in got.iter().zip(expected).enumerate() {
        let want = match reference["kind"].as_str().unwrap() {
            "stick" => EventKind::Stick,
            "slip" | "reversal" => EventKind::Slip,
            other => panic!("{other}"),
        };
        assert_eq!(event.kind, want, "{}: friction event {k}", file.name);
        let t_ref = number(&reference["t"]);
        let error = (event.t - t_ref).abs();
        worst = worst.max(error);
        assert!(
            error <= bound(t_ref),
            "{}: friction event {k} ({:?}) at {} against {t_ref} (error {error:e}, bound {:e})",
            file.name,
            event.kind,
            event.t,
            bound(t_ref)
        );
    }
    worst
}

/// Ball2D_kernel_only_with_friction.cpp (closed form): the disk sticks at its first impact
/// (tangential impulse 2/7 within the cone 0.595), bounces without slip to the bouncing ball's
/// Zeno point and rolls on.
///
/// Bounds. A flight under constant gravity is stepped in closed form, so the times carry only
/// rounding, but of the gap `x − R` near `x = R = 0.5`: an ulp of `x` is `ε R`, which moves a
/// landing by `ε R/v` at the landing speed `v`; a few operations (64 `ε R`) per landing, each
/// landing's error carried on to the next: impact `k` within `Σ_{j≤k} 64 ε R/v_j` (with
/// `v_j = v_1 e^j`, read off the reference's normal impulses `m (1 + e) v_j`) plus the
/// rounding of `t`. Deep in the sequence that grows as `1/v` (measured: 1.1e-9 at impact 128,
/// `v = 4.8e-6`; the frictionless balls, whose gap is `y` near 0, keep 1e-13). The Zeno time
/// is predicted from the last impact's flight in closed form, `2 v⁺/(g (1 − e))` further: the
/// last impact's time error `δ` and the speed error `g δ` it carries give at most `21 δ`. The
/// tangential impulses: 2/7 at the first impact, none after (the slip stays 0), to rounding.
/// The final state (rolling at the first impact's velocities): 1e-12.
#[test]
fn ball_2d_sticks_at_its_first_impact_then_rolls() {
    let name = "ball2d-friction";
    let file = model(name);
    let reference = reference(name);
    let (run, trajectory) = run_with(&file, None);
    assert_eq!(run.outcome, Outcome::Finished);
    check_physics(&file, &run, &trajectory, 1e-9);
    let (m, r, e) = (
        parameter(&file, "m"),
        parameter(&file, "R"),
        parameter(&file, "e"),
    );
    let expected = reference["impacts"].as_array().unwrap();
    let speeds: Vec<f64> = expected
        .iter()
        .map(|i| number(&i["normal_impulse"]) / (m * (1.0 + e)))
        .collect();
    let bound = |k: usize| {
        let landing: f64 = speeds[..=k]
            .iter()
            .map(|v| 64.0 * f64::EPSILON * r / v)
            .sum();
        landing + 4.0 * (k + 1) as f64 * f64::EPSILON * number(&expected[k]["t"])
    };
    compare_impacts(&file, &run, &reference["impacts"], false, bound);
    let impacts = events(&run, EventKind::Impact);
    assert!(impacts.len() > 100, "only {} impacts", impacts.len());
    let first = number(&reference["first_impact"]["tangential_impulse"]);
    assert!(
        (impacts[0].tangential[0] - first).abs() <= 1e-14,
        "{:?}",
        impacts[0]
    );
    for e in &impacts[1..] {
        assert!(e.tangential[0].abs() <= 1e-14, "{e:?}");
    }
    // The Zeno point.
    assert_eq!(run.zeno.len(), 1);
    let zeno_ref = number(&reference["zeno"][0]["t"]);
    let zeno_bound = 21.0 * bound(impacts.len() - 1);
    let zeno_error = (run.zeno[0].t_zeno - zeno_ref).abs();
    assert!(zeno_error <= zeno_bound, "{zeno_error:e} > {zeno_bound:e}");
    compare_final(&file, &run, &reference, &[1e-12; 6]);
    // Rolling: held and sticking from the Zeno point to t_end, without another friction event.
    assert!(events(&run, EventKind::Stick).is_empty() && events(&run, EventKind::Slip).is_empty());
    assert!(held(run.final_mode).contains(0));
    let last = trajectory.points.last().unwrap();
    assert!(last.grips.stick.contains(0), "{last:?}");
}

/// ImpactingStick.cpp: two impacts of the stick's end, both slipping, against the reference's
/// energy-consistent law (zenosim's, docs/friction.md): the first reverses the slip, and with
/// `e = 1` as written Newton's law would create 7.1e-4 J there (the reference's alternative
/// "newton", which Siconos follows), so the restitution is scaled (by 0.99184).
///
/// Bounds. The flights (a parabola and a uniform rotation) are exact to rounding, and so is
/// the first landing (measured 7e-17 s). The scale of the restitution is found by 48
/// bisection steps (2⁻⁴⁸ = 3.6e-15) with a loss accepted to rounding: the velocities after
/// the first impact carry about 1e-14 relative (measured 6e-14 on `θ̇`), which moves the
/// second landing by about 1e-14 s (measured 9e-15) and the state at t_end by about 1e-13
/// (measured 1.9e-13 on `θ̇`). Bounds ten times those: 1e-13 s on the impacts, 2e-12 on the
/// final state, and 1e-12 relative on the impulses.
#[test]
fn impacting_stick_follows_the_energy_consistent_law() {
    let name = "impacting-stick";
    let file = model(name);
    let reference = reference(name);
    let (run, trajectory) = run_with(&file, None);
    assert_eq!(run.outcome, Outcome::Finished);
    check_physics(&file, &run, &trajectory, 1e-9);
    compare_impacts(&file, &run, &reference["impacts"], true, |_| 1e-13);
    let derived = Derived::new(&file.model).unwrap();
    for (e, r) in events(&run, EventKind::Impact)
        .iter()
        .zip(reference["impacts"].as_array().unwrap())
    {
        let (normal, tangential) = (
            number(&r["normal_impulse"]),
            number(&r["tangential_impulse"]),
        );
        assert!((e.impulses[0] - normal).abs() <= 1e-12 * normal, "{e:?}");
        assert!(
            (e.tangential[0] - tangential).abs() <= 1e-12 * normal,
            "{e:?}"
        );
        // Where the reference scales the restitution, the impact keeps the energy exactly.
        if number(&r["restitution_scale"]) < 1.0 {
            let before = derived.energy(&e.before.q, &e.before.q_dot);
            let after = derived.energy(&e.after.q, &e.after.q_dot);
            assert!((after - before).abs() <= 1e-12, "{:e}", after - before);
        }
    }
    compare_final(&file, &run, &reference, &[2e-12; 6]);
    // Siconos's law (the alternative "newton") gains energy at the first impact and lands the
    // second 9.1e-4 s later: the two laws are told apart here.
    let newton = &reference["alternatives"][0];
    assert_eq!(newton["name"], "newton");
    assert!(-number(&newton["impacts"][0]["loss"]) > 1e-4);
    let second = events(&run, EventKind::Impact)[1].t;
    assert!(number(&newton["impacts"][1]["t"]) - second > 5e-4);
}

/// FrictionOscillator.py (closed form): seven half-swings, each ending in a reversal of the
/// slip (zenosim's slip events), then a stick at t = 22.42 for good.
///
/// Bounds. The swings are integrated (harmonic, not closed form), and the phase of an
/// oscillation integrated at tolerance `tol` drifts by `O(tol)` per radian: an event time by
/// `O(tol t)`, a position by `O(tol ω t)` times the amplitude. As for the linear oscillator of
/// `siconos.rs`: the events within `100 tol t` (measured 9.9e-11 at t ≤ 22.4), the final
/// position within `100 tol ω t_stick x0` (measured 7.1e-11), the velocities at rest exactly,
/// and `y` on the floor exactly.
#[test]
fn friction_oscillator_stops_after_seven_swings() {
    let name = "friction-oscillator";
    let file = model(name);
    let reference = reference(name);
    let (run, trajectory) = run_with(&file, None);
    assert_eq!(run.outcome, Outcome::Finished);
    check_physics(&file, &run, &trajectory, 0.0);
    let tol = DEFAULT_TOLERANCE;
    compare_friction_events(&file, &run, &reference, |t| 100.0 * tol * t);
    let omega = (parameter(&file, "k") / parameter(&file, "m")).sqrt();
    let events = reference["friction_events"].as_array().unwrap();
    let t_stick = number(&events[events.len() - 1]["t"]);
    let x0 = parameter(&file, "x0");
    compare_final(
        &file,
        &run,
        &reference,
        &[100.0 * tol * omega * t_stick * x0, 0.0, 0.0, 0.0],
    );
    for p in &trajectory.points {
        assert!(p.q[1] == 0.0 && p.q_dot[1] == 0.0, "{p:?}");
    }
}

/// TwoDofsFrictionOscillator.py (exact modal solutions in mpmath): the forced chain's second
/// mass slips and sticks 107 times before t = 500, never reversing.
///
/// Bounds as for the single oscillator (harmonic flows integrated at `tol`): every event
/// within `100 tol t` (measured 8.4e-9 at t = 127.8: a stick that ends a short, slow slip,
/// whose root is flat); the final state within `100 tol ω₂ T` (ω₂ = 1.618, the faster mode;
/// amplitudes about 1; measured 3.5e-10), the second mass's velocity (stuck) exactly 0 and its
/// height on the floor exactly.
#[test]
fn two_dofs_friction_oscillator_stick_slip() {
    let name = "two-dofs-friction-oscillator";
    let file = model(name);
    let reference = reference(name);
    let (run, trajectory) = run_with(&file, None);
    assert_eq!(run.outcome, Outcome::Finished);
    check_physics(&file, &run, &trajectory, 0.0);
    let tol = DEFAULT_TOLERANCE;
    compare_friction_events(&file, &run, &reference, |t| 100.0 * tol * t);
    let t_end = run.t_final;
    let fast = ((3.0 + 5f64.sqrt()) / 2.0).sqrt();
    let drift = 100.0 * tol * fast * t_end;
    compare_final(
        &file,
        &run,
        &reference,
        &[drift, drift, 0.0, drift, 0.0, 0.0],
    );
    for p in &trajectory.points {
        assert!(p.q[2] == 0.0 && p.q_dot[2] == 0.0, "{p:?}");
    }
}

/// Every frictional port finishes at tolerances 1e-6 to 1e-12 with the reference's count of
/// impacts (all of them, or some before the Zeno point) and of friction events.
#[test]
fn friction_ports_finish_at_every_tolerance() {
    for name in [
        "ball2d-friction",
        "impacting-stick",
        "friction-oscillator",
        "two-dofs-friction-oscillator",
    ] {
        let file = model(name);
        let reference = reference(name);
        for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
            let (run, _) = run_with(&file, Some(tol));
            assert_eq!(run.outcome, Outcome::Finished, "{name} at {tol:e}");
            let impacts = events(&run, EventKind::Impact)
                .iter()
                .filter(|e| e.impulses.iter().any(|&l| l > 0.0))
                .count();
            let expected = reference["impacts"].as_array().map_or(0, Vec::len);
            if reference.get("zeno").is_some() {
                assert!(impacts > 0 && impacts <= expected, "{name} at {tol:e}");
            } else {
                assert_eq!(impacts, expected, "{name} at {tol:e}");
            }
            let friction = run
                .events
                .iter()
                .filter(|e| matches!(e.kind, EventKind::Stick | EventKind::Slip))
                .count();
            let expected = reference["friction_events"].as_array().map_or(0, Vec::len);
            assert_eq!(friction, expected, "{name} at {tol:e}: friction events");
        }
    }
}

/// The friction oscillator's floor carries the block's whole weight at every instant, so it
/// must never let go. It once did, at one of the seven reversals (a different one at each
/// tolerance: t = 12.9988 at 1e-10), re-closed at once by an impact without impulse: the
/// search found the slip margin past 0 on the dense output, while the step to that time still
/// slipped forwards at 1.4e-10, so law 1 saw no change and the largest margin there, in units
/// of the slip's tiny scale at the mode's start, was below the normal force's. The change is
/// now read off the dense output's state where the margin crossed, and a slip that stopped
/// there is stopped in the step's state too before law 1 decides again.
#[test]
fn a_slip_reversal_is_not_taken_for_a_lift_off() {
    let file = model("friction-oscillator");
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        let (run, trajectory) = run_with(&file, Some(tol));
        assert_eq!(run.outcome, Outcome::Finished);
        let lifts: Vec<f64> = events(&run, EventKind::Liftoff)
            .iter()
            .map(|e| e.t)
            .collect();
        assert!(lifts.is_empty(), "at {tol:e}: lift-offs at {lifts:?}");
        for p in &trajectory.points {
            assert!(held(p.mode).contains(0), "at {tol:e}: free at t = {}", p.t);
        }
    }
}

/// Siconos's woodpecker (`bench/siconos/unported/woodpecker.toml`: not a port, no reference;
/// bench/siconos/README.md, "Not ported") must at least finish. It stopped at 1e-6, 1e-8 and
/// 1e-12 at t = 0.1213355, just after a plastic, slipping impact of the sleeve's lower edge,
/// with "the solver of the contact problem on constraints 'lower' failed": the impact's LCP
/// had a normal approach of -1.7e-17 beside a slip of -0.31, whose rounding (carried into the
/// normal row by the elimination) is larger, so no basis solved it to its accuracy. The
/// impact law now counts that rounding in the normal rows' (docs/friction.md).
#[test]
fn a_slipping_contact_hardly_approaching_has_its_impact_solved() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../bench/siconos/unported/woodpecker.toml");
    let source = std::fs::read_to_string(&path).unwrap();
    let file = parse_model("woodpecker", &source, &[]).unwrap_or_else(|e| panic!("{e}"));
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        let (run, _) = run_with(&file, Some(tol));
        assert_eq!(
            run.outcome,
            Outcome::Finished,
            "at {tol:e}: t = {}",
            run.t_final
        );
    }
}
