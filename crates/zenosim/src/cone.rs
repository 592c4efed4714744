//! The frictional contact problem with isotropic Coulomb cones (docs/friction.md, "Contacts in
//! space: the isotropic cone"), which the LCP cannot state exactly once a contact has two
//! tangential directions.
//!
//! # The problem
//!
//! `k` contacts, contact `i` with a normal row and `dᵢ ∈ {0, 1, 2}` tangential rows, stacked in
//! `m = Σ (1 + dᵢ)` rows; a real `m×m` matrix `W` (the Delassus matrix `J M⁻¹ Jᵀ`, or one that
//! carries the kinetic friction of contacts whose slip direction is known: then not symmetric)
//! and `q`. Find `P` (impulses or forces, pushing) with `u = q + W P` and, at every contact,
//!
//! ```text
//! 0 ≤ Pₙ ⊥ uₙ ≥ 0,   |Pₜ| ≤ μ Pₙ,   uₜ = 0  or  Pₜ = −μ Pₙ uₜ/|uₜ|
//! ```
//!
//! (Coulomb's law with the isotropic cone: exactly, not a polygon; `|·|` is the Euclidean
//! length of the `dᵢ` tangential parts).
//!
//! # The method
//!
//! Alart and Curnier's equations (P. Alart, A. Curnier, "A mixed formulation for frictional
//! contact problems prone to Newton like solution methods", Comput. Methods Appl. Mech. Engrg.
//! 92 (1991) 353–375): with a scale `ρᵢ > 0` per contact, the conditions above are exactly
//!
//! ```text
//! Fₙ = Pₙ − max(0, Pₙ − ρ uₙ) = 0,
//! Fₜ = Pₜ − proj(Pₜ − ρ uₜ, disc of radius μ max(0, Pₙ)) = 0,
//! ```
//!
//! piecewise smooth in `P`. A semismooth Newton method solves `F(P) = 0`: each step solves
//! `J ΔP = −F` with an element `J` of the generalized Jacobian (least squares of least norm
//! where it is singular, as it is for dependent contacts), and a line search halves the step
//! until `½|F|²` decreases (Armijo). Near a solution the pieces no longer change and the
//! method converges quadratically, to the rounding of `u`: the answer is exact to the working
//! precision, as the LCP's is. It starts from every contact sticking (the least-norm solution
//! of `W P = −q`, cut into the cones); if that fails, from where Gauss–Seidel sweeps take it,
//! then from `P = 0`, then from a fixed sequence of impulses scattered over the cones.
//! `ρᵢ = 1/Wₙₙ` of the contact (the unit of an impulse), as Alart and Curnier suggest.

use nalgebra::{DMatrix, DVector};

/// Newton steps from one start before it is abandoned.
const ITERATIONS: usize = 100;

/// Scattered starts ([`Problem::scattered`]) tried after the three others.
const SCATTERED: usize = 16;

/// Sweeps of the Gauss–Seidel method over the contacts.
const SWEEPS: usize = 200;

/// Impulses larger than this times [`Problem::natural_scale`] are taken for a drift along
/// impulses that change no velocity, not for an answer.
const DRIFT: f64 = 1e8;

/// Halvings of a step before the line search gives up on it.
const HALVINGS: usize = 40;

/// One contact of the problem: its rows `start`, `start + 1 … start + tangents`, and its
/// coefficient of friction.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Contact {
    pub start: usize,
    pub tangents: usize,
    pub mu: f64,
}

/// Why the problem was not solved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ConeError {
    /// `W` or `q` has an entry that is not finite.
    NonFinite,
    /// Newton's method did not bring `|F|` to the rounding of the data from either start;
    /// `residual` is the best `|F|∞` relative to the impulses' scale.
    NoConvergence { residual: f64 },
}

/// The problem, with its scales.
struct Problem<'a> {
    w: &'a DMatrix<f64>,
    q: &'a DVector<f64>,
    contacts: &'a [Contact],
    rho: Vec<f64>,
}

