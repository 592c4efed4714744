//! What is checked about the problem and an answer: the acceptance check of a solution, the
//! proof that none exists, and how far from singular the matrix is.

use super::Conditioning;

/// An answer is accepted when, in every row, `−wᵢ` and `min(zᵢ / ‖z‖∞, |wᵢ| / termsᵢ)` are at most
/// this, `termsᵢ = |qᵢ| + Σⱼ |mᵢⱼ zⱼ|` (nonnegativity of `w` and complementarity, relative to the
/// size of what `w` is computed from; free of units), beyond [`UNDERFLOW`]. Answers of a
/// correct method meet it with a margin of several orders.
pub(super) const ACCEPTANCE: f64 = 1e-9;

/// The absolute allowance of the checks, in the scaled units (the largest entries of `m` and `q`
/// in `[1, 2)`): 2¹⁰ times the smallest subnormal number, `5·10⁻³²¹`, in `w` and in each `zⱼ`
/// (that is `(1 + Σⱼ |mᵢⱼ|)` times it in `wᵢ`). A subnormal number carries fewer digits than its
/// size suggests (`5·10⁻³²⁴` has one), so a relative test cannot be asked of quantities this
/// small; everything above it is tested relative to its terms.
pub(super) const UNDERFLOW: f64 = 1024.0 * f64::from_bits(1);

/// A vector `y ≥ 0` proves that no `z ≥ 0` has `m z + q ≥ 0` when `(mᵀy)ⱼ ≤` this times
/// `Σᵢ |mᵢⱼ| yᵢ` for every `j` and `qᵀy < −` this times `Σᵢ |qᵢ| yᵢ` (up to [`UNDERFLOW`]):
/// `mᵀy ≤ 0` and `qᵀy < 0` beyond the rounding of the sums and of `y` itself. Then any `z ≥ 0`
/// with `m z + q ≥ 0` would need `(mᵀy)ᵀ z ≥ −qᵀy`, that is `z` some `10¹⁰` times larger than
/// the scale of the problem.
const CERTIFICATE: f64 = 1e-10;

