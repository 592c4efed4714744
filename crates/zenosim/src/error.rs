//! The errors of the engine: bad setups, refused before a run, and numerical failures during one
//! (those end the run with `Outcome::Failed`, keeping what was computed).

use std::fmt;

/// Everything that can go wrong in the engine. Each message says what to do about it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The model has no coordinates or too many.
    #[error("the model has {dimension} coordinates; zenosim handles 1 to {max}: reduce the model or raise MAX_DIMENSION")]
    Dimension {
        /// The model's dimension.
        dimension: usize,
        /// The largest supported.
        max: usize,
    },
    /// The model's [`crate::HybridLagrangian::DIMENSION`] is not its
    /// [`crate::HybridLagrangian::dimension`].
    #[error("the model's type declares DIMENSION = Some({declared}) but dimension() is {dimension}: make them agree, or declare None")]
    DeclaredDimension {
        /// What the type declares.
        declared: usize,
        /// What `dimension()` returns.
        dimension: usize,
    },
    /// The model has no constraint or too many.
    #[error("the model has {count} constraints; zenosim needs 1 to {max}")]
    ConstraintCount {
        /// How many the model has.
        count: usize,
        /// The largest supported.
        max: usize,
    },
    /// An initial vector has the wrong length.
    #[error("{what} has {got} entries but the model has {expected} coordinates: give one value per coordinate")]
    Length {
        /// `"q0"` or `"q_dot0"`.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The model's dimension.
        expected: usize,
    },
    /// A restitution outside `[0, 1]`.
    #[error("constraint '{constraint}' has restitution {value}; it must lie in [0, 1] (0 plastic, 1 elastic)")]
    Restitution {
        /// The constraint's name.
        constraint: String,
        /// The value given.
        value: f64,
    },
    /// Friction coefficients that are not `0 ≤ μₖ ≤ μₛ`, finite.
    #[error("constraint '{constraint}' has friction coefficients static {static_coefficient}, kinetic {kinetic_coefficient}; they must be finite with 0 ≤ kinetic ≤ static (one coefficient gives both)")]
    Friction {
        /// The constraint's name.
        constraint: String,
        /// The static coefficient given.
        static_coefficient: f64,
        /// The kinetic coefficient given.
        kinetic_coefficient: f64,
    },
    /// An option with a value it cannot take.
    #[error("option {option} = {} is invalid: {expected}", Readable(*value))]
    Option {
        /// The option's name.
        option: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// The initial state is not finite.
    #[error("{what}[{index}] is {value}: give finite initial values")]
    NonFiniteInitialState {
        /// `"q0"` or `"q_dot0"`.
        what: &'static str,
        /// The entry.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The initial state violates a constraint.
    #[error("the initial state violates constraint '{constraint}': h = {h:e} < 0; start on the admissible side h >= 0")]
    Inadmissible {
        /// The constraint's name.
        constraint: String,
        /// `h(q0)`.
        h: f64,
    },
    /// A model that declares itself autonomous ([`crate::HybridLagrangian::is_autonomous`])
    /// has a function that depends on `t`, a generalized force or a dissipation function.
    #[error("the model declares itself autonomous (is_autonomous() = true), but its {what}; return false from is_autonomous() so that zenosim accounts for it")]
    NotAutonomous {
        /// What was found, in words.
        what: String,
    },
    /// `M = ∂²L/∂q̇²` is not positive definite.
    #[error("at t = {}: the mass matrix ∂²L/∂q̇² is not positive definite (q = {q:?}, q_dot = {q_dot:?}); every coordinate needs a kinetic term, and coordinate singularities (like sin θ = 0) must be avoided", Readable(*t))]
    SingularMassMatrix {
        /// When.
        t: f64,
        /// Where.
        q: Vec<f64>,
        /// With what velocity.
        q_dot: Vec<f64>,
    },
    /// `∂h/∂q` vanishes where the constraint has to act.
    #[error("at t = {}: constraint '{constraint}' has ∂h/∂q = 0 where it must act (impact or contact force); write h so that its gradient does not vanish on h = 0", Readable(*t))]
    DegenerateConstraint {
        /// When.
        t: f64,
        /// The constraint's name.
        constraint: String,
    },
    /// The state or its derivative became NaN or infinite.
    #[error("at t = {}: the state or its derivative is not finite (NaN or infinity); check the model's functions at the state reached", Readable(*t))]
    NonFinite {
        /// When.
        t: f64,
    },
    /// The step size fell below what floating point resolves.
    #[error("at t = {}: the step size {h:e} underflowed: the tolerances ask for more than f64 resolves (an atol far below the state's size), or the equations are stiff or singular there; loosen the tolerances or check the model", Readable(*t))]
    StepSizeUnderflow {
        /// When.
        t: f64,
        /// The step size reached.
        h: f64,
    },
    /// The gradients of constraints that have to hold together are nearly, but not exactly,
    /// dependent: their contact forces are too ill-determined to compute.
    #[error("at t = {}: constraints {} have to hold together but their gradients ∂h/∂q are nearly dependent (agreeing to about twelve digits or more, but not to rounding), so their contact forces cannot be determined reliably: make them exactly dependent (the same surface, or legs exactly in one plane) or clearly independent", Readable(*t), quoted(constraints))]
    NearlyDependent {
        /// When.
        t: f64,
        /// The constraints of the set.
        constraints: Vec<String>,
    },
    /// The contact problem (the impact law or the contact forces on a set) is proven to have no
    /// solution: no impulses or forces keep the motion admissible. The proof is a secondary ray
    /// of Lemke's method, checked against the data ([`crate::lcp::LcpError::NoSolution`]).
    #[error("at t = {}: the contact problem on constraints {} has no solution: no contact forces keep the motion on the admissible side of all of them at once (their surfaces leave it no way to move from this state; proven to rounding by a secondary ray of Lemke's method); change the geometry or the initial state", Readable(*t), quoted(constraints))]
    ContactProblem {
        /// When.
        t: f64,
        /// The constraints of the set.
        constraints: Vec<String>,
    },
    /// The solver of the contact problem on a set failed: it found neither impulses or forces
    /// that meet the contact law to its accuracy nor a proof that none exist
    /// ([`crate::lcp::LcpError::Failed`]). A limit of the solver, not a fault of the model.
    #[error("at t = {}: the solver of the contact problem on constraints {} failed ({stop}): it found neither contact forces that meet the contact law to the accuracy required nor a proof that there are none; their Delassus matrix W = A M⁻¹ Aᵀ is {conditioning}. This is a failure of zenosim's solver, not a fault of the model; where W is ill-conditioned (constraints nearly dependent), making them exactly dependent or clearly independent avoids it", Readable(*t), quoted(constraints))]
    ContactSolver {
        /// When.
        t: f64,
        /// The constraints of the set.
        constraints: Vec<String>,
        /// How the solver's first method stopped.
        stop: crate::lcp::Stop,
        /// How far from singular `W` is.
        conditioning: crate::lcp::Conditioning,
    },
    /// Painlevé's paradox (docs/friction.md): with friction, the contact problem on these
    /// constraints has no solution, or more than one, in the friction states it is in (a
    /// slipping contact whose normal force would grow as its normal acceleration falls: a rod
    /// sliding on a rough floor with large `μ`).
    #[error("at t = {}: Painlevé's paradox at constraints {}: with Coulomb friction the contact problem has no solution or several (the normal force of a slipping contact would grow as its normal acceleration falls); the rigid model with this friction coefficient cannot say what happens next: lower the friction coefficient, or change the geometry", Readable(*t), quoted(constraints))]
    Painleve {
        /// When.
        t: f64,
        /// The constraints of the contact problem.
        constraints: Vec<String>,
    },
    /// With contacts in space (two slip components, docs/friction.md), zenosim's solver for
    /// Coulomb's law with isotropic cones found no answer: a limit of the solver (Newton's
    /// method, then Gauss–Seidel sweeps), or a problem with none.
    #[error("at t = {}: friction in space at constraints {}: zenosim's solver found no impulses or forces that meet Coulomb's law with the isotropic cones at once (Newton's method on Alart and Curnier's equations did not converge from any start; docs/friction.md). The problem may have no answer (dependent contacts, or friction coefficients far above 1), or the solver failed on it; check the contacts' geometry and coefficients, or write a contact in a plane (one slip formula) where the motion allows", Readable(*t), quoted(constraints))]
    SpatialFriction {
        /// When.
        t: f64,
        /// The constraints of the contact problem.
        constraints: Vec<String>,
    },
    /// The projection onto `h = 0` did not converge.
    #[error("at t = {}: projecting onto constraint '{constraint}' left |h| = {residual:e}; h = 0 may be singular or unreachable here: write h so that ∂h/∂q does not vanish on h = 0, or use the default completion (the general projection)", Readable(*t))]
    Projection {
        /// When.
        t: f64,
        /// The constraint's name.
        constraint: String,
        /// `|h|` left.
        residual: f64,
    },
    /// A limit of the run was reached.
    #[error("{}", limit_message(*t, what, *limit, *recent))]
    Limit {
        /// When.
        t: f64,
        /// `"events"` or `"steps"`.
        what: &'static str,
        /// The limit.
        limit: u64,
        /// For the event limit: how many of the last events came within how many seconds
        /// (`(k, span)`), to tell a long Zeno sequence from an event storm.
        recent: Option<(u64, f64)>,
    },
}

/// A number as messages write it: plain decimals where they read well (magnitudes from `1e-4`
/// to `1e15`), else scientific notation, so `1e-7` is not written `0.0000001`. Shortest
/// round-trip digits either way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Readable(pub f64);

impl fmt::Display for Readable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = self.0;
        if t == 0.0 || !t.is_finite() || (1e-4..1e15).contains(&t.abs()) {
            write!(f, "{t}")
        } else {
            write!(f, "{t:e}")
        }
    }
}

