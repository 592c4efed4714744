//! The equations of motion of one mode, over any number type: `M`'s Cholesky factor, the free
//! and the constrained acceleration, and a constraint's direction `M⁻¹Aᵀ`.
//!
//! Each is one function from `(q, q̇)` to numbers, with no branch on a value: a model file's
//! compiled derivatives ([`crate::compiled`]) trace it whole into one straight-line program, in
//! which the factorisation of a constant `M` (a point mass in Cartesian coordinates) folds to
//! constants; a Rust model runs it over `f64`. Both give the same numbers. What depends on a
//! value (is `M` positive definite, does the constraint have a direction) is decided by the
//! caller ([`crate::mechanics`]) from the outputs: the pivots of the factorisation and `A M⁻¹ Aᵀ`.

use crate::derivatives::{
    array, constraint_parts_of, lagrangian_terms_of, mass_matrix_of, ConstraintParts,
    LagrangianTerms,
};
use crate::model::{HybridLagrangian, Scalar};
use nalgebra::{SMatrix, SVector};

/// The Cholesky factor `M = L Lᵀ`, computed without branching on a value.
pub(crate) struct Factor<const N: usize, T> {
    /// `L`, lower triangle.
    l: SMatrix<T, N, N>,
    /// The pivots `L_jj²` before their square roots: `M` is positive definite exactly when all
    /// are positive.
    pivots: SVector<T, N>,
}

impl<const N: usize, T: Scalar> Factor<N, T> {
    pub(crate) fn new(m: &SMatrix<T, N, N>) -> Self {
        let mut l = SMatrix::<T, N, N>::zeros();
        let mut pivots = SVector::<T, N>::zeros();
        for j in 0..N {
            let mut d = m[(j, j)];
            for k in 0..j {
                d -= l[(j, k)] * l[(j, k)];
            }
            pivots[j] = d;
            let l_jj = d.sqrt();
            l[(j, j)] = l_jj;
            for i in j + 1..N {
                let mut s = m[(i, j)];
                for k in 0..j {
                    s -= l[(i, k)] * l[(j, k)];
                }
                l[(i, j)] = s / l_jj;
            }
        }
        Self { l, pivots }
    }

    /// `M⁻¹ b`: `L y = b`, then `Lᵀ x = y`.
    fn solve(&self, b: &SVector<T, N>) -> SVector<T, N> {
        let l = &self.l;
        let mut y = *b;
        for i in 0..N {
            let mut s = y[i];
            for k in 0..i {
                s -= l[(i, k)] * y[k];
            }
            y[i] = s / l[(i, i)];
        }
        for i in (0..N).rev() {
            let mut s = y[i];
            for k in i + 1..N {
                s -= l[(k, i)] * y[k];
            }
            y[i] = s / l[(i, i)];
        }
        y
    }
}

/// The numbers of a motion in order, written and read back: the one layout of a compiled
/// program's outputs.
pub(crate) trait Outputs<T>: Sized {
    /// The numbers in order.
    fn write(&self, out: &mut Vec<T>);
    /// The numbers back from the front of `flat`, in the order of [`Outputs::write`].
    #[inline(always)]
    fn read(flat: &[T]) -> Self {
        Self::read_from(&mut Cursor { flat })
    }
    /// [`Outputs::read`] from a cursor, which it moves past its numbers.
    fn read_from(cursor: &mut Cursor<'_, T>) -> Self;
}

/// The numbers not read yet.
pub(crate) struct Cursor<'a, T> {
    flat: &'a [T],
}

impl<T: Scalar> Cursor<'_, T> {
    #[inline(always)]
    fn scalar(&mut self) -> T {
        let (first, rest) = self.flat.split_first().expect("as many outputs as written");
        self.flat = rest;
        *first
    }

    #[inline(always)]
    fn vector<const N: usize>(&mut self) -> SVector<T, N> {
        let (first, rest) = self.flat.split_at(N);
        self.flat = rest;
        SVector::<T, N>::from_column_slice(first)
    }
}

/// The free motion at `(q, q̇)`.
pub(crate) struct FreeMotion<const N: usize, T = f64> {
    /// The pivots of `M`'s factorisation (all positive: `M` is positive definite).
    pub pivots: SVector<T, N>,
    /// `q̈ = M⁻¹ f`.
    pub acc: SVector<T, N>,
}

