//! The classic bouncing ball against its closed form (REFERENCE §3):
//! `τ_k = t1 (1 + 2e (1 − e^(k−1))/(1 − e))`, `τ∞ = t1 (1+e)/(1−e)`, `t1 = √(2 h0/g)`.

use zenosim::models::BouncingBall;
use zenosim::{
    Constraint, EventKind, Execution, HybridLagrangian, Mode, Outcome, Scalar, Simulation,
    SimulationOptions, Tolerances, Trajectory, ZenoKind, ZenoStrategy,
};

const G: f64 = 9.81;
const H0: f64 = 1.0;

fn run(e: f64, zeno: ZenoStrategy, t_end: f64) -> (BouncingBall, Execution, Trajectory) {
    let ball = BouncingBall::new(1.0, G, e);
    let options = SimulationOptions {
        t_end,
        zeno,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&ball, &[H0], &[0.0], options)
        .unwrap()
        .run(&mut trajectory);
    (ball, run, trajectory)
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn zeno_time_and_first_30_impacts_match_the_closed_form() {
    for e in [0.5, 0.8] {
        let (ball, run, _) = run(e, ZenoStrategy::Auto, 10.0);
        assert_eq!(run.outcome, Outcome::Finished);
        let tau_inf = ball.zeno_time(H0);
        assert_eq!(run.zeno.len(), 1, "e = {e}");
        let z = &run.zeno[0];
        assert_eq!(z.kind, ZenoKind::Genuine);
        assert!(
            relative(z.t_zeno, tau_inf) < 1e-9,
            "e = {e}: τ∞ = {} vs closed form {tau_inf}",
            z.t_zeno
        );
        let impacts = run.impact_times(0);
        assert!(
            impacts.len() >= 30,
            "e = {e}: only {} impacts",
            impacts.len()
        );
        for (k, t) in impacts.iter().take(30).enumerate() {
            let exact = ball.impact_time(H0, k as u32 + 1);
            assert!(
                relative(*t, exact) < 1e-9,
                "e = {e}: impact {} at {t} vs closed form {exact}",
                k + 1
            );
        }
        // The measured ratio of flight times tends to e (REFERENCE §1). It comes from the last
        // flights, ~1e-11 s long, timed to an ulp of t ≈ 1.4: about 3e-5 relative.
        assert!((z.ratio.unwrap() - e).abs() < 1e-4, "{:?}", z.ratio);
        // The switch comes before τ∞, and only just.
        assert!(z.t_switch < tau_inf && tau_inf - z.t_switch < 1e-8);
    }
}

#[test]
fn after_the_zeno_point_the_ball_rests_on_the_floor() {
    let (ball, run, trajectory) = run(0.5, ZenoStrategy::Auto, 5.0);
    let tau_inf = ball.zeno_time(H0);
    assert_eq!(
        run.final_mode,
        Mode::Constrained(zenosim::ActiveSet::single(0))
    );
    for p in trajectory.points.iter().filter(|p| p.t > tau_inf) {
        assert!(p.q[0].abs() <= 1e-12 && p.q_dot[0].abs() <= 1e-12, "{p:?}");
        // The floor carries the weight: λ = −m g (contact force −Aᵀλ = m g up).
        assert!((p.lambda[0] + G).abs() < 1e-9, "{p:?}");
    }
}

/// Regression: a single plastic impact (e = 0) was reported as a "Zeno point (chattering)
/// after 1 impact". The paper's hybrid system has infinitely many zero-length intervals there
/// (its chattering Zeno); zenosim records what happens, one impact at t1 that leaves the ball
/// at rest on the floor, held from then on (docs/contact-laws.md, law 2).
#[test]
fn a_single_plastic_impact_was_reported_as_a_zeno_point() {
    let (ball, run, trajectory) = run(0.0, ZenoStrategy::Auto, 2.0);
    let t1 = ball.impact_time(H0, 1);
    assert!(run.zeno.is_empty(), "{:?}", run.zeno);
    assert_eq!(run.stats.impacts, 1);
    assert_eq!(run.events.len(), 1);
    let impact = &run.events[0];
    assert_eq!(impact.kind, EventKind::Impact);
    assert!(relative(impact.t, t1) < 1e-12);
    assert_eq!(impact.after.q_dot[0], 0.0);
    let floor = Mode::Constrained(zenosim::ActiveSet::single(0));
    assert_eq!(run.final_mode, floor);
    for p in trajectory.points.iter().filter(|p| p.t > impact.t) {
        assert_eq!(p.mode, floor);
        assert!(p.q[0].abs() <= 1e-12 && p.q_dot[0].abs() <= 1e-12, "{p:?}");
    }
}

#[test]
fn off_stalls_at_the_zeno_point_and_never_falls_through() {
    let (ball, run, trajectory) = run(0.5, ZenoStrategy::Off, 10.0);
    let tau_inf = ball.zeno_time(H0);
    let Outcome::ZenoStalled { t_zeno, .. } = run.outcome else {
        panic!("expected a stall, got {:?}", run.outcome);
    };
    assert!(relative(t_zeno, tau_inf) < 1e-9);
    // It stops where f64 time can no longer separate the impacts from τ∞.
    assert!(run.t_final <= t_zeno && t_zeno - run.t_final < 1e-12);
    assert!(trajectory.points.iter().all(|p| p.q[0] >= -1e-12));
    assert!(run.events.iter().all(|e| e.kind == EventKind::Impact));
}

#[test]
fn the_epsilon_rule_switches_on_the_pre_impact_state() {
    let eps = 1e-3;
    let (ball, run, _) = run(0.5, ZenoStrategy::Epsilon(eps), 5.0);
    let zeno = run
        .events
        .iter()
        .find(|e| e.kind == EventKind::Zeno)
        .unwrap();
    // The last free state before the switch is within ε of the surface, moving in.
    assert!(zeno.before.q[0].abs() <= eps && zeno.before.q_dot[0].abs() <= eps);
    assert!(zeno.before.q_dot[0] <= 0.0);
    // Every earlier impact came in faster than ε.
    for e in run.events.iter().filter(|e| e.kind == EventKind::Impact) {
        assert!(e.before.q_dot[0].abs() > eps);
    }
    // The prediction of τ∞ from the pre-impact state is still the closed form (flat floor).
    assert!(relative(run.zeno[0].t_zeno, ball.zeno_time(H0)) < 1e-9);
    // The crossing replaced by the switch is not an impact: the counts agree.
    let impacts = run.impact_times(0).len();
    assert_eq!(run.zeno[0].impacts, impacts);
    assert_eq!(run.stats.impacts, impacts as u64);
}

/// An observer that keeps the trajectory and asks to stop once it has seen `after` samples.
struct StopAfter {
    after: usize,
    kept: Trajectory,
}

impl zenosim::Observer for StopAfter {
    fn sample(&mut self, sample: &zenosim::Sample<'_>) {
        self.kept.sample(sample);
    }

    fn interrupted(&mut self) -> bool {
        self.kept.points.len() >= self.after
    }
}

#[test]
fn an_interrupted_run_ends_where_it_was_asked_keeping_what_it_computed() {
    let ball = BouncingBall::new(1.0, G, 0.8);
    let mut observer = StopAfter {
        after: 40,
        kept: Trajectory::default(),
    };
    let run = Simulation::new(&ball, &[H0], &[0.0], SimulationOptions::default())
        .unwrap()
        .run(&mut observer);
    assert_eq!(run.outcome, Outcome::Interrupted);
    // It stopped at the first step after the 40th sample, long before t_end = 10 and before
    // the Zeno time: the record ends at the last state sent.
    let last = observer.kept.points.last().unwrap();
    assert!(observer.kept.points.len() >= 40 && observer.kept.points.len() < 44);
    assert_eq!(run.t_final, last.t);
    assert_eq!(run.final_state.q, last.q);
    assert_eq!(run.final_state.q_dot, last.q_dot);
    assert!(run.t_final < ball.zeno_time(H0));
    assert_eq!(run.intervals.last().unwrap().end, run.t_final);
    // The impacts before the stop are recorded, and each is one of the closed form's.
    let impacts = run.impact_times(0);
    assert!(!impacts.is_empty());
    for (k, t) in impacts.iter().enumerate() {
        assert!(relative(*t, ball.impact_time(H0, k as u32 + 1)) < 1e-9);
    }
}

#[test]
fn an_interrupt_during_a_long_step_of_a_fine_grid_waited_for_the_step() {
    // At rest on the floor after its Zeno point, the ball takes steps of seconds, each holding
    // millions of points of a 1e-6 grid: the observer was asked only between steps, so Ctrl-C
    // took seconds (and the writer kept writing). It is now asked every 4096 grid points.
    let ball = BouncingBall::new(1.0, G, 0.5);
    let options = SimulationOptions {
        t_end: 10.0,
        output: zenosim::OutputGrid::Uniform(1e-6),
        max_steps: u64::MAX,
        ..Default::default()
    };
    let mut observer = StopAfter {
        after: 3_000_000,
        kept: Trajectory::default(),
    };
    let run = Simulation::new(&ball, &[H0], &[0.0], options)
        .unwrap()
        .run(&mut observer);
    assert_eq!(run.outcome, Outcome::Interrupted);
    // Within 4096 samples of the request (and one more: the state where it stopped).
    let kept = observer.kept.points.len();
    assert!((3_000_000..=3_004_097).contains(&kept), "{kept} samples");
    let last = observer.kept.points.last().unwrap();
    assert_eq!(run.t_final, last.t);
    assert!(run.t_final < 10.0);
}

/// Regression: the test that a constraint can act compared squares of norms, which overflow for
/// a ball of mass 1e-156 (`|M⁻¹Aᵀ|² = ∞`) and underflow for one of 1e201, so both failed with
/// "∂h/∂q = 0" at the first impact. The mass cancels out of the motion: every mass gives the
/// closed form's impacts and Zeno time.
#[test]
fn a_ball_of_any_mass_bounces_as_the_closed_form_says() {
    let tau_inf = BouncingBall::new(1.0, G, 0.5).zeno_time(H0);
    for m in [1e-300, 1e-156, 1e201, 1e300] {
        let ball = BouncingBall::new(m, G, 0.5);
        let options = SimulationOptions {
            t_end: 3.0,
            ..Default::default()
        };
        let run = Simulation::new(&ball, &[H0], &[0.0], options)
            .unwrap()
            .run(&mut ());
        assert_eq!(run.outcome, Outcome::Finished, "m = {m}");
        assert_eq!(run.zeno.len(), 1, "m = {m}");
        assert!(relative(run.zeno[0].t_zeno, tau_inf) < 1e-9, "m = {m}");
        for (k, t) in run.impact_times(0).iter().take(20).enumerate() {
            assert!(
                relative(*t, ball.impact_time(H0, k as u32 + 1)) < 1e-9,
                "m = {m}"
            );
        }
    }
}

/// A ball under `g` run to 3 s with `atol`: its outcome, Zeno points and first impact time.
fn scaled(g: f64, atol: f64) -> (BouncingBall, Execution) {
    let ball = BouncingBall::new(1.0, g, 0.5);
    let options = SimulationOptions {
        t_end: 3.0,
        tolerances: Tolerances { rtol: 1e-10, atol },
        ..Default::default()
    };
    let run = Simulation::new(&ball, &[H0], &[0.0], options)
        .unwrap()
        .run(&mut ());
    (ball, run)
}

#[test]
fn the_step_size_floor_had_a_unit_of_time() {
    // Under g = 1e50 the ball reaches the floor after t1 = 1.4e-25 s, far below 16 ε · 1 s,
    // the smallest step the integrator used to allow at t < 1: the run failed at t = 0 with a
    // "step size underflow" and advice to loosen the tolerances.
    for g in [1e30, 1e50, 1e100] {
        let (ball, run) = scaled(g, 1e-10);
        assert_eq!(run.outcome, Outcome::Finished, "g = {g}");
        assert_eq!(run.zeno.len(), 1, "g = {g}");
        let tau_inf = ball.zeno_time(H0);
        assert!(relative(run.zeno[0].t_zeno, tau_inf) < 1e-9, "g = {g}");
        let first = run.impact_times(0)[0];
        assert!(relative(first, ball.impact_time(H0, 1)) < 1e-9, "g = {g}");
    }
}

#[test]
fn the_first_step_guess_overflowed_with_a_tiny_atol() {
    // The velocity starts at 0, so its tolerance is atol alone: with atol = 1e-300 the first
    // step's guess squared g / atol ≈ 1e301 to ∞ and the run failed at t = 0 with h = 0.
    let (ball, run) = scaled(G, 1e-300);
    assert_eq!(run.outcome, Outcome::Finished);
    assert_eq!(run.zeno.len(), 1);
    assert!(relative(run.zeno[0].t_zeno, ball.zeno_time(H0)) < 1e-9);
}

#[test]
fn the_first_step_guess_was_zero_when_the_weighted_derivative_overflowed() {
    // With atol = 1e-300 the velocity's weight is 1e-300, and g / 1e-300 overflows for
    // g ≥ 1.8e8: the first step's guess 0.01 · ‖y‖ / ‖f‖ was 0.01 · d0 / ∞ = 0, and the run
    // failed at t = 0 with "step size 0 underflowed" and advice to loosen the tolerances.
    for (g, atol) in [(G * 1e10, 1e-300), (1e9, 1e-308)] {
        let (ball, run) = scaled(g, atol);
        assert_eq!(run.outcome, Outcome::Finished, "g = {g:e}");
        assert_eq!(run.zeno.len(), 1, "g = {g:e}");
        assert!(
            relative(run.zeno[0].t_zeno, ball.zeno_time(H0)) < 1e-9,
            "g = {g:e}: τ∞ = {:e} vs {:e}",
            run.zeno[0].t_zeno,
            ball.zeno_time(H0)
        );
    }
    // Regression (a review of the fix): where the ratio is still 0 after rescaling (the first
    // step 1e-350 s or less), a first guess of 1e-6 s gave a run that ended as if well with its
    // first impact 2 m above the floor. No step f64 holds serves: the run stops at t = 0.
    for g in [1e60, 1e140] {
        let (_, run) = scaled(g, 1e-300);
        assert!(
            matches!(run.outcome, Outcome::Failed(_)),
            "g = {g:e}: {:?}",
            run.outcome
        );
        assert_eq!(run.t_final, 0.0, "g = {g:e}");
        assert!(run.events.is_empty(), "g = {g:e}");
    }
}

#[test]
fn a_fast_ball_was_put_to_rest_at_its_first_impact() {
    // The time resolution was 64 ε max(|t|, 1 s): under g = 1e30 the flight after the first
    // impact, 1.4e-15 s, was below it, and the run switched to the Zeno limit there as
    // "chattering after 1 impact", at t1 though τ∞ = 3 t1 (under g = 1e25, 6 impacts and 2%
    // early). Scaled by λ (g → λ² g, every time → time/λ) the ball must bounce as at λ = 1:
    // as many impacts, genuinely Zeno, switched at the same fraction of τ∞. The tolerance is
    // relative (atol = 1e-200, far below every state's rounding): an absolute one on the
    // velocity, which scales by λ, would be a tighter tolerance on the faster ball, and `Auto`
    // switches by it (with atol = 1e-10: 37 impacts at λ = 1, 46 at the others).
    let reference = |g: f64| {
        let (ball, run) = scaled(g, 1e-200);
        assert_eq!(run.outcome, Outcome::Finished, "g = {g}");
        assert_eq!(run.zeno.len(), 1, "g = {g}");
        let z = &run.zeno[0];
        assert_eq!(z.kind, ZenoKind::Genuine, "g = {g}");
        let tau_inf = ball.zeno_time(H0);
        assert!(
            relative(z.t_zeno, tau_inf) < 1e-9,
            "g = {g}: τ∞ = {} vs closed form {tau_inf}",
            z.t_zeno
        );
        let impacts = run.impact_times(0).len();
        assert_eq!(impacts, z.impacts, "g = {g}");
        (impacts, z.t_switch / tau_inf)
    };
    let (impacts, fraction) = reference(G);
    for lambda in [1e5, 1e10, 1e15, 1e25] {
        let g = G * lambda * lambda;
        let (scaled_impacts, scaled_fraction) = reference(g);
        assert_eq!(scaled_impacts, impacts, "λ = {lambda}");
        assert!(
            relative(scaled_fraction, fraction) < 1e-6,
            "λ = {lambda}: switched at {scaled_fraction} τ∞, at λ = 1 at {fraction} τ∞"
        );
    }
}

#[test]
fn a_slow_ball_failed_at_its_zeno_point_with_a_step_of_one_microsecond() {
    // Under g = 9.81e-20 the Zeno point is at τ∞ = 1.35e10 s. Resting there, the first step's
    // guess fell back to Hairer's 1e-6 s, below what f64 resolves at t = 1.35e10 (16 ε t =
    // 4.8e-5 s): the run failed with a "step size underflow" at its Zeno point. Scaled by λ
    // (g → λ² g) the ball must run to its end as at λ = 1, genuinely Zeno at its closed form.
    for lambda in [1e-5, 1e-10] {
        let g = G * lambda * lambda;
        let ball = BouncingBall::new(1.0, g, 0.5);
        let tau_inf = ball.zeno_time(H0);
        let options = SimulationOptions {
            t_end: 2.0 * tau_inf,
            tolerances: Tolerances {
                rtol: 1e-10,
                atol: 1e-200,
            },
            ..Default::default()
        };
        let run = Simulation::new(&ball, &[H0], &[0.0], options)
            .unwrap()
            .run(&mut ());
        assert_eq!(run.outcome, Outcome::Finished, "λ = {lambda}");
        assert_eq!(run.zeno.len(), 1, "λ = {lambda}");
        assert_eq!(run.zeno[0].kind, ZenoKind::Genuine, "λ = {lambda}");
        assert!(
            relative(run.zeno[0].t_zeno, tau_inf) < 1e-9,
            "λ = {lambda}: τ∞ = {} vs closed form {tau_inf}",
            run.zeno[0].t_zeno
        );
    }
}

/// Regression (issue 24): a ball started at rest on the floor was "a Zeno point after 1 impact,
/// ratio null": an impact of zero impulse at t = 0 and a switch there. It is held from t = 0:
/// no event, no Zeno point, one constrained interval, and it stays on the floor.
#[test]
fn a_start_at_rest_on_the_floor_was_a_zeno_point_after_one_impact() {
    let ball = BouncingBall::new(1.0, G, 0.5);
    for zeno in [ZenoStrategy::Auto, ZenoStrategy::Off] {
        let options = SimulationOptions {
            t_end: 2.0,
            zeno,
            ..Default::default()
        };
        let mut trajectory = Trajectory::default();
        let run = Simulation::new(&ball, &[0.0], &[0.0], options)
            .unwrap()
            .run(&mut trajectory);
        assert_eq!(run.outcome, Outcome::Finished, "{zeno:?}");
        assert!(run.zeno.is_empty(), "{zeno:?}: {:?}", run.zeno);
        assert!(run.events.is_empty(), "{zeno:?}: {:?}", run.events);
        assert_eq!(run.stats.impacts, 0);
        assert_eq!(run.intervals.len(), 1);
        let held = Mode::Constrained(zenosim::ActiveSet::single(0));
        assert_eq!((run.intervals[0].start, run.intervals[0].mode), (0.0, held));
        assert_eq!(run.final_mode, held);
        assert!(trajectory.points.iter().all(|p| p.q[0].abs() <= 1e-12));
    }
    // Resting on it but thrown up, or above it: a flight as before.
    let options = SimulationOptions {
        t_end: 0.5,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&ball, &[0.0], &[1.0], options)
        .unwrap()
        .run(&mut trajectory);
    assert_eq!(run.intervals[0].mode, Mode::Free);
    assert!(relative(run.impact_times(0)[0], 2.0 / G) < 1e-9);
}

/// A ball above a floor far from the origin, `h = y − 5e11`.
struct FarFloor {
    constraints: [Constraint; 1],
}

impl HybridLagrangian for FarFloor {
    fn dimension(&self) -> usize {
        1
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], q_dot: &[D]) -> D {
        q_dot[0] * q_dot[0] * 0.5 - q[0] * G
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0] - 5e11
    }
}

