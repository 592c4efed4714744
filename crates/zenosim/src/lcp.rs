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
//! In contact mechanics `m` is the Delassus matrix `W = A M⁻¹ Aᵀ` of the active constraints:
//! symmetric positive definite when the constraint gradients are independent (a P-matrix: exactly
//! one solution for every `q`), positive semi-definite when they are dependent (the same
//! constraint twice, say): then a solution may or may not exist and need not be unique, but
//! `w = m z + q` is the same for all of them.
//!
//! # The method
//!
//! Lemke's complementary pivoting method (C. E. Lemke, "Bimatrix equilibrium points and
//! mathematical programming", Management Science 11 (1965) 681–689), with an auxiliary variable
//! `z₀` and the covering vector `e = (1, …, 1)`: the system
//!
//! ```text
//! w − m z − e z₀ = q,   w, z, z₀ ≥ 0,   zᵢ wᵢ = 0,
//! ```
//!
//! starts from the basis `w` with `z₀ = −minᵢ qᵢ` and follows, one pivot at a time, the path of
//! almost-complementary bases (the variable that enters is always the complement of the one that
//! has just left) until `z₀` leaves the basis (a solution) or the entering column has no positive
//! entry (a secondary ray). For matrices that are copositive-plus, positive semi-definite ones
//! among them, a secondary ray proves that the problem has no solution; for P-matrices it cannot
//! occur.
//!
//! The leaving variable is chosen by the lexicographic minimum-ratio rule (R. W. Cottle,
//! J.-S. Pang, R. E. Stone, "The Linear Complementarity Problem", Academic Press, 1992, §4.4 and
//! §4.9): among the rows that tie in the ordinary ratio `q̄ᵢ / d̄ᵢ`, the one whose row of the
//! inverse basis, `(B⁻¹)ᵢ· / d̄ᵢ`, is lexicographically smallest. The rows of `B⁻¹` are
//! independent, so the choice is unique: this is the pivoting of the problem with `q` perturbed
//! by `(ε, ε², …, εᵏ)`, which is nondegenerate, so degenerate problems (`q` with zeros, repeated
//! constraints) cannot cycle. When `z₀`'s row is among the ties it is taken (that ends the
//! pivoting at once). The tableau is dense and holds `B⁻¹` in the columns of `w`; it takes
//! `O(k²)` memory, a pivot `O(k²)` operations.
//!
//! # Numerics
//!
//! The solver first scales `m` and `q`, each by a power of two (exactly), so that their largest
//! entries lie in `[1, 2)`; all tolerances then apply to numbers of order one, and the answer does
//! not depend on the units of `m` and `q` (nothing overflows or underflows at `10¹⁵⁰` or
//! `10⁻¹⁵⁰`). Every tolerance is relative to the size of the terms a number is computed from:
//! a pivot must stand out of the round-off of its column, ratios tie when they agree up to the
//! round-off of the basic variables they move (rank-deficient matrices make exact ties that
//! round-off would otherwise break at random).
//!
//! After the pivoting, negative round-off in `z` is set to 0 and `w = m z + q` is recomputed from
//! the data; then `m_SS z_S = −q_S` is solved once on the support `S = {i : zᵢ > 0}` by Gaussian
//! elimination with partial pivoting, and that refined `z` is kept if it is at least as good. The
//! answer is returned only if it passes a check free of units (`w ≥ 0` and `zᵢ wᵢ = 0` to `10⁻⁹`
//! of the terms of `m z + q`); if not, or if the pivoting failed, Lemke's method runs once more,
//! treating as zero the pivots below `10⁻⁸` of their column instead of `10⁻¹²` (constraints that
//! are dependent to that precision are then taken as dependent). A problem that is solvable but
//! so ill-conditioned that neither pass yields an answer that passes the check (in tests:
//! constraints that coincide to between `10⁻⁶` and `10⁻⁹`, a few in `10⁵` such cases) is reported
//! as [`LcpError::Unsolvable`]: an inaccurate answer is never returned. Matrices up to `k ≈ 64`
//! are meant; larger ones work, but slowly.

/// Why no solution was returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LcpError {
    /// Lemke's method ended on a secondary ray: the entering column had no positive entry. For a
    /// positive semi-definite (more generally copositive-plus) matrix this proves that the problem
    /// has no solution; for other matrices it may have one that the method cannot reach. Also
    /// returned, rarely, when the pivoting ended with an answer that is not a solution to the
    /// accuracy required (`10⁻⁹` relative): a matrix so ill-conditioned (nearly dependent
    /// constraints) that the digits were lost.
    #[error("the problem has no solution (Lemke's method ended on a secondary ray)")]
    Unsolvable,
    /// The pivoting took more than `50 (k+1)²` pivots (it does not cycle, but Lemke's method can
    /// take exponentially many pivots on contrived matrices).
    #[error("the pivoting did not end within its limit")]
    IterationLimit,
    /// `m` or `q` has a NaN or infinite entry. Also returned, exceptionally, when the computation
    /// itself overflows (a solution too large for `f64`).
    #[error("the problem has a non-finite entry")]
    NonFinite,
}

/// A solution: z and w = m z + q.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// `z ≥ 0`, complementary to `w`.
    pub z: Vec<f64>,
    /// `w = m z + q ≥ 0`, recomputed from the data with the returned `z`.
    pub w: Vec<f64>,
}

/// How many pivots, per `(k+1)²`, the pivoting may take.
const ITERATIONS_PER_SQUARE: usize = 50;

/// An entry `d̄ᵢ` of the entering column is a pivot candidate when it exceeds a tolerance times
/// the size of what it was computed from, `‖(B⁻¹)ᵢ·‖₁ ‖aₑ‖∞` (`aₑ` the entering column of the
/// original tableau). The first pass takes `1e-12` (about `4500 ε`: room for the round-off of
/// many pivots, far below the pivots of a reasonably conditioned matrix). If its answer fails
/// [`ACCEPTANCE`] (constraints dependent up to `~1e-10`, whose pivots are tiny but not round-off,
/// leave a basis too ill-conditioned to keep the digits) or it ends without one, a second pass
/// takes `1e-8`: constraints dependent to that precision are then treated as dependent.
const PIVOT_TOLERANCES: [f64; 2] = [1e-12, 1e-8];

