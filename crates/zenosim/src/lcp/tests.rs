//! The solver against enumeration of complementary bases and closed forms, on random and
//! constructed problems.

use super::check::affine;
use super::*;
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

/// The test data are of order one: these are absolute.
const TOL: f64 = 1e-9;

/// Every solution found by enumerating the `2ᵏ` complementary bases: for each subset `S`
/// with `m_SS` well conditioned, `z_S = −m_SS⁻¹ q_S`, `z = 0` elsewhere, kept if `z ≥ 0`
/// and `w = m z + q ≥ 0` (within `TOL`).
fn oracle(m: &[f64], q: &[f64]) -> Vec<Vec<f64>> {
    let k = q.len();
    let mut found = Vec::new();
    for mask in 0u32..(1 << k) {
        let s: Vec<usize> = (0..k).filter(|&i| mask & (1 << i) != 0).collect();
        let mut z = vec![0.0; k];
        if !s.is_empty() {
            let a = DMatrix::from_fn(s.len(), s.len(), |r, c| m[s[r] * k + s[c]]);
            let sv = a.clone().singular_values();
            if sv.min() <= 1e-9 * sv.max() {
                continue;
            }
            let b = DVector::from_fn(s.len(), |r, _| -q[s[r]]);
            let Some(x) = a.lu().solve(&b) else { continue };
            for (r, &i) in s.iter().enumerate() {
                z[i] = x[r];
            }
        }
        let w = affine(m, q, &z);
        if z.iter().chain(&w).all(|&x| x >= -TOL) {
            found.push(z);
        }
    }
    found
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |acc, v| acc.max(v.abs()))
}

/// `TOL` relative to the size of the terms: nearly singular problems have large solutions,
/// and `w` on the support is then round-off of the size of `m z`; `zᵢ wᵢ` is that times `z`.
fn tol_for(m: &[f64], z: &[f64]) -> f64 {
    let terms = max_abs(m) * max_abs(z) * z.len() as f64;
    TOL * (1.0 + terms) * (1.0 + max_abs(z))
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0, |acc, (x, y)| acc.max((x - y).abs()))
}

/// `m` is a P-matrix: Lemke's answer is the enumerated one (which is unique) and a solution.
fn check_unique(m: &[f64], q: &[f64]) -> Result<(), TestCaseError> {
    let expected = oracle(m, q);
    prop_assert!(!expected.is_empty(), "the oracle found no solution");
    for other in &expected[1..] {
        prop_assert!(
            max_diff(other, &expected[0]) <= 1e-7,
            "two different solutions"
        );
    }
    let s = solve(m, q).map_err(|e| TestCaseError::fail(format!("{e}")))?;
    prop_assert!(is_solution(m, q, &s.z, &s.w, TOL), "{s:?}");
    let scale = max_abs(&expected[0]).max(1.0);
    prop_assert!(
        max_diff(&s.z, &expected[0]) <= 1e-9 * scale,
        "z = {:?}, expected {:?}",
        s.z,
        expected[0]
    );
    let w = affine(m, q, &s.z);
    prop_assert_eq!(&s.w, &w);
    Ok(())
}

/// `b bᵀ + δ I`, `b` `k×k` row-major.
fn spd(b: &[f64], k: usize, delta: f64) -> Vec<f64> {
    gram(b, k, k, delta)
}

/// `b bᵀ + δ I`, `b` `k×r` row-major.
fn gram(b: &[f64], k: usize, r: usize, delta: f64) -> Vec<f64> {
    let mut m = vec![0.0; k * k];
    for i in 0..k {
        for j in 0..k {
            m[i * k + j] = (0..r).map(|l| b[i * r + l] * b[j * r + l]).sum::<f64>();
        }
        m[i * k + i] += delta;
    }
    m
}

