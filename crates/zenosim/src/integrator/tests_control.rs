//! Tests of the step loop: stopping times, step limits, work counters,
//! failing and non-finite right-hand sides, restarts.

use super::tests_support::{
    integrate, max_diff, FailAfter, Linear, Oscillator, RefuseNegative, Refused, Riccati, METHODS,
};
use super::{Method, OdeSystem, StepError, Stepper, Tolerances};

#[test]
fn steps_never_pass_t_stop_and_respect_h_max() {
    for method in METHODS {
        let mut sys = Oscillator { calls: 0 };
        let mut st = Stepper::new(
            method,
            2,
            Tolerances {
                rtol: 1e-8,
                atol: 1e-8,
            },
        );
        st.start(&mut sys, 0.0, &[1.0, 0.0], None).unwrap();
        let stops = [0.013, 0.5, 0.5 + 1e-13, 1.7, 1.7000001, 3.0, 10.0];
        let h_max = 0.3;
        for &t_stop in &stops {
            while st.t() < t_stop {
                let before = st.t();
                st.step(&mut sys, t_stop, h_max).unwrap();
                assert!(st.t() <= t_stop, "{method:?}: passed {t_stop}");
                assert_eq!(st.t_previous(), before);
                // At most h_max, up to the rounding of t + h.
                let slack = 2.0 * f64::EPSILON * st.t().abs();
                assert!(
                    st.t() - before <= h_max + slack,
                    "{method:?}: step longer than h_max"
                );
            }
            assert_eq!(st.t(), t_stop, "{method:?}: must land exactly on t_stop");
        }
        // t_stop == t is a no-op.
        let stats = st.stats();
        st.step(&mut sys, 10.0, h_max).unwrap();
        assert_eq!((st.t(), st.stats()), (10.0, stats));
        // The controller's proposal survives the shortened landing steps.
        assert!(
            st.suggested_step() > 0.05,
            "{method:?}: {}",
            st.suggested_step()
        );
    }
}

#[test]
fn backward_integration_lands_on_t_stop() {
    // y' = y from y(1) = e back to t = 0: y(0) = 1 (closed form).
    for method in METHODS {
        let mut sys = Linear::new(1.0);
        let st = integrate(
            method,
            Tolerances::default(),
            &mut sys,
            1.0,
            &[std::f64::consts::E],
            0.0,
        )
        .unwrap();
        assert_eq!(st.t(), 0.0);
        assert!((st.y()[0] - 1.0).abs() < 1e-9, "{method:?}: {}", st.y()[0]);
    }
}

#[test]
fn statistics_count_steps_rejections_and_evaluations() {
    // y' = -50 y with a far too large first step (hint 1): rejections happen.
    // Per trial DOPRI5 evaluates 6 times; DOP853 11 times plus the FSAL stage
    // f(t + h, y_new) on acceptance; start costs 1 (+1 for hinit).
    for method in METHODS {
        let mut sys = Linear::new(-50.0);
        let mut st = Stepper::new(
            method,
            1,
            Tolerances {
                rtol: 1e-9,
                atol: 1e-12,
            },
        );
        st.start(&mut sys, 0.0, &[1.0], Some(1.0)).unwrap();
        let mut dense_calls = 0;
        while st.t() < 1.0 {
            st.step(&mut sys, 1.0, f64::INFINITY).unwrap();
            st.prepare_dense(&mut sys).unwrap();
            st.prepare_dense(&mut sys).unwrap(); // at most once per step
            dense_calls += 1;
        }
        let s = st.stats();
        assert!(
            s.rejected_steps > 0,
            "{method:?}: the large hint must be rejected"
        );
        assert_eq!(s.rhs_evals, sys.calls, "{method:?}: counted evaluations");
        let expected = match method {
            Method::Dop853 => 1 + 12 * s.steps + 11 * s.rejected_steps + 3 * dense_calls,
            Method::Dopri5 => 1 + 6 * (s.steps + s.rejected_steps),
        };
        assert_eq!(s.rhs_evals, expected, "{method:?}: {s:?}");
        assert_eq!(s.steps, dense_calls);

        // A restart keeps the statistics; hinit costs one probe evaluation.
        st.start(&mut sys, 0.0, &[1.0], None).unwrap();
        assert_eq!(st.stats().rhs_evals, expected + 2);
        assert_eq!(st.stats().steps, s.steps);
        assert!(st.suggested_step() > 0.0 && st.suggested_step() < 1.0);
    }
}

