//! Exact derivatives of `L` and `h` by forward-mode automatic differentiation (num-dual).
//!
//! Every quantity the mechanics needs comes from evaluations of `L` or `h` over scalar dual
//! numbers, so nothing allocates and a model's functions are compiled for a few number types
//! whatever its dimension (`N`, the number of coordinates, sizes only the arrays):
//! - `M = ∂²L/∂q̇²`: hyper-duals, one pass per entry, seeded on `q̇_i` and `q̇_j`;
//! - `(∂²L/∂q̇∂q) q̇`: hyper-duals, one pass per row, `ε₁` on `q̇_i`, `ε₂` the direction `q̇` in `q`;
//! - `∂L/∂q`: duals, one pass per coordinate;
//! - `A = ∂h/∂q`, `A q̇` and `Ȧ q̇ = q̇ᵀ∇²h q̇`: hyper-duals, one pass per coordinate, `ε₁` on
//!   `q_i`, `ε₂` the direction `q̇`;
//! - the energy `q̇ᵀ ∂L/∂q̇ − L`: a dual in the direction `q̇` of `q̇`.
//!
//! The runtime dimension is mapped to `N` by [`with_dimension!`] (up to [`MAX_DIMENSION`]).

use crate::model::{HybridLagrangian, Scalar};
use nalgebra::{SMatrix, SVector};
use num_dual::{Dual, Dual2, HyperDual};

/// The largest number of coordinates a model may have.
///
/// Each dimension up to it compiles the mechanics' statically sized linear algebra separately
/// for every model type, so it bounds the build time (the model's own functions are compiled
/// once per number type, whatever the dimension). Raising it means adding the new dimensions to
/// the list in the crate's `with_dimension!` macro (a unit test checks that they agree).
pub const MAX_DIMENSION: usize = 20;

/// Runs `$body` with `$N` a `const usize` equal to the runtime dimension `$n`
/// (1..=[`MAX_DIMENSION`]).
///
/// With a model type first (`with_dimension!(L; n, N => …)`), the body is compiled only for the
/// dimensions `L` may have ([`HybridLagrangian::DIMENSION`]): the arms of the others are
/// constant-false after monomorphisation, and rustc neither collects nor compiles their code.
macro_rules! with_dimension {
    ($L:ty; $n:expr, $N:ident => $body:expr) => {
        $crate::derivatives::with_dimension!($n, $N => {
            if $crate::derivatives::Possible::<$L, $N>::DIMENSION {
                $body
            } else {
                unreachable!(
                    "dimension {} is not the {:?} the model's type declares: setup refuses it",
                    $N,
                    <$L as $crate::model::HybridLagrangian>::DIMENSION
                )
            }
        })
    };
    ($n:expr, $N:ident => $body:expr) => {
        $crate::derivatives::dimension_match!(
            $n, $N, $body, [1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20]
        )
    };
}
pub(crate) use with_dimension;

/// Whether a model of type `L` may have dimension `N`: a constant for each pair, so that
/// [`with_dimension!`] compiles only the dimensions `L` declares.
pub(crate) struct Possible<L, const N: usize>(std::marker::PhantomData<L>);

impl<L: HybridLagrangian, const N: usize> Possible<L, N> {
    pub(crate) const DIMENSION: bool = match L::DIMENSION {
        None => true,
        Some(d) => d == N,
    };
}

/// `model`'s dimension, or the error that refuses it: 0, above [`MAX_DIMENSION`], or not the
/// [`HybridLagrangian::DIMENSION`] its type declares.
pub(crate) fn checked_dimension<L: HybridLagrangian>(model: &L) -> Result<usize, crate::Error> {
    let n = model.dimension();
    if n == 0 || n > MAX_DIMENSION {
        return Err(crate::Error::Dimension {
            dimension: n,
            max: MAX_DIMENSION,
        });
    }
    match L::DIMENSION {
        Some(declared) if declared != n => Err(crate::Error::DeclaredDimension {
            declared,
            dimension: n,
        }),
        _ => Ok(n),
    }
}

/// The `match` behind [`with_dimension!`]: one arm per listed dimension, each with its own
/// `const $N`, and `$body` written into every arm.
macro_rules! dimension_match {
    ($n:expr, $N:ident, $body:expr, [$($dimension:literal)+]) => {
        match $n {
            $(
                $dimension => {
                    const $N: usize = $dimension;
                    $body
                }
            )+
            other => unreachable!("dimension {other} was checked against MAX_DIMENSION at setup"),
        }
    };
}
pub(crate) use dimension_match;

/// The Lagrangian's terms at `(q, q̇)`: `M q̈ = force` is the Euler–Lagrange equation.
///
/// Over `f64` they are numbers; over a traced number ([`crate::compiled`]) the formulas for them.
pub(crate) struct LagrangianTerms<const N: usize, T = f64> {
    /// `M = ∂²L/∂q̇²`.
    pub mass: SMatrix<T, N, N>,
    /// `∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q`, i.e. `−(C q̇ + N) + Q` for `L = ½ q̇ᵀMq̇ − V`,
    /// with `Q` the generalized force and `−∂D/∂q̇` of the dissipation function.
    pub force: SVector<T, N>,
}

/// One constraint at `q`: `h` and its gradient.
pub(crate) struct ConstraintTerms<const N: usize> {
    /// `h(q)`.
    pub h: f64,
    /// `A = ∂h/∂q` (as a column).
    pub gradient: SVector<f64, N>,
}

/// The derivatives of one constraint that [`ConstraintTerms`] is made of, over any number type.
///
/// For a surface that moves, `h(t, q)`: the normal velocity is `ḣ = A q̇ + ∂ₜh`, and its
/// acceleration `ḧ = A q̈ + q̇ᵀ∇²h q̇ + 2 ∂ₜA q̇ + ∂ₜ²h` (docs/forces-and-time.md).
pub(crate) struct ConstraintParts<const N: usize, T> {
    /// `h(t, q)`.
    pub h: T,
    /// `A = ∂h/∂q`.
    pub gradient: SVector<T, N>,
    /// `ḣ = A q̇ + ∂ₜh`.
    pub a_q_dot: T,
    /// `∇²h q̇ + ∂ₜAᵀ`.
    pub hessian_q_dot: SVector<T, N>,
    /// `∂ₜh`: 0 where the surface does not move.
    pub h_t: T,
    /// `∂ₜA q̇ + ∂ₜ²h`: with `q̇ · hessian_q_dot`, the part of `ḧ` that `q̈` does not give.
    pub time_drift: T,
}

/// `[f(0), …, f(N − 1)]`, filled over `fill` by a plain loop: std's `array::from_fn` goes
/// through its fallible machinery, which was compiled once per closure, dimension and model (a
/// fifth of a benchmark binary's code).
pub(crate) fn array<X: Copy, const N: usize>(fill: X, mut f: impl FnMut(usize) -> X) -> [X; N] {
    let mut out = [fill; N];
    for (k, x) in out.iter_mut().enumerate() {
        *x = f(k);
    }
    out
}

