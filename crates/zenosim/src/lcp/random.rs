//! Random degenerate positive definite problems against enumeration of complementary bases:
//! zeros, tiny, subnormal and repeated entries in `q`, ratios that nearly tie, problems whose
//! solution is planted with both `zᵢ` and `wᵢ` zero; `m` the identity, a Gram matrix of random
//! rows (repeated rows among them) plus a multiple of the identity, scaled rows and columns, a
//! chain of contacts (the column of beads), integer Gram matrices; `k` from 1 to 12.
//!
//! `LCP_RANDOM_CASES=N cargo test --release -p zenosim --lib lcp::random -- --nocapture` runs
//! `N` of them (the default keeps the test suite's run to a few seconds) and prints the count,
//! the failures and the time; `LCP_RANDOM_FIRST=S` starts at the seed `S` (to replay one).

use std::time::Instant;

use super::check::{affine, UNDERFLOW};
use super::{solve, solve_rounded, Solution};

/// A small deterministic generator (SplitMix64), so that a failing case is named by its seed.
pub(super) struct Rng(u64);

impl Rng {
    pub(super) fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut x = self.0;
        x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        x ^ (x >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[a, b)`.
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }

    /// Uniform in `0..n` (`n > 0`).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn sign(&mut self) -> f64 {
        if self.next() & 1 == 0 {
            1.0
        } else {
            -1.0
        }
    }
}

/// The complementary basic solution of `(m, q)` with the smallest violation, over all `2ᵏ`
/// bases `S` (`z_S = −m_SS⁻¹ q_S` by Cholesky, `z = 0` off `S`; `m` positive definite), and
/// that violation: `max((−zᵢ)⁺ / ‖z‖∞, (−wᵢ − u)⁺ / termsᵢ)`, as the solver's check measures it.
pub(super) fn enumerate(m: &[f64], q: &[f64]) -> (Vec<f64>, f64) {
    let k = q.len();
    let mut best = (vec![0.0; k], f64::INFINITY);
    let mut l = vec![0.0; k * k];
    for mask in 0u32..(1 << k) {
        let s: Vec<usize> = (0..k).filter(|&i| mask & (1 << i) != 0).collect();
        let p = s.len();
        let mut ok = true;
        for c in 0..p {
            let mut d = m[s[c] * k + s[c]];
            for r in 0..c {
                d -= l[c * p + r] * l[c * p + r];
            }
            if d.is_nan() || d <= 0.0 {
                ok = false;
                break;
            }
            l[c * p + c] = d.sqrt();
            for r in c + 1..p {
                let mut x = m[s[r] * k + s[c]];
                for j in 0..c {
                    x -= l[r * p + j] * l[c * p + j];
                }
                l[r * p + c] = x / l[c * p + c];
            }
        }
        if !ok {
            continue;
        }
        // z_S = −m_SS⁻¹ q_S, then two corrections from the residual (iterative refinement);
        // the best of the three is the basis's solution.
        let solve = |b: &[f64]| {
            let mut y = b.to_vec();
            for r in 0..p {
                for j in 0..r {
                    y[r] -= l[r * p + j] * y[j];
                }
                y[r] /= l[r * p + r];
            }
            for r in (0..p).rev() {
                for j in r + 1..p {
                    y[r] -= l[j * p + r] * y[j];
                }
                y[r] /= l[r * p + r];
            }
            y
        };
        let mut y = solve(&s.iter().map(|&i| -q[i]).collect::<Vec<_>>());
        let mut last = f64::INFINITY;
        for refinement in 0..3 {
            if refinement > 0 {
                if best.1 < 1e-12 || last > 1e-3 {
                    // Accurate enough, or a basis far from feasible.
                    break;
                }
                let residual: Vec<f64> = s
                    .iter()
                    .map(|&i| {
                        -q[i]
                            - s.iter()
                                .zip(&y)
                                .map(|(&j, yj)| m[i * k + j] * yj)
                                .sum::<f64>()
                    })
                    .collect();
                for (yr, d) in y.iter_mut().zip(solve(&residual)) {
                    *yr += d;
                }
            }
            let mut z = vec![0.0; k];
            for (&i, &x) in s.iter().zip(&y) {
                z[i] = x;
            }
            let worst = measure(m, q, &z);
            last = worst;
            if worst < best.1 {
                best = (z, worst);
            }
        }
    }
    best
}

/// `max((−zᵢ)⁺ / ‖z‖∞, (−wᵢ − u)⁺ / termsᵢ, min(zᵢ⁺ / ‖z‖∞, (|wᵢ| − u)⁺ / termsᵢ))`, `w = m z + q`,
/// `termsᵢ = |qᵢ| + Σⱼ |mᵢⱼ zⱼ|`, `uᵢ` the solver's allowance for subnormal numbers (relative to
/// `‖q‖∞` in `w`, and in each `zⱼ`): 0 for an exact solution, free of units (written apart from
/// the solver's own check).
pub(super) fn measure(m: &[f64], q: &[f64], z: &[f64]) -> f64 {
    let k = q.len();
    let w = affine(m, q, z);
    let norm = z.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    // The solver's allowance is UNDERFLOW in w, in units of q's largest entry (rounded down to
    // a power of two), and in each zⱼ.
    let q_norm = q.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let mut worst = 0.0_f64;
    for i in 0..k {
        let terms: f64 = q[i].abs() + (0..k).map(|j| (m[i * k + j] * z[j]).abs()).sum::<f64>();
        let allowance = UNDERFLOW * (q_norm + (0..k).map(|j| m[i * k + j].abs()).sum::<f64>());
        let relative = |x: f64| if x > 0.0 { x / terms } else { 0.0 };
        if norm > 0.0 {
            worst = worst.max(-z[i] / norm);
            worst = worst.max((z[i].max(0.0) / norm).min(relative(w[i].abs() - allowance)));
        }
        worst = worst.max(relative(-w[i] - allowance));
    }
    if worst.is_nan() {
        f64::INFINITY
    } else {
        worst
    }
}

/// Checks the solver's answer on `(m, q)` (positive definite `m`) against enumeration; `Err`
/// says what is wrong.
pub(super) fn check_against_enumeration(
    m: &[f64],
    q: &[f64],
    result: &Result<Solution, super::LcpError>,
) -> Result<(), String> {
    let s = result.as_ref().map_err(|e| format!("solver: {e}"))?;
    let (expected, expected_worst) = enumerate(m, q);
    if expected_worst > 1e-9 {
        return Err(format!(
            "enumeration found no solution ({expected_worst:e})"
        ));
    }
    let worst = measure(m, q, &s.z);
    if worst > 1e-9 {
        return Err(format!("the answer violates the LCP by {worst:e}: {s:?}"));
    }
    if s.w != affine(m, q, &s.z) {
        return Err(format!("w is not m z + q: {s:?}"));
    }
    // Both answers pass the check, so each solves the problem up to a residual of 10⁻⁹ of its
    // terms plus the allowance uᵢ for subnormal numbers; with m̃ = D m D scaled to a unit
    // diagonal (D = diag(mᵢᵢ)^−½) and λ its smallest eigenvalue, two such answers differ by at
    // most 2 √k (10⁻⁹ (‖q̃‖∞ + k ‖z̃‖∞) + maxᵢ uᵢ / dᵢ) / λ in z̃ = D⁻¹ z: the test allows that.
    let k = q.len();
    let d: Vec<f64> = (0..k).map(|i| m[i * k + i].sqrt()).collect();
    let scaled = nalgebra::DMatrix::from_fn(k, k, |i, j| m[i * k + j] / (d[i] * d[j]));
    let lambda = scaled.symmetric_eigen().eigenvalues.min();
    let q_norm = (0..k).fold(0.0_f64, |a, i| a.max((q[i] / d[i]).abs()));
    let z_norm = (0..k).fold(0.0_f64, |a, i| a.max((expected[i] * d[i]).abs()));
    let largest_q = q.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let allowance = (0..k).fold(0.0_f64, |a, i| {
        let row: f64 = (0..k).map(|j| m[i * k + j].abs()).sum();
        a.max(UNDERFLOW * (largest_q + row) / d[i])
    });
    let tolerance =
        2.0 * (k as f64).sqrt() * (1e-9 * (q_norm + k as f64 * z_norm) + allowance) / lambda;
    let differs = (0..k).any(|i| ((s.z[i] - expected[i]) * d[i]).abs() > tolerance);
    if differs {
        return Err(format!("z = {:?}, enumeration {expected:?}", s.z));
    }
    Ok(())
}

/// One random degenerate positive definite problem, and a rounding bound per entry of `q`
/// (`None`: solved as exact).
pub(super) fn problem(rng: &mut Rng) -> (Vec<f64>, Vec<f64>, Option<Vec<f64>>) {
    let k = 1 + rng.below(12);
    let mut m = vec![0.0; k * k];
    let kind = rng.below(5);
    match kind {
        0 => {
            // A multiple of the identity.
            let s = 2f64.powi(rng.below(9) as i32 - 4);
            for i in 0..k {
                m[i * k + i] = s;
            }
        }
        1 | 4 => {
            // A Gram matrix of random rows, some repeated, plus δ I; kind 4 then scaled,
            // D m D with D from 10⁻³ to 10³.
            let n = k + rng.below(3);
            let mut a: Vec<f64> = (0..k * n).map(|_| rng.range(-1.0, 1.0)).collect();
            for i in 1..k {
                if rng.below(4) == 0 {
                    let source = rng.below(i);
                    let row: Vec<f64> = a[source * n..(source + 1) * n].to_vec();
                    a[i * n..(i + 1) * n].copy_from_slice(&row);
                }
            }
            let delta = 10f64.powf(rng.range(-3.0, 0.0));
            for i in 0..k {
                for j in 0..=i {
                    let x: f64 = (0..n).map(|l| a[i * n + l] * a[j * n + l]).sum();
                    m[i * k + j] = x;
                    m[j * k + i] = x;
                }
                m[i * k + i] += delta;
            }
            if kind == 4 {
                let d: Vec<f64> = (0..k).map(|_| 10f64.powf(rng.range(-3.0, 3.0))).collect();
                for i in 0..k {
                    for j in 0..k {
                        m[i * k + j] *= d[i] * d[j];
                    }
                }
            }
        }
        2 => {
            // A column of beads on a floor: the chain's Delassus matrix, broken into blocks
            // where some contacts are absent.
            for i in 0..k {
                m[i * k + i] = if i == 0 && rng.below(2) == 0 {
                    1.0
                } else {
                    2.0
                };
                if i > 0 && rng.below(4) != 0 {
                    m[i * k + i - 1] = -1.0;
                    m[(i - 1) * k + i] = -1.0;
                }
            }
        }
        _ => {
            // An integer Gram matrix plus the identity: exact ties.
            let n = k;
            let a: Vec<f64> = (0..k * n).map(|_| rng.below(5) as f64 - 2.0).collect();
            for i in 0..k {
                for j in 0..k {
                    m[i * k + j] = (0..n).map(|l| a[i * n + l] * a[j * n + l]).sum();
                }
                m[i * k + i] += 1.0;
            }
        }
    }
    let q = if rng.below(4) == 0 {
        planted(rng, &m, k)
    } else {
        (0..k).map(|_| entry(rng)).collect::<Vec<_>>()
    };
    // Filled in order: entry() may copy an earlier entry or nearly tie with it.
    let q = {
        let mut filled = q;
        for i in 0..k {
            if filled[i].is_nan() {
                let j = rng.below(i.max(1));
                filled[i] = if i == 0 {
                    0.0
                } else {
                    tie(rng, &m, k, &filled, i, j)
                };
            }
        }
        filled
    };
    let round_off = (rng.below(3) == 0).then(|| {
        q.iter()
            .map(|x| x.abs() * 10f64.powf(rng.range(-1.0, 1.0)))
            .collect()
    });
    (m, q, round_off)
}

/// One entry of `q` (NaN: to be filled as a near tie with an earlier entry).
fn entry(rng: &mut Rng) -> f64 {
    match rng.below(9) {
        0 | 1 => 0.0,
        // Subnormal.
        2 => rng.sign() * f64::from_bits(1 + rng.next() % (1u64 << 52)),
        // Tiny, down to 10⁻³⁰⁰.
        3 => rng.sign() * 10f64.powf(rng.range(-300.0, -10.0)),
        // The remains of a cancellation in f32 range, as in the column of beads.
        4 => rng.sign() * 2.6624670822171523e-45 * (1 + rng.below(4)) as f64,
        // Repeated or nearly tied: filled afterwards.
        5 | 6 => f64::NAN,
        _ => rng.range(-2.0, 2.0),
    }
}

/// `qᵢ` equal to `qⱼ`, or with the ratio `qᵢ / mᵢᵢ` equal to `qⱼ / mⱼⱼ` up to a relative
/// `10⁻¹⁶` to `10⁻⁸`.
fn tie(rng: &mut Rng, m: &[f64], k: usize, q: &[f64], i: usize, j: usize) -> f64 {
    if rng.below(2) == 0 {
        return q[j];
    }
    let ratio = q[j] / m[j * k + j] * m[i * k + i];
    ratio * (1.0 + rng.sign() * 10f64.powf(rng.range(-16.0, -8.0)))
}

/// `q = w* − m z*` for a complementary pair with zeros in both at some indices (degenerate),
/// some entries of `z*` tiny.
fn planted(rng: &mut Rng, m: &[f64], k: usize) -> Vec<f64> {
    let mut z = vec![0.0; k];
    let mut w = vec![0.0; k];
    for i in 0..k {
        match rng.below(4) {
            0 => {}
            1 => z[i] = rng.range(0.0, 2.0),
            2 => w[i] = rng.range(0.0, 2.0),
            _ => z[i] = 10f64.powf(rng.range(-40.0, -1.0)),
        }
    }
    (0..k)
        .map(|i| w[i] - (0..k).map(|j| m[i * k + j] * z[j]).sum::<f64>())
        .collect()
}

/// The problem with its entries within their rounding set to 0, as `solve_rounded` does.
fn cleaned(q: &[f64], round_off: &Option<Vec<f64>>) -> Vec<f64> {
    match round_off {
        None => q.to_vec(),
        Some(r) => q
            .iter()
            .zip(r)
            .map(|(&x, &r)| if x.abs() <= r { 0.0 } else { x })
            .collect(),
    }
}

#[test]
fn random_degenerate_positive_definite_problems_match_enumeration() {
    let cases: u64 = std::env::var("LCP_RANDOM_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3000);
    let first: u64 = std::env::var("LCP_RANDOM_FIRST")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let start = Instant::now();
    let mut failures = Vec::new();
    let mut failed = 0u64;
    for seed in first..first.saturating_add(cases) {
        let mut rng = Rng::new(seed);
        let (m, q, round_off) = problem(&mut rng);
        let result = match &round_off {
            None => solve(&m, &q),
            Some(r) => solve_rounded(&m, &q, r),
        };
        if let Err(why) = check_against_enumeration(&m, &cleaned(&q, &round_off), &result) {
            failed += 1;
            if failures.len() < 10 {
                failures.push(format!("seed {seed}: m = {m:?}, q = {q:?}: {why}"));
            }
        }
    }
    eprintln!(
        "{cases} random degenerate positive definite problems: {failed} failures, {:.1} s",
        start.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
