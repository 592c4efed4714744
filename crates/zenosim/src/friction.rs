//! Friction at contacts at one state (docs/friction.md): each contact's slip, the forces of a
//! set held in known friction states, law 1 with friction (which contacts hold, stick or
//! slip: an LCP), and the impact law with friction (Newton and Coulomb: an LCP at the level of
//! velocities, never creating energy).
//!
//! Signs: forces and impulses push (`fₙ ≥ 0`); a tangential force `fₜ` acts along `Sᵀ`, so a
//! positive one drives the slip `s` up. The engine's multiplier is `λ = −fₙ`.

use nalgebra::{DMatrix, DVector};
use num_dual::Dual64;

use crate::cone::{self, ring_root};
use crate::execution::{ActiveSet, Grips};
use crate::lcp;
use crate::mechanics::{DynamicsError, Mechanics, Normal};
use crate::model::HybridLagrangian;
use crate::motion::dot;

/// Rounding allowance of the sums below, in units of `ε` times the size of their terms.
const ROUND_OFF: f64 = 64.0 * f64::EPSILON;

/// Sweeps over the contacts in space that slip from rest before their directions must agree.
const SETTLE_SWEEPS: usize = 50;

/// How many numbers [`Frame::scales`] keeps per contact.
const SCALES: usize = 5;

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

/// Component `component` of the slip of constraint `index`'s contact at `(t, q, q̇)`, by
/// first-order duals: one pass per velocity for `S`, one along `(q̇, 1)` in `(q, t)` for `σ`.
pub(crate) fn slip<L: HybridLagrangian>(
    model: &L,
    index: usize,
    component: usize,
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
        row[k] = model.slip(index, component, time, &fixed, &velocities).eps;
        velocities[k].eps = 0.0;
    }
    let along: Vec<Dual64> = q
        .iter()
        .zip(q_dot)
        .map(|(&x, &v)| Dual64::new(x, v))
        .collect();
    let pass = model.slip(index, component, Dual64::new(t, 1.0), &along, &velocities);
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

impl Slip {
    /// The slip along `w` of the two components `a` and `b`: `w₁ a + w₂ b`.
    fn along(a: &Slip, b: &Slip, w: [f64; 2]) -> Slip {
        Slip {
            s: w[0] * a.s + w[1] * b.s,
            row: a
                .row
                .iter()
                .zip(&b.row)
                .map(|(x, y)| w[0] * x + w[1] * y)
                .collect(),
            sigma: w[0] * a.sigma + w[1] * b.sigma,
            scale: w[0].abs() * a.scale + w[1].abs() * b.scale,
        }
    }
}

/// One direction of a contact's slip at one state: the slip along it, `M⁻¹ Sᵀ`, and `ṡ` under
/// the free motion with its rounding.
#[derive(Clone, Debug)]
pub(crate) struct Part {
    pub slip: Slip,
    /// `M⁻¹ Sᵀ`.
    direction: Vec<f64>,
    /// `ṡ` under the free motion: `S M⁻¹ F + σ`.
    pub s_dot_free: f64,
    /// The rounding error of `ṡ_free`.
    pub s_dot_round_off: f64,
}

impl Part {
    /// Component `component` of constraint `index`'s slip, with `M⁻¹` from `factor` and the
    /// free motion's `q̈`.
    fn of<L: HybridLagrangian>(
        model: &L,
        index: usize,
        component: usize,
        (t, q, q_dot): (f64, &[f64], &[f64]),
        factor: &nalgebra::Cholesky<f64, nalgebra::Dyn>,
        acc_free: &[f64],
    ) -> Self {
        let slip = slip(model, index, component, t, q, q_dot);
        let direction = factor.solve(&DVector::from_column_slice(&slip.row));
        let direction: Vec<f64> = direction.iter().copied().collect();
        let along: f64 = dot(&slip.row, acc_free);
        let terms: f64 = slip
            .row
            .iter()
            .zip(acc_free)
            .map(|(a, x)| (a * x).abs())
            .sum();
        Part {
            s_dot_free: along + slip.sigma,
            s_dot_round_off: ROUND_OFF * (terms + slip.sigma.abs()),
            slip,
            direction,
        }
    }

    /// The part along `w` of the two components `a` and `b` (everything is linear in them).
    fn along(a: &Part, b: &Part, w: [f64; 2]) -> Part {
        Part {
            slip: Slip::along(&a.slip, &b.slip, w),
            direction: a
                .direction
                .iter()
                .zip(&b.direction)
                .map(|(x, y)| w[0] * x + w[1] * y)
                .collect(),
            s_dot_free: w[0] * a.s_dot_free + w[1] * b.s_dot_free,
            s_dot_round_off: w[0].abs() * a.s_dot_round_off + w[1].abs() * b.s_dot_round_off,
        }
    }
}

/// A contact in space (docs/friction.md): its two slip components, the unit vector `basis`
/// (in their plane) its [`Tangent`]'s main part runs along, and the part `cross` across it,
/// along `(−basis₂, basis₁)`. Slipping, the main part runs along the slip (the cross part's
/// slip is 0); sticking, both are held.
#[derive(Clone, Debug)]
pub(crate) struct Space {
    parts: [Part; 2],
    pub basis: [f64; 2],
    pub cross: Part,
}

/// A frictional contact's tangential side at one state: in a plane, its one slip; in space,
/// the slip along [`Space::basis`] (the slip's own direction while it slips).
#[derive(Clone, Debug)]
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
    /// A contact in space: its second slip direction.
    pub space: Option<Box<Space>>,
}

impl Tangent {
    /// Whether the contact's slip is 0: to its rounding, or below the run's floor (in space,
    /// the slip's length).
    pub fn at_rest(&self) -> bool {
        let (size, scale) = match &self.space {
            None => (self.slip.s.abs(), self.slip.scale),
            Some(space) => (
                self.slip.s.hypot(space.cross.slip.s),
                self.slip.scale + space.cross.slip.scale,
            ),
        };
        size <= (ROUND_OFF * scale).max(self.floor)
    }

    /// In space, whether the slip is small enough for its direction to be the one the forces
    /// drive it in ([`Frame::settled`]) rather than its own: at most `√floor` (`10⁻⁵` for the
    /// default tolerance). Across a slip that small the kinetic force damps any turn of the
    /// slip at the rate `μₖ fₙ/|s|` (times the response across), far faster than a step can
    /// follow: the slip's own direction, off by its rounding, would make the motion unstable,
    /// while the direction of the forces is where that damping takes it.
    fn settling(&self) -> bool {
        let v = self.slip_vector();
        let scale = self.slip.scale + self.space.as_ref().map_or(0.0, |s| s.cross.slip.scale);
        v[0].hypot(v[1]) <= self.floor.sqrt().max(ROUND_OFF * scale)
    }

