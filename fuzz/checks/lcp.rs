//! The check of the lcp fuzz target (`fuzz/fuzz_targets/lcp.rs`), shared with the test that
//! replays the seeds in CI (`crates/zenosim-cli/tests/fuzz_replay.rs`), both of which include
//! this file by `#[path]`.
//!
//! The input is a linear complementarity problem as bytes: the first byte gives `k`
//! (`byte % 13`), the second how to read the rest (bit 0: with rounding bounds, solved by
//! `lcp::solve_rounded`, else by `lcp::solve`; bit 1: `m` is the Gram matrix `A Aᵀ + δ I` of the
//! `k × k` matrix `A` read in its place, as the engine's Delassus matrices are, else `m` is read
//! as it is). Then `f64`s, 8 bytes each, little-endian: `m` (or `A`) row by row, `q`, the
//! rounding bounds, `δ`; missing ones are 0.
//!
//! Nothing may panic. An input with a NaN or an infinity (in `m` as built) is refused as
//! `NonFinite`. An answer is checked free of units, as the solver promises
//! (docs/contact-laws.md, "The LCP solver"): `z ≥ 0`, `w` is `m z + q` (`q` cleaned of the
//! entries within their bounds), and in every row `−wᵢ` and `min(zᵢ / ‖z‖∞, |wᵢ| / termsᵢ)` are
//! at most `10⁻⁹` of `termsᵢ = |qᵢ| + Σⱼ |mᵢⱼ zⱼ|`, up to the allowance for subnormal numbers.
//! A symmetric `m` whose Cholesky pivots all exceed `10⁻⁶` of their diagonal entries (well
//! conditioned, positive definite: exactly one solution) must be solved, unless the solution
//! overflows `f64` or the entries of `m` or `q` span more than `2⁵⁰⁰` (the solver scales each
//! by one power of two).

use zenosim::lcp::{self, LcpError};

/// The checks' tolerance, the solver's own.
const ACCEPTANCE: f64 = 1e-9;

/// The solver's allowance for subnormal numbers: 2¹⁰ units of the smallest, in `w` relative to
/// the largest entry of `q` (rounded down to a power of two; here the entry itself, which is at
/// most twice as lenient) and in each `zⱼ`.
const UNDERFLOW: f64 = 1024.0 * f64::from_bits(1);

/// The check of one input: panics on a finding.
pub fn check(data: &[u8]) {
    let k = usize::from(data.first().copied().unwrap_or(0)) % 13;
    let flags = data.get(1).copied().unwrap_or(0);
    let (rounded, gram) = (flags & 1 != 0, flags & 2 != 0);
    let mut values = data.get(2..).unwrap_or_default().chunks(8).map(|chunk| {
        let mut bytes = [0u8; 8];
        bytes[..chunk.len()].copy_from_slice(chunk);
        f64::from_le_bytes(bytes)
    });
    let mut next = || values.next().unwrap_or(0.0);
    let entries: Vec<f64> = (0..k * k).map(|_| next()).collect();
    let q: Vec<f64> = (0..k).map(|_| next()).collect();
    let round_off: Vec<f64> = if rounded {
        (0..k).map(|_| next()).collect()
    } else {
        Vec::new()
    };
    let m = if gram {
        let delta = next().abs();
        let mut m = vec![0.0; k * k];
        for i in 0..k {
            for j in 0..k {
                m[i * k + j] = (0..k)
                    .map(|l| entries[i * k + l] * entries[j * k + l])
                    .sum();
            }
            m[i * k + i] += delta;
        }
        m
    } else {
        entries
    };
    let result = if rounded {
        lcp::solve_rounded(&m, &q, &round_off)
    } else {
        lcp::solve(&m, &q)
    };
    if !m.iter().chain(&q).chain(&round_off).all(|x| x.is_finite()) {
        assert_eq!(result, Err(LcpError::NonFinite));
        return;
    }
    let cleaned: Vec<f64> = if rounded {
        q.iter()
            .zip(&round_off)
            .map(|(&x, &r)| if x.abs() <= r { 0.0 } else { x })
            .collect()
    } else {
        q.clone()
    };
    match result {
        Ok(s) => check_answer(&m, &cleaned, &s.z, &s.w),
        Err(LcpError::NonFinite) => {}
        Err(error) => assert!(
            !(well_conditioned(&m, k) && moderate(&m) && moderate(&q)),
            "{error} on a well-conditioned positive definite problem"
        ),
    }
}

/// Panics unless `(z, w)` solves `(m, q)` as the solver promises.
fn check_answer(m: &[f64], q: &[f64], z: &[f64], w: &[f64]) {
    let k = q.len();
    assert!(z.len() == k && w.len() == k);
    assert!(z.iter().chain(w).all(|x| x.is_finite()), "{z:?} {w:?}");
    assert!(z.iter().all(|&x| x >= 0.0), "{z:?}");
    let norm = z.iter().fold(0.0_f64, |a, &x| a.max(x));
    let q_norm = q.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    for i in 0..k {
        let row = &m[i * k..(i + 1) * k];
        let affine = row
            .iter()
            .zip(z)
            .fold(q[i], |acc, (mij, zj)| acc + mij * zj);
        assert_eq!(w[i], affine, "w is not m z + q in row {i}");
        let terms = row
            .iter()
            .zip(z)
            .fold(q[i].abs(), |acc, (mij, zj)| acc + (mij * zj).abs());
        let allowance = UNDERFLOW * (q_norm + row.iter().map(|x| x.abs()).sum::<f64>());
        let negative = (-w[i] - allowance).max(0.0);
        let off = (w[i].abs() - allowance).max(0.0);
        assert!(negative <= ACCEPTANCE * terms, "w[{i}] = {} < 0", w[i]);
        if norm > 0.0 {
            assert!(
                z[i] <= ACCEPTANCE * norm || off <= ACCEPTANCE * terms,
                "row {i} not complementary: z = {}, w = {}",
                z[i],
                w[i]
            );
        }
    }
}

/// Whether the nonzero entries of `x` lie within `2⁻⁵⁰⁰` of the largest (the solver scales by
/// powers of two, in which entries `2⁻¹⁰⁷⁴` below the largest would vanish).
fn moderate(x: &[f64]) -> bool {
    let largest = x.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    x.iter()
        .all(|v| *v == 0.0 || v.abs() >= largest * 2f64.powi(-500))
}

/// Whether `m` is symmetric and its Cholesky pivots all exceed `10⁻⁶` of their diagonal
/// entries.
fn well_conditioned(m: &[f64], k: usize) -> bool {
    let mut l = vec![0.0; k * k];
    for j in 0..k {
        for i in 0..j {
            if m[i * k + j] != m[j * k + i] {
                return false;
            }
        }
        let mut d = m[j * k + j];
        for p in 0..j {
            d -= l[j * k + p] * l[j * k + p];
        }
        if !d.is_finite() || d <= 1e-6 * m[j * k + j] {
            return false;
        }
        l[j * k + j] = d.sqrt();
        for i in j + 1..k {
            let mut s = m[i * k + j];
            for p in 0..j {
                s -= l[i * k + p] * l[j * k + p];
            }
            l[i * k + j] = s / l[j * k + j];
        }
    }
    true
}