/// `W = A D Aᵀ` and `q = A v`, `A` `k×n` row-major, `D` diagonal.
fn delassus(a: &[f64], d: &[f64], v: &[f64], k: usize, n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut w = vec![0.0; k * k];
    for i in 0..k {
        for j in 0..k {
            w[i * k + j] = (0..n).map(|l| a[i * n + l] * d[l] * a[j * n + l]).sum();
        }
    }
    let q = (0..k)
        .map(|i| (0..n).map(|l| a[i * n + l] * v[l]).sum())
        .collect();
    (w, q)
}

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        // Failing cases are reported, not stored next to the sources.
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

fn vec_in(range: std::ops::Range<f64>, n: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(range, n)
}

fn ints(range: std::ops::RangeInclusive<i32>, n: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(range.prop_map(f64::from), n)
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn symmetric_positive_definite_matches_enumeration(
        (k, b, delta, q) in (1usize..=6).prop_flat_map(|k| {
            (Just(k), vec_in(-1.0..1.0, k * k), 0.05..1.0f64, vec_in(-2.0..2.0, k))
        })
    ) {
        check_unique(&spd(&b, k, delta), &q)?;
    }

    #[test]
    fn nonsymmetric_p_matrix_matches_enumeration(
        (k, off, delta, q) in (1usize..=6).prop_flat_map(|k| {
            (Just(k), vec_in(-1.0..1.0, k * k), 0.05..1.0f64, vec_in(-2.0..2.0, k))
        })
    ) {
        // Strictly diagonally dominant rows with a positive diagonal: a P-matrix.
        let mut m = off.clone();
        for i in 0..k {
            let row: f64 = (0..k).filter(|&j| j != i).map(|j| off[i * k + j].abs()).sum();
            m[i * k + i] = row + delta;
        }
        check_unique(&m, &q)?;
    }

    #[test]
    fn degenerate_integer_positive_definite_matches_enumeration(
        (k, b, q) in (1usize..=6).prop_flat_map(|k| {
            (Just(k), ints(-2..=2, k * k), ints(-2..=2, k))
        })
    ) {
        // Small integers: exact ties in q, zeros in q, repeated rows in b, zeros in w.
        check_unique(&gram(&b, k, k, 1.0), &q)?;
    }

    #[test]
    fn semidefinite_solvable_is_solved(
        (k, r, b, q) in (1usize..=5).prop_flat_map(|k| (Just(k), 1..=k)).prop_flat_map(
            |(k, r)| (Just(k), Just(r), ints(-2..=2, k * r), ints(-3..=3, k))
        )
    ) {
        // b bᵀ with rank ≤ r (dependent constraint gradients), integer so that the
        // enumeration's verdict is exact.
        let m = gram(&b, k, r, 0.0);
        let solvable = !oracle(&m, &q).is_empty();
        match solve(&m, &q) {
            Ok(s) => {
                prop_assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{:?}", s)
            }
            Err(e) => prop_assert!(!solvable, "{} on a solvable problem", e),
        }
    }

    #[test]
    fn dependent_constraints_are_solved(
        (k, n, a, d, v, copies) in (1usize..=6)
            .prop_flat_map(|k| (Just(k), 1..=k))
            .prop_flat_map(|(k, n)| {
                (
                    Just(k),
                    Just(n),
                    vec_in(-1.0..1.0, k * n),
                    vec_in(0.2..5.0, n),
                    vec_in(-2.0..2.0, n),
                    prop::collection::vec(0..=k, k),
                )
            })
    ) {
        // The Delassus matrix W = A M⁻¹ Aᵀ of k constraints on n ≤ k coordinates (M⁻¹ = D
        // diagonal), computed in floating point, and q = A v: q lies in the range of W, so a
        // solution exists (the problem is that of minimising ½ zᵀ W z + qᵀ z on z ≥ 0, which
        // is bounded below), and w is the same for all solutions. Some rows of A are copies
        // of earlier ones (the same constraint twice), some are 0.
        let mut a = a;
        for (i, &source) in copies.iter().enumerate() {
            if source < i {
                let row: Vec<f64> = a[source * n..(source + 1) * n].to_vec();
                a[i * n..(i + 1) * n].copy_from_slice(&row);
            } else if source == k && i % 2 == 1 {
                a[i * n..(i + 1) * n].fill(0.0);
            }
        }
        let (w_matrix, q) = delassus(&a, &d, &v, k, n);
        let s = solve(&w_matrix, &q).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert!(
            is_solution(&w_matrix, &q, &s.z, &s.w, tol_for(&w_matrix, &s.z)),
            "{:?}",
            s
        );
    }

    #[test]
    fn ill_conditioned_positive_definite_is_solved(
        (k, b, delta, q) in (1usize..=8).prop_flat_map(|k| {
            (Just(k), vec_in(-1.0..1.0, k * k), -12.0..-6.0f64, vec_in(-2.0..2.0, k))
        })
    ) {
        // b bᵀ + δ I, condition numbers up to about 10¹³.
        let m = spd(&b, k, 10f64.powf(delta));
        let s = solve(&m, &q).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{:?}", s);
    }

    #[test]
    fn indefinite_answers_are_solutions(
        (_k, m, q) in (1usize..=5).prop_flat_map(|k| {
            (Just(k), vec_in(-2.0..2.0, k * k), vec_in(-2.0..2.0, k))
        })
    ) {
        if let Ok(s) = solve(&m, &q) {
            prop_assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{:?}", s);
        }
    }

    #[test]
    fn integer_indefinite_answers_are_solutions(
        (_k, m, q) in (1usize..=5).prop_flat_map(|k| {
            (Just(k), ints(-2..=2, k * k), ints(-2..=2, k))
        })
    ) {
        if let Ok(s) = solve(&m, &q) {
            prop_assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{:?}", s);
        }
    }

    #[test]
    fn any_input_no_panic(
        (k, m, q) in (0usize..=4).prop_flat_map(|k| {
            (
                Just(k),
                prop::collection::vec(prop::num::f64::ANY, k * k),
                prop::collection::vec(prop::num::f64::ANY, k),
            )
        })
    ) {
        let result = solve(&m, &q);
        if m.iter().chain(&q).any(|x| !x.is_finite()) {
            prop_assert_eq!(result, Err(LcpError::NonFinite));
        } else if let Ok(s) = result {
            prop_assert!(s.z.iter().chain(&s.w).all(|x| x.is_finite()));
            prop_assert!(s.z.iter().all(|&x| x >= 0.0));
        }
        let z = vec![0.0; k];
        let _ = is_solution(&m, &q, &z, &q, TOL);
    }
}

