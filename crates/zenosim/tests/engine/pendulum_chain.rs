//! The chain of `n` pendulums whose tip is stopped by a wall ([`PendulumChain`]): the engine at
//! up to `MAX_DIMENSION` = 20 coordinates, against what physics gives for free (REFERENCE §3):
//! energy lost only at impacts (exactly `½(1−e²)(A q̇)²/(A M⁻¹ Aᵀ)`), kept with `e = 1`,
//! `A q̇⁺ = −e A q̇⁻`, and on the wall `h = 0, A q̇ = 0` to the tolerance with a pushing contact.
//!
//! The physics of [`PendulumChain::example`]: gravity holds the tip against the wall, so the
//! tip's bounces accumulate at a genuine Zeno point (flight ratio → `e`); then it slides on the
//! wall while the links above it swing; from about 4 links they swing hard enough to pull the
//! tip off the wall, and it lands again through another Zeno point.

use crate::conservation::assert_energy_constant_between_events;
use nalgebra::{DMatrix, DVector};
use zenosim::models::{Example, PendulumChain};
use zenosim::{
    Derived, Error, EventKind, Execution, Mode, Outcome, Simulation, SimulationOptions, State,
    Trajectory, ZenoKind, MAX_DIMENSION,
};

/// Runs `example` to `t_end`, sampled at the step ends.
fn run(example: &Example<PendulumChain>, t_end: f64) -> (Execution, Trajectory) {
    let options = SimulationOptions {
        t_end,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&example.model, &example.q0, &example.q_dot0, options)
        .expect("a valid chain")
        .run(&mut trajectory);
    (run, trajectory)
}

/// `A q̇` and `A M⁻¹ Aᵀ` at `state`.
fn normal(chain: &PendulumChain, state: &State) -> (f64, f64) {
    let derived = Derived::new(chain).unwrap();
    let n = chain.links;
    let (mass, positive) = derived.mass_matrix(&state.q, &state.q_dot);
    assert!(positive);
    let (_, a) = derived.constraint(0, &state.q);
    let a = DVector::from_vec(a);
    let m_inv_a = DMatrix::from_row_slice(n, n, &mass)
        .cholesky()
        .expect("M is positive definite")
        .solve(&a);
    (
        derived.normal_velocity(0, &state.q, &state.q_dot),
        a.dot(&m_inv_a),
    )
}

/// The energy at `state`.
fn energy(chain: &PendulumChain, state: &State) -> f64 {
    Derived::new(chain).unwrap().energy(&state.q, &state.q_dot)
}

#[test]
fn twenty_links_are_the_most_the_engine_takes() {
    assert_eq!(MAX_DIMENSION, 20);
}

/// Shortened to 1 s (the first Zeno point and some sliding on the wall): the tests run
/// unoptimised, where the whole 4 s take about 20 s at n = 20 (the benchmark runs them).
#[test]
fn a_chain_of_twenty_links_runs_past_its_zeno_point_and_finishes() {
    let chain = PendulumChain::example(20);
    let (run, trajectory) = run(&chain, 1.0);
    assert_eq!(run.outcome, Outcome::Finished);
    assert_eq!(run.t_final, 1.0);
    assert!(!run.zeno.is_empty(), "{:?}", run.stats);
    assert_eq!(run.zeno[0].kind, ZenoKind::Genuine);
    assert_eq!(run.final_state.q.len(), 20);
    assert!(
        trajectory.points.iter().all(|p| p.h[0] >= -1e-9),
        "the tip went through the wall"
    );
}

#[test]
fn a_chain_of_twenty_one_links_is_refused_with_the_dimension_error() {
    let chain = PendulumChain::example(MAX_DIMENSION + 1);
    let options = SimulationOptions::default();
    let err = Simulation::new(&chain.model, &chain.q0, &chain.q_dot0, options)
        .err()
        .expect("21 coordinates are more than the engine takes");
    assert_eq!(
        err,
        Error::Dimension {
            dimension: 21,
            max: 20
        }
    );
    assert!(err.to_string().contains("1 to 20"), "{err}");
    assert!(matches!(
        Derived::new(&chain.model),
        Err(Error::Dimension {
            dimension: 21,
            max: 20
        })
    ));
}

