//! Friction at contacts at one state (docs/friction.md): each contact's slip, the forces of a
//! set held in known friction states, law 1 with friction (which contacts hold, stick or
//! slip: an LCP), and the impact law with friction (Newton and Coulomb: an LCP at the level of
//! velocities, never creating energy).
//!
//! Signs: forces and impulses push (`fₙ ≥ 0`); a tangential force `fₜ` acts along `Sᵀ`, so a
//! positive one drives the slip `s` up. The engine's multiplier is `λ = −fₙ`.

use nalgebra::{DMatrix, DVector};
use num_dual::Dual64;

use crate::execution::{ActiveSet, Grips};
use crate::lcp;
use crate::mechanics::{DynamicsError, Mechanics, Normal};
use crate::model::HybridLagrangian;
use crate::motion::dot;

/// Rounding allowance of the sums below, in units of `ε` times the size of their terms.
const ROUND_OFF: f64 = 64.0 * f64::EPSILON;

/// The slip of a contact at one state (docs/friction.md): `s`, its row `S = ∂s/∂q̇`, the part
/// of `ṡ` that `q̈` does not give, `σ = (∂s/∂q) q̇ + ∂s/∂t`, and the size of `s`'s terms.
#[derive(Clone, Debug)]
pub(crate) struct Slip {
    pub s: f64,
    pub row: Vec<f64>,
    pub sigma: f64,
    /// `Σ|Sₖ q̇ₖ| + |s − S q̇|`: rounding the velocities changes `s` by about `ε` times this.
    pub scale: f64,
}

/// The slip of constraint `index`'s contact at `(t, q, q̇)`, by first-order duals: one pass per
/// velocity for `S`, one along `(q̇, 1)` in `(q, t)` for `σ`.
pub(crate) fn slip<L: HybridLagrangian>(
    model: &L,
    index: usize,
    t: f64,
    q: &[f64],
    q_dot: &[f64],
) -> Slip {
    let n = q.len();
    let fixed: Vec<Dual64> = q.iter().map(|&x| Dual64::from_re(x)).collect();
    let mut velocities: Vec<Dual64> = q_dot.iter().map(|&v| Dual64::from_re(v)).collect();
    let time = Dual64::from_re(t);
    let mut row = vec![0.0; n];
    for k in 0..n {
        velocities[k].eps = 1.0;
        row[k] = model.slip(index, time, &fixed, &velocities).eps;
        velocities[k].eps = 0.0;
    }
    let along: Vec<Dual64> = q
        .iter()
        .zip(q_dot)
        .map(|(&x, &v)| Dual64::new(x, v))
        .collect();
    let pass = model.slip(index, Dual64::new(t, 1.0), &along, &velocities);
    let s = pass.re;
    let moving: f64 = row.iter().zip(q_dot).map(|(a, v)| a * v).sum();
    let scale = row
        .iter()
        .zip(q_dot)
        .map(|(a, v)| (a * v).abs())
        .sum::<f64>()
        + (s - moving).abs();
    Slip {
        s,
        row,
        sigma: pass.eps,
        scale,
    }
}

/// A frictional contact's tangential side at one state.
pub(crate) struct Tangent {
    pub mu_static: f64,
    pub mu_kinetic: f64,
    pub slip: Slip,
    /// `M⁻¹ Sᵀ`.
    direction: Vec<f64>,
    /// `ṡ` under the free motion: `S M⁻¹ F + σ`.
    pub s_dot_free: f64,
    /// The rounding error of `ṡ_free`.
    pub s_dot_round_off: f64,
    /// The slip speed below which the contact is at rest ([`Mechanics::slip_floor`]).
    floor: f64,
}

impl Tangent {
    /// Whether the contact's slip is 0: to its rounding, or below the run's floor.
    pub fn at_rest(&self) -> bool {
        self.slip.s.abs() <= (ROUND_OFF * self.slip.scale).max(self.floor)
    }
}

/// The LCP's failure on `set`: "no solution" (proven) is Painlevé's paradox; a failure of the
/// solver is the solver's, not the model's.
fn lcp_error(set: ActiveSet, error: lcp::LcpError) -> DynamicsError {
    match error {
        lcp::LcpError::NonFinite => DynamicsError::NonFinite,
        lcp::LcpError::NoSolution => paradox(set),
        lcp::LcpError::Failed { stop, conditioning } => DynamicsError::ContactSolver {
            constraints: set,
            stop,
            conditioning,
        },
    }
}

/// `x` with `g x = rhs` for a square `g` that may be singular where contacts are dependent
/// (two corners of a block on one floor slip along the same direction: their sticking rows
/// are equal): the least-squares solution of least norm (singular values below `1e-12` of
/// the largest dropped), accepted where it solves the system to `1e-9` of its scale; `None`
/// where the system is inconsistent or not finite.
fn solve_least_norm(g: &DMatrix<f64>, rhs: &DVector<f64>) -> Option<DVector<f64>> {
    if rhs.is_empty() {
        return Some(DVector::zeros(0));
    }
    let svd = g.clone().svd(true, true);
    let largest = svd.singular_values.max();
    if !largest.is_finite() {
        return None;
    }
    let x = svd.solve(rhs, 1e-12 * largest).ok()?;
    let residual = (g * &x - rhs).amax();
    let scale = rhs.amax() + g.abs().column_sum().amax() * x.amax();
    (x.iter().all(|v| v.is_finite()) && residual <= 1e-9 * scale).then_some(x)
}