#[test]
fn refused_evaluations_shrink_the_step_and_integration_succeeds() {
    // y' = -y, y(0) = 1 refuses y < 0; the solution exp(-t) stays positive.
    // (atol is negligible so that the relative error is controlled down to exp(-20).)
    for method in METHODS {
        let mut sys = RefuseNegative {
            refusals: 0,
            calls: 0,
        };
        let mut st = Stepper::new(
            method,
            1,
            Tolerances {
                rtol: 1e-10,
                atol: 1e-30,
            },
        );
        st.start(&mut sys, 0.0, &[1.0], Some(50.0)).unwrap();
        while st.t() < 20.0 {
            st.step(&mut sys, 20.0, f64::INFINITY).unwrap();
        }
        let exact = (-20.0f64).exp();
        assert!(
            sys.refusals > 0,
            "{method:?}: the test must exercise refusals"
        );
        assert!(st.stats().rejected_steps >= sys.refusals);
        assert_eq!(st.stats().rhs_evals, sys.calls);
        let rel = (st.y()[0] - exact).abs() / exact;
        eprintln!(
            "{method:?}: {} refusals, relative error {rel:.1e}, {:?}",
            sys.refusals,
            st.stats()
        );
        assert!(rel < 5e-9, "{method:?}: relative error {rel:e}");
    }
}

#[test]
fn persistently_failing_rhs_returns_rhs_error() {
    for method in METHODS {
        // Fails everywhere: already at the start.
        let mut sys = FailAfter {
            after: f64::NEG_INFINITY,
            calls: 0,
        };
        let mut st = Stepper::new(method, 1, Tolerances::default());
        let r = st.start(&mut sys, 0.0, &[0.0], None);
        assert!(
            matches!(
                r,
                Err(StepError::Rhs {
                    t: 0.0,
                    source: Refused
                })
            ),
            "{r:?}"
        );

        // Fails for every t > 0: the step shrinks to underflow, then reports Rhs.
        let mut sys = FailAfter {
            after: 0.0,
            calls: 0,
        };
        st.start(&mut sys, 0.0, &[0.0], None).unwrap();
        let r = st.step(&mut sys, 1.0, f64::INFINITY);
        assert!(
            matches!(
                r,
                Err(StepError::Rhs {
                    t: 0.0,
                    source: Refused
                })
            ),
            "{r:?}"
        );
        assert_eq!(st.t(), 0.0);
        assert!(sys.calls < 200, "{method:?}: {} calls", sys.calls);
        let message = r.unwrap_err();
        let source = std::error::Error::source(&message).map(|e| e.to_string());
        assert_eq!(source.as_deref(), Some("refused"));
    }
}

#[test]
fn blow_up_returns_an_error_and_never_hangs() {
    // y' = y^2, y(0) = 1: y = 1 / (1 - t) blows up at t = 1 < t_stop = 2.
    for method in METHODS {
        let mut sys = Riccati { calls: 0 };
        let mut st = Stepper::new(method, 1, Tolerances::default());
        st.start(&mut sys, 0.0, &[1.0], None).unwrap();
        let mut outcome = None;
        for _ in 0..100_000 {
            if let Err(e) = st.step(&mut sys, 2.0, f64::INFINITY) {
                outcome = Some(e);
                break;
            }
        }
        eprintln!(
            "{method:?}: {outcome:?} after {:?}, y = {:e}",
            st.stats(),
            st.y()[0]
        );
        assert!(
            matches!(
                outcome,
                Some(StepError::StepSizeUnderflow { .. } | StepError::NonFinite { .. })
            ),
            "{method:?}: {outcome:?}"
        );
        // The numerical solution has its own pole, within O(tol) of t = 1.
        assert!(
            (st.t() - 1.0).abs() < 1e-6,
            "{method:?}: stopped at {}",
            st.t()
        );
    }
}

