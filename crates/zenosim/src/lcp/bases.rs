//! The last resort for small problems: every complementary basis, one after the other.
//!
//! For `k ≤ MAX_SIZE`, after the active-set method and Lemke's method have both failed (a
//! matrix that is not copositive-plus, such as the contact problem with friction, on which
//! Lemke's method may end on a ray that proves nothing), each of the `2ᵏ` bases `S` is tried:
//! `z_S` solves `m_SS z_S = −q_S` (Gaussian elimination with partial pivoting), `z = 0` off
//! `S`, and the one with the smallest violation of the check ([`super::check::violation`]) is
//! returned, for the caller to check again. An LCP that has a solution has a complementary
//! basic one (where its basis matrix is regular), so this finds it wherever the matrices of
//! the bases on the way are not singular.

use super::check::{affine, violation};

/// The largest problem enumerated: `2¹²` bases of at most `12×12`.
pub(super) const MAX_SIZE: usize = 12;

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
        let Some(z_s) = solve_square(m, k, &s, q) else {
            continue;
        };
        let mut z = vec![0.0; k];
        for (&i, &v) in s.iter().zip(&z_s) {
            z[i] = v;
        }
        let w = affine(m, q, &z);
        let worst = violation(m, q, &z, &w);
        if worst.is_finite() && best.as_ref().is_none_or(|b| worst < b.1) {
            let done = worst == 0.0;
            best = Some((z, worst));
            if done {
                break;
            }
        }
    }
    best
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
