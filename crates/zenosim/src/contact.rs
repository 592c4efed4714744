//! The contacts at one state (docs/contact-laws.md), any number of them: the Delassus matrix of
//! a set of constraints, the motion held on the set, the impact law on the set (the generalized
//! Newton law, an LCP), the contact forces that decide which constraints hold (law 1, an LCP),
//! and the projection `R∞` onto the set.
//!
//! The run asks only the set operations at the end of this file ([`impact_law`], [`held_of`],
//! [`margin`], [`multipliers`], [`project_onto`]): one constraint is the set of size 1. For it
//! each takes the single-constraint mechanics of [`crate::mechanics`] (its traced programs, no
//! matrix), a specialisation that gives what the general law gives, in fewer operations.
//!
//! Signs: the engine's multiplier `λ` pulls when positive (the contact force is `−Aᵀλ`); the
//! laws are written with forces and impulses `f = −λ ≥ 0` that push.

use crate::execution::{ActiveSet, Grips};
use crate::friction::Frame;
use crate::lcp;
use crate::mechanics::{guard_scale, DynamicsError, Mechanics, Normal};
use crate::model::{Constraint, HybridLagrangian};
use crate::motion::dot;

/// Rounding allowance of the sums below, in units of `ε` times the size of their terms.
const ROUND_OFF: f64 = 64.0 * f64::EPSILON;

/// A Delassus matrix `W` whose Cholesky pivot falls below this fraction of its diagonal entry is
/// not positive definite enough to solve with: the constraints' gradients are dependent to
/// about twelve digits, and forces solved from it would carry relative errors of 1e-4 or more.
const DEPENDENT_PIVOT: f64 = 1e-12;

/// Below this fraction of its diagonal entry, a pivot of `W` is rounding: the gradients are
/// dependent exactly, as far as `f64` tells (a table's four legs, the same surface twice).
/// Between this and [`DEPENDENT_PIVOT`] they are nearly dependent, and the forces on the set
/// are too ill-determined to trust either way.
const ROUNDING_PIVOT: f64 = 16.0 * f64::EPSILON;

/// How far `W` is from singular.
enum Rank {
    /// Positive definite: solve with its factor.
    Full(Cholesky),
    /// Singular to rounding: the forces from the LCP, the projection by least squares.
    Deficient,
}

/// The constraints of a set at one state `(q, q̇)`: their rows `Aᵢ`, directions `M⁻¹Aᵢᵀ`, normal
/// responses, and the Delassus matrix `W = A M⁻¹ Aᵀ`.
pub(crate) struct Contacts {
    /// The set.
    pub set: ActiveSet,
    /// The constraint indices, increasing.
    pub indices: Vec<usize>,
    n: usize,
    /// `hᵢ(t, q)`.
    pub h: Vec<f64>,
    /// `|hᵢ| + Σ|Aᵢⱼ qⱼ|`, the size of `hᵢ`'s terms.
    pub h_scale: Vec<f64>,
    /// `Aᵢ`, row after row.
    gradient: Vec<f64>,
    /// `M⁻¹ Aᵢᵀ`, row after row.
    w: Vec<f64>,
    /// Each constraint's normal response under the free motion.
    pub normals: Vec<Normal>,
    /// `W`, `k × k`, row-major.
    pub delassus: Vec<f64>,
}