/// 1 or 0 as a `T`: a seed of a dual number.
fn unit<T: Scalar>(on: bool) -> T {
    if on {
        T::one()
    } else {
        T::zero()
    }
}

/// `M = ∂²L/∂q̇²`, over any number type `T` (`f64`, or traced).
///
/// One scalar hyper-dual pass per entry of the upper triangle (`ε₁` along `q̇_i`, `ε₂` along
/// `q̇_j`): plain `Copy` numbers that the compiler keeps in registers, which measured faster
/// over whole runs than one pass over a hyper-dual vector with `N × N` matrices.
pub(crate) fn mass_matrix_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> SMatrix<T, N, N> {
    let t_d = HyperDual::from_re(t);
    let q_d: [HyperDual<T>; N] = array(HyperDual::from_re(T::zero()), |k| HyperDual::from_re(q[k]));
    let mut mass = SMatrix::<T, N, N>::zeros();
    for i in 0..N {
        for j in i..N {
            let q_dot_d: [HyperDual<T>; N] = array(HyperDual::from_re(T::zero()), |k| {
                HyperDual::new(q_dot[k], unit(k == i), unit(k == j), T::zero())
            });
            let m_ij = model.lagrangian_at(t_d, &q_d, &q_dot_d).eps1eps2;
            mass[(i, j)] = m_ij;
            mass[(j, i)] = m_ij;
        }
    }
    mass
}

/// `M` and the Euler–Lagrange force `∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q`, over any number
/// type `T`.
pub(crate) fn lagrangian_terms_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> LagrangianTerms<N, T> {
    let mass = mass_matrix_of::<T, N, L>(model, t, q, q_dot);
    let force = force_of::<T, N, L>(model, t, q, q_dot);
    LagrangianTerms { mass, force }
}

/// The Euler–Lagrange force `∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q`, over any number type `T`.
pub(crate) fn force_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> SVector<T, N> {
    // (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t: one scalar hyper-dual pass per row, ε₁ on q̇_i, ε₂ along
    // (q̇, 1) in (q, t) (cheaper than one pass over a hyper-dual vector, whose optional parts
    // cost branches per operation). Where L does not depend on t, its ε₂ part is never read.
    let t_along = HyperDual::new(t, T::zero(), T::one(), T::zero());
    let q_along: [HyperDual<T>; N] = array(HyperDual::from_re(T::zero()), |k| {
        HyperDual::new(q[k], T::zero(), q_dot[k], T::zero())
    });
    let mixed: [T; N] = array(T::zero(), |i| {
        let q_dot_d: [HyperDual<T>; N] = array(HyperDual::from_re(T::zero()), |k| {
            HyperDual::new(q_dot[k], unit(k == i), T::zero(), T::zero())
        });
        model.lagrangian_at(t_along, &q_along, &q_dot_d).eps1eps2
    });

    // ∂L/∂q: one scalar dual pass per coordinate. Scalar passes only, here and below: the
    // model's functions are then compiled for a few number types whatever the dimension, where
    // dual vectors made one copy per dimension (most of the build time of a model's crate).
    let t_g = Dual::from_re(t);
    let q_dot_g: [Dual<T>; N] = array(Dual::from_re(T::zero()), |k| Dual::from_re(q_dot[k]));
    let dl_dq: [T; N] = array(T::zero(), |i| {
        let q_g: [Dual<T>; N] = array(Dual::from_re(T::zero()), |k| Dual::new(q[k], unit(k == i)));
        model.lagrangian_at(t_g, &q_g, &q_dot_g).eps
    });

    let mut force = SVector::from(array(T::zero(), |i| dl_dq[i] - mixed[i]));
    if !model.is_autonomous() {
        let applied = applied_force_of::<T, N, L>(model, t, q, q_dot);
        for i in 0..N {
            force[i] += applied[i];
        }
    }
    force
}

/// The applied generalized force `Q(t, q, q̇) − ∂D/∂q̇`: the model's forces and its dissipation
/// function's, over any number type (one dual pass per coordinate for `∂D/∂q̇`).
pub(crate) fn applied_force_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> [T; N] {
    let mut force = [T::zero(); N];
    model.generalized_force(t, &q[..N], &q_dot[..N], &mut force);
    let t_g = Dual::from_re(t);
    let q_g: [Dual<T>; N] = array(Dual::from_re(T::zero()), |k| Dual::from_re(q[k]));
    for (i, f) in force.iter_mut().enumerate() {
        let q_dot_g: [Dual<T>; N] = array(Dual::from_re(T::zero()), |k| {
            Dual::new(q_dot[k], unit(k == i))
        });
        *f -= model.dissipation(t_g, &q_g, &q_dot_g).eps;
    }
    force
}

