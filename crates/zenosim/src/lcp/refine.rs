//! Iterative refinement of an answer on its support.
//!
//! An answer solved by elimination on a basis is backward stable for the basis as a whole, not
//! row by row: where one variable is fixed by a row of large terms and another row of small
//! terms depends on it (a contact hardly approaching while it slips fast: the slip's row sets
//! the tangential unknowns to the rounding of its size), the small row's `wᵢ` is off by that
//! rounding, which the acceptance check ([`super::check::violation`]) measures against the
//! small row's own terms. Steps of iterative refinement in working precision,
//! `z_S ← z_S − m_SS⁻¹ (m_SS z_S + q_S)`, bring every row's residual to the rounding of its own
//! terms (Skeel, "Iterative refinement implies numerical stability for Gaussian elimination",
//! Math. Comp. 35, 1980).

use super::check::{affine, violation};
use super::lemke::gauss_solve;

/// At most this many steps.
const STEPS: usize = 3;

/// `z` refined on its support `{i : zᵢ > 0}` while its [`violation`] falls, and that violation.
pub(super) fn refine(m: &[f64], q: &[f64], z: Vec<f64>) -> (Vec<f64>, f64) {
    let k = q.len();
    let support: Vec<usize> = (0..k).filter(|&i| z[i] > 0.0).collect();
    let n = support.len();
    let mut best_violation = violation(m, q, &z, &affine(m, q, &z));
    let mut best = z;
    if n == 0 {
        return (best, best_violation);
    }
    let mut a = vec![0.0; n * n];
    for _ in 0..STEPS {
        let w = affine(m, q, &best);
        let mut r: Vec<f64> = support.iter().map(|&i| w[i]).collect();
        for (row, &i) in support.iter().enumerate() {
            for (col, &j) in support.iter().enumerate() {
                a[row * n + col] = m[i * k + j];
            }
        }
        if gauss_solve(&mut a, &mut r, n).is_none() {
            break;
        }
        let mut next = best.clone();
        for (&i, d) in support.iter().zip(&r) {
            next[i] = (next[i] - d).max(0.0);
        }
        let next_violation = violation(m, q, &next, &affine(m, q, &next));
        // (A NaN violation is no improvement.)
        if next_violation.partial_cmp(&best_violation) != Some(std::cmp::Ordering::Less) {
            break;
        }
        (best, best_violation) = (next, next_violation);
    }
    (best, best_violation)
}
