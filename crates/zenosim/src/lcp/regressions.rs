//! Problems the solver once failed, named after the failure, and the behaviour of its errors.

use super::check::{affine, violation};
use super::random::check_against_enumeration;
use super::*;

/// The Delassus matrix of a column of beads on a floor, for the constraints `floor`, `gap0` …
/// `gap8` of a subset: `W = A Aᵀ` with unit masses, `floor = y₀`, `gapᵢ = yᵢ₊₁ − yᵢ`.
fn column_of_beads(constraints: &[usize]) -> Vec<f64> {
    let row = |c: usize| -> Vec<f64> {
        let mut a = vec![0.0; 10];
        if c == 0 {
            a[0] = 1.0;
        } else {
            a[c - 1] = -1.0;
            a[c] = 1.0;
        }
        a
    };
    let k = constraints.len();
    let mut w = vec![0.0; k * k];
    for (i, &ci) in constraints.iter().enumerate() {
        for (j, &cj) in constraints.iter().enumerate() {
            w[i * k + j] = row(ci).iter().zip(row(cj)).map(|(a, b)| a * b).sum();
        }
    }
    w
}

/// The impact laws on which `zenosim run` stopped in Siconos's ColumnOfBeadsTS example (10 beads
/// of mass 1 and radius 0.1, centres at `1 + 0.25 i`, falling onto a floor, `e = 0.9`, to
/// `t = 2`): `W` and `q = (1 + e) A q̇⁻` printed in full precision by the impact law
/// (`Contacts::impact`) where the solver failed, at `rtol = atol = 1e-10` (t = 1.18710), 1e-6
/// (t = 1.17736), 1e-8 (t = 1.20249), 1e-12 (t = 1.19548) and with `--zeno 1e-3`
/// (t = 1.19516), with the rounding bounds of `q` the engine computes
/// (`(1 + e) · Normal::a_q_dot_round_off`). The constraints of each set, as indices into
/// `floor, gap0, …, gap8`.
#[allow(clippy::type_complexity)]
fn beads_cases() -> Vec<(Vec<usize>, Vec<f64>, Vec<f64>)> {
    let held = [0, 1, 2, 3, 4, 5, 6, 8];
    vec![
        (
            held.to_vec(),
            vec![
                -2.6624670822171523e-45,
                2.6624670822171523e-45,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                -0.12268525544980818,
            ],
            vec![2.235287196701547e-15, 3.1611734693742643e-15],
        ),
        (
            vec![0, 1, 2, 4, 5, 6, 7, 8],
            vec![
                -0.07660042234544169,
                0.0,
                0.0,
                -6.591949208711867e-18,
                6.591949208711867e-18,
                0.0,
                -6.591949208711867e-18,
                6.591949208711867e-18,
            ],
            vec![3.7293281769980195e-15, 5.27406648645073e-15],
        ),
        (
            held.to_vec(),
            vec![
                -1.0649868328868609e-44,
                1.0649868328868609e-44,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                -0.04960390792172617,
            ],
            vec![4.0722534812060635e-16, 5.759036102542665e-16],
        ),
        (
            held.to_vec(),
            vec![
                -5.3249341644343046e-45,
                5.3249341644343046e-45,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                -0.07649051117856522,
            ],
            vec![1.0998962888941462e-15, 1.5554882489579375e-15],
        ),
        (
            vec![0, 1, 2, 4, 6],
            vec![0.0, 0.0, 0.0, -3.2959746043559333e-18, -0.09468713382690049],
            vec![1.1136347852965007e-15, 1.5749174168967613e-15],
        ),
    ]
}

/// The rounding bounds of a case: the floor's, then every gap's.
fn bounds(k: usize, floor_and_gap: &[f64]) -> Vec<f64> {
    (0..k).map(|i| floor_and_gap[usize::from(i > 0)]).collect()
}

