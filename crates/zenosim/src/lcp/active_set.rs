//! The active-set method for a symmetric positive definite `m`: the LCP is the strictly convex
//! quadratic program `min f(z) = ½ zᵀ m z + qᵀ z` on `z ≥ 0`, whose gradient is `w = m z + q`
//! (the KKT conditions of the program are the LCP). The method is Lawson and Hanson's NNLS
//! (*Solving Least Squares Problems*, 1974, chapter 23) with the quadratic `f` in place of the
//! least-squares objective:
//!
//! ```text
//! P = ∅, z = 0
//! loop:                                          (z minimises f on {z : z_Z = 0}, z_P > 0)
//!     w = m z + q; if wᵢ ≥ 0 (to rounding) for every i ∉ P: z solves the LCP
//!     P ← P ∪ {t}, t ∉ P with wₜ < 0 (the largest decrease wₜ² / mₜₜ)
//!     loop:
//!         s: m_PP s_P = −q_P, s = 0 off P            (Cholesky)
//!         if s_P > 0: z ← s, next outer iteration
//!         z ← z + α (s − z), α the largest step that keeps z ≥ 0;
//!         the indices that reach 0 leave P
//! ```
//!
//! Why it is finite (in exact arithmetic): each outer iteration starts at the minimiser of `f`
//! on its passive set `P`, and the next one at a strictly lower value of `f` (the direction into
//! `zₜ > 0` descends since `wₜ < 0`, and a positive definite `m` makes the first `sₜ` positive),
//! so no `P` recurs; the inner loop removes at least one index per step. No tie between ratios
//! is ever decided, so zeros and repeated entries in `q` need no special rule.
//!
//! In floating point the starting point of an outer iteration is a function of `P` alone, so a
//! recurring `P` means the method would cycle; the sets are recorded, and a recurrence stops the
//! method with its current `z` (still `≥ 0`), which is returned if it passes the acceptance
//! check. A limit of `4 (k+1)²` steps bounds the rest (the method, like every pivoting method,
//! has contrived inputs that take exponentially many).
//!
//! The signs it decides on must be right where the problem is degenerate (entries of `q` that
//! nearly cancel, solutions with components `10⁻⁹` next to `1`). A `wᵢ` far below its terms is
//! summed again in twice the working precision. A first pass solves each subsystem by Cholesky
//! alone, which gives every component to the rounding of the largest; where that leaves a sign
//! in doubt, its answer fails the check, and a second pass refines each subsystem's solution
//! with residuals accumulated in twice the working precision, so that every component is
//! accurate to its own size.

use super::check::{affine, dot2, violation, ACCEPTANCE, UNDERFLOW};
use super::Stop;

/// `wᵢ` counts as negative, for `i` to enter `P`, below minus this times its terms
/// `|qᵢ| + Σⱼ |mᵢⱼ zⱼ|` (and [`UNDERFLOW`]): ten thousand times the rounding that `z` gives it, a
/// thousand times below the acceptance check, so that an answer at which the method stops
/// passes the check.
const NEGATIVE: f64 = 1e-12;

/// A `wᵢ` summed in working precision is trusted above this times its terms (its rounding is
/// below `k ε` of them); below, it is summed again in twice the precision.
const CANCELLATION: f64 = 1e-8;

/// How many steps of the inner loop, per `(k+1)²`, the method may take.
const STEPS_PER_SQUARE: usize = 4;

/// How many steps of iterative refinement may follow each solve of a subsystem.
const REFINEMENTS: usize = 3;

/// Solves the LCP `(m, q)` for a symmetric positive definite `m` (scaled units); returns a `z`
/// that passes the acceptance check, or how the method stopped.
///
/// A first pass solves the subsystems by Cholesky alone; if its answer fails the check (a
/// degenerate problem whose signs that leaves in doubt), a second pass refines every solve.
pub(super) fn solve(m: &[f64], q: &[f64]) -> Result<Vec<f64>, Stop> {
    let k = q.len();
    let limit = STEPS_PER_SQUARE.saturating_mul((k + 1).saturating_mul(k + 1));
    let mut first_stop = None;
    for refined in [false, true] {
        let (z, ended) = descend(m, q, limit, refined);
        if violation(m, q, &z, &affine(m, q, &z)) <= ACCEPTANCE {
            return Ok(z);
        }
        first_stop.get_or_insert(ended.unwrap_or(Stop::Inaccurate));
    }
    Err(first_stop.unwrap_or(Stop::Inaccurate))
}