/// Every impact loses exactly `½(1−e²)(A q̇⁻)²/(A M⁻¹ Aᵀ) ≥ 0` and gives `A q̇⁺ = −e A q̇⁻`; the
/// switch onto the wall (`R∞`, a plastic impact) loses energy too, a lift-off none; in between
/// the energy is constant, in flight and on the wall.
#[test]
fn energy_never_increases_at_an_impact_and_is_constant_between_events() {
    for n in [1, 3, 5] {
        let chain = PendulumChain::example(n);
        let model = &chain.model;
        let (run, trajectory) = run(&chain, chain.t_end);
        assert_eq!(run.outcome, Outcome::Finished, "n = {n}");
        let e = 0.5;
        let mut impacts = 0;
        for event in &run.events {
            let (before, after) = (energy(model, &event.before), energy(model, &event.after));
            let scale = before.abs();
            match event.kind {
                EventKind::Impact => {
                    let (a_q_dot, a_m_a) = normal(model, &event.before);
                    let loss = 0.5 * (1.0 - e * e) * a_q_dot * a_q_dot / a_m_a;
                    assert!(
                        ((before - after) - loss).abs() <= 1e-12 * scale,
                        "n = {n}, t = {}: lost {} instead of {loss}",
                        event.t,
                        before - after
                    );
                    assert!(after <= before + 1e-13 * scale, "n = {n}, t = {}", event.t);
                    let (a_q_dot_after, _) = normal(model, &event.after);
                    assert!(
                        (a_q_dot_after + e * a_q_dot).abs() <= 1e-12 * (1.0 + a_q_dot.abs()),
                        "n = {n}, t = {}: A q̇ {a_q_dot} → {a_q_dot_after}",
                        event.t
                    );
                    impacts += 1;
                }
                EventKind::Zeno => assert!(after <= before + 1e-13 * scale),
                // The state is the same on both sides of a lift-off (and of a friction state's
                // change, which a frictionless chain has none of).
                EventKind::Liftoff | EventKind::Stick | EventKind::Slip => {}
            }
        }
        assert!(impacts >= 10, "n = {n}: {impacts} impacts");
        assert_energy_constant_between_events(&run, &trajectory);
    }
}

#[test]
fn with_e_1_energy_is_conserved_through_every_impact() {
    for n in [1, 3, 5] {
        let mut chain = PendulumChain::example(n);
        chain.model = chain.model.with_restitution(1.0);
        let model = &chain.model;
        let (run, trajectory) = run(&chain, chain.t_end);
        assert_eq!(run.outcome, Outcome::Finished, "n = {n}");
        // Elastic impacts never accumulate here: the tip bounces off the wall and comes back.
        assert!(run.zeno.is_empty(), "n = {n}: {:?}", run.zeno);
        assert!(
            run.events.len() >= 4,
            "n = {n}: {} impacts",
            run.events.len()
        );
        let e0 = energy(
            model,
            &State {
                q: chain.q0.clone(),
                q_dot: chain.q_dot0.clone(),
            },
        );
        for event in &run.events {
            assert_eq!(event.kind, EventKind::Impact);
            let (before, after) = (energy(model, &event.before), energy(model, &event.after));
            assert!(
                (after - before).abs() <= 1e-13 * before.abs(),
                "n = {n}, t = {}: {before} → {after}",
                event.t
            );
        }
        for p in &trajectory.points {
            assert!(
                (p.energy - e0).abs() <= 1e-8 * e0.abs(),
                "n = {n}, t = {}: energy {} vs {e0}",
                p.t,
                p.energy
            );
        }
    }
}

/// The tip's bounces shrink by `e` to a genuine Zeno point, and from there it slides on the
/// wall: `h = 0` and `A q̇ = 0` to the tolerance, the wall pushing (`λ < 0`), the tip moving.
#[test]
fn the_tip_bounces_to_a_zeno_point_then_slides_on_the_wall() {
    let chain = PendulumChain::example(3);
    let model = &chain.model;
    let (run, trajectory) = run(&chain, chain.t_end);
    assert_eq!(run.outcome, Outcome::Finished);
    assert_eq!(run.zeno.len(), 1);
    let zeno = &run.zeno[0];
    assert_eq!(zeno.kind, ZenoKind::Genuine);
    assert!(zeno.impacts >= 15, "{zeno:?}");
    assert!((zeno.ratio.unwrap() - 0.5).abs() < 1e-3, "{zeno:?}");
    // The switch comes just before τ∞: here once the next bounce is within 1e4 ulps of the
    // rounding of h (about 1e-12 high, 1e-6 s with the remaining ones).
    assert!(
        zeno.t_switch < zeno.t_zeno && zeno.t_zeno - zeno.t_switch < 1e-5,
        "{zeno:?}"
    );
    // The later flights shrink (the first ones are still shaped by the links' swing).
    let times = run.impact_times(0);
    let flights: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    for pair in flights[flights.len() - 10..].windows(2) {
        assert!(pair[1] < pair[0], "{flights:?}");
    }
    assert_eq!(
        run.final_mode,
        Mode::Constrained(zenosim::ActiveSet::single(0))
    );

    let derived = Derived::new(model).unwrap();
    let on_wall: Vec<_> = trajectory
        .points
        .iter()
        .filter(|p| matches!(p.mode, Mode::Constrained(_)))
        .collect();
    assert!(on_wall.len() > 20, "{} points on the wall", on_wall.len());
    for p in &on_wall {
        let a_q_dot = derived.normal_velocity(0, &p.q, &p.q_dot);
        assert!(
            p.h[0].abs() <= 1e-10 && a_q_dot.abs() <= 1e-10,
            "{p:?}: A q̇ = {a_q_dot}"
        );
        assert!(p.lambda[0] < 0.0, "the wall pulls: {p:?}");
        let (x, _) = model.tip(&p.q);
        assert!(
            (x - model.wall).abs() <= 1e-10,
            "the tip is off the wall: x = {x}"
        );
    }
    let heights: Vec<f64> = on_wall.iter().map(|p| model.tip(&p.q).1).collect();
    let range = heights.iter().fold(f64::MIN, |a, &b| a.max(b))
        - heights.iter().fold(f64::MAX, |a, &b| a.min(b));
    assert!(range > 1e-2, "the tip stays put on the wall: {range}");
}

