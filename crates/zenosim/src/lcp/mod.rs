//! A small dense solver for the linear complementarity problem (LCP).
//!
//! # The problem
//!
//! Given a `k×k` matrix `m` and a vector `q` of length `k`, find `z` with
//!
//! ```text
//! z ≥ 0,   w = m z + q ≥ 0,   zᵢ wᵢ = 0 for every i.
//! ```
//!
//! In contact mechanics `m` is the Delassus matrix `W = A M⁻¹ Aᵀ` of the active constraints
//! (docs/contact-laws.md): symmetric positive definite when the constraint gradients are
//! independent (a P-matrix: exactly one solution for every `q`), positive semi-definite when they
//! are dependent (the same constraint twice, a table on four legs): then a solution may or may
//! not exist and need not be unique, but `w = m z + q` is the same for all of them.
//!
//! # Right-hand sides cleaned of round-off
//!
//! [`solve_rounded`] takes, with `q`, a bound on the rounding error of each entry (the caller
//! knows what each was computed from: a normal velocity `A q̇`, a free normal acceleration). An
//! entry no larger than its bound is not known to be either sign, and counts as 0: a contact
//! at rest to rounding is at rest. This makes the degenerate problems of resting contact
//! (entries `±10⁻⁴⁵` that are the remains of a cancellation) exactly degenerate, which the
//! methods below handle by their rules rather than by chance. [`solve`] takes `q` as exact.
//!
//! # The methods
//!
//! **Symmetric positive definite `m`** (its Cholesky factorisation runs through with every pivot
//! above `10⁻¹²` of its diagonal entry): the LCP is the strictly convex quadratic program
//! `min ½ zᵀ m z + qᵀ z` on `z ≥ 0`, solved by the primal active-set method of Lawson and Hanson's
//! NNLS (C. L. Lawson, R. J. Hanson, *Solving Least Squares Problems*, Prentice-Hall 1974,
//! chapter 23), written for a quadratic objective (module `active_set`). Each step solves a
//! principal subsystem `m_PP s_P = −q_P` by Cholesky; `z` stays `≥ 0` throughout. The method is
//! finite: the objective strictly decreases from one passive set to the next, so no passive set
//! recurs, and there are `2ᵏ` of them. No ratio is compared with another to decide a tie, so
//! degenerate problems (zeros, repeated and tiny entries in `q`) need no rule against cycling.
//! Rounding can only break the strict decrease where a step is at rounding level; the method
//! then meets a passive set it has already left, detects it (the sets are recorded) and stops
//! with its current `z ≥ 0`, which is returned if it passes the check below. So it is finite in
//! floating point too. Its signs are those of the exact problem wherever they are determined:
//! a `wᵢ` far below its terms is accumulated in twice the working precision (T. Ogita,
//! S. M. Rump, S. Oishi, "Accurate sum and dot product", SIAM J. Sci. Comput. 26 (2005)
//! 1955–1988), and where a first pass, which solves each subsystem by Cholesky alone, ends with
//! an answer that fails the check, a second one refines each solve with residuals so
//! accumulated.
//!
//! **Every other matrix** (positive semi-definite, nearly singular, not symmetric): Lemke's
//! complementary pivoting method (C. E. Lemke, "Bimatrix equilibrium points and mathematical
//! programming", Management Science 11 (1965) 681–689) with the lexicographic minimum-ratio rule
//! against cycling (R. W. Cottle, J.-S. Pang, R. E. Stone, *The Linear Complementarity Problem*,
//! Academic Press 1992, §4.4 and §4.9), module `lemke`. For a copositive-plus matrix, positive
//! semi-definite ones among them, Lemke's method ends either with a solution or on a secondary
//! ray; the ray proves that none exists. The solver does not take that on trust: it reads from
//! the ray a vector `y ≥ 0` with `mᵀy ≤ 0` and `qᵀy < 0` (Farkas: then no `z ≥ 0` has
//! `m z + q ≥ 0`, since `0 ≤ yᵀ(m z + q) = (mᵀy)ᵀz + qᵀy < 0`), and checks it against the data,
//! up to `10⁻¹⁰` of the terms of each product. Only a checked proof is reported as
//! [`LcpError::NoSolution`].
//!
//! If the first method's answer fails the check, the other one is tried (Lemke after the
//! active-set method; the active-set method after Lemke when `m`'s Cholesky factorisation runs
//! through at all); for `k ≤ 12` then every complementary basis is tried (module `bases`: a
//! matrix that is not copositive-plus, such as the contact problem with friction, can end
//! Lemke's method on a ray that proves nothing); if none gives an answer, the failure is the solver's,
//! [`LcpError::Failed`], and says how far from singular `m` is ([`Conditioning`]).
//!
//! # Numerics
//!
//! The solver first scales `m` and `q`, each by a power of two (exactly), so that their largest
//! entries lie in `[1, 2)`; all tolerances then apply to numbers of order one, and the answer does
//! not depend on the units of `m` and `q` (nothing overflows or underflows at `10¹⁵⁰` or
//! `10⁻¹⁵⁰`). Every answer is checked before it is returned, free of units: in every row
//! `−wᵢ ≤ 10⁻⁹ termsᵢ` and `min(zᵢ / ‖z‖∞, |wᵢ| / termsᵢ) ≤ 10⁻⁹`, with
//! `termsᵢ = |qᵢ| + Σⱼ |mᵢⱼ zⱼ|` the size of what `wᵢ` is computed from, plus an absolute
//! allowance of 2¹⁰ units of the smallest subnormal number (in `w` relative to the largest entry
//! of `q`, and in each `zⱼ`), since subnormal numbers carry fewer digits. The check is made
//! again on the answer in the data's units. An inaccurate answer is never returned. Matrices up
//! to `k ≈ 64` are meant; larger ones work, but slowly.