#[test]
fn nonnegative_q_gives_zero() {
    let m = [2.0, 1.0, 1.0, 2.0];
    for q in [[0.0, 0.0], [1.0, 0.0], [0.0, 3.0], [-0.0, 0.5]] {
        let s = solve(&m, &q).unwrap();
        assert_eq!(s.z, vec![0.0, 0.0]);
        assert_eq!(s.w, q.to_vec());
    }
    let empty = solve(&[], &[]).unwrap();
    assert!(empty.z.is_empty() && empty.w.is_empty());
}

#[test]
fn zeros_in_q_with_positive_definite_m() {
    let m = [2.0, 1.0, 0.0, 1.0, 2.0, 1.0, 0.0, 1.0, 2.0];
    for q in [
        [0.0, -1.0, 0.0],
        [-1.0, 0.0, -1.0],
        [0.0, 0.0, -1.0],
        [-1.0, 0.0, 0.0],
    ] {
        let s = solve(&m, &q).unwrap();
        assert!(is_solution(&m, &q, &s.z, &s.w, 1e-12), "{q:?}: {s:?}");
        let expected = oracle(&m, &q);
        assert!(
            max_diff(&s.z, &expected[0]) <= 1e-12,
            "{q:?}: {s:?} {expected:?}"
        );
    }
}

#[test]
fn one_dimensional() {
    let s = solve(&[2.0], &[-4.0]).unwrap();
    assert_eq!(s.z, vec![2.0]);
    assert_eq!(s.w, vec![0.0]);
    let s = solve(&[0.5], &[3.0]).unwrap();
    assert_eq!((s.z, s.w), (vec![0.0], vec![3.0]));
}