/// From 5 links, the links' swing pulls the tip off the wall (`λ` reaches 0) and it falls back:
/// impacts, a Zeno point, a lift-off, impacts, a Zeno point.
#[test]
fn the_tip_lifts_off_the_wall_and_lands_again() {
    let chain = PendulumChain::example(5);
    let (run, trajectory) = run(&chain, chain.t_end);
    assert_eq!(run.outcome, Outcome::Finished);
    let kinds: String = run
        .events
        .iter()
        .map(|e| match e.kind {
            EventKind::Impact => 'i',
            EventKind::Zeno => 'Z',
            EventKind::Liftoff => 'L',
            EventKind::Stick | EventKind::Slip => 'F',
        })
        .collect();
    let pattern = kinds.trim_start_matches('i');
    assert!(
        kinds.len() - pattern.len() >= 10 && pattern.starts_with("ZLiiiiiiiiii"),
        "{kinds}"
    );
    assert_eq!(run.zeno.len(), 2, "{kinds}");
    let liftoff = run
        .events
        .iter()
        .find(|e| e.kind == EventKind::Liftoff)
        .unwrap();
    // At the lift-off the contact force has vanished (relative to its size at rest) …
    let rest_force = chain.model.wall_rest_force();
    let lambda_at = |t: f64| {
        trajectory
            .points
            .iter()
            .rfind(|p| p.t <= t && matches!(p.mode, Mode::Constrained(_)))
            .map(|p| p.lambda[0])
            .unwrap()
    };
    assert!(
        lambda_at(liftoff.t).abs() <= 1e-6 * rest_force,
        "{}",
        lambda_at(liftoff.t)
    );
    // … and the tip then flies clear of the wall before it lands again.
    let landing = run.events.iter().find(|e| e.t > liftoff.t).unwrap();
    let clearance = trajectory
        .points
        .iter()
        .filter(|p| p.t > liftoff.t && p.t < landing.t)
        .map(|p| p.h[0])
        .fold(0.0, f64::max);
    assert!(clearance > 1e-3, "{clearance}");
}

/// Started at rest in [`PendulumChain::wall_rest`], the chain stays there, the wall pushing the
/// tip with `F = f m g` (its force balance).
#[test]
fn the_rest_shape_on_the_wall_is_an_equilibrium() {
    for n in [1, 4, 10] {
        let model = PendulumChain::example(n).model;
        let rest = model.wall_rest();
        let chain = Example {
            q0: rest.clone(),
            q_dot0: vec![0.0; n],
            t_end: 1.0,
            model,
        };
        let (run, trajectory) = run(&chain, 1.0);
        assert_eq!(run.outcome, Outcome::Finished, "n = {n}");
        assert_eq!(
            run.final_mode,
            Mode::Constrained(zenosim::ActiveSet::single(0))
        );
        let force = chain.model.wall_rest_force();
        for p in trajectory.points.iter().filter(|p| p.t > 0.0) {
            for (q, r) in p.q.iter().zip(&rest) {
                assert!((q - r).abs() <= 1e-9, "n = {n}, t = {}: {:?}", p.t, p.q);
            }
            assert!(
                (p.lambda[0] + force).abs() <= 1e-9 * force,
                "n = {n}: λ = {} vs −F = {}",
                p.lambda[0],
                -force
            );
        }
    }
}