/// [`Error::Limit`]'s message.
fn limit_message(t: f64, what: &str, limit: u64, recent: Option<(u64, f64)>) -> String {
    let mut text = format!(
        "at t = {}: the limit of {limit} {what} was reached",
        Readable(t)
    );
    if let Some((count, span)) = recent {
        text += &format!(", the last {count} of them within {} s", Readable(span));
    }
    text += &format!("; raise max_{what} if the run needs more");
    if recent.is_some() {
        text += ", or, if the events come faster than the motion explains (an event storm), \
                 check the constraints' geometry";
    }
    text
}

/// `'a', 'b' and 'c'`.
fn quoted(names: &[String]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
    match quoted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_read_as_numbers_at_every_scale() {
        let shown = |t: f64| Readable(t).to_string();
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(2.5), "2.5");
        assert_eq!(shown(2.0456107), "2.0456107");
        assert_eq!(shown(1.0000049999924754e-7), "1.0000049999924754e-7");
        assert_eq!(shown(1e20), "1e20");
        let storm = Error::Limit {
            t: 1e-7,
            what: "events",
            limit: 100_000,
            recent: Some((100, 2e-10)),
        };
        assert!(
            storm
                .to_string()
                .starts_with("at t = 1e-7: the limit of 100000 events was reached, the last 100 of them within 2e-10 s; raise max_events"),
            "{storm}"
        );
    }

    #[test]
    fn a_failed_solver_is_not_blamed_on_the_model() {
        let names = vec!["floor".to_string(), "gap0".to_string()];
        let failed = Error::ContactSolver {
            t: 1.5,
            constraints: names.clone(),
            stop: crate::lcp::Stop::Cycle,
            conditioning: crate::lcp::Conditioning::PositiveDefinite { pivot_ratio: 0.5 },
        }
        .to_string();
        assert!(
            failed.starts_with(
                "at t = 1.5: the solver of the contact problem on constraints 'floor' and 'gap0' \
                 failed (the active-set method came back to a set it had left)"
            ),
            "{failed}"
        );
        assert!(
            failed.contains(
                "W = A M⁻¹ Aᵀ is positive definite, its smallest Cholesky pivot 5.0e-1 of its \
                 diagonal entry (conditioned to about 2e0)"
            ),
            "{failed}"
        );
        assert!(failed.contains("not a fault of the model"), "{failed}");
        assert!(!failed.contains("no solution") && !failed.contains("change the geometry"));
        let proven = Error::ContactProblem {
            t: 0.0,
            constraints: names,
        }
        .to_string();
        assert!(proven.contains("has no solution"), "{proven}");
        assert!(proven.contains("proven"), "{proven}");
    }
}