impl<const N: usize, T: Scalar> Outputs<T> for FreeMotion<N, T> {
    fn write(&self, out: &mut Vec<T>) {
        out.extend(self.pivots.iter().chain(&self.acc).copied());
    }
    #[inline(always)]
    fn read_from(c: &mut Cursor<'_, T>) -> Self {
        let pivots = c.vector();
        let acc = c.vector();
        Self { pivots, acc }
    }
}

/// A constraint at `q` and the direction it acts in: what the impact map and the projection
/// need.
pub(crate) struct Direction<const N: usize, T = f64> {
    /// The pivots of `M`'s factorisation.
    pub pivots: SVector<T, N>,
    /// `h(q)`.
    pub h: T,
    /// `A = ∂h/∂q`.
    pub gradient: SVector<T, N>,
    /// `ḣ = A q̇ + ∂ₜh`: the normal velocity.
    pub a_q_dot: T,
    /// `∂ₜh`: the surface's own velocity along its normal (0 where it does not move).
    pub h_t: T,
    /// `w = M⁻¹ Aᵀ`.
    pub w: SVector<T, N>,
    /// `s = A M⁻¹ Aᵀ`.
    pub s: T,
}

impl<const N: usize, T: Scalar> Outputs<T> for Direction<N, T> {
    fn write(&self, out: &mut Vec<T>) {
        out.extend(self.pivots.iter().copied());
        out.push(self.h);
        out.extend(self.gradient.iter().copied());
        out.push(self.a_q_dot);
        out.push(self.h_t);
        out.extend(self.w.iter().copied());
        out.push(self.s);
    }
    #[inline(always)]
    fn read_from(c: &mut Cursor<'_, T>) -> Self {
        Self {
            pivots: c.vector(),
            h: c.scalar(),
            gradient: c.vector(),
            a_q_dot: c.scalar(),
            h_t: c.scalar(),
            w: c.vector(),
            s: c.scalar(),
        }
    }
}

/// The motion held on one constraint at `(q, q̇)`, with the constraint's normal response.
pub(crate) struct ConstrainedMotion<const N: usize, T = f64> {
    /// The constraint, its direction, and `M`'s pivots.
    pub direction: Direction<N, T>,
    /// `∇²h q̇ + ∂ₜAᵀ`.
    pub hessian_q_dot: SVector<T, N>,
    /// The part of `ḧ` that `q̈` does not give: `Ȧ q̇ = q̇ᵀ ∇²h q̇`, and `+ 2 ∂ₜA q̇ + ∂ₜ²h`
    /// where the surface moves.
    pub a_dot_q_dot: T,
    /// The free acceleration `M⁻¹ f`.
    pub acc_free: SVector<T, N>,
    /// `ḧ` under the free motion: `A M⁻¹ f + Ȧ q̇` (with the surface's motion).
    pub h_ddot_free: T,
    /// `λ = ḧ_free / (A M⁻¹ Aᵀ)`.
    pub lambda: T,
    /// `q̈ = M⁻¹ f − M⁻¹Aᵀ λ`: `ḧ = 0`.
    pub acc: SVector<T, N>,
}

impl<const N: usize, T: Scalar> Outputs<T> for ConstrainedMotion<N, T> {
    fn write(&self, out: &mut Vec<T>) {
        self.direction.write(out);
        out.extend(self.hessian_q_dot.iter().copied());
        out.push(self.a_dot_q_dot);
        out.extend(self.acc_free.iter().copied());
        out.push(self.h_ddot_free);
        out.push(self.lambda);
        out.extend(self.acc.iter().copied());
    }
    #[inline(always)]
    fn read_from(c: &mut Cursor<'_, T>) -> Self {
        Self {
            direction: Direction::read_from(c),
            hessian_q_dot: c.vector(),
            a_dot_q_dot: c.scalar(),
            acc_free: c.vector(),
            h_ddot_free: c.scalar(),
            lambda: c.scalar(),
            acc: c.vector(),
        }
    }
}