    /// The slip in the model's components: `(s, 0)` in a plane.
    pub fn slip_vector(&self) -> [f64; 2] {
        match &self.space {
            None => [self.slip.s, 0.0],
            Some(space) => {
                let [b1, b2] = space.basis;
                let c = space.cross.slip.s;
                [b1 * self.slip.s - b2 * c, b2 * self.slip.s + b1 * c]
            }
        }
    }

    /// The slip's components in the model's terms: the one in a plane, the two in space.
    pub fn components_slips(&self) -> impl Iterator<Item = &Slip> {
        let parts = self
            .space
            .as_ref()
            .map(|space| [&space.parts[0].slip, &space.parts[1].slip]);
        match parts {
            None => [&self.slip, &self.slip].into_iter().take(1),
            Some(parts) => parts.into_iter().take(2),
        }
    }

    /// Each slip component in the model's terms (the one in a plane, the two in space, not
    /// turned to the basis): its slip, `M⁻¹ Sᵀ`, `ṡ` under the free motion and its rounding.
    fn component_parts(&self) -> Vec<(&Slip, &[f64], f64, f64)> {
        match &self.space {
            None => vec![(
                &self.slip,
                &self.direction,
                self.s_dot_free,
                self.s_dot_round_off,
            )],
            Some(space) => space
                .parts
                .iter()
                .map(|part| {
                    (
                        &part.slip,
                        part.direction.as_slice(),
                        part.s_dot_free,
                        part.s_dot_round_off,
                    )
                })
                .collect(),
        }
    }

    /// The part along `basis` of a contact in space becomes the main one (nothing in a plane).
    fn rotate(&mut self, basis: [f64; 2]) {
        let Some(space) = &mut self.space else { return };
        let norm = basis[0].hypot(basis[1]);
        let basis = [basis[0] / norm, basis[1] / norm];
        let main = Part::along(&space.parts[0], &space.parts[1], basis);
        space.cross = Part::along(&space.parts[0], &space.parts[1], [-basis[1], basis[0]]);
        space.basis = basis;
        self.slip = main.slip;
        self.direction = main.direction;
        self.s_dot_free = main.s_dot_free;
        self.s_dot_round_off = main.s_dot_round_off;
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
/// are equal). Where `g` is well conditioned (LU pivots within `10¹⁰` of each other), by LU
/// with a step of iterative refinement: nalgebra's SVD can leave a residual of `10⁻⁹` of the
/// terms there (a dumbbell turning on one end, its other end slipping nearly across its
/// sticking rows). Otherwise the least-squares solution of least norm (singular values below
/// `10⁻¹²` of the largest dropped). Accepted where it solves
/// the system to `10⁻⁹` of its scale; `None` where the system is inconsistent or not finite.
fn solve_least_norm(g: &DMatrix<f64>, rhs: &DVector<f64>) -> Option<DVector<f64>> {
    solve_least_norm_and_say(g, rhs).0
}

/// [`solve_least_norm`], and whether `g`'s rows are dependent (an LU pivot below
/// [`DEPENDENT`] of the largest: the least-norm solution is then one of many).
fn solve_least_norm_and_say(g: &DMatrix<f64>, rhs: &DVector<f64>) -> (Option<DVector<f64>>, bool) {
    if rhs.is_empty() {
        return (Some(DVector::zeros(0)), false);
    }
    let accept = |x: DVector<f64>| {
        let residual = (g * &x - rhs).amax();
        let scale = rhs.amax() + g.abs().column_sum().amax() * x.amax();
        (x.iter().all(|v| v.is_finite()) && residual <= 1e-9 * scale).then_some(x)
    };
    let lu = g.clone().lu();
    let pivots = lu.u().diagonal().abs();
    let dependent = pivots.min() <= DEPENDENT * pivots.max();
    if !dependent {
        if let Some(mut x) = lu.solve(rhs) {
            if let Some(correction) = lu.solve(&(rhs - g * &x)) {
                x += correction;
            }
            return (accept(x), false);
        }
    }
    let svd = g.clone().svd(true, true);
    let largest = svd.singular_values.max();
    if !largest.is_finite() {
        return (None, dependent);
    }
    (
        svd.solve(rhs, 1e-12 * largest).ok().and_then(accept),
        dependent,
    )
}

/// LU pivots below this fraction of the largest: the rows are dependent.
const DEPENDENT: f64 = 1e-10;

/// Why the contact problem with friction has no answer.
fn paradox(set: ActiveSet) -> DynamicsError {
    DynamicsError::Painleve { constraints: set }
}

/// The contacts of a set at one state `(t, q, q̇)`, with their friction: the normal rows `Aᵢ`
/// and directions `M⁻¹Aᵢᵀ` and responses, and for those with friction, their tangential side.
#[derive(Clone)]
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
    /// `fₜ` of each contact (0 without friction), in the set's order: in space, along its
    /// basis.
    pub tangent: Vec<f64>,
    /// In space, the tangential force across the basis (0 otherwise).
    pub cross: Vec<f64>,
    /// In space, the basis the forces were found in (`(1, 0)` otherwise).
    pub basis: Vec<[f64; 2]>,
    /// `q̈`.
    pub q_ddot: Vec<f64>,
}

/// What the impact law with friction did: the normal and tangential impulses in the set's order
/// (the tangential ones in the model's slip components), its loss and the work of the moving
/// surfaces' impulses.
pub(crate) struct FrictionalImpact {
    pub normal: Vec<f64>,
    pub tangent: Vec<[f64; 2]>,
    pub loss: f64,
    pub work: f64,
}

/// The friction states law 1 gives a set (docs/friction.md): the constraints that hold, and the
/// states of those with friction.
pub(crate) struct Decision {
    pub held: ActiveSet,
    pub grips: Grips,
}

/// How a contact enters [`Frame::cone_accelerations`].
#[derive(Clone, Copy, Debug)]
enum Role {
    /// With its cone, of this coefficient.
    Cone(f64),
    /// Slipping on with its kinetic force along its basis, times this sign.
    Kinetic(f64),
    /// Without friction (or none of it counted).
    Normal,
}

/// What [`Frame::solve_cones`] found.
struct ConeSolution {
    /// The forces or impulses `P`, row by row.
    solution: DVector<f64>,
    /// `q + W P`: the normal and slip accelerations (or velocities after an impact).
    rows: DVector<f64>,
    /// The rows of each contact, with the coefficient it was last solved with.
    contacts: Vec<cone::Contact>,
    /// The rounding of each of `rows`.
    rounds: Vec<f64>,
}

impl Forces {
    /// The tangential force of the contact at position `p` (with its tangent `t`) in the
    /// model's slip components.
    pub fn components(&self, p: usize, t: &Tangent) -> [f64; 2] {
        match &t.space {
            None => [self.tangent[p], 0.0],
            Some(_) => {
                let [b1, b2] = self.basis[p];
                let (main, cross) = (self.tangent[p], self.cross[p]);
                [b1 * main - b2 * cross, b2 * main + b1 * cross]
            }
        }
    }
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
                    let state = (t, q, q_dot);
                    let part = |c| Part::of(model, index, c, state, &factor, &frame.acc_free);
                    let main = part(0);
                    let space = (model.slip_components(index) == 2).then(|| {
                        let cross = part(1);
                        Box::new(Space {
                            parts: [main.clone(), cross.clone()],
                            basis: [1.0, 0.0],
                            cross,
                        })
                    });
                    let mut tangent = Tangent {
                        mu_static: friction.static_coefficient,
                        mu_kinetic: friction.kinetic_coefficient,
                        floor: mech.slip_floor(),
                        slip: main.slip,
                        direction: main.direction,
                        s_dot_free: main.s_dot_free,
                        s_dot_round_off: main.s_dot_round_off,
                        space,
                    };
                    // In space, the main part runs along the slip while it slips.
                    if tangent.space.is_some() && !tangent.at_rest() {
                        tangent.rotate(tangent.slip_vector());
                    }
                    tangent
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

