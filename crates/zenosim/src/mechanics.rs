//! The mechanics derived from a hybrid Lagrangian: equations of motion (free and constrained),
//! the impact map `P`, and the projection `R∞` onto `h = 0, ḣ = 0` (`ḣ = A q̇ + ∂ₜh`).
//!
//! Conventions (REFERENCE §1, the paper's typo corrected):
//! - free motion `M q̈ = f`, `f = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q` (docs/forces-and-time.md);
//! - constrained motion `M q̈ = f − Aᵀλ`, `λ = (A M⁻¹ Aᵀ)⁻¹ (A M⁻¹ f + Ȧ q̇)`; the contact force is
//!   `−Aᵀλ`, so the constraint pushes while `λ ≤ 0`, and `λ = ḧ_free / (A M⁻¹ Aᵀ)`;
//! - impact `q̇⁺ = q̇ − (1+e) ḣ/(A M⁻¹ Aᵀ) M⁻¹ Aᵀ`, so `ḣ⁺ = −e ḣ⁻`, with the normal velocity
//!   `ḣ = A q̇ + ∂ₜh` (`A q̇` where the surface does not move).

use crate::derivatives::{constraint_terms, mass_matrix, with_dimension};
use crate::execution::ActiveSet;
use crate::model::HybridLagrangian;
use crate::motion::{
    check_pivots, constrained_motion, degenerate, degenerate_scaled, direction, dot, free_motion,
    held_acceleration, pivots, route, squares_trusted, ConstrainedMotion, Direction, PivotError,
    Route,
};

/// A failure of the mechanics at one state; the caller adds the time and the state.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub(crate) enum DynamicsError {
    /// `M` is not positive definite.
    #[error("the mass matrix is not positive definite")]
    MassMatrix,
    /// `A M⁻¹ Aᵀ` vanishes: `∂h/∂q = 0` where the constraint has to act.
    #[error("constraint {constraint} has a vanishing gradient")]
    DegenerateConstraint { constraint: usize },
    /// The right-hand side is not finite.
    #[error("a non-finite value")]
    NonFinite,
    /// The gradients of a set are nearly but not exactly dependent.
    #[error("the constraints {constraints:?} have nearly dependent gradients")]
    NearlyDependent { constraints: ActiveSet },
    /// The contact problem on a set is proven to have no solution.
    #[error("the contact problem on {constraints:?} has no solution")]
    ContactProblem { constraints: ActiveSet },
    /// The solver of the contact problem on a set failed: neither a solution nor a proof that
    /// none exists.
    #[error(
        "the solver of the contact problem on {constraints:?} failed ({stop}; W is {conditioning})"
    )]
    ContactSolver {
        constraints: ActiveSet,
        stop: crate::lcp::Stop,
        conditioning: crate::lcp::Conditioning,
    },
    /// Painlevé's paradox: the frictional contact problem on a set has no solution or several.
    #[error("Painlevé's paradox on {constraints:?}")]
    Painleve { constraints: ActiveSet },
    /// With contacts in space, the cone solver found no answer that meets Coulomb's law.
    #[error("no answer of Coulomb's law with isotropic cones on {constraints:?}")]
    SpatialFriction { constraints: ActiveSet },
    /// Newton's method did not bring `h` to zero.
    #[error("the projection onto constraint {constraint} left |h| = {residual}")]
    Projection { constraint: usize, residual: f64 },
}

/// What the projection `R∞` left behind: the residuals `|h|` and `|A q̇|`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Residuals {
    /// `|h(q)|` after the projection.
    pub h: f64,
    /// `|A(q) q̇|` after the projection.
    pub a_q_dot: f64,
}

impl From<PivotError> for DynamicsError {
    fn from(err: PivotError) -> Self {
        match err {
            PivotError::NonFinite => DynamicsError::NonFinite,
            PivotError::NotPositiveDefinite => DynamicsError::MassMatrix,
        }
    }
}