/// An answer is accepted when, in every row, `−wᵢ` and `min(zᵢ / ‖z‖∞, |wᵢ| / termsᵢ)` are at most
/// this, `termsᵢ = |qᵢ| + Σⱼ |mᵢⱼ zⱼ|` (nonnegativity of `w` and complementarity, relative to the
/// size of what `w` is computed from; free of units). Answers of the support system after a
/// correct pivoting meet it with a margin of several orders.
const ACCEPTANCE: f64 = 1e-9;

/// The round-off of a basic variable `b̄ⱼ − θ d̄ⱼ` is taken as this times the size of what it is
/// computed from, `‖(B⁻¹)ⱼ·‖₁ (‖q‖∞ + |θ| ‖aₑ‖∞)`, in the scaled units. A pivot row whose ratio
/// leaves every other basic variable above minus its round-off ties with the minimum ratio; the
/// ties are resolved lexicographically (with `z₀` first). Rank-deficient matrices make exact
/// ties whose computed ratios differ far more than the ratios' size suggests (small `d̄ⱼ` from
/// cancellation); `z₀` at or below its round-off on a secondary ray counts as 0.
const VALUE_TOLERANCE: f64 = 1e-11;

/// Two components in the lexicographic comparison are equal when they differ by less than this
/// times the largest component of the two rows compared.
const LEX_TOLERANCE: f64 = 1e-12;

/// A pivot of the support system smaller than this times `n · maxᵢⱼ |aᵢⱼ|` counts as singular
/// (the refinement is then skipped: the support matrix of a semi-definite problem may be
/// singular).
const SINGULAR_TOLERANCE: f64 = 1e3 * f64::EPSILON;

/// Solves the LCP by Lemke's complementary pivoting method with the covering vector e = (1,…,1)
/// and a lexicographic minimum-ratio rule (so that degenerate problems do not cycle).
/// `q ≥ 0` returns z = 0 at once. Length mismatches panic (a programming error).
///
/// `m` is the `k×k` matrix, row-major (`m[i*k + j]`), `q` has length `k`; `k = 0` is allowed.
/// The result is deterministic; memory is `O(k²)`.
///
/// # Errors
///
/// - [`LcpError::NonFinite`] if an entry of `m` or `q` is NaN or infinite;
/// - [`LcpError::Unsolvable`] if the pivoting ends on a secondary ray (for a positive
///   semi-definite `m`: the problem has no solution), or, rarely, with an answer that fails the
///   accuracy check (see the [module](self) documentation);
/// - [`LcpError::IterationLimit`] if it takes more than `50 (k+1)²` pivots (in each of its at
///   most two passes).
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
    let k = q.len();
    let limit = ITERATIONS_PER_SQUARE.saturating_mul((k + 1).saturating_mul(k + 1));
    solve_with_limit(m, q, limit)
}

/// Whether (z, w) solves the LCP (m, q) within `tol`: z ≥ −tol, w ≥ −tol, |zᵢ wᵢ| ≤ tol, and
/// |w − (m z + q)| ≤ tol·(1 + scale) componentwise, with scale from the magnitudes of the terms.
///
/// The scale of row `i` is `|qᵢ| + Σⱼ |mᵢⱼ zⱼ|`. The first three tests are absolute: they are in
/// the units of `z`, `w` and `z w`. Lengths that do not fit together (`m.len() != k²`, or `z`,
/// `w` not of length `k = q.len()`), a NaN anywhere, or sums that overflow give `false`.
pub fn is_solution(m: &[f64], q: &[f64], z: &[f64], w: &[f64], tol: f64) -> bool {
    let k = q.len();
    if k.checked_mul(k) != Some(m.len()) || z.len() != k || w.len() != k {
        return false;
    }
    for i in 0..k {
        let (zi, wi) = (z[i], w[i]);
        if !(zi >= -tol && wi >= -tol && (zi * wi).abs() <= tol) {
            return false;
        }
        let mut sum = q[i];
        let mut scale = q[i].abs();
        for (mij, zj) in m[i * k..(i + 1) * k].iter().zip(z) {
            let term = mij * zj;
            sum += term;
            scale += term.abs();
        }
        let residual = (wi - sum).abs();
        if !(residual.is_finite() && scale.is_finite() && residual <= tol * (1.0 + scale)) {
            return false;
        }
    }
    true
}