/// The method proper: its last `z ≥ 0`, and how it stopped if not at a point where every `wᵢ`
/// off `P` is nonnegative to rounding. `refined`: whether each subsystem's solution is refined
/// ([`Subsystem::solve`]).
fn descend(m: &[f64], q: &[f64], limit: usize, refined: bool) -> (Vec<f64>, Option<Stop>) {
    let k = q.len();
    let mut work = Subsystem::new(k, refined);
    let mut z = vec![0.0; k];
    let mut passive = vec![false; k];
    let mut s = vec![0.0; k];
    // The passive sets met at the start of an outer iteration, as bit sets of `words` words.
    let words = k.div_ceil(64);
    let mut visited: Vec<u64> = Vec::new();
    let mut steps = 0usize;
    loop {
        let Some(t) = entering(m, q, &z, &passive) else {
            return (z, None);
        };
        let mut set = vec![0u64; words];
        for i in (0..k).filter(|&i| passive[i]) {
            set[i / 64] |= 1 << (i % 64);
        }
        if visited
            .chunks_exact(words)
            .any(|seen| seen == set.as_slice())
        {
            return (z, Some(Stop::Cycle));
        }
        visited.extend_from_slice(&set);
        passive[t] = true;
        loop {
            steps += 1;
            if steps > limit {
                return (z, Some(Stop::IterationLimit));
            }
            if !work.solve(m, q, &passive, &mut s) {
                return (z, Some(Stop::Breakdown));
            }
            // The largest step from z towards s that keeps z ≥ 0, and the index that blocks it.
            let mut step = f64::INFINITY;
            let mut blocking = None;
            for i in (0..k).filter(|&i| passive[i]) {
                if s[i] > 0.0 {
                    continue;
                }
                let gap = z[i] - s[i];
                let ratio = if gap > 0.0 { z[i] / gap } else { 0.0 };
                if ratio < step {
                    step = ratio;
                    blocking = Some(i);
                }
            }
            let Some(blocking) = blocking else {
                z.copy_from_slice(&s);
                break;
            };
            for i in 0..k {
                if passive[i] {
                    z[i] += step * (s[i] - z[i]);
                    if i == blocking || z[i] <= 0.0 {
                        z[i] = 0.0;
                        passive[i] = false;
                    }
                }
            }
        }
    }
}

/// The index to free: among `i ∉ P` with `wᵢ` negative beyond [`NEGATIVE`] of its terms, the one
/// with the largest `wᵢ² / mᵢᵢ` (the decrease of `f` along `zᵢ` alone: free of the units of
/// each row), the first of equal ones.
fn entering(m: &[f64], q: &[f64], z: &[f64], passive: &[bool]) -> Option<usize> {
    let k = q.len();
    let mut best: Option<(usize, f64)> = None;
    for i in (0..k).filter(|&i| !passive[i]) {
        let row = &m[i * k..(i + 1) * k];
        let (mut w, mut terms) = (q[i], q[i].abs());
        for (mij, zj) in row.iter().zip(z) {
            let term = mij * zj;
            w += term;
            terms += term.abs();
        }
        if terms > 0.0 && (w.is_nan() || w.abs() <= CANCELLATION * terms) {
            // Far below its terms (a cancellation): its sign from twice the precision.
            w = dot2(q[i], row.iter().copied(), z.iter().copied());
        }
        if w.is_nan() || w >= -(NEGATIVE * terms + UNDERFLOW) {
            continue;
        }
        let decrease = w * w / row[i];
        if best.is_none_or(|(_, b)| decrease > b) {
            best = Some((i, decrease));
        }
    }
    best.map(|(i, _)| i)
}

/// The workspace of the principal subsystems `m_PP x_P = −b_P`.
struct Subsystem {
    /// Whether solutions are refined.
    refined: bool,
    index: Vec<usize>,
    l: Vec<f64>,
    x: Vec<f64>,
    r: Vec<f64>,
    y: Vec<f64>,
}

impl Subsystem {
    fn new(k: usize, refined: bool) -> Self {
        Self {
            refined,
            index: Vec::with_capacity(k),
            l: vec![0.0; k * k],
            x: vec![0.0; k],
            r: vec![0.0; k],
            y: vec![0.0; k],
        }
    }

