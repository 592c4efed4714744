//! The paper's Example 6 (ball on `x3 = sin x2`, `e = 0.6`) and the authors' demo (`e = 0.9`).

use zenosim::models::BallOnSine;
use zenosim::{
    Completion, Derived, EventKind, Execution, Mode, Outcome, OutputGrid, Simulation,
    SimulationOptions, Trajectory, ZenoKind, ZenoStrategy,
};

fn run_paper(options: SimulationOptions) -> (Execution, Trajectory) {
    let ex = BallOnSine::paper();
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options)
        .unwrap()
        .run(&mut trajectory);
    (run, trajectory)
}

/// The largest difference between the final states `(q, q̇)` of two runs.
fn final_state_gap(a: &Execution, b: &Execution) -> f64 {
    let state = |x: &Execution| {
        let s = &x.final_state;
        s.q.iter().chain(&s.q_dot).copied().collect::<Vec<f64>>()
    };
    state(a)
        .iter()
        .zip(state(b))
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn paper_options() -> SimulationOptions {
    SimulationOptions {
        t_end: BallOnSine::paper().t_end,
        ..Default::default()
    }
}

#[test]
fn the_completed_system_runs_to_the_stop_time_past_the_zeno_point() {
    let (run, trajectory) = run_paper(paper_options());
    assert_eq!(run.outcome, Outcome::Finished);
    assert_eq!(run.t_final, 6.0);
    assert_eq!(run.zeno.len(), 1);
    let z = &run.zeno[0];
    assert_eq!(z.kind, ZenoKind::Genuine);
    // The paper: the plain simulation "gets stuck at around 2.04".
    assert!((2.0..2.1).contains(&z.t_zeno), "τ∞ = {}", z.t_zeno);
    // Near the Zeno point the flight times shrink by e = 0.6 (REFERENCE §1).
    assert!((z.ratio.unwrap() - 0.6).abs() < 1e-4, "{:?}", z.ratio);
    // After it, the ball slides along the surface (Fig. 5): it moves through a trough, so x2
    // changes direction at least once on the constrained interval.
    let after: Vec<_> = trajectory
        .points
        .iter()
        .filter(|p| p.t > z.t_switch && p.mode != Mode::Free)
        .collect();
    assert!(after.len() > 20);
    let turns = after
        .windows(2)
        .filter(|w| w[0].q_dot[1].signum() != w[1].q_dot[1].signum())
        .count();
    assert!(turns >= 1, "the ball should oscillate along the surface");
}

#[test]
fn x1_moves_uniformly_through_flights_impacts_the_switch_and_the_constrained_motion() {
    // x1 is absent from L and h: x1 = 0.5 t exactly (conservation law).
    let (_, trajectory) = run_paper(paper_options());
    for p in &trajectory.points {
        assert!((p.q[0] - 0.5 * p.t).abs() <= 1e-9, "{p:?}");
        assert!((p.q_dot[0] - 0.5).abs() <= 1e-9, "{p:?}");
    }
}

#[test]
fn the_constrained_motion_stays_on_the_surface_and_keeps_its_energy() {
    let (run, trajectory) = run_paper(paper_options());
    let ex = BallOnSine::paper();
    let derived = Derived::new(&ex.model).unwrap();
    let zeno = &run.zeno[0];
    // R∞ lands exactly on h = 0, A q̇ = 0.
    let (h, _) = derived.constraint(0, &zeno.point.q);
    let a_q_dot = derived.normal_velocity(0, &zeno.point.q, &zeno.point.q_dot);
    assert!(
        h.abs() <= 1e-12 && a_q_dot.abs() <= 1e-12,
        "{h:e} {a_q_dot:e}"
    );
    let constrained: Vec<_> = trajectory
        .points
        .iter()
        .filter(|p| matches!(p.mode, Mode::Constrained(_)))
        .collect();
    let e0 = constrained[0].energy;
    for p in &constrained {
        let a_q_dot = derived.normal_velocity(0, &p.q, &p.q_dot);
        assert!(p.h[0].abs() <= 1e-9 && a_q_dot.abs() <= 1e-9, "{p:?}");
        // No lift-off on this run: the surface pushes all along.
        assert!(p.lambda[0] <= 0.0, "{p:?}");
        // Energy is conserved on the constraint, to the integration tolerance.
        assert!(
            (p.energy - e0).abs() <= 1e-8 * (1.0 + e0.abs()),
            "{} vs {e0}",
            p.energy
        );
    }
}

/// DOPRI5 through the same run: each step on the surface is projected after its error test
/// (its estimate takes `f` at the step's end, before the projection), and the committed states
/// are on `h = 0`, `A q̇ = 0` to rounding; the Zeno point and the final state agree with
/// DOP853's to the tolerance.
#[test]
fn dopri5_runs_through_the_zeno_point_and_keeps_to_the_surface() {
    let tol = zenosim::Tolerances {
        rtol: 1e-8,
        atol: 1e-8,
    };
    let options = |method| SimulationOptions {
        method,
        tolerances: tol,
        ..paper_options()
    };
    let (dopri, trajectory) = run_paper(options(zenosim::Method::Dopri5));
    let (dop853, _) = run_paper(options(zenosim::Method::Dop853));
    assert_eq!(dopri.outcome, Outcome::Finished);
    assert_eq!(dopri.zeno.len(), 1);
    let gap = (dopri.zeno[0].t_zeno - dop853.zeno[0].t_zeno).abs();
    assert!(gap < 1e-7, "τ∞ {gap:e} apart");
    let ex = BallOnSine::paper();
    let derived = Derived::new(&ex.model).unwrap();
    let mut on_surface = 0;
    for p in trajectory.points.iter().filter(|p| p.mode != Mode::Free) {
        let a_q_dot = derived.normal_velocity(0, &p.q, &p.q_dot);
        assert!(p.h[0].abs() <= 1e-12 && a_q_dot.abs() <= 1e-12, "{p:?}");
        on_surface += 1;
    }
    assert!(on_surface > 20, "{on_surface} states on the surface");
    let gap = final_state_gap(&dopri, &dop853);
    assert!(gap < 1e-5, "final states {gap:e} apart");
}

#[test]
fn without_completion_the_run_stops_by_itself_near_t_2_04() {
    let (auto, _) = run_paper(paper_options());
    let (off, trajectory) = run_paper(SimulationOptions {
        zeno: ZenoStrategy::Off,
        ..paper_options()
    });
    let Outcome::ZenoStalled { t_zeno, constraint } = off.outcome else {
        panic!("expected a stall, got {:?}", off.outcome);
    };
    assert_eq!(constraint, 0);
    // The paper's Fig. 4: stuck at about 2.04; the same τ∞ as the completed run predicts.
    assert!((2.0..2.1).contains(&t_zeno));
    assert!((t_zeno - auto.zeno[0].t_zeno).abs() < 1e-8);
    assert!(off.t_final < t_zeno);
    assert!(off.events.iter().all(|e| e.kind == EventKind::Impact));
    assert!(trajectory.points.iter().all(|p| p.h[0] >= -1e-9));
}

#[test]
fn the_papers_epsilon_rule_lands_close_to_auto() {
    // ε = 1e-3 (the authors' demos). The switch is earlier, and what it changes after the Zeno
    // point is of order |A q̇|·T_rem, far below ε.
    let (auto, _) = run_paper(paper_options());
    let (eps, _) = run_paper(SimulationOptions {
        zeno: ZenoStrategy::Epsilon(1e-3),
        ..paper_options()
    });
    assert_eq!(eps.outcome, Outcome::Finished);
    assert!(eps.zeno[0].t_switch < auto.zeno[0].t_switch);
    assert!(eps.stats.impacts < auto.stats.impacts);
    for (a, b) in auto.final_state.q.iter().zip(&eps.final_state.q) {
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }
}

#[test]
fn the_papers_own_completion_map_also_lands_on_the_surface() {
    // With the paper's rule the paper's map acts on the state just before the impact, as in
    // the paper: x3 = sin x2, ẋ3 = cos(x2) ẋ2, with x2 and ẋ2 kept from the free state.
    let (run, _) = run_paper(SimulationOptions {
        completion: Completion::ModelMap,
        zeno: ZenoStrategy::Epsilon(1e-3),
        ..paper_options()
    });
    assert_eq!(run.outcome, Outcome::Finished);
    let point = &run.zeno[0].point;
    let before = &run
        .events
        .iter()
        .find(|e| e.kind == EventKind::Zeno)
        .unwrap()
        .before;
    assert_eq!(point.q[1], before.q[1]);
    assert_eq!(point.q_dot[1], before.q_dot[1]);
    assert!((point.q[2] - point.q[1].sin()).abs() < 1e-15);
}

/// The authors' demo (e = 0.9, to t = 20) with the paper's map under `Auto`: the switch comes
/// while the bounces not taken still have a normal velocity of about 1e-5, which the paper's map
/// (ẋ3 = cos(x2) ẋ2, ẋ2 kept) would turn into an error along the surface; projected first, the
/// run ends where the general projection's does, which the ε rule converges to as ε → 0.
#[test]
fn under_auto_the_papers_map_acts_on_the_projected_state() {
    let demo = BallOnSine::demo();
    let run = |completion, zeno| {
        let options = SimulationOptions {
            t_end: demo.t_end,
            completion,
            zeno,
            ..Default::default()
        };
        Simulation::new(&demo.model, &demo.q0, &demo.q_dot0, options)
            .unwrap()
            .run(&mut ())
    };
    let map = run(Completion::ModelMap, ZenoStrategy::Auto);
    let projection = run(Completion::Projection, ZenoStrategy::Auto);
    assert_eq!(map.outcome, Outcome::Finished);
    let leftover = {
        let before = &map
            .events
            .iter()
            .find(|e| e.kind == EventKind::Zeno)
            .unwrap()
            .before;
        let d = Derived::new(&demo.model).unwrap();
        d.normal_velocity(0, &before.q, &before.q_dot).abs()
    };
    assert!(
        leftover > 1e-7,
        "the switch leaves a normal velocity: {leftover}"
    );
    let gap = final_state_gap(&map, &projection);
    // Without the projection first this gap was 3.8e-5.
    assert!(gap < 1e-8, "paper's map vs projection at t = 20: {gap}");
}

#[test]
fn a_uniform_output_grid_samples_every_dt_and_every_event() {
    let dt = 0.01;
    let (run, trajectory) = run_paper(SimulationOptions {
        output: OutputGrid::Uniform(dt),
        ..paper_options()
    });
    let grid: Vec<_> = trajectory
        .points
        .iter()
        .map(|p| p.t)
        .filter(|t| !run.events.iter().any(|e| e.t == *t))
        .collect();
    assert_eq!(grid.len(), 601, "0, 0.01, …, 6");
    for (k, t) in grid.iter().enumerate() {
        assert!((t - k as f64 * dt).abs() < 1e-12, "{k}: {t}");
    }
    // Two points (before and after) for every event; a state shared by two events (the switch
    // right after an impact starts from that impact's state after) is sent once.
    let shared = run
        .events
        .windows(2)
        .filter(|w| w[0].t == w[1].t && w[0].after == w[1].before)
        .count();
    let at_events = trajectory.points.len() - grid.len();
    assert_eq!(at_events, 2 * run.events.len() - shared);
}

#[test]
fn the_authors_demo_with_e_0_9_runs_to_its_stop_time() {
    let ex = BallOnSine::demo();
    let options = SimulationOptions {
        t_end: ex.t_end,
        ..Default::default()
    };
    let run = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options)
        .unwrap()
        .run(&mut ());
    assert_eq!(run.outcome, Outcome::Finished);
    assert!(run.zeno.iter().all(|z| z.kind == ZenoKind::Genuine));
    assert!((run.zeno[0].ratio.unwrap() - 0.9).abs() < 1e-4);
    assert!((run.final_state.q[0] - 0.5 * ex.t_end).abs() < 1e-9);
}