/// [`solve`] with a given limit on the number of pivots after the first.
fn solve_with_limit(m: &[f64], q: &[f64], limit: usize) -> Result<Solution, LcpError> {
    let k = q.len();
    assert!(
        k.checked_mul(k) == Some(m.len()),
        "lcp::solve: m has {} entries but q has {} (m must be k×k for q of length k)",
        m.len(),
        k
    );
    if !m.iter().chain(q).all(|x| x.is_finite()) {
        return Err(LcpError::NonFinite);
    }
    if q.iter().all(|&x| x >= 0.0) {
        return Ok(Solution {
            z: vec![0.0; k],
            w: q.to_vec(),
        });
    }
    // m̃ = 2^−em m and q̃ = 2^−eq q; a solution z̃ of (m̃, q̃) gives z = 2^(eq−em) z̃ and
    // w = 2^eq w̃. Scaling by powers of two is exact, so w̃ recomputed from m̃, q̃ and z̃ is
    // m z + q recomputed from the data, scaled.
    let em = magnitude_exponent(m);
    let eq = magnitude_exponent(q);
    let ms: Vec<f64> = m.iter().map(|&x| mul_pow2(x, -em)).collect();
    let qs: Vec<f64> = q.iter().map(|&x| mul_pow2(x, -eq)).collect();
    let mut first_error = None;
    for pivot_tolerance in PIVOT_TOLERANCES {
        let error = match lemke(&ms, &qs, limit, pivot_tolerance) {
            Ok(zs) => {
                let (zs, ws, violation) = polish(&ms, &qs, zs);
                if violation <= ACCEPTANCE {
                    let z: Vec<f64> = zs.iter().map(|&x| mul_pow2(x, eq - em)).collect();
                    let w: Vec<f64> = ws.iter().map(|&x| mul_pow2(x, eq)).collect();
                    if !z.iter().chain(&w).all(|x| x.is_finite()) {
                        return Err(LcpError::NonFinite);
                    }
                    return Ok(Solution { z, w });
                }
                LcpError::Unsolvable
            }
            Err(error) => error,
        };
        first_error.get_or_insert(error);
    }
    Err(first_error.unwrap_or(LcpError::Unsolvable))
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

/// `m z + q`.
fn affine(m: &[f64], q: &[f64], z: &[f64]) -> Vec<f64> {
    let k = q.len();
    (0..k)
        .map(|i| {
            m[i * k..(i + 1) * k]
                .iter()
                .zip(z)
                .fold(q[i], |acc, (mij, zj)| acc + mij * zj)
        })
        .collect()
}

/// Lemke's method on the scaled problem; returns `z` (with possible round-off below 0), to be
/// checked. `pivot_tolerance` is one of [`PIVOT_TOLERANCES`].
///
/// The tableau has `k` rows and the columns `w₀…w_{k−1}`, `z₀…z_{k−1}`, the auxiliary variable
/// and the right-hand side; it starts as `[I | −m | −e | q]` and always equals `B⁻¹ [I | −m | −e
/// | q]`, so its `w` columns hold `B⁻¹`.
fn lemke(m: &[f64], q: &[f64], limit: usize, pivot_tolerance: f64) -> Result<Vec<f64>, LcpError> {
    let k = q.len();
    let width = 2 * k + 2;
    let aux = 2 * k;
    let rhs = 2 * k + 1;
    let mut t = vec![0.0; k * width];
    for (i, row) in t.chunks_exact_mut(width).enumerate() {
        row[i] = 1.0;
        for (entry, mij) in row[k..2 * k].iter_mut().zip(&m[i * k..(i + 1) * k]) {
            *entry = -mij;
        }
        row[aux] = -1.0;
        row[rhs] = q[i];
    }
    // ‖aₑ‖∞ for the z columns of the original tableau (the others are columns of I or −e).
    let column_norms: Vec<f64> = (0..k)
        .map(|j| (0..k).fold(0.0_f64, |acc, i| acc.max(m[i * k + j].abs())))
        .collect();
    let mut basis: Vec<usize> = (0..k).collect();
    let mut pivot_row = vec![0.0; width];
    let mut candidates: Vec<(usize, f64)> = Vec::with_capacity(k);
    let mut ties: Vec<usize> = Vec::with_capacity(k);
    let mut inverse_norms = vec![0.0; k];
    let q_norm = q.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()));

    // The auxiliary variable enters at the most negative qᵢ; among equal ones the
    // lexicographic rule (rows (qᵢ, eᵢ)) takes the last.
    let mut first = 0;
    for i in 1..k {
        if q[i] <= q[first] {
            first = i;
        }
    }
    pivot(&mut t, width, first, aux, &mut pivot_row);
    let mut entering = complement(basis[first], k);
    basis[first] = aux;

    for _ in 0..limit {
        let column_norm = if (k..2 * k).contains(&entering) {
            column_norms[entering - k]
        } else {
            1.0
        };
        // The candidates d̄ᵢ > 0, and the row of the minimum ratio θ.
        candidates.clear();
        let mut smallest: Option<(usize, f64)> = None;
        for (i, row) in t.chunks_exact(width).enumerate() {
            let d = row[entering];
            if !(d.is_finite() && row[rhs].is_finite()) {
                return Err(LcpError::NonFinite);
            }
            inverse_norms[i] = row[..k].iter().map(|x| x.abs()).sum();
            if d > pivot_tolerance * inverse_norms[i] * column_norm {
                let ratio = row[rhs] / d;
                candidates.push((i, ratio));
                if smallest.is_none_or(|(_, theta)| ratio < theta) {
                    smallest = Some((i, ratio));
                }
            }
        }
        let Some((smallest_row, _)) = smallest else {
            // A secondary ray. If z₀ is 0 up to round-off here, the basis is complementary
            // after all: a solution (checked, like every answer, by the caller).
            let r = aux_row(&basis, aux);
            if t[r * width + rhs] <= VALUE_TOLERANCE * inverse_norms[r] * q_norm {
                return Ok(basic_z(&t, width, &basis, k));
            }
            return Err(LcpError::Unsolvable);
        };
        // The ties: rows whose ratio θᵢ leaves every candidate's basic variable
        // b̄ⱼ − θᵢ d̄ⱼ ≥ 0 up to its round-off (exactly the rows of the minimum ratio, in exact
        // arithmetic). The rows of the minimum ratio are always among them.
        ties.clear();
        for &(i, theta) in &candidates {
            let feasible = candidates.iter().all(|&(j, _)| {
                let row = &t[j * width..(j + 1) * width];
                let noise =
                    VALUE_TOLERANCE * inverse_norms[j] * (q_norm + theta.abs() * column_norm);
                row[rhs] - theta * row[entering] >= -noise
            });
            if feasible || i == smallest_row {
                ties.push(i);
            }
        }
        let leave = match ties.iter().find(|&&i| basis[i] == aux) {
            Some(&i) => i,
            None => {
                let mut best = ties[0];
                for &i in &ties[1..] {
                    if lex_less(&t, width, k, entering, i, best) {
                        best = i;
                    }
                }
                best
            }
        };
        pivot(&mut t, width, leave, entering, &mut pivot_row);
        let leaving = std::mem::replace(&mut basis[leave], entering);
        if leaving == aux {
            return Ok(basic_z(&t, width, &basis, k));
        }
        entering = complement(leaving, k);
    }
    Err(LcpError::IterationLimit)
}

/// The row of the auxiliary variable `aux`, which is basic.
fn aux_row(basis: &[usize], aux: usize) -> usize {
    basis.iter().position(|&v| v == aux).unwrap_or(0)
}

/// The `z` of the basic solution: `zⱼ` from its row where basic, 0 where not.
fn basic_z(t: &[f64], width: usize, basis: &[usize], k: usize) -> Vec<f64> {
    let mut z = vec![0.0; k];
    for (row, &variable) in t.chunks_exact(width).zip(basis) {
        if (k..2 * k).contains(&variable) {
            z[variable - k] = row[width - 1];
        }
    }
    z
}