/// Why the contact problem with friction has no answer.
fn paradox(set: ActiveSet) -> DynamicsError {
    DynamicsError::Painleve { constraints: set }
}

/// The contacts of a set at one state `(t, q, q̇)`, with their friction: the normal rows `Aᵢ`
/// and directions `M⁻¹Aᵢᵀ` and responses, and for those with friction, their tangential side.
pub(crate) struct Frame {
    n: usize,
    /// The constraint indices, increasing.
    pub indices: Vec<usize>,
    pub normals: Vec<Normal>,
    rows: Vec<f64>,
    directions: Vec<f64>,
    pub tangents: Vec<Option<Tangent>>,
    /// `q̈` of the free motion.
    acc_free: Vec<f64>,
    /// `M`, row-major.
    mass: Vec<f64>,
}

/// The forces of a held set in known friction states, and the motion they give.
pub(crate) struct Forces {
    /// `fₙ` of each contact, in the set's order.
    pub normal: Vec<f64>,
    /// `fₜ` of each contact (0 without friction), in the set's order.
    pub tangent: Vec<f64>,
    /// `q̈`.
    pub q_ddot: Vec<f64>,
}

/// What the impact law with friction did: the normal and tangential impulses in the set's order,
/// its loss and the work of the moving surfaces' impulses.
pub(crate) struct FrictionalImpact {
    pub normal: Vec<f64>,
    pub tangent: Vec<f64>,
    pub loss: f64,
    pub work: f64,
}

/// The friction states law 1 gives a set (docs/friction.md): the constraints that hold, and the
/// states of those with friction.
pub(crate) struct Decision {
    pub held: ActiveSet,
    pub grips: Grips,
}

