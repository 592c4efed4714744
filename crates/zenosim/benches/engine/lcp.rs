//! The contact problems' LCP solver (`zenosim::lcp`, docs/contact-laws.md) on the sets the
//! engine meets: the impact law of a column of beads on a floor (positive definite, degenerate),
//! a chain of twelve contacts struck at one end, and law 1 on a table standing on four legs
//! (dependent: positive semi-definite). Each is solved through `lcp::solve`, whose signature
//! the solver has kept, so that the same file measures any version of it.

use std::hint::black_box;

use criterion::Criterion;
use zenosim::lcp;

pub fn benches(c: &mut Criterion) {
    // The column of beads at t = 1.187 (rtol = atol = 1e-10): contacts floor, gap0 … gap5 and
    // gap7, the normal velocities cleaned of their rounding (what the engine passes).
    let beads = chain(8, &[7]);
    let beads_q = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.12268525544980818];
    // A column of twelve beads on the floor, the floor contact struck (W of the chain).
    let cradle = chain(12, &[]);
    let mut cradle_q = [0.0; 12];
    cradle_q[0] = -2.0;
    // A square table on four legs at (±1, ±1) (z, and the tilts p, r: three coordinates,
    // unit inertia), law 1 under gravity: W = A Aᵀ of rank 3.
    let legs: [[f64; 3]; 4] = [
        [1.0, 1.0, 1.0],
        [1.0, 1.0, -1.0],
        [1.0, -1.0, 1.0],
        [1.0, -1.0, -1.0],
    ];
    let table: Vec<f64> = (0..16)
        .map(|ij| (0..3).map(|l| legs[ij / 4][l] * legs[ij % 4][l]).sum())
        .collect();
    let table_q = [-9.81; 4];
    for (name, m, q) in [
        (
            "lcp: column of beads, impact (k = 8)",
            &beads[..],
            &beads_q[..],
        ),
        (
            "lcp: a chain of 12 contacts, impact at one end (k = 12)",
            &cradle[..],
            &cradle_q[..],
        ),
        (
            "lcp: table on four legs, forces (k = 4, dependent)",
            &table[..],
            &table_q[..],
        ),
    ] {
        let solution = lcp::solve(m, q).expect("a solvable problem");
        assert!(lcp::is_solution(m, q, &solution.z, &solution.w, 1e-9));
        c.bench_function(name, |b| b.iter(|| lcp::solve(black_box(m), black_box(q))));
    }
}

/// The Delassus matrix of a chain of `k` contacts (a floor, then gaps between unit masses),
/// without the couplings of the contacts in `apart` to the one before them.
fn chain(k: usize, apart: &[usize]) -> Vec<f64> {
    let mut w = vec![0.0; k * k];
    for i in 0..k {
        w[i * k + i] = if i == 0 { 1.0 } else { 2.0 };
        if i > 0 && !apart.contains(&i) {
            w[i * k + i - 1] = -1.0;
            w[(i - 1) * k + i] = -1.0;
        }
    }
    w
}