    /// `x_P` solving `m_PP x_P = −b_P` by Cholesky, `x = 0` off `P`; `false` if a pivot is not
    /// positive and finite (`m_PP` not positive definite to working precision) or the solution
    /// is not finite.
    ///
    /// If `self.refined`, the solve is followed by up to [`REFINEMENTS`] steps of iterative
    /// refinement, the
    /// residual from `m`'s rows accumulated in twice the working precision ([`dot2`]), the
    /// correction from the factor (Higham, *Accuracy and Stability of Numerical Algorithms*,
    /// 2002, chapter 12). The factorisation's own error is relative to the whole system: a
    /// component far smaller than the others it is coupled to (`10⁻⁹` next to `1`, where `q` has
    /// entries that nearly cancel) comes out with a relative error of `10⁻⁸`, enough to give
    /// the wrong sign to a `wᵢ` computed from it; refined so, each component is accurate to
    /// about its own rounding.
    fn solve(&mut self, m: &[f64], b: &[f64], passive: &[bool], x: &mut [f64]) -> bool {
        let k = b.len();
        self.index.clear();
        self.index.extend((0..k).filter(|&i| passive[i]));
        let p = self.index.len();
        if !self.factor(m, k) {
            return false;
        }
        // x_P = −m_PP⁻¹ b_P.
        for r in 0..p {
            self.r[r] = -b[self.index[r]];
        }
        self.substitute();
        self.y[..p].copy_from_slice(&self.x[..p]);
        let refinements = if self.refined { REFINEMENTS } else { 0 };
        for _ in 0..refinements {
            // y ← y + m_PP⁻¹ (−b_P − m_PP y); done when no component moves by more than a few
            // units of its last place.
            self.residual(m, b, k);
            self.substitute();
            let mut moved = false;
            for (yr, d) in self.y[..p].iter_mut().zip(&self.x[..p]) {
                let next = *yr + d;
                moved |= next.is_nan() || (next - *yr).abs() > 4.0 * f64::EPSILON * next.abs();
                *yr = next;
            }
            if !moved {
                break;
            }
        }
        x.fill(0.0);
        for (&i, &yr) in self.index.iter().zip(&self.y) {
            x[i] = yr;
        }
        x.iter().all(|v| v.is_finite())
    }

    /// The Cholesky factor of `m_PP` into `self.l` (`p × p`, lower); `false` if a pivot is not
    /// positive and finite.
    fn factor(&mut self, m: &[f64], k: usize) -> bool {
        let (index, l) = (&self.index, &mut self.l);
        let p = index.len();
        for c in 0..p {
            let mut d = m[index[c] * k + index[c]];
            for r in 0..c {
                d -= l[c * p + r] * l[c * p + r];
            }
            if !(d > 0.0 && d.is_finite()) {
                return false;
            }
            let l_cc = d.sqrt();
            l[c * p + c] = l_cc;
            for r in c + 1..p {
                let mut s = m[index[r] * k + index[c]];
                for j in 0..c {
                    s -= l[r * p + j] * l[c * p + j];
                }
                l[r * p + c] = s / l_cc;
            }
        }
        true
    }

    /// `self.x = m_PP⁻¹ self.r` from the factor (`L y = r`, then `Lᵀ x = y`).
    fn substitute(&mut self) {
        let (l, x, r) = (&self.l, &mut self.x, &self.r);
        let p = self.index.len();
        for i in 0..p {
            let mut s = r[i];
            for j in 0..i {
                s -= l[i * p + j] * x[j];
            }
            x[i] = s / l[i * p + i];
        }
        for i in (0..p).rev() {
            let mut s = x[i];
            for j in i + 1..p {
                s -= l[j * p + i] * x[j];
            }
            x[i] = s / l[i * p + i];
        }
    }

    /// The residual `−b_P − m_PP y` into `self.r`, each row accumulated by [`dot2`].
    fn residual(&mut self, m: &[f64], b: &[f64], k: usize) {
        let p = self.index.len();
        for (row, &i) in self.index.iter().enumerate() {
            self.r[row] = -dot2(
                b[i],
                self.index.iter().map(|&j| m[i * k + j]),
                self.y[..p].iter().copied(),
            );
        }
    }
}