#[test]
fn lemke_ended_on_a_ray_for_a_column_of_beads() {
    // The matrices are those printed (small integers, exact): W is positive definite, so each
    // problem has exactly one solution, which enumeration finds. Lemke's method took a tie
    // between z₀ and a row whose q̄ is −10⁻⁴⁵ for one and ended with w = −10⁻⁴⁵; the check
    // refused it, and the run stopped with "no solution (Lemke's method ended on a ray)".
    for (constraints, q, floor_and_gap) in beads_cases() {
        let m = column_of_beads(&constraints);
        let k = q.len();
        assert!(matches!(
            conditioning(&m, k),
            Conditioning::PositiveDefinite { pivot_ratio } if pivot_ratio > 0.1
        ));
        // Exact: the tiny entries are data.
        let result = solve(&m, &q);
        check_against_enumeration(&m, &q, &result).unwrap_or_else(|e| panic!("{q:?}: {e}"));
        // With the engine's rounding bounds: the entries ±10⁻⁴⁵ and ±10⁻¹⁸ are rounding, and
        // count as 0; the answer solves the problem so cleaned.
        let round_off = bounds(k, &floor_and_gap);
        let cleaned: Vec<f64> = q
            .iter()
            .zip(&round_off)
            .map(|(&x, &r)| if x.abs() <= r { 0.0 } else { x })
            .collect();
        assert!(cleaned.iter().filter(|&&x| x != 0.0).count() == 1, "{q:?}");
        let result = solve_rounded(&m, &q, &round_off);
        check_against_enumeration(&m, &cleaned, &result).unwrap_or_else(|e| panic!("{q:?}: {e}"));
    }
}

#[test]
fn lemke_with_its_tie_rule_solves_the_column_of_beads() {
    // Lemke's method alone (the method for matrices that are not clearly positive definite), on
    // the problems as the engine now passes them, cleaned of their rounding: exactly
    // degenerate (zeros in q, exact ties between z₀ and the rows of the chain), which the
    // lexicographic rule resolves. (On the raw q it cannot tell −10⁻⁴⁵ from 0: q̄ = q₀ − q₇
    // rounds to −q₇, an exact tie in floating point. That is one reason why positive definite
    // problems go to the active-set method.)
    for (constraints, q, floor_and_gap) in beads_cases() {
        let m = column_of_beads(&constraints);
        let round_off = bounds(q.len(), &floor_and_gap);
        let q: Vec<f64> = q
            .iter()
            .zip(&round_off)
            .map(|(&x, &r)| if x.abs() <= r { 0.0 } else { x })
            .collect();
        let Ok(lemke::End::Complementary(z)) =
            lemke::solve(&m, &q, lemke_limit(q.len()), lemke::PIVOT_TOLERANCES[0])
        else {
            panic!("{q:?}: no complementary basis");
        };
        let (z, worst) = lemke::polish(&m, &q, z);
        assert!(worst <= check::ACCEPTANCE, "{q:?}: {z:?} ({worst:e})");
        check_against_enumeration(
            &m,
            &q,
            &Ok(Solution {
                w: affine(&m, &q, &z),
                z,
            }),
        )
        .unwrap_or_else(|e| panic!("{q:?}: {e}"));
    }
}

#[test]
fn the_auxiliary_variable_left_at_a_false_tie() {
    // W = I (two independent contacts, the impact law), q = (−1.06·10⁻¹⁰, −5.46): the ratios of
    // z₀ and w₀ differ by 1.06·10⁻¹⁰, which a tolerance of 10⁻¹¹ of ‖q‖∞ took for a tie; z₀
    // left there, w₀ = −1.06·10⁻¹⁰, and the check refused the answer. The solution is −q.
    let m = [1.0, 0.0, 0.0, 1.0];
    let q = [-1.06e-10, -5.46];
    let s = solve(&m, &q).unwrap();
    assert_eq!(s.z, vec![1.06e-10, 5.46]);
    assert_eq!(s.w, vec![0.0, 0.0]);
    // Lemke's method alone, too: it ends on the right basis (z₀ = 5.46 − (5.46 − 1.06·10⁻¹⁰)
    // keeps 5 digits), which the solve on its support makes exact.
    let Ok(lemke::End::Complementary(z)) = lemke::solve(&m, &q, 100, lemke::PIVOT_TOLERANCES[0])
    else {
        panic!("no complementary basis");
    };
    assert!((z[0] / 1.06e-10 - 1.0).abs() < 1e-5, "{z:?}");
    assert_eq!(lemke::polish(&m, &q, z), (vec![1.06e-10, 5.46], 0.0));
    // At every scale of the small entry, and the other way round.
    for e in [-300, -200, -100, -50, -20, -15, -12, -9, -6, -3] {
        let tiny = -(10f64.powi(e));
        for q in [[tiny, -5.46], [-5.46, tiny]] {
            let s = solve(&m, &q).unwrap();
            assert_eq!(s.z, vec![-q[0], -q[1]], "{q:?}");
        }
    }
}