#[test]
fn newtons_cradle() {
    let m = [2.0, -1.0, -1.0, 2.0];
    let q = [-2.0, 0.0];
    let s = solve(&m, &q).unwrap();
    approx::assert_relative_eq!(s.z[0], 4.0 / 3.0, max_relative = 1e-14);
    approx::assert_relative_eq!(s.z[1], 2.0 / 3.0, max_relative = 1e-14);
    assert!(s.w.iter().all(|w| w.abs() <= 1e-15), "{s:?}");
}

#[test]
fn the_same_constraint_twice() {
    // W = [[s, s], [s, s]]: one contact counted twice. Solutions z₁ + z₂ = 1/s, w = 0.
    for s in [1.0, 3.0, 0.3, 7e-3] {
        let m = [s, s, s, s];
        let q = [-1.0, -1.0];
        let sol = solve(&m, &q).unwrap();
        assert!(is_solution(&m, &q, &sol.z, &sol.w, 1e-12), "{sol:?}");
        assert!(sol.w.iter().all(|w| w.abs() <= 1e-15), "{sol:?}");
        approx::assert_relative_eq!(sol.z[0] + sol.z[1], 1.0 / s, max_relative = 1e-14);
    }
    // a aᵀ with duplicated rows: gradients a₁, a₁, a₂, a₂ (M = I).
    let a = [
        [1.0, 0.5, 0.0],
        [1.0, 0.5, 0.0],
        [0.0, 1.0, -1.0],
        [0.0, 1.0, -1.0],
    ];
    let m: Vec<f64> = (0..16)
        .map(|ij| (0..3).map(|l| a[ij / 4][l] * a[ij % 4][l]).sum())
        .collect();
    let v = [-1.0, -2.0, 0.5];
    let q: Vec<f64> = a
        .iter()
        .map(|r| (0..3).map(|l| r[l] * v[l]).sum())
        .collect();
    let sol = solve(&m, &q).unwrap();
    assert!(is_solution(&m, &q, &sol.z, &sol.w, 1e-12), "{sol:?}");
    assert_eq!(sol.w, affine(&m, &q, &sol.z));
    // The same w as any enumerated solution (w is unique for semi-definite m).
    let expected = oracle(&m, &q);
    assert!(!expected.is_empty());
    for z in &expected {
        assert!(max_diff(&affine(&m, &q, z), &sol.w) <= 1e-12);
    }
}

#[test]
fn rank_deficient_exact_ties() {
    // Found by search: W of rank 2 with two zero rows; z₀ and w₁ reach 0 together, their
    // computed ratios 10⁻⁹ apart (the entries of the entering column are small, from
    // cancellation). The tie must go to z₀, and a secondary ray reached with z₀ at its
    // round-off is a solution.
    let a = [
        -0.9051669251637597,
        0.7680726735840228,
        0.5672845789673489,
        0.0,
        0.6815291567051781,
        -0.5789852552958722,
        0.0,
        0.0,
        0.0,
        0.0,
    ];
    let (m, q) = delassus(
        &a,
        &[0.6788772307527456, 1.472347034158464],
        &[0.8165882834494105, 0.0],
        5,
        2,
    );
    let s = solve(&m, &q).unwrap();
    assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{s:?}");
}

#[test]
fn nearly_dependent_constraints() {
    // Found by search: rows 0 and 2 of A equal, row 1 equal to 10⁻¹⁰; the first pivoting
    // passes through a basis with ‖B⁻¹‖ ≈ 10¹⁰ and ends with w₃ = −0.18: that answer must
    // not be returned (the second pass treats the rows as dependent).
    let (k, n) = (4, 2);
    let near = 10f64.powf(-9.766793216790258);
    let row = [0.35526714460128883, -0.9169712851365855];
    let a = [
        row[0],
        row[1],
        row[0] * (1.0 - 0.5 * near),
        row[1] * (1.0 + 0.5 * near),
        row[0],
        row[1],
        0.0,
        0.5272753298700514,
    ];
    let (m, q) = delassus(
        &a,
        &[0.01; 2],
        &[-1.6585215694550068, 1.5929978408197838],
        k,
        n,
    );
    let s = solve(&m, &q).unwrap();
    assert!(is_solution(&m, &q, &s.z, &s.w, tol_for(&m, &s.z)), "{s:?}");
    for w in &s.w {
        assert!(*w >= -1e-9, "{s:?}");
    }
}