impl Frame {
    /// The contacts of `set` at `(t, q, q̇)`.
    pub fn at<L: HybridLagrangian>(
        mech: &Mechanics<'_, L>,
        set: ActiveSet,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Result<Self, (DynamicsError, usize)> {
        let n = q.len();
        let model = mech.model();
        let first = set.iter().next().unwrap_or(0);
        let mut mass = vec![0.0; n * n];
        mech.mass_matrix(t, q, q_dot, &mut mass)
            .map_err(|e| (e, first))?;
        let factor = DMatrix::from_row_slice(n, n, &mass)
            .cholesky()
            .ok_or((DynamicsError::MassMatrix, first))?;
        let mut acc_free = vec![0.0; n];
        mech.acceleration(t, q, q_dot, None, &mut acc_free)
            .map_err(|e| (e, first))?;
        let indices: Vec<usize> = set.iter().collect();
        let k = indices.len();
        let mut frame = Self {
            n,
            indices,
            normals: Vec::with_capacity(k),
            rows: vec![0.0; k * n],
            directions: vec![0.0; k * n],
            tangents: Vec::with_capacity(k),
            acc_free,
            mass,
        };
        for p in 0..k {
            let index = frame.indices[p];
            let normal = mech
                .normal(
                    index,
                    t,
                    q,
                    q_dot,
                    &mut frame.directions[p * n..(p + 1) * n],
                )
                .map_err(|e| (e, index))?;
            frame.normals.push(normal);
            mech.constraint_gradient(index, t, q, &mut frame.rows[p * n..(p + 1) * n]);
            let frictional = mech.frictional(ActiveSet::single(index));
            let tangent = model.constraints()[index]
                .friction
                .filter(|_| frictional)
                .map(|friction| {
                    let slip = slip(model, index, t, q, q_dot);
                    let direction = factor.solve(&DVector::from_column_slice(&slip.row));
                    let direction: Vec<f64> = direction.iter().copied().collect();
                    let along: f64 = dot(&slip.row, &frame.acc_free);
                    let terms: f64 = slip
                        .row
                        .iter()
                        .zip(&frame.acc_free)
                        .map(|(a, x)| (a * x).abs())
                        .sum();
                    Tangent {
                        mu_static: friction.static_coefficient,
                        mu_kinetic: friction.kinetic_coefficient,
                        s_dot_free: along + slip.sigma,
                        s_dot_round_off: ROUND_OFF * (terms + slip.sigma.abs()),
                        floor: mech.slip_floor(),
                        slip,
                        direction,
                    }
                });
            frame.tangents.push(tangent);
        }
        Ok(frame)
    }

    /// [`Frame::at`], its error without the constraint it names.
    pub fn of<L: HybridLagrangian>(
        mech: &Mechanics<'_, L>,
        set: ActiveSet,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Result<Self, DynamicsError> {
        Self::at(mech, set, t, q, q_dot).map_err(|(e, _)| e)
    }

    /// The number of contacts.
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    fn row(&self, p: usize) -> &[f64] {
        &self.rows[p * self.n..(p + 1) * self.n]
    }

    fn direction(&self, p: usize) -> &[f64] {
        &self.directions[p * self.n..(p + 1) * self.n]
    }

    /// Row `r` of the contacts' rows `A₁ … A_k` followed by the slip rows `S` of the contacts
    /// `extra` (positions in the frame, each with friction).
    fn stacked_row(&self, extra: &[usize], r: usize) -> &[f64] {
        let k = self.len();
        if r < k {
            self.row(r)
        } else {
            &self.tangent(extra[r - k]).slip.row
        }
    }

    /// Column `r` of `M⁻¹` times the rows of [`Frame::stacked_row`]: `M⁻¹Aᵀ`, then `M⁻¹Sᵀ`.
    fn stacked_direction(&self, extra: &[usize], r: usize) -> &[f64] {
        let k = self.len();
        if r < k {
            self.direction(r)
        } else {
            &self.tangent(extra[r - k]).direction
        }
    }

    /// The tangential side of the contact at position `p`, which has friction.
    fn tangent(&self, p: usize) -> &Tangent {
        self.tangents[p]
            .as_ref()
            .expect("a sticking or candidate contact has friction")
    }

    /// The kinetic energy `½ q̇ᵀ M q̇`.
    fn kinetic(&self, q_dot: &[f64]) -> f64 {
        let n = self.n;
        (0..n)
            .map(|i| q_dot[i] * dot(&self.mass[i * n..(i + 1) * n], q_dot))
            .sum::<f64>()
            * 0.5
    }

    /// The forces that hold the motion on every contact of the frame in the friction states
    /// `grips`: the normal forces, the sticking contacts' tangential forces (`ṡ = 0`), the
    /// slipping contacts' kinetic ones, and the motion. An error where the states admit no
    /// unique motion (Painlevé's paradox: the system is singular, or the normal forces of the
    /// slipping contacts would grow as their normal accelerations fall).
    pub fn forces(&self, set: ActiveSet, grips: Grips) -> Result<Forces, DynamicsError> {
        let k = self.len();
        let n = self.n;
        // The unknowns: every normal force, then the sticking contacts' tangential forces.
        let stick: Vec<usize> = (0..k)
            .filter(|&p| grips.stick.contains(self.indices[p]) && self.tangents[p].is_some())
            .collect();
        let size = k + stick.len();
        // Each unknown's column, M⁻¹ applied: a normal force's along M⁻¹Aᵀ, less μₖ times M⁻¹Sᵀ
        // in its slip's direction where it slips; a tangential force's along M⁻¹Sᵀ.
        let mut columns = vec![0.0; size * n];
        for p in 0..k {
            let column = &mut columns[p * n..(p + 1) * n];
            column.copy_from_slice(self.direction(p));
            let sign = grips.direction(self.indices[p]);
            if let (Some(t), true) = (&self.tangents[p], sign != 0.0) {
                for (c, d) in column.iter_mut().zip(&t.direction) {
                    *c -= t.mu_kinetic * sign * d;
                }
            }
        }
        for (u, &p) in stick.iter().enumerate() {
            columns[(k + u) * n..(k + u + 1) * n].copy_from_slice(&self.tangent(p).direction);
        }
        let mut g = DMatrix::zeros(size, size);
        let mut rhs = DVector::zeros(size);
        for r in 0..size {
            for c in 0..size {
                g[(r, c)] = dot(self.stacked_row(&stick, r), &columns[c * n..(c + 1) * n]);
            }
            rhs[r] = -if r < k {
                self.normals[r].h_ddot_free
            } else {
                self.tangent(stick[r - k]).s_dot_free
            };
        }
        // The states are given: the forces solve a square system, which is singular only where
        // the contacts are dependent (then the forces of least norm: the motion is the same for
        // all that solve it). Whether the states are consistent, a normal force that pulls
        // says (a margin), and law 1 decides again (`decide`, where Painlevé's paradox shows).
        let x = solve_least_norm(&g, &rhs).ok_or_else(|| paradox(set))?;
        let mut q_ddot = self.acc_free.clone();
        for c in 0..size {
            for (a, col) in q_ddot.iter_mut().zip(&columns[c * n..(c + 1) * n]) {
                *a += x[c] * col;
            }
        }
        let normal: Vec<f64> = (0..k).map(|p| x[p]).collect();
        let mut tangent = vec![0.0; k];
        for p in 0..k {
            let sign = grips.direction(self.indices[p]);
            if let (Some(t), true) = (&self.tangents[p], sign != 0.0) {
                tangent[p] = -t.mu_kinetic * sign * normal[p];
            }
        }
        for (u, &p) in stick.iter().enumerate() {
            tangent[p] = x[k + u];
        }
        if !q_ddot
            .iter()
            .chain(&normal)
            .chain(&tangent)
            .all(|x| x.is_finite())
        {
            return Err(DynamicsError::NonFinite);
        }
        Ok(Forces {
            normal,
            tangent,
            q_ddot,
        })
    }

    /// How far each contact of the held frame is from a transition in the states `grips`,
    /// positive where one happens (docs/friction.md): a normal force that would pull, a
    /// sticking contact's tangential force beyond the cone (`|fₜ| − μₛ fₙ`), a slipping contact's
    /// slip past 0 (`−s` in its direction). Each is divided by the fixed scale `scales` gives
    /// it (one per contact and kind, [`Frame::scales`]), so that they compare.
    pub fn margins(&self, forces: &Forces, grips: Grips, scales: &[f64]) -> f64 {
        let mut largest = f64::NEG_INFINITY;
        for p in 0..self.len() {
            let index = self.indices[p];
            let f = forces.normal[p];
            // The rounding of the normal force, from that of ḧ_free through A M⁻¹ Aᵀ.
            let round = self.normals[p].h_ddot_round_off / self.normals[p].s + ROUND_OFF * f.abs();
            largest = largest.max((-f - round) / scales[3 * p]);
            if let Some(t) = &self.tangents[p] {
                if grips.stick.contains(index) {
                    // Beyond the cone by more than the rounding of the forces.
                    let beyond = forces.tangent[p].abs()
                        - t.mu_static * f
                        - ROUND_OFF * (forces.tangent[p].abs() + t.mu_static * f.abs())
                        - t.mu_static * round;
                    largest = largest.max(beyond / scales[3 * p + 1]);
                } else {
                    let sign = grips.direction(index);
                    if sign != 0.0 {
                        largest = largest.max(-sign * t.slip.s / scales[3 * p + 2]);
                    }
                }
            }
        }
        largest
    }

    /// The change of state the largest margin of [`Frame::margins`] stands for: the contact
    /// lets go (its normal force), starts to slip against its tangential force (its cone), or
    /// sticks (its slip): the held set and friction states after it.
    pub fn worst_change(
        &self,
        set: ActiveSet,
        forces: &Forces,
        grips: Grips,
        scales: &[f64],
    ) -> (ActiveSet, Grips) {
        let mut best = (f64::NEG_INFINITY, 0, 0);
        for p in 0..self.len() {
            let index = self.indices[p];
            let f = forces.normal[p];
            let round = self.normals[p].h_ddot_round_off / self.normals[p].s + ROUND_OFF * f.abs();
            let mut consider = |margin: f64, kind: usize| {
                if margin > best.0 {
                    best = (margin, p, kind);
                }
            };
            consider((-f - round) / scales[3 * p], 0);
            if let Some(t) = &self.tangents[p] {
                if grips.stick.contains(index) {
                    // Beyond the cone by more than the rounding of the forces.
                    let beyond = forces.tangent[p].abs()
                        - t.mu_static * f
                        - ROUND_OFF * (forces.tangent[p].abs() + t.mu_static * f.abs())
                        - t.mu_static * round;
                    consider(beyond / scales[3 * p + 1], 1);
                } else {
                    let sign = grips.direction(index);
                    if sign != 0.0 {
                        consider(-sign * t.slip.s / scales[3 * p + 2], 2);
                    }
                }
            }
        }
        let (_, p, kind) = best;
        let index = self.indices[p];
        let only = ActiveSet::single(index);
        let mut grips = grips;
        let mut held = set;
        match kind {
            0 => held = set.minus(only),
            1 => {
                grips.stick = grips.stick.minus(only);
                // It slips against the force that held it at the cone's edge.
                if forces.tangent[p] > 0.0 {
                    grips.backward = grips.backward.with(index);
                } else {
                    grips.forward = grips.forward.with(index);
                }
            }
            _ => {
                grips.forward = grips.forward.minus(only);
                grips.backward = grips.backward.minus(only);
                grips.stick = grips.stick.with(index);
            }
        }
        (held, grips.within(held))
    }

    /// The scales of [`Frame::margins`] in the states `grips`, three per contact: its normal
    /// force, its tangential force, its slip, each the largest of its size now and its rounding
    /// (taken when a mode starts, and kept through it).
    pub fn scales(&self, forces: &Forces) -> Vec<f64> {
        let mut scales = Vec::with_capacity(3 * self.len());
        let force_scale = forces
            .normal
            .iter()
            .chain(&forces.tangent)
            .fold(0.0_f64, |m, f| m.max(f.abs()))
            .max(f64::MIN_POSITIVE);
        for p in 0..self.len() {
            scales.push(force_scale);
            scales.push(force_scale);
            let slip = self.tangents[p]
                .as_ref()
                .map_or(1.0, |t| t.slip.s.abs().max(t.slip.scale))
                .max(f64::MIN_POSITIVE);
            scales.push(slip);
        }
        scales
    }

    /// The LCP of Pfeiffer and Glocker on the frame's contacts (docs/friction.md), in the
    /// unknowns `(fₙ, a, ṡ⁻)` (or their impulses): each contact's normal column `M⁻¹(Aᵀ − μ Sᵀ)`
    /// with its entry of `mu` (the static coefficient for a candidate, the kinetic one times
    /// the slip's direction for a contact that slips, 0 without friction), each candidate's
    /// `a` along `M⁻¹Sᵀ`; the right-hand side `normal_q` in the normal rows and `slip_q` of each
    /// candidate in its slip row; then `ṡ⁺ = ṡ + ṡ⁻` and `2 μₛ fₙ − a ≥ 0 ⊥ ṡ⁻`. Row-major
    /// matrix and right-hand side, of size `k + 2m`, and the columns (`k + m` of them, each of
    /// the model's dimension) that give the velocities' change from `(fₙ, a)`.
    fn coulomb_lcp(
        &self,
        candidates: &[usize],
        mu: &[f64],
        normal_q: &[f64],
        slip_q: impl Fn(&Tangent) -> f64,
    ) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (k, n, m) = (self.len(), self.n, candidates.len());
        let size = k + 2 * m;
        let tangent = |p: usize| self.tangent(p);
        // The columns of the forces fₙ and a (M⁻¹ applied).
        let mut columns = vec![0.0; (k + m) * n];
        for p in 0..k {
            let column = &mut columns[p * n..(p + 1) * n];
            column.copy_from_slice(self.direction(p));
            if let Some(t) = &self.tangents[p] {
                for (c, d) in column.iter_mut().zip(&t.direction) {
                    *c -= mu[p] * d;
                }
            }
        }
        for (u, &p) in candidates.iter().enumerate() {
            columns[(k + u) * n..(k + u + 1) * n].copy_from_slice(&tangent(p).direction);
        }
        let mut matrix = vec![0.0; size * size];
        let mut q = vec![0.0; size];
        for r in 0..k + m {
            let row = self.stacked_row(candidates, r);
            for c in 0..k + m {
                matrix[r * size + c] = dot(row, &columns[c * n..(c + 1) * n]);
            }
            q[r] = if r < k {
                normal_q[r]
            } else {
                slip_q(tangent(candidates[r - k]))
            };
        }
        for (u, &p) in candidates.iter().enumerate() {
            matrix[(k + u) * size + (k + m + u)] = 1.0;
            let r = k + m + u;
            matrix[r * size + p] = 2.0 * tangent(p).mu_static;
            matrix[r * size + (k + u)] = -1.0;
        }
        (matrix, q, columns)
    }

    /// Law 1 with friction (docs/friction.md): of the frame's contacts (closed: at rest on their
    /// surfaces), which hold, and which of those with friction stick or slip. A contact whose
    /// slip is 0 to its rounding is a candidate to stick, with the static coefficient; one that
    /// slips keeps its slip's direction, with the kinetic one. The LCP of Pfeiffer and Glocker
    /// in the forces `fₙ`, `a = fₜ + μₛ fₙ` and `ṡ⁻`. An error where it has no solution
    /// (Painlevé's paradox).
    pub fn decide(&self, set: ActiveSet) -> Result<Decision, DynamicsError> {
        let k = self.len();
        let candidates: Vec<usize> = (0..k)
            .filter(|&p| self.tangents[p].as_ref().is_some_and(Tangent::at_rest))
            .collect();
        let m = candidates.len();
        // Where every contact can hold, those at rest sticking and the others slipping on, in
        // equilibrium (every normal force pushing, every sticking force within its static
        // cone), that is law 1's answer: the contact problem with friction may have others
        // (a block resting on two rough corners could also pivot on one, its friction
        // lifting the other), and a run at rest must stay at rest.
        if let Some(decision) = self.all_held(set, &candidates) {
            return Ok(decision);
        }
        let size = k + 2 * m;
        // Contacts at rest enter with μₛ, the others with μₖ in their slip's direction.
        let mu: Vec<f64> = self
            .tangents
            .iter()
            .map(|t| {
                t.as_ref().map_or(0.0, |t| {
                    if t.at_rest() {
                        t.mu_static
                    } else {
                        t.mu_kinetic * t.slip.s.signum()
                    }
                })
            })
            .collect();
        let normal_q: Vec<f64> = self.normals.iter().map(|n| n.h_ddot_free).collect();
        let (matrix, q, _) = self.coulomb_lcp(&candidates, &mu, &normal_q, |t| t.s_dot_free);
        let round_off: Vec<f64> = (0..size)
            .map(|r| {
                if r < k {
                    self.normals[r].h_ddot_round_off
                } else if r < k + m {
                    self.tangents[candidates[r - k]]
                        .as_ref()
                        .map_or(0.0, |t| t.s_dot_round_off)
                } else {
                    0.0
                }
            })
            .collect();
        let solution =
            lcp::solve_rounded(&matrix, &q, &round_off).map_err(|e| lcp_error(set, e))?;
        let (z, w) = (&solution.z, &solution.w);
        let mut held = ActiveSet::empty();
        for p in 0..k {
            let terms: f64 = (0..size).map(|c| (matrix[p * size + c] * z[c]).abs()).sum();
            let round = self.normals[p].h_ddot_round_off + ROUND_OFF * terms;
            if w[p] <= round {
                held = held.with(self.indices[p]);
            }
        }
        let mut grips = Grips::none();
        for p in 0..k {
            let index = self.indices[p];
            let Some(t) = &self.tangents[p] else { continue };
            if !held.contains(index) {
                continue;
            }
            if !t.at_rest() {
                if t.slip.s > 0.0 {
                    grips.forward = grips.forward.with(index);
                } else {
                    grips.backward = grips.backward.with(index);
                }
                continue;
            }
            let u = candidates
                .iter()
                .position(|&c| c == p)
                .expect("a contact at rest is a candidate");
            let forward = w[k + u];
            let backward = z[k + m + u];
            let round = t.s_dot_round_off
                + ROUND_OFF
                    * (0..size)
                        .map(|c| (matrix[(k + u) * size + c] * z[c]).abs())
                        .sum::<f64>();
            // The slip's acceleration ṡ = ṡ⁺ − ṡ⁻ (both may be positive where no normal force
            // bounds the tangential one).
            let s_ddot = forward - backward;
            if s_ddot < -round {
                grips.backward = grips.backward.with(index);
            } else if s_ddot > round {
                grips.forward = grips.forward.with(index);
            } else {
                grips.stick = grips.stick.with(index);
            }
        }
        Ok(Decision { held, grips })
    }

    /// Every contact of `set` held, those of `candidates` (at rest) sticking, the others slipping
    /// in their slip's direction, if that is consistent: every normal force pushes, and every
    /// sticking force is within its static cone (to rounding). `None` otherwise.
    fn all_held(&self, set: ActiveSet, candidates: &[usize]) -> Option<Decision> {
        let mut grips = Grips::none();
        for p in 0..self.len() {
            let Some(t) = &self.tangents[p] else { continue };
            let index = self.indices[p];
            if candidates.contains(&p) {
                grips.stick = grips.stick.with(index);
            } else if t.slip.s > 0.0 {
                grips.forward = grips.forward.with(index);
            } else {
                grips.backward = grips.backward.with(index);
            }
        }
        let forces = self.forces(set, grips).ok()?;
        for p in 0..self.len() {
            let f = forces.normal[p];
            let round = self.normals[p].h_ddot_round_off / self.normals[p].s + ROUND_OFF * f.abs();
            if f < -round {
                return None;
            }
            if let Some(t) = &self.tangents[p] {
                if candidates.contains(&p)
                    && forces.tangent[p].abs()
                        > t.mu_static * f + ROUND_OFF * (f.abs() + forces.tangent[p].abs())
                {
                    return None;
                }
            }
        }
        Some(Decision { held: set, grips })
    }

    /// The impact law with friction on the frame's contacts (docs/friction.md): the generalized
    /// Newton law with the restitutions `restitution` (in the set's order) and Coulomb's law on
    /// the slip after the impact, `q̇` updated in place. A contact sticks through the impact
    /// where the static cone allows; one that slips does so at the kinetic coefficient. Where
    /// the law with the model's restitutions would create energy (beyond rounding), the
    /// restitutions are scaled down to the largest fraction that does not (bisection; without
    /// restitution the law never creates energy).
    pub fn impact(
        &self,
        set: ActiveSet,
        restitution: &[f64],
        h_t: &[f64],
        q_dot: &mut [f64],
    ) -> Result<FrictionalImpact, DynamicsError> {
        let before = q_dot.to_vec();
        let t_before = self.kinetic(&before);
        let approach: Vec<f64> = self.normals.iter().map(|normal| normal.a_q_dot).collect();
        let attempt =
            |scale: f64, out: &mut [f64]| -> Result<(Vec<f64>, Vec<f64>), DynamicsError> {
                out.copy_from_slice(&before);
                let e: Vec<f64> = restitution.iter().map(|e| e * scale).collect();
                self.impact_with(set, &e, &approach, out)
            };
        let mut after = before.clone();
        let (mut normal, mut tangent) = attempt(1.0, &mut after)?;
        // The law creates energy where its own loss `−½ Σ Λₙ (ḣ⁺ + ḣ⁻) − ½ Σ Λₜ (s⁺ + s⁻)` is
        // negative beyond rounding (what a surface that moves puts in is not the law's).
        let gained = |result: &(Vec<f64>, Vec<f64>), after: &[f64]| {
            let (loss, _) = self.loss_and_work(&result.0, &result.1, h_t, &before, after);
            loss < -ROUND_OFF * (t_before + self.kinetic(after))
        };
        if restitution.iter().any(|&e| e > 0.0)
            && gained(&(normal.clone(), tangent.clone()), &after)
        {
            // Bisection on the fraction of the restitutions: 0 never gains (docs/friction.md).
            let (mut low, mut high) = (0.0, 1.0);
            let mut best = attempt(0.0, &mut after)?;
            let mut best_after = after.clone();
            for _ in 0..48 {
                let mid = 0.5 * (low + high);
                let result = attempt(mid, &mut after)?;
                if gained(&result, &after) {
                    high = mid;
                } else {
                    low = mid;
                    best = result;
                    best_after.copy_from_slice(&after);
                }
            }
            (normal, tangent) = best;
            after = best_after;
        }
        q_dot.copy_from_slice(&after);
        let (loss, work) = self.loss_and_work(&normal, &tangent, h_t, &before, &after);
        Ok(FrictionalImpact {
            normal,
            tangent,
            loss,
            work,
        })
    }

    /// An impact's loss `−½ Σ Λₙ (ḣ⁺ + ḣ⁻) − ½ Σ Λₜ (s⁺ + s⁻)` and its impulses' work on the
    /// surfaces that move, `−Σ Λₙ ∂ₜh − Σ Λₜ s₀` (`s₀ = s − S q̇`: a belt's own velocity), from the
    /// velocities before and after.
    fn loss_and_work(
        &self,
        normal: &[f64],
        tangent: &[f64],
        h_t: &[f64],
        before: &[f64],
        after: &[f64],
    ) -> (f64, f64) {
        let mut loss = 0.0;
        let mut work = 0.0;
        for p in 0..self.len() {
            let h_before = dot(self.row(p), before) + h_t[p];
            let h_after = dot(self.row(p), after) + h_t[p];
            loss -= 0.5 * normal[p] * (h_after + h_before);
            work -= normal[p] * h_t[p];
            if let Some(t) = &self.tangents[p] {
                let s0 = t.slip.s - dot(&t.slip.row, before);
                let s_before = t.slip.s;
                let s_after = dot(&t.slip.row, after) + s0;
                loss -= 0.5 * tangent[p] * (s_after + s_before);
                work -= tangent[p] * s0;
            }
        }
        (loss, work)
    }

    /// The plastic impact with friction (`e = 0`) on the frame's contacts, each taken to
    /// approach at the normal velocity `approach` (in the set's order) instead of its own, `q̇`
    /// updated: the normal impulses that stop those approaches, and the tangential impulses
    /// Coulomb's law allows with them (docs/friction.md, Zeno points).
    pub fn plastic(
        &self,
        set: ActiveSet,
        approach: &[f64],
        q_dot: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let plastic = vec![0.0; self.len()];
        self.impact_with(set, &plastic, approach, q_dot).map(|_| ())
    }

    /// The impact law with friction for the restitutions `e`, each contact approaching at the
    /// normal velocity `approach` (its own `ḣ⁻`, for an impact), from `q̇` (updated): the
    /// normal and tangential impulses. Contacts that slip in the static solve are solved again
    /// with the kinetic coefficient in their slip's direction, until the directions agree.
    fn impact_with(
        &self,
        set: ActiveSet,
        e: &[f64],
        approach: &[f64],
        q_dot: &mut [f64],
    ) -> Result<(Vec<f64>, Vec<f64>), DynamicsError> {
        let k = self.len();
        let n = self.n;
        let before = q_dot.to_vec();
        // Contacts fixed to slip at the kinetic coefficient, with their direction.
        let mut sliding: Vec<f64> = vec![0.0; k];
        // Each pass only moves contacts from the static cone to sliding: k + 1 passes suffice.
        for _ in 0..=k {
            let candidates: Vec<usize> = (0..k)
                .filter(|&p| self.tangents[p].is_some() && sliding[p] == 0.0)
                .collect();
            let m = candidates.len();
            let size = k + 2 * m;
            let mu: Vec<f64> = (0..k)
                .map(|p| {
                    self.tangents[p].as_ref().map_or(0.0, |t| {
                        if sliding[p] == 0.0 {
                            t.mu_static
                        } else {
                            t.mu_kinetic * sliding[p]
                        }
                    })
                })
                .collect();
            let normal_q: Vec<f64> = (0..k).map(|r| (1.0 + e[r]) * approach[r]).collect();
            let (matrix, q, columns) = self.coulomb_lcp(&candidates, &mu, &normal_q, |t| t.slip.s);
            // Each right-hand side within the rounding of the velocities it is made of is 0.
            let round_off: Vec<f64> = (0..size)
                .map(|r| {
                    if r < k {
                        let terms: f64 = self
                            .row(r)
                            .iter()
                            .zip(&before)
                            .map(|(a, v)| (a * v).abs())
                            .sum();
                        ROUND_OFF * (1.0 + e[r]) * (terms + approach[r].abs())
                    } else if r < k + m {
                        self.tangents[candidates[r - k]]
                            .as_ref()
                            .map_or(0.0, |t| ROUND_OFF * t.slip.scale)
                    } else {
                        0.0
                    }
                })
                .collect();
            let solution =
                lcp::solve_rounded(&matrix, &q, &round_off).map_err(|err| lcp_error(set, err))?;
            let z = &solution.z;
            q_dot.copy_from_slice(&before);
            for c in 0..k + m {
                for (v, col) in q_dot.iter_mut().zip(&columns[c * n..(c + 1) * n]) {
                    *v += z[c] * col;
                }
            }
            let normal: Vec<f64> = (0..k).map(|p| z[p]).collect();
            let mut tangent = vec![0.0; k];
            let mut changed = false;
            for p in 0..k {
                let Some(t) = &self.tangents[p] else { continue };
                if sliding[p] != 0.0 {
                    tangent[p] = -t.mu_kinetic * sliding[p] * normal[p];
                    // The slip it was fixed to must still run that way after the impact.
                    let s0 = t.slip.s - dot(&t.slip.row, &before);
                    let s_after = dot(&t.slip.row, q_dot) + s0;
                    if sliding[p] * s_after < -ROUND_OFF * t.slip.scale {
                        return Err(paradox(set));
                    }
                    continue;
                }
                let u = candidates
                    .iter()
                    .position(|&c| c == p)
                    .expect("a free contact is a candidate");
                tangent[p] = z[k + u] - t.mu_static * normal[p];
                // Slipping at the cone's edge with a kinetic coefficient below the static:
                // solve again with it, in the slip's direction.
                let on_edge = z[k + u] <= 0.0 || z[k + m + u] > 0.0;
                if t.mu_kinetic < t.mu_static && normal[p] > 0.0 && on_edge {
                    let s0 = t.slip.s - dot(&t.slip.row, &before);
                    let s_after = dot(&t.slip.row, q_dot) + s0;
                    if s_after.abs() > ROUND_OFF * t.slip.scale {
                        sliding[p] = s_after.signum();
                        changed = true;
                    }
                }
            }
            if !changed {
                return Ok((normal, tangent));
            }
        }
        Err(paradox(set))
    }
}

impl Frame {
    /// At a Zeno point onto `set`, `duration` before it: the plastic projection that stops
    /// every contact, normal and tangential velocities, if the impulses of the impacts not
    /// taken can be that within the static cones. Those impacts last `duration`, over which
    /// the contacts also carry the body (the forces `F` of the set held, every contact
    /// sticking): each contact's impulse `Λ + F duration` must push and have its tangential
    /// part within `μₛ` times its normal one, to rounding. The accumulated impacts then stick,
    /// as each of them would (Housner's rocking block). `q̇` is changed only then; whether it
    /// was is returned.
    pub fn stick_all(
        &self,
        set: ActiveSet,
        duration: f64,
        q_dot: &mut [f64],
    ) -> Result<bool, DynamicsError> {
        let stick = (0..self.len())
            .filter(|&p| self.tangents[p].is_some())
            .fold(ActiveSet::empty(), |s, p| s.with(self.indices[p]));
        let grips = Grips {
            stick,
            ..Grips::none()
        };
        let Ok(held) = self.forces(set, grips) else {
            return Ok(false);
        };
        let mut trial = q_dot.to_vec();
        let mu = self.stop_slip(set, stick, &mut trial)?;
        let k = self.len();
        let mut u = k;
        for p in 0..k {
            if -mu[p] + held.normal[p] * duration < -ROUND_OFF * mu[p].abs() {
                return Ok(false);
            }
            let Some(t) = &self.tangents[p] else { continue };
            let normal = -mu[p] + held.normal[p] * duration;
            let tangent = -mu[u] + held.tangent[p] * duration;
            u += 1;
            let round = ROUND_OFF * (normal.abs() + tangent.abs());
            if normal < -round || tangent.abs() > t.mu_static * normal.max(0.0) + round {
                return Ok(false);
            }
        }
        q_dot.copy_from_slice(&trial);
        Ok(true)
    }