mod active_set;
mod bases;
mod check;
mod lemke;
mod refine;

#[cfg(test)]
mod random;
#[cfg(test)]
mod regressions;
#[cfg(test)]
mod tests;

use std::fmt;

pub(crate) use check::conditioning;
pub use check::is_solution;
use check::{proves_infeasible, ACCEPTANCE};

/// Why no solution was returned.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum LcpError {
    /// The problem has no solution, proven: Lemke's method ended on a secondary ray, and the ray
    /// gave a vector `y ≥ 0` with `mᵀy ≤ 0` and `qᵀy < 0` up to rounding (checked against the
    /// data), so that no `z ≥ 0` has `m z + q ≥ 0`. (Up to rounding: any solution would have to
    /// be some `10¹⁰` times larger than the problem's own scale.)
    #[error("the problem has no solution (proven by a secondary ray of Lemke's method: a y ≥ 0 with mᵀy ≤ 0 and qᵀy < 0)")]
    NoSolution,
    /// The solver found no answer that passes its accuracy check, and no proof that none
    /// exists: a failure of the solver, not a property of the problem.
    #[error("the LCP solver failed ({stop}) on a matrix that is {conditioning}")]
    Failed {
        /// How the solver's first method stopped.
        stop: Stop,
        /// How far from singular `m` is.
        conditioning: Conditioning,
    },
    /// `m`, `q` or a rounding bound has a NaN or infinite entry. Also returned, exceptionally,
    /// when the computation itself overflows (a solution too large for `f64`).
    #[error("the problem has a non-finite entry")]
    NonFinite,
}

/// How one of the solver's methods stopped without an answer that passed the check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Lemke's method ended on a secondary ray that proves nothing: the matrix is not
    /// copositive-plus, or the proof read from the ray did not check to rounding.
    Ray,
    /// A method took more steps than its limit.
    IterationLimit,
    /// A method ended with an answer that failed the accuracy check.
    Inaccurate,
    /// The active-set method met a passive set it had left (rounding broke its descent), and
    /// its answer there failed the check.
    Cycle,
    /// A principal submatrix was not positive definite to working precision.
    Breakdown,
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stop::Ray => "Lemke's method ended on a ray that proves nothing",
            Stop::IterationLimit => "the pivoting did not end within its limit",
            Stop::Inaccurate => "its answer failed the accuracy check",
            Stop::Cycle => "the active-set method came back to a set it had left",
            Stop::Breakdown => "a principal submatrix was singular to working precision",
        })
    }
}

