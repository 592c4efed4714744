//! The target: the cost of reaching and passing a Zeno point grows with
//! `log(1/tolerance)`, not with `1/tolerance`. Counted, never timed, so the test is
//! deterministic; `cargo test -p zenosim --test engine zeno_cost -- --nocapture` prints the table.
//!
//! Why it holds: after impact `k` the time left to `τ∞` is about `Δ₁ eᵏ/(1 − e)`, and
//! `ZenoStrategy::Auto` switches once that time times the integrator's rate `|q̈|/atol` is
//! below 1 (the execution can no longer move by the tolerance), so after
//! `k ≈ log(tol)/log(e) + const` impacts. Each flight costs a bounded number of steps (the step
//! after an impact is bounded by the predicted flight), so the work grows like the impacts.
//! Switching on the paper's `ε` rule with `ε` = the tolerance gives the same count; a
//! simulator that integrated each flight to a fixed step instead would pay `1/tol`.
//!
//! Two models:
//! - the bouncing ball (`e = 0.5`, from 1 m), whose flights are parabolas, stepped in closed
//!   form: all of its cost is the impacts';
//! - the authors' cart pendulum (`e = 0.9`, to its Zeno point at `t ≈ 30.5`), where the
//!   integration of 30 s of smooth arcs costs more at tighter tolerance, as DOP853 does
//!   anywhere (about `tol^(−1/8)`: a factor `10^(6/8) ≈ 5.6` between the increments six decades
//!   apart compared below, where `1/tol` would give `10⁶`). Its impacts stop growing from
//!   `tol ≈ 1e-5`: its guard `h = cos θ` is rounded to about `ε·π/2`, and the switch comes once
//!   the next bounce is within 1e4 ulps of that rounding, whatever the tolerance (the heights
//!   shrink by `e²` per impact, so that cap is itself `log(ε)/log(e²)` + const impacts).

use zenosim::models::{BouncingBall, CartPendulum};
use zenosim::{HybridLagrangian, Outcome, Simulation, SimulationOptions, Tolerances};

const TOLERANCES: [f64; 9] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12];

/// The work of one run to just past the Zeno point, at `rtol = atol = tol`.
#[derive(Clone, Copy, Debug)]
struct Cost {
    tol: f64,
    /// Impacts of the Zeno sequence, before the switch.
    impacts: usize,
    steps: u64,
    rhs: u64,
}

/// The cost of running `model` from `(q0, q̇0)` to `t_end` at each of [`TOLERANCES`]; every run
/// must finish through exactly one Zeno point.
fn costs<L: HybridLagrangian>(model: &L, q0: &[f64], q_dot0: &[f64], t_end: f64) -> Vec<Cost> {
    TOLERANCES
        .iter()
        .map(|&tol| {
            let options = SimulationOptions {
                t_end,
                tolerances: Tolerances {
                    rtol: tol,
                    atol: tol,
                },
                ..Default::default()
            };
            let run = Simulation::new(model, q0, q_dot0, options)
                .unwrap()
                .run(&mut ());
            assert_eq!(run.outcome, Outcome::Finished, "tol = {tol:e}");
            assert_eq!(run.zeno.len(), 1, "tol = {tol:e}");
            Cost {
                tol,
                impacts: run.zeno[0].impacts,
                steps: run.stats.steps + run.stats.rejected_steps,
                rhs: run.stats.rhs_evals,
            }
        })
        .collect()
}

/// `impacts − log(tol)/log(e)`: constant if the impacts follow the log law.
fn offset(cost: &Cost, e: f64) -> f64 {
    cost.impacts as f64 - cost.tol.ln() / e.ln()
}

fn print_table(name: &str, e: f64, costs: &[Cost]) {
    eprintln!("{name}: tol, impacts before the switch, log(tol)/log(e), steps, rhs evaluations");
    for c in costs {
        eprintln!(
            "  {:>7.0e} {:>4} {:>7.1} {:>5} {:>6}",
            c.tol,
            c.impacts,
            c.tol.ln() / e.ln(),
            c.steps,
            c.rhs
        );
    }
}

