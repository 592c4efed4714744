//! The errors of the engine: bad setups, refused before a run, and numerical failures during one
//! (those end the run with `Outcome::Failed`, keeping what was computed).

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
    /// An option with a value it cannot take.
    #[error("option {option} = {value} is invalid: {expected}")]
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
    /// `M = ∂²L/∂q̇²` is not positive definite.
    #[error("at t = {t}: the mass matrix ∂²L/∂q̇² is not positive definite (q = {q:?}, q_dot = {q_dot:?}); every coordinate needs a kinetic term, and coordinate singularities (like sin θ = 0) must be avoided")]
    SingularMassMatrix {
        /// When.
        t: f64,
        /// Where.
        q: Vec<f64>,
        /// With what velocity.
        q_dot: Vec<f64>,
    },
    /// `∂h/∂q` vanishes where the constraint has to act.
    #[error("at t = {t}: constraint '{constraint}' has ∂h/∂q = 0 where it must act (impact or contact force); write h so that its gradient does not vanish on h = 0")]
    DegenerateConstraint {
        /// When.
        t: f64,
        /// The constraint's name.
        constraint: String,
    },
    /// The state or its derivative became NaN or infinite.
    #[error("at t = {t}: the state or its derivative is not finite (NaN or infinity); check the model's functions at the state reached")]
    NonFinite {
        /// When.
        t: f64,
    },
    /// The step size fell below what floating point resolves.
    #[error("at t = {t}: the step size {h:e} underflowed: the tolerances ask for more than f64 resolves (an atol far below the state's size), or the equations are stiff or singular there; loosen the tolerances or check the model")]
    StepSizeUnderflow {
        /// When.
        t: f64,
        /// The step size reached.
        h: f64,
    },
    /// Two contacts at once.
    #[error("at t = {t}: constraints '{first}' and '{second}' are in contact at the same time; simultaneous contacts are not supported yet: change the initial state or the geometry so that the contacts come one at a time")]
    SimultaneousContact {
        /// When.
        t: f64,
        /// One constraint.
        first: String,
        /// The other.
        second: String,
    },
    /// The projection onto `h = 0` did not converge.
    #[error("at t = {t}: projecting onto constraint '{constraint}' left |h| = {residual:e}; h = 0 may be singular or unreachable here: write h so that ∂h/∂q does not vanish on h = 0, or use the default completion (the general projection)")]
    Projection {
        /// When.
        t: f64,
        /// The constraint's name.
        constraint: String,
        /// `|h|` left.
        residual: f64,
    },
    /// A limit of the run was reached.
    #[error("at t = {t}: the limit of {limit} {what} was reached; raise it (SimulationOptions::max_{what}) if the run needs more")]
    Limit {
        /// When.
        t: f64,
        /// `"events"` or `"steps"`.
        what: &'static str,
        /// The limit.
        limit: u64,
    },
}