#[test]
fn entries_within_their_rounding_count_as_zero() {
    let m = [2.0, -1.0, -1.0, 2.0];
    // 10⁻¹⁷ is within its bound 10⁻¹⁶: the problem is (0, −1).
    let s = solve_rounded(&m, &[-1e-17, -1.0], &[1e-16, 1e-16]).unwrap();
    let expected = solve(&m, &[0.0, -1.0]).unwrap();
    assert_eq!(s, expected);
    assert_eq!(s.w, affine(&m, &[0.0, -1.0], &s.z));
    // Outside its bound it is data.
    let s = solve_rounded(&m, &[-1e-15, -1.0], &[1e-16, 1e-16]).unwrap();
    assert_eq!(s, solve(&m, &[-1e-15, -1.0]).unwrap());
    // A negative bound cleans nothing; everything within its bound: z = 0, w = 0.
    let s = solve_rounded(&m, &[-1e-17, -1.0], &[-1.0, -1.0]).unwrap();
    assert_eq!(s, solve(&m, &[-1e-17, -1.0]).unwrap());
    let s = solve_rounded(&m, &[-1e-17, 1e-17], &[1e-16, 1e-16]).unwrap();
    assert_eq!((s.z, s.w), (vec![0.0; 2], vec![0.0; 2]));
    // A bound that is not finite is refused.
    for bad in [f64::NAN, f64::INFINITY] {
        assert_eq!(
            solve_rounded(&m, &[-1.0, -1.0], &[0.0, bad]),
            Err(LcpError::NonFinite)
        );
    }
}

#[test]
#[should_panic(expected = "lcp::solve")]
fn rounding_bounds_of_the_wrong_length_panic() {
    let _ = solve_rounded(&[1.0], &[-1.0], &[]);
}

#[test]
fn no_solution_only_with_a_proof() {
    // A point pinched between y ≥ 0 and y ≤ −x² at the origin, moving along x
    // (crates/zenosim-cli/tests/corpus/faults/pinched.toml): W = [[1, −1], [−1, 1]] (the two
    // gradients opposite), ḧ_free = (−g, g − 2ẋ²). y = (1, 1) proves it: Wy = 0, qᵀy = −2ẋ² < 0.
    let m = [1.0, -1.0, -1.0, 1.0];
    let q = [-9.81, 7.81];
    assert_eq!(solve(&m, &q), Err(LcpError::NoSolution));
    assert!(check::proves_infeasible(&m, &q, &[1.0, 1.0]));
    // Not a proof: mᵀy ≤ 0 fails, or qᵀy is not negative, or y is not ≥ 0 or is 0.
    assert!(!check::proves_infeasible(&m, &q, &[1.0, 0.0]));
    assert!(!check::proves_infeasible(&m, &[-1.0, 1.0], &[1.0, 1.0]));
    assert!(!check::proves_infeasible(&m, &q, &[-1.0, -1.0]));
    assert!(!check::proves_infeasible(&m, &q, &[0.0, 0.0]));
    assert!(!check::proves_infeasible(&m, &q, &[f64::NAN, 1.0]));
    // With q in the range of W (ẋ = 0: g − 2ẋ² = g) the same matrix has solutions.
    let s = solve(&m, &[-9.81, 9.81]).unwrap();
    assert!(violation(&m, &[-9.81, 9.81], &s.z, &s.w) <= check::ACCEPTANCE);
}

