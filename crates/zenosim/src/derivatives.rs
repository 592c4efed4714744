//! Exact derivatives of `L` and `h` by forward-mode automatic differentiation (num-dual).
//!
//! Every quantity the mechanics needs comes from one evaluation of `L` or `h` over a dual number
//! whose size is known at compile time (`N` = number of coordinates), so nothing allocates:
//! - `M = ∂²L/∂q̇²`: hyper-dual, both infinitesimal parts seeded on `q̇`;
//! - `(∂²L/∂q̇∂q) q̇`: hyper-dual, `ε₁` on `q̇`, `ε₂` the direction `q̇` in `q`;
//! - `∂L/∂q`: dual vector on `q`;
//! - `A = ∂h/∂q`, `A q̇` and `Ȧ q̇ = q̇ᵀ∇²h q̇`: hyper-dual, `ε₁` on `q`, `ε₂` the direction `q̇`;
//! - the energy `q̇ᵀ ∂L/∂q̇ − L`: a scalar dual in the direction `q̇` of `q̇`.
//!
//! The runtime dimension is mapped to `N` by [`with_dimension!`] (up to [`MAX_DIMENSION`]).

use crate::model::HybridLagrangian;
use nalgebra::{Const, SMatrix, SVector, U1};
use num_dual::{Derivative, Dual2, Dual64, DualVec, HyperDualVec};

/// The largest number of coordinates a model may have.
pub const MAX_DIMENSION: usize = 20;

/// Runs `$body` with `$N` a `const usize` equal to the runtime dimension `$n` (1..=20).
macro_rules! with_dimension {
    ($n:expr, $N:ident => $body:expr) => {
        match $n {
            1 => { const $N: usize = 1; $body }
            2 => { const $N: usize = 2; $body }
            3 => { const $N: usize = 3; $body }
            4 => { const $N: usize = 4; $body }
            5 => { const $N: usize = 5; $body }
            6 => { const $N: usize = 6; $body }
            7 => { const $N: usize = 7; $body }
            8 => { const $N: usize = 8; $body }
            9 => { const $N: usize = 9; $body }
            10 => { const $N: usize = 10; $body }
            11 => { const $N: usize = 11; $body }
            12 => { const $N: usize = 12; $body }
            13 => { const $N: usize = 13; $body }
            14 => { const $N: usize = 14; $body }
            15 => { const $N: usize = 15; $body }
            16 => { const $N: usize = 16; $body }
            17 => { const $N: usize = 17; $body }
            18 => { const $N: usize = 18; $body }
            19 => { const $N: usize = 19; $body }
            20 => { const $N: usize = 20; $body }
            other => unreachable!("dimension {other} was checked against MAX_DIMENSION at setup"),
        }
    };
}
pub(crate) use with_dimension;

/// The Lagrangian's terms at `(q, q̇)`: `M q̈ = force` is the Euler–Lagrange equation.
pub(crate) struct LagrangianTerms<const N: usize> {
    /// `M = ∂²L/∂q̇²`.
    pub mass: SMatrix<f64, N, N>,
    /// `∂L/∂q − (∂²L/∂q̇∂q) q̇`, i.e. `−(C q̇ + N)` for `L = ½ q̇ᵀMq̇ − V`.
    pub force: SVector<f64, N>,
}

/// One constraint's terms at `(q, q̇)`.
pub(crate) struct ConstraintTerms<const N: usize> {
    /// `h(q)`.
    pub h: f64,
    /// `A = ∂h/∂q` (as a column).
    pub gradient: SVector<f64, N>,
    /// `A q̇`.
    pub a_q_dot: f64,
    /// `Ȧ q̇ = q̇ᵀ ∇²h q̇`.
    pub a_dot_q_dot: f64,
}

fn constants<D: Copy, const N: usize>(x: &[f64], lift: impl Fn(f64) -> D) -> [D; N] {
    std::array::from_fn(|i| lift(x[i]))
}

/// `M = ∂²L/∂q̇²`.
pub(crate) fn mass_matrix<const N: usize, L: HybridLagrangian>(
    model: &L,
    q: &[f64],
    q_dot: &[f64],
) -> SMatrix<f64, N, N> {
    type Hd<const N: usize> = HyperDualVec<f64, Const<N>, Const<N>>;
    let q_d: [Hd<N>; N] = constants(q, Hd::<N>::from_re);
    let q_dot_d: [Hd<N>; N] = std::array::from_fn(|i| {
        let mut v = Hd::<N>::from_re(q_dot[i]);
        v.eps1 = Derivative::derivative_generic(Const::<N>, U1, i);
        v.eps2 = Derivative::derivative_generic(U1, Const::<N>, i);
        v
    });
    model
        .lagrangian(&q_d, &q_dot_d)
        .eps1eps2
        .unwrap_generic(Const::<N>, Const::<N>)
}