    /// The slip part `extra` names: the main part of the contact at position `p`, or its
    /// part across (`(p, true)`, in space).
    fn part(&self, (p, cross): (usize, bool)) -> (&Slip, &[f64], f64) {
        let t = self.tangent(p);
        match (&t.space, cross) {
            (Some(space), true) => (
                &space.cross.slip,
                &space.cross.direction,
                space.cross.s_dot_free,
            ),
            _ => (&t.slip, &t.direction, t.s_dot_free),
        }
    }

    /// Row `r` of the contacts' rows `A₁ … A_k` followed by the slip rows `S` of the parts
    /// `extra` ([`Frame::part`]).
    fn stacked_row(&self, extra: &[(usize, bool)], r: usize) -> &[f64] {
        let k = self.len();
        if r < k {
            self.row(r)
        } else {
            &self.part(extra[r - k]).0.row
        }
    }

    /// Column `r` of `M⁻¹` times the rows of [`Frame::stacked_row`]: `M⁻¹Aᵀ`, then `M⁻¹Sᵀ`.
    fn stacked_direction(&self, extra: &[(usize, bool)], r: usize) -> &[f64] {
        let k = self.len();
        if r < k {
            self.direction(r)
        } else {
            self.part(extra[r - k]).1
        }
    }

    /// The parts a sticking contact holds: its main one, and in space the one across.
    fn held_parts(&self, p: usize) -> impl Iterator<Item = (usize, bool)> {
        let space = self.tangent(p).space.is_some();
        [(p, false), (p, true)]
            .into_iter()
            .take(1 + usize::from(space))
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
    /// slipping contacts would grow as their normal accelerations fall). A contact in space that
    /// slips from rest slips the way its own force drives it ([`Frame::settled`]).
    pub fn forces(&self, set: ActiveSet, grips: Grips) -> Result<Forces, DynamicsError> {
        match self.settled(set, grips)? {
            Some(frame) => frame.forces_held(set, grips),
            None => self.forces_held(set, grips),
        }
    }

    /// [`Frame::forces`] in the frame's bases as they are, with the parts across of the
    /// slipping contacts at the positions `across` held too (their slip across stays 0).
    fn forces_held(&self, set: ActiveSet, grips: Grips) -> Result<Forces, DynamicsError> {
        let k = self.len();
        let n = self.n;
        // The unknowns: every normal force, then the sticking contacts' tangential forces (two
        // in space).
        let mut stick: Vec<(usize, bool)> = Vec::new();
        for p in 0..k {
            if grips.stick.contains(self.indices[p]) && self.tangents[p].is_some() {
                stick.extend(self.held_parts(p));
            }
        }
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
        for (u, &part) in stick.iter().enumerate() {
            columns[(k + u) * n..(k + u + 1) * n].copy_from_slice(self.part(part).1);
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
                self.part(stick[r - k]).2
            };
        }
        // The states are given: the forces solve a square system, which is singular only where
        // the contacts are dependent (then the forces of least norm: the motion is the same for
        // all that solve it). Whether the states are consistent, a normal force that pulls
        // says (a margin), and law 1 decides again (`decide`, where Painlevé's paradox shows).
        // Where the contacts are dependent (statically indeterminate: a box on four corners),
        // the least-norm forces are one choice of many, and may lie outside a sticking
        // contact's cone where another choice does not: then the choice Coulomb's law with
        // every cone at once makes, if it holds every contact as `grips` says. (Where they are
        // not, the forces are unique, and one outside a cone is the stick's end.)
        let x = match solve_least_norm_and_say(&g, &rhs) {
            (Some(x), dependent) if !dependent || self.within_cones(&x, grips, &stick) => x,
            (least, _) => match self.redistributed(&g, &rhs, grips, &stick) {
                Some(x) => x,
                None => least.ok_or_else(|| paradox(set))?,
            },
        };
        let mut q_ddot = self.acc_free.clone();
        for c in 0..size {
            for (a, col) in q_ddot.iter_mut().zip(&columns[c * n..(c + 1) * n]) {
                *a += x[c] * col;
            }
        }
        let normal: Vec<f64> = (0..k).map(|p| x[p]).collect();
        let mut tangent = vec![0.0; k];
        let mut cross = vec![0.0; k];
        for p in 0..k {
            let sign = grips.direction(self.indices[p]);
            if let (Some(t), true) = (&self.tangents[p], sign != 0.0) {
                tangent[p] = -t.mu_kinetic * sign * normal[p];
            }
        }
        for (u, &(p, across)) in stick.iter().enumerate() {
            if across {
                cross[p] = x[k + u];
            } else {
                tangent[p] = x[k + u];
            }
        }
        if !q_ddot
            .iter()
            .chain(&normal)
            .chain(&tangent)
            .chain(&cross)
            .all(|x| x.is_finite())
        {
            return Err(DynamicsError::NonFinite);
        }
        let basis = self
            .tangents
            .iter()
            .map(|t| {
                t.as_ref()
                    .and_then(|t| t.space.as_ref())
                    .map_or([1.0, 0.0], |space| space.basis)
            })
            .collect();
        Ok(Forces {
            normal,
            tangent,
            cross,
            basis,
            q_ddot,
        })
    }

    /// Whether the forces `x` of [`Frame::forces_held`] (normal forces, then the parts `stick`
    /// of the sticking contacts) lie within every sticking contact's static cone, to rounding.
    /// (A normal force that pulls is the motion's own answer: the contact lets go.)
    fn within_cones(&self, x: &DVector<f64>, grips: Grips, stick: &[(usize, bool)]) -> bool {
        let k = self.len();
        let round = ROUND_OFF * x.amax();
        let mut tangential = vec![0.0_f64; k];
        for (u, &(p, _)) in stick.iter().enumerate() {
            tangential[p] += x[k + u] * x[k + u];
        }
        (0..k).all(|p| {
            let size = tangential[p].sqrt();
            !grips.stick.contains(self.indices[p])
                || self.tangents[p]
                    .as_ref()
                    .is_none_or(|t| size <= t.mu_static * x[p] + round)
        })
    }