/// What the right-hand side needs of the motion held on a constraint: the acceleration, the
/// multiplier, and what tells whether they can be trusted.
pub(crate) struct HeldAcceleration<const N: usize, T = f64> {
    /// `q̈`.
    pub acc: SVector<T, N>,
    /// `λ`.
    pub lambda: T,
    /// The pivots of `M`'s factorisation.
    pub pivots: SVector<T, N>,
    /// `s = A M⁻¹ Aᵀ`.
    pub s: T,
    /// `|A|²`.
    pub gradient_norm2: T,
    /// `|M⁻¹ Aᵀ|²`.
    pub w_norm2: T,
}

impl<const N: usize, T: Scalar> Outputs<T> for HeldAcceleration<N, T> {
    fn write(&self, out: &mut Vec<T>) {
        out.extend(self.acc.iter().copied());
        out.push(self.lambda);
        out.extend(self.pivots.iter().copied());
        out.extend([self.s, self.gradient_norm2, self.w_norm2]);
    }
    #[inline(always)]
    fn read_from(c: &mut Cursor<'_, T>) -> Self {
        Self {
            acc: c.vector(),
            lambda: c.scalar(),
            pivots: c.vector(),
            s: c.scalar(),
            gradient_norm2: c.scalar(),
            w_norm2: c.scalar(),
        }
    }
}

/// A [`HeldAcceleration`] read in place from the numbers its program leaves, in the order of
/// its [`Outputs::write`]: for a right-hand side, which needs no vectors of it.
pub(crate) struct HeldView<'a, const N: usize> {
    flat: &'a [f64],
}

impl<'a, const N: usize> HeldView<'a, N> {
    /// The view of `flat`, the outputs of a program for [`HeldAcceleration<N>`].
    #[inline(always)]
    pub fn new(flat: &'a [f64]) -> Self {
        assert!(flat.len() >= 2 * N + 4, "as many outputs as written");
        Self { flat }
    }
    /// `q̈`.
    #[inline(always)]
    pub fn acc(&self) -> &'a [f64] {
        &self.flat[..N]
    }
    /// `λ`.
    #[inline(always)]
    pub fn lambda(&self) -> f64 {
        self.flat[N]
    }
    /// The pivots of `M`'s factorisation.
    #[inline(always)]
    pub fn pivots(&self) -> &'a [f64] {
        &self.flat[N + 1..2 * N + 1]
    }
    /// `(s, |A|², |M⁻¹ Aᵀ|²)`.
    #[inline(always)]
    pub fn acting(&self) -> (f64, f64, f64) {
        let k = 2 * N + 1;
        (self.flat[k], self.flat[k + 1], self.flat[k + 2])
    }
}

/// `a · b` in index order from zero (the same sum over every number type), over slices: one
/// function for every dimension.
pub(crate) fn dot<T: Scalar>(a: &[T], b: &[T]) -> T {
    let mut sum = T::zero();
    for (&x, &y) in a.iter().zip(b) {
        sum += x * y;
    }
    sum
}

/// The free motion, over any number type.
pub(crate) fn free_motion_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> FreeMotion<N, T> {
    free_from(&lagrangian_terms_of::<T, N, L>(model, t, q, q_dot))
}

/// The free motion from `M` and the force.
pub(crate) fn free_from<T: Scalar, const N: usize>(
    terms: &LagrangianTerms<N, T>,
) -> FreeMotion<N, T> {
    let factor = Factor::new(&terms.mass);
    FreeMotion {
        acc: factor.solve(&terms.force),
        pivots: factor.pivots,
    }
}

/// A constraint's direction under `factor`, with `∇²h q̇`.
pub(crate) fn direction_from<T: Scalar, const N: usize>(
    parts: &ConstraintParts<N, T>,
    factor: &Factor<N, T>,
) -> (Direction<N, T>, SVector<T, N>) {
    let w = factor.solve(&parts.gradient);
    let direction = Direction {
        pivots: factor.pivots,
        h: parts.h,
        s: dot(parts.gradient.as_slice(), w.as_slice()),
        gradient: parts.gradient,
        a_q_dot: parts.a_q_dot,
        h_t: parts.h_t,
        w,
    };
    (direction, parts.hessian_q_dot)
}

/// Constraint `index`'s direction, over any number type (`M` only, no forces).
pub(crate) fn direction_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> Direction<N, T> {
    let factor = Factor::new(&mass_matrix_of::<T, N, L>(model, t, q, q_dot));
    let parts = constraint_parts_of::<T, N, L>(model, index, t, q, q_dot);
    direction_from(&parts, &factor).0
}

