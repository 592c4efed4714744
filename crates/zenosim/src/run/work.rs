//! The energy balance along a run (docs/forces-and-time.md): the works of the forces, of `L`'s
//! time dependence and of surfaces that move, integrated between events on each step's dense
//! output, and the work and loss of every impact from its impulses.

use super::{interpolate, Runner};
use crate::contact::{self, Contacts};
use crate::derivatives::{energy, guard_along, powers};
use crate::error::Error;
use crate::execution::{ActiveSet, EventKind, Work};
use crate::mechanics::DynamicsError;
use crate::model::HybridLagrangian;
use crate::observer::Observer;

/// The five Gauss–Legendre nodes on `[0, 1]` and their weights, exact for polynomials of degree
/// 9 (the powers along DOP853's degree-7 interpolant are smooth: an `O(h¹⁰)` error per step),
/// from their closed forms on `[−1, 1]`:
/// `0` and `±⅓√(5 ∓ 2√(10/7))`, weights `128/225` and `(322 ± 13√70)/900`.
fn gauss() -> [(f64, f64); 5] {
    let inner = (5.0 - 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
    let outer = (5.0 + 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
    let w_inner = (322.0 + 13.0 * 70.0f64.sqrt()) / 900.0;
    let w_outer = (322.0 - 13.0 * 70.0f64.sqrt()) / 900.0;
    // x ∈ [−1, 1] to [0, 1]: (1 + x)/2, weights halved.
    [
        (0.5 * (1.0 - outer), 0.5 * w_outer),
        (0.5 * (1.0 - inner), 0.5 * w_inner),
        (0.5, 0.5 * 128.0 / 225.0),
        (0.5 * (1.0 + inner), 0.5 * w_inner),
        (0.5 * (1.0 + outer), 0.5 * w_outer),
    ]
}

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// The execution's time and state are now `(t, y)`: the record's balance follows, where it
    /// has been integrated to `t` (a failure inside a step leaves the last one at `t`).
    pub(super) fn commit_time(&mut self, t: f64, y: &[f64]) {
        self.t = t;
        self.y.copy_from_slice(y);
        if self.record.work_t == t {
            self.record.work_at_t = self.record.work;
        }
    }

    /// The energy balance at `t`, within the last step (from the committed balance at
    /// `work_t`, not committing it): for a sample.
    pub(super) fn work_at(&mut self, t: f64) -> Result<Work, Error> {
        let mut work = self.record.work;
        if !self.powered() || t == self.record.work_t {
            return Ok(work);
        }
        let [forces, drive, constraints, friction] = self.integrate_power(self.record.work_t, t)?;
        work.forces += forces;
        work.drive += drive;
        work.constraints += constraints;
        work.friction += friction;
        Ok(work)
    }

    /// Commits the energy balance up to `t` (inside the last step, or at its start).
    #[inline]
    pub(super) fn advance_work(&mut self, t: f64) -> Result<(), Error> {
        if self.powered() {
            self.record.work = self.work_at(t)?;
        }
        self.record.work_t = t;
        Ok(())
    }

    /// Whether anything does work along the motion: forces or time in the model, or friction
    /// at a slipping contact.
    #[inline]
    fn powered(&self) -> bool {
        // (A contact held with friction may ride a surface that moves, sticking or slipping.)
        !self.sim.model.is_autonomous() || !self.grips.all().is_empty()
    }

    /// `∫ (Q·q̇, −∂ₜL, −Σλᵢ Aᵢq̇, Σ fₜ,ᵢ sᵢ) dt` from `t0` to `t1` on the last step's dense output, in the
    /// current mode; zero where the last step does not cover both (a restart at the same time).
    fn integrate_power(&mut self, t0: f64, t1: f64) -> Result<[f64; 4], Error> {
        let (start, end) = (self.stepper.t_previous(), self.stepper.t());
        let covered = start < end && start <= t0.min(t1) && t0.max(t1) <= end;
        if !covered {
            debug_assert!(
                t0 == t1,
                "the energy balance from {t0} to {t1} outside the last step [{start}, {end}]"
            );
            return Ok([0.0; 4]);
        }
        self.dense()?;
        let whole = self.gauss(t0, t1)?;
        self.refine(t0, t1, whole, 12)
    }

    /// `∫ power` from `t0` to `t1` whose 5-point estimate is `whole`, within the integrator's
    /// tolerances: accepted where the two halves agree with it, else each half refined, at most
    /// `depth` times. (The step's error control bounds the state, not the powers: a held state
    /// that does not move under a force that does, a table's drive, would otherwise be
    /// integrated over steps of a period.)
    fn refine(&mut self, t0: f64, t1: f64, whole: [f64; 4], depth: u32) -> Result<[f64; 4], Error> {
        let t_mid = 0.5 * (t0 + t1);
        let (left, right) = (self.gauss(t0, t_mid)?, self.gauss(t_mid, t1)?);
        let tol = self.sim.options.tolerances;
        let agree = (0..4).all(|k| {
            let halves = left[k] + right[k];
            (halves - whole[k]).abs() <= tol.atol + tol.rtol * halves.abs()
        });
        if agree || depth == 0 || t_mid <= t0.min(t1) || t_mid >= t0.max(t1) {
            return Ok([0, 1, 2, 3].map(|k| left[k] + right[k]));
        }
        let left = self.refine(t0, t_mid, left, depth - 1)?;
        let right = self.refine(t_mid, t1, right, depth - 1)?;
        Ok([0, 1, 2, 3].map(|k| left[k] + right[k]))
    }

    /// `∫ power` from `t0` to `t1` by 5-point Gauss–Legendre on the last step's interpolant.
    fn gauss(&mut self, t0: f64, t1: f64) -> Result<[f64; 4], Error> {
        let mut y = vec![0.0; 2 * self.n];
        let mut sum = [0.0; 4];
        let h = t1 - t0;
        for (node, weight) in gauss() {
            let t = t0 + node * h;
            interpolate(&self.stepper, self.cubic, t, &mut y);
            let power = self
                .power(t, &y)
                .map_err(|err| self.dynamics_error(err, t, &y))?;
            for (s, p) in sum.iter_mut().zip(power) {
                *s += weight * h * p;
            }
        }
        Ok(sum)
    }

    /// The powers `(Q·q̇, −∂ₜL, −Σλᵢ Aᵢq̇ − Σ fₜ,ᵢ s₀,ᵢ, Σ fₜ,ᵢ sᵢ)` at `(t, y)` in the current
    /// mode; on the held constraints, where `ḣᵢ = 0`, `−λᵢ Aᵢq̇ = λᵢ ∂ₜhᵢ`: exactly 0 on a
    /// surface that does not move (`−λ A q̇` would be the rounding of `A q̇`); friction's power
    /// is that of the slipping contacts (a sticking one has `s = 0`), and what a moving surface
    /// does through it (`s₀`, the slip's part of the surface's own velocity) is the surface's.
    fn power(&mut self, t: f64, y: &[f64]) -> Result<[f64; 4], DynamicsError> {
        let (q, q_dot) = y.split_at(self.n);
        let (forces, drive) = if self.sim.model.is_autonomous() {
            (0.0, 0.0)
        } else {
            powers(self.sim.model, t, q, q_dot)
        };
        // Σ λᵢ ∂ₜhᵢ, summed as `Iterator::sum` does (from −0), 0 where nothing is held.
        let mut constraints: Option<f64> = None;
        let mut friction = 0.0;
        let slipping = self.grips.slipping();
        let mut w = vec![0.0; self.n];
        let (held, grips) = (self.held(), self.grips);
        contact::multipliers(
            &self.mech,
            held,
            grips,
            t,
            q,
            q_dot,
            &mut w,
            |i, l, h_t, f, s, s0| {
                // A surface that moves under a contact with friction (a belt) works on the body
                // through fₜ too: `fₜ S q̇ = fₜ s − fₜ s₀`, the second part its own.
                let surface = f[0] * s0[0] + f[1] * s0[1];
                let surface = if surface != 0.0 { surface } else { 0.0 };
                constraints = Some(constraints.unwrap_or(-0.0) + l * h_t - surface);
                if slipping.contains(i) {
                    friction += f[0] * s[0] + f[1] * s[1];
                }
            },
        )?;
        Ok([forces, drive, constraints.unwrap_or(0.0), friction])
    }

    /// The work `−Σ Λᵢ ∂ₜhᵢ` of the impulses that took the normal velocities of `contacts` from
    /// those of `before` to those of `after`.
    fn impulse_work(
        &self,
        contacts: ActiveSet,
        t: f64,
        before: &[f64],
        after: &[f64],
    ) -> Result<f64, DynamicsError> {
        let n = self.n;
        let c = Contacts::at(&self.mech, contacts, t, &after[..n], &after[n..]).map_err(|e| e.0)?;
        let h_dot_before: Vec<f64> = c
            .indices
            .iter()
            .map(|&i| guard_along(self.sim.model, i, t, &before[..n], &before[n..]).1)
            .collect();
        let impulses = c.impulses_from(&h_dot_before)?;
        Ok(-impulses
            .iter()
            .zip(&c.normals)
            .map(|(l, normal)| l * normal.h_t)
            .sum::<f64>())
    }

    /// The jump of an event at `t` from `before` to `after` in the balance: an impact's
    /// impulses lose `−½ Σ Λᵢ (ḣᵢ⁺ + ḣᵢ⁻)` and do the work `−Σ Λᵢ ∂ₜhᵢ` (their law's,
    /// [`crate::contact::ImpactLaw`]);
    /// any other change of state (the switch at a Zeno point onto `contacts`) loses what the
    /// energy measures, less its impulse's work on a surface that moves.
    pub(super) fn record_jump(
        &mut self,
        kind: EventKind,
        contacts: ActiveSet,
        t: f64,
        before: &[f64],
        after: &[f64],
    ) -> Result<(), Error> {
        let n = self.n;
        let model = self.sim.model;
        if kind == EventKind::Impact {
            // From the law, as the impact left it (`ImpactLaw`).
            let (loss, work) = self.record.jump.take().unwrap_or((0.0, 0.0));
            self.record.work.impact_loss += loss;
            self.record.work.constraints += work;
        } else if before != after {
            let e_before = energy(model, t, &before[..n], &before[n..]);
            let e_after = energy(model, t, &after[..n], &after[n..]);
            // On a surface that moves, the switch's plastic impulse does work as an impact's
            // does (the ball brought to the table's velocity): that goes to the constraints.
            let impulse_work = if model.is_autonomous() || contacts.is_empty() {
                0.0
            } else {
                self.impulse_work(contacts, t, before, after)
                    .map_err(|err| self.dynamics_error(err, t, after))?
            };
            self.record.work.constraints += impulse_work;
            self.record.work.impact_loss += e_before - e_after + impulse_work;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::gauss;

    #[test]
    fn the_quadrature_is_exact_to_degree_nine_and_no_further() {
        let integral = |k: i32| gauss().iter().map(|(x, w)| w * x.powi(k)).sum::<f64>();
        for k in 0..=9 {
            let exact = 1.0 / f64::from(k + 1);
            assert!(
                (integral(k) - exact).abs() <= 4.0 * f64::EPSILON,
                "degree {k}"
            );
        }
        assert!((integral(10) - 1.0 / 11.0).abs() > 1e-8);
    }
}