#[test]
fn the_solver_says_when_it_failed() {
    // Not symmetric, so Lemke's method alone, with no pivot allowed: the failure is the
    // solver's, and the message says so and how far from singular the matrix is.
    let m = [2.0, -1.0, -0.5, 2.0];
    let error = solve_with_limit(&m, &[-2.0, 0.0], None, 0).unwrap_err();
    assert_eq!(
        error.to_string(),
        "the LCP solver failed (the pivoting did not end within its limit) on a matrix that is \
         not symmetric"
    );
    let failed = LcpError::Failed {
        stop: Stop::Cycle,
        conditioning: Conditioning::PositiveDefinite { pivot_ratio: 3e-14 },
    };
    assert_eq!(
        failed.to_string(),
        "the LCP solver failed (the active-set method came back to a set it had left) on a \
         matrix that is positive definite, its smallest Cholesky pivot 3.0e-14 of its diagonal \
         entry (conditioned to about 3e13)"
    );
}

#[test]
fn conditioning_from_the_cholesky_pivots() {
    assert_eq!(
        conditioning(&[4.0, 0.0, 0.0, 9.0], 2),
        Conditioning::PositiveDefinite { pivot_ratio: 1.0 }
    );
    // [[2, −1], [−1, 2]]: pivots 2 and 3/2.
    assert_eq!(
        conditioning(&[2.0, -1.0, -1.0, 2.0], 2),
        Conditioning::PositiveDefinite { pivot_ratio: 0.75 }
    );
    // The same surface twice: the second pivot is 0.
    assert_eq!(
        conditioning(&[1.0, 1.0, 1.0, 1.0], 2),
        Conditioning::NotPositiveDefinite { pivot_ratio: 0.0 }
    );
    assert_eq!(
        conditioning(&[0.0, 0.0, 0.0, 1.0], 2),
        Conditioning::NotPositiveDefinite {
            pivot_ratio: f64::NEG_INFINITY
        }
    );
    assert_eq!(
        conditioning(&[1.0, 0.5, 0.0, 1.0], 2),
        Conditioning::Nonsymmetric
    );
    // Symmetric to rounding counts as symmetric.
    assert!(matches!(
        conditioning(&[1.0, 0.1, 0.1 * (1.0 + f64::EPSILON), 1.0], 2),
        Conditioning::PositiveDefinite { .. }
    ));
    assert_eq!(
        Conditioning::NotPositiveDefinite { pivot_ratio: 0.0 }.to_string(),
        "not positive definite (a Cholesky pivot of 0.0e0 of its diagonal entry)"
    );
}

#[test]
fn dot2_keeps_the_digits_of_a_cancellation() {
    // 1 + 2⁻⁶⁰ − 1, and (1 + 2⁻³⁰)² − 1 − 2⁻²⁹ = 2⁻⁶⁰: rounded to f64 on the way, both give 0.
    let tiny = 2f64.powi(-60);
    assert_eq!(
        check::dot2(-1.0, [1.0, tiny].into_iter(), [1.0, 1.0].into_iter()),
        tiny
    );
    let a = 1.0 + 2f64.powi(-30);
    assert_eq!(
        check::dot2(-1.0 - 2f64.powi(-29), [a].into_iter(), [a].into_iter()),
        tiny
    );
}

/// The impact LCP with friction (Pfeiffer and Glocker's, docs/friction.md) on which a random
/// Housner block (b = 0.1747, c = 0.9640, μ = 0.05, th0 = 0.1674) stopped when it landed flat,
/// slipping on its left corner, at t = 1.6382: both corners slip along the same row, so the
/// two slip rows are equal to rounding and every basis holding both is singular. Lemke's
/// method and the bases (Gaussian elimination) failed; the basis's solution of least norm
/// solves it (the left corner lets go, the right takes the impulse and slides).
#[test]
fn a_block_landing_flat_on_two_rough_corners_has_its_impact_solved() {
    #[rustfmt::skip]
    let m = [
        1.1217402830988084, 0.9309046493158237, -0.5264493241463384, -0.5264493241463379, 0.0, 0.0,
        0.8782597169011894, 1.0690953506841776, 0.5264493241463477, 0.5264493241463473, 0.0, 0.0,
        -0.7216784333017638, 0.3312202149909223, 3.904582183108509, 3.904582183108507, 1.0, 0.0,
        -0.7216784333017633, 0.331220214990922, 3.904582183108507, 3.904582183108505, 0.0, 1.0,
        0.1, 0.0, -1.0, 0.0, 0.0, 0.0,
        0.0, 0.1, 0.0, -1.0, 0.0, 0.0,
    ];
    let q = [
        0.0,
        -0.10751096016007833,
        -0.11458702166072049,
        -0.11458702166072027,
        0.0,
        0.0,
    ];
    let solution = solve(&m, &q).unwrap();
    let w = affine(&m, &q, &solution.z);
    assert!(violation(&m, &q, &solution.z, &w) <= 1e-12, "{solution:?}");
    // The left corner's normal impulse is 0, the right corner's is not.
    assert_eq!(solution.z[0], 0.0, "{solution:?}");
    assert!(solution.z[1] > 0.09, "{solution:?}");
}