/// How far from singular the matrix `m` is, read off its Cholesky factorisation
/// (`m = L Lᵀ`, pivots `dⱼ = Lⱼⱼ²`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Conditioning {
    /// `m` is symmetric and every pivot is positive: `pivot_ratio` is the smallest ratio of a
    /// pivot to its diagonal entry, `minⱼ dⱼ / mⱼⱼ` (1 for a diagonal matrix; about the inverse
    /// of the condition number of `m` scaled to a unit diagonal).
    PositiveDefinite {
        /// `minⱼ dⱼ / mⱼⱼ`, in `(0, 1]`.
        pivot_ratio: f64,
    },
    /// `m` is symmetric but the factorisation met a pivot that is not positive: singular or
    /// indefinite (for a Delassus matrix: gradients dependent to rounding).
    NotPositiveDefinite {
        /// That pivot over its diagonal entry (`−∞` where the diagonal entry is not positive).
        pivot_ratio: f64,
    },
    /// `m` is not symmetric.
    Nonsymmetric,
}

impl Conditioning {
    /// Whether the active-set method is the first one tried: positive definite with every
    /// pivot above [`CLEAR_PIVOT`] of its diagonal entry.
    fn clearly_positive_definite(self) -> bool {
        matches!(self, Conditioning::PositiveDefinite { pivot_ratio } if pivot_ratio > CLEAR_PIVOT)
    }
}

impl fmt::Display for Conditioning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Conditioning::PositiveDefinite { pivot_ratio } => write!(
                f,
                "positive definite, its smallest Cholesky pivot {pivot_ratio:.1e} of its diagonal \
                 entry (conditioned to about {:.0e})",
                1.0 / pivot_ratio
            ),
            Conditioning::NotPositiveDefinite { pivot_ratio } if pivot_ratio.is_finite() => write!(
                f,
                "not positive definite (a Cholesky pivot of {pivot_ratio:.1e} of its diagonal \
                 entry)"
            ),
            Conditioning::NotPositiveDefinite { .. } => {
                f.write_str("not positive definite (a diagonal entry is not positive)")
            }
            Conditioning::Nonsymmetric => f.write_str("not symmetric"),
        }
    }
}

/// A solution: z and w = m z + q.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// `z ≥ 0`, complementary to `w`.
    pub z: Vec<f64>,
    /// `w = m z + q ≥ 0`, recomputed from the data with the returned `z` (with `q` cleaned of
    /// its round-off, for [`solve_rounded`]).
    pub w: Vec<f64>,
}

/// How many pivots of Lemke's method, per `(k+1)²`, a pass may take.
const ITERATIONS_PER_SQUARE: usize = 50;

/// A positive definite `m` whose Cholesky pivots all exceed this fraction of their diagonal
/// entries goes to the active-set method first (docs/contact-laws.md, "Degenerate sets": the
/// same bound tells independent constraints from nearly dependent ones).
const CLEAR_PIVOT: f64 = 1e-12;

/// Solves the LCP `0 ≤ z ⊥ m z + q ≥ 0`, with `q` taken as exact. See [`solve_rounded`], which
/// this is with rounding bounds 0, and the [module](self) documentation.
///
/// # Errors
///
/// As [`solve_rounded`].
///
/// # Panics
///
/// If `m.len() != q.len()²`.
///
/// # Example
///
/// ```
/// use zenosim::lcp::solve;
/// // Two balls in contact, the first struck: the impulses of Newton's cradle.
/// let s = solve(&[2.0, -1.0, -1.0, 2.0], &[-2.0, 0.0]).unwrap();
/// assert!((s.z[0] - 4.0 / 3.0).abs() < 1e-12 && (s.z[1] - 2.0 / 3.0).abs() < 1e-12);
/// ```
pub fn solve(m: &[f64], q: &[f64]) -> Result<Solution, LcpError> {
    solve_with_limit(m, q, None, lemke_limit(q.len()))
}