/// `m z + q`.
pub(super) fn affine(m: &[f64], q: &[f64], z: &[f64]) -> Vec<f64> {
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

/// How far `(z ≥ 0, w = m z + q)` is from a solution, free of units: the largest over the rows
/// of `(−wᵢ − uᵢ)⁺ / termsᵢ` and `min(zᵢ / ‖z‖∞, (|wᵢ| − uᵢ)⁺ / termsᵢ)`,
/// `termsᵢ = |qᵢ| + Σⱼ |mᵢⱼ zⱼ|`, `uᵢ = (1 + Σⱼ |mᵢⱼ|)` [`UNDERFLOW`] (a row whose terms are all
/// 0 has `wᵢ = 0`); infinite if anything is not finite or `z` has a negative entry.
pub(super) fn violation(m: &[f64], q: &[f64], z: &[f64], w: &[f64]) -> f64 {
    violation_with(m, q, z, w, UNDERFLOW)
}

/// [`violation`] with the allowance `u_w + u_z Σⱼ |mᵢⱼ|` in row `i`, `u_w` given, `u_z` =
/// [`UNDERFLOW`] (for the data in their own units, `u_w` is [`UNDERFLOW`] times the power of two
/// `q` was scaled by; `z` is in its own units either way).
pub(super) fn violation_with(m: &[f64], q: &[f64], z: &[f64], w: &[f64], u_w: f64) -> f64 {
    let k = q.len();
    let mut z_norm = 0.0_f64;
    for (zi, wi) in z.iter().zip(w) {
        if !(*zi >= 0.0 && zi.is_finite() && wi.is_finite()) {
            return f64::INFINITY;
        }
        z_norm = z_norm.max(*zi);
    }
    let mut worst = 0.0_f64;
    for i in 0..k {
        // A row with wᵢ ≥ 0 and zᵢ = 0 (or wᵢ = 0) meets both conditions exactly.
        if w[i] >= 0.0 && (z[i] == 0.0 || w[i] == 0.0) {
            continue;
        }
        let row = &m[i * k..(i + 1) * k];
        let (mut terms, mut allowance) = (q[i].abs(), u_w);
        for (mij, zj) in row.iter().zip(z) {
            terms += (mij * zj).abs();
            allowance += UNDERFLOW * mij.abs();
        }
        if !terms.is_finite() {
            return f64::INFINITY;
        }
        let negative = (-w[i] - allowance).max(0.0);
        let off = (w[i].abs() - allowance).max(0.0);
        if negative == 0.0 && off == 0.0 {
            continue;
        }
        let complementary = if z_norm > 0.0 {
            (z[i] / z_norm).min(off / terms)
        } else {
            0.0
        };
        worst = worst.max(negative / terms).max(complementary);
    }
    worst
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

/// Whether `y` proves that `(m, q)` has no solution (Farkas): `y ≥ 0`, `y ≠ 0`, `mᵀy ≤ 0` and
/// `qᵀy < 0`, each beyond [`CERTIFICATE`] of its terms. Scaled units.
pub(super) fn proves_infeasible(m: &[f64], q: &[f64], y: &[f64]) -> bool {
    let k = q.len();
    if y.len() != k || !y.iter().all(|&v| v >= 0.0 && v.is_finite()) || y.iter().all(|&v| v == 0.0)
    {
        return false;
    }
    for j in 0..k {
        let (mut sum, mut terms) = (0.0, 0.0);
        for (i, &yi) in y.iter().enumerate() {
            let term = m[i * k + j] * yi;
            sum += term;
            terms += term.abs();
        }
        if sum.is_nan() || sum > CERTIFICATE * terms + UNDERFLOW {
            return false;
        }
    }
    let (mut sum, mut terms) = (0.0, 0.0);
    for (qi, yi) in q.iter().zip(y) {
        sum += qi * yi;
        terms += (qi * yi).abs();
    }
    sum < -(CERTIFICATE * terms + UNDERFLOW)
}

/// Two entries `mᵢⱼ`, `mⱼᵢ` are equal for [`conditioning`] when they differ by at most this
/// times the larger: a matrix `A D Aᵀ` computed entry by entry is symmetric only to rounding.
const SYMMETRY: f64 = 8.0 * f64::EPSILON;

/// How far from singular `m` (`k × k`, row-major) is: the Cholesky factorisation of its lower
/// triangle, when it is symmetric to rounding ([`SYMMETRY`]; the Delassus matrices of
/// `crate::contact` are symmetric exactly).
pub(crate) fn conditioning(m: &[f64], k: usize) -> Conditioning {
    for i in 0..k {
        for j in 0..i {
            let (a, b) = (m[i * k + j], m[j * k + i]);
            if a.is_nan() || b.is_nan() || (a - b).abs() > SYMMETRY * a.abs().max(b.abs()) {
                return Conditioning::Nonsymmetric;
            }
        }
    }
    let mut l = vec![0.0; k * k];
    let mut smallest = 1.0_f64;
    for j in 0..k {
        let diagonal = m[j * k + j];
        let mut d = diagonal;
        for p in 0..j {
            d -= l[j * k + p] * l[j * k + p];
        }
        if diagonal.is_nan() || diagonal <= 0.0 {
            return Conditioning::NotPositiveDefinite {
                pivot_ratio: f64::NEG_INFINITY,
            };
        }
        let ratio = d / diagonal;
        if ratio.is_nan() || ratio <= 0.0 {
            return Conditioning::NotPositiveDefinite { pivot_ratio: ratio };
        }
        smallest = smallest.min(ratio);
        let l_jj = d.sqrt();
        l[j * k + j] = l_jj;
        for i in j + 1..k {
            let mut s = m[i * k + j];
            for p in 0..j {
                s -= l[i * k + p] * l[j * k + p];
            }
            l[i * k + j] = s / l_jj;
        }
    }
    Conditioning::PositiveDefinite {
        pivot_ratio: smallest,
    }
}

/// `init + Σⱼ aⱼ bⱼ`, accumulated in twice the working precision and rounded once at the end
/// (Ogita, Rump and Oishi, "Accurate sum and dot product", SIAM J. Sci. Comput. 26 (2005),
/// algorithm Dot2: error-free products by Dekker's splitting and error-free sums by Knuth's
/// TwoSum): as accurate as if computed in about 106 bits, so that a result far smaller than its
/// terms (a cancellation) keeps its sign and its leading digits.
pub(super) fn dot2(init: f64, a: impl Iterator<Item = f64>, b: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut error) = (init, 0.0);
    for (x, y) in a.zip(b) {
        let (product, product_error) = two_product(x, y);
        let (total, sum_error) = two_sum(sum, product);
        sum = total;
        error += sum_error + product_error;
    }
    sum + error
}

/// `a + b = s + e` exactly (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let v = s - a;
    (s, (a - (s - v)) + (b - v))
}

/// `a b = p + e` exactly, for products that neither overflow nor underflow (Dekker's
/// TwoProduct, with Veltkamp's splitting into 26-bit halves: no fused multiply-add needed).
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    (p, al * bl - (((p - ah * bh) - al * bh) - ah * bl))
}

/// `a = h + l` with `h` holding the leading 26 bits (Veltkamp).
fn split(a: f64) -> (f64, f64) {
    const FACTOR: f64 = 134_217_729.0; // 2²⁷ + 1
    let c = FACTOR * a;
    let h = c - (c - a);
    (h, a - h)
}