    /// The forces of [`Frame::forces_held`] (the system `g x = rhs`, unknowns in its order)
    /// as Coulomb's law with the cones of every contact at once chooses them ([`crate::cone`]:
    /// each sticking contact with its static cone, every normal force pushing), if that choice
    /// holds every contact as `grips` says (every row's acceleration 0, to rounding); `None`
    /// otherwise.
    fn redistributed(
        &self,
        g: &DMatrix<f64>,
        rhs: &DVector<f64>,
        grips: Grips,
        stick: &[(usize, bool)],
    ) -> Option<DVector<f64>> {
        let k = self.len();
        // The unknowns by contact: its normal force, then its sticking parts.
        let mut order = Vec::with_capacity(rhs.len());
        let mut contacts = Vec::with_capacity(k);
        for p in 0..k {
            let start = order.len();
            order.push(p);
            order.extend((0..stick.len()).filter(|&u| stick[u].0 == p).map(|u| k + u));
            let sticking = grips.stick.contains(self.indices[p]);
            contacts.push(cone::Contact {
                start,
                tangents: order.len() - start - 1,
                mu: match &self.tangents[p] {
                    Some(t) if sticking => t.mu_static,
                    _ => 0.0,
                },
            });
        }
        let size = order.len();
        let w = DMatrix::from_fn(size, size, |r, c| g[(order[r], order[c])]);
        let q = DVector::from_fn(size, |r, _| -rhs[order[r]]);
        let forces = cone::solve(&w, &q, &contacts).ok()?;
        let accelerations = &q + &w * &forces;
        let held = (0..size).all(|r| {
            let terms: f64 = q[r].abs()
                + (0..size)
                    .map(|c| (w[(r, c)] * forces[c]).abs())
                    .sum::<f64>();
            accelerations[r].abs() <= 1e-12 * terms
        });
        if !held {
            return None;
        }
        let mut x = DVector::zeros(size);
        for (r, &unknown) in order.iter().enumerate() {
            x[unknown] = forces[r];
        }
        Some(x)
    }

    /// Where contacts in space slip in `grips` from rest or nearly ([`Tangent::settling`]), the
    /// frame with each one's basis along the direction the forces drive its slip in: the
    /// kinetic force along `−basis` must drive the slip along `basis`, so the slip's
    /// acceleration has no part across it ([`Frame::slip_direction`]; for several, by sweeps
    /// contact by contact, and where those do not settle, as dependent contacts make them, all
    /// at once by [`Frame::settled_by_cones`]). `None` where no contact slips from rest.
    fn settled(&self, set: ActiveSet, grips: Grips) -> Result<Option<Frame>, DynamicsError> {
        let mut moving: Vec<usize> = (0..self.len())
            .filter(|&p| {
                self.tangents[p].as_ref().is_some_and(|t| {
                    t.space.is_some() && t.settling() && grips.direction(self.indices[p]) != 0.0
                })
            })
            .collect();
        if moving.is_empty() {
            return Ok(None);
        }
        // A small slip that is not at rest and slows down along its own direction is on its
        // way to 0 (a sphere about to roll): its direction stays its own.
        if moving.iter().any(|&p| !self.tangent(p).at_rest()) {
            if let Ok(forces) = self.forces_held(set, grips) {
                moving.retain(|&p| {
                    let t = self.tangent(p);
                    t.at_rest() || dot(&t.slip.row, &forces.q_ddot) + t.slip.sigma >= 0.0
                });
            }
            if moving.is_empty() {
                return Ok(None);
            }
        }
        let mut frame = self.clone();
        for _ in 0..SETTLE_SWEEPS {
            let mut change = 0.0_f64;
            for &p in &moving {
                // Near its own direction where it moves, else near the one against the force
                // that would hold it. Where it has no such direction (a slip that has just
                // stopped, seen in the states before law 1 decides again), against that force;
                // its basis stays only where that is 0.
                let t = frame.tangent(p);
                let guess = if t.at_rest() {
                    frame.against_holding(set, grips, p)
                } else {
                    t.space.as_ref().map(|s| s.basis)
                };
                // At rest with nothing to hold (a sphere's slip reaching 0 as it rolls): no
                // force drives a slip; its basis stays.
                if guess.is_none() {
                    continue;
                }
                let Some(new) = frame
                    .slip_direction(set, grips, p, guess)
                    .or_else(|| frame.against_holding(set, grips, p))
                else {
                    continue;
                };
                let old = frame
                    .tangent(p)
                    .space
                    .as_ref()
                    .map_or([1.0, 0.0], |s| s.basis);
                change = change.max((new[0] - old[0]).hypot(new[1] - old[1]));
                if let Some(t) = frame.tangents[p].as_mut() {
                    t.rotate(new);
                }
            }
            if moving.len() == 1 || change <= 1e-13 {
                return Ok(Some(frame));
            }
        }
        // The sweeps, contact by contact, did not settle (dependent contacts: a box's corners
        // share their slips): the directions of the slips' accelerations in Coulomb's law with
        // every cone at once.
        self.settled_by_cones(set, grips, &moving).map(Some)
    }

    /// The frame with the contacts in space at `moving` (slipping from rest) turned along the
    /// accelerations of their slips in Coulomb's law with the cones of every contact at once
    /// ([`Frame::cone_accelerations`]): the moving ones with their kinetic cones, the sticking
    /// ones with their static cones, those slipping on with their kinetic forces. There the
    /// kinetic force of each moving contact is along minus its slip's acceleration, as the law
    /// for a slip from rest asks, jointly for all.
    fn settled_by_cones(
        &self,
        set: ActiveSet,
        grips: Grips,
        moving: &[usize],
    ) -> Result<Frame, DynamicsError> {
        let roles: Vec<Role> = (0..self.len())
            .map(|p| match &self.tangents[p] {
                None => Role::Normal,
                Some(t) => {
                    let index = self.indices[p];
                    let sign = grips.direction(index);
                    if moving.contains(&p) {
                        Role::Cone(t.mu_kinetic)
                    } else if grips.stick.contains(index) {
                        Role::Cone(t.mu_static)
                    } else if sign != 0.0 {
                        Role::Kinetic(sign)
                    } else {
                        Role::Normal
                    }
                }
            })
            .collect();
        let solution = self.cone_accelerations(set, &roles)?;
        let mut frame = self.clone();
        for &p in moving {
            let c = solution.contacts[p];
            let slip = solution.rows.rows_range(c.start + 1..=c.start + c.tangents);
            if c.tangents == 2 && slip.norm() > 0.0 {
                if let Some(t) = frame.tangents[p].as_mut() {
                    t.rotate([slip[0], slip[1]]);
                }
            }
        }
        Ok(frame)
    }