impl Contacts {
    /// The set's constraints at `(q, q̇)`.
    pub fn at<L: HybridLagrangian>(
        mech: &Mechanics<'_, L>,
        set: ActiveSet,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Result<Self, (DynamicsError, usize)> {
        let n = q.len();
        let indices: Vec<usize> = set.iter().collect();
        let k = indices.len();
        let mut contacts = Self {
            set,
            indices,
            n,
            h: vec![0.0; k],
            h_scale: vec![0.0; k],
            gradient: vec![0.0; k * n],
            w: vec![0.0; k * n],
            normals: Vec::with_capacity(k),
            delassus: vec![0.0; k * k],
        };
        for (row, &index) in contacts.indices.iter().enumerate() {
            let normal = mech
                .normal(index, t, q, q_dot, &mut contacts.w[row * n..(row + 1) * n])
                .map_err(|e| (e, index))?;
            contacts.normals.push(normal);
            let a = &mut contacts.gradient[row * n..(row + 1) * n];
            contacts.h[row] = mech.constraint_gradient(index, t, q, a);
            contacts.h_scale[row] = guard_scale(contacts.h[row], a, q);
        }
        for i in 0..k {
            for j in 0..k {
                // Symmetric by construction: the mean of A_i M⁻¹ A_jᵀ computed both ways.
                let ij = dot(contacts.row(i), contacts.direction(j));
                let ji = dot(contacts.row(j), contacts.direction(i));
                contacts.delassus[i * k + j] = 0.5 * (ij + ji);
            }
        }
        Ok(contacts)
    }

    /// The number of constraints.
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    /// `Aᵢ` of the `i`-th constraint of the set.
    pub fn row(&self, i: usize) -> &[f64] {
        &self.gradient[i * self.n..(i + 1) * self.n]
    }

    /// `M⁻¹Aᵢᵀ` of the `i`-th constraint of the set.
    pub fn direction(&self, i: usize) -> &[f64] {
        &self.w[i * self.n..(i + 1) * self.n]
    }

    /// `v ← v + Σ M⁻¹Aᵢᵀ xᵢ`.
    pub fn add_directions(&self, x: &[f64], v: &mut [f64]) {
        for (i, &xi) in x.iter().enumerate() {
            for (vj, wj) in v.iter_mut().zip(self.direction(i)) {
                *vj += xi * wj;
            }
        }
    }

    /// The impulses `Λ` (pushing, `M Δq̇ = Σ Aᵢᵀ Λᵢ`) that took the normal velocities from
    /// `h_dot_before` to those of this state: `W Λ = ḣ − ḣ_before` (least squares where `W` is
    /// singular to rounding).
    pub fn impulses_from(&self, h_dot_before: &[f64]) -> Result<Vec<f64>, DynamicsError> {
        let (factor, _) = self.factor_or_regularized()?;
        let change: Vec<f64> = self
            .normals
            .iter()
            .zip(h_dot_before)
            .map(|(normal, before)| normal.a_q_dot - before)
            .collect();
        Ok(factor.solve(&change))
    }

    /// Whether `W` is positive definite (with its factor), or singular to rounding; an error
    /// where it is nearly singular, with a pivot between [`ROUNDING_PIVOT`] and
    /// [`DEPENDENT_PIVOT`] of its diagonal entry.
    fn rank(&self) -> Result<Rank, DynamicsError> {
        // The first pivot below DEPENDENT_PIVOT decides: after it the factorisation means
        // nothing. One that is not a number is rounding too.
        match Cholesky::factor_or_ratio(&self.delassus, self.len(), DEPENDENT_PIVOT) {
            Ok(factor) => Ok(Rank::Full(factor)),
            Err(ratio) if ratio.is_nan() || ratio <= ROUNDING_PIVOT => Ok(Rank::Deficient),
            Err(_) => Err(DynamicsError::NearlyDependent {
                constraints: self.set,
            }),
        }
    }

    /// `W`'s Cholesky factor, or where `W` is singular to rounding that of `W + δ I` with `δ`
    /// [`ROUNDING_PIVOT`] times its largest diagonal entry: least-squares steps that treat
    /// its rounding-level directions as null and take every other one whole. The flag says
    /// which: `true` for the regularized one.
    fn factor_or_regularized(&self) -> Result<(Cholesky, bool), DynamicsError> {
        if let Rank::Full(factor) = self.rank()? {
            return Ok((factor, false));
        }
        let k = self.len();
        let largest = (0..k).map(|i| self.delassus[i * k + i]).fold(0.0, f64::max);
        let mut regularized = self.delassus.clone();
        for i in 0..k {
            regularized[i * k + i] += ROUNDING_PIVOT * largest;
        }
        // Not positive definite even so (W has an eigenvalue below minus its rounding, which
        // A M⁻¹ Aᵀ cannot have): no least-squares step exists, a numerical failure.
        let singular = |_| DynamicsError::ContactSolver {
            constraints: self.set,
            stop: lcp::Stop::Breakdown,
            conditioning: lcp::conditioning(&self.delassus, k),
        };
        let factor = Cholesky::factor_or_ratio(&regularized, k, 0.0).map_err(singular)?;
        Ok((factor, true))
    }

    /// The forces that hold the motion on every constraint of the set, and how far each
    /// constraint is from letting go (positive: it lets go).
    ///
    /// With independent gradients the multipliers solve `W λ = ḧ_free` (engine's sign: positive
    /// pulls), and a constraint lets go where its `λ` would have to pull beyond its rounding
    /// error, bounded through `|W⁻¹|` from the rounding of each `ḧ_free`. With dependent
    /// gradients (`W` singular: the legs of a table on a floor, the same surface twice) the
    /// forces are not unique, but the motion is: the forces are those of law 1's LCP
    /// (`0 ≤ f ⊥ W f + ḧ_free ≥ 0`, solved by Lemke's method; every solution gives the same
    /// `M⁻¹Aᵀf` for a positive semi-definite `W`), `λ = −f`, and a constraint lets go where
    /// its `ḧ = W f + ḧ_free` rises above its rounding.
    pub fn hold(&self) -> Result<Hold, DynamicsError> {
        let k = self.len();
        let b: Vec<f64> = self.normals.iter().map(|n| n.h_ddot_free).collect();
        if let Rank::Full(factor) = self.rank()? {
            let lambda = factor.solve(&b);
            let inverse = factor.inverse();
            let margins = (0..k)
                .map(|i| {
                    let round: f64 = (0..k)
                        .map(|j| inverse[i * k + j].abs() * self.normals[j].h_ddot_round_off)
                        .sum();
                    lambda[i] - round - ROUND_OFF * lambda[i].abs()
                })
                .collect();
            return Ok(Hold { lambda, margins });
        }
        let solution = self.solve_forces(&b)?;
        // In units of λ, as above: ḧ over W's diagonal entry.
        let margins = (0..k)
            .map(|i| {
                let h_ddot = solution.w[i] - self.acceleration_round_off(i, &solution.z);
                h_ddot / self.delassus[i * k + i]
            })
            .collect();
        let lambda = solution.z.iter().map(|f| -f).collect();
        Ok(Hold { lambda, margins })
    }

    /// The rounding error of `ḧᵢ = (W f)ᵢ + ḧ_free,i`.
    fn acceleration_round_off(&self, i: usize, f: &[f64]) -> f64 {
        let k = self.len();
        let terms: f64 = (0..k)
            .map(|j| (self.delassus[i * k + j] * f[j]).abs())
            .sum();
        self.normals[i].h_ddot_round_off + ROUND_OFF * terms
    }

    /// The held set of law 1 (resting contact): the contact forces `f ≥ 0` solve
    /// `0 ≤ f ⊥ W f + ḧ_free ≥ 0`; a constraint holds unless it accelerates away (`ḧᵢ > 0`
    /// beyond its rounding), which happens only where its force is 0.
    pub fn held_set(&self) -> Result<ActiveSet, DynamicsError> {
        let b: Vec<f64> = self.normals.iter().map(|n| n.h_ddot_free).collect();
        let solution = self.solve_forces(&b)?;
        let mut held = ActiveSet::empty();
        for i in 0..self.len() {
            if solution.w[i] <= self.acceleration_round_off(i, &solution.z) {
                held = held.with(self.indices[i]);
            }
        }
        Ok(held)
    }

    /// The impact law on the set (the generalized Newton law): the impulses `Λ ≥ 0` solve
    /// `0 ≤ Λ ⊥ W Λ + (1 + e) ∘ ḣ⁻ ≥ 0`, and `q̇⁺ = q̇⁻ + M⁻¹ Aᵀ Λ`, so that
    /// `ḣᵢ⁺ ≥ −eᵢ ḣᵢ⁻` with equality where `Λᵢ > 0` (`ḣ = A q̇ + ∂ₜh`). Returns `Λ`, in the
    /// set's order.
    pub fn impact(
        &self,
        restitution: &[f64],
        q_dot: &mut [f64],
    ) -> Result<Vec<f64>, DynamicsError> {
        let c: Vec<f64> = self
            .normals
            .iter()
            .zip(restitution)
            .map(|(n, e)| (1.0 + e) * n.a_q_dot)
            .collect();
        // A normal velocity within its rounding is 0 (docs/contact-laws.md, "The LCP solver").
        let round_off: Vec<f64> = self
            .normals
            .iter()
            .zip(restitution)
            .map(|(n, e)| (1.0 + e) * n.a_q_dot_round_off)
            .collect();
        let solution =
            lcp::solve_rounded(&self.delassus, &c, &round_off).map_err(|e| self.lcp_error(e))?;
        self.add_directions(&solution.z, q_dot);
        if q_dot.iter().all(|v| v.is_finite()) {
            Ok(solution.z)
        } else {
            Err(DynamicsError::NonFinite)
        }
    }

    /// The projection's failure, named after the constraint with the largest `|h|`.
    fn projection_error(&self) -> DynamicsError {
        let worst = (0..self.len())
            .max_by(|&i, &j| self.h[i].abs().total_cmp(&self.h[j].abs()))
            .unwrap_or(0);
        DynamicsError::Projection {
            constraint: self.indices[worst],
            residual: self.h[worst].abs(),
        }
    }

    /// Law 1's LCP `0 ≤ f ⊥ W f + ḧ_free ≥ 0` for the right-hand side `b = ḧ_free`, each
    /// entry within its rounding counting as 0 (docs/contact-laws.md, "The LCP solver").
    fn solve_forces(&self, b: &[f64]) -> Result<lcp::Solution, DynamicsError> {
        let round_off: Vec<f64> = self.normals.iter().map(|n| n.h_ddot_round_off).collect();
        lcp::solve_rounded(&self.delassus, b, &round_off).map_err(|e| self.lcp_error(e))
    }

    /// The LCP's failure: "no solution" only where it is proven; otherwise the solver's
    /// failure, with how far from singular `W` is.
    fn lcp_error(&self, error: lcp::LcpError) -> DynamicsError {
        match error {
            lcp::LcpError::NonFinite => DynamicsError::NonFinite,
            lcp::LcpError::NoSolution => DynamicsError::ContactProblem {
                constraints: self.set,
            },
            lcp::LcpError::Failed { stop, conditioning } => DynamicsError::ContactSolver {
                constraints: self.set,
                stop,
                conditioning,
            },
        }
    }
}

/// The Cholesky factor of a small symmetric positive definite matrix (`W`).
pub(crate) struct Cholesky {
    k: usize,
    l: Vec<f64>,
}

impl Cholesky {
    /// The factor of `a` (`k × k`, row-major), or the ratio to its diagonal entry of the first
    /// pivot that is not positive, finite and above `floor` times that entry.
    fn factor_or_ratio(a: &[f64], k: usize, floor: f64) -> Result<Self, f64> {
        let mut l = vec![0.0; k * k];
        for j in 0..k {
            let mut d = a[j * k + j];
            for p in 0..j {
                d -= l[j * k + p] * l[j * k + p];
            }
            let clear = d > 0.0 && d > floor * a[j * k + j] && d.is_finite();
            if !clear {
                return Err(d / a[j * k + j]);
            }
            let l_jj = d.sqrt();
            l[j * k + j] = l_jj;
            for i in j + 1..k {
                let mut s = a[i * k + j];
                for p in 0..j {
                    s -= l[i * k + p] * l[j * k + p];
                }
                l[i * k + j] = s / l_jj;
            }
        }
        Ok(Self { k, l })
    }

