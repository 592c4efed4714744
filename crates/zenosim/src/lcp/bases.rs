//! The last resort for small problems: every complementary basis, one after the other.
//!
//! For `k ≤ MAX_SIZE`, after the active-set method and Lemke's method have both failed (a
//! matrix that is not copositive-plus, such as the contact problem with friction, on which
//! Lemke's method may end on a ray that proves nothing), each of the `2ᵏ` bases `S` is tried:
//! `z_S` solves `m_SS z_S = −q_S` (Gaussian elimination with partial pivoting), `z = 0` off
//! `S`, and the one with the smallest violation of the check ([`super::check::violation`]) is
//! returned, for the caller to check again. An LCP that has a solution has a complementary
//! basic one (where its basis matrix is regular), so this finds it wherever the matrices of
//! the bases on the way are not singular. Where a basis matrix is singular or nearly so (two
//! contacts with the same slip row: a block landing flat on two rough corners), its solution
//! of least norm (singular values below `1e-12` of the largest dropped) is tried too: the
//! equations are then consistent, and that solution meets them.

use super::check::{affine, violation};

/// The largest problem enumerated: `2¹²` bases of at most `12×12`.
pub(super) const MAX_SIZE: usize = 12;

/// How close to 0, relative to the largest entry, a basic variable is taken for 0.
const ROUNDING: f64 = 256.0 * f64::EPSILON;

/// The complementary basic solution of `(m, q)` with the smallest violation, if any basis is
/// regular, and that violation.
pub(super) fn solve(m: &[f64], q: &[f64]) -> Option<(Vec<f64>, f64)> {
    let k = q.len();
    if k > MAX_SIZE {
        return None;
    }
    let mut best: Option<(Vec<f64>, f64)> = None;
    for mask in 0u32..(1 << k) {
        let s: Vec<usize> = (0..k).filter(|&i| mask & (1 << i) != 0).collect();
        let tries = [solve_square(m, k, &s, q), solve_least_norm(m, k, &s, q)];
        for z_s in tries.into_iter().flatten() {
            let mut z = vec![0.0; k];
            for (&i, &v) in s.iter().zip(&z_s) {
                z[i] = v;
            }
            // A basic variable at 0 comes out of the solve at its rounding, either side: it is
            // 0 (the check that follows judges the result; a row whose terms are that rounding
            // alone could not meet it otherwise).
            let size = z.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            for v in &mut z {
                if v.abs() <= ROUNDING * size {
                    *v = 0.0;
                }
            }
            let w = affine(m, q, &z);
            let worst = violation(m, q, &z, &w);
            if worst.is_finite() && best.as_ref().is_none_or(|b| worst < b.1) {
                best = Some((z, worst));
            }
        }
        if best.as_ref().is_some_and(|b| b.1 == 0.0) {
            break;
        }
    }
    best
}

/// `x` with `m_SS x = −q_S` of least norm, singular values below `1e-12` of the largest
/// dropped; `None` where it is not finite.
fn solve_least_norm(m: &[f64], k: usize, s: &[usize], q: &[f64]) -> Option<Vec<f64>> {
    let p = s.len();
    if p == 0 {
        return Some(Vec::new());
    }
    let a = nalgebra::DMatrix::from_fn(p, p, |r, c| m[s[r] * k + s[c]]);
    let b = nalgebra::DVector::from_fn(p, |r, _| -q[s[r]]);
    let svd = a.svd(true, true);
    let largest = svd.singular_values.max();
    if !largest.is_finite() || largest == 0.0 {
        return None;
    }
    let x = svd.solve(&b, 1e-12 * largest).ok()?;
    x.iter()
        .all(|v| v.is_finite())
        .then(|| x.iter().copied().collect())
}

/// `x` with `m_SS x = −q_S`, by Gaussian elimination with partial pivoting; `None` where a
/// pivot vanishes.
fn solve_square(m: &[f64], k: usize, s: &[usize], q: &[f64]) -> Option<Vec<f64>> {
    let p = s.len();
    let mut a: Vec<f64> = Vec::with_capacity(p * (p + 1));
    for &r in s {
        a.extend(s.iter().map(|&c| m[r * k + c]));
        a.push(-q[r]);
    }
    let width = p + 1;
    for c in 0..p {
        let pivot =
            (c..p).max_by(|&x, &y| a[x * width + c].abs().total_cmp(&a[y * width + c].abs()))?;
        if a[pivot * width + c] == 0.0 || !a[pivot * width + c].is_finite() {
            return None;
        }
        if pivot != c {
            for j in 0..width {
                a.swap(c * width + j, pivot * width + j);
            }
        }
        for r in c + 1..p {
            let factor = a[r * width + c] / a[c * width + c];
            for j in c..width {
                a[r * width + j] -= factor * a[c * width + j];
            }
        }
    }
    let mut x = vec![0.0; p];
    for r in (0..p).rev() {
        let mut v = a[r * width + p];
        for j in r + 1..p {
            v -= a[r * width + j] * x[j];
        }
        x[r] = v / a[r * width + r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A matrix on which Lemke's method may end on a ray: not copositive-plus (a negative
    /// diagonal entry), with the solution z = (0, 1), w = (1, 0).
    #[test]
    fn every_basis_finds_the_solution_of_a_small_problem() {
        let m = [-1.0, 2.0, 1.0, 1.0];
        let q = [-1.0, -1.0];
        let (z, worst) = solve(&m, &q).unwrap();
        assert!(worst <= 1e-15, "{z:?} {worst}");
        let w = affine(&m, &q, &z);
        assert!(
            z.iter()
                .zip(&w)
                .all(|(z, w)| *z >= 0.0 && *w >= -1e-15 && z * w == 0.0),
            "{z:?} {w:?}"
        );
    }
}