/// A model whose free flight is declared a parabola, or not, by hand (whatever the model says).
struct Declared<M> {
    model: M,
    parabolic: bool,
}

impl<M: zenosim::HybridLagrangian> zenosim::HybridLagrangian for Declared<M> {
    const DIMENSION: Option<usize> = M::DIMENSION;
    fn dimension(&self) -> usize {
        self.model.dimension()
    }
    fn lagrangian<D: zenosim::Scalar>(&self, q: &[D], q_dot: &[D]) -> D {
        self.model.lagrangian(q, q_dot)
    }
    fn constraints(&self) -> &[zenosim::Constraint] {
        self.model.constraints()
    }
    fn constraint<D: zenosim::Scalar>(&self, index: usize, q: &[D]) -> D {
        self.model.constraint(index, q)
    }
    fn parabolic_flight(&self) -> bool {
        self.parabolic
    }
}

/// Stepping a free flight on its parabola in closed form, and reading the states inside it off
/// its cubic interpolant (exact there), gives the execution of the general route (Runge–Kutta
/// steps, their dense output, a fresh step to each impact) to within the integration's
/// accuracy, with a third fewer evaluations.
#[test]
fn a_parabolic_flight_runs_as_the_general_route_with_fewer_evaluations() {
    use zenosim::HybridLagrangian;
    let ex = BallOnSine::paper();
    assert!(ex.model.parabolic_flight());
    // Without the declaration zenosim takes Runge–Kutta steps, prepares each free step's dense
    // output and steps again to each impact.
    let undeclared = Declared {
        model: ex.model.clone(),
        parabolic: false,
    };
    assert!(!undeclared.parabolic_flight());
    let options = paper_options();
    let fast = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options)
        .unwrap()
        .run(&mut ());
    let general = Simulation::new(&undeclared, &ex.q0, &ex.q_dot0, options)
        .unwrap()
        .run(&mut ());
    assert_eq!(fast.outcome, Outcome::Finished);
    assert_eq!(general.outcome, Outcome::Finished);
    // The bounces the integration resolves (the last ones before the switch are at the
    // guard's rounding, where any two computations part).
    let (a, b) = (fast.impact_times(0), general.impact_times(0));
    assert!(a.len() > 20 && b.len() > 20, "{} and {}", a.len(), b.len());
    for (k, (x, y)) in a.iter().zip(&b).take(15).enumerate() {
        assert!((x - y).abs() <= 1e-12, "impact {k}: {x} and {y}");
    }
    let (za, zb) = (&fast.zeno[0], &general.zeno[0]);
    assert!(
        (za.t_zeno - zb.t_zeno).abs() <= 1e-9,
        "τ∞ {} and {}",
        za.t_zeno,
        zb.t_zeno
    );
    // The state at t = 6 within the tolerance (1e-10) of each other.
    let gap = final_state_gap(&fast, &general);
    assert!(gap <= 1e-10, "final states differ by {gap:e}");
    let (fewer, more) = (fast.stats.rhs_evals, general.stats.rhs_evals);
    println!(
        "parabolic flight: τ∞ {} and {}, final states {gap:e} apart, {fewer} and {more} \
         evaluations",
        za.t_zeno, zb.t_zeno
    );
    assert!(3 * fewer <= 2 * more, "{fewer} and {more} evaluations");
}

