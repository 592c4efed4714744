//! Lemke's complementary pivoting method (Lemke 1965), with an auxiliary variable `z₀` and the
//! covering vector `e = (1, …, 1)`: the system
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
//! occur. The ray's `z` part is returned, for the caller to check as a proof.
//!
//! The leaving variable is chosen by the lexicographic minimum-ratio rule (Cottle, Pang and
//! Stone 1992, §4.4 and §4.9): among the rows that tie in the ordinary ratio `q̄ᵢ / d̄ᵢ`, the one
//! whose row of the inverse basis, `(B⁻¹)ᵢ· / d̄ᵢ`, is lexicographically smallest. The rows of
//! `B⁻¹` are independent, so the choice is unique: this is the pivoting of the problem with `q`
//! perturbed by `(ε, ε², …, εᵏ)`, which is nondegenerate, so degenerate problems (`q` with zeros,
//! repeated constraints) cannot cycle. When `z₀`'s row is among the ties it is taken (that ends
//! the pivoting at once, with every basic variable nonnegative). The tableau is dense and holds
//! `B⁻¹` in the columns of `w`; it takes `O(k²)` memory, a pivot `O(k²)` operations.
//!
//! Ratios tie when they agree to the rounding of what they are computed from: that of `q̄ⱼ` and
//! `d̄ⱼ` (whose error is that of the row `(B⁻¹)ⱼ·` the pivots made, times `‖q‖∞` or the size of
//! the entering column), and that of the ratio `θᵢ = q̄ᵢ / d̄ᵢ` they are compared at, which is
//! large where `d̄ᵢ` is small from cancellation (rank-deficient matrices make exact ties that
//! rounding would otherwise break at random). The allowance is some thousand times the
//! rounding unit, no more: a small entry of `q` is data, and `q = (−1.06·10⁻¹⁰, −5.46)` with
//! `m = I` is not a tie (a tolerance of `10⁻¹¹` of `‖q‖∞` took it for one, let `z₀` leave there
//! and left `w₀ = −1.06·10⁻¹⁰`).

use super::check::{affine, violation};
use std::cmp::Ordering;

/// An entry `d̄ᵢ` of the entering column is a pivot candidate when it exceeds a tolerance times
/// the size of what it was computed from, `‖(B⁻¹)ᵢ·‖₁ ‖aₑ‖∞` (`aₑ` the entering column of the
/// original tableau). The first pass takes `1e-12` (about `4500 ε`: room for the rounding of
/// many pivots, far below the pivots of a reasonably conditioned matrix). If its answer fails
/// the acceptance check (constraints dependent up to `~1e-10`, whose pivots are tiny but not
/// rounding, leave a basis too ill-conditioned to keep the digits) or it ends without one, a
/// second pass takes `1e-8`: constraints dependent to that precision are then treated as
/// dependent.
pub(super) const PIVOT_TOLERANCES: [f64; 2] = [1e-12, 1e-8];

/// The rounding of a basic variable `b̄ⱼ − θᵢ d̄ⱼ` at the ratio `θᵢ = b̄ᵢ / d̄ᵢ` of row `i` is
/// taken as this times the size of what it is computed from, `‖(B⁻¹)ⱼ·‖₁ (‖q‖∞ + |θᵢ| ‖aₑ‖∞)`,
/// plus `d̄ⱼ` times the same for `θᵢ`, `‖(B⁻¹)ᵢ·‖₁ (‖q‖∞ + |θᵢ| ‖aₑ‖∞) / d̄ᵢ`, in the scaled
/// units: some thousand times the rounding unit, room for the rounding of the pivots that made
/// `B⁻¹`. A pivot row whose ratio leaves every other basic variable above minus its rounding
/// ties with the minimum ratio; the ties are resolved lexicographically (with `z₀` first). `z₀`
/// at or below its rounding on a secondary ray counts as 0.
const VALUE_TOLERANCE: f64 = 1e-13;

/// Two components in the lexicographic comparison are equal when they differ by less than this
/// times the largest component of the two rows compared.
const LEX_TOLERANCE: f64 = 1e-12;

/// A pivot of the support system smaller than this times `n · maxᵢⱼ |aᵢⱼ|` counts as singular
/// (the refinement is then skipped: the support matrix of a semi-definite problem may be
/// singular).
const SINGULAR_TOLERANCE: f64 = 1e3 * f64::EPSILON;

/// How Lemke's method ended.
pub(super) enum End {
    /// `z₀` left the basis: `z` of the complementary basis reached (negative rounding
    /// included), to be checked.
    Complementary(Vec<f64>),
    /// A secondary ray: the `z` part of its direction (`≥ 0`), a candidate proof that the
    /// problem has no solution.
    Ray(Vec<f64>),
}

/// Why Lemke's method gave neither.
pub(super) enum Breakdown {
    /// More pivots than the limit.
    IterationLimit,
    /// The tableau overflowed.
    NonFinite,
}

