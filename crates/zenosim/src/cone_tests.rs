//! The cone solver against closed forms, against the LCP (the planar problem is one), and
//! against Coulomb's law itself on random problems in space.

use nalgebra::{DMatrix, DVector};

use super::{solve, Contact};
use crate::lcp;

/// A small deterministic generator (xorshift), uniform in `[-1, 1)`.
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A random Delassus matrix `J M⁻¹ Jᵀ` of `rows` rows from `dofs` coordinates (singular where
/// `rows > dofs`: dependent contacts).
fn delassus(random: &mut Random, rows: usize, dofs: usize) -> DMatrix<f64> {
    delassus_and_rows(random, rows, dofs).0
}

/// [`delassus`] and the rows `J` it is made of.
fn delassus_and_rows(
    random: &mut Random,
    rows: usize,
    dofs: usize,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let j = DMatrix::from_fn(rows, dofs, |_, _| random.next());
    let a = DMatrix::from_fn(dofs, dofs, |_, _| random.next());
    let inverse_mass = &a * a.transpose() + DMatrix::identity(dofs, dofs) * 0.1;
    (&j * inverse_mass * j.transpose(), j)
}

fn contacts(tangents: &[usize], mu: &[f64]) -> Vec<Contact> {
    let mut start = 0;
    tangents
        .iter()
        .zip(mu)
        .map(|(&d, &mu)| {
            let c = Contact {
                start,
                tangents: d,
                mu,
            };
            start += 1 + d;
            c
        })
        .collect()
}

/// The worst violation of Coulomb's law with the isotropic cone by `p`, relative to the scale
/// of the impulses and velocities.
fn violation(w: &DMatrix<f64>, q: &DVector<f64>, cs: &[Contact], p: &DVector<f64>) -> f64 {
    let u = q + w * p;
    // Impulses are of the size of `q` (W is of order 1 here).
    let scale_p = p.amax().max(q.amax()).max(1e-300);
    let scale_u = q.amax().max((w * p).amax()).max(1e-300);
    let mut worst = 0.0_f64;
    for c in cs {
        let (pn, un) = (p[c.start], u[c.start]);
        worst = worst
            .max(-pn / scale_p)
            .max(-un / scale_u)
            .max((pn / scale_p).min(un / scale_u).abs());
        if c.tangents == 0 {
            continue;
        }
        let range = c.start + 1..c.start + 1 + c.tangents;
        let pt = p.rows_range(range.clone());
        let ut = u.rows_range(range);
        worst = worst.max((pt.norm() - c.mu * pn) / scale_p);
        if ut.norm() > 1e-9 * scale_u {
            // Sliding: Pₜ = −μ Pₙ uₜ/|uₜ|.
            let expected = -(c.mu * pn / ut.norm()) * ut;
            worst = worst.max((pt - expected).amax() / scale_p);
        }
    }
    worst
}

#[test]
fn a_single_contact_slides_against_its_slip_in_closed_form() {
    // W = I, approaching at 1, slipping at (3, 4): Pₙ = 1 stops it; |uₜ| = 5 > μ Pₙ, so it
    // slides with Pₜ = −μ (3, 4)/5, and uₜ = (3, 4)(1 − μ/5).
    let w = DMatrix::identity(3, 3);
    let q = DVector::from_vec(vec![-1.0, 3.0, 4.0]);
    let cs = contacts(&[2], &[0.5]);
    let p = solve(&w, &q, &cs).unwrap();
    let expected = [1.0, -0.3, -0.4];
    for (a, b) in p.iter().zip(expected) {
        assert!((a - b).abs() <= 1e-15, "{p}");
    }
    // With μ = 10 it sticks: Pₜ = −(3, 4).
    let cs = contacts(&[2], &[10.0]);
    let p = solve(&w, &q, &cs).unwrap();
    let expected = [1.0, -3.0, -4.0];
    for (a, b) in p.iter().zip(expected) {
        assert!((a - b).abs() <= 1e-15, "{p}");
    }
}

#[test]
fn a_contact_moving_away_takes_no_impulse() {
    let w = DMatrix::identity(3, 3);
    let q = DVector::from_vec(vec![2.0, 3.0, -4.0]);
    let p = solve(&w, &q, &contacts(&[2], &[0.5])).unwrap();
    assert_eq!(p.amax(), 0.0, "{p}");
}

/// The planar problem as Glocker's LCP in `(Pₙ, a = Pₜ + μPₙ, uₜ⁻)`: `w = (uₙ, uₜ⁺, 2μPₙ − a)`.
fn planar_by_lcp(w: &DMatrix<f64>, q: &DVector<f64>, mu: &[f64]) -> DVector<f64> {
    let k = mu.len();
    let size = 3 * k;
    let (n, t) = (|i: usize| 2 * i, |i: usize| 2 * i + 1);
    let mut m = vec![0.0; size * size];
    let mut rhs = vec![0.0; size];
    for i in 0..k {
        for (row, r) in [(i, n(i)), (k + i, t(i))] {
            rhs[row] = q[r];
            for j in 0..k {
                // Pₙⱼ's column carries −μⱼ times Pₜⱼ's.
                m[row * size + j] = w[(r, n(j))] - mu[j] * w[(r, t(j))];
                m[row * size + k + j] = w[(r, t(j))];
            }
        }
        m[(k + i) * size + 2 * k + i] = 1.0;
        m[(2 * k + i) * size + i] = 2.0 * mu[i];
        m[(2 * k + i) * size + k + i] = -1.0;
    }
    let z = lcp::solve(&m, &rhs).expect("the planar LCP is solved").z;
    DVector::from_fn(2 * k, |r, _| {
        let i = r / 2;
        if r % 2 == 0 {
            z[i]
        } else {
            z[k + i] - mu[i] * z[i]
        }
    })
}

#[test]
fn planar_problems_agree_with_the_lcp() {
    let mut random = Random(0x2545_f491_4f6c_dd1d);
    let mut compared = 0;
    for case in 0..300 {
        let k = 1 + case % 4;
        let w = delassus(&mut random, 2 * k, 2 * k + 1);
        let q = DVector::from_fn(2 * k, |_, _| random.next());
        // Small coefficients: the solution is unique for a positive definite W.
        let mu: Vec<f64> = (0..k).map(|_| 0.1 * (1.0 + random.next())).collect();
        let cs = contacts(&vec![1; k], &mu);
        let p = solve(&w, &q, &cs).unwrap_or_else(|e| panic!("case {case}: {e:?}"));
        assert!(violation(&w, &q, &cs, &p) <= 1e-12, "case {case}: {p}");
        let reference = planar_by_lcp(&w, &q, &mu);
        let (u, u_ref) = (&q + &w * &p, &q + &w * &reference);
        assert!(
            (&u - &u_ref).amax() <= 1e-10 * (1.0 + u_ref.amax()),
            "case {case}: velocities {u} and the LCP's {u_ref}"
        );
        compared += 1;
    }
    assert_eq!(compared, 300);
}

#[test]
fn random_problems_in_space_meet_coulombs_law() {
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    let mut worst = 0.0_f64;
    for case in 0..1000 {
        let k = 1 + case % 5;
        let tangents: Vec<usize> = (0..k).map(|i| if i % 3 == 2 { 1 } else { 2 }).collect();
        let rows: usize = tangents.iter().map(|d| 1 + d).sum();
        // Every third case has fewer coordinates than rows (dependent contacts, a table on
        // four legs); its velocities are then those of the coordinates, `q = J v`, as an
        // impact's are.
        let dependent = case % 3 == 0;
        let dofs = if dependent {
            rows.div_ceil(2) + 1
        } else {
            rows + 2
        };
        let (w, j) = delassus_and_rows(&mut random, rows, dofs);
        let q = if dependent {
            &j * DVector::from_fn(dofs, |_, _| random.next())
        } else {
            DVector::from_fn(rows, |_, _| random.next())
        };
        let mu: Vec<f64> = (0..k).map(|_| 1.0 * (1.0 + random.next())).collect();
        let cs = contacts(&tangents, &mu);
        let p = solve(&w, &q, &cs).unwrap_or_else(|e| panic!("case {case}: {e:?}"));
        let v = violation(&w, &q, &cs, &p);
        assert!(v <= 1e-10, "case {case}: violation {v:e}, P = {p}");
        worst = worst.max(v);
    }
    assert!(worst <= 1e-10, "worst violation {worst:e}");
}

#[test]
fn a_planar_problem_written_in_space_gives_the_planar_answer() {
    let mut random = Random(0x1234_5678_9abc_def1);
    for case in 0..100 {
        let k = 1 + case % 3;
        let w2 = delassus(&mut random, 2 * k, 2 * k + 2);
        let q2 = DVector::from_fn(2 * k, |_, _| random.next());
        let mu: Vec<f64> = (0..k).map(|_| 0.2 * (1.0 + random.next())).collect();
        let planar = solve(&w2, &q2, &contacts(&vec![1; k], &mu)).unwrap();
        // The second tangent of each contact is decoupled, with nothing driving it.
        let w3 = DMatrix::from_fn(3 * k, 3 * k, |r, c| {
            let (i, a) = (r / 3, r % 3);
            let (j, b) = (c / 3, c % 3);
            match (a, b) {
                (2, 2) if i == j => 1.0,
                (2, _) | (_, 2) => 0.0,
                _ => w2[(2 * i + a, 2 * j + b)],
            }
        });
        let q3 = DVector::from_fn(3 * k, |r, _| {
            if r % 3 == 2 {
                0.0
            } else {
                q2[2 * (r / 3) + r % 3]
            }
        });
        let space = solve(&w3, &q3, &contacts(&vec![2; k], &mu)).unwrap();
        for i in 0..k {
            assert!((space[3 * i] - planar[2 * i]).abs() <= 1e-12, "case {case}");
            assert!(
                (space[3 * i + 1] - planar[2 * i + 1]).abs() <= 1e-12,
                "case {case}"
            );
            assert!(space[3 * i + 2].abs() <= 1e-14, "case {case}");
        }
    }
}

#[test]
fn non_finite_data_is_refused() {
    let w = DMatrix::identity(3, 3);
    let q = DVector::from_vec(vec![-1.0, f64::NAN, 0.0]);
    assert_eq!(
        solve(&w, &q, &contacts(&[2], &[0.5])),
        Err(super::ConeError::NonFinite)
    );
}

/// A single contact whose sliding solution lies next to the angle where its normal response to
/// its own sliding vanishes (the wedging edge): the ring search of the exact single-contact
/// solve on 48 angles could not bracket it, and Newton's method failed from the three starts it
/// had; a reviewer's random start found it (violation 8e-15). The exact solve searches 720
/// angles now (and Newton's method has scattered starts besides).
#[test]
fn a_slide_next_to_the_wedging_edge_is_found() {
    let w = DMatrix::from_row_slice(
        3,
        3,
        &[
            0.45713557809530214,
            0.4401408367281503,
            -0.9720290396584108,
            0.4401408367281503,
            0.7367507492672394,
            -1.7372810785728987,
            -0.9720290396584108,
            -1.7372810785728987,
            4.440980679681228,
        ],
    );
    let q = DVector::from_vec(vec![
        -0.004623381780824845,
        -0.0061316184911455185,
        -0.618083829448619,
    ]);
    let cs = contacts(&[2], &[0.6932866304963579]);
    let p = solve(&w, &q, &cs).expect("solved");
    assert!(violation(&w, &q, &cs, &p) <= 1e-12, "{p}");
    // Sliding: the reviewer's answer, (0.33438, 0.11176, 0.20310).
    for (a, b) in p.iter().zip([0.33438, 0.11176, 0.20310]) {
        assert!((a - b).abs() < 1e-4, "{p}");
    }
}