    /// The direction in which the contact in space at position `p`, at rest, slips in the
    /// states `grips` (the others as they are): the unit vector `b` at which, the kinetic force
    /// along `−b` (and none across), the slip's acceleration has no part across `b` and its
    /// part along `b` is not negative (to `10⁻⁸` of its size around the ring: at the
    /// onset of a slip with `μₛ = μₖ` it is 0). Bracketed on a ring of angles, then bisected to
    /// rounding; of several, the one the slip accelerates along most. `None` where there is
    /// none.
    fn slip_direction(
        &self,
        set: ActiveSet,
        grips: Grips,
        p: usize,
        guess: Option<[f64; 2]>,
    ) -> Option<[f64; 2]> {
        let mut frame = self.clone();
        let mut at = |angle: f64| -> Option<(f64, f64)> {
            let basis = [angle.cos(), angle.sin()];
            frame.tangents[p].as_mut()?.rotate(basis);
            let forces = frame.forces_held(set, grips).ok()?;
            let t = frame.tangent(p);
            let along = dot(&t.slip.row, &forces.q_ddot) + t.slip.sigma;
            let cross = &t.space.as_ref()?.cross;
            let across = dot(&cross.slip.row, &forces.q_ddot) + cross.slip.sigma;
            Some((across, along))
        };
        // First near the guess: a bracket of ±0.05 rad closed by the Illinois method (the
        // force across is smooth in the angle).
        if let Some(guess) = guess {
            let centre = guess[1].atan2(guess[0]);
            let (a, b) = (centre - 0.05, centre + 0.05);
            if let (Some((ga, aa)), Some((gb, ab))) = (at(a), at(b)) {
                if ga * gb <= 0.0 {
                    let root = illinois(&mut at, (a, ga), (b, gb));
                    let size = aa.abs().max(ab.abs());
                    if let Some((_, along)) = root.and_then(|r| at(r).map(|v| (r, v.1))) {
                        if along >= -1e-8 * size {
                            let r = root.expect("found");
                            return Some([r.cos(), r.sin()]);
                        }
                    }
                }
            }
        }
        ring_root(&mut at, |along, size| along >= -1e-8 * size, 48)
    }

    /// The direction against the force that would hold the contact in space at position `p`
    /// sticking (the others in `grips`): where it starts to slip at its cone's edge, it slips
    /// that way (exactly for an isotropic response). `None` where that force is 0 or not found.
    fn against_holding(&self, set: ActiveSet, grips: Grips, p: usize) -> Option<[f64; 2]> {
        let only = ActiveSet::single(self.indices[p]);
        let holding = Grips {
            stick: grips.stick.union(only),
            forward: grips.forward.minus(only),
            backward: grips.backward.minus(only),
        };
        let forces = self.forces_held(set, holding).ok()?;
        let f = forces.components(p, self.tangent(p));
        let size = f[0].hypot(f[1]);
        (size > 0.0).then(|| [-f[0] / size, -f[1] / size])
    }

    /// How far each contact of the held frame is from a transition in the states `grips`,
    /// positive where one happens (docs/friction.md): a normal force that would pull, a
    /// sticking contact's tangential force beyond the cone (`|fₜ| − μₛ fₙ`), a slipping contact's
    /// slip past 0 (`−s` in its direction; in space, along the direction it slipped when the
    /// mode started). Each is divided by the fixed scale `scales` gives it (per contact and
    /// kind, [`Frame::scales`]), so that they compare.
    pub fn margins(&self, forces: &Forces, grips: Grips, scales: &[f64]) -> f64 {
        (0..self.len())
            .flat_map(|p| self.contact_margins(p, forces, grips, scales))
            .fold(f64::NEG_INFINITY, |m, (margin, _)| m.max(margin))
    }

    /// The margins of [`Frame::margins`] of the contact at position `p`, each with its kind:
    /// 0 its normal force, 1 its cone, 2 its slip.
    fn contact_margins(
        &self,
        p: usize,
        forces: &Forces,
        grips: Grips,
        scales: &[f64],
    ) -> impl Iterator<Item = (f64, usize)> {
        let index = self.indices[p];
        let f = forces.normal[p];
        // The rounding of the normal force, from that of ḧ_free through A M⁻¹ Aᵀ.
        let round = self.normals[p].h_ddot_round_off / self.normals[p].s + ROUND_OFF * f.abs();
        let normal = Some(((-f - round) / scales[SCALES * p], 0));
        let mut tangential = None;
        if let Some(t) = &self.tangents[p] {
            if grips.stick.contains(index) {
                // Beyond the cone by more than the rounding of the forces.
                let size = forces.tangent[p].hypot(forces.cross[p]);
                let beyond = size
                    - t.mu_static * f
                    - ROUND_OFF * (size + t.mu_static * f.abs())
                    - t.mu_static * round;
                tangential = Some((beyond / scales[SCALES * p + 1], 1));
            } else if let Some(slip) = self.slip_past(p, grips, scales) {
                tangential = Some((slip / scales[SCALES * p + 2], 2));
            }
        }
        normal.into_iter().chain(tangential)
    }

    /// How far the slipping contact at position `p` has slipped past 0: `−s` in its
    /// direction, in space along the direction kept in `scales` when the mode started. `None`
    /// where it does not slip.
    fn slip_past(&self, p: usize, grips: Grips, scales: &[f64]) -> Option<f64> {
        let t = self.tangents[p].as_ref()?;
        let sign = grips.direction(self.indices[p]);
        if sign == 0.0 {
            return None;
        }
        Some(match &t.space {
            None => -sign * t.slip.s,
            Some(_) => {
                let v = t.slip_vector();
                -sign * (scales[SCALES * p + 3] * v[0] + scales[SCALES * p + 4] * v[1])
            }
        })
    }

    /// The directions the slip margins of the contacts in space that slip in `grips` are
    /// measured along (kept in `scales`, [`Frame::scales`]) renewed to their slips now, where
    /// those are not at rest: renewed every step, a margin crosses 0 where the slip stops, not
    /// where it turns (a puck sliding across a slope turns its slip by more than a right angle).
    pub fn renew_directions(&self, grips: Grips, scales: &mut [f64]) {
        for p in 0..self.len() {
            let Some(t) = &self.tangents[p] else { continue };
            let Some(space) = &t.space else { continue };
            if grips.direction(self.indices[p]) != 0.0 && !t.at_rest() {
                scales[SCALES * p + 3] = space.basis[0];
                scales[SCALES * p + 4] = space.basis[1];
            }
        }
    }

