//! Checks of the transcribed tableaus against the Runge–Kutta order
//! conditions `b . Phi(t) = 1 / gamma(t)` for all rooted trees `t` (Butcher
//! theory, HNW I, II.2, Theorem 2.13), and `b(theta) . Phi(t) = theta^|t| /
//! gamma(t)` for continuous extensions (HNW I, II.6, Theorem 6.1).

use super::{dop853_tableau as d8, dopri5 as d5};

/// A rooted tree: its order and the indices (in the generated list) of the
/// subtrees attached to its root, as a non-decreasing multiset.
struct Tree {
    order: usize,
    children: Vec<usize>,
}

/// All rooted trees up to `max_order`, each exactly once, ordered by order.
fn trees_up_to(max_order: usize) -> Vec<Tree> {
    fn multisets(
        orders: &[usize],
        remaining: usize,
        start: usize,
        cur: &mut Vec<usize>,
        out: &mut Vec<Vec<usize>>,
    ) {
        if remaining == 0 {
            out.push(cur.clone());
            return;
        }
        for i in start..orders.len() {
            if orders[i] <= remaining {
                cur.push(i);
                multisets(orders, remaining - orders[i], i, cur, out);
                cur.pop();
            }
        }
    }
    let mut trees = vec![Tree {
        order: 1,
        children: vec![],
    }];
    for order in 2..=max_order {
        let orders: Vec<usize> = trees.iter().map(|t| t.order).collect();
        let mut found = Vec::new();
        multisets(&orders, order - 1, 0, &mut Vec::new(), &mut found);
        trees.extend(found.into_iter().map(|children| Tree { order, children }));
    }
    trees
}

/// For every tree: its order, `gamma(t)` and `Phi(t)` (the vector of stage
/// elementary weights, `Phi(tau) = 1`, `Phi([t1..tm])_i = prod_k (A Phi(t_k))_i`).
fn elementary_weights<const S: usize>(
    a: &[[f64; S]; S],
    max_order: usize,
) -> Vec<(usize, f64, [f64; S])> {
    let trees = trees_up_to(max_order);
    let mut out: Vec<(usize, f64, [f64; S])> = Vec::new();
    let mut a_phi: Vec<[f64; S]> = Vec::new();
    for t in &trees {
        let mut phi = [1.0; S];
        let mut gamma = t.order as f64;
        for &c in &t.children {
            gamma *= out[c].1;
            for (p, ap) in phi.iter_mut().zip(&a_phi[c]) {
                *p *= ap;
            }
        }
        let ap: [f64; S] = std::array::from_fn(|i| (0..S).map(|j| a[i][j] * phi[j]).sum());
        a_phi.push(ap);
        out.push((t.order, gamma, phi));
    }
    out
}

/// Largest `|w(t) . Phi(t) - target(order, gamma)|` over trees up to `max_order`.
fn residual<const S: usize>(
    weights: &[(usize, f64, [f64; S])],
    max_order: usize,
    w: &[f64; S],
    target: impl Fn(usize, f64) -> f64,
) -> f64 {
    weights
        .iter()
        .filter(|(order, _, _)| *order <= max_order)
        .map(|(order, gamma, phi)| {
            let v: f64 = w.iter().zip(phi).map(|(a, b)| a * b).sum();
            (v - target(*order, *gamma)).abs()
        })
        .fold(0.0, f64::max)
}

/// `residual`, also printed (run with `--nocapture` to see the margins).
fn report<const S: usize>(
    what: &str,
    weights: &[(usize, f64, [f64; S])],
    max_order: usize,
    w: &[f64; S],
    target: impl Fn(usize, f64) -> f64,
) -> f64 {
    let r = residual(weights, max_order, w, target);
    eprintln!("{what}: max residual up to order {max_order} = {r:.3e}");
    r
}

fn pad<const S: usize>(v: &[f64]) -> [f64; S] {
    std::array::from_fn(|i| v.get(i).copied().unwrap_or(0.0))
}

#[test]
fn tree_generator_counts_match_a000081() {
    // Number of rooted trees with n nodes: OEIS A000081 = 1, 1, 2, 4, 9, 20, 48, 115.
    let trees = trees_up_to(8);
    let counts: Vec<usize> = (1..=8)
        .map(|n| trees.iter().filter(|t| t.order == n).count())
        .collect();
    assert_eq!(counts, [1, 1, 2, 4, 9, 20, 48, 115]);
}

#[test]
fn stage_nodes_are_row_sums() {
    for (i, row) in d8::A.iter().enumerate() {
        assert!(
            (row.iter().sum::<f64>() - d8::C[i]).abs() < 1e-14,
            "DOP853 row {i}"
        );
    }
    for (i, row) in d5::A.iter().enumerate() {
        assert!(
            (row.iter().sum::<f64>() - d5::C[i]).abs() < 1e-15,
            "DOPRI5 row {i}"
        );
    }
}