    /// `a⁻¹ b`.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let (k, l) = (self.k, &self.l);
        let mut y = b.to_vec();
        for i in 0..k {
            let mut s = y[i];
            for p in 0..i {
                s -= l[i * k + p] * y[p];
            }
            y[i] = s / l[i * k + i];
        }
        for i in (0..k).rev() {
            let mut s = y[i];
            for p in i + 1..k {
                s -= l[p * k + i] * y[p];
            }
            y[i] = s / l[i * k + i];
        }
        y
    }

    /// `a⁻¹`, row-major.
    pub fn inverse(&self) -> Vec<f64> {
        let k = self.k;
        let mut inverse = vec![0.0; k * k];
        let mut e = vec![0.0; k];
        for j in 0..k {
            e.iter_mut().for_each(|x| *x = 0.0);
            e[j] = 1.0;
            for (i, x) in self.solve(&e).into_iter().enumerate() {
                inverse[i * k + j] = x;
            }
        }
        inverse
    }
}

/// What holds the motion on a set: [`Contacts::hold`].
pub(crate) struct Hold {
    /// The multipliers, in the set's order (engine's sign: the contact force is `−Aᵀλ`).
    pub lambda: Vec<f64>,
    /// How far each constraint is from letting go: positive where it does.
    pub margins: Vec<f64>,
}