/// `M` and the Euler–Lagrange force `∂L/∂q − (∂²L/∂q̇∂q) q̇`.
pub(crate) fn lagrangian_terms<const N: usize, L: HybridLagrangian>(
    model: &L,
    q: &[f64],
    q_dot: &[f64],
) -> LagrangianTerms<N> {
    let mass = mass_matrix::<N, L>(model, q, q_dot);

    // (∂²L/∂q̇∂q) q̇: ε₁ on q̇, ε₂ along q̇ in q.
    type Mixed<const N: usize> = HyperDualVec<f64, Const<N>, U1>;
    let q_m: [Mixed<N>; N] = std::array::from_fn(|i| {
        let mut x = Mixed::<N>::from_re(q[i]);
        x.eps2 = Derivative::some(SMatrix::<f64, 1, 1>::new(q_dot[i]));
        x
    });
    let q_dot_m: [Mixed<N>; N] = std::array::from_fn(|i| {
        let mut v = Mixed::<N>::from_re(q_dot[i]);
        v.eps1 = Derivative::derivative_generic(Const::<N>, U1, i);
        v
    });
    let mixed = model
        .lagrangian(&q_m, &q_dot_m)
        .eps1eps2
        .unwrap_generic(Const::<N>, U1);

    // ∂L/∂q.
    type Grad<const N: usize> = DualVec<f64, Const<N>>;
    let q_g: [Grad<N>; N] = std::array::from_fn(|i| {
        let mut x = Grad::<N>::from_re(q[i]);
        x.eps = Derivative::derivative_generic(Const::<N>, U1, i);
        x
    });
    let q_dot_g: [Grad<N>; N] = constants(q_dot, Grad::<N>::from_re);
    let dl_dq = model
        .lagrangian(&q_g, &q_dot_g)
        .eps
        .unwrap_generic(Const::<N>, U1);

    LagrangianTerms {
        mass,
        force: dl_dq - mixed,
    }
}

/// `h`, `A`, `A q̇` and `Ȧ q̇` of constraint `index`.
pub(crate) fn constraint_terms<const N: usize, L: HybridLagrangian>(
    model: &L,
    index: usize,
    q: &[f64],
    q_dot: &[f64],
) -> ConstraintTerms<N> {
    type Hd<const N: usize> = HyperDualVec<f64, Const<N>, U1>;
    let q_d: [Hd<N>; N] = std::array::from_fn(|i| {
        let mut x = Hd::<N>::from_re(q[i]);
        x.eps1 = Derivative::derivative_generic(Const::<N>, U1, i);
        x.eps2 = Derivative::some(SMatrix::<f64, 1, 1>::new(q_dot[i]));
        x
    });
    let h = model.constraint(index, &q_d);
    let hessian_q_dot = h.eps1eps2.unwrap_generic(Const::<N>, U1);
    let v = SVector::<f64, N>::from_column_slice(&q_dot[..N]);
    ConstraintTerms {
        h: h.re,
        gradient: h.eps1.unwrap_generic(Const::<N>, U1),
        a_q_dot: h.eps2.unwrap_generic(U1, U1)[0],
        a_dot_q_dot: hessian_q_dot.dot(&v),
    }
}

/// `h`, `A q̇` and `Ȧ q̇` of constraint `index`, without the full gradient: the guard and its
/// first two time derivatives along free flight, in one scalar second-order pass (any `n`).
pub(crate) fn guard_along<L: HybridLagrangian>(
    model: &L,
    index: usize,
    q: &[f64],
    q_dot: &[f64],
) -> (f64, f64, f64) {
    let mut q_d = [Dual2::<f64>::from_re(0.0); MAX_DIMENSION];
    for ((x, &qi), &vi) in q_d.iter_mut().zip(q).zip(q_dot) {
        *x = Dual2::new(qi, vi, 0.0);
    }
    let h = model.constraint(index, &q_d[..q.len()]);
    (h.re, h.v1, h.v2)
}

/// The energy `q̇ᵀ ∂L/∂q̇ − L` (any `n`).
pub(crate) fn energy<L: HybridLagrangian>(model: &L, q: &[f64], q_dot: &[f64]) -> f64 {
    let mut q_d = [Dual64::from_re(0.0); MAX_DIMENSION];
    let mut v_d = [Dual64::from_re(0.0); MAX_DIMENSION];
    for (x, &qi) in q_d.iter_mut().zip(q) {
        *x = Dual64::from_re(qi);
    }
    for (v, &vi) in v_d.iter_mut().zip(q_dot) {
        *v = Dual64::new(vi, vi);
    }
    let n = q.len();
    let l = model.lagrangian(&q_d[..n], &v_d[..n]);
    l.eps - l.re
}