/// Solves the LCP `0 ≤ z ⊥ m z + q ≥ 0` where `qᵢ` is known to within `round_off[i]`: an entry
/// with `|qᵢ| ≤ round_off[i]` counts as 0 (a negative bound cleans nothing), and the returned
/// `w` is `m z` plus `q` so cleaned. `q ≥ 0` (after cleaning) returns `z = 0` at once.
///
/// `m` is the `k×k` matrix, row-major (`m[i*k + j]`), `q` and `round_off` have length `k`;
/// `k = 0` is allowed. The result is deterministic; memory is `O(k²)`.
///
/// # Errors
///
/// - [`LcpError::NonFinite`] if an entry of `m`, `q` or `round_off` is NaN or infinite;
/// - [`LcpError::NoSolution`] if the problem is proven to have no solution (see the
///   [module](self) documentation);
/// - [`LcpError::Failed`] if the solver found neither a solution that passes its accuracy
///   check nor such a proof.
///
/// # Panics
///
/// If `m.len() != q.len()²` or `round_off.len() != q.len()` (a programming error).
pub fn solve_rounded(m: &[f64], q: &[f64], round_off: &[f64]) -> Result<Solution, LcpError> {
    solve_with_limit(m, q, Some(round_off), lemke_limit(q.len()))
}

/// `50 (k+1)²`, saturating.
fn lemke_limit(k: usize) -> usize {
    ITERATIONS_PER_SQUARE.saturating_mul((k + 1).saturating_mul(k + 1))
}

/// [`solve_rounded`] with a given limit on the number of pivots of Lemke's method (after its
/// first); the active-set method takes at most `4 (k+1)²` steps.
fn solve_with_limit(
    m: &[f64],
    q: &[f64],
    round_off: Option<&[f64]>,
    limit: usize,
) -> Result<Solution, LcpError> {
    let k = q.len();
    assert!(
        k.checked_mul(k) == Some(m.len()) && round_off.is_none_or(|r| r.len() == k),
        "lcp::solve: m has {} entries, q {} and round_off {:?} (m must be k×k for q and \
         round_off of length k)",
        m.len(),
        k,
        round_off.map(<[f64]>::len)
    );
    let bounds = round_off.unwrap_or_default();
    if !m.iter().chain(q).chain(bounds).all(|x| x.is_finite()) {
        return Err(LcpError::NonFinite);
    }
    let q: Vec<f64> = match round_off {
        None => q.to_vec(),
        Some(bounds) => q
            .iter()
            .zip(bounds)
            .map(|(&x, &r)| if x.abs() <= r { 0.0 } else { x })
            .collect(),
    };
    if q.iter().all(|&x| x >= 0.0) {
        return Ok(Solution {
            z: vec![0.0; k],
            w: q,
        });
    }
    // m̃ = 2^−em m and q̃ = 2^−eq q; a solution z̃ of (m̃, q̃) gives z = 2^(eq−em) z̃ and
    // w = 2^eq w̃. Scaling by powers of two is exact (but for numbers it takes below the
    // normal range, of which only the digits of a subnormal number are kept).
    let em = magnitude_exponent(m);
    let eq = magnitude_exponent(&q);
    let ms: Vec<f64> = m.iter().map(|&x| mul_pow2(x, -em)).collect();
    let qs: Vec<f64> = q.iter().map(|&x| mul_pow2(x, -eq)).collect();
    let conditioning = conditioning(&ms, k);
    // The answer in the data's units, checked again there (scaling it back rounds what falls
    // below the normal range): `None` if it fails.
    let allowance = mul_pow2(check::UNDERFLOW, eq);
    let unscale = |zs: Vec<f64>| -> Result<Option<Solution>, LcpError> {
        let z: Vec<f64> = zs.iter().map(|&x| mul_pow2(x, eq - em)).collect();
        let w = check::affine(m, &q, &z);
        if !z.iter().chain(&w).all(|x| x.is_finite()) {
            return Err(LcpError::NonFinite);
        }
        let worst = check::violation_with(m, &q, &z, &w, allowance);
        if worst <= ACCEPTANCE {
            return Ok(Some(Solution { z, w }));
        }
        // Refined on its support, each row may meet the check (module `refine`).
        let (z, _) = refine::refine(m, &q, z);
        let w = check::affine(m, &q, &z);
        let worst = check::violation_with(m, &q, &z, &w, allowance);
        Ok(
            (worst <= ACCEPTANCE && z.iter().chain(&w).all(|x| x.is_finite()))
                .then_some(Solution { z, w }),
        )
    };
    let mut first_stop = None;
    let mut active_set_tried = false;
    if conditioning.clearly_positive_definite() {
        active_set_tried = true;
        match active_set::solve(&ms, &qs) {
            Ok(zs) => match unscale(zs)? {
                Some(solution) => return Ok(solution),
                None => first_stop = Some(Stop::Inaccurate),
            },
            Err(stop) => first_stop = Some(stop),
        }
    }
    for pivot_tolerance in lemke::PIVOT_TOLERANCES {
        let stop = match lemke::solve(&ms, &qs, limit, pivot_tolerance) {
            Ok(lemke::End::Complementary(zs)) => {
                // (Checked, and refined where the check asks for it, in the data's units.)
                let (zs, _) = lemke::polish(&ms, &qs, zs);
                if let Some(solution) = unscale(zs)? {
                    return Ok(solution);
                }
                Stop::Inaccurate
            }
            Ok(lemke::End::Ray(y)) => {
                if proves_infeasible(&ms, &qs, &y) {
                    return Err(LcpError::NoSolution);
                }
                Stop::Ray
            }
            Err(lemke::Breakdown::IterationLimit) => Stop::IterationLimit,
            Err(lemke::Breakdown::NonFinite) => return Err(LcpError::NonFinite),
        };
        first_stop.get_or_insert(stop);
    }
    if !active_set_tried && matches!(conditioning, Conditioning::PositiveDefinite { .. }) {
        let stop = match active_set::solve(&ms, &qs) {
            Ok(zs) => match unscale(zs)? {
                Some(solution) => return Ok(solution),
                None => Stop::Inaccurate,
            },
            Err(stop) => stop,
        };
        first_stop.get_or_insert(stop);
    }
    // The last resort for small problems: every complementary basis (module `bases`), where
    // their number is within the limit on the pivots.
    let enumerable = k <= bases::MAX_SIZE && (1usize << k) <= limit;
    if let Some((zs, _)) = enumerable.then(|| bases::solve(&ms, &qs)).flatten() {
        if let Some(solution) = unscale(zs)? {
            return Ok(solution);
        }
    }
    Err(LcpError::Failed {
        stop: first_stop.unwrap_or(Stop::Inaccurate),
        conditioning,
    })
}

