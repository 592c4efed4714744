//! Runs that the contact problem's solver once stopped (docs/contact-laws.md, "The LCP
//! solver"), each run to its end and checked against what the physics fixes.

use zenosim::{ActiveSet, EventKind, Mode, Outcome};
use zenosim_model::parse_model;

/// Siconos's ColumnOfBeadsTS example: ten beads of mass 1 and radius 0.1, their centres at
/// `1 + 0.25 i`, falling onto a floor, `e = 0.9` on every contact, to `t = 2`. The beads touch
/// each other and the floor in every combination; the impact law's LCP is degenerate (held
/// contacts whose normal velocities are 0, or 10⁻⁴⁵ where a cancellation left its remains).
const COLUMN_OF_BEADS: &str = r#"
name = "column-of-beads"
coordinates = ["y0", "y1", "y2", "y3", "y4", "y5", "y6", "y7", "y8", "y9"]
lagrangian = "0.5*m*y0_dot^2 - m*g*y0 + 0.5*m*y1_dot^2 - m*g*y1 + 0.5*m*y2_dot^2 - m*g*y2 + 0.5*m*y3_dot^2 - m*g*y3 + 0.5*m*y4_dot^2 - m*g*y4 + 0.5*m*y5_dot^2 - m*g*y5 + 0.5*m*y6_dot^2 - m*g*y6 + 0.5*m*y7_dot^2 - m*g*y7 + 0.5*m*y8_dot^2 - m*g*y8 + 0.5*m*y9_dot^2 - m*g*y9"

[parameters]
m = 1.0
g = 9.81
r = 0.1
e = 0.9

[[constraint]]
name = "floor"
h = "y0 - r"
restitution = "e"

[[constraint]]
name = "gap0"
h = "y1 - y0 - 2*r"
restitution = "e"

[[constraint]]
name = "gap1"
h = "y2 - y1 - 2*r"
restitution = "e"

[[constraint]]
name = "gap2"
h = "y3 - y2 - 2*r"
restitution = "e"

[[constraint]]
name = "gap3"
h = "y4 - y3 - 2*r"
restitution = "e"

[[constraint]]
name = "gap4"
h = "y5 - y4 - 2*r"
restitution = "e"

[[constraint]]
name = "gap5"
h = "y6 - y5 - 2*r"
restitution = "e"

[[constraint]]
name = "gap6"
h = "y7 - y6 - 2*r"
restitution = "e"

[[constraint]]
name = "gap7"
h = "y8 - y7 - 2*r"
restitution = "e"

[[constraint]]
name = "gap8"
h = "y9 - y8 - 2*r"
restitution = "e"

[initial]
y0 = 1.0
y1 = 1.25
y2 = 1.5
y3 = 1.75
y4 = 2.0
y5 = 2.25
y6 = 2.5
y7 = 2.75
y8 = 3.0
y9 = 3.25

[simulation]
t_end = 2.0
"#;

/// The column of beads stopped, at every tolerance from 1e-6 to 1e-12 and with the paper's
/// ε rule, between t = 1.177 and t = 1.203 with "the contact problem on constraints 'floor',
/// 'gap0', … has no solution (Lemke's method ended on a ray)": Lemke's method had let its
/// auxiliary variable leave at a false tie with a row whose q̄ was −10⁻⁴⁵, and the check
/// refused the answer. Each run now finishes at t = 2 with the column at rest on the floor.
#[test]
fn lemke_ended_on_a_ray_for_a_column_of_beads() {
    // (settings, where the run used to stop)
    let cases = [
        ("", 1.187102620580677),
        ("rtol = 1e-6\natol = 1e-6\n", 1.1773550018561003),
        ("rtol = 1e-8\natol = 1e-8\n", 1.2024940521898568),
        ("rtol = 1e-12\natol = 1e-12\n", 1.1954781141403155),
        ("zeno = { epsilon = 1e-3 }\n", 1.1951625554757097),
    ];
    for (settings, stopped) in cases {
        let source = format!("{COLUMN_OF_BEADS}{settings}");
        let file = parse_model("column-of-beads.toml", &source, &[]).unwrap();
        let (run, trajectory) = file.run_keeping().unwrap();
        assert_eq!(run.outcome, Outcome::Finished, "{settings}");
        assert_eq!(run.t_final, 2.0);
        assert!(run.events.iter().any(|e| e.t > stopped), "{settings}");
        // No contact crossed at any sample, no impact gains energy (the potential is the
        // same on both sides), every impulse pushes.
        for p in &trajectory.points {
            assert!(p.h.iter().all(|&h| h >= -1e-9), "{settings}: {p:?}");
        }
        let derived = zenosim::Derived::new(&file.model).unwrap();
        for e in run.events.iter().filter(|e| e.kind == EventKind::Impact) {
            let before = derived.energy(&e.before.q, &e.before.q_dot);
            let after = derived.energy(&e.after.q, &e.after.q_dot);
            assert!(after <= before + 1e-12 * before.abs(), "{settings}: {e:?}");
            assert!(e.impulses.iter().all(|&l| l >= -1e-12), "{settings}: {e:?}");
        }
        // The beads fall together until the lowest reaches the floor, from 0.9 above it:
        // at √(2 · 0.9 / g).
        let first = &run.events[0];
        assert_eq!(first.kind, EventKind::Impact);
        assert_eq!(first.constraint, 0);
        let t_floor = (2.0 * 0.9 / 9.81_f64).sqrt();
        assert!((first.t - t_floor).abs() <= 1e-9 * t_floor, "{}", first.t);
        // At rest in a column on the floor: every contact held, yᵢ = r + 2 r i.
        let all = (1..10).fold(ActiveSet::single(0), |set, i| set.with(i));
        assert_eq!(run.final_mode, Mode::Constrained(all), "{settings}");
        let s = &run.final_state;
        for (i, (y, v)) in s.q.iter().zip(&s.q_dot).enumerate() {
            let rest = 0.1 + 0.2 * i as f64;
            assert!(
                (y - rest).abs() <= 1e-9 && v.abs() <= 1e-9,
                "{settings}: {s:?}"
            );
        }
    }
}
