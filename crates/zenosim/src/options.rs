//! The options of a run, each with its default and the reason for it.

use crate::error::Error;
use crate::integrator::{Method, Tolerances};

/// How a Zeno execution is carried past its Zeno point.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum ZenoStrategy {
    /// Default. After each impact, predict the remaining time to `τ∞` (the next flight
    /// `2 A q̇⁺/|ḧ|` summed geometrically with ratio `e`) and switch to the constrained motion
    /// once the state change that the remaining bounces make is below the integration tolerance.
    /// The post-Zeno motion is then as accurate as the integration.
    #[default]
    Auto,
    /// The paper's rule `H̄ε`: switch when `|h| ≤ ε` and `|A q̇| ≤ ε`, tested on the state just
    /// before each impact, as the authors' demos do (they use `ε = 1e-3`).
    Epsilon(f64),
    /// The plain hybrid system: impacts only. The run stops by itself with
    /// `Outcome::ZenoStalled` once the impacts accumulate below what `f64` time can resolve.
    Off,
}

/// The map `R∞` used at the switch to the constrained motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Completion {
    /// Default: the general projection (positions onto `h = 0` along `M⁻¹Aᵀ`, velocities by the
    /// plastic impact). Physically right for every model: it keeps every momentum the
    /// constraint does not touch.
    #[default]
    Projection,
    /// The model's own map ([`crate::HybridLagrangian::completion_map`]), then the projection to
    /// remove what it leaves off the constraint. Falls back to the projection if it has none.
    ///
    /// With [`ZenoStrategy::Auto`] the state is projected before the map as well: the switch
    /// comes a few bounces before `τ∞` (once they are below what `f64` resolves of `h`), and a
    /// map that keeps some velocities and solves for others (the paper's) would turn the normal
    /// velocity of the bounces not taken into a tangential error (3.8e-5 at `t = 20` on the
    /// authors' demo ball). With [`ZenoStrategy::Epsilon`] the map acts on the state just
    /// before the impact, as in the paper.
    ModelMap,
}

/// Where the trajectory is sampled for the observer.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum OutputGrid {
    /// Default: at the end of every accepted step (plus the states around every event).
    #[default]
    Steps,
    /// Uniformly every `dt`, from the dense output (plus the states around every event).
    Uniform(f64),
}

/// The options of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulationOptions {
    /// The stop time. Default 10.
    pub t_end: f64,
    /// Relative and absolute tolerances. Default `1e-10` each: tight enough that the post-Zeno
    /// motion is accurate to well below plotting resolution, and cheap with an 8th-order pair.
    pub tolerances: Tolerances,
    /// The Runge–Kutta pair. Default DOP853 (efficient at tight tolerances).
    pub method: Method,
    /// The Zeno strategy. Default [`ZenoStrategy::Auto`].
    pub zeno: ZenoStrategy,
    /// The completion map. Default [`Completion::Projection`].
    pub completion: Completion,
    /// The output grid. Default [`OutputGrid::Steps`].
    pub output: OutputGrid,
    /// The largest step. Default infinity (the error control decides).
    pub max_step: f64,
    /// The most events (impacts, switches, lift-offs) a run may have before it stops as failed.
    /// Default 100 000: a Zeno sequence needs about `log(tolerance)/log(e)` impacts (26 for the
    /// paper's ball, 126 for the cart pendulum and 258 for the bouncing ball with `e = 0.9`,
    /// 230 000 for `e = 0.9999`: raise it for such models), and
    /// a storm ends in well under a second.
    pub max_events: u64,
    /// The most accepted steps a run may take before it stops as failed. Default 10 000 000.
    pub max_steps: u64,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        Self {
            t_end: 10.0,
            tolerances: Tolerances::default(),
            method: Method::default(),
            zeno: ZenoStrategy::default(),
            completion: Completion::default(),
            output: OutputGrid::default(),
            max_step: f64::INFINITY,
            max_events: 100_000,
            max_steps: 10_000_000,
        }
    }
}

impl SimulationOptions {
    /// Checks every option, naming the first one that is wrong.
    pub fn validate(&self) -> Result<(), Error> {
        let positive = |option, value: f64, expected| {
            if value > 0.0 && value.is_finite() {
                Ok(())
            } else {
                Err(Error::Option {
                    option,
                    value,
                    expected,
                })
            }
        };
        if !(self.t_end.is_finite() && self.t_end > 0.0) {
            return Err(Error::Option {
                option: "t_end",
                value: self.t_end,
                expected: "a finite stop time > 0",
            });
        }
        positive(
            "rtol",
            self.tolerances.rtol,
            "a relative tolerance > 0 (e.g. 1e-10)",
        )?;
        positive(
            "atol",
            self.tolerances.atol,
            "an absolute tolerance > 0 (e.g. 1e-10)",
        )?;
        if self.tolerances.rtol < 1e-15 {
            return Err(Error::Option {
                option: "rtol",
                value: self.tolerances.rtol,
                expected: "at least 1e-15: f64 cannot resolve less",
            });
        }
        if self.max_step.is_nan() || self.max_step <= 0.0 {
            return Err(Error::Option {
                option: "max_step",
                value: self.max_step,
                expected: "a largest step > 0 (infinity for none)",
            });
        }
        if let ZenoStrategy::Epsilon(eps) = self.zeno {
            positive(
                "zeno epsilon",
                eps,
                "a threshold ε > 0 (the paper uses 1e-3)",
            )?;
        }
        if let OutputGrid::Uniform(dt) = self.output {
            if !(dt.is_finite() && dt > 0.0) {
                return Err(Error::Option {
                    option: "dt",
                    value: dt,
                    expected: "a finite sampling interval > 0",
                });
            }
            // A grid denser than the step limit allows is a slip (dt = 1e-9 over t_end = 3
            // would write 3e9 rows): it would run for hours and fill the disk.
            if self.t_end / dt > self.max_steps as f64 {
                return Err(Error::Option {
                    option: "dt",
                    value: dt,
                    expected: "at most max_steps samples over t_end (t_end / dt ≤ max_steps): \
                               use a larger dt, or raise max_steps",
                });
            }
        }
        Ok(())
    }
}
