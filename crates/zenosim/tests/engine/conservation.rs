//! Momenta whose coordinate is absent from `L` and from `A` are conserved through flights,
//! impacts, the switch and the constrained motion (REFERENCE §3).

use zenosim::models::{CartPendulum, Example, SphericalPendulum};
use zenosim::{
    Execution, HybridLagrangian, Mode, Outcome, Simulation, SimulationOptions, Trajectory, ZenoKind,
};

/// Runs a demo to its stop time, sampled at step ends (the dense output in between is about
/// 10× less accurate), with steps of at most 0.5 s: on the constraint the motion is simple
/// enough to cross in one. It must finish, through exactly one Zeno point.
fn run_to_the_end<M: HybridLagrangian>(ex: &Example<M>) -> (Execution, Trajectory) {
    let options = SimulationOptions {
        t_end: ex.t_end,
        max_step: 0.5,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options)
        .unwrap()
        .run(&mut trajectory);
    assert_eq!(run.outcome, Outcome::Finished);
    assert_eq!(run.zeno.len(), 1);
    (run, trajectory)
}

#[test]
fn the_carts_velocity_after_the_zeno_point_is_p_x_over_the_total_mass() {
    let ex = CartPendulum::demo();
    let model = &ex.model;
    let (run, trajectory) = run_to_the_end(&ex);
    assert_eq!(run.zeno[0].kind, ZenoKind::Genuine);
    let p_x = model.momentum_x(&ex.q0, &ex.q_dot0);
    let x_dot_after = p_x / (model.cart_mass + model.bob_mass);
    let mut checked = 0;
    for p in &trajectory.points {
        // p_x is conserved everywhere (relative to its size).
        let drift = (model.momentum_x(&p.q, &p.q_dot) - p_x).abs();
        assert!(drift <= 1e-8 * p_x.abs(), "t = {}: drift {drift:e}", p.t);
        if matches!(p.mode, Mode::Constrained(_)) {
            assert!(
                (p.q_dot[1] - x_dot_after).abs() <= 1e-9,
                "{p:?} vs {x_dot_after}"
            );
            assert!((p.q[0].abs() - std::f64::consts::FRAC_PI_2).abs() <= 1e-12);
            checked += 1;
        }
    }
    assert!(checked > 10);
}

#[test]
fn the_spherical_pendulums_phi_dot_after_the_zeno_point_is_sin2_theta0_phi_dot0() {
    let ex = SphericalPendulum::demo();
    let model = &ex.model;
    let (_, trajectory) = run_to_the_end(&ex);
    let p_phi = model.momentum_phi(&ex.q0, &ex.q_dot0);
    let phi_dot_after = ex.q0[0].sin().powi(2) * ex.q_dot0[1];
    let mut checked = 0;
    for p in &trajectory.points {
        let drift = (model.momentum_phi(&p.q, &p.q_dot) - p_phi).abs();
        assert!(drift <= 1e-8 * p_phi.abs(), "t = {}: drift {drift:e}", p.t);
        if matches!(p.mode, Mode::Constrained(_)) {
            assert!(
                (p.q_dot[1] - phi_dot_after).abs() <= 1e-9,
                "{p:?} vs {phi_dot_after}"
            );
            checked += 1;
        }
    }
    assert!(checked > 10);
}

#[test]
fn energy_is_lost_only_at_impacts() {
    let ex = CartPendulum::demo();
    let options = SimulationOptions {
        t_end: ex.t_end,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options)
        .unwrap()
        .run(&mut trajectory);
    assert_energy_constant_between_events(&run, &trajectory);
}

/// The energy is constant between consecutive events (free flight, or motion on a
/// constraint), to the integration tolerance (`rtol = atol = 1e-10`, over some hundred steps).
pub fn assert_energy_constant_between_events(run: &Execution, trajectory: &Trajectory) {
    let mut bounds: Vec<f64> = run.events.iter().map(|e| e.t).collect();
    bounds.push(f64::INFINITY);
    let mut start = f64::NEG_INFINITY;
    let mut checked = 0;
    for end in bounds {
        let inside: Vec<_> = trajectory
            .points
            .iter()
            .filter(|p| p.t > start && p.t < end)
            .collect();
        if let Some(first) = inside.first() {
            for p in &inside {
                assert!(
                    (p.energy - first.energy).abs() <= 1e-8 * (1.0 + first.energy.abs()),
                    "t = {} ({}): energy {} but {} at t = {}",
                    p.t,
                    p.mode.name(),
                    p.energy,
                    first.energy,
                    first.t
                );
                checked += 1;
            }
        }
        start = end;
    }
    assert!(checked >= 10, "only {checked} points between events");
}