/// The oscillator kept on its circle `x² + v² = 1` by [`OdeSystem::correct_end`], which
/// rescales each accepted end onto it (and refuses once `refuse_after` ends were corrected);
/// with `push`, it moves the end off the circle by that much instead.
struct OnCircle {
    oscillator: Oscillator,
    corrections: u64,
    refuse_after: u64,
    push: f64,
}

impl OnCircle {
    fn new(refuse_after: u64) -> Self {
        Self {
            oscillator: Oscillator { calls: 0 },
            corrections: 0,
            refuse_after,
            push: 0.0,
        }
    }
}

impl OdeSystem for OnCircle {
    type Error = Refused;
    fn dimension(&self) -> usize {
        2
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Refused> {
        let Ok(()) = self.oscillator.rhs(t, y, dy);
        Ok(())
    }
    fn correct_end(&mut self, _t: f64, y: &mut [f64]) -> Result<bool, Refused> {
        if self.corrections >= self.refuse_after {
            return Err(Refused);
        }
        self.corrections += 1;
        if self.push != 0.0 {
            y[0] += self.push;
        } else {
            let r = y[0].hypot(y[1]);
            y.iter_mut().for_each(|x| *x /= r);
        }
        Ok(true)
    }
}

#[test]
fn a_corrected_end_is_where_the_next_step_starts_and_the_dense_output_ends() {
    for method in METHODS {
        let mut sys = OnCircle::new(u64::MAX);
        let tol = Tolerances {
            rtol: 1e-6,
            atol: 1e-6,
        };
        let mut st = Stepper::new(method, 2, tol);
        // A first step far too long: rejected trials, which are not corrected.
        st.start(&mut sys, 0.0, &[1.0, 0.0], Some(2.0)).unwrap();
        while st.t() < 5.0 {
            let (calls, rejected) = (sys.oscillator.calls, st.stats().rejected_steps);
            st.step(&mut sys, 5.0, f64::INFINITY).unwrap();
            // On the circle to rounding, and the end evaluated there (no evaluation more).
            let y = st.y();
            assert!(
                (y[0].hypot(y[1]) - 1.0).abs() < 4.0 * f64::EPSILON,
                "{method:?}"
            );
            assert_eq!(st.dy(), &[y[1], -y[0]][..], "{method:?}");
            // DOPRI5's error estimate takes f at the uncorrected end: f once more at the
            // corrected one.
            let stages = if method == Method::Dop853 { 12 } else { 7 };
            if st.stats().rejected_steps == rejected {
                assert_eq!(sys.oscillator.calls - calls, stages, "{method:?}");
            }
            let (t, y) = (st.t(), st.y().to_vec());
            st.prepare_dense(&mut sys).unwrap();
            let mut out = [0.0; 2];
            st.interpolate(t, &mut out);
            assert_eq!(
                &out[..],
                &y[..],
                "{method:?}: dense output ends at the corrected end"
            );
        }
        assert!(st.stats().rejected_steps > 0, "{method:?}");
        assert_eq!(sys.corrections, st.stats().steps, "{method:?}");
        // Still the oscillator's solution, within the tolerance.
        assert!(
            max_diff(st.y(), &[5f64.cos(), -5f64.sin()]) < 1e-5,
            "{method:?}"
        );
    }
}

#[test]
fn the_error_test_sees_the_uncorrected_end() {
    // A correction that moves the end by 1e-3, far beyond the tolerance, changes nothing of
    // how the first step is tried, rejected, accepted and sized (to the bit), against the same
    // system without a correction: its error test comes before the correction. (The next steps
    // start from the moved end.)
    for method in METHODS {
        let mut plain_sys = Oscillator { calls: 0 };
        let mut plain = Stepper::new(method, 2, Tolerances::default());
        plain
            .start(&mut plain_sys, 0.0, &[1.0, 0.0], Some(1.0))
            .unwrap();
        plain.step(&mut plain_sys, 10.0, f64::INFINITY).unwrap();
        let mut pushed_sys = OnCircle::new(u64::MAX);
        pushed_sys.push = 1e-3;
        let mut pushed = Stepper::new(method, 2, Tolerances::default());
        pushed
            .start(&mut pushed_sys, 0.0, &[1.0, 0.0], Some(1.0))
            .unwrap();
        pushed.step(&mut pushed_sys, 10.0, f64::INFINITY).unwrap();
        let step = |st: &Stepper| (st.t(), st.stats().rejected_steps, st.suggested_step());
        assert!(
            plain.stats().rejected_steps > 0,
            "{method:?}: the first trial is rejected"
        );
        assert_eq!(step(&plain), step(&pushed), "{method:?}");
        assert_eq!(
            pushed_sys.corrections, 1,
            "{method:?}: the accepted trial only"
        );
        assert_eq!(pushed.y()[0], plain.y()[0] + 1e-3, "{method:?}");
        assert_eq!(pushed.y()[1], plain.y()[1], "{method:?}");
    }
}

#[test]
fn a_refused_correction_fails_the_trial_like_a_refused_evaluation() {
    for method in METHODS {
        let mut sys = OnCircle::new(3);
        let mut st = Stepper::new(method, 2, Tolerances::default());
        st.start(&mut sys, 0.0, &[1.0, 0.0], None).unwrap();
        for _ in 0..3 {
            st.step(&mut sys, 10.0, f64::INFINITY).unwrap();
        }
        let (t, y) = (st.t(), st.y().to_vec());
        // Every later trial is refused: the step shrinks until it underflows, and the state
        // stays where the last accepted step left it.
        match st.step(&mut sys, 10.0, f64::INFINITY) {
            Err(StepError::Rhs {
                source: Refused, ..
            }) => {}
            other => panic!("{method:?}: {other:?}"),
        }
        assert_eq!((st.t(), st.y()), (t, &y[..]), "{method:?}");
    }
}

#[test]
fn replace_state_reevaluates_and_keeps_the_last_step() {
    // Oscillator from (1, 0): the last step's extension stays that of the step
    // as computed; the next step starts from the replaced state.
    for method in METHODS {
        for prepare_before in [true, false] {
            let mut sys = Oscillator { calls: 0 };
            let mut st = Stepper::new(method, 2, Tolerances::default());
            st.start(&mut sys, 0.0, &[1.0, 0.0], None).unwrap();
            st.step(&mut sys, 1.0, f64::INFINITY).unwrap();
            st.step(&mut sys, 1.0, f64::INFINITY).unwrap();
            if prepare_before {
                st.prepare_dense(&mut sys).unwrap();
            }
            let (t0, t, h, calls) = (st.t_previous(), st.t(), st.suggested_step(), sys.calls);
            let (y0, y1) = (st.y_previous().to_vec(), st.y().to_vec());
            st.replace_state(&mut sys, &[0.5, 0.25]).unwrap();
            assert_eq!(sys.calls, calls + 1);
            assert_eq!((st.t(), st.t_previous(), st.suggested_step()), (t, t0, h));
            assert_eq!((st.y(), st.dy()), (&[0.5, 0.25][..], &[0.25, -0.5][..]));
            assert_eq!(st.y_previous(), &y0[..]);
            st.prepare_dense(&mut sys).unwrap();
            let mut out = [0.0; 2];
            st.interpolate(t, &mut out);
            assert_eq!(
                out,
                &y1[..],
                "{method:?}: extension ends at the computed state"
            );
            let mid = 0.5 * (t0 + t);
            st.interpolate(mid, &mut out);
            assert!(
                max_diff(&out, &[mid.cos(), -mid.sin()]) < 1e-9,
                "{method:?}: {out:?}"
            );
            st.step(&mut sys, 1.0, f64::INFINITY).unwrap();
            assert_eq!(st.y_previous(), &[0.5, 0.25]);
            assert_eq!(st.dy_previous(), &[0.25, -0.5]);
        }
    }
}

#[test]
#[should_panic(expected = "prepare_dense")]
fn interpolate_without_prepare_dense_panics() {
    let mut sys = Oscillator { calls: 0 };
    let mut st = Stepper::new(Method::default(), 2, Tolerances::default());
    st.start(&mut sys, 0.0, &[1.0, 0.0], None).unwrap();
    st.step(&mut sys, 1.0, f64::INFINITY).unwrap();
    st.interpolate(st.t(), &mut [0.0; 2]);
}

#[test]
fn failed_step_keeps_state_and_prepared_dense_output() {
    // y' = 1 (solution y = t) failing for t > 0.5.
    for method in METHODS {
        let mut sys = FailAfter {
            after: 0.5,
            calls: 0,
        };
        let mut st = Stepper::new(method, 1, Tolerances::default());
        st.start(&mut sys, 0.0, &[0.0], None).unwrap();
        while st.t() < 0.5 {
            st.step(&mut sys, 0.5, 0.2).unwrap();
        }
        st.prepare_dense(&mut sys).unwrap();
        let (t0, y1, stats) = (st.t_previous(), st.y()[0], st.stats());
        assert!(matches!(
            st.step(&mut sys, 1.0, 0.2),
            Err(StepError::Rhs { t: 0.5, .. })
        ));
        assert_eq!(
            (st.t(), st.y(), st.t_previous(), st.stats().steps),
            (0.5, &[y1][..], t0, stats.steps)
        );
        let mut out = [0.0];
        let mid = 0.5 * (t0 + 0.5);
        st.interpolate(mid, &mut out);
        assert!((out[0] - mid).abs() < 1e-15, "{method:?}: {}", out[0]);
    }
}

#[test]
fn rewind_is_a_start_at_the_last_step_without_evaluating_f_again() {
    for method in METHODS {
        let mut sys = Oscillator { calls: 0 };
        let mut rewound = Stepper::new(method, 2, Tolerances::default());
        rewound.start(&mut sys, 0.0, &[1.0, 0.0], None).unwrap();
        rewound.step(&mut sys, 1.0, 0.3).unwrap();
        rewound.step(&mut sys, 1.0, 0.3).unwrap();
        let (t0, y0) = (rewound.t_previous(), rewound.y_previous().to_vec());
        let h = 0.5 * (rewound.t() - t0);

        let calls = sys.calls;
        rewound.rewind(h);
        assert_eq!(sys.calls, calls, "{method:?}: rewind evaluates f");
        assert_eq!((rewound.t(), rewound.y()), (t0, &y0[..]));

        let mut started = Stepper::new(method, 2, Tolerances::default());
        started.start(&mut sys, t0, &y0, Some(h)).unwrap();
        assert_eq!(rewound.dy(), started.dy());
        rewound.step(&mut sys, 1.0, h).unwrap();
        started.step(&mut sys, 1.0, h).unwrap();
        assert_eq!((rewound.t(), rewound.y()), (started.t(), started.y()));
        assert_eq!(rewound.suggested_step(), started.suggested_step());
    }
}

/// Records where [`OdeSystem::rhs_at_end`] was called last, for a Riccati equation whose first
/// steps are rejected (`y' = y²` from 1 blows up at t = 1).
struct EndRecorder {
    inner: Riccati,
    last_end: Option<(f64, f64)>,
    ends: usize,
}

impl OdeSystem for EndRecorder {
    type Error = std::convert::Infallible;
    fn dimension(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Self::Error> {
        self.inner.rhs(t, y, dy)
    }
    fn rhs_at_end(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Self::Error> {
        self.last_end = Some((t, y[0]));
        self.ends += 1;
        self.inner.rhs(t, y, dy)
    }
}

#[test]
fn the_last_evaluation_at_a_trial_s_end_is_at_the_accepted_step_s_end() {
    for method in METHODS {
        let mut sys = EndRecorder {
            inner: Riccati { calls: 0 },
            last_end: None,
            ends: 0,
        };
        let mut st = Stepper::new(method, 1, Tolerances::default());
        // A first step far too long: the trials before the accepted one are rejected.
        st.start(&mut sys, 0.0, &[1.0], Some(0.9)).unwrap();
        // Up to the landing on t_stop = 0.99 (y = 100), each step checked.
        for _ in 0..1000 {
            st.step(&mut sys, 0.99, f64::INFINITY).unwrap();
            assert_eq!(sys.last_end, Some((st.t(), st.y()[0])), "{method:?}");
            if st.t() == 0.99 {
                break;
            }
        }
        assert_eq!(st.t(), 0.99, "{method:?}");
        let stats = st.stats();
        assert!(stats.rejected_steps > 0, "{method:?}: {stats:?}");
        // One per accepted step (DOP853), one per trial (DOPRI5, whose error estimate needs it).
        let trials = (stats.steps + stats.rejected_steps) as usize;
        let expected = match method {
            Method::Dop853 => stats.steps as usize,
            Method::Dopri5 => trials,
        };
        assert_eq!(sys.ends, expected, "{method:?}: {stats:?}");
    }
}

/// A body falling under gravity, `y = (x, v)`, `y' = (v, −g)`: its solution is a parabola, the
/// closed form [`Stepper::step_exact`] is for.
struct Fall;

const G: f64 = 9.81;

impl OdeSystem for Fall {
    type Error = std::convert::Infallible;
    fn dimension(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Self::Error> {
        dy[0] = y[1];
        dy[1] = -G;
        Ok(())
    }
}

/// The state a time `h` after `(x, v)` with `ẍ = dy[1]`, and whether the acceleration is the
/// same at both ends.
fn parabola(y: &[f64], dy: &[f64], h: f64, end: &mut [f64]) {
    end[0] = y[0] + h * (y[1] + 0.5 * h * dy[1]);
    end[1] = y[1] + h * dy[1];
}

fn same_acceleration(start: &[f64], end: &[f64]) -> bool {
    start[1] == end[1]
}

#[test]
fn an_exact_step_is_the_step_the_integrator_takes_for_one_evaluation() {
    for method in METHODS {
        let mut exact = Stepper::new(method, 2, Tolerances::default());
        exact.start(&mut Fall, 0.0, &[1.0, 2.0], Some(0.1)).unwrap();
        for t_stop in [1.0, 10.0] {
            while exact.t() < t_stop {
                // The integrator's step from the same state, for comparison.
                let mut rk = exact.clone();
                rk.step(&mut Fall, t_stop, 0.7).unwrap();
                let evaluations = exact.stats().rhs_evals;
                let taken = exact
                    .step_exact(&mut Fall, t_stop, 0.7, parabola, same_acceleration)
                    .unwrap();
                assert!(taken);
                assert_eq!(exact.stats().rhs_evals, evaluations + 1, "{method:?}");
                // The same step (its size, landing on t_stop), on the closed form; the next
                // one grows as after no error at all.
                assert_eq!(exact.t(), rk.t(), "{method:?}");
                assert_eq!(exact.t_previous(), rk.t_previous(), "{method:?}");
                assert!(exact.suggested_step() >= rk.suggested_step(), "{method:?}");
                let t = exact.t();
                let (h, next) = (t - exact.t_previous(), exact.suggested_step());
                if t < t_stop && h < 0.6 {
                    // Not shortened (by t_stop or h_max = 0.7): the largest growth (6 for
                    // DOP853, 10 for DOPRI5).
                    let growth = if method == Method::Dop853 { 6.0 } else { 10.0 };
                    // (h as t − t_previous, up to its rounding.)
                    assert!((next - h * growth).abs() <= 4.0 * f64::EPSILON * next);
                }
                let closed = [1.0 + 2.0 * t - 0.5 * G * t * t, 2.0 - G * t];
                let scale = 1.0 + G * t * t;
                assert!(max_diff(exact.y(), &closed) <= 4.0 * f64::EPSILON * scale);
                let gap = max_diff(exact.y(), rk.y());
                // (The Runge–Kutta step rounds its stages' sum.)
                assert!(
                    gap <= 32.0 * f64::EPSILON * scale,
                    "{method:?} at {t}: {gap:e}"
                );
                // Its extension is the cubic, with nothing to prepare.
                exact.prepare_dense(&mut Fall).unwrap();
                assert_eq!(exact.stats().rhs_evals, evaluations + 1, "{method:?}");
                let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
                let s = exact.t_previous() + 0.3 * (t - exact.t_previous());
                exact.interpolate(s, &mut a);
                exact.interpolate_cubic(s, &mut b);
                assert_eq!(a, b, "{method:?}");
                let at_s = [1.0 + 2.0 * s - 0.5 * G * s * s, 2.0 - G * s];
                assert!(max_diff(&a, &at_s) <= 8.0 * f64::EPSILON * scale);
            }
            assert_eq!(exact.t(), t_stop, "{method:?}");
        }
    }
}

#[test]
fn an_exact_step_whose_closed_form_fails_leaves_the_stepper_as_it_was() {
    // The oscillator's acceleration changes along the step: no parabola.
    for method in METHODS {
        let mut sys = Oscillator { calls: 0 };
        let mut st = Stepper::new(method, 2, Tolerances::default());
        st.start(&mut sys, 0.0, &[1.0, 0.0], Some(0.1)).unwrap();
        st.step(&mut sys, 10.0, 1.0).unwrap();
        let before = st.clone();
        let taken = st
            .step_exact(&mut sys, 10.0, 1.0, parabola, same_acceleration)
            .unwrap();
        assert!(!taken, "{method:?}");
        assert_eq!(st.stats().rhs_evals, before.stats().rhs_evals + 1);
        assert_eq!(st.stats().steps, before.stats().steps);
        assert_eq!((st.t(), st.t_previous()), (before.t(), before.t_previous()));
        assert_eq!((st.y(), st.dy()), (before.y(), before.dy()));
        assert_eq!(st.suggested_step(), before.suggested_step());
        // The last step's extension is still there to prepare.
        let mut prepared = before.clone();
        prepared.prepare_dense(&mut sys).unwrap();
        st.prepare_dense(&mut sys).unwrap();
        let middle = 0.5 * (st.t_previous() + st.t());
        let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
        st.interpolate(middle, &mut a);
        prepared.interpolate(middle, &mut b);
        assert_eq!(a, b, "{method:?}");
        // The integrator goes on as if the trial had not been made.
        let mut again = before.clone();
        st.step(&mut sys, 10.0, 1.0).unwrap();
        again.step(&mut sys, 10.0, 1.0).unwrap();
        assert_eq!((st.t(), st.y()), (again.t(), again.y()), "{method:?}");
        assert_eq!(st.suggested_step(), again.suggested_step(), "{method:?}");
    }
}

#[test]
fn an_exact_step_whose_end_cannot_be_evaluated_is_an_error_that_changes_nothing() {
    // y' = −y refusing y < 0; a "closed form" that lands below 0.
    for method in METHODS {
        let mut sys = RefuseNegative {
            refusals: 0,
            calls: 0,
        };
        let mut st = Stepper::new(method, 1, Tolerances::default());
        st.start(&mut sys, 0.0, &[1.0], Some(0.1)).unwrap();
        let before = st.clone();
        let below = |_: &[f64], _: &[f64], _: f64, end: &mut [f64]| end[0] = -1.0;
        let outcome = st.step_exact(&mut sys, 1.0, 1.0, below, |_, _| true);
        assert!(
            matches!(outcome, Err(StepError::Rhs { t: 0.0, .. })),
            "{method:?}"
        );
        assert_eq!(sys.refusals, 1);
        assert_eq!(
            (st.t(), st.y(), st.dy()),
            (before.t(), before.y(), before.dy())
        );
        assert_eq!(st.suggested_step(), before.suggested_step());
        assert_eq!(st.stats().steps, before.stats().steps);
    }
}

#[test]
fn a_replaced_end_keeps_the_exact_step_s_cubic() {
    // After an exact step, a projection replaces its end: the step's interpolant still runs
    // through the end as computed (and its derivative there), the next step starts from the new
    // state.
    for method in METHODS {
        let mut st = Stepper::new(method, 2, Tolerances::default());
        st.start(&mut Fall, 0.0, &[1.0, 2.0], Some(0.1)).unwrap();
        assert!(st
            .step_exact(&mut Fall, 1.0, 1.0, parabola, same_acceleration)
            .unwrap());
        let (t0, t1, end) = (st.t_previous(), st.t(), st.y().to_vec());
        let inside = |st: &Stepper| {
            let mut out = [0.0; 2];
            st.interpolate(t0 + 0.3 * (t1 - t0), &mut out);
            out
        };
        let before = inside(&st);
        st.replace_state(&mut Fall, &[end[0] + 1e-3, end[1]])
            .unwrap();
        assert_eq!(inside(&st), before, "{method:?}");
        let mut out = [0.0; 2];
        st.interpolate_cubic(t1, &mut out);
        assert_eq!(out.as_slice(), end.as_slice(), "{method:?}");
        assert_eq!(st.y(), &[end[0] + 1e-3, end[1]]);
        st.step(&mut Fall, 1.0, 1.0).unwrap();
        assert_eq!(st.t_previous(), t1);
    }
}

/// Towards the pole of `y' = y²` (`y = 1/(1 − t)`) every derivative grows from step to step, so
/// that a step size proposed from the last step's error alone overshoots again and again. The
/// predictive controller follows the error's growth instead. (DOP853 without it: 25 rejected
/// trials to t = 0.999, 961 evaluations and a relative error of 1.3e-8; with it none, 722 and
/// 8.6e-9. DOPRI5's control, whose PI term weighs more, rejected none before either.)
#[test]
fn a_growing_error_is_predicted_instead_of_rejected_step_after_step() {
    for (method, t_end) in [(Method::Dop853, 0.999), (Method::Dopri5, 0.99)] {
        let mut sys = Riccati { calls: 0 };
        let tol = Tolerances {
            rtol: 1e-10,
            atol: 1e-10,
        };
        let st = integrate(method, tol, &mut sys, 0.0, &[1.0], t_end).unwrap();
        let stats = st.stats();
        let exact = 1.0 / (1.0 - t_end);
        let error = (st.y()[0] - exact).abs() / exact;
        assert!(stats.rejected_steps <= 2, "{method:?}: {stats:?}");
        // The global error near the pole grows like the solution's sensitivity, 1/(1 − t)².
        assert!(error <= 1e-7, "{method:?}: relative error {error:e}");
    }
}

/// A step cut short to land on a `t_stop` just ahead has an error at rounding level, which says
/// nothing of the error's growth: the predictive controller must not shrink the next step from
/// it, and the proposal it was cut from is kept.
#[test]
fn a_short_landing_keeps_the_proposal_with_the_predictive_controller() {
    for method in METHODS {
        let mut sys = Oscillator { calls: 0 };
        let tol = Tolerances {
            rtol: 1e-8,
            atol: 1e-8,
        };
        let mut st = Stepper::new(method, 2, tol);
        st.start(&mut sys, 0.0, &[1.0, 0.0], None).unwrap();
        for _ in 0..3 {
            st.step(&mut sys, f64::INFINITY, f64::INFINITY).unwrap();
        }
        let proposal = st.suggested_step();
        let t_stop = st.t() + 1e-4 * proposal;
        st.step(&mut sys, t_stop, f64::INFINITY).unwrap();
        assert_eq!(st.t(), t_stop);
        assert!(
            st.suggested_step() >= proposal,
            "{method:?}: {} after the landing, {proposal} before",
            st.suggested_step()
        );
    }
}