/// Checks that constraint `index` can act: `M` positive definite (its pivots), and
/// `s = A M⁻¹ Aᵀ` away from 0 against `|A|²` and `|M⁻¹Aᵀ|²`.
/// Where the squares say it cannot but may have over- or underflowed (a model of extreme scale),
/// `precise` decides from the vectors ([`degenerate_scaled`]); it runs only then.
#[inline(always)]
fn check_acting(
    pivots: &[f64],
    s: f64,
    gradient_norm2: f64,
    w_norm2: f64,
    index: usize,
    precise: impl FnOnce() -> bool,
) -> Result<(), DynamicsError> {
    check_pivots(pivots)?;
    if degenerate(s, gradient_norm2, w_norm2)
        && (squares_trusted(s, gradient_norm2, w_norm2) || precise())
    {
        return Err(DynamicsError::DegenerateConstraint { constraint: index });
    }
    Ok(())
}

/// [`check_acting`] for a constraint's direction.
#[inline(always)]
fn check_direction<const N: usize>(d: &Direction<N>, index: usize) -> Result<(), DynamicsError> {
    let (gradient, w) = (d.gradient.as_slice(), d.w.as_slice());
    let (gradient_norm2, w_norm2) = (dot(gradient, gradient), dot(w, w));
    let precise = || degenerate_scaled(d.s, gradient, w);
    check_acting(
        d.pivots.as_slice(),
        d.s,
        gradient_norm2,
        w_norm2,
        index,
        precise,
    )
}

/// [`degenerate_scaled`] of constraint `index` at `(q, q̇)`, from its direction: for the rare
/// state where the held motion's squared norms cannot tell.
#[cold]
fn degenerate_at<const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> bool {
    let d = direction::<N, L>(model, index, t, q, q_dot);
    degenerate_scaled(d.s, d.gradient.as_slice(), d.w.as_slice())
}

/// `q̈ = acc` into `q_ddot`, unless it or the multiplier `λ` is not finite. Inlined, so that
/// the copy has the model's dimension as a constant (no call to `memcpy` per evaluation).
#[inline(always)]
fn write_finite(acc: &[f64], lambda: f64, q_ddot: &mut [f64]) -> Result<(), DynamicsError> {
    if !acc.iter().all(|x| x.is_finite()) || !lambda.is_finite() {
        return Err(DynamicsError::NonFinite);
    }
    q_ddot[..acc.len()].copy_from_slice(acc);
    Ok(())
}

/// The normal response from the motion held on the constraint at `(q, q̇)`.
fn normal_of<const N: usize>(
    motion: &ConstrainedMotion<N>,
    q_dot: &[f64],
) -> Result<Normal, DynamicsError> {
    const ROUND_OFF: f64 = 64.0 * f64::EPSILON;
    let d = &motion.direction;
    let speed = norm(&q_dot[..N]);
    let gradient_norm = norm(d.gradient.as_slice());
    let curvature = norm(motion.hessian_q_dot.as_slice());
    let normal = Normal {
        a_q_dot: d.a_q_dot,
        h_t: d.h_t,
        h_ddot_free: motion.h_ddot_free,
        s: d.s,
        gradient_norm,
        curvature: if speed > 0.0 { curvature / speed } else { 0.0 },
        a_q_dot_round_off: ROUND_OFF * (gradient_norm * speed + d.h_t.abs()),
        h_ddot_round_off: ROUND_OFF
            * (gradient_norm * norm(motion.acc_free.as_slice()) + motion.a_dot_q_dot.abs()),
    };
    if normal.h_ddot_free.is_finite() {
        Ok(normal)
    } else {
        Err(DynamicsError::NonFinite)
    }
}

/// `|x|`, summed as [`dot`] sums (over slices: nalgebra's unrolled `norm` was compiled once per
/// dimension and model).
fn norm(x: &[f64]) -> f64 {
    dot(x, x).sqrt()
}

/// A constraint's normal response, from [`Mechanics::normal`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Normal {
    /// `ḣ = A q̇ + ∂ₜh`: the normal velocity.
    pub a_q_dot: f64,
    /// `∂ₜh`: the surface's own normal velocity (0 where it does not move).
    pub h_t: f64,
    /// `ḧ` under the free motion: `A M⁻¹ f + Ȧ q̇`.
    pub h_ddot_free: f64,
    /// `A M⁻¹ Aᵀ`.
    pub s: f64,
    /// `|A|`.
    pub gradient_norm: f64,
    /// `|∇²h q̇| / |q̇|`: the curvature of `h` along the motion (0 at rest).
    pub curvature: f64,
    /// The rounding error of `A q̇` (from its terms): below it, the normal velocity is 0.
    pub a_q_dot_round_off: f64,
    /// The rounding error of `ḧ_free` (from its terms): below it, the normal force is 0.
    pub h_ddot_round_off: f64,
}