/// Regression (review of issue 24): a ball at rest 40 m above a floor at y = 5e11 was "started
/// at rest on 'floor': held from t = 0" and floated there, because a start counted as on the
/// surface within the position tolerance, rtol·|y| = 50 m. It falls: 4.9 m in the first second.
#[test]
fn a_ball_far_from_the_origin_was_held_40_m_above_its_floor() {
    let ball = FarFloor {
        constraints: [Constraint::new("floor", 0.5)],
    };
    let options = SimulationOptions {
        t_end: 1.0,
        ..Default::default()
    };
    let run = Simulation::new(&ball, &[5e11 + 40.0], &[0.0], options)
        .unwrap()
        .run(&mut ());
    assert_eq!(run.outcome, Outcome::Finished);
    assert_eq!(run.intervals[0].mode, Mode::Free);
    let fallen = 5e11 + 40.0 - run.final_state.q[0];
    assert!((fallen - 0.5 * G).abs() < 1e-3, "fell {fallen} m");
    // On the floor exactly, at rest: held from the start.
    let run = Simulation::new(&ball, &[5e11], &[0.0], options)
        .unwrap()
        .run(&mut ());
    assert_eq!(
        run.intervals[0].mode,
        Mode::Constrained(zenosim::ActiveSet::single(0))
    );
}