impl Hold {
    /// The largest margin: positive where some constraint of the set lets go.
    pub fn margin(&self) -> f64 {
        self.margins
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The motion held on a set of two or more constraints: `q̈ = M⁻¹f − Σ M⁻¹Aᵢᵀ λᵢ` with the
/// multipliers of [`Contacts::hold`], into `q_ddot`; returns the contacts and the hold.
pub(crate) fn held_acceleration<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
    q_ddot: &mut [f64],
) -> Result<(Contacts, Hold), DynamicsError> {
    mech.acceleration(t, q, q_dot, None, q_ddot)?;
    let contacts = Contacts::at(mech, set, t, q, q_dot).map_err(|(e, _)| e)?;
    let hold = contacts.hold()?;
    let minus: Vec<f64> = hold.lambda.iter().map(|l| -l).collect();
    contacts.add_directions(&minus, q_ddot);
    if q_ddot.iter().chain(&hold.lambda).all(|x| x.is_finite()) {
        Ok((contacts, hold))
    } else {
        Err(DynamicsError::NonFinite)
    }
}

/// `R∞` onto a set: `q` onto `hᵢ = 0` for every constraint of the set by Newton steps along
/// `M⁻¹Aᵀ` (`W δ = h`, `q ← q − M⁻¹Aᵀ δ`), then `q̇` by the plastic projection onto `ḣ = 0`
/// (`W μ = ḣ`, `q̇ ← q̇ − M⁻¹Aᵀ μ`), which keeps every momentum the constraints do not touch.
/// Where the gradients are dependent, `W + δ I` takes `W`'s place (least-squares steps), and the
/// velocity is projected twice.
pub(crate) fn project<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    t: f64,
    q: &mut [f64],
    q_dot: &mut [f64],
) -> Result<(), DynamicsError> {
    const MAX_NEWTON: usize = 30;
    let name_first = |e: (DynamicsError, usize)| e.0;
    let mut best = f64::INFINITY;
    for _ in 0..MAX_NEWTON {
        let c = Contacts::at(mech, set, t, q, q_dot).map_err(name_first)?;
        if !c.h.iter().all(|h| h.is_finite()) {
            return Err(DynamicsError::NonFinite);
        }
        let (factor, deficient) = c.factor_or_regularized()?;
        // Each h against the size of its terms: the largest relative residual decides.
        let size =
            c.h.iter()
                .zip(&c.h_scale)
                .map(|(h, s)| h.abs() / s.max(1.0))
                .fold(0.0, f64::max);
        if size <= 4.0 * f64::EPSILON || size >= best {
            let a_q_dot: Vec<f64> = c.normals.iter().map(|n| n.a_q_dot).collect();
            let mu: Vec<f64> = factor.solve(&a_q_dot).iter().map(|m| -m).collect();
            c.add_directions(&mu, q_dot);
            if deficient {
                // What W + δI left of A q̇ (about 16 ε of it), taken out once more.
                let rest: Vec<f64> = (0..c.len())
                    .map(|i| dot(c.row(i), q_dot) + c.normals[i].h_t)
                    .collect();
                let mu: Vec<f64> = factor.solve(&rest).iter().map(|m| -m).collect();
                c.add_directions(&mu, q_dot);
            }
            // A deficient set may be inconsistent by rounding of its geometry (a table's legs
            // coplanar to 1e-11): its least-squares residual is accepted up to 1e-9.
            let accepted = if deficient { 1e-9 } else { 1e-12 };
            if size > accepted {
                return Err(c.projection_error());
            }
            return Ok(());
        }
        best = size;
        let delta: Vec<f64> = factor.solve(&c.h).iter().map(|d| -d).collect();
        c.add_directions(&delta, q);
    }
    let c = Contacts::at(mech, set, t, q, q_dot).map_err(name_first)?;
    Err(c.projection_error())
}