    /// Takes back from `q̇` what the kinetic friction of the contacts slipping in `grips` will
    /// add over `duration` (`M⁻¹ Sᵀ fₜ` each): at a Zeno point the held motion starts at the
    /// switch, `duration` before the point, while the impacts not taken, whose tangential
    /// impulses are applied in full, last until it (docs/friction.md). Nothing where a slip
    /// would reverse over `duration`.
    pub fn unwind_slip(
        &self,
        set: ActiveSet,
        grips: Grips,
        duration: f64,
        q_dot: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let forces = self.forces(set, grips)?;
        let mut change = vec![0.0; self.n];
        for p in 0..self.len() {
            let Some(t) = &self.tangents[p] else { continue };
            if grips.direction(self.indices[p]) == 0.0 {
                continue;
            }
            for (c, d) in change.iter_mut().zip(&t.direction) {
                *c -= forces.tangent[p] * duration * d;
            }
        }
        for p in 0..self.len() {
            let Some(t) = &self.tangents[p] else { continue };
            let sign = grips.direction(self.indices[p]);
            if sign != 0.0 && sign * (t.slip.s + dot(&t.slip.row, &change)) <= 0.0 {
                return Ok(());
            }
        }
        for (v, c) in q_dot.iter_mut().zip(&change) {
            *v += c;
        }
        Ok(())
    }