#[test]
fn unsolvable() {
    let cases: [(&[f64], &[f64]); 4] = [
        (&[0.0], &[-1.0]),
        (&[-1.0], &[-1.0]),
        // w₁ + w₂ = −2 whatever z.
        (&[1.0, -1.0, -1.0, 1.0], &[-1.0, -1.0]),
        (&[0.0, 0.0, 0.0, 0.0], &[1.0, -1.0]),
    ];
    for (m, q) in cases {
        assert!(oracle(m, q).is_empty(), "{m:?} {q:?}");
        // Each has a proof, read from the ray: y = 1, (1, 1), (1, 1) and (0, 1).
        assert_eq!(solve(m, q), Err(LcpError::NoSolution), "{m:?} {q:?}");
    }
}

#[test]
fn degenerate_problems_that_cycle_without_the_lexicographic_rule() {
    // Found by search: with ties broken by the smallest row index instead, the pivoting
    // cycles on these (indefinite, degenerate) problems until the iteration limit; they have no
    // solution.
    let cases: [(&[f64], &[f64]); 2] = [
        (
            &[
                -2.0, 0.0, 2.0, 1.0, -2.0, 1.0, -2.0, -2.0, -2.0, -2.0, 2.0, -2.0, -1.0, 0.0, 2.0,
                2.0, 1.0, 1.0, 0.0, -2.0, 2.0, -1.0, -2.0, 2.0, -1.0,
            ],
            &[-1.0, 1.0, -1.0, -1.0, 1.0],
        ),
        (
            &[
                1.0, 2.0, 1.0, 1.0, -2.0, -1.0, -1.0, 1.0, 1.0, 0.0, -2.0, 0.0, 0.0, -2.0, 0.0,
                -1.0, 1.0, 2.0, -1.0, 2.0, 0.0, 2.0, 1.0, -1.0, -2.0,
            ],
            &[-1.0, -1.0, -1.0, -1.0, 0.0],
        ),
    ];
    for (m, q) in cases {
        assert!(oracle(m, q).is_empty(), "{m:?} {q:?}");
        // The pivoting ends on a ray (a proof or not: the matrices are indefinite), never at
        // the iteration limit.
        let result = solve(m, q);
        assert!(
            matches!(
                result,
                Err(LcpError::NoSolution
                    | LcpError::Failed {
                        stop: Stop::Ray,
                        ..
                    })
            ),
            "{m:?} {q:?}: {result:?}"
        );
    }
}

#[test]
fn iteration_limit() {
    // Not symmetric (a P-matrix): Lemke's method alone.
    let m = [2.0, -1.0, -0.5, 2.0];
    let q = [-2.0, 0.0];
    assert_eq!(
        solve_with_limit(&m, &q, None, 0),
        Err(LcpError::Failed {
            stop: Stop::IterationLimit,
            conditioning: Conditioning::Nonsymmetric
        })
    );
    assert!(solve_with_limit(&m, &q, None, 10).is_ok());
}