/// What the impact law did on a set: the impulses `Λ` (pushing, in the set's order), and from
/// each constraint's normal velocity before and after (`ḣ⁻`, `ḣ⁺ = ḣ⁻ + (W Λ)ᵢ`, the law's own)
/// and `∂ₜh`, its loss `−½ Σ Λᵢ (ḣᵢ⁺ + ḣᵢ⁻)` and the work `−Σ Λᵢ ∂ₜhᵢ` of the impulses on
/// surfaces that move (docs/forces-and-time.md): the energy balance without evaluating again.
pub(crate) struct ImpactLaw {
    pub impulses: Vec<f64>,
    /// The tangential impulses where the set has friction, in the model's slip components
    /// (the second 0 in a plane; empty without friction).
    pub tangential: Vec<[f64; 2]>,
    pub loss: f64,
    pub work: f64,
}

impl ImpactLaw {
    /// The law's impulses `impulses`, with the loss and work from the normal velocities before
    /// and after and `∂ₜh` of each constraint (given by `each(i)` for the `i`-th).
    fn new(impulses: Vec<f64>, each: impl Fn(usize) -> (f64, f64, f64)) -> Self {
        let mut loss = 0.0;
        let mut work = 0.0;
        for (i, &impulse) in impulses.iter().enumerate() {
            let (h_dot_before, h_dot_after, h_t) = each(i);
            loss -= 0.5 * impulse * (h_dot_after + h_dot_before);
            work -= impulse * h_t;
        }
        Self {
            impulses,
            tangential: Vec::new(),
            loss,
            work,
        }
    }
}