    /// The plastic projection of the velocities `q̇` (the frame's own) onto `ḣ = 0` on every
    /// contact of `set` and `s = 0` on those of `stick`, jointly: `W μ = (ḣ, s)`,
    /// `q̇ ← q̇ − M⁻¹ Bᵀ μ` with `B` the rows `Aᵢ` and `Sⱼ` (it keeps every momentum they do not
    /// touch). Returns `μ`: minus the impulses, normal ones first (the set's order), then the
    /// sticking contacts' tangential ones.
    pub fn stop_slip(
        &self,
        set: ActiveSet,
        stick: ActiveSet,
        q_dot: &mut [f64],
    ) -> Result<Vec<f64>, DynamicsError> {
        let n = self.n;
        let k = self.len();
        let sticking: Vec<usize> = (0..k)
            .filter(|&p| stick.contains(self.indices[p]) && self.tangents[p].is_some())
            .collect();
        let size = k + sticking.len();
        let row = |r: usize| self.stacked_row(&sticking, r);
        let direction = |r: usize| self.stacked_direction(&sticking, r);
        let w = DMatrix::from_fn(size, size, |r, c| dot(row(r), direction(c)));
        let rhs = DVector::from_fn(size, |r, _| {
            if r < k {
                self.normals[r].a_q_dot
            } else {
                self.tangent(sticking[r - k]).slip.s
            }
        });
        let mu = solve_least_norm(&w, &rhs).ok_or_else(|| paradox(set))?;
        for r in 0..size {
            for (v, d) in q_dot.iter_mut().zip(direction(r)) {
                *v -= mu[r] * d;
            }
        }
        if q_dot.iter().all(|v| v.is_finite()) && q_dot.len() == n {
            Ok(mu.iter().copied().collect())
        } else {
            Err(DynamicsError::NonFinite)
        }
    }
}