/// The motion held on constraint `index`, over any number type.
pub(crate) fn constrained_motion_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> ConstrainedMotion<N, T> {
    let terms = lagrangian_terms_of::<T, N, L>(model, t, q, q_dot);
    let parts = constraint_parts_of::<T, N, L>(model, index, t, q, q_dot);
    constrained_from(&terms, &parts, q_dot)
}

/// The motion held on a constraint from `M`, the force and the constraint's derivatives.
pub(crate) fn constrained_from<T: Scalar, const N: usize>(
    terms: &LagrangianTerms<N, T>,
    parts: &ConstraintParts<N, T>,
    q_dot: &[T],
) -> ConstrainedMotion<N, T> {
    let factor = Factor::new(&terms.mass);
    let acc_free = factor.solve(&terms.force);
    let (direction, hessian_q_dot) = direction_from(parts, &factor);
    let a_dot_q_dot = dot(hessian_q_dot.as_slice(), &q_dot[..N]) + parts.time_drift;
    let h_ddot_free = dot(direction.gradient.as_slice(), acc_free.as_slice()) + a_dot_q_dot;
    let lambda = h_ddot_free / direction.s;
    let acc = SVector::from(array(T::zero(), |i| acc_free[i] - direction.w[i] * lambda));
    ConstrainedMotion {
        direction,
        hessian_q_dot,
        a_dot_q_dot,
        acc_free,
        h_ddot_free,
        lambda,
        acc,
    }
}

/// The acceleration held on constraint `index`, over any number type (the part of
/// [`constrained_motion_of`] a right-hand side needs).
pub(crate) fn held_acceleration_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> HeldAcceleration<N, T> {
    held_from(&constrained_motion_of::<T, N, L>(model, index, t, q, q_dot))
}

/// What a right-hand side needs of the motion held on a constraint.
pub(crate) fn held_from<T: Scalar, const N: usize>(
    motion: &ConstrainedMotion<N, T>,
) -> HeldAcceleration<N, T> {
    let d = &motion.direction;
    HeldAcceleration {
        acc: motion.acc,
        lambda: motion.lambda,
        pivots: d.pivots,
        s: d.s,
        gradient_norm2: dot(d.gradient.as_slice(), d.gradient.as_slice()),
        w_norm2: dot(d.w.as_slice(), d.w.as_slice()),
    }
}

/// How a model file's compiled derivatives give the motion: whole, from one traced program
/// each (where `M` is constant, its factorisation folds away), or in parts, from the traced
/// `M`, force and constraint derivatives with the factorisation and solves done here (where
/// `M` varies, they cost less here than interpreted). Both give the numbers of the
/// differentiation, bit for bit.
pub(crate) enum Route<'c> {
    Whole(&'c crate::Compiled),
    Parts(&'c crate::Compiled),
    None,
}

pub(crate) fn route<L: HybridLagrangian>(model: &L) -> Route<'_> {
    match model.compiled() {
        Some(c) if c.whole_motion() => Route::Whole(c),
        Some(c) => Route::Parts(c),
        None => Route::None,
    }
}