/// The impact law on `set` at `(t, q, q̇)`, `q̇` updated in place (docs/contact-laws.md, law
/// 2): the generalized Newton law, an LCP, with each constraint's restitution from
/// `constraints` (the model's). For one constraint the law is the paper's map `P`,
/// `Λ = −(1 + e) ḣ⁻/(A M⁻¹ Aᵀ)`, from the mechanics of that constraint, whose normal response
/// at this state is `reached`.
pub(crate) fn impact_law<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    reached: &Normal,
    constraints: &[Constraint],
    t: f64,
    q: &[f64],
    q_dot: &mut [f64],
) -> Result<ImpactLaw, (DynamicsError, usize)> {
    if mech.frictional(set) {
        let frame = Frame::at(mech, set, t, q, q_dot)?;
        let restitution: Vec<f64> = frame
            .indices
            .iter()
            .map(|&i| constraints[i].restitution)
            .collect();
        let h_t: Vec<f64> = frame.normals.iter().map(|n| n.h_t).collect();
        let first = frame.indices[0];
        let law = frame
            .impact(set, &restitution, &h_t, q_dot)
            .map_err(|err| (err, first))?;
        return Ok(ImpactLaw {
            impulses: law.normal,
            tangential: law.tangent,
            loss: law.loss,
            work: law.work,
        });
    }
    if let Some(index) = set.only() {
        let e = constraints[index].restitution;
        mech.impact(index, e, t, q, q_dot)
            .map_err(|err| (err, index))?;
        // Pushing, so not below 0 (at rest, `A q̇` may round to either side of it).
        let impulse = -(1.0 + e) * reached.a_q_dot / reached.s;
        let impulse = if impulse > 0.0 { impulse } else { 0.0 };
        // The law's own normal velocity after it: ḣ⁺ = ḣ⁻ + s Λ.
        let after = reached.a_q_dot + reached.s * impulse;
        return Ok(ImpactLaw::new(vec![impulse], |_| {
            (reached.a_q_dot, after, reached.h_t)
        }));
    }
    let contacts = Contacts::at(mech, set, t, q, q_dot)?;
    let first = contacts.indices[0];
    let restitution: Vec<f64> = contacts
        .indices
        .iter()
        .map(|&i| constraints[i].restitution)
        .collect();
    let impulses = contacts
        .impact(&restitution, q_dot)
        .map_err(|err| (err, first))?;
    let k = contacts.len();
    let after: Vec<f64> = (0..k)
        .map(|i| {
            let row = &contacts.delassus[i * k..(i + 1) * k];
            let before = contacts.normals[i].a_q_dot;
            before + row.iter().zip(&impulses).map(|(w, l)| w * l).sum::<f64>()
        })
        .collect();
    Ok(ImpactLaw::new(impulses, |i| {
        let normal = &contacts.normals[i];
        (normal.a_q_dot, after[i], normal.h_t)
    }))
}

/// Law 1 on the constraints `closed` at `(t, q, q̇)`: those that hold, and the friction states
/// of those with friction (docs/contact-laws.md, law 1; docs/friction.md).
pub(crate) fn decide<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    closed: ActiveSet,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
    w: &mut [f64],
) -> Result<(ActiveSet, Grips), (DynamicsError, usize)> {
    if !mech.frictional(closed) {
        return held_of(mech, closed, t, q, q_dot, w).map(|held| (held, Grips::none()));
    }
    let frame = Frame::at(mech, closed, t, q, q_dot)?;
    let first = frame.indices[0];
    let decision = frame.decide(closed).map_err(|err| (err, first))?;
    Ok((decision.held, decision.grips))
}

/// The constraints of `closed` that hold at `(t, q, q̇)` (docs/contact-laws.md, law 1): those
/// that would not have to pull. One constraint holds while its lift margin is not positive.
fn held_of<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    closed: ActiveSet,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
    w: &mut [f64],
) -> Result<ActiveSet, (DynamicsError, usize)> {
    if closed.is_empty() {
        return Ok(closed);
    }
    if let Some(index) = closed.only() {
        let normal = mech
            .normal(index, t, q, q_dot, w)
            .map_err(|err| (err, index))?;
        return Ok(if normal.lift_margin() > 0.0 {
            ActiveSet::empty()
        } else {
            closed
        });
    }
    let contacts = Contacts::at(mech, closed, t, q, q_dot)?;
    let first = contacts.indices[0];
    contacts.held_set().map_err(|err| (err, first))
}

/// How far the constraints held in `set` are from letting go at `(t, q, q̇)`: the largest lift
/// margin, positive where one of them would have to pull (docs/contact-laws.md, law 1). One
/// constraint: its [`Normal::lift_margin`]. `w` and `acc` are scratch of the model's dimension.
/// With friction, from any transition of the friction states `grips` too, each margin divided
/// by its scale in `scales` ([`Frame::margins`]).
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn margin<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    scales: &[f64],
    t: f64,
    q: &[f64],
    q_dot: &[f64],
    w: &mut [f64],
    acc: &mut [f64],
) -> Result<f64, DynamicsError> {
    if mech.frictional(set) {
        let frame = Frame::of(mech, set, t, q, q_dot)?;
        let forces = frame.forces(set, grips)?;
        return Ok(frame.margins(&forces, grips, scales));
    }
    match set.only() {
        Some(index) => Ok(mech.normal(index, t, q, q_dot, w)?.lift_margin()),
        None => Ok(held_acceleration(mech, set, t, q, q_dot, acc)?.1.margin()),
    }
}

