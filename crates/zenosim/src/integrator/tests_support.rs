//! Test systems with closed-form solutions and helpers shared by the tests.

use std::convert::Infallible;

use super::{Method, OdeSystem, StepError, Stepper, Tolerances};

/// Both methods, for tests that run each.
pub(super) const METHODS: [Method; 2] = [Method::Dop853, Method::Dopri5];

/// Error type of the fallible test systems.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Refused;

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("refused")
    }
}

impl std::error::Error for Refused {}

/// `y' = lambda * y` (solution `y0 * exp(lambda t)`), counting its evaluations.
pub(super) struct Linear {
    pub lambda: f64,
    pub calls: u64,
}

impl Linear {
    pub(super) fn new(lambda: f64) -> Self {
        Self { lambda, calls: 0 }
    }
}

impl OdeSystem for Linear {
    type Error = Infallible;
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Infallible> {
        self.calls += 1;
        dy[0] = self.lambda * y[0];
        Ok(())
    }
}

/// Harmonic oscillator `x' = v, v' = -x` (solution `cos t, -sin t` from `(1, 0)`).
pub(super) struct Oscillator {
    pub calls: u64,
}

impl OdeSystem for Oscillator {
    type Error = Infallible;
    fn dimension(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Infallible> {
        self.calls += 1;
        dy[0] = y[1];
        dy[1] = -y[0];
        Ok(())
    }
}

/// Kepler problem `q'' = -q / |q|^3` (HNW I, II.10), state `(q1, q2, p1, p2)`.
pub(super) struct Kepler;

impl OdeSystem for Kepler {
    type Error = Infallible;
    fn dimension(&self) -> usize {
        4
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Infallible> {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r3 = r2 * r2.sqrt();
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = -y[0] / r3;
        dy[3] = -y[1] / r3;
        Ok(())
    }
}

/// Closed-form Kepler orbit with semi-major axis 1 and eccentricity `e`,
/// starting at perihelion at `t = 0`: solve Kepler's equation
/// `E - e sin E = t` by Newton's method, then `q = (cos E - e, sqrt(1-e^2) sin E)`
/// and `p = dq/dt` with `dE/dt = 1 / (1 - e cos E)`.
pub(super) fn kepler_exact(e: f64, t: f64) -> [f64; 4] {
    let mut big_e = t;
    for _ in 0..100 {
        let delta = (big_e - e * big_e.sin() - t) / (1.0 - e * big_e.cos());
        big_e -= delta;
        if delta.abs() < 1e-16 {
            break;
        }
    }
    let (s, c) = big_e.sin_cos();
    let w = (1.0 - e * e).sqrt();
    let rate = 1.0 / (1.0 - e * c);
    [c - e, w * s, -s * rate, w * c * rate]
}

/// Polynomial right-hand side `y1' = 2t, y2' = 3t^2` (solution `t^2, t^3`).
pub(super) struct Polynomial;

impl OdeSystem for Polynomial {
    type Error = Infallible;
    fn dimension(&self) -> usize {
        2
    }
    fn rhs(&mut self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), Infallible> {
        dy[0] = 2.0 * t;
        dy[1] = 3.0 * t * t;
        Ok(())
    }
}

/// `y' = -y` that refuses states with `y < 0` (the solution `exp(-t)` stays positive).
pub(super) struct RefuseNegative {
    pub refusals: u64,
    pub calls: u64,
}

impl OdeSystem for RefuseNegative {
    type Error = Refused;
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Refused> {
        self.calls += 1;
        if y[0] < 0.0 {
            self.refusals += 1;
            return Err(Refused);
        }
        dy[0] = -y[0];
        Ok(())
    }
}

/// `y' = 1` that fails for every `t > after`.
pub(super) struct FailAfter {
    pub after: f64,
    pub calls: u64,
}

impl OdeSystem for FailAfter {
    type Error = Refused;
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), Refused> {
        self.calls += 1;
        if t > self.after {
            return Err(Refused);
        }
        dy[0] = 1.0;
        Ok(())
    }
}

/// `y' = y^2` (solution `1 / (1 - t)` from `y(0) = 1`, blowing up at `t = 1`).
pub(super) struct Riccati {
    pub calls: u64,
}

impl OdeSystem for Riccati {
    type Error = Infallible;
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Infallible> {
        self.calls += 1;
        dy[0] = y[0] * y[0];
        Ok(())
    }
}

/// Tolerances so loose that no step is ever rejected: with `h_max = h` and a
/// start hint `h` the stepper then takes fixed steps `h`.
pub(super) const FIXED_STEP: Tolerances = Tolerances {
    rtol: 1e6,
    atol: 1e6,
};

/// Integrates from `(t0, y0)` to `t_end` with unrestricted steps, returning the stepper.
pub(super) fn integrate<S: OdeSystem>(
    method: Method,
    tol: Tolerances,
    sys: &mut S,
    t0: f64,
    y0: &[f64],
    t_end: f64,
) -> Result<Stepper, StepError<S::Error>> {
    let mut st = Stepper::new(method, y0.len(), tol);
    st.start(sys, t0, y0, None)?;
    while st.t() != t_end {
        st.step(sys, t_end, f64::INFINITY)?;
    }
    Ok(st)
}

/// Fixed-step integration of `n` steps of size `(t_end - t0) / n` (up to a
/// relative 1e-9, so that rounding cannot leave a sliver step at the end).
pub(super) fn fixed_steps<S: OdeSystem>(
    method: Method,
    sys: &mut S,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    n: u32,
) -> Stepper
where
    S::Error: std::fmt::Debug,
{
    let h = (t_end - t0) / f64::from(n);
    let mut st = Stepper::new(method, y0.len(), FIXED_STEP);
    st.start(sys, t0, y0, Some(h)).unwrap();
    while st.t() != t_end {
        st.step(sys, t_end, h * (1.0 + 1e-9)).unwrap();
    }
    assert_eq!(
        st.stats().steps,
        u64::from(n),
        "fixed-step run took other steps"
    );
    assert_eq!(st.stats().rejected_steps, 0);
    st
}

/// Least-squares slope of `log(err)` against `log(h)`.
pub(super) fn fitted_order(hs: &[f64], errs: &[f64]) -> f64 {
    let xs: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Max-norm distance.
pub(super) fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