impl Normal {
    /// The multiplier that holds the motion on the constraint: `λ = ḧ_free / (A M⁻¹ Aᵀ)`.
    pub fn lambda(&self) -> f64 {
        self.h_ddot_free / self.s
    }

    /// How far the constraint is from letting go, in units of `λ`: positive when it would have
    /// to pull (`ḧ_free` above its rounding error), `≤ 0` while it holds. A contact without
    /// force (a plastic impact on a wall parallel to gravity, up to rounding) holds.
    pub fn lift_margin(&self) -> f64 {
        (self.h_ddot_free - self.h_ddot_round_off) / self.s
    }
}

/// The size of `h`'s terms at `q`: `|h| + Σ|A_i q_i|`. Rounding the coordinates changes `h`
/// by about `ε` times this; coordinates `h` ignores do not count.
pub(crate) fn guard_scale(h: f64, gradient: &[f64], q: &[f64]) -> f64 {
    h.abs()
        + gradient
            .iter()
            .zip(q)
            .map(|(a, x)| (a * x).abs())
            .sum::<f64>()
}

/// The derived mechanics of one model; cheap to copy, borrows the model.
pub(crate) struct Mechanics<'a, L> {
    model: &'a L,
    n: usize,
    /// The constraints with friction (docs/friction.md).
    frictional: ActiveSet,
    /// The slip speed below which a contact is at rest (the integration's absolute tolerance:
    /// [`Mechanics::with_slip_floor`]); 0 by default.
    slip_floor: f64,
}

impl<L> Clone for Mechanics<'_, L> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<L> Copy for Mechanics<'_, L> {}

impl<'a, L: HybridLagrangian> Mechanics<'a, L> {
    /// Mechanics of `model`, whose dimension has been checked to lie in `1..=MAX_DIMENSION`.
    pub fn new(model: &'a L) -> Self {
        let frictional = model
            .constraints()
            .iter()
            .enumerate()
            .filter(|(i, c)| c.has_friction() && *i < ActiveSet::CAPACITY)
            .fold(ActiveSet::empty(), |set, (i, _)| set.with(i));
        Self {
            model,
            n: model.dimension(),
            frictional,
            slip_floor: 0.0,
        }
    }

    /// These mechanics with slips of at most `floor` taken as rest (a run's absolute
    /// tolerance: a slip that small is 0 to the integration's accuracy, and at rest its terms
    /// are all noise, so that rounding alone cannot tell; docs/friction.md).
    pub fn with_slip_floor(mut self, floor: f64) -> Self {
        self.slip_floor = floor;
        self
    }

    /// The slip speed below which a contact is at rest ([`Mechanics::with_slip_floor`]).
    #[inline]
    pub fn slip_floor(&self) -> f64 {
        self.slip_floor
    }

    /// Whether any constraint of `set` has friction.
    #[inline]
    pub fn frictional(&self, set: ActiveSet) -> bool {
        !set.intersection(self.frictional).is_empty()
    }