/// The exponent `e` with `2^e ≤ maxᵢ |xᵢ| < 2^(e+1)`; 0 if all entries are 0. Entries finite.
fn magnitude_exponent(x: &[f64]) -> i32 {
    let largest = x.iter().fold(0.0_f64, |acc, v| acc.max(v.abs()));
    if largest > 0.0 {
        exponent(largest)
    } else {
        0
    }
}

/// The binary exponent of a positive finite `x`: `2^e ≤ x < 2^(e+1)`.
fn exponent(x: f64) -> i32 {
    if x < f64::MIN_POSITIVE {
        // Subnormal: bring it into the normal range first (exactly).
        return exponent(x * pow2(64)) - 64;
    }
    // The biased exponent has 11 bits: the cast cannot truncate.
    ((x.to_bits() >> 52) & 0x7ff) as i32 - 1023
}

/// `2^e` for `e` in the normal range `−1022..=1023`.
fn pow2(e: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&e));
    // `e + 1023` lies in 1..=2046 here: the biased exponent of a normal number.
    f64::from_bits(u64::from((e + 1023).unsigned_abs()) << 52)
}

/// `x · 2^e`, in steps that neither overflow nor underflow on the way.
fn mul_pow2(mut x: f64, mut e: i32) -> f64 {
    while e > 1000 {
        x *= pow2(1000);
        e -= 1000;
    }
    while e < -1000 {
        x *= pow2(-1000);
        e += 1000;
    }
    x * pow2(e)
}
