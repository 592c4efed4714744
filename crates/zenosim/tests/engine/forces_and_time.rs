//! Forces, dissipation and surfaces that move (docs/forces-and-time.md), against the closed
//! forms of the models in `zenosim::models`, and the energy balance on each.

use zenosim::models::{DampedOscillator, DraggedBall, VibratingTable};
use zenosim::{
    Constraint, Derived, Error, EventKind, Execution, HybridLagrangian, Outcome, Scalar,
    Simulation, SimulationOptions, Trajectory,
};

/// Runs `example`'s model from its initial state to `t_end`, keeping the trajectory.
fn run<L: HybridLagrangian>(
    model: &L,
    q0: &[f64],
    q_dot0: &[f64],
    t_end: f64,
) -> (Execution, Trajectory) {
    let options = SimulationOptions {
        t_end,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(model, q0, q_dot0, options)
        .unwrap()
        .run(&mut trajectory);
    assert_eq!(run.outcome, Outcome::Finished, "{:?}", run.outcome);
    (run, trajectory)
}

/// `E(t) − E(0) = W_forces + W_drive + W_constraints − ΔE_impacts` at every sample and at the
/// end, to `tol` relative to the energies and works involved; the worst residual.
fn balance_holds<L: HybridLagrangian>(
    model: &L,
    run: &Execution,
    trajectory: &Trajectory,
    tol: f64,
) -> f64 {
    let worst = trajectory.balance_residual();
    assert!(worst <= tol, "the energy balance is off by {worst:e}");
    let e0 = trajectory.points[0].energy;
    let derived = Derived::new(model).unwrap().at_time(run.t_final);
    let end = derived.energy(&run.final_state.q, &run.final_state.q_dot);
    let w = run.work;
    let size = e0.abs() + end.abs() + w.forces.abs() + w.drive.abs() + w.constraints.abs();
    let residual = (end - e0 - w.balance()).abs() / (size + w.impact_loss.abs());
    assert!(residual <= tol, "at the end: {residual:e}");
    worst.max(residual)
}

/// With `a ω² > g`, the ball chatters to rest on the table, is carried, and leaves it where the
/// table's downward acceleration reaches `g`, every time.
#[test]
fn a_ball_on_a_vibrating_table_leaves_it_where_the_table_decelerates_at_g() {
    let example = VibratingTable::example();
    let model = &example.model;
    let phase = model.liftoff_phase().expect("a ω² > g");
    let (run, trajectory) = run(model, &example.q0, &example.q_dot0, example.t_end);
    let liftoffs: Vec<f64> = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Liftoff)
        .map(|e| e.t)
        .collect();
    assert!(liftoffs.len() >= 20, "{} lift-offs", liftoffs.len());
    assert!(run.zeno.len() >= 20, "{} Zeno points", run.zeno.len());
    let mut worst: f64 = 0.0;
    for t in liftoffs {
        let theta = (model.frequency * t).rem_euclid(std::f64::consts::TAU);
        worst = worst.max((theta - phase).abs());
        assert!(
            (theta - phase).abs() <= 1e-9,
            "lift-off at t = {t}: phase {theta}, expected {phase}"
        );
    }
    let balance = balance_holds(model, &run, &trajectory, 1e-8);
    eprintln!("vibrating table: lift-off phase within {worst:e} rad; balance {balance:e}");
}

/// With `a ω² < g` the ball, once at rest on the table after its Zeno point, never leaves it.
#[test]
fn a_ball_on_a_gently_vibrating_table_stays_on_it_after_its_zeno_point() {
    let model = VibratingTable::new(1.0, 9.81, 0.002, 20.0 * std::f64::consts::PI, 0.5);
    assert_eq!(model.liftoff_phase(), None);
    let (run, trajectory) = run(&model, &[0.05], &[0.0], 2.0);
    assert_eq!(run.zeno.len(), 1);
    assert!(run.events.iter().all(|e| e.kind != EventKind::Liftoff));
    let last = run.events.last().unwrap();
    assert_eq!(last.kind, EventKind::Zeno);
    // Carried by the table from there: y = a sin(ω t) to the tolerance.
    for p in trajectory.points.iter().filter(|p| p.t > last.t) {
        let table = model.table(p.t);
        assert!(
            (p.q[0] - table).abs() <= 1e-9,
            "t = {}: y = {}, table {table}",
            p.t,
            p.q[0]
        );
    }
    balance_holds(&model, &run, &trajectory, 1e-8);
}

#[test]
fn a_ball_with_air_drag_bounces_at_the_closed_form_times_and_zeno_time() {
    let example = DraggedBall::example();
    let (exact, t_zeno) = example.model.impacts(example.q0[0]);
    let (run, trajectory) = run(&example.model, &example.q0, &example.q_dot0, example.t_end);
    let times = run.impact_times(0);
    assert!(times.len() >= 20);
    for (k, (t, x)) in times.iter().zip(&exact).enumerate() {
        assert!((t - x).abs() <= 1e-9 * x, "impact {k}: {t} against {x}");
    }
    assert_eq!(run.zeno.len(), 1);
    let t_zeno_run = run.zeno[0].t_zeno;
    assert!(
        (t_zeno_run - t_zeno).abs() <= 1e-8 * t_zeno,
        "Zeno time {t_zeno_run} against {t_zeno}"
    );
    balance_holds(&example.model, &run, &trajectory, 1e-8);
    // The drag did negative work, the impacts took energy out.
    assert!(run.work.forces < 0.0 && run.work.impact_loss > 0.0);
}

#[test]
fn a_damped_oscillator_against_a_wall_hits_it_at_the_closed_form_times() {
    let example = DampedOscillator::example();
    let (exact, t_zeno) = example.model.impacts(example.q0[0]);
    let (run, trajectory) = run(&example.model, &example.q0, &example.q_dot0, example.t_end);
    let times = run.impact_times(0);
    assert!(times.len() >= 20);
    for (k, (t, x)) in times.iter().zip(&exact).enumerate() {
        assert!((t - x).abs() <= 1e-9 * x, "impact {k}: {t} against {x}");
    }
    assert_eq!(run.zeno.len(), 1);
    let t_zeno_run = run.zeno[0].t_zeno;
    assert!(
        (t_zeno_run - t_zeno).abs() <= 1e-8 * t_zeno,
        "Zeno time {t_zeno_run} against {t_zeno}"
    );
    balance_holds(&example.model, &run, &trajectory, 1e-8);
}

/// A model that says it is autonomous but has a force is refused at the start, not run
/// without it.
#[test]
fn a_model_that_hides_its_force_is_refused() {
    struct Hidden([Constraint; 1]);
    impl HybridLagrangian for Hidden {
        fn dimension(&self) -> usize {
            1
        }
        fn lagrangian<D: Scalar>(&self, _q: &[D], v: &[D]) -> D {
            v[0] * v[0] * 0.5
        }
        fn constraints(&self) -> &[Constraint] {
            &self.0
        }
        fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
            q[0]
        }
        fn generalized_force<D: Scalar>(&self, _t: D, _q: &[D], _v: &[D], force: &mut [D]) {
            force[0] -= D::one();
        }
    }
    let model = Hidden([Constraint::new("floor", 0.5)]);
    let refused = Simulation::new(&model, &[1.0], &[0.0], SimulationOptions::default());
    assert!(matches!(refused, Err(Error::NotAutonomous { .. })));
}