/// A model that declares a parabolic flight it does not have (its acceleration differs at the
/// ends of every free step) gets the execution it would get without the claim, to the bit:
/// every closed-form step is checked by the acceleration at its end, and taken by the
/// integrator instead where that differs. The claim costs that one evaluation per free step.
#[test]
fn a_wrong_parabolic_claim_changes_nothing_but_one_evaluation_per_free_step() {
    use zenosim::models::CartPendulum;
    let ex = CartPendulum::demo();
    let options = SimulationOptions {
        t_end: ex.t_end,
        ..Default::default()
    };
    // The cart pendulum's pendulum swings: its flight is no parabola.
    let claimed = Declared {
        model: ex.model.clone(),
        parabolic: true,
    };
    let honest = Simulation::new(&ex.model, &ex.q0, &ex.q_dot0, options)
        .unwrap()
        .run(&mut ());
    let wrong = Simulation::new(&claimed, &ex.q0, &ex.q_dot0, options)
        .unwrap()
        .run(&mut ());
    assert_eq!(honest.outcome, Outcome::Finished);
    assert_eq!(wrong.outcome, honest.outcome);
    assert_eq!(wrong.events, honest.events);
    assert_eq!(wrong.zeno, honest.zeno);
    assert_eq!(wrong.intervals, honest.intervals);
    assert_eq!(wrong.final_state, honest.final_state);
    assert_eq!(wrong.stats.steps, honest.stats.steps);
    assert_eq!(wrong.stats.impacts, honest.stats.impacts);
    assert!(honest.stats.impacts > 100, "{:?}", honest.stats);
    let extra = wrong.stats.rhs_evals - honest.stats.rhs_evals;
    assert!(
        extra > 0 && extra < wrong.stats.steps,
        "{extra} more evaluations over {} steps",
        wrong.stats.steps
    );
}