/// The impact LCP with friction on which a random ball with backspin (μ = 0.018, e = 0.022,
/// ẋ₀ = −3, θ̇₀ = −40, dropped from 0.86) stopped at its fourth impact, t = 0.41133: it barely
/// approaches (`q₀ = −1.0e-6`) while it slips fast (`−6.7`), so elimination leaves the cone's
/// row (`2 μ Λ − a`, terms of 7e-8) off by the slip's rounding (1e-15), 1.1e-9 of its terms:
/// every method's answer failed the check. One step of iterative refinement on the support
/// (module `refine`) meets it.
#[test]
fn a_fast_slipping_ball_hardly_approaching_has_its_impact_solved() {
    #[rustfmt::skip]
    let m = [
        1.0, 0.0, 0.0,
        -0.06307518011554705, 3.4999999999999996, 1.0,
        0.03604296006602689, -1.0, 0.0,
    ];
    let q = [-1.027675742560818e-6, -6.745480131421527, 0.0];
    let round_off = [2.856656560604265e-20, 9.585903813191303e-14, 0.0];
    let solution = solve_rounded(&m, &q, &round_off).unwrap();
    let w = affine(&m, &q, &solution.z);
    assert!(violation(&m, &q, &solution.z, &w) <= 1e-12, "{solution:?}");
    // The normal impulse stops the approach; the contact slides on.
    assert!(
        (solution.z[0] - 1.027675742560818e-6).abs() < 1e-21,
        "{solution:?}"
    );
    assert!(solution.z[2] > 6.7, "{solution:?}");
}

/// A second random Housner block landing flat while slipping on its left corner (b = 0.1034,
/// c = 0.6557, μ = 0.0694, th0 = 0.0814, at t = 0.38995): the basis of the answer holds both
/// equal slip rows, and its least-norm solution has the left corner's `a` at 1e-17 (0 but for
/// rounding), on which the cone row `2 μ Λ − a`, of no other terms, failed the check. Basic
/// variables within the rounding of the largest are 0.
#[test]
fn a_second_block_landing_flat_has_its_impact_solved() {
    #[rustfmt::skip]
    let m = [
        1.1048090938516761, 0.9592210444503827, -0.46160925474888403, -0.4616092547488839, 0.0, 0.0,
        0.8951909061483221, 1.040778955549618, 0.4616092547488916, 0.46160925474889153, 0.0, 0.0,
        -0.733981980330273, 0.18923652916750297, 3.927205975299353, 3.9272059752993522, 1.0, 0.0,
        -0.7339819803302727, 0.18923652916750286, 3.927205975299352, 3.9272059752993513, 0.0, 1.0,
        0.13871069014180087, 0.0, -1.0, 0.0, 0.0, 0.0,
        0.0, 0.13871069014180087, 0.0, -1.0, 0.0, 0.0,
    ];
    let q = [
        0.0,
        -0.11958963496037169,
        -0.13521295420599871,
        -0.1352129542059986,
        0.0,
        0.0,
    ];
    let solution = solve(&m, &q).unwrap();
    let w = affine(&m, &q, &solution.z);
    assert!(violation(&m, &q, &solution.z, &w) <= 1e-12, "{solution:?}");
    assert_eq!(solution.z[0], 0.0, "{solution:?}");
    assert!(solution.z[1] > 0.1, "{solution:?}");
}