/// The complement of variable `v` (`wⱼ ↔ zⱼ`).
fn complement(v: usize, k: usize) -> usize {
    if v < k {
        v + k
    } else {
        v - k
    }
}

/// Whether row `a`'s `(B⁻¹)_a· / d̄_a` is lexicographically smaller than row `b`'s, `d̄` the
/// column `entering` (positive in both rows).
fn lex_less(t: &[f64], width: usize, k: usize, entering: usize, a: usize, b: usize) -> bool {
    let (ra, rb) = (
        &t[a * width..(a + 1) * width],
        &t[b * width..(b + 1) * width],
    );
    let (da, db) = (ra[entering], rb[entering]);
    let scale = ra[..k]
        .iter()
        .map(|x| (x / da).abs())
        .chain(rb[..k].iter().map(|x| (x / db).abs()))
        .fold(0.0_f64, f64::max);
    for j in 0..k {
        let (x, y) = (ra[j] / da, rb[j] / db);
        if (x - y).abs() > LEX_TOLERANCE * scale {
            return x < y;
        }
    }
    false
}

/// Pivots the tableau on `(r, c)`: row `r` divided by the pivot, column `c` eliminated from the
/// others. `buffer` holds a copy of the pivot row (length `width`).
fn pivot(t: &mut [f64], width: usize, r: usize, c: usize, buffer: &mut [f64]) {
    let p = t[r * width + c];
    for (b, x) in buffer.iter_mut().zip(&t[r * width..(r + 1) * width]) {
        *b = x / p;
    }
    buffer[c] = 1.0;
    for (i, row) in t.chunks_exact_mut(width).enumerate() {
        if i == r {
            row.copy_from_slice(buffer);
            continue;
        }
        let f = row[c];
        if f != 0.0 {
            for (x, b) in row.iter_mut().zip(buffer.iter()) {
                *x -= f * b;
            }
        }
        row[c] = 0.0;
    }
}

/// Cleans Lemke's `z` (negative round-off set to 0) and refines it once on its support; returns
/// the better of the two (by [`violation`]), its `w = m z + q`, and its violation.
fn polish(m: &[f64], q: &[f64], mut z: Vec<f64>) -> (Vec<f64>, Vec<f64>, f64) {
    for x in &mut z {
        if *x < 0.0 {
            *x = 0.0;
        }
    }
    let w = affine(m, q, &z);
    let base = violation(m, q, &z, &w);
    if let Some(refined) = support_solve(m, q, &z) {
        let refined_w = affine(m, q, &refined);
        let refined_violation = violation(m, q, &refined, &refined_w);
        if refined_violation <= base {
            return (refined, refined_w, refined_violation);
        }
    }
    (z, w, base)
}

/// How far `(z ≥ 0, w = m z + q)` is from a solution, free of units: the largest over the rows
/// of `(−wᵢ)⁺ / termsᵢ` and `min(zᵢ / ‖z‖∞, |wᵢ| / termsᵢ)`, `termsᵢ = |qᵢ| + Σⱼ |mᵢⱼ zⱼ|`
/// (a row whose terms are all 0 has `wᵢ = 0`); infinite if anything is not finite.
fn violation(m: &[f64], q: &[f64], z: &[f64], w: &[f64]) -> f64 {
    let k = q.len();
    let z_norm = z.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()));
    let mut worst = 0.0_f64;
    for i in 0..k {
        let terms = m[i * k..(i + 1) * k]
            .iter()
            .zip(z)
            .fold(q[i].abs(), |acc, (mij, zj)| acc + (mij * zj).abs());
        if !(terms.is_finite() && w[i].is_finite() && z[i].is_finite()) {
            return f64::INFINITY;
        }
        if terms == 0.0 {
            continue;
        }
        let negative = (-w[i]).max(0.0) / terms;
        let complementary = if z_norm > 0.0 {
            (z[i] / z_norm).min(w[i].abs() / terms)
        } else {
            0.0
        };
        worst = worst.max(negative).max(complementary);
    }
    worst
}

/// The solution of `m_SS z_S = −q_S` on `S = {i : zᵢ > 0}`, 0 elsewhere, negative entries set
/// to 0; `None` if `S` is empty or `m_SS` is singular to working precision.
fn support_solve(m: &[f64], q: &[f64], z: &[f64]) -> Option<Vec<f64>> {
    let k = q.len();
    let support: Vec<usize> = (0..k).filter(|&i| z[i] > 0.0).collect();
    let n = support.len();
    if n == 0 {
        return None;
    }
    let mut a = vec![0.0; n * n];
    let mut b = vec![0.0; n];
    for (r, &i) in support.iter().enumerate() {
        for (c, &j) in support.iter().enumerate() {
            a[r * n + c] = m[i * k + j];
        }
        b[r] = -q[i];
    }
    gauss_solve(&mut a, &mut b, n)?;
    let mut refined = vec![0.0; k];
    for (&i, &x) in support.iter().zip(&b) {
        if !x.is_finite() {
            return None;
        }
        refined[i] = x.max(0.0);
    }
    Some(refined)
}