#[test]
fn scale_free() {
    let m = [2.0, -1.0, 0.5, -1.0, 3.0, 0.0, 0.5, 0.0, 1.5];
    let q = [-2.0, 2.0, -1.0];
    let base = solve(&m, &q).unwrap();
    // A mixed support: z₁ = 0 < w₁, the others the other way round.
    assert!(
        base.z[0] > 0.0 && base.z[1] == 0.0 && base.z[2] > 0.0,
        "{base:?}"
    );
    assert!(base.w[1] > 0.0, "{base:?}");
    // (α m, β q) has the solution (β/α) z, with w scaled by β.
    for (alpha, beta) in [
        (1e-150, 1e-150),
        (1e150, 1e150),
        (1e-150, 1.0),
        (1.0, 1e-150),
        (1e150, 1e-150),
        (1e-150, 1e150),
        (1e-310, 1e-310),
    ] {
        let ms: Vec<f64> = m.iter().map(|x| x * alpha).collect();
        let qs: Vec<f64> = q.iter().map(|x| x * beta).collect();
        let s = solve(&ms, &qs).unwrap();
        for (z, z0) in s.z.iter().zip(&base.z) {
            approx::assert_relative_eq!(*z, z0 * (beta / alpha), max_relative = 1e-12);
        }
        for (w, w0) in s.w.iter().zip(&base.w) {
            assert!(
                (w - w0 * beta).abs() <= 1e-14 * beta,
                "{alpha} {beta}: {s:?}"
            );
        }
        assert!(is_solution(
            &m,
            &q,
            &s.z.iter().map(|z| z * alpha / beta).collect::<Vec<_>>(),
            &s.w.iter().map(|w| w / beta).collect::<Vec<_>>(),
            1e-12
        ));
    }
}

#[test]
fn non_finite() {
    let m = [2.0, -1.0, -1.0, 2.0];
    let q = [-2.0, 0.0];
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for i in 0..4 {
            let mut mb = m;
            mb[i] = bad;
            assert_eq!(solve(&mb, &q), Err(LcpError::NonFinite));
        }
        for i in 0..2 {
            let mut qb = q;
            qb[i] = bad;
            assert_eq!(solve(&m, &qb), Err(LcpError::NonFinite));
        }
        // Also with q ≥ 0 otherwise (the early return must not hide it).
        assert_eq!(solve(&m, &[bad, 1.0]), Err(LcpError::NonFinite));
        assert!(!is_solution(&m, &q, &[bad, 0.0], &[0.0, 0.0], 1.0));
    }
    // The solution itself would overflow f64.
    assert_eq!(solve(&[1e-300], &[-1e300]), Err(LcpError::NonFinite));
}

#[test]
#[should_panic(expected = "lcp::solve")]
fn length_mismatch_panics() {
    let _ = solve(&[1.0, 2.0, 3.0], &[-1.0, 0.0]);
}

#[test]
fn is_solution_rejects() {
    let m = [2.0, -1.0, -1.0, 2.0];
    let q = [-2.0, 0.0];
    let (z, w) = ([4.0 / 3.0, 2.0 / 3.0], [0.0, 0.0]);
    assert!(is_solution(&m, &q, &z, &w, 1e-12));
    // w ≠ m z + q.
    assert!(!is_solution(&m, &q, &z, &[0.0, 1e-3], 1e-6));
    // z < 0.
    assert!(!is_solution(&m, &q, &[-1.0, 0.0], &[-4.0, 1.0], 1e-6));
    // Not complementary: z = (2, 1), w = (1, 0).
    assert!(!is_solution(&m, &q, &[2.0, 1.0], &[1.0, 0.0], 1e-6));
    // Lengths.
    assert!(!is_solution(&m, &q, &z[..1], &w, 1e-6));
    assert!(!is_solution(&m[..3], &q, &z, &w, 1e-6));
}

#[test]
fn largest_size() {
    // k = 64, a chain of contacts (tridiagonal, like a long Newton's cradle) plus a random
    // low-rank part, deterministic.
    let k = 64;
    let mut m = vec![0.0; k * k];
    let mut state = 12345u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let u: Vec<f64> = (0..k).map(|_| next()).collect();
    for i in 0..k {
        m[i * k + i] = 2.0;
        if i + 1 < k {
            m[i * k + i + 1] = -1.0;
            m[(i + 1) * k + i] = -1.0;
        }
        for j in 0..k {
            m[i * k + j] += u[i] * u[j];
        }
    }
    let q: Vec<f64> = (0..k).map(|_| 2.0 * next()).collect();
    let s = solve(&m, &q).unwrap();
    assert!(is_solution(&m, &q, &s.z, &s.w, 1e-10), "{s:?}");
    assert_eq!(solve(&m, &q).unwrap(), s);
}