/// `P` with `u = q + W P` meeting Coulomb's law at every contact, to the rounding of `u`
/// (module docs). `q` entries the caller knows to be rounding should be 0 already.
pub(crate) fn solve(
    w: &DMatrix<f64>,
    q: &DVector<f64>,
    contacts: &[Contact],
) -> Result<DVector<f64>, ConeError> {
    let m = q.len();
    assert!(
        w.nrows() == m
            && w.ncols() == m
            && contacts
                .iter()
                .all(|c| c.tangents <= 2 && c.start + c.tangents < m),
        "cone::solve: W is {}×{} for q of length {m}, with contacts {contacts:?}",
        w.nrows(),
        w.ncols()
    );
    if !w.iter().chain(q.iter()).all(|x| x.is_finite())
        || !contacts.iter().all(|c| c.mu.is_finite() && c.mu >= 0.0)
    {
        return Err(ConeError::NonFinite);
    }
    if m == 0 {
        return Ok(DVector::zeros(0));
    }
    let rho = contacts
        .iter()
        .map(|c| {
            let diagonal = w[(c.start, c.start)];
            if diagonal > 0.0 {
                1.0 / diagonal
            } else {
                let size = w.row(c.start).amax();
                if size > 0.0 {
                    1.0 / size
                } else {
                    1.0
                }
            }
        })
        .collect();
    let problem = Problem {
        w,
        q,
        contacts,
        rho,
    };
    let mut best = f64::INFINITY;
    let mut start = problem.sticking_start();
    // A fixed sequence of starts spread over the cones (a linear congruential generator): the
    // same problem always takes the same path.
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    for attempt in 0..3 + SCATTERED {
        match problem.newton(start.clone()) {
            Ok(p) => return Ok(p),
            Err(residual) => best = best.min(residual),
        }
        // Then from where sweeps of Gauss and Seidel take it, then from none, then from
        // scattered impulses in the cones (a start near the wedging edge of a cone, where a
        // contact's normal response to its own sliding vanishes, is found that way).
        start = match attempt {
            0 => problem.gauss_seidel(start),
            1 => DVector::zeros(m),
            _ => problem.scattered(&mut seed),
        };
    }
    Err(ConeError::NoConvergence { residual: best })
}

