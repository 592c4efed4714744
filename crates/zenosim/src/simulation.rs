//! Setting up a run: the model, the initial state and the options, checked before anything runs.

use crate::derivatives::checked_dimension;
use crate::derived::Derived;
use crate::error::Error;
use crate::execution::{ActiveSet, Execution};
use crate::mechanics::{guard_scale, Mechanics};
use crate::model::HybridLagrangian;
use crate::observer::Observer;
use crate::options::SimulationOptions;
use crate::run::Runner;

/// A run of the completed hybrid system of a model from one initial state.
///
/// ```
/// # use zenosim::{Simulation, SimulationOptions, models::BouncingBall, Outcome};
/// let ball = BouncingBall::new(1.0, 9.81, 0.5);
/// let options = SimulationOptions { t_end: 3.0, ..Default::default() };
/// let run = Simulation::new(&ball, &[1.0], &[0.0], options).unwrap().run(&mut ());
/// assert_eq!(run.outcome, Outcome::Finished);
/// assert_eq!(run.zeno.len(), 1); // the Zeno point at 3·√(2/9.81) was reached and passed
/// ```
pub struct Simulation<'a, L> {
    pub(crate) model: &'a L,
    pub(crate) q0: Vec<f64>,
    pub(crate) q_dot0: Vec<f64>,
    pub(crate) options: SimulationOptions,
}

impl<'a, L: HybridLagrangian> Simulation<'a, L> {
    /// Checks the model, the initial state `(q0, q̇0)` and the options, naming the first problem.
    pub fn new(
        model: &'a L,
        q0: &[f64],
        q_dot0: &[f64],
        options: SimulationOptions,
    ) -> Result<Self, Error> {
        options.validate()?;
        let n = checked_dimension(model)?;
        let constraints = model.constraints();
        if constraints.is_empty() || constraints.len() > ActiveSet::CAPACITY {
            return Err(Error::ConstraintCount {
                count: constraints.len(),
                max: ActiveSet::CAPACITY,
            });
        }
        for (what, v) in [("q0", q0), ("q_dot0", q_dot0)] {
            if v.len() != n {
                return Err(Error::Length {
                    what,
                    got: v.len(),
                    expected: n,
                });
            }
        }
        for (what, v) in [("q0", q0), ("q_dot0", q_dot0)] {
            if let Some((index, &value)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                return Err(Error::NonFiniteInitialState { what, index, value });
            }
        }
        let derived = Derived::new(model)?;
        for (index, c) in constraints.iter().enumerate() {
            if !(0.0..=1.0).contains(&c.restitution) {
                return Err(Error::Restitution {
                    constraint: c.name.clone(),
                    value: c.restitution,
                });
            }
            if let Some(f) = c.friction {
                let (mu_s, mu_k) = (f.static_coefficient, f.kinetic_coefficient);
                if !(mu_s.is_finite() && mu_k.is_finite() && 0.0 <= mu_k && mu_k <= mu_s) {
                    return Err(Error::Friction {
                        constraint: c.name.clone(),
                        static_coefficient: mu_s,
                        kinetic_coefficient: mu_k,
                    });
                }
            }
            let (h, gradient) = derived.constraint(index, q0);
            if !admissible_start(h, &gradient, q0) {
                return Err(Error::Inadmissible {
                    constraint: c.name.clone(),
                    h,
                });
            }
        }
        if model.is_autonomous() {
            check_autonomous(model, q0, q_dot0)?;
        }
        let mut mass = vec![0.0; n * n];
        if Mechanics::new(model)
            .mass_matrix(0.0, q0, q_dot0, &mut mass)
            .is_err()
        {
            return Err(Error::SingularMassMatrix {
                t: 0.0,
                q: q0.to_vec(),
                q_dot: q_dot0.to_vec(),
            });
        }
        Ok(Self {
            model,
            q0: q0.to_vec(),
            q_dot0: q_dot0.to_vec(),
            options,
        })
    }

    /// The options of this run.
    pub fn options(&self) -> &SimulationOptions {
        &self.options
    }

    /// Runs to the stop time (or to a Zeno stall, or to a failure), streaming the trajectory to
    /// `observer`; the record of the execution is returned whatever the outcome.
    pub fn run(&self, observer: &mut impl Observer) -> Execution {
        Runner::new(self, observer).run()
    }
}

/// The rule for an initial state, the one zenosim and its model files apply: `h(q0)` is on the
/// admissible side, or below it by no more than its rounding, `h ≥ −10⁻¹² (|h| + Σ|A_i q0_i|)`.
/// A start placed on the surface by a formula carries the round-off of `h`'s terms (`h` of a
/// block's corner is −5.6·10⁻¹⁷ for a block put on it with the same trigonometry in another
/// order), and the size of those terms, not a fixed unit, says what is round-off: the rule is
/// the same for a model written in metres or in nanometres (docs/contact-laws.md).
pub fn admissible_start(h: f64, gradient: &[f64], q0: &[f64]) -> bool {
    h >= -START_ROUND_OFF * guard_scale(h, gradient, q0)
}

/// The relative rounding [`admissible_start`] allows `h(q0)` below 0.
const START_ROUND_OFF: f64 = 1e-12;

/// Refuses a model that declares itself autonomous but whose `L` or `h` change with `t` at the
/// initial state, or that has a force or a dissipation there: zenosim would otherwise leave out
/// their terms ([`HybridLagrangian::is_autonomous`]).
fn check_autonomous<L: HybridLagrangian>(
    model: &L,
    q0: &[f64],
    q_dot0: &[f64],
) -> Result<(), Error> {
    let refuse = |what: &str| {
        Err(Error::NotAutonomous {
            what: what.to_string(),
        })
    };
    let times = [0.0, 0.731, -2.25];
    let l0 = model.lagrangian_at(0.0, q0, q_dot0);
    if times
        .iter()
        .any(|&t| model.lagrangian_at(t, q0, q_dot0).to_bits() != l0.to_bits())
    {
        return refuse("Lagrangian changes with t");
    }
    for (index, c) in model.constraints().iter().enumerate() {
        let h0 = model.constraint_at(index, 0.0, q0);
        if times
            .iter()
            .any(|&t| model.constraint_at(index, t, q0).to_bits() != h0.to_bits())
        {
            return refuse(&format!("constraint '{}' changes with t", c.name));
        }
    }
    // At the initial velocity and at another (a dissipation function vanishes at rest).
    let moving: Vec<f64> = q_dot0.iter().map(|v| v + 0.37).collect();
    for v in [q_dot0, &moving] {
        let mut force = vec![0.0; q0.len()];
        model.generalized_force(0.731, q0, v, &mut force);
        if force.iter().any(|&f| f != 0.0) {
            return refuse("generalized force is not zero");
        }
        if model.dissipation(0.731, q0, v) != 0.0 {
            return refuse("dissipation function is not zero");
        }
    }
    Ok(())
}