/// Lemke's method on the scaled problem. `pivot_tolerance` is one of [`PIVOT_TOLERANCES`].
///
/// The tableau has `k` rows and the columns `w₀…w_{k−1}`, `z₀…z_{k−1}`, the auxiliary variable
/// and the right-hand side; it starts as `[I | −m | −e | q]` and always equals `B⁻¹ [I | −m | −e
/// | q]`, so its `w` columns hold `B⁻¹`.
pub(super) fn solve(
    m: &[f64],
    q: &[f64],
    limit: usize,
    pivot_tolerance: f64,
) -> Result<End, Breakdown> {
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
    let mut basis: Vec<usize> = (0..k).collect();
    let mut pivot_row = vec![0.0; width];
    let mut candidates: Vec<(usize, f64)> = Vec::with_capacity(k);
    let mut ties: Vec<usize> = Vec::with_capacity(k);
    // Per row: ‖(B⁻¹)ᵢ·‖₁ ‖q‖∞ and ‖(B⁻¹)ᵢ·‖₁ ‖a‖∞, the sizes q̄ᵢ and d̄ᵢ are computed from.
    let mut q_sizes = vec![0.0; k];
    let mut d_sizes = vec![0.0; k];
    let q_norm = q.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()));
    // ‖aₑ‖∞ for the z columns of the original tableau (the others are columns of I or −e).
    let column_norms: Vec<f64> = (0..k)
        .map(|j| (0..k).fold(0.0_f64, |acc, i| acc.max(m[i * k + j].abs())))
        .collect();

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
        let a_norm = if (k..2 * k).contains(&entering) {
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
                return Err(Breakdown::NonFinite);
            }
            let inverse_norm: f64 = row[..k].iter().map(|x| x.abs()).sum();
            q_sizes[i] = inverse_norm * q_norm;
            d_sizes[i] = inverse_norm * a_norm;
            if d > pivot_tolerance * d_sizes[i] {
                let ratio = row[rhs] / d;
                candidates.push((i, ratio));
                if smallest.is_none_or(|(_, theta)| ratio < theta) {
                    smallest = Some((i, ratio));
                }
            }
        }
        let Some((smallest_row, _)) = smallest else {
            // A secondary ray. If z₀ is 0 up to rounding here, the basis is complementary
            // after all: a solution (checked, like every answer, by the caller).
            let r = basis.iter().position(|&v| v == aux).unwrap_or(0);
            if t[r * width + rhs] <= VALUE_TOLERANCE * q_sizes[r] {
                return Ok(End::Complementary(basic_z(&t, width, &basis, k)));
            }
            return Ok(End::Ray(ray(&t, width, &basis, k, entering)));
        };
        // The ties: rows whose ratio θᵢ leaves every candidate's basic variable
        // b̄ⱼ − θᵢ d̄ⱼ ≥ 0 up to its rounding (exactly the rows of the minimum ratio, in exact
        // arithmetic). The rows of the minimum ratio are always among them.
        ties.clear();
        for &(i, theta) in &candidates {
            // The rounding of θᵢ = q̄ᵢ / d̄ᵢ itself, from that of q̄ᵢ and d̄ᵢ (large where d̄ᵢ
            // is small from cancellation), which moves b̄ⱼ − θᵢ d̄ⱼ by d̄ⱼ times as much.
            let d_i = t[i * width + entering];
            let theta_noise = (q_sizes[i] + theta.abs() * d_sizes[i]) / d_i;
            let feasible = candidates.iter().all(|&(j, _)| {
                let row = &t[j * width..(j + 1) * width];
                let noise = VALUE_TOLERANCE
                    * (q_sizes[j] + theta.abs() * d_sizes[j] + row[entering] * theta_noise);
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
            return Ok(End::Complementary(basic_z(&t, width, &basis, k)));
        }
        entering = complement(leaving, k);
    }
    Err(Breakdown::IterationLimit)
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

/// The `z` part of the secondary ray's direction: the entering variable grows by 1 and each
/// basic variable by `−d̄ᵢ` (`≤ 0` up to the pivot tolerance; clamped to `≥ 0`).
fn ray(t: &[f64], width: usize, basis: &[usize], k: usize, entering: usize) -> Vec<f64> {
    let mut y = vec![0.0; k];
    if (k..2 * k).contains(&entering) {
        y[entering - k] = 1.0;
    }
    for (row, &variable) in t.chunks_exact(width).zip(basis) {
        if (k..2 * k).contains(&variable) {
            y[variable - k] = (-row[entering]).max(0.0);
        }
    }
    y
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
            return x.partial_cmp(&y) == Some(Ordering::Less);
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

/// Cleans Lemke's `z` (negative rounding set to 0) and refines it once on its support; returns
/// the better of the two and its [`violation`].
pub(super) fn polish(m: &[f64], q: &[f64], mut z: Vec<f64>) -> (Vec<f64>, f64) {
    for x in &mut z {
        if *x < 0.0 {
            *x = 0.0;
        }
    }
    let base = violation(m, q, &z, &affine(m, q, &z));
    if let Some(refined) = support_solve(m, q, &z) {
        let refined_violation = violation(m, q, &refined, &affine(m, q, &refined));
        if refined_violation <= base {
            return (refined, refined_violation);
        }
    }
    (z, base)
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
pub(super) fn gauss_solve(a: &mut [f64], b: &mut [f64], n: usize) -> Option<()> {
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