fn rhs_at(costs: &[Cost], tol: f64) -> u64 {
    costs.iter().find(|c| c.tol == tol).unwrap().rhs
}

/// The growth of the work with the tolerance: `(increase from 1e-10 to 1e-12) / (increase from
/// 1e-4 to 1e-6)` (1 for a log law, `10⁶` for `1/tol`), and `rhs(1e-12)/rhs(1e-4)` (`10⁸` for
/// `1/tol`).
fn growth(costs: &[Cost]) -> (f64, f64) {
    let loose = rhs_at(costs, 1e-6) - rhs_at(costs, 1e-4);
    let tight = rhs_at(costs, 1e-12) - rhs_at(costs, 1e-10);
    (
        tight as f64 / loose as f64,
        rhs_at(costs, 1e-12) as f64 / rhs_at(costs, 1e-4) as f64,
    )
}

#[test]
fn the_bouncing_balls_zeno_cost_grows_with_log_one_over_tolerance() {
    let (e, h0) = (0.5, 1.0);
    let ball = BouncingBall::new(1.0, 9.81, e);
    let costs = costs(&ball, &[h0], &[0.0], ball.zeno_time(h0) + 0.01);
    print_table("bouncing ball, e = 0.5", e, &costs);
    // The impacts follow log(tol)/log(e) + const, to within a bounce or two.
    let offsets: Vec<f64> = costs.iter().map(|c| offset(c, e)).collect();
    let spread = offsets.iter().fold(f64::MIN, |a, &b| a.max(b))
        - offsets.iter().fold(f64::MAX, |a, &b| a.min(b));
    assert!(spread <= 2.0, "offsets from the log law: {offsets:?}");
    // The work per decade of tolerance stays the same.
    let (per_decade, total) = growth(&costs);
    eprintln!("  increase 1e-10→1e-12 / increase 1e-4→1e-6 = {per_decade:.2}, rhs(1e-12)/rhs(1e-4) = {total:.2}");
    assert!(per_decade <= 2.0, "{per_decade}");
    assert!(total <= 3.0, "{total}");
    for pair in costs.windows(2) {
        assert!(pair[1].impacts > pair[0].impacts && pair[1].rhs > pair[0].rhs);
    }
}

#[test]
fn the_cart_pendulums_zeno_cost_grows_with_log_one_over_tolerance() {
    let cart = CartPendulum::demo();
    let e = 0.9;
    // Just past its Zeno point (τ∞ from a run at the default tolerance).
    let options = SimulationOptions {
        t_end: cart.t_end,
        ..Default::default()
    };
    let reference = Simulation::new(&cart.model, &cart.q0, &cart.q_dot0, options)
        .unwrap()
        .run(&mut ());
    let t_end = reference.zeno[0].t_zeno + 0.01;
    let costs = costs(&cart.model, &cart.q0, &cart.q_dot0, t_end);
    print_table("cart pendulum, e = 0.9", e, &costs);
    // Never more impacts than the log law from the loosest tolerance (fewer once the guard's
    // rounding caps them), and never fewer at a tighter tolerance.
    let first = offset(&costs[0], e);
    for pair in costs.windows(2) {
        assert!(pair[1].impacts >= pair[0].impacts, "{costs:?}");
    }
    for c in &costs {
        assert!(
            offset(c, e) <= first + 2.0,
            "{c:?}: {} above the log law",
            offset(c, e) - first
        );
    }
    // The work per decade grows no faster than DOP853's on the smooth arcs (≈ 5.6 over these six
    // decades), nowhere near 1/tol.
    let (per_decade, total) = growth(&costs);
    eprintln!("  increase 1e-10→1e-12 / increase 1e-4→1e-6 = {per_decade:.2}, rhs(1e-12)/rhs(1e-4) = {total:.2}");
    assert!(per_decade <= 6.0, "{per_decade}");
    assert!(total <= 3.0, "{total}");
}
