//! Accuracy tests against closed-form solutions: global error, measured
//! convergence orders of the step and of the continuous extension, exactness
//! on polynomial solutions.

use super::tests_support::{
    fitted_order, fixed_steps, integrate, kepler_exact, max_diff, Kepler, Linear, Oscillator,
    Polynomial, FIXED_STEP, METHODS,
};
use super::{Method, Stepper, Tolerances};

/// Compact scientific formatting of a list of errors.
fn sci(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:.2e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[test]
fn exponential_growth_reaches_e_within_tolerance() {
    // y' = y, y(0) = 1: y(1) = e (closed form, std::f64::consts::E).
    for method in METHODS {
        for tol in [1e-10, 1e-6] {
            let mut sys = Linear::new(1.0);
            let tols = Tolerances {
                rtol: tol,
                atol: tol,
            };
            let st = integrate(method, tols, &mut sys, 0.0, &[1.0], 1.0).unwrap();
            let err = (st.y()[0] - std::f64::consts::E).abs();
            eprintln!(
                "{method:?} tol {tol:e}: |y(1) - e| = {err:.2e}, {:?}",
                st.stats()
            );
            assert_eq!(st.t(), 1.0);
            assert!(err < 5.0 * tol, "{method:?} tol {tol:e}: error {err:e}");
        }
    }
}

#[test]
fn harmonic_oscillator_ten_periods() {
    // x' = v, v' = -x from (1, 0): (cos t, -sin t), energy (x^2 + v^2)/2 = 1/2.
    for method in METHODS {
        let t_end = 20.0 * std::f64::consts::PI;
        let mut sys = Oscillator { calls: 0 };
        let mut st = Stepper::new(method, 2, Tolerances::default());
        st.start(&mut sys, 0.0, &[1.0, 0.0], None).unwrap();
        let (mut max_err, mut max_drift) = (0.0f64, 0.0f64);
        while st.t() < t_end {
            st.step(&mut sys, t_end, f64::INFINITY).unwrap();
            let (t, y) = (st.t(), st.y());
            max_err = max_err.max(max_diff(y, &[t.cos(), -t.sin()]));
            max_drift = max_drift.max((0.5 * (y[0] * y[0] + y[1] * y[1]) - 0.5).abs());
        }
        let stats = st.stats();
        eprintln!(
            "{method:?} oscillator 10 periods at 1e-10: max error {max_err:.2e}, energy drift \
             {max_drift:.2e}, {stats:?}"
        );
        assert_eq!(stats.rhs_evals, sys.calls);
        assert!(max_err < 1e-8, "{method:?}: error {max_err:e}");
        assert!(max_drift < 1e-8, "{method:?}: energy drift {max_drift:e}");
    }
}

/// Errors at `t = 2` of fixed-step runs of the Kepler problem (e = 0.5).
fn kepler_fixed_step_errors(method: Method, steps: &[u32]) -> (Vec<f64>, Vec<f64>) {
    let (e, t_end) = (0.5, 2.0);
    let y0 = kepler_exact(e, 0.0);
    let exact = kepler_exact(e, t_end);
    let hs = steps.iter().map(|&n| t_end / f64::from(n)).collect();
    let errs = steps
        .iter()
        .map(|&n| {
            max_diff(
                fixed_steps(method, &mut Kepler, 0.0, &y0, t_end, n).y(),
                &exact,
            )
        })
        .collect();
    (hs, errs)
}

#[test]
fn measured_convergence_orders_8_and_5() {
    // Reference: closed-form Kepler orbit (Kepler's equation, `kepler_exact`).
    for (method, steps) in [
        (Method::Dop853, [16, 24, 32, 48]),
        (Method::Dopri5, [40, 80, 160, 320]),
    ] {
        let (hs, errs) = kepler_fixed_step_errors(method, &steps);
        let order = fitted_order(&hs, &errs);
        eprintln!("{method:?}: errors {}, fitted order {order:.2}", sci(&errs));
        let expected = f64::from(method.order());
        assert!((order - expected).abs() < 0.5, "{method:?}: order {order}");
    }
}

/// Error of the continuous extension at the middle of a single step of size
/// `h` from the Kepler perihelion (e = 0.2), against `kepler_exact`.
fn dense_midpoint_error(method: Method, h: f64) -> f64 {
    let e = 0.2;
    let mut st = Stepper::new(method, 4, FIXED_STEP);
    st.start(&mut Kepler, 0.0, &kepler_exact(e, 0.0), Some(h))
        .unwrap();
    st.step(&mut Kepler, h, h).unwrap();
    assert_eq!(st.t(), h);
    st.prepare_dense(&mut Kepler).unwrap();
    let mut out = [0.0; 4];
    st.interpolate(0.5 * h, &mut out);
    max_diff(&out, &kepler_exact(e, 0.5 * h))
}

#[test]
fn dense_output_orders_7_and_4() {
    // A continuous extension of order p* has local error O(h^(p*+1)) mid-step.
    for (method, hs) in [
        (Method::Dop853, [0.4, 0.3, 0.2, 0.15]),
        (Method::Dopri5, [0.2, 0.1, 0.05, 0.025]),
    ] {
        let errs: Vec<f64> = hs
            .iter()
            .map(|&h| dense_midpoint_error(method, h))
            .collect();
        let slope = fitted_order(&hs, &errs);
        eprintln!(
            "{method:?} dense: errors {}, local slope {slope:.2}",
            sci(&errs)
        );
        let expected = f64::from(method.dense_order() + 1);
        assert!(
            (slope - expected).abs() < 0.5,
            "{method:?}: dense slope {slope}"
        );
    }
}

#[test]
fn dense_output_is_exact_at_both_ends_and_close_inside() {
    // Kepler orbit (e = 0.5) over one period, reference `kepler_exact`.
    let e = 0.5;
    let t_end = 2.0 * std::f64::consts::PI;
    for method in METHODS {
        let mut st = Stepper::new(
            method,
            4,
            Tolerances {
                rtol: 1e-9,
                atol: 1e-9,
            },
        );
        st.start(&mut Kepler, 0.0, &kepler_exact(e, 0.0), None)
            .unwrap();
        let mut out = [0.0; 4];
        let mut max_err = 0.0f64;
        while st.t() < t_end {
            st.step(&mut Kepler, t_end, f64::INFINITY).unwrap();
            st.prepare_dense(&mut Kepler).unwrap();
            st.interpolate(st.t_previous(), &mut out);
            assert_eq!(out, st.y_previous(), "{method:?}: start of step");
            st.interpolate(st.t(), &mut out);
            assert_eq!(out, st.y(), "{method:?}: end of step");
            for frac in [0.25, 0.5, 0.75] {
                let t = st.t_previous() + frac * (st.t() - st.t_previous());
                st.interpolate(t, &mut out);
                max_err = max_err.max(max_diff(&out, &kepler_exact(e, t)));
            }
        }
        eprintln!("{method:?}: dense error inside steps at 1e-9: {max_err:.2e}");
        assert!(max_err < 1e-6, "{method:?}: dense error {max_err:e}");
    }
}

/// Steps `y1' = 2t, y2' = 3t^2` from (0, 0), whose solution `(t^2, t^3)` every step takes
/// exactly, and checks `interpolate` (after `prepare`) inside each step against it, and at the
/// step's ends against its states.
fn exact_on_cubics(
    prepare: fn(&mut Stepper),
    interpolate: fn(&Stepper, f64, &mut [f64]),
    ends_exact: bool,
) {
    for method in METHODS {
        let mut st = Stepper::new(method, 2, Tolerances::default());
        st.start(&mut Polynomial, 0.0, &[0.0, 0.0], Some(0.1))
            .unwrap();
        let mut out = [0.0; 2];
        let t_end = 3.0;
        while st.t() < t_end {
            st.step(&mut Polynomial, t_end, 0.7).unwrap();
            let (t0, t) = (st.t_previous(), st.t());
            assert!(max_diff(st.y(), &[t * t, t * t * t]) <= 1e-14 * t.powi(3).max(1.0));
            prepare(&mut st);
            if ends_exact {
                interpolate(&st, t0, &mut out);
                assert_eq!(out, st.y_previous(), "{method:?}: the step's start");
                interpolate(&st, t, &mut out);
                assert_eq!(out, st.y(), "{method:?}: the step's end");
            }
            for frac in [0.1, 0.5, 0.9] {
                let s = t0 + frac * (t - t0);
                interpolate(&st, s, &mut out);
                let err = max_diff(&out, &[s * s, s * s * s]);
                assert!(
                    err <= 1e-14 * s.powi(3).max(1.0),
                    "{method:?} at {s}: {err:e}"
                );
            }
        }
        assert_eq!(st.t(), t_end);
    }
}

#[test]
fn polynomial_solutions_are_exact_including_dense_output() {
    exact_on_cubics(
        |st| st.prepare_dense(&mut Polynomial).unwrap(),
        |st, t, out| st.interpolate(t, out),
        false,
    );
}

#[test]
fn the_cubic_interpolant_is_exact_on_cubics_and_at_the_ends() {
    // The Hermite cubic through a step's ends reproduces (t^2, t^3) (up to rounding), without
    // the dense output's evaluations.
    exact_on_cubics(|_| {}, |st, t, out| st.interpolate_cubic(t, out), true);
    // A state that does not move stays exactly what it is (y' = 0).
    let mut still = Linear::new(0.0);
    let mut st = Stepper::new(Method::Dop853, 1, Tolerances::default());
    st.start(&mut still, 0.0, &[0.3], Some(1.0)).unwrap();
    st.step(&mut still, 1.0, f64::INFINITY).unwrap();
    assert_eq!(st.t(), 1.0);
    let mut out = [0.0];
    for s in [0.1, 0.5, 0.7, 0.999] {
        st.interpolate_cubic(s, &mut out);
        assert_eq!(out[0], 0.3, "at {s}");
    }
    // Elsewhere it is of order 3 only: y' = y over one step of 0.5 from 1, at its middle,
    // is off by about h^4 y/384 (the cubic's remainder), far more than the step's error.
    let mut growth = Linear::new(1.0);
    let loose = Tolerances {
        rtol: 1e-3,
        atol: 1e-3,
    };
    let mut st = Stepper::new(Method::Dop853, 1, loose);
    st.start(&mut growth, 0.0, &[1.0], Some(0.5)).unwrap();
    st.step(&mut growth, 0.5, 0.5).unwrap();
    assert_eq!(st.t(), 0.5);
    st.interpolate_cubic(0.25, &mut out);
    let err = (out[0] - 0.25f64.exp()).abs();
    let remainder = 0.5f64.powi(4) / 384.0 * 0.25f64.exp();
    assert!(
        err > 0.5 * remainder && err < 2.0 * remainder,
        "cubic error {err:e}, remainder {remainder:e}"
    );
}