    /// Whether the contact at position `p`, slipping in `grips`, has stopped: its slip is 0 or
    /// has turned against its direction (a root of its slip margin).
    pub fn slip_stopped(&self, p: usize, grips: Grips, scales: &[f64]) -> bool {
        self.slip_past(p, grips, scales)
            .is_some_and(|past| past >= 0.0)
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
            for (margin, kind) in self.contact_margins(p, forces, grips, scales) {
                if margin > best.0 {
                    best = (margin, p, kind);
                }
            }
        }
        let (_, p, kind) = best;
        let index = self.indices[p];
        let only = ActiveSet::single(index);
        let mut grips = grips;
        let mut held = set;
        let in_space = self.tangents[p].as_ref().is_some_and(|t| t.space.is_some());
        match kind {
            0 => held = set.minus(only),
            1 => {
                grips.stick = grips.stick.minus(only);
                // It slips against the force that held it at the cone's edge (in space,
                // forwards along the direction its force drives it, found from rest).
                if forces.tangent[p] > 0.0 && !in_space {
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

    /// The scales of [`Frame::margins`] in the states `grips`, [`SCALES`] per contact: its
    /// normal force, its tangential force, its slip, each the largest of its size now and its
    /// rounding, then in space the direction it slips in (taken when a mode starts, and kept
    /// through it).
    pub fn scales(&self, forces: &Forces) -> Vec<f64> {
        let mut scales = Vec::with_capacity(SCALES * self.len());
        let force_scale = forces
            .normal
            .iter()
            .chain(&forces.tangent)
            .chain(&forces.cross)
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
            scales.extend(forces.basis[p]);
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
        let extra: Vec<(usize, bool)> = candidates.iter().map(|&p| (p, false)).collect();
        for r in 0..k + m {
            let row = self.stacked_row(&extra, r);
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
        let at_rest: Vec<usize> = (0..k)
            .filter(|&p| self.tangents[p].as_ref().is_some_and(Tangent::at_rest))
            .collect();
        // Where every contact can hold, those at rest sticking and the others slipping on, in
        // equilibrium (every normal force pushing, every sticking force within its static
        // cone), that is law 1's answer: the contact problem with friction may have others
        // (a block resting on two rough corners could also pivot on one, its friction
        // lifting the other), and a run at rest must stay at rest.
        if let Some(decision) = self.all_held(set, &at_rest) {
            return Ok(decision);
        }
        // With a contact in space at rest, Coulomb's law with the isotropic cones, exactly.
        let in_space = at_rest.iter().any(|&p| self.tangent(p).space.is_some());
        if in_space {
            self.decide_cone(set, &at_rest)
        } else {
            self.decide_lcp(set, &at_rest)
        }
    }

    /// Law 1 with contacts in space ([`crate::cone`], at the level of accelerations): the
    /// contacts at positions `candidates` (at rest) with their cones, one or two slip
    /// components, the static coefficient first and the kinetic one where it then slips and is
    /// lower; the others with friction slip on, their kinetic force in their normal columns.
    /// A contact holds where its normal acceleration is 0 (to rounding); a candidate that holds
    /// sticks where its slip's acceleration is 0, and otherwise slips (in space, from rest, in
    /// the direction [`Frame::settled`] finds; that is the direction of its acceleration here).
    fn decide_cone(&self, set: ActiveSet, candidates: &[usize]) -> Result<Decision, DynamicsError> {
        let roles: Vec<Role> = (0..self.len())
            .map(|p| match &self.tangents[p] {
                None => Role::Normal,
                Some(t) if candidates.contains(&p) => Role::Cone(t.mu_static),
                // Slipping on, in its slip's direction (in space the basis runs along it).
                Some(t) if t.slip.s < 0.0 && t.space.is_none() => Role::Kinetic(-1.0),
                Some(_) => Role::Kinetic(1.0),
            })
            .collect();
        let solution = self.cone_accelerations(set, &roles)?;
        let (accelerations, rounds) = (&solution.rows, &solution.rounds);
        let mut held = ActiveSet::empty();
        let mut grips = Grips::none();
        for (p, c) in solution.contacts.iter().enumerate() {
            let index = self.indices[p];
            if accelerations[c.start] > rounds[c.start] {
                continue;
            }
            held = held.with(index);
            let Some(t) = &self.tangents[p] else { continue };
            if let Role::Kinetic(sign) = roles[p] {
                if sign < 0.0 {
                    grips.backward = grips.backward.with(index);
                } else {
                    grips.forward = grips.forward.with(index);
                }
                continue;
            }
            let range = c.start + 1..=c.start + c.tangents;
            let slip = accelerations.rows_range(range.clone());
            let round: f64 = range.map(|r| rounds[r]).sum();
            if slip.norm() <= round {
                grips.stick = grips.stick.with(index);
            } else if t.space.is_some() || slip[0] > 0.0 {
                grips.forward = grips.forward.with(index);
            } else {
                grips.backward = grips.backward.with(index);
            }
        }
        Ok(Decision { held, grips })
    }

    /// Coulomb's law with isotropic cones at the level of accelerations on the frame's contacts
    /// ([`crate::cone`]), each in its [`Role`]: with a cone (its one or two slip components in
    /// the model's terms, the coefficient given, then the kinetic one where it slips and that is
    /// lower), slipping on with its kinetic force in its normal column, or without friction.
    /// The accelerations, the problem's layout and each row's rounding.
    fn cone_accelerations(
        &self,
        set: ActiveSet,
        roles: &[Role],
    ) -> Result<ConeSolution, DynamicsError> {
        let k = self.len();
        let n = self.n;
        // Each row with its column (`M⁻¹` applied), right-hand side and rounding.
        let mut rows: Vec<&[f64]> = Vec::new();
        let mut columns: Vec<Vec<f64>> = Vec::new();
        let mut q = Vec::new();
        let mut round_off = Vec::new();
        let mut contacts = Vec::with_capacity(k);
        for (p, &role) in roles.iter().enumerate() {
            let start = rows.len();
            rows.push(self.row(p));
            let mut column = self.direction(p).to_vec();
            q.push(self.normals[p].h_ddot_free);
            round_off.push(self.normals[p].h_ddot_round_off);
            let mut tangents = 0;
            let mut mu = 0.0;
            match (&self.tangents[p], role) {
                (Some(t), Role::Cone(coefficient)) => {
                    mu = coefficient;
                    for (slip, direction, free, round) in t.component_parts() {
                        columns.push(column);
                        rows.push(&slip.row);
                        column = direction.to_vec();
                        q.push(free);
                        round_off.push(round);
                        tangents += 1;
                    }
                }
                (Some(t), Role::Kinetic(sign)) => {
                    // `fₜ = −μₖ fₙ` along the basis (its slip's direction), times `sign`.
                    for (c, d) in column.iter_mut().zip(&t.direction) {
                        *c -= t.mu_kinetic * sign * d;
                    }
                }
                _ => {}
            }
            columns.push(column);
            contacts.push(cone::Contact {
                start,
                tangents,
                mu,
            });
        }
        debug_assert!(columns.iter().all(|c| c.len() == n));
        let size = rows.len();
        let w = DMatrix::from_fn(size, size, |r, c| dot(rows[r], &columns[c]));
        self.solve_cones(set, &w, &q, &round_off, contacts)
    }

    /// Coulomb's law with isotropic cones ([`crate::cone`]) on the rows of `w` with right-hand
    /// sides `q` (each within its `round_off` taken as 0) and `contacts` with their first
    /// coefficients: a contact that then slips (beyond the rounding of its rows) under a normal
    /// force, with a kinetic coefficient below its cone's, is solved again with the kinetic one,
    /// until none is. The solution, `q + W P`, each row's rounding and the contacts as last
    /// solved.
    fn solve_cones(
        &self,
        set: ActiveSet,
        w: &DMatrix<f64>,
        q: &[f64],
        round_off: &[f64],
        mut contacts: Vec<cone::Contact>,
    ) -> Result<ConeSolution, DynamicsError> {
        let size = q.len();
        let q = DVector::from_fn(size, |r, _| {
            if q[r].abs() <= round_off[r] {
                0.0
            } else {
                q[r]
            }
        });
        for _ in 0..=contacts.len() {
            let solution = cone::solve(w, &q, &contacts).map_err(|error| match error {
                cone::ConeError::NonFinite => DynamicsError::NonFinite,
                cone::ConeError::NoConvergence { .. } => {
                    DynamicsError::SpatialFriction { constraints: set }
                }
            })?;
            let rows = &q + w * &solution;
            let rounding = |r: usize| {
                round_off[r]
                    + ROUND_OFF
                        * (0..size)
                            .map(|c| (w[(r, c)] * solution[c]).abs())
                            .sum::<f64>()
            };
            let mut changed = false;
            for (p, c) in contacts.iter_mut().enumerate() {
                let Some(t) = &self.tangents[p] else { continue };
                let slip = rows.rows_range(c.start + 1..=c.start + c.tangents);
                let round: f64 = (c.start + 1..=c.start + c.tangents).map(rounding).sum();
                if c.tangents > 0
                    && c.mu > t.mu_kinetic
                    && solution[c.start] > 0.0
                    && slip.norm() > round
                {
                    c.mu = t.mu_kinetic;
                    changed = true;
                }
            }
            if !changed {
                let rounds = (0..size).map(rounding).collect();
                return Ok(ConeSolution {
                    solution,
                    rows,
                    contacts,
                    rounds,
                });
            }
        }
        Err(DynamicsError::SpatialFriction { constraints: set })
    }

    /// Law 1's LCP (Pfeiffer and Glocker) with the contacts at positions `candidates` free to
    /// stick; the others with friction slip, in the direction of their slip or, at rest (in
    /// space), forwards along their basis.
    fn decide_lcp(&self, set: ActiveSet, candidates: &[usize]) -> Result<Decision, DynamicsError> {
        let k = self.len();
        let m = candidates.len();
        let size = k + 2 * m;
        // Candidates enter with μₛ, the others with μₖ in their slip's direction (in space,
        // forwards: the basis runs along the slip).
        let direction = |t: &Tangent| {
            if t.slip.s < 0.0 && t.space.is_none() {
                -1.0
            } else {
                1.0
            }
        };
        let mu: Vec<f64> = (0..k)
            .map(|p| {
                self.tangents[p].as_ref().map_or(0.0, |t| {
                    if candidates.contains(&p) {
                        t.mu_static
                    } else {
                        t.mu_kinetic * direction(t)
                    }
                })
            })
            .collect();
        let normal_q: Vec<f64> = self.normals.iter().map(|n| n.h_ddot_free).collect();
        let (matrix, q, _) = self.coulomb_lcp(candidates, &mu, &normal_q, |t| t.s_dot_free);
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
            let Some(u) = candidates.iter().position(|&c| c == p) else {
                if direction(t) > 0.0 {
                    grips.forward = grips.forward.with(index);
                } else {
                    grips.backward = grips.backward.with(index);
                }
                continue;
            };
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
            if t.space.is_some() && s_ddot.abs() > round {
                // In space it slips forwards along the direction it finds from rest.
                grips.forward = grips.forward.with(index);
            } else if s_ddot < -round {
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
                let size = forces.tangent[p].hypot(forces.cross[p]);
                if candidates.contains(&p) && size > t.mu_static * f + ROUND_OFF * (f.abs() + size)
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
            |scale: f64, out: &mut [f64]| -> Result<(Vec<f64>, Vec<[f64; 2]>), DynamicsError> {
                out.copy_from_slice(&before);
                let e: Vec<f64> = restitution.iter().map(|e| e * scale).collect();
                self.impact_any(set, &e, &approach, out)
            };
        let mut after = before.clone();
        let (mut normal, mut tangent) = attempt(1.0, &mut after)?;
        // The law creates energy where its own loss `−½ Σ Λₙ (ḣ⁺ + ḣ⁻) − ½ Σ Λₜ (s⁺ + s⁻)` is
        // negative beyond rounding (what a surface that moves puts in is not the law's).
        let gained = |result: &(Vec<f64>, Vec<[f64; 2]>), after: &[f64]| {
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
        tangent: &[[f64; 2]],
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
                for (c, slip) in t.components_slips().enumerate() {
                    let s0 = slip.s - dot(&slip.row, before);
                    let s_after = dot(&slip.row, after) + s0;
                    loss -= 0.5 * tangent[p][c] * (s_after + slip.s);
                    work -= tangent[p][c] * s0;
                }
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
        self.impact_any(set, &plastic, approach, q_dot).map(|_| ())
    }

    /// The impact law with friction for the restitutions `e`, each contact approaching at the
    /// normal velocity `approach`, from `q̇` (updated): the normal impulses and the tangential
    /// ones in the model's slip components. In a plane, [`Frame::impact_with`]; with contacts
    /// in space, [`Frame::impact_in_space`].
    fn impact_any(
        &self,
        set: ActiveSet,
        e: &[f64],
        approach: &[f64],
        q_dot: &mut [f64],
    ) -> Result<(Vec<f64>, Vec<[f64; 2]>), DynamicsError> {
        let in_space = self
            .tangents
            .iter()
            .any(|t| t.as_ref().is_some_and(|t| t.space.is_some()));
        if in_space {
            return self.impact_in_space(set, e, approach, q_dot);
        }
        let (normal, tangent) = self.impact_with(set, e, approach, q_dot)?;
        Ok((normal, tangent.iter().map(|&f| [f, 0.0]).collect()))
    }

    /// The impact law with friction where some contacts are in space: Coulomb's law with the
    /// isotropic cones, exactly, on every contact at once ([`crate::cone`]), the static
    /// coefficients first; contacts that slide with a kinetic coefficient below the static are
    /// solved again with it, until none is added. `q̇` updated; the normal impulses and the
    /// tangential ones in the model's slip components.
    fn impact_in_space(
        &self,
        set: ActiveSet,
        e: &[f64],
        approach: &[f64],
        q_dot: &mut [f64],
    ) -> Result<(Vec<f64>, Vec<[f64; 2]>), DynamicsError> {
        let k = self.len();
        // The rows: each contact's normal one, then its slip components; with `M⁻¹` applied.
        let mut rows: Vec<(&[f64], &[f64])> = Vec::new();
        let mut q = Vec::new();
        let mut round_off = Vec::new();
        let mut contacts = Vec::with_capacity(k);
        for p in 0..k {
            let start = rows.len();
            rows.push((self.row(p), self.direction(p)));
            let terms: f64 = self
                .row(p)
                .iter()
                .zip(q_dot.iter())
                .map(|(a, v)| (a * v).abs())
                .sum();
            q.push((1.0 + e[p]) * approach[p]);
            round_off.push(ROUND_OFF * (1.0 + e[p]) * (terms + approach[p].abs()));
            let tangents = match &self.tangents[p] {
                None => 0,
                Some(t) => {
                    let parts = t.component_parts();
                    for &(slip, direction, _, _) in &parts {
                        rows.push((&slip.row, direction));
                        q.push(slip.s);
                        round_off.push(ROUND_OFF * slip.scale);
                    }
                    parts.len()
                }
            };
            contacts.push(cone::Contact {
                start,
                tangents,
                mu: self.tangents[p].as_ref().map_or(0.0, |t| t.mu_static),
            });
        }
        let size = rows.len();
        let w = DMatrix::from_fn(size, size, |r, c| dot(rows[r].0, rows[c].1));
        let cones = self.solve_cones(set, &w, &q, &round_off, contacts)?;
        let impulses = &cones.solution;
        for (r, &(_, direction)) in rows.iter().enumerate() {
            for (v, d) in q_dot.iter_mut().zip(direction) {
                *v += impulses[r] * d;
            }
        }
        if !q_dot.iter().all(|v| v.is_finite()) {
            return Err(DynamicsError::NonFinite);
        }
        let normal: Vec<f64> = cones.contacts.iter().map(|c| impulses[c.start]).collect();
        let tangent: Vec<[f64; 2]> = cones
            .contacts
            .iter()
            .map(|c| {
                let mut out = [0.0; 2];
                for a in 0..c.tangents {
                    out[a] = impulses[c.start + 1 + a];
                }
                out
            })
            .collect();
        Ok((normal, tangent))
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
                        // And the slips', as eliminating them carries their rounding into
                        // this row (a contact hardly approaching while it slips fast).
                        let slips: f64 = (k..k + m)
                            .filter(|&c| matrix[c * size + c] != 0.0)
                            .map(|c| (matrix[r * size + c] * q[c] / matrix[c * size + c]).abs())
                            .sum();
                        ROUND_OFF * ((1.0 + e[r]) * (terms + approach[r].abs()) + slips)
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
            let main = -mu[u] + held.tangent[p] * duration;
            u += 1;
            let cross = if t.space.is_some() {
                u += 1;
                -mu[u - 1] + held.cross[p] * duration
            } else {
                0.0
            };
            let tangent = main.hypot(cross);
            let round = ROUND_OFF * (normal.abs() + tangent);
            if normal < -round || tangent > t.mu_static * normal.max(0.0) + round {
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
    /// contact of `set` and `s = 0` on those of `stick` (in space, both parts), jointly:
    /// `W μ = (ḣ, s)`, `q̇ ← q̇ − M⁻¹ Bᵀ μ` with `B` the rows `Aᵢ` and `Sⱼ` (it keeps every
    /// momentum they do not touch). Returns `μ`: minus the impulses, normal ones first (the
    /// set's order), then the sticking contacts' tangential parts.
    pub fn stop_slip(
        &self,
        set: ActiveSet,
        stick: ActiveSet,
        q_dot: &mut [f64],
    ) -> Result<Vec<f64>, DynamicsError> {
        let approach: Vec<f64> = self.normals.iter().map(|n| n.a_q_dot).collect();
        self.project_rows(set, stick, &approach, q_dot)
    }

    /// [`Frame::stop_slip`] with `W μ = (normal_rhs, s)`: the normal velocities' parts `A q̇`
    /// lowered by `normal_rhs` instead of to 0 (`(1 + e) A q̇⁻` gives Newton's law).
    fn project_rows(
        &self,
        set: ActiveSet,
        stick: ActiveSet,
        normal_rhs: &[f64],
        q_dot: &mut [f64],
    ) -> Result<Vec<f64>, DynamicsError> {
        let n = self.n;
        let k = self.len();
        let mut sticking: Vec<(usize, bool)> = Vec::new();
        for p in 0..k {
            if stick.contains(self.indices[p]) && self.tangents[p].is_some() {
                sticking.extend(self.held_parts(p));
            }
        }
        let size = k + sticking.len();
        let row = |r: usize| self.stacked_row(&sticking, r);
        let direction = |r: usize| self.stacked_direction(&sticking, r);
        let w = DMatrix::from_fn(size, size, |r, c| dot(row(r), direction(c)));
        let rhs = DVector::from_fn(size, |r, _| {
            if r < k {
                normal_rhs[r]
            } else {
                self.part(sticking[r - k]).0.s
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

/// The root of `g` (the first of the pair `at` returns) between `a` and `b`, where `g` changes
/// sign, by the Illinois method (regula falsi that halves the weight of an end kept twice) to
/// adjacent angles or at most 60 evaluations; `None` where an evaluation fails.
fn illinois(
    at: &mut impl FnMut(f64) -> Option<(f64, f64)>,
    (mut a, mut ga): (f64, f64),
    (mut b, mut gb): (f64, f64),
) -> Option<f64> {
    if ga == 0.0 {
        return Some(a);
    }
    if gb == 0.0 {
        return Some(b);
    }
    let mut side = 0;
    for _ in 0..60 {
        let x = (a * gb - b * ga) / (gb - ga);
        if !(x > a.min(b) && x < a.max(b)) || (b - a).abs() <= 4.0 * f64::EPSILON * a.abs().max(1.0)
        {
            return Some(0.5 * (a + b));
        }
        let (gx, _) = at(x)?;
        if gx == 0.0 {
            return Some(x);
        }
        if (gx < 0.0) == (gb < 0.0) {
            (b, gb) = (x, gx);
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        } else {
            (a, ga) = (x, gx);
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        }
    }
    Some(0.5 * (a + b))
}