impl Problem<'_> {
    /// A solution `p` to rounding, cut into the cones ([`Problem::cut_into_cones`]), unless its
    /// impulses have drifted beyond [`DRIFT`] times the data's (then its velocities are
    /// rounding: `None`).
    fn accepted(&self, p: DVector<f64>) -> Option<DVector<f64>> {
        (p.amax() <= DRIFT * self.natural_scale()).then(|| self.cut_into_cones(p))
    }

    /// `p` with each contact's part cut into its cone, `Pₙ ≥ 0` and `|Pₜ| ≤ μ Pₙ`: a change at
    /// the rounding of a solution, which then meets the cones exactly.
    fn cut_into_cones(&self, mut p: DVector<f64>) -> DVector<f64> {
        for c in self.contacts {
            let normal = p[c.start].max(0.0);
            p[c.start] = normal;
            let range = c.start + 1..c.start + 1 + c.tangents;
            let size = p.rows_range(range.clone()).norm();
            let limit = c.mu * normal;
            if size > limit {
                for r in range {
                    p[r] *= limit / size;
                }
            }
        }
        p
    }

    /// Impulses spread over the cones: each `Pₙ` up to twice [`Problem::natural_scale`], each
    /// `Pₜ` anywhere in its disc, drawn from `seed` (advanced).
    fn scattered(&self, seed: &mut u64) -> DVector<f64> {
        let mut next = || {
            *seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (*seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let scale = 2.0 * self.natural_scale();
        let mut p = DVector::zeros(self.q.len());
        for c in self.contacts {
            let normal = scale * next();
            p[c.start] = normal;
            let (radius, angle) = (c.mu * normal * next(), std::f64::consts::TAU * next());
            if c.tangents == 1 {
                p[c.start + 1] = radius * angle.cos().signum();
            } else if c.tangents == 2 {
                p[c.start + 1] = radius * angle.cos();
                p[c.start + 2] = radius * angle.sin();
            }
        }
        p
    }

    /// Every contact sticking: the least-norm `P` with `W P = −q`, each contact's part cut into
    /// its cone (`Pₙ ≥ 0`, `|Pₜ| ≤ μ Pₙ`).
    fn sticking_start(&self) -> DVector<f64> {
        let m = self.q.len();
        let svd = self.w.clone().svd(true, true);
        let largest = svd.singular_values.max();
        let p = svd
            .solve(&(-self.q), 1e-12 * largest)
            .ok()
            .filter(|p| p.iter().all(|x| x.is_finite()))
            .unwrap_or_else(|| DVector::zeros(m));
        self.cut_into_cones(p)
    }

    /// Sweeps of the nonsmooth Gauss–Seidel method from `p` (M. Jean, "The non-smooth contact
    /// dynamics method", Comput. Methods Appl. Mech. Engrg. 177 (1999) 235–257): each contact's
    /// own problem solved exactly in turn, the others' impulses held. It converges, if slowly,
    /// where Newton's method from afar does not; Newton's method then finishes from its answer.
    fn gauss_seidel(&self, mut p: DVector<f64>) -> DVector<f64> {
        for _ in 0..SWEEPS {
            let mut change = 0.0_f64;
            for (i, c) in self.contacts.iter().enumerate() {
                let rows = c.start..c.start + 1 + c.tangents;
                let size = rows.len();
                let w = self.w.view((c.start, c.start), (size, size)).into_owned();
                let mut q = DVector::from_fn(size, |r, _| self.q[c.start + r]);
                for (r, row) in rows.clone().enumerate() {
                    for j in (0..p.len()).filter(|j| !rows.contains(j)) {
                        q[r] += self.w[(row, j)] * p[j];
                    }
                }
                let local = [Contact { start: 0, ..*c }];
                let own = Problem {
                    w: &w,
                    q: &q,
                    contacts: &local,
                    rho: vec![self.rho[i]],
                };
                let start = p.rows_range(rows.clone()).into_owned();
                let solved = own
                    .single()
                    .or_else(|| own.newton(start.clone()).ok())
                    .unwrap_or_else(|| own.projected(start));
                change = change.max((&solved - p.rows_range(rows.clone())).amax());
                p.rows_range_mut(rows).copy_from(&solved);
            }
            if change <= 1e-10 * p.amax() {
                break;
            }
            // Dependent contacts can push against each other without end (impulses that
            // change no velocity): the sweeps have lost their way.
            if p.amax() > DRIFT * self.natural_scale() {
                break;
            }
        }
        p
    }

    /// The size of an impulse the data call for: `ρ |q|`, the largest over the rows.
    fn natural_scale(&self) -> f64 {
        self.contacts
            .iter()
            .zip(&self.rho)
            .flat_map(|(c, &rho)| (c.start..=c.start + c.tangents).map(move |r| (r, rho)))
            .fold(f64::MIN_POSITIVE, |m, (r, rho)| {
                m.max(rho * self.q[r].abs())
            })
    }

    /// The problem of one contact (at rows 0…), solved exactly: it lets go (`qₙ ≥ 0`), or it
    /// sticks (`W P = −q` within the cone), or it slides along a unit `b` with
    /// `P = Pₙ (1, −μ b)`, `uₙ = 0`, at which `uₜ` runs along `b` (in a plane `b = ±1`; in
    /// space the angle at which `uₜ` has no part across `b`, on a ring of 720 angles,
    /// [`ring_root`]). `None` where none of these is found.
    fn single(&self) -> Option<DVector<f64>> {
        let [c] = self.contacts else { return None };
        let (w, q, size) = (self.w, self.q, 1 + c.tangents);
        if q[0] >= 0.0 {
            return Some(DVector::zeros(size));
        }
        if let Some(p) = w.clone().lu().solve(&(-q)) {
            let tangential = p.rows_range(1..size).norm();
            if p[0] >= 0.0 && tangential <= c.mu * p[0] * (1.0 + 1e-12) {
                return Some(p);
            }
        }
        // Sliding along `b`: `P = Pₙ (1, −μ b)`, `Pₙ` from `uₙ = 0`.
        let slide = |b: [f64; 2]| -> Option<(DVector<f64>, DVector<f64>)> {
            let mut direction = DVector::zeros(size);
            direction[0] = 1.0;
            for a in 0..c.tangents {
                direction[1 + a] = -c.mu * b[a];
            }
            let column = w * &direction;
            if column[0] <= 0.0 {
                return None;
            }
            let normal = -q[0] / column[0];
            Some((direction * normal, q + column * normal))
        };
        if c.tangents == 1 {
            return [[1.0, 0.0], [-1.0, 0.0]]
                .into_iter()
                .find_map(|b| slide(b).filter(|(_, u)| u[1] * b[0] > 0.0).map(|(p, _)| p));
        }
        let mut at = |angle: f64| {
            let b = [angle.cos(), angle.sin()];
            slide(b).map(|(_, u)| (b[0] * u[2] - b[1] * u[1], b[0] * u[1] + b[1] * u[2]))
        };
        // A fine ring (half a degree): an interval with an end where the contact cannot slide
        // (its normal response to its own sliding is not positive) is not searched, and the
        // slide may lie right next to such an angle (the wedging edge).
        let b = ring_root(&mut at, |along, _| along > 0.0, 720)?;
        slide(b).map(|(p, _)| p)
    }

    /// Alart and Curnier's fixed point `P ← P − F(P)` (a projection), from `p`.
    fn projected(&self, mut p: DVector<f64>) -> DVector<f64> {
        for _ in 0..ITERATIONS {
            let f = self.residual(&p, None);
            p -= &f;
        }
        p
    }

    /// Newton's method from `p`: the solution, or the best relative residual reached.
    fn newton(&self, mut p: DVector<f64>) -> Result<DVector<f64>, f64> {
        let m = self.q.len();
        let mut jacobian = DMatrix::zeros(m, m);
        let mut f = self.residual(&p, Some(&mut jacobian));
        let mut best = f64::INFINITY;
        for _ in 0..ITERATIONS {
            let (size, bound) = self.size_and_rounding(&p, &f);
            best = best.min(size);
            if size <= bound {
                return self.accepted(p).ok_or(best);
            }
            let Some(step) = newton_step(&jacobian, &f) else {
                return Err(best);
            };
            let merit = f.norm_squared();
            let mut t = 1.0;
            let mut moved = false;
            for _ in 0..HALVINGS {
                let trial = &p + t * &step;
                let f_trial = self.residual(&trial, None);
                if f_trial.norm_squared() <= (1.0 - 1e-4 * t) * merit {
                    p = trial;
                    moved = true;
                    break;
                }
                t *= 0.5;
            }
            if !moved {
                // No decrease along the step: the pieces met at `p` are not those of the
                // solution near it. A step of the fixed point `P ← P − F(P)` (Alart and
                // Curnier's projection) moves onto others.
                p -= &f;
            }
            f = self.residual(&p, Some(&mut jacobian));
        }
        let (size, bound) = self.size_and_rounding(&p, &f);
        if size <= bound {
            self.accepted(p).ok_or(best)
        } else {
            Err(best.min(size))
        }
    }

    /// `|F|` row by row relative to the size of the terms it is made of (`ρ(|q| + |W||P|)` and
    /// `|P|`, and `μ|Pₙ|` in a tangential row), the largest, and the rounding allowance on
    /// that. Row by row, so that a contact with small forces is solved as well as its own
    /// data allow, whatever the others'.
    fn size_and_rounding(&self, p: &DVector<f64>, f: &DVector<f64>) -> (f64, f64) {
        let mut size = 0.0_f64;
        for (c, &rho) in self.contacts.iter().zip(&self.rho) {
            for r in c.start..=c.start + c.tangents {
                let row: f64 = (0..p.len()).map(|j| (self.w[(r, j)] * p[j]).abs()).sum();
                let mut terms = rho * (self.q[r].abs() + row) + p[r].abs();
                if r > c.start {
                    terms += c.mu * p[c.start].abs();
                }
                if f[r] != 0.0 {
                    size = size.max(f[r].abs() / terms.max(f64::MIN_POSITIVE));
                }
            }
        }
        (size, 64.0 * f64::EPSILON)
    }

    /// `F(P)` (module docs), and an element of its generalized Jacobian in `jacobian` if asked.
    fn residual(&self, p: &DVector<f64>, mut jacobian: Option<&mut DMatrix<f64>>) -> DVector<f64> {
        let m = p.len();
        let u = self.q + self.w * p;
        let mut f = DVector::zeros(m);
        if let Some(j) = jacobian.as_deref_mut() {
            j.fill(0.0);
        }
        for (c, &rho) in self.contacts.iter().zip(&self.rho) {
            let n = c.start;
            // Normal: uₙ where it pushes (ρ uₙ), Pₙ where it lets go.
            if p[n] - rho * u[n] > 0.0 {
                f[n] = rho * u[n];
                if let Some(j) = jacobian.as_deref_mut() {
                    j.row_mut(n).copy_from(&(rho * self.w.row(n)));
                }
            } else {
                f[n] = p[n];
                if let Some(j) = jacobian.as_deref_mut() {
                    j[(n, n)] = 1.0;
                }
            }
            if c.tangents == 0 {
                continue;
            }
            let range = n + 1..n + 1 + c.tangents;
            let radius = c.mu * p[n].max(0.0);
            let x: Vec<f64> = range.clone().map(|r| p[r] - rho * u[r]).collect();
            let length = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            if length <= radius {
                // Within the cone: sticking, `ρ uₜ`.
                for r in range {
                    f[r] = rho * u[r];
                    if let Some(j) = jacobian.as_deref_mut() {
                        j.row_mut(r).copy_from(&(rho * self.w.row(r)));
                    }
                }
                continue;
            }
            // On the cone's edge: `Pₜ − r x/|x|`, `r = μ Pₙ⁺`.
            let unit: Vec<f64> = x.iter().map(|v| v / length).collect();
            for (a, r) in range.clone().enumerate() {
                f[r] = p[r] - radius * unit[a];
            }
            let Some(j) = jacobian.as_deref_mut() else {
                continue;
            };
            // ∂x/∂P = E − ρ W_t (E selects the tangential parts); ∂(x/|x|)/∂x = (I − x̂x̂ᵀ)/|x|.
            let growing = if p[n] > 0.0 { c.mu } else { 0.0 };
            for (a, r) in range.clone().enumerate() {
                j[(r, r)] += 1.0;
                j[(r, n)] -= growing * unit[a];
                for (b, s) in range.clone().enumerate() {
                    let projector = f64::from(u8::from(a == b)) - unit[a] * unit[b];
                    let weight = radius * projector / length;
                    if weight == 0.0 {
                        continue;
                    }
                    // −weight · (e_s − ρ W_s,:)
                    j[(r, s)] -= weight;
                    for col in 0..m {
                        j[(r, col)] += weight * rho * self.w[(s, col)];
                    }
                }
            }
        }
        f
    }
}

/// The Newton step `−J⁻¹F`: the least-squares step of least norm (singular values below
/// `10⁻¹²` of the largest dropped), which is `−J⁻¹F` where `J` is regular and, where it is
/// singular (dependent contacts: impulses that change no velocity), moves no impulse that
/// changes nothing; `None` where it is not finite.
fn newton_step(jacobian: &DMatrix<f64>, f: &DVector<f64>) -> Option<DVector<f64>> {
    let svd = jacobian.clone().svd(true, true);
    let largest = svd.singular_values.max();
    svd.solve(&(-f), 1e-12 * largest)
        .ok()
        .filter(|step| step.iter().all(|x| x.is_finite()))
}

/// The unit vector at the angle where `g` (the first of the pair `at` returns) vanishes and
/// the second, `along`, is largest of those `accept(along, size)` takes (`size` the largest
/// `|along|` around the ring): `g` sampled on a ring of `ring` angles, each change of sign
/// bisected to adjacent angles. `None` where no root is taken.
pub(crate) fn ring_root(
    at: &mut impl FnMut(f64) -> Option<(f64, f64)>,
    accept: impl Fn(f64, f64) -> bool,
    ring: u32,
) -> Option<[f64; 2]> {
    let step = std::f64::consts::TAU / f64::from(ring);
    let samples: Vec<Option<(f64, f64)>> = (0..=ring).map(|i| at(step * f64::from(i))).collect();
    let size = samples
        .iter()
        .flatten()
        .fold(0.0_f64, |m, &(_, a)| m.max(a.abs()));
    let mut best: Option<(f64, f64)> = None;
    for i in 1..=ring {
        let (Some((g0, _)), Some((g1, _))) = (samples[i as usize - 1], samples[i as usize]) else {
            continue;
        };
        if g0 * g1 > 0.0 {
            continue;
        }
        let angle = step * f64::from(i);
        let (mut low, mut high, mut g_low) = (angle - step, angle, g0);
        for _ in 0..64 {
            let mid = 0.5 * (low + high);
            if mid <= low || mid >= high {
                break;
            }
            let Some((g, _)) = at(mid) else { break };
            if (g <= 0.0) == (g_low <= 0.0) {
                low = mid;
                g_low = g;
            } else {
                high = mid;
            }
        }
        let root = 0.5 * (low + high);
        let Some((_, along)) = at(root) else { continue };
        if accept(along, size) && best.is_none_or(|(_, a)| along > a) {
            best = Some((root, along));
        }
    }
    best.map(|(angle, _)| [angle.cos(), angle.sin()])
}

#[cfg(test)]
#[path = "cone_tests.rs"]
mod tests;