#[test]
fn dop853_weights_satisfy_order_8_conditions() {
    let w = elementary_weights(&d8::A, 9);
    let b: [f64; 16] = pad(&d8::B);
    let r8 = report("DOP853 b", &w, 8, &b, |_, g| 1.0 / g);
    assert!(r8 < 2e-14, "order-8 residual {r8:e}");
    // ... and not of order 9 (a genuine 8th-order method).
    let r9 = report("DOP853 b", &w, 9, &b, |_, g| 1.0 / g);
    assert!(r9 > 1e-6, "order-9 residual {r9:e}");
}

#[test]
fn dop853_error_estimators_have_orders_5_and_3() {
    let w = elementary_weights(&d8::A, 6);
    // er = b - b_hat with b_hat of order 5: er annihilates Phi(t) for |t| <= 5.
    let er: [f64; 16] = pad(&d8::ER);
    let r5 = report("DOP853 er", &w, 5, &er, |_, _| 0.0);
    assert!(r5 < 5e-14, "er residual up to order 5: {r5:e}");
    assert!(
        report("DOP853 er", &w, 6, &er, |_, _| 0.0) > 1e-6,
        "er should not vanish at order 6"
    );
    // bhh is a 3rd-order quadrature-type formula: bhh . Phi = 1/gamma for |t| <= 3.
    let bhh: [f64; 16] = pad(&d8::BHH);
    let r3 = report("DOP853 bhh", &w, 3, &bhh, |_, g| 1.0 / g);
    assert!(r3 < 5e-14, "bhh residual up to order 3: {r3:e}");
    assert!(report("DOP853 bhh", &w, 4, &bhh, |_, g| 1.0 / g) > 1e-6);
}

/// Stage weights `b_j(theta)` of the continuous extension as evaluated by
/// `interpolate`: `theta b + theta(1-theta) [(e_1 - b) + theta ((2b - e_1 - e_fsal)
/// + (1-theta)(d_0 + theta (d_1 + (1-theta)(d_2 + theta d_3 ...))))]`.
fn dense_weights<const S: usize>(
    theta: f64,
    b: &[f64; S],
    fsal: usize,
    d: &[[f64; S]],
) -> [f64; S] {
    let s1 = 1.0 - theta;
    std::array::from_fn(|j| {
        let mut tail = 0.0;
        for (r, dr) in d.iter().enumerate().rev() {
            let f = if r % 2 == 0 { s1 } else { theta };
            tail = f * (dr[j] + tail);
        }
        let e1 = if j == 0 { 1.0 } else { 0.0 };
        let ef = if j == fsal { 1.0 } else { 0.0 };
        theta * b[j] + theta * s1 * ((e1 - b[j]) + theta * ((2.0 * b[j] - e1 - ef) + tail))
    })
}

#[test]
fn dop853_dense_output_satisfies_order_7_conditions() {
    let w = elementary_weights(&d8::A, 8);
    let b: [f64; 16] = pad(&d8::B);
    for theta in [0.0, 0.2, 0.5, 0.7, 1.0] {
        let bt = dense_weights(theta, &b, 12, &d8::D);
        let r7 = report("DOP853 dense", &w, 7, &bt, |o, g| theta.powi(o as i32) / g);
        assert!(r7 < 2e-14, "theta = {theta}: order-7 residual {r7:e}");
    }
    let bt = dense_weights(0.5, &b, 12, &d8::D);
    assert!(
        report("DOP853 dense theta=0.5", &w, 8, &bt, |o, g| 0.5f64
            .powi(o as i32)
            / g)
            > 1e-8
    );
}

#[test]
fn dopri5_orders_5_4_and_dense_4() {
    let w = elementary_weights(&d5::A, 6);
    let b = d5::A[6];
    assert!(report("DOPRI5 b", &w, 5, &b, |_, g| 1.0 / g) < 5e-15);
    assert!(report("DOPRI5 b", &w, 6, &b, |_, g| 1.0 / g) > 1e-6);
    let b_hat: [f64; 7] = std::array::from_fn(|j| b[j] - d5::E[j]);
    assert!(report("DOPRI5 b_hat", &w, 4, &b_hat, |_, g| 1.0 / g) < 5e-15);
    assert!(report("DOPRI5 b_hat", &w, 5, &b_hat, |_, g| 1.0 / g) > 1e-6);
    for theta in [0.0, 0.3, 0.5, 0.9, 1.0] {
        let bt = dense_weights(theta, &b, d5::FSAL, &[d5::D]);
        let r4 = report("DOPRI5 dense", &w, 4, &bt, |o, g| theta.powi(o as i32) / g);
        assert!(r4 < 5e-15, "theta = {theta}: order-4 residual {r4:e}");
    }
}