/// `q̈` of the motion held on `set` at `(t, q, q̇)` into `q_ddot`: free where the set is empty,
/// the single-constraint mechanics' for one, [`held_acceleration`] for several.
pub(crate) fn acceleration<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
    q_ddot: &mut [f64],
) -> Result<(), DynamicsError> {
    if mech.frictional(set) {
        let frame = Frame::of(mech, set, t, q, q_dot)?;
        let forces = frame.forces(set, grips)?;
        q_ddot.copy_from_slice(&forces.q_ddot);
        return Ok(());
    }
    if set.len() <= 1 {
        return mech
            .acceleration(t, q, q_dot, set.only(), q_ddot)
            .map(|_| ());
    }
    held_acceleration(mech, set, t, q, q_dot, q_ddot).map(|_| ())
}

/// The lift margins of the constraints held in `set`, each with its constraint's index, in the
/// set's order: [`margin`] constraint by constraint (without friction).
pub(crate) fn margins<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> Result<Vec<(usize, f64)>, DynamicsError> {
    let n = q.len();
    if let Some(index) = set.only() {
        let mut w = vec![0.0; n];
        return Ok(vec![(
            index,
            mech.normal(index, t, q, q_dot, &mut w)?.lift_margin(),
        )]);
    }
    let mut acc = vec![0.0; n];
    let (contacts, hold) = held_acceleration(mech, set, t, q, q_dot, &mut acc)?;
    Ok(contacts.indices.into_iter().zip(hold.margins).collect())
}

/// The multipliers `λᵢ` that hold the motion on `set` at `(t, q, q̇)` (engine's sign: the
/// contact force is `−Aᵢᵀλᵢ`), each with its constraint's index and `∂ₜhᵢ`, in the set's order.
/// One constraint: `λ = ḧ_free/(A M⁻¹ Aᵀ)` from its mechanics. `w` is scratch of the model's
/// dimension. With friction (in the states `grips`), `each` also has each contact's tangential
/// force `fₜ`, slip `s` and the slip's part `s₀ = s − S q̇` that the surface's own motion gives,
/// in the model's slip components (the second 0 in a plane; all 0 without friction).
#[allow(clippy::too_many_arguments)]
pub(crate) fn multipliers<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
    w: &mut [f64],
    mut each: impl FnMut(usize, f64, f64, [f64; 2], [f64; 2], [f64; 2]),
) -> Result<(), DynamicsError> {
    let n = q.len();
    if mech.frictional(set) {
        let frame = Frame::of(mech, set, t, q, q_dot)?;
        let forces = frame.forces(set, grips)?;
        for p in 0..frame.len() {
            let (mut f, mut s, mut s0) = ([0.0; 2], [0.0; 2], [0.0; 2]);
            if let Some(t) = &frame.tangents[p] {
                f = forces.components(p, t);
                for (c, slip) in t.components_slips().enumerate() {
                    let moving: f64 = slip.row.iter().zip(q_dot).map(|(a, v)| a * v).sum();
                    (s[c], s0[c]) = (slip.s, slip.s - moving);
                }
            }
            let normal = &frame.normals[p];
            each(frame.indices[p], -forces.normal[p], normal.h_t, f, s, s0);
        }
        return Ok(());
    }
    if let Some(index) = set.only() {
        let normal = mech.normal(index, t, q, q_dot, w)?;
        each(
            index,
            normal.lambda(),
            normal.h_t,
            [0.0; 2],
            [0.0; 2],
            [0.0; 2],
        );
        return Ok(());
    }
    if set.is_empty() {
        return Ok(());
    }
    let mut acc = vec![0.0; n];
    let (contacts, hold) = held_acceleration(mech, set, t, q, q_dot, &mut acc)?;
    for ((&index, lambda), normal) in contacts
        .indices
        .iter()
        .zip(hold.lambda)
        .zip(&contacts.normals)
    {
        each(index, lambda, normal.h_t, [0.0; 2], [0.0; 2], [0.0; 2]);
    }
    Ok(())
}

/// `R∞` onto the constraints of `set` at `y = (q, q̇)` (nothing where the set is empty): one
/// constraint's projection ([`Mechanics::project`]), or [`project`] onto the set; then, where
/// contacts of it stick (`grips`), the velocities onto their `s = 0` too (docs/friction.md).
pub(crate) fn project_onto<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    t: f64,
    n: usize,
    y: &mut [f64],
) -> Result<(), DynamicsError> {
    let (q, q_dot) = y.split_at_mut(n);
    match set.only() {
        _ if set.is_empty() => return Ok(()),
        Some(index) => mech.project(index, t, q, q_dot).map(|_| ())?,
        None => project(mech, set, t, q, q_dot)?,
    }
    let stick = grips.stick.intersection(set);
    if stick.is_empty() {
        return Ok(());
    }
    let frame = Frame::of(mech, set, t, q, q_dot)?;
    frame.stop_slip(set, stick, q_dot).map(|_| ())
}