/// The free motion: compiled if the model has it, else computed over `f64`.
pub(crate) fn free_motion<const N: usize, L: HybridLagrangian>(
    model: &L,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> FreeMotion<N> {
    let motion = match route(model) {
        Route::Whole(c) => c.free_motion::<N>(t, q, q_dot),
        Route::Parts(c) => c
            .lagrangian_terms::<N>(t, q, q_dot)
            .map(|terms| free_from(&terms)),
        Route::None => None,
    };
    motion.unwrap_or_else(|| free_motion_of::<f64, N, L>(model, t, q, q_dot))
}

/// `M`, the force and constraint `index`'s derivatives from the compiled parts.
fn parts<const N: usize>(
    c: &crate::Compiled,
    index: usize,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> Option<(LagrangianTerms<N>, ConstraintParts<N, f64>)> {
    Some((
        c.lagrangian_terms::<N>(t, q, q_dot)?,
        c.constraint_parts::<N>(index, t, q, q_dot)?,
    ))
}

/// The motion held on constraint `index`: compiled, or computed over `f64`.
pub(crate) fn constrained_motion<const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> ConstrainedMotion<N> {
    let motion = match route(model) {
        Route::Whole(c) => c.constrained_motion::<N>(index, t, q, q_dot),
        Route::Parts(c) => {
            parts::<N>(c, index, t, q, q_dot).map(|(terms, p)| constrained_from(&terms, &p, q_dot))
        }
        Route::None => None,
    };
    motion.unwrap_or_else(|| constrained_motion_of::<f64, N, L>(model, index, t, q, q_dot))
}

/// The acceleration held on constraint `index`: compiled, or computed over `f64`.
pub(crate) fn held_acceleration<const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> HeldAcceleration<N> {
    let held = match route(model) {
        Route::Whole(c) => c.held_acceleration::<N>(index, t, q, q_dot),
        Route::Parts(c) => parts::<N>(c, index, t, q, q_dot)
            .map(|(terms, p)| held_from(&constrained_from(&terms, &p, q_dot))),
        Route::None => None,
    };
    held.unwrap_or_else(|| held_acceleration_of::<f64, N, L>(model, index, t, q, q_dot))
}

/// Constraint `index`'s direction: compiled, or computed over `f64`.
pub(crate) fn direction<const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> Direction<N> {
    let direction = match route(model) {
        Route::Whole(c) => c.direction::<N>(index, t, q, q_dot),
        Route::Parts(c) => parts::<N>(c, index, t, q, q_dot)
            .map(|(terms, p)| direction_from(&p, &Factor::new(&terms.mass)).0),
        Route::None => None,
    };
    direction.unwrap_or_else(|| direction_of::<f64, N, L>(model, index, t, q, q_dot))
}

/// Whether a constraint has no direction to act in: `s = A M⁻¹ Aᵀ` is not positive, or
/// negligible against `|A| |M⁻¹Aᵀ|` (`s = |A|²/μ` with `μ` an eigenvalue of `M`, so the
/// comparison is free of scale), or `A = 0`. From the squares of the norms, which a model of
/// extreme scale over- or underflows (a mass of 1e-156 makes `|M⁻¹Aᵀ|² = ∞`): a verdict of
/// "degenerate" stands only where [`squares_trusted`], and [`degenerate_scaled`] decides
/// otherwise. (A verdict of "acting" is sound: `s²` above the bound is no artefact.)
pub(crate) fn degenerate(s: f64, gradient_norm2: f64, w_norm2: f64) -> bool {
    s.is_nan() || s <= 0.0 || s * s <= 1e-28 * gradient_norm2 * w_norm2 || gradient_norm2 == 0.0
}

/// Whether [`degenerate`]'s verdict is exact: `s` not positive, or the squares and the bound
/// normal numbers (neither overflowed nor underflowed).
#[cold]
pub(crate) fn squares_trusted(s: f64, gradient_norm2: f64, w_norm2: f64) -> bool {
    s.is_nan()
        || s <= 0.0
        || [
            s * s,
            1e-28 * gradient_norm2 * w_norm2,
            gradient_norm2,
            w_norm2,
        ]
        .iter()
        .all(|x| x.is_normal())
}

/// [`degenerate`] from `s` and the vectors `A` and `M⁻¹Aᵀ`, with norms that neither overflow nor
/// underflow for finite vectors: for any scale of the model.
pub(crate) fn degenerate_scaled(s: f64, gradient: &[f64], w: &[f64]) -> bool {
    let (a, w) = (scaled_norm(gradient), scaled_norm(w));
    let cosine = s / a / w;
    s.is_nan() || s <= 0.0 || a == 0.0 || cosine.is_nan() || cosine <= 1e-14
}

/// `|x|`, scaled by its largest entry so that the squares neither overflow nor underflow.
pub(crate) fn scaled_norm(x: &[f64]) -> f64 {
    let largest = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest * x.iter().map(|v| (v / largest).powi(2)).sum::<f64>().sqrt()
}

/// The pivots of `m`'s Cholesky factorisation (see [`check_pivots`]).
pub(crate) fn pivots<const N: usize>(m: &SMatrix<f64, N, N>) -> SVector<f64, N> {
    Factor::new(m).pivots
}

/// Whether `M` is positive definite, from its pivots: `Err` names why not, from the first pivot
/// that is not a positive number (a negative pivot makes every later one NaN).
#[inline(always)]
pub(crate) fn check_pivots(pivots: &[f64]) -> Result<(), PivotError> {
    if pivots.iter().all(|&p| p > 0.0 && p < f64::INFINITY) {
        return Ok(());
    }
    match pivots.iter().find(|&&p| !(p > 0.0 && p.is_finite())) {
        None => Ok(()),
        Some(p) if p.is_finite() => Err(PivotError::NotPositiveDefinite),
        Some(_) => Err(PivotError::NonFinite),
    }
}

/// Why a factorisation failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PivotError {
    /// `M` has a non-finite entry (or one that overflows).
    NonFinite,
    /// `M` is not positive definite.
    NotPositiveDefinite,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_view_reads_what_a_held_acceleration_wrote() {
        let held = HeldAcceleration::<3> {
            acc: SVector::from([1.0, 2.0, 3.0]),
            lambda: 4.0,
            pivots: SVector::from([5.0, 6.0, 7.0]),
            s: 8.0,
            gradient_norm2: 9.0,
            w_norm2: 10.0,
        };
        let mut flat = Vec::new();
        held.write(&mut flat);
        let view = HeldView::<3>::new(&flat);
        assert_eq!(view.acc(), held.acc.as_slice());
        assert_eq!(view.lambda(), held.lambda);
        assert_eq!(view.pivots(), held.pivots.as_slice());
        assert_eq!(view.acting(), (held.s, held.gradient_norm2, held.w_norm2));
    }

    #[test]
    fn the_factor_solves_a_symmetric_positive_definite_system() {
        let m = SMatrix::<f64, 3, 3>::new(4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0);
        let factor = Factor::new(&m);
        assert!(factor.pivots.iter().all(|&p| p > 0.0));
        let b = SVector::<f64, 3>::new(1.0, -2.0, 0.5);
        let x = factor.solve(&b);
        let residual = (m * x - b).norm();
        assert!(residual < 1e-14, "residual {residual:e}");
        let l = factor.l;
        assert!((l * l.transpose() - m).norm() < 1e-14);
    }

    #[test]
    fn the_acting_test_defers_where_the_squares_overflow_and_decides_from_the_vectors() {
        // A ball of mass 1e-156: A = 1, w = M⁻¹Aᵀ = 1e156, s = 1e156; |w|² overflows.
        assert!(degenerate(1e156, 1.0, f64::INFINITY));
        assert!(!squares_trusted(1e156, 1.0, f64::INFINITY));
        assert!(!degenerate_scaled(1e156, &[1.0], &[1e156]));
        // Of mass 1e201: s = 1e-201, and s², |w|² underflow to 0.
        assert!(degenerate(1e-201, 1.0, 0.0));
        assert!(!squares_trusted(1e-201, 1.0, 0.0));
        assert!(!degenerate_scaled(1e-201, &[1.0], &[1e-201]));
        // Ordinary scales are decided by the squares, and a vanishing or orthogonal gradient
        // is degenerate at any scale.
        assert!(!degenerate(2.0, 4.0, 1.0));
        assert!(degenerate(1e-20, 1.0, 1.0) && squares_trusted(1e-20, 1.0, 1.0));
        assert!(degenerate_scaled(0.0, &[0.0, 0.0], &[0.0, 0.0]));
        assert!(degenerate_scaled(1e-300, &[1e150, 0.0], &[0.0, 1e150]));
        // Pythagoras, to rounding, where the squares would overflow and underflow.
        assert!((scaled_norm(&[3e200, 4e200]) / 5e200 - 1.0).abs() < 4.0 * f64::EPSILON);
        assert!((scaled_norm(&[3e-200, 4e-200]) / 5e-200 - 1.0).abs() < 4.0 * f64::EPSILON);
    }

    #[test]
    fn an_indefinite_matrix_has_a_pivot_that_is_not_positive() {
        let m = SMatrix::<f64, 2, 2>::new(1.0, 2.0, 2.0, 1.0);
        let pivots = Factor::new(&m).pivots;
        assert_eq!(pivots[0], 1.0);
        assert_eq!(pivots[1], -3.0);
    }
}