/// The powers that change the energy between impacts, over `f64` (any `n`):
/// `(Q·q̇, −∂ₜL)`, the applied forces' (with the dissipation's) and the time dependence of `L`'s
/// (docs/forces-and-time.md).
pub(crate) fn powers<L: HybridLagrangian>(
    model: &L,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> (f64, f64) {
    with_dimension!(L; q.len(), N => {
        let applied = applied_force_of::<f64, N, L>(model, t, q, q_dot);
        let forces: f64 = applied.iter().zip(q_dot).map(|(f, v)| f * v).sum();
        let q_g: [Dual<f64>; N] = array(Dual::from_re(0.0), |k| Dual::from_re(q[k]));
        let v_g: [Dual<f64>; N] = array(Dual::from_re(0.0), |k| Dual::from_re(q_dot[k]));
        let dl_dt = model.lagrangian_at(Dual::new(t, 1.0), &q_g, &v_g).eps;
        (forces, -dl_dt)
    })
}

/// `h`, `A`, `ḣ` and `∇²h q̇ + ∂ₜAᵀ` of constraint `index`, over any number type `T`: one scalar
/// hyper-dual pass per coordinate, `ε₁` on `q_i`, `ε₂` the direction `(q̇, 1)` in `(q, t)`; and,
/// for a model that is not autonomous, one more with `ε₁` on `t` for `∂ₜh` and `∂ₜA q̇ + ∂ₜ²h`.
pub(crate) fn constraint_parts_of<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> ConstraintParts<N, T> {
    let t_along = HyperDual::new(t, T::zero(), T::one(), T::zero());
    let q_along = |i: Option<usize>| -> [HyperDual<T>; N] {
        array(HyperDual::from_re(T::zero()), |k| {
            HyperDual::new(q[k], unit(Some(k) == i), q_dot[k], T::zero())
        })
    };
    let passes: [HyperDual<T>; N] = array(HyperDual::from_re(T::zero()), |i| {
        model.constraint_at(index, t_along, &q_along(Some(i)))
    });
    let (h_t, time_drift) = if model.is_autonomous() {
        (T::zero(), T::zero())
    } else {
        let t_d = HyperDual::new(t, T::one(), T::one(), T::zero());
        let pass = model.constraint_at(index, t_d, &q_along(None));
        (pass.eps1, pass.eps1eps2)
    };
    ConstraintParts {
        h: passes[0].re,
        gradient: SVector::from(array(T::zero(), |i| passes[i].eps1)),
        a_q_dot: passes[0].eps2,
        hessian_q_dot: SVector::from(array(T::zero(), |i| passes[i].eps1eps2)),
        h_t,
        time_drift,
    }
}

/// `h`, `ḣ = A q̇ + ∂ₜh` and the part of `ḧ` that `q̈` does not give, `q̇ᵀ∇²h q̇ + 2 ∂ₜA q̇ +
/// ∂ₜ²h`, of constraint `index` along free flight, over any number type, in one scalar
/// second-order pass along `(q̇, 1)` (any `n`).
pub(crate) fn guard_along_of<T: Scalar, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> (T, T, T) {
    // A model that declares its size gets arrays of that size: no array of MAX_DIMENSION
    // numbers to clear at every sample of a guard (a call to memset each).
    match L::DIMENSION {
        Some(_) => {
            with_dimension!(L; q.len(), N => guard_along_in::<T, N, L>(model, index, t, q, q_dot))
        }
        None => guard_along_in::<T, MAX_DIMENSION, L>(model, index, t, q, q_dot),
    }
}

/// [`guard_along_of`] with its duals in an array of `N ≥ n`.
#[inline(always)]
fn guard_along_in<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> (T, T, T) {
    let mut q_d = [Dual2::<T>::from_re(T::zero()); N];
    for ((x, &qi), &vi) in q_d.iter_mut().zip(q).zip(q_dot) {
        *x = Dual2::new(qi, vi, T::zero());
    }
    let t_d = Dual2::new(t, T::one(), T::zero());
    let h = model.constraint_at(index, t_d, &q_d[..q.len()]);
    (h.re, h.v1, h.v2)
}

/// The energy `q̇ᵀ ∂L/∂q̇ − L` over any number type (any `n`): a dual in the direction `q̇`.
pub(crate) fn energy_of<T: Scalar, L: HybridLagrangian>(
    model: &L,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> T {
    // Arrays of the model's size where it declares one, as for [`guard_along_of`].
    match L::DIMENSION {
        Some(_) => with_dimension!(L; q.len(), N => energy_in::<T, N, L>(model, t, q, q_dot)),
        None => energy_in::<T, MAX_DIMENSION, L>(model, t, q, q_dot),
    }
}

/// [`energy_of`] with its duals in arrays of `N ≥ n`.
#[inline(always)]
fn energy_in<T: Scalar, const N: usize, L: HybridLagrangian>(
    model: &L,
    t: T,
    q: &[T],
    q_dot: &[T],
) -> T {
    let mut q_d = [Dual::<T>::from_re(T::zero()); N];
    let mut v_d = [Dual::<T>::from_re(T::zero()); N];
    for (x, &qi) in q_d.iter_mut().zip(q) {
        *x = Dual::from_re(qi);
    }
    for (v, &vi) in v_d.iter_mut().zip(q_dot) {
        *v = Dual::new(vi, vi);
    }
    let n = q.len();
    let l = model.lagrangian_at(Dual::from_re(t), &q_d[..n], &v_d[..n]);
    l.eps - l.re
}

/// `M = ∂²L/∂q̇²`: from the model's compiled derivatives if it has them, else differentiated.
pub(crate) fn mass_matrix<const N: usize, L: HybridLagrangian>(
    model: &L,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> SMatrix<f64, N, N> {
    match model
        .compiled()
        .and_then(|c| c.lagrangian_terms::<N>(t, q, q_dot))
    {
        Some(terms) => terms.mass,
        None => mass_matrix_of::<f64, N, L>(model, t, q, q_dot),
    }
}

/// `M` and the Euler–Lagrange force: compiled if the model has them, else differentiated.
#[cfg(test)]
pub(crate) fn lagrangian_terms<const N: usize, L: HybridLagrangian>(
    model: &L,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> LagrangianTerms<N> {
    match model
        .compiled()
        .and_then(|c| c.lagrangian_terms::<N>(t, q, q_dot))
    {
        Some(terms) => terms,
        None => lagrangian_terms_of::<f64, N, L>(model, t, q, q_dot),
    }
}

/// `h` and `A` of constraint `index` at `(t, q)`: compiled or differentiated.
pub(crate) fn constraint_terms<const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: f64,
    q: &[f64],
) -> ConstraintTerms<N> {
    let q_dot = [0.0; N];
    let parts = match model
        .compiled()
        .and_then(|c| c.constraint_parts::<N>(index, t, q, &q_dot))
    {
        Some(parts) => parts,
        None => constraint_parts_of::<f64, N, L>(model, index, t, q, &q_dot),
    };
    ConstraintTerms {
        h: parts.h,
        gradient: parts.gradient,
    }
}

/// `h`, `ḣ` and the part of `ḧ` that `q̈` does not give, of constraint `index`, without the full
/// gradient: the guard and its first two time derivatives along free flight (any `n`);
/// compiled or differentiated.
#[inline]
pub(crate) fn guard_along<L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> (f64, f64, f64) {
    match model
        .compiled()
        .and_then(|c| c.guard_along(index, t, q, q_dot))
    {
        Some(guard) => guard,
        None => guard_along_of::<f64, L>(model, index, t, q, q_dot),
    }
}

/// The energy `q̇ᵀ ∂L/∂q̇ − L` (any `n`): compiled or differentiated.
pub(crate) fn energy<L: HybridLagrangian>(model: &L, t: f64, q: &[f64], q_dot: &[f64]) -> f64 {
    match model.compiled().and_then(|c| c.energy(t, q, q_dot)) {
        Some(e) => e,
        None => energy_of::<f64, L>(model, t, q, q_dot),
    }
}

#[cfg(test)]
mod tests {
    //! The automatic derivatives against central finite differences of the models' own
    //! `lagrangian::<f64>` and `constraint::<f64>`, at random states.
    //!
    //! Finite-difference steps and the tolerance: a first derivative uses the 2nd-order central
    //! difference with step 1e-5 (truncation `h² f'''/6 ≈ 1e-11`, round-off `ε|f|/h ≈ 2e-11 |f|`);
    //! a second derivative uses the mixed central difference with steps 1e-3 and 5e-4 combined
    //! by Richardson extrapolation (truncation `O(h⁴) ≈ 1e-12`, round-off `≈ 4ε|f|/h² ≈ 4e-9 |f|`;
    //! step 1e-5 would leave round-off of `ε|f|/h² ≈ 2e-6 |f|`). The comparison tolerance
    //! `1e-6 · (1 + scale)`, with `scale` the size of the values the differences are taken of,
    //! leaves two or more orders of margin over both errors, while any wrong term (a sign, a
    //! factor 2, a missing curvature term) is an O(1) relative error.

    use super::*;
    use crate::model::{Constraint, Scalar};
    use crate::models::{BallOnSine, BouncingBall, CartPendulum, PendulumChain, SphericalPendulum};
    use crate::motion::{
        constrained_motion_of, direction_of, free_motion_of, held_acceleration_of, Outputs,
    };
    use proptest::prelude::*;

    const STEP1: f64 = 1e-5;
    const STEP2: f64 = 1e-3;
    const TOL: f64 = 1e-6;

    /// `d/ds f(z + s a)` at 0, 2nd-order central difference.
    fn d1(f: &impl Fn(&[f64]) -> f64, z: &[f64], a: &[f64]) -> f64 {
        let at = |s: f64| {
            let p: Vec<f64> = z.iter().zip(a).map(|(x, d)| x + s * d).collect();
            f(&p)
        };
        (at(STEP1) - at(-STEP1)) / (2.0 * STEP1)
    }

    /// `∂²/∂s∂t f(z + s a + t b)` at 0: mixed central differences, Richardson-extrapolated.
    fn d2(f: &impl Fn(&[f64]) -> f64, z: &[f64], a: &[f64], b: &[f64]) -> f64 {
        let at = |s: f64, t: f64| {
            let p: Vec<f64> = z
                .iter()
                .zip(a.iter().zip(b))
                .map(|(x, (da, db))| x + s * da + t * db)
                .collect();
            f(&p)
        };
        let mixed = |h: f64| (at(h, h) - at(h, -h) - at(-h, h) + at(-h, -h)) / (4.0 * h * h);
        (4.0 * mixed(STEP2 / 2.0) - mixed(STEP2)) / 3.0
    }

    fn unit(len: usize, i: usize) -> Vec<f64> {
        let mut e = vec![0.0; len];
        e[i] = 1.0;
        e
    }

    fn close(what: &str, ad: f64, fd: f64, scale: f64) -> Result<(), TestCaseError> {
        prop_assert!(
            (ad - fd).abs() <= TOL * (1.0 + scale),
            "{what}: automatic {ad:e}, finite differences {fd:e} (scale {scale:e})"
        );
        Ok(())
    }

    /// Every derived quantity of `model` at `(q, q̇)` against finite differences.
    fn check_model<const N: usize, L: HybridLagrangian>(
        model: &L,
        q: &[f64],
        v: &[f64],
    ) -> Result<(), TestCaseError> {
        assert_eq!(model.dimension(), N);
        // L and h as functions of z = (q, q̇), resp. q.
        let lz = |z: &[f64]| model.lagrangian::<f64>(&z[..N], &z[N..]);
        let z: Vec<f64> = q.iter().chain(v).copied().collect();
        let l_scale = lz(&z).abs()
            + model.lagrangian::<f64>(q, &[0.0; N]).abs()
            + (lz(&z) - model.lagrangian::<f64>(q, &[0.0; N])).abs();
        let in_q = |d: &[f64]| -> Vec<f64> { d.iter().copied().chain([0.0; N]).collect() };
        let in_v =
            |d: &[f64]| -> Vec<f64> { [0.0; N].iter().copied().chain(d.iter().copied()).collect() };

        // M = ∂²L/∂q̇².
        let terms = lagrangian_terms::<N, L>(model, 0.0, q, v);
        let mass = mass_matrix::<N, L>(model, 0.0, q, v);
        prop_assert_eq!(
            mass,
            terms.mass,
            "mass_matrix and lagrangian_terms disagree"
        );
        for i in 0..N {
            for j in 0..N {
                let fd = d2(&lz, &z, &in_v(&unit(N, i)), &in_v(&unit(N, j)));
                close(&format!("M[{i}][{j}]"), mass[(i, j)], fd, l_scale)?;
            }
        }

        // force = ∂L/∂q − (∂²L/∂q̇∂q) q̇, by nested differences.
        for i in 0..N {
            let dl_dq = d1(&lz, &z, &in_q(&unit(N, i)));
            let mixed = d2(&lz, &z, &in_v(&unit(N, i)), &in_q(v));
            close(
                &format!("force[{i}]"),
                terms.force[i],
                dl_dq - mixed,
                l_scale,
            )?;
        }

        // The Euler–Lagrange equation itself: with q̈ = M⁻¹ force,
        // d/dt ∂L/∂q̇_i along (q̇, q̈) equals ∂L/∂q_i.
        if let Some(chol) = nalgebra::Cholesky::new(terms.mass) {
            let acc = chol.solve(&terms.force);
            let flow: Vec<f64> = v.iter().chain(acc.iter()).copied().collect();
            for i in 0..N {
                let d_dt = d2(&lz, &z, &in_v(&unit(N, i)), &flow);
                let dl_dq = d1(&lz, &z, &in_q(&unit(N, i)));
                close(
                    &format!("Euler–Lagrange residual [{i}]"),
                    d_dt,
                    dl_dq,
                    l_scale,
                )?;
            }
        }

        // The energy q̇ᵀ ∂L/∂q̇ − L.
        let p_dot_v: f64 = (0..N).map(|i| v[i] * d1(&lz, &z, &in_v(&unit(N, i)))).sum();
        close(
            "energy",
            energy(model, 0.0, q, v),
            p_dot_v - lz(&z),
            l_scale,
        )?;

        // The constraints: h, A, A q̇, Ȧ q̇ = q̇ᵀ ∇²h q̇, and guard_along.
        for index in 0..model.constraints().len() {
            let hq = |x: &[f64]| model.constraint::<f64>(index, x);
            let h = hq(q);
            let c = full_terms::<N, L>(model, index, q, v);
            let h_scale = h.abs() + 1.0;
            // The real part is the same arithmetic as the f64 evaluation.
            prop_assert!((c.h - h).abs() <= 1e-14 * h_scale, "h: {} vs {}", c.h, h);
            for i in 0..N {
                let fd = d1(&hq, q, &unit(N, i));
                close(
                    &format!("A[{i}] of constraint {index}"),
                    c.gradient[i],
                    fd,
                    h_scale,
                )?;
            }
            let a_q_dot: f64 = c.gradient.iter().zip(v).map(|(a, x)| a * x).sum();
            prop_assert!(
                (c.a_q_dot - a_q_dot).abs() <= 1e-12 * (1.0 + a_q_dot.abs()),
                "A q̇ = {} but A·q̇ = {}",
                c.a_q_dot,
                a_q_dot
            );
            close("A q̇", c.a_q_dot, d1(&hq, q, v), h_scale)?;
            close("Ȧ q̇", c.a_dot_q_dot, d2(&hq, q, v, v), h_scale)?;

            let (g, g_dot, g_ddot) = guard_along(model, index, 0.0, q, v);
            prop_assert_eq!(g, c.h, "guard_along's h");
            let tight = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()));
            prop_assert!(
                tight(g_dot, c.a_q_dot),
                "guard_along ḣ {g_dot} vs A q̇ {}",
                c.a_q_dot
            );
            prop_assert!(
                tight(g_ddot, c.a_dot_q_dot),
                "guard_along ḧ {g_ddot} vs Ȧ q̇ {}",
                c.a_dot_q_dot
            );
        }
        Ok(())
    }

    /// A test model with a configuration-dependent, non-diagonal and velocity-dependent (not
    /// quadratic) kinetic term and two curved constraints, to exercise every term of the
    /// derivatives that the four example models leave at zero.
    /// `M = [[3 + 2cos q2 + 1.2 q̇1², 1 + cos q2], [1 + cos q2, 1]]`, `det = 2 − cos²q2 + 1.2 q̇1² > 0`.
    struct Coupled {
        constraints: [Constraint; 2],
    }

    impl HybridLagrangian for Coupled {
        const DIMENSION: Option<usize> = Some(2);
        fn dimension(&self) -> usize {
            2
        }
        fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
            let c2 = q[1].cos();
            (c2 * 2.0 + 3.0) * v[0] * v[0] * 0.5
                + (c2 + 1.0) * v[0] * v[1]
                + v[1] * v[1] * 0.5
                + v[0].powi(4) * 0.1
                + (q[0].cos() + (q[0] + q[1]).cos()) * 9.81
        }
        fn constraints(&self) -> &[Constraint] {
            &self.constraints
        }
        fn constraint<D: Scalar>(&self, index: usize, q: &[D]) -> D {
            match index {
                0 => q[0].cos() + 1.5 - (q[0] + q[1]).sin().powi(2) * 0.5,
                _ => q[0] * q[1].exp() - q[1] * q[1] * 0.3,
            }
        }
    }

    /// `h`, `A`, `A q̇` and `Ȧ q̇` of constraint `index` as the engine computes them (the motion
    /// held on the constraint).
    struct FullTerms<const N: usize> {
        h: f64,
        gradient: SVector<f64, N>,
        a_q_dot: f64,
        a_dot_q_dot: f64,
    }

    fn full_terms<const N: usize, L: HybridLagrangian>(
        model: &L,
        index: usize,
        q: &[f64],
        v: &[f64],
    ) -> FullTerms<N> {
        let motion = crate::motion::constrained_motion::<N, L>(model, index, 0.0, q, v);
        FullTerms {
            h: motion.direction.h,
            gradient: motion.direction.gradient,
            a_q_dot: motion.direction.a_q_dot,
            a_dot_q_dot: motion.a_dot_q_dot,
        }
    }

    /// Bitwise equality, NaN included (a compiled part must give the very same numbers).
    fn same_bits(what: &str, compiled: f64, differentiated: f64) -> Result<(), TestCaseError> {
        prop_assert!(
            compiled.to_bits() == differentiated.to_bits()
                || (compiled == 0.0 && differentiated == 0.0),
            "{what}: compiled {compiled:e}, differentiated {differentiated:e}"
        );
        Ok(())
    }

    /// Every compiled part of `model` against the differentiation it was traced from, bit for
    /// bit (zeros of either sign are equal: the tracer may drop the sign of an exact zero).
    fn check_compiled<const N: usize, L: HybridLagrangian>(
        model: &L,
        compiled: &crate::Compiled,
        q: &[f64],
        v: &[f64],
    ) -> Result<(), TestCaseError> {
        let terms = compiled.lagrangian_terms::<N>(0.0, q, v).expect("traced");
        let reference = lagrangian_terms_of::<f64, N, L>(model, 0.0, q, v);
        for (k, (a, b)) in terms.mass.iter().zip(reference.mass.iter()).enumerate() {
            same_bits(&format!("M[{k}]"), *a, *b)?;
        }
        for (k, (a, b)) in terms.force.iter().zip(reference.force.iter()).enumerate() {
            same_bits(&format!("force[{k}]"), *a, *b)?;
        }
        for index in 0..model.constraints().len() {
            let c = compiled
                .constraint_parts::<N>(index, 0.0, q, v)
                .expect("traced");
            let r = constraint_parts_of::<f64, N, L>(model, index, 0.0, q, v);
            same_bits("h", c.h, r.h)?;
            same_bits("A q̇", c.a_q_dot, r.a_q_dot)?;
            for k in 0..N {
                same_bits(&format!("A[{k}]"), c.gradient[k], r.gradient[k])?;
                same_bits(
                    &format!("∇²h q̇[{k}]"),
                    c.hessian_q_dot[k],
                    r.hessian_q_dot[k],
                )?;
            }
            let g = compiled.guard_along(index, 0.0, q, v).expect("traced");
            let rg = guard_along_of::<f64, L>(model, index, 0.0, q, v);
            same_bits("guard h", g.0, rg.0)?;
            same_bits("guard ḣ", g.1, rg.1)?;
            same_bits("guard ḧ", g.2, rg.2)?;
        }
        same_bits(
            "energy",
            compiled.energy(0.0, q, v).expect("traced"),
            energy_of::<f64, L>(model, 0.0, q, v),
        )?;
        // The motion is traced whole only where M is constant; otherwise zenosim assembles it
        // from the parts checked above.
        if !compiled.whole_motion() {
            prop_assert!(compiled.free_motion::<N>(0.0, q, v).is_none());
            return Ok(());
        }
        // A program refuses (None, and zenosim computes instead) only where the motion divides
        // by a zero that the tracer may have signed differently: a zero pivot of M, or s = 0.
        let zero_divisor =
            |d: &crate::motion::Direction<N>| d.s == 0.0 || d.pivots.iter().any(|&p| p == 0.0);
        same_outputs(
            "free motion",
            compiled.free_motion::<N>(0.0, q, v).as_ref(),
            &free_motion_of::<f64, N, L>(model, 0.0, q, v),
            |m| m.pivots.iter().any(|&p| p == 0.0),
        )?;
        for index in 0..model.constraints().len() {
            same_outputs(
                &format!("motion held on constraint {index}"),
                compiled.constrained_motion::<N>(index, 0.0, q, v).as_ref(),
                &constrained_motion_of::<f64, N, L>(model, index, 0.0, q, v),
                |m| zero_divisor(&m.direction),
            )?;
            same_outputs(
                &format!("acceleration held on constraint {index}"),
                compiled.held_acceleration::<N>(index, 0.0, q, v).as_ref(),
                &held_acceleration_of::<f64, N, L>(model, index, 0.0, q, v),
                |m| m.s == 0.0 || m.pivots.iter().any(|&p| p == 0.0),
            )?;
            same_outputs(
                &format!("direction of constraint {index}"),
                compiled.direction::<N>(index, 0.0, q, v).as_ref(),
                &direction_of::<f64, N, L>(model, index, 0.0, q, v),
                zero_divisor,
            )?;
        }
        Ok(())
    }

    /// Every output of a compiled motion against the motion computed over `f64`, bit for bit;
    /// a program may refuse only where `refusable` says so of the computed motion.
    fn same_outputs<O: Outputs<f64>>(
        what: &str,
        compiled: Option<&O>,
        computed: &O,
        refusable: impl Fn(&O) -> bool,
    ) -> Result<(), TestCaseError> {
        let Some(compiled) = compiled else {
            prop_assert!(refusable(computed), "{what}: the program refused");
            return Ok(());
        };
        let (mut a, mut b) = (Vec::new(), Vec::new());
        compiled.write(&mut a);
        computed.write(&mut b);
        prop_assert_eq!(a.len(), b.len());
        for (k, (x, y)) in a.into_iter().zip(b).enumerate() {
            same_bits(&format!("{what}, output {k}"), x, y)?;
        }
        Ok(())
    }

    /// `L = ½ (1.5 + 0.3 sin t cos q₁) q̇₁² + 0.4 cos 2t q̇₁ q̇₂ + ½ q̇₂² − 9.81 (1 + 0.1 t) q₂`,
    /// `h = q₂ − 0.2 sin 3t q₁ + 0.1 cos t q₁²`, `Q = (sin t − 0.3 q̇₂, 0)`, `D = 0.25 q̇₁² q̇₂²`.
    struct TimeDependent {
        constraints: [Constraint; 1],
    }

    impl HybridLagrangian for TimeDependent {
        const DIMENSION: Option<usize> = Some(2);
        fn dimension(&self) -> usize {
            2
        }
        fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
            self.lagrangian_at(D::zero(), q, v)
        }
        fn lagrangian_at<D: Scalar>(&self, t: D, q: &[D], v: &[D]) -> D {
            (t.sin() * q[0].cos() * 0.3 + 1.5) * v[0] * v[0] * 0.5
                + (t * 2.0).cos() * v[0] * v[1] * 0.4
                + v[1] * v[1] * 0.5
                - (t * 0.1 + 1.0) * q[1] * 9.81
        }
        fn constraints(&self) -> &[Constraint] {
            &self.constraints
        }
        fn constraint<D: Scalar>(&self, index: usize, q: &[D]) -> D {
            self.constraint_at(index, D::zero(), q)
        }
        fn constraint_at<D: Scalar>(&self, _index: usize, t: D, q: &[D]) -> D {
            q[1] - (t * 3.0).sin() * q[0] * 0.2 + t.cos() * q[0] * q[0] * 0.1
        }
        fn generalized_force<D: Scalar>(&self, t: D, _q: &[D], v: &[D], force: &mut [D]) {
            force[0] += t.sin() - v[1] * 0.3;
        }
        fn dissipation<D: Scalar>(&self, _t: D, _q: &[D], v: &[D]) -> D {
            v[0] * v[0] * v[1] * v[1] * 0.25
        }
        fn is_autonomous(&self) -> bool {
            false
        }
    }

    fn check_time_dependent(t: f64, q: &[f64], v: &[f64]) -> Result<(), TestCaseError> {
        use num_dual::Dual64;
        let model = TimeDependent {
            constraints: [Constraint::new("moving", 0.5)],
        };
        // ∂L/∂q̇ᵢ and ∂L/∂qᵢ at (t, q, q̇) by duals of the model itself.
        let partial = |t: f64, q: &[f64], v: &[f64], i: usize, of_velocity: bool| {
            let seed = |x: &[f64], on: bool| -> Vec<Dual64> {
                x.iter()
                    .enumerate()
                    .map(|(k, &x)| Dual64::new(x, if on && k == i { 1.0 } else { 0.0 }))
                    .collect()
            };
            let (qd, vd) = (seed(q, !of_velocity), seed(v, of_velocity));
            model.lagrangian_at(Dual64::from_re(t), &qd, &vd).eps
        };
        let terms = lagrangian_terms_of::<f64, 2, _>(&model, t, q, v);
        let acc = nalgebra::Cholesky::new(terms.mass)
            .expect("M > 0")
            .solve(&terms.force);
        // d/dt ∂L/∂q̇ᵢ along (q̇, q̈, 1) = ∂L/∂qᵢ + Qᵢ − ∂D/∂q̇ᵢ.
        let along = |s: f64, i: usize| {
            let qs: Vec<f64> = (0..2).map(|k| q[k] + s * v[k]).collect();
            let vs: Vec<f64> = (0..2).map(|k| v[k] + s * acc[k]).collect();
            partial(t + s, &qs, &vs, i, true)
        };
        for i in 0..2 {
            let d_dt = (along(STEP1, i) - along(-STEP1, i)) / (2.0 * STEP1);
            let applied = applied_force_of::<f64, 2, _>(&model, t, q, v)[i];
            let rhs = partial(t, q, v, i, false) + applied;
            close(
                &format!("Euler–Lagrange residual [{i}] at t = {t}"),
                d_dt,
                rhs,
                10.0,
            )?;
        }
        // The applied force: Q and −∂D/∂q̇ in closed form.
        let applied = applied_force_of::<f64, 2, _>(&model, t, q, v);
        close(
            "Q₁",
            applied[0],
            t.sin() - 0.3 * v[1] - 0.5 * v[0] * v[1] * v[1],
            1.0,
        )?;
        close("Q₂", applied[1], -0.5 * v[0] * v[0] * v[1], 1.0)?;
        // h along (q̇, 1): its first and second derivatives are ḣ and the drift of ḧ.
        let h_along = |s: f64| {
            let qs: Vec<f64> = (0..2).map(|k| q[k] + s * v[k]).collect();
            model.constraint_at::<f64>(0, t + s, &qs)
        };
        let c = constraint_parts_of::<f64, 2, _>(&model, 0, t, q, v);
        let h_t = (model.constraint_at::<f64>(0, t + STEP1, q)
            - model.constraint_at::<f64>(0, t - STEP1, q))
            / (2.0 * STEP1);
        close("∂ₜh", c.h_t, h_t, 1.0)?;
        close(
            "ḣ",
            c.a_q_dot,
            (h_along(STEP1) - h_along(-STEP1)) / (2.0 * STEP1),
            1.0,
        )?;
        let s = STEP2;
        let second = |s: f64| (h_along(s) - 2.0 * h_along(0.0) + h_along(-s)) / (s * s);
        let drift = (4.0 * second(s / 2.0) - second(s)) / 3.0;
        let q_dot_hessian: f64 = c.hessian_q_dot.iter().zip(v).map(|(a, b)| a * b).sum();
        close("the drift of ḧ", q_dot_hessian + c.time_drift, drift, 1.0)?;
        let (g, g_dot, g_ddot) = guard_along_of::<f64, _>(&model, 0, t, q, v);
        prop_assert_eq!(g, c.h);
        close("guard ḣ", g_dot, c.a_q_dot, 1.0)?;
        close("guard drift", g_ddot, q_dot_hessian + c.time_drift, 1.0)?;
        // The traced programs, at this time.
        let compiled = crate::Compiled::trace_n::<2, _>(&model);
        let traced = compiled.constraint_parts::<2>(0, t, q, v).expect("traced");
        same_bits("∂ₜh traced", traced.h_t, c.h_t)?;
        same_bits("drift traced", traced.time_drift, c.time_drift)?;
        let traced = compiled.lagrangian_terms::<2>(t, q, v).expect("traced");
        for k in 0..2 {
            same_bits("force traced", traced.force[k], terms.force[k])?;
        }
        same_bits(
            "energy traced",
            compiled.energy(t, q, v).expect("traced"),
            energy_of::<f64, _>(&model, t, q, v),
        )?;
        Ok(())
    }

    /// A model whose constraint branches on a value (`abs`): that part cannot be traced.
    struct Branching {
        constraints: [Constraint; 1],
    }

    impl HybridLagrangian for Branching {
        const DIMENSION: Option<usize> = Some(1);
        fn dimension(&self) -> usize {
            1
        }
        fn lagrangian<D: Scalar>(&self, _q: &[D], v: &[D]) -> D {
            v[0] * v[0] * 0.5
        }
        fn constraints(&self) -> &[Constraint] {
            &self.constraints
        }
        fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
            -q[0].abs() + 1.0
        }
    }

    #[test]
    fn with_dimension_covers_one_to_max_dimension() {
        for n in 1..=MAX_DIMENSION {
            assert_eq!(with_dimension!(n, N => N), n);
        }
        let beyond = std::panic::catch_unwind(|| with_dimension!(MAX_DIMENSION + 1, N => N));
        assert!(
            beyond.is_err(),
            "a dimension above MAX_DIMENSION has an arm"
        );
    }

    #[test]
    fn a_branch_on_a_value_leaves_that_part_differentiated() {
        let model = Branching {
            constraints: [Constraint::new("wall", 0.5)],
        };
        let compiled = crate::Compiled::trace_n::<1, _>(&model);
        // The Lagrangian terms, the energy and the free motion traced; the constraint, its
        // guard, the motion held on it and its direction did not.
        assert_eq!(compiled.coverage(), (3, 8));
        assert!(compiled
            .constrained_motion::<1>(0, 0.0, &[0.3], &[1.0])
            .is_none());
        assert!(compiled.free_motion::<1>(0.0, &[0.3], &[1.0]).is_some());
        assert!(compiled
            .constraint_parts::<1>(0, 0.0, &[0.3], &[1.0])
            .is_none());
        assert!(compiled.guard_along(0, 0.0, &[0.3], &[1.0]).is_none());
        assert!(compiled
            .lagrangian_terms::<1>(0.0, &[0.3], &[1.0])
            .is_some());
        // The trace is over: an ordinary evaluation is unaffected.
        assert!(!crate::Compiled::is_tracing());
    }

    #[test]
    fn the_paper_ball_compiles_to_a_few_operations() {
        let model = BallOnSine::paper().model;
        let compiled = crate::Compiled::trace_n::<3, _>(&model);
        assert_eq!(compiled.coverage(), (8, 8));
        // M = m I and the force (0, 0, −m g) are constants: the Euler–Lagrange terms and the
        // free motion need no operation at all (M's factorisation folds away); h, A, ∇²h q̇, the
        // guard, the motion held on the surface and its direction need a handful.
        assert_eq!(compiled.free_operations(), Some(0));
        assert!(compiled.whole_motion());
        // That constant is the dual numbers' only where q̇ is finite (they multiply it by M's
        // zero derivatives): a run checks the velocity, and gives nothing where it is not.
        let q = [0.1, 0.2, 0.3];
        assert!(compiled
            .free_motion::<3>(0.0, &q, &[1.0, 2.0, 3.0])
            .is_some());
        assert!(compiled
            .free_motion::<3>(0.0, &q, &[1.0, f64::NAN, 3.0])
            .is_none());
        assert!(compiled
            .free_motion::<3>(0.0, &q, &[1.0, 2.0, f64::INFINITY])
            .is_none());
        // The cart pendulum's M depends on θ: its motion is assembled from the traced parts.
        let cart = CartPendulum::demo().model;
        assert!(!crate::Compiled::trace_n::<2, _>(&cart).whole_motion());
        let terms = compiled.lagrangian_terms::<3>(0.0, &[0.1, 0.2, 0.3], &[1.0, 2.0, 3.0]);
        assert!(terms.is_some());
        // 61 when written: 7 each for the constraint and its guard, 8 for its direction, 14
        // for the motion held on the surface, 10 for the acceleration held on it, 15 for the
        // energy (73 before the programs folded the negations of the dual numbers' derivatives
        // of sin and cos into the operations that take them).
        assert!(
            compiled.operations() < 65,
            "{} operations",
            compiled.operations()
        );
    }

    fn vec_in(range: std::ops::Range<f64>, n: usize) -> impl Strategy<Value = Vec<f64>> {
        prop::collection::vec(range, n)
    }

    proptest! {
        // Failing cases are reported, not stored next to the sources.
        #![proptest_config(ProptestConfig {
            cases: 200,
            failure_persistence: None,
            ..ProptestConfig::default()
        })]

        #[test]
        fn bouncing_ball_derivatives(q in vec_in(-5.0..5.0, 1), v in vec_in(-5.0..5.0, 1)) {
            check_model::<1, _>(&BouncingBall::new(1.3, 9.81, 0.5), &q, &v)?;
        }

        #[test]
        fn ball_on_sine_derivatives(q in vec_in(-4.0..4.0, 3), v in vec_in(-3.0..3.0, 3)) {
            check_model::<3, _>(&BallOnSine::paper().model, &q, &v)?;
            check_model::<3, _>(&BallOnSine::new(2.5, 9.8, 0.9), &q, &v)?;
        }

        #[test]
        fn cart_pendulum_derivatives(q in vec_in(-3.2..3.2, 2), v in vec_in(-3.0..3.0, 2)) {
            check_model::<2, _>(&CartPendulum::demo().model, &q, &v)?;
        }

        #[test]
        fn spherical_pendulum_derivatives(
            theta in 0.2..2.9f64,
            phi in -3.2..3.2f64,
            v in vec_in(-3.0..3.0, 2),
        ) {
            check_model::<2, _>(&SphericalPendulum::demo().model, &[theta, phi], &v)?;
        }

        #[test]
        fn pendulum_chain_derivatives(q in vec_in(-3.2..3.2, 4), v in vec_in(-3.0..3.0, 4)) {
            check_model::<4, _>(&PendulumChain::example(4).model, &q, &v)?;
        }

        /// The chain's mass matrix in closed form, `M_ij = m (n + 1 − max(i, j)) l² cos(θ_i − θ_j)`
        /// (1-based), and `h = l Σ sin θ_i − w`, `A_i = l cos θ_i`.
        #[test]
        fn pendulum_chain_closed_form(q in vec_in(-3.2..3.2, 5), v in vec_in(-3.0..3.0, 5)) {
            let chain = PendulumChain::new(5, 0.7, 1.3, 9.81, 1.1, 0.5);
            let (l, m) = (0.7, 1.3);
            let mass = mass_matrix::<5, _>(&chain, 0.0, &q, &v);
            for i in 0..5 {
                for j in 0..5 {
                    let exact = m * (5 - i.max(j)) as f64 * l * l * (q[i] - q[j]).cos();
                    prop_assert!(
                        (mass[(i, j)] - exact).abs() <= 1e-14 * 5.0 * m * l * l,
                        "M[{i}][{j}] = {} vs {exact}", mass[(i, j)]
                    );
                }
            }
            let c = full_terms::<5, _>(&chain, 0, &q, &v);
            let h = l * q.iter().map(|t| t.sin()).sum::<f64>() - 1.1;
            prop_assert!((c.h - h).abs() <= 1e-14 * 5.0);
            for (a, theta) in c.gradient.iter().zip(&q) {
                prop_assert!((a - l * theta.cos()).abs() <= 1e-15);
            }
        }

        /// A model whose `L` and `h` depend on time, with forces and dissipation: the free
        /// motion satisfies the Euler–Lagrange equation with `t` moving, `∂ₜh`, `ḣ` and the drift of
        /// `ḧ` are the finite differences along `(q̇, 1)`, and the traced programs give the
        /// same bits as the differentiation.
        #[test]
        fn time_dependent_model_derivatives(
            t in -3.0..3.0f64,
            q in vec_in(-2.0..2.0, 2),
            v in vec_in(-2.0..2.0, 2),
        ) {
            check_time_dependent(t, &q, &v)?;
        }

        #[test]
        fn coupled_model_derivatives(q in vec_in(-3.2..3.2, 2), v in vec_in(-2.0..2.0, 2)) {
            let model = Coupled {
                constraints: [Constraint::new("a", 0.5), Constraint::new("b", 0.5)],
            };
            check_model::<2, _>(&model, &q, &v)?;
        }

        /// The compiled derivatives of every example model, and of the coupled test model, are
        /// the differentiated ones, bit for bit. The chain's programs are large enough to run
        /// in the large bank of registers, the others in the small one.
        #[test]
        fn compiled_derivatives_are_the_differentiated_ones(
            q in vec_in(-3.0..3.0, 4),
            v in vec_in(-3.0..3.0, 4),
        ) {
            let ball = BouncingBall::new(1.3, 9.81, 0.5);
            check_compiled::<1, _>(&ball, &crate::Compiled::trace_n::<1, _>(&ball), &q[..1], &v[..1])?;
            let sine = BallOnSine::paper().model;
            let traced = crate::Compiled::trace_n::<3, _>(&sine);
            prop_assert!(!traced.uses_large_registers());
            check_compiled::<3, _>(&sine, &traced, &q[..3], &v[..3])?;
            let chain = PendulumChain::new(4, 0.5, 0.5, 9.81, 1.0, 0.5);
            let traced = crate::Compiled::trace_n::<4, _>(&chain);
            prop_assert!(traced.uses_large_registers());
            check_compiled::<4, _>(&chain, &traced, &q, &v)?;
            let cart = CartPendulum::demo().model;
            check_compiled::<2, _>(&cart, &crate::Compiled::trace_n::<2, _>(&cart), &q[..2], &v[..2])?;
            let sph = SphericalPendulum::demo().model;
            check_compiled::<2, _>(&sph, &crate::Compiled::trace_n::<2, _>(&sph), &q[..2], &v[..2])?;
            let coupled = Coupled {
                constraints: [Constraint::new("a", 0.5), Constraint::new("b", 0.5)],
            };
            let compiled = crate::Compiled::trace_n::<2, _>(&coupled);
            // M varies: the terms, the energy and each constraint's derivatives and guard.
            prop_assert_eq!(compiled.coverage(), (6, 6));
            check_compiled::<2, _>(&coupled, &compiled, &q[..2], &v[..2])?;
        }

        /// Closed form for the paper's ball on the sinusoid (Example 6):
        /// `L = ½ m |ẋ|² − m g x3` gives `M = m I`, force `= (0, 0, −m g)`;
        /// `h = x3 − sin x2` gives `A = (0, −cos x2, 1)`, `Ȧ q̇ = q̇ᵀ∇²h q̇ = sin(x2) ẋ2²`;
        /// energy `½ m |ẋ|² + m g x3`.
        #[test]
        fn ball_on_sine_closed_form(q in vec_in(-4.0..4.0, 3), v in vec_in(-3.0..3.0, 3)) {
            let (m, g) = (2.5, 9.8);
            let model = BallOnSine::new(m, g, 0.9);
            let terms = lagrangian_terms::<3, _>(&model, 0.0, &q, &v);
            for i in 0..3 {
                for j in 0..3 {
                    prop_assert_eq!(terms.mass[(i, j)], if i == j { m } else { 0.0 });
                }
            }
            prop_assert_eq!(terms.force[0], 0.0);
            prop_assert_eq!(terms.force[1], 0.0);
            prop_assert!((terms.force[2] + m * g).abs() <= 1e-14 * m * g);
            let c = full_terms::<3, _>(&model, 0, &q, &v);
            let exact = |a: f64, b: f64| (a - b).abs() <= 1e-15 * (1.0 + b.abs());
            prop_assert!(exact(c.h, q[2] - q[1].sin()));
            prop_assert!(exact(c.gradient[0], 0.0) && exact(c.gradient[2], 1.0));
            prop_assert!(exact(c.gradient[1], -q[1].cos()), "A[1] = {}", c.gradient[1]);
            prop_assert!(exact(c.a_q_dot, v[2] - q[1].cos() * v[1]));
            prop_assert!(
                (c.a_dot_q_dot - q[1].sin() * v[1] * v[1]).abs() <= 1e-14 * (1.0 + v[1] * v[1]),
                "Ȧ q̇ = {} but sin(x2) ẋ2² = {}", c.a_dot_q_dot, q[1].sin() * v[1] * v[1]
            );
            let e = 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + m * g * q[2];
            prop_assert!((energy(&model, 0.0, &q, &v) - e).abs() <= 1e-13 * (1.0 + e.abs()));
        }

        /// The energies in closed form, `T + V` (REFERENCE §3's Lagrangians).
        #[test]
        fn energies_closed_form(q in vec_in(-3.0..3.0, 2), v in vec_in(-3.0..3.0, 2)) {
            // Equal up to the rounding of a sum of terms, which cancel (the cart's energy is
            // −0.47 from terms of ±400): relative to the sum of their sizes.
            let close = |a: f64, terms: &[f64]| {
                let (sum, size) = (terms.iter().sum::<f64>(), terms.iter().map(|t| t.abs()).sum::<f64>());
                (a - sum).abs() <= 32.0 * f64::EPSILON * (1.0 + size)
            };
            let ball = BouncingBall::new(1.3, 9.81, 0.5);
            let e_ball = [0.5 * 1.3 * v[0] * v[0], 1.3 * 9.81 * q[0]];
            prop_assert!(close(energy(&ball, 0.0, &q[..1], &v[..1]), &e_ball));

            let cart = CartPendulum::demo().model;
            let (mc, mb, l, g) = (10.0, 5.0, 10.0, 9.8);
            let (th, thd, xd) = (q[0], v[0], v[1]);
            let e_cart = [
                0.5 * (mc + mb) * xd * xd,
                mb * l * th.cos() * xd * thd,
                0.5 * mb * l * l * thd * thd,
                mb * g * l * th.cos(),
            ];
            prop_assert!(close(energy(&cart, 0.0, &q, &v), &e_cart), "{} vs {:?}", energy(&cart, 0.0, &q, &v), e_cart);

            let sph = SphericalPendulum::demo().model;
            let e_sph = [
                0.5 * 100.0 * (thd * thd + th.sin().powi(2) * v[1] * v[1]),
                9.8 * 10.0 * th.cos(),
            ];
            prop_assert!(close(energy(&sph, 0.0, &q, &v), &e_sph), "{} vs {:?}", energy(&sph, 0.0, &q, &v), e_sph);
        }
    }
}