/// The contacts of `set` that slip in the states `grips` and whose slip has reached 0 at
/// `y = (q, q̇)` (it is 0 or has turned against their direction: a root of their slip margin),
/// their slips set to 0 by the plastic projection, jointly with `ḣ = 0` on `set` and `s = 0` on
/// those that stick already (docs/friction.md): law 1 then decides from rest whether they
/// stick, with the static cone, or slip on, either way. The contacts stopped.
pub(crate) fn stop_reached_slips<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    scales: &[f64],
    t: f64,
    n: usize,
    y: &mut [f64],
) -> Result<ActiveSet, DynamicsError> {
    let slipping = grips.slipping().intersection(set);
    if slipping.is_empty() {
        return Ok(slipping);
    }
    let (q, q_dot) = y.split_at_mut(n);
    let frame = Frame::of(mech, set, t, q, q_dot)?;
    let mut stopped = ActiveSet::empty();
    for (p, &index) in frame.indices.iter().enumerate() {
        if slipping.contains(index) && frame.slip_stopped(p, grips, scales) {
            stopped = stopped.with(index);
        }
    }
    if !stopped.is_empty() {
        frame.stop_slip(set, grips.stick.intersection(set).union(stopped), q_dot)?;
    }
    Ok(stopped)
}

/// At a Zeno point switched `duration` before the point, the kinetic friction the held
/// motion on `set` in the states `grips` would add over that time taken back from `y`'s
/// velocities ([`Frame::unwind_slip`]), then `R∞` onto `set` again.
pub(crate) fn unwind_slip<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    t: f64,
    n: usize,
    y: &mut [f64],
    duration: f64,
) -> Result<(), DynamicsError> {
    if grips.slipping().intersection(set).is_empty() || duration <= 0.0 {
        return Ok(());
    }
    {
        let (q, q_dot) = y.split_at_mut(n);
        let frame = Frame::of(mech, set, t, q, q_dot)?;
        frame.unwind_slip(set, grips, duration, q_dot)?;
    }
    project_onto(mech, set, grips, t, n, y)
}

/// At a Zeno point onto `set` at `y = (q, q̇)`, `duration` before it: every contact stopped,
/// normal and tangential velocities, where the impulses that takes are within the static cones
/// ([`Frame::stick_all`]); whether it was done.
pub(crate) fn stick_all<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    t: f64,
    n: usize,
    y: &mut [f64],
    duration: f64,
) -> Result<bool, DynamicsError> {
    let (q, q_dot) = y.split_at_mut(n);
    let frame = Frame::of(mech, set, t, q, q_dot)?;
    frame.stick_all(set, duration, q_dot)
}

/// The scales of the margins of the contacts held in `set` in the friction states `grips` at
/// `(t, q, q̇)` ([`Frame::scales`]): taken when a mode with friction starts.
pub(crate) fn scales<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> Result<Vec<f64>, DynamicsError> {
    let frame = Frame::of(mech, set, t, q, q_dot)?;
    let forces = frame.forces(set, grips)?;
    Ok(frame.scales(&forces))
}

/// With contacts in space that slip in `grips`, the directions of their slip margins renewed to
/// their slips at `(t, q, q̇)` ([`Frame::renew_directions`]); nothing for contacts in a plane.
#[allow(clippy::too_many_arguments)]
pub(crate) fn renew_slip_directions<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
    scales: &mut [f64],
) -> Result<(), DynamicsError> {
    let model = mech.model();
    let in_space = grips
        .slipping()
        .intersection(set)
        .iter()
        .any(|i| model.constraints()[i].friction.is_some() && model.slip_components(i) == 2);
    if !in_space {
        return Ok(());
    }
    let frame = Frame::of(mech, set, t, q, q_dot)?;
    frame.renew_directions(grips, scales);
    Ok(())
}

/// The change of state at a root where law 1 still sees the old states, with friction
/// ([`Frame::worst_change`]): the held set and friction states after it.
pub(crate) fn worst_change<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    grips: Grips,
    scales: &[f64],
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> Result<(ActiveSet, Grips), DynamicsError> {
    let frame = Frame::of(mech, set, t, q, q_dot)?;
    let forces = frame.forces(set, grips)?;
    Ok(frame.worst_change(set, &forces, grips, scales))
}