    /// The model.
    pub fn model(&self) -> &'a L {
        self.model
    }

    /// `q̈` of the free motion (`active = None`) or of the motion constrained to `h_active = 0`;
    /// returns `λ` of the active constraint (0 when free).
    pub fn acceleration(
        &self,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
        active: Option<usize>,
        q_ddot: &mut [f64],
    ) -> Result<f64, DynamicsError> {
        with_dimension!(L; self.n, N => self.acceleration_n::<N>(t, q, q_dot, active, q_ddot))
    }

    /// The first-order right-hand side at `y = (q, q̇)`: `(q̇, q̈)` into `dy`, `q̈` as
    /// [`Mechanics::acceleration`] gives it; returns `λ` as it does.
    pub fn state_derivative(
        &self,
        t: f64,
        y: &[f64],
        active: Option<usize>,
        dy: &mut [f64],
    ) -> Result<f64, DynamicsError> {
        with_dimension!(L; self.n, N => {
            let (q, q_dot) = y.split_at(N);
            let (velocity, q_ddot) = dy.split_at_mut(N);
            velocity.copy_from_slice(&q_dot[..N]);
            match self.held_compiled::<N>(t, q, q_dot, active, q_ddot) {
                Some(lambda) => lambda,
                None => self.acceleration_n::<N>(t, q, q_dot, active, q_ddot),
            }
        })
    }

    /// [`Mechanics::state_derivative`] on a constraint, straight from the outputs of the
    /// model's compiled program for the acceleration held on it, where the motion is compiled
    /// whole (a constant `M`: [`route`]'s choice, as for [`held_acceleration`]): the same numbers and checks,
    /// without assembling the motion's vectors, once per stage of every step on a constraint.
    /// `None` where there is no such program or it refuses (a witness failed).
    #[inline(always)]
    fn held_compiled<const N: usize>(
        &self,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
        active: Option<usize>,
        q_ddot: &mut [f64],
    ) -> Option<Result<f64, DynamicsError>> {
        let index = active?;
        let Route::Whole(compiled) = route(self.model) else {
            return None;
        };
        // [`check_acting`]'s checks, but no program may run while this one's outputs are read:
        // where the squares say that the constraint does not act (they may have over- or
        // underflowed), the general path decides, as where there is no program. (Deferring
        // there, not mapping an error afterwards, keeps the path of every other state short.)
        compiled
            .held_view::<N, _>(index, t, q, q_dot, |held| {
                if let Err(err) = check_pivots(held.pivots()) {
                    return Some(Err(err.into()));
                }
                let (s, gradient_norm2, w_norm2) = held.acting();
                if degenerate(s, gradient_norm2, w_norm2) {
                    return None;
                }
                Some(write_finite(held.acc(), held.lambda(), q_ddot).map(|()| held.lambda()))
            })
            .flatten()
    }

    fn acceleration_n<const N: usize>(
        &self,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
        active: Option<usize>,
        q_ddot: &mut [f64],
    ) -> Result<f64, DynamicsError> {
        let (acc, lambda) = match active {
            None => {
                let motion = free_motion::<N, L>(self.model, t, q, q_dot);
                check_pivots(motion.pivots.as_slice())?;
                (motion.acc, 0.0)
            }
            Some(index) => {
                let held = held_acceleration::<N, L>(self.model, index, t, q, q_dot);
                check_acting(
                    held.pivots.as_slice(),
                    held.s,
                    held.gradient_norm2,
                    held.w_norm2,
                    index,
                    || degenerate_at::<N, L>(self.model, index, t, q, q_dot),
                )?;
                (held.acc, held.lambda)
            }
        };
        write_finite(acc.as_slice(), lambda, q_ddot)?;
        Ok(lambda)
    }

    /// The constraint's normal response at `(q, q̇)` under the free motion: `A q̇`, `ḧ_free`,
    /// `A M⁻¹ Aᵀ`, and `M⁻¹ Aᵀ` into `w`. The multiplier that would hold the motion on the
    /// constraint is `λ = ḧ_free / (A M⁻¹ Aᵀ)`; a contact can hold only while `λ ≤ 0`.
    pub fn normal(
        &self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
        w: &mut [f64],
    ) -> Result<Normal, DynamicsError> {
        with_dimension!(L; self.n, N => {
            let motion = constrained_motion::<N, L>(self.model, index, t, q, q_dot);
            check_direction(&motion.direction, index)?;
            w[..N].copy_from_slice(motion.direction.w.as_slice());
            normal_of(&motion, q_dot)
        })
    }

    /// `q̈` of the motion held on constraint `index` into `q_ddot`, as
    /// [`Mechanics::acceleration`] gives it (to the bit), and the constraint's normal response
    /// at `(q, q̇)`, as [`Mechanics::normal`] gives it: both from one evaluation of the motion.
    pub fn held_acceleration_and_normal(
        &self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
        q_ddot: &mut [f64],
    ) -> Result<Normal, DynamicsError> {
        with_dimension!(L; self.n, N => {
            let motion = constrained_motion::<N, L>(self.model, index, t, q, q_dot);
            check_direction(&motion.direction, index)?;
            write_finite(motion.acc.as_slice(), motion.lambda, q_ddot)?;
            normal_of(&motion, q_dot)
        })
    }

    /// The impact map `P`: `q̇ ← q̇ − (1+e) ḣ/(A M⁻¹ Aᵀ) M⁻¹ Aᵀ` for constraint `index`.
    pub fn impact(
        &self,
        index: usize,
        e: f64,
        t: f64,
        q: &[f64],
        q_dot: &mut [f64],
    ) -> Result<(), DynamicsError> {
        with_dimension!(L; self.n, N => {
            let d = direction::<N, L>(self.model, index, t, q, q_dot);
            check_direction(&d, index)?;
            let scale = (1.0 + e) * d.a_q_dot / d.s;
            for (v, wi) in q_dot.iter_mut().zip(d.w.as_slice()) {
                *v -= scale * wi;
            }
            Ok(())
        })
    }

    /// The general completion `R∞` for constraint `index`: `q` onto `h = 0` by Newton steps along
    /// `M⁻¹Aᵀ`, then `q̇` by the plastic impact (`e = 0`), which keeps every momentum the constraint
    /// does not touch.
    pub fn project(
        &self,
        index: usize,
        t: f64,
        q: &mut [f64],
        q_dot: &mut [f64],
    ) -> Result<Residuals, DynamicsError> {
        with_dimension!(L; self.n, N => self.project_n::<N>(index, t, q, q_dot))
    }

    fn project_n<const N: usize>(
        &self,
        index: usize,
        t: f64,
        q: &mut [f64],
        q_dot: &mut [f64],
    ) -> Result<Residuals, DynamicsError> {
        const MAX_NEWTON: usize = 30;
        // Scaled by how much the coordinates weigh in h (|h| + Σ|A_i q_i|, in h's units, and
        // divided by |A| in q's): a coordinate h ignores must not loosen the stop.
        let mut c = direction::<N, L>(self.model, index, t, q, q_dot);
        let h_scale = guard_scale(c.h, c.gradient.as_slice(), q).max(1.0);
        let q_scale = (h_scale / norm(c.gradient.as_slice())).max(1.0);
        let mut best = f64::INFINITY;
        for iteration in 0..MAX_NEWTON {
            if iteration > 0 {
                c = direction::<N, L>(self.model, index, t, q, q_dot);
            }
            if !c.h.is_finite() {
                return Err(DynamicsError::NonFinite);
            }
            check_direction(&c, index)?;
            let (w, s) = (c.w, c.s);
            let step = c.h / s;
            // Converged: the Newton step is at round-off, or h has stopped decreasing. Then the
            // velocity: the plastic impact at this position, with this factorisation.
            if c.h == 0.0
                || step.abs() * norm(w.as_slice()) <= 4.0 * f64::EPSILON * q_scale
                || c.h.abs() >= best
            {
                let scale = c.a_q_dot / s;
                for (v, wi) in q_dot.iter_mut().zip(w.as_slice()) {
                    *v -= scale * wi;
                }
                let residuals = Residuals {
                    h: c.h.abs(),
                    a_q_dot: (dot(c.gradient.as_slice(), &q_dot[..N]) + c.h_t).abs(),
                };
                if residuals.h > 1e-12 * h_scale {
                    break;
                }
                return Ok(residuals);
            }
            best = c.h.abs();
            for (x, wi) in q.iter_mut().zip(w.as_slice()) {
                *x -= step * wi;
            }
        }
        let c = constraint_terms::<N, L>(self.model, index, t, q);
        Err(DynamicsError::Projection {
            constraint: index,
            residual: c.h.abs(),
        })
    }

    /// `M(q)` (symmetric, so row- and column-major agree) into `out` (`n²` entries); an error if it is not positive definite.
    pub fn mass_matrix(
        &self,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
        out: &mut [f64],
    ) -> Result<(), DynamicsError> {
        with_dimension!(L; self.n, N => {
            let m = mass_matrix::<N, L>(self.model, t, q, q_dot);
            out[..N * N].copy_from_slice(m.as_slice());
            Ok(check_pivots(pivots(&m).as_slice())?)
        })
    }

    /// `A = ∂h/∂q` of constraint `index` into `out`; returns `h`.
    pub fn constraint_gradient(&self, index: usize, t: f64, q: &[f64], out: &mut [f64]) -> f64 {
        with_dimension!(L; self.n, N => {
            let c = constraint_terms::<N, L>(self.model, index, t, q);
            out[..N].copy_from_slice(c.gradient.as_slice());
            c.h
        })
    }
}