/// Solves `a x = b` (`a` is `n×n`, row-major) in place by Gaussian elimination with partial
/// pivoting; `b` becomes `x`. `None` if a pivot is below [`SINGULAR_TOLERANCE`]` · n · max|a|`.
fn gauss_solve(a: &mut [f64], b: &mut [f64], n: usize) -> Option<()> {
    let largest = a.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()));
    let tiny = SINGULAR_TOLERANCE * n as f64 * largest;
    for c in 0..n {
        let mut p = c;
        for i in c + 1..n {
            if a[i * n + c].abs() > a[p * n + c].abs() {
                p = i;
            }
        }
        let size = a[p * n + c].abs();
        if size.is_nan() || size <= tiny {
            return None;
        }
        if p != c {
            for j in 0..n {
                a.swap(p * n + j, c * n + j);
            }
            b.swap(p, c);
        }
        let pivot = a[c * n + c];
        for i in c + 1..n {
            let f = a[i * n + c] / pivot;
            if f != 0.0 {
                for j in c..n {
                    a[i * n + j] -= f * a[c * n + j];
                }
                b[i] -= f * b[c];
            }
        }
    }
    for c in (0..n).rev() {
        let mut s = b[c];
        for j in c + 1..n {
            s -= a[c * n + j] * b[j];
        }
        b[c] = s / a[c * n + c];
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};
    use proptest::prelude::*;

    /// The test data are of order one: these are absolute.
    const TOL: f64 = 1e-9;

    /// Every solution found by enumerating the `2ᵏ` complementary bases: for each subset `S`
    /// with `m_SS` well conditioned, `z_S = −m_SS⁻¹ q_S`, `z = 0` elsewhere, kept if `z ≥ 0`
    /// and `w = m z + q ≥ 0` (within `TOL`).
    fn oracle(m: &[f64], q: &[f64]) -> Vec<Vec<f64>> {
        let k = q.len();
        let mut found = Vec::new();
        for mask in 0u32..(1 << k) {
            let s: Vec<usize> = (0..k).filter(|&i| mask & (1 << i) != 0).collect();
            let mut z = vec![0.0; k];
            if !s.is_empty() {
                let a = DMatrix::from_fn(s.len(), s.len(), |r, c| m[s[r] * k + s[c]]);
                let sv = a.clone().singular_values();
                if sv.min() <= 1e-9 * sv.max() {
                    continue;
                }
                let b = DVector::from_fn(s.len(), |r, _| -q[s[r]]);
                let Some(x) = a.lu().solve(&b) else { continue };
                for (r, &i) in s.iter().enumerate() {
                    z[i] = x[r];
                }
            }
            let w = affine(m, q, &z);
            if z.iter().chain(&w).all(|&x| x >= -TOL) {
                found.push(z);
            }
        }
        found
    }

    fn max_abs(x: &[f64]) -> f64 {
        x.iter().fold(0.0, |acc, v| acc.max(v.abs()))
    }

    /// `TOL` relative to the size of the terms: nearly singular problems have large solutions,
    /// and `w` on the support is then round-off of the size of `m z`; `zᵢ wᵢ` is that times `z`.
    fn tol_for(m: &[f64], z: &[f64]) -> f64 {
        let terms = max_abs(m) * max_abs(z) * z.len() as f64;
        TOL * (1.0 + terms) * (1.0 + max_abs(z))
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .fold(0.0, |acc, (x, y)| acc.max((x - y).abs()))
    }

    /// `m` is a P-matrix: Lemke's answer is the enumerated one (which is unique) and a solution.
    fn check_unique(m: &[f64], q: &[f64]) -> Result<(), TestCaseError> {
        let expected = oracle(m, q);
        prop_assert!(!expected.is_empty(), "the oracle found no solution");
        for other in &expected[1..] {
            prop_assert!(
                max_diff(other, &expected[0]) <= 1e-7,
                "two different solutions"
            );
        }
        let s = solve(m, q).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert!(is_solution(m, q, &s.z, &s.w, TOL), "{s:?}");
        let scale = max_abs(&expected[0]).max(1.0);
        prop_assert!(
            max_diff(&s.z, &expected[0]) <= 1e-9 * scale,
            "z = {:?}, expected {:?}",
            s.z,
            expected[0]
        );
        let w = affine(m, q, &s.z);
        prop_assert_eq!(&s.w, &w);
        Ok(())
    }

    /// `b bᵀ + δ I`, `b` `k×k` row-major.
    fn spd(b: &[f64], k: usize, delta: f64) -> Vec<f64> {
        gram(b, k, k, delta)
    }

    /// `b bᵀ + δ I`, `b` `k×r` row-major.
    fn gram(b: &[f64], k: usize, r: usize, delta: f64) -> Vec<f64> {
        let mut m = vec![0.0; k * k];
        for i in 0..k {
            for j in 0..k {
                m[i * k + j] = (0..r).map(|l| b[i * r + l] * b[j * r + l]).sum::<f64>();
            }
            m[i * k + i] += delta;
        }
        m
    }

    /// `W = A D Aᵀ` and `q = A v`, `A` `k×n` row-major, `D` diagonal.
    fn delassus(a: &[f64], d: &[f64], v: &[f64], k: usize, n: usize) -> (Vec<f64>, Vec<f64>) {
        let mut w = vec![0.0; k * k];
        for i in 0..k {
            for j in 0..k {
                w[i * k + j] = (0..n).map(|l| a[i * n + l] * d[l] * a[j * n + l]).sum();
            }
        }
        let q = (0..k)
            .map(|i| (0..n).map(|l| a[i * n + l] * v[l]).sum())
            .collect();
        (w, q)
    }

    fn config(cases: u32) -> ProptestConfig {
        ProptestConfig {
            cases,
            // Failing cases are reported, not stored next to the sources.
            failure_persistence: None,
            ..ProptestConfig::default()
        }
    }

    fn vec_in(range: std::ops::Range<f64>, n: usize) -> impl Strategy<Value = Vec<f64>> {
        prop::collection::vec(range, n)
    }

    fn ints(range: std::ops::RangeInclusive<i32>, n: usize) -> impl Strategy<Value = Vec<f64>> {
        prop::collection::vec(range.prop_map(f64::from), n)
    }

    proptest! {
        #![proptest_config(config(256))]

        #[test]
        fn symmetric_positive_definite_matches_enumeration(
            (k, b, delta, q) in (1usize..=6).prop_flat_map(|k| {
                (Just(k), vec_in(-1.0..1.0, k * k), 0.05..1.0f64, vec_in(-2.0..2.0, k))
            })
        ) {
            check_unique(&spd(&b, k, delta), &q)?;
        }

        #[test]
        fn nonsymmetric_p_matrix_matches_enumeration(
            (k, off, delta, q) in (1usize..=6).prop_flat_map(|k| {
                (Just(k), vec_in(-1.0..1.0, k * k), 0.05..1.0f64, vec_in(-2.0..2.0, k))
            })
        ) {
            // Strictly diagonally dominant rows with a positive diagonal: a P-matrix.
            let mut m = off.clone();
            for i in 0..k {
                let row: f64 = (0..k).filter(|&j| j != i).map(|j| off[i * k + j].abs()).sum();
                m[i * k + i] = row + delta;
            }
            check_unique(&m, &q)?;
        }

        #[test]
        fn degenerate_integer_positive_definite_matches_enumeration(
            (k, b, q) in (1usize..=6).prop_flat_map(|k| {
                (Just(k), ints(-2..=2, k * k), ints(-2..=2, k))
            })
        ) {
            // Small integers: exact ties in q, zeros in q, repeated rows in b, zeros in w.
            check_unique(&gram(&b, k, k, 1.0), &q)?;
        }

        #[test]
        fn semidefinite_solvable_is_solved(
            (k, r, b, q) in (1usize..=5).prop_flat_map(|k| (Just(k), 1..=k)).prop_flat_map(
                |(k, r)| (Just(k), Just(r), ints(-2..=2, k * r), ints(-3..=3, k))
            )
        ) {
            // b bᵀ with rank ≤ r (dependent constraint gradients), integer so that the
            // enumeration's verdict is exact.
            let m = gram(&b, k, r, 0.0);
            let solvable = !oracle(&m, &q).is_empty();
            match solve(&m, &q) {
                Ok(s) => {
                    prop_assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{:?}", s)
                }
                Err(e) => prop_assert!(!solvable, "{} on a solvable problem", e),
            }
        }

        #[test]
        fn dependent_constraints_are_solved(
            (k, n, a, d, v, copies) in (1usize..=6)
                .prop_flat_map(|k| (Just(k), 1..=k))
                .prop_flat_map(|(k, n)| {
                    (
                        Just(k),
                        Just(n),
                        vec_in(-1.0..1.0, k * n),
                        vec_in(0.2..5.0, n),
                        vec_in(-2.0..2.0, n),
                        prop::collection::vec(0..=k, k),
                    )
                })
        ) {
            // The Delassus matrix W = A M⁻¹ Aᵀ of k constraints on n ≤ k coordinates (M⁻¹ = D
            // diagonal), computed in floating point, and q = A v: q lies in the range of W, so a
            // solution exists (the problem is that of minimising ½ zᵀ W z + qᵀ z on z ≥ 0, which
            // is bounded below), and w is the same for all solutions. Some rows of A are copies
            // of earlier ones (the same constraint twice), some are 0.
            let mut a = a;
            for (i, &source) in copies.iter().enumerate() {
                if source < i {
                    let row: Vec<f64> = a[source * n..(source + 1) * n].to_vec();
                    a[i * n..(i + 1) * n].copy_from_slice(&row);
                } else if source == k && i % 2 == 1 {
                    a[i * n..(i + 1) * n].fill(0.0);
                }
            }
            let (w_matrix, q) = delassus(&a, &d, &v, k, n);
            let s = solve(&w_matrix, &q).map_err(|e| TestCaseError::fail(format!("{e}")))?;
            prop_assert!(
                is_solution(&w_matrix, &q, &s.z, &s.w, tol_for(&w_matrix, &s.z)),
                "{:?}",
                s
            );
        }

        #[test]
        fn ill_conditioned_positive_definite_is_solved(
            (k, b, delta, q) in (1usize..=8).prop_flat_map(|k| {
                (Just(k), vec_in(-1.0..1.0, k * k), -12.0..-6.0f64, vec_in(-2.0..2.0, k))
            })
        ) {
            // b bᵀ + δ I, condition numbers up to about 10¹³.
            let m = spd(&b, k, 10f64.powf(delta));
            let s = solve(&m, &q).map_err(|e| TestCaseError::fail(format!("{e}")))?;
            prop_assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{:?}", s);
        }

        #[test]
        fn indefinite_answers_are_solutions(
            (_k, m, q) in (1usize..=5).prop_flat_map(|k| {
                (Just(k), vec_in(-2.0..2.0, k * k), vec_in(-2.0..2.0, k))
            })
        ) {
            if let Ok(s) = solve(&m, &q) {
                prop_assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{:?}", s);
            }
        }

        #[test]
        fn integer_indefinite_answers_are_solutions(
            (_k, m, q) in (1usize..=5).prop_flat_map(|k| {
                (Just(k), ints(-2..=2, k * k), ints(-2..=2, k))
            })
        ) {
            if let Ok(s) = solve(&m, &q) {
                prop_assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{:?}", s);
            }
        }

        #[test]
        fn any_input_no_panic(
            (k, m, q) in (0usize..=4).prop_flat_map(|k| {
                (
                    Just(k),
                    prop::collection::vec(prop::num::f64::ANY, k * k),
                    prop::collection::vec(prop::num::f64::ANY, k),
                )
            })
        ) {
            let result = solve(&m, &q);
            if m.iter().chain(&q).any(|x| !x.is_finite()) {
                prop_assert_eq!(result, Err(LcpError::NonFinite));
            } else if let Ok(s) = result {
                prop_assert!(s.z.iter().chain(&s.w).all(|x| x.is_finite()));
                prop_assert!(s.z.iter().all(|&x| x >= 0.0));
            }
            let z = vec![0.0; k];
            let _ = is_solution(&m, &q, &z, &q, TOL);
        }
    }

    #[test]
    fn nonnegative_q_gives_zero() {
        let m = [2.0, 1.0, 1.0, 2.0];
        for q in [[0.0, 0.0], [1.0, 0.0], [0.0, 3.0], [-0.0, 0.5]] {
            let s = solve(&m, &q).unwrap();
            assert_eq!(s.z, vec![0.0, 0.0]);
            assert_eq!(s.w, q.to_vec());
        }
        let empty = solve(&[], &[]).unwrap();
        assert!(empty.z.is_empty() && empty.w.is_empty());
    }

    #[test]
    fn zeros_in_q_with_positive_definite_m() {
        let m = [2.0, 1.0, 0.0, 1.0, 2.0, 1.0, 0.0, 1.0, 2.0];
        for q in [
            [0.0, -1.0, 0.0],
            [-1.0, 0.0, -1.0],
            [0.0, 0.0, -1.0],
            [-1.0, 0.0, 0.0],
        ] {
            let s = solve(&m, &q).unwrap();
            assert!(is_solution(&m, &q, &s.z, &s.w, 1e-12), "{q:?}: {s:?}");
            let expected = oracle(&m, &q);
            assert!(
                max_diff(&s.z, &expected[0]) <= 1e-12,
                "{q:?}: {s:?} {expected:?}"
            );
        }
    }

    #[test]
    fn one_dimensional() {
        let s = solve(&[2.0], &[-4.0]).unwrap();
        assert_eq!(s.z, vec![2.0]);
        assert_eq!(s.w, vec![0.0]);
        let s = solve(&[0.5], &[3.0]).unwrap();
        assert_eq!((s.z, s.w), (vec![0.0], vec![3.0]));
    }

    #[test]
    fn newtons_cradle() {
        let m = [2.0, -1.0, -1.0, 2.0];
        let q = [-2.0, 0.0];
        let s = solve(&m, &q).unwrap();
        approx::assert_relative_eq!(s.z[0], 4.0 / 3.0, max_relative = 1e-14);
        approx::assert_relative_eq!(s.z[1], 2.0 / 3.0, max_relative = 1e-14);
        assert!(s.w.iter().all(|w| w.abs() <= 1e-15), "{s:?}");
    }

    #[test]
    fn the_same_constraint_twice() {
        // W = [[s, s], [s, s]]: one contact counted twice. Solutions z₁ + z₂ = 1/s, w = 0.
        for s in [1.0, 3.0, 0.3, 7e-3] {
            let m = [s, s, s, s];
            let q = [-1.0, -1.0];
            let sol = solve(&m, &q).unwrap();
            assert!(is_solution(&m, &q, &sol.z, &sol.w, 1e-12), "{sol:?}");
            assert!(sol.w.iter().all(|w| w.abs() <= 1e-15), "{sol:?}");
            approx::assert_relative_eq!(sol.z[0] + sol.z[1], 1.0 / s, max_relative = 1e-14);
        }
        // a aᵀ with duplicated rows: gradients a₁, a₁, a₂, a₂ (M = I).
        let a = [
            [1.0, 0.5, 0.0],
            [1.0, 0.5, 0.0],
            [0.0, 1.0, -1.0],
            [0.0, 1.0, -1.0],
        ];
        let m: Vec<f64> = (0..16)
            .map(|ij| (0..3).map(|l| a[ij / 4][l] * a[ij % 4][l]).sum())
            .collect();
        let v = [-1.0, -2.0, 0.5];
        let q: Vec<f64> = a
            .iter()
            .map(|r| (0..3).map(|l| r[l] * v[l]).sum())
            .collect();
        let sol = solve(&m, &q).unwrap();
        assert!(is_solution(&m, &q, &sol.z, &sol.w, 1e-12), "{sol:?}");
        assert_eq!(sol.w, affine(&m, &q, &sol.z));
        // The same w as any enumerated solution (w is unique for semi-definite m).
        let expected = oracle(&m, &q);
        assert!(!expected.is_empty());
        for z in &expected {
            assert!(max_diff(&affine(&m, &q, z), &sol.w) <= 1e-12);
        }
    }

    #[test]
    fn rank_deficient_exact_ties() {
        // Found by search: W of rank 2 with two zero rows; z₀ and w₁ reach 0 together, their
        // computed ratios 10⁻⁹ apart (the entries of the entering column are small, from
        // cancellation). The tie must go to z₀, and a secondary ray reached with z₀ at its
        // round-off is a solution.
        let a = [
            -0.9051669251637597,
            0.7680726735840228,
            0.5672845789673489,
            0.0,
            0.6815291567051781,
            -0.5789852552958722,
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        let (m, q) = delassus(
            &a,
            &[0.6788772307527456, 1.472347034158464],
            &[0.8165882834494105, 0.0],
            5,
            2,
        );
        let s = solve(&m, &q).unwrap();
        assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{s:?}");
    }

    #[test]
    fn nearly_dependent_constraints() {
        // Found by search: rows 0 and 2 of A equal, row 1 equal to 10⁻¹⁰; the first pivoting
        // passes through a basis with ‖B⁻¹‖ ≈ 10¹⁰ and ends with w₃ = −0.18: that answer must
        // not be returned (the second pass treats the rows as dependent).
        let (k, n) = (4, 2);
        let near = 10f64.powf(-9.766793216790258);
        let row = [0.35526714460128883, -0.9169712851365855];
        let a = [
            row[0],
            row[1],
            row[0] * (1.0 - 0.5 * near),
            row[1] * (1.0 + 0.5 * near),
            row[0],
            row[1],
            0.0,
            0.5272753298700514,
        ];
        let (m, q) = delassus(
            &a,
            &[0.01; 2],
            &[-1.6585215694550068, 1.5929978408197838],
            k,
            n,
        );
        let s = solve(&m, &q).unwrap();
        assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{s:?}");
        for w in &s.w {
            assert!(*w >= -1e-9, "{s:?}");
        }
    }

    #[test]
    fn unsolvable() {
        let cases: [(&[f64], &[f64]); 4] = [
            (&[0.0], &[-1.0]),
            (&[-1.0], &[-1.0]),
            // w₁ + w₂ = −2 whatever z.
            (&[1.0, -1.0, -1.0, 1.0], &[-1.0, -1.0]),
            (&[0.0, 0.0, 0.0, 0.0], &[1.0, -1.0]),
        ];
        for (m, q) in cases {
            assert!(oracle(m, q).is_empty(), "{m:?} {q:?}");
            assert_eq!(solve(m, q), Err(LcpError::Unsolvable), "{m:?} {q:?}");
        }
    }

    #[test]
    fn degenerate_problems_that_cycle_without_the_lexicographic_rule() {
        // Found by search: with ties broken by the smallest row index instead, the pivoting
        // cycles on these (indefinite, degenerate) problems until the iteration limit; they have no
        // solution.
        let cases: [(&[f64], &[f64]); 2] = [
            (
                &[
                    -2.0, 0.0, 2.0, 1.0, -2.0, 1.0, -2.0, -2.0, -2.0, -2.0, 2.0, -2.0, -1.0, 0.0,
                    2.0, 2.0, 1.0, 1.0, 0.0, -2.0, 2.0, -1.0, -2.0, 2.0, -1.0,
                ],
                &[-1.0, 1.0, -1.0, -1.0, 1.0],
            ),
            (
                &[
                    1.0, 2.0, 1.0, 1.0, -2.0, -1.0, -1.0, 1.0, 1.0, 0.0, -2.0, 0.0, 0.0, -2.0, 0.0,
                    -1.0, 1.0, 2.0, -1.0, 2.0, 0.0, 2.0, 1.0, -1.0, -2.0,
                ],
                &[-1.0, -1.0, -1.0, -1.0, 0.0],
            ),
        ];
        for (m, q) in cases {
            assert!(oracle(m, q).is_empty(), "{m:?} {q:?}");
            assert_eq!(solve(m, q), Err(LcpError::Unsolvable), "{m:?} {q:?}");
        }
    }

    #[test]
    fn iteration_limit() {
        let m = [2.0, -1.0, -1.0, 2.0];
        let q = [-2.0, 0.0];
        assert_eq!(solve_with_limit(&m, &q, 0), Err(LcpError::IterationLimit));
        assert!(solve_with_limit(&m, &q, 10).is_ok());
    }

    #[test]
    fn scale_free() {
        let m = [2.0, -1.0, 0.5, -1.0, 3.0, 0.0, 0.5, 0.0, 1.5];
        let q = [-2.0, 2.0, -1.0];
        let base = solve(&m, &q).unwrap();
        // A mixed support: z₁ = 0 < w₁, the others the other way round.
        assert!(
            base.z[0] > 0.0 && base.z[1] == 0.0 && base.z[2] > 0.0,
            "{base:?}"
        );
        assert!(base.w[1] > 0.0, "{base:?}");
        // (α m, β q) has the solution (β/α) z, with w scaled by β.
        for (alpha, beta) in [
            (1e-150, 1e-150),
            (1e150, 1e150),
            (1e-150, 1.0),
            (1.0, 1e-150),
            (1e150, 1e-150),
            (1e-150, 1e150),
            (1e-310, 1e-310),
        ] {
            let ms: Vec<f64> = m.iter().map(|x| x * alpha).collect();
            let qs: Vec<f64> = q.iter().map(|x| x * beta).collect();
            let s = solve(&ms, &qs).unwrap();
            for (z, z0) in s.z.iter().zip(&base.z) {
                approx::assert_relative_eq!(*z, z0 * (beta / alpha), max_relative = 1e-12);
            }
            for (w, w0) in s.w.iter().zip(&base.w) {
                assert!(
                    (w - w0 * beta).abs() <= 1e-14 * beta,
                    "{alpha} {beta}: {s:?}"
                );
            }
            assert!(is_solution(
                &m,
                &q,
                &s.z.iter().map(|z| z * alpha / beta).collect::<Vec<_>>(),
                &s.w.iter().map(|w| w / beta).collect::<Vec<_>>(),
                1e-12
            ));
        }
    }

    #[test]
    fn non_finite() {
        let m = [2.0, -1.0, -1.0, 2.0];
        let q = [-2.0, 0.0];
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for i in 0..4 {
                let mut mb = m;
                mb[i] = bad;
                assert_eq!(solve(&mb, &q), Err(LcpError::NonFinite));
            }
            for i in 0..2 {
                let mut qb = q;
                qb[i] = bad;
                assert_eq!(solve(&m, &qb), Err(LcpError::NonFinite));
            }
            // Also with q ≥ 0 otherwise (the early return must not hide it).
            assert_eq!(solve(&m, &[bad, 1.0]), Err(LcpError::NonFinite));
            assert!(!is_solution(&m, &q, &[bad, 0.0], &[0.0, 0.0], 1.0));
        }
        // The solution itself would overflow f64.
        assert_eq!(solve(&[1e-300], &[-1e300]), Err(LcpError::NonFinite));
    }

    #[test]
    #[should_panic(expected = "lcp::solve")]
    fn length_mismatch_panics() {
        let _ = solve(&[1.0, 2.0, 3.0], &[-1.0, 0.0]);
    }

    #[test]
    fn is_solution_rejects() {
        let m = [2.0, -1.0, -1.0, 2.0];
        let q = [-2.0, 0.0];
        let (z, w) = ([4.0 / 3.0, 2.0 / 3.0], [0.0, 0.0]);
        assert!(is_solution(&m, &q, &z, &w, 1e-12));
        // w ≠ m z + q.
        assert!(!is_solution(&m, &q, &z, &[0.0, 1e-3], 1e-6));
        // z < 0.
        assert!(!is_solution(&m, &q, &[-1.0, 0.0], &[-4.0, 1.0], 1e-6));
        // Not complementary: z = (2, 1), w = (1, 0).
        assert!(!is_solution(&m, &q, &[2.0, 1.0], &[1.0, 0.0], 1e-6));
        // Lengths.
        assert!(!is_solution(&m, &q, &z[..1], &w, 1e-6));
        assert!(!is_solution(&m[..3], &q, &z, &w, 1e-6));
    }

    #[test]
    fn largest_size() {
        // k = 64, a chain of contacts (tridiagonal, like a long Newton's cradle) plus a random
        // low-rank part, deterministic.
        let k = 64;
        let mut m = vec![0.0; k * k];
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let u: Vec<f64> = (0..k).map(|_| next()).collect();
        for i in 0..k {
            m[i * k + i] = 2.0;
            if i + 1 < k {
                m[i * k + i + 1] = -1.0;
                m[(i + 1) * k + i] = -1.0;
            }
            for j in 0..k {
                m[i * k + j] += u[i] * u[j];
            }
        }
        let q: Vec<f64> = (0..k).map(|_| 2.0 * next()).collect();
        let s = solve(&m, &q).unwrap();
        assert!(is_solution(&m, &q, &s.z, &s.w, 1e-10), "{s:?}");
        assert_eq!(solve(&m, &q).unwrap(), s);
    }
}
