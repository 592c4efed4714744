//! Models with several constraints, one contact at a time.

use zenosim::{
    Constraint, Error, EventKind, HybridLagrangian, Mode, Outcome, Scalar, Simulation,
    SimulationOptions, Trajectory,
};

/// A point in the box `0 ≤ x ≤ width`, `y ≥ 0` under gravity `g` (pointing to −y):
/// constraints `left: x`, `right: width − x`, `floor: y`.
struct Box2d {
    width: f64,
    gravity: f64,
    constraints: Vec<Constraint>,
}

impl Box2d {
    fn new(width: f64, gravity: f64, e_walls: f64, e_floor: f64) -> Self {
        Self {
            width,
            gravity,
            constraints: vec![
                Constraint::new("left", e_walls),
                Constraint::new("right", e_walls),
                Constraint::new("floor", e_floor),
            ],
        }
    }
}

impl HybridLagrangian for Box2d {
    const DIMENSION: Option<usize> = Some(2);
    fn dimension(&self) -> usize {
        2
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * self.gravity
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, index: usize, q: &[D]) -> D {
        match index {
            0 => q[0],
            1 => -q[0] + self.width,
            _ => q[1],
        }
    }
}

#[test]
fn a_particle_between_two_walls_bounces_at_the_closed_form_times() {
    // No gravity, e = 0.5 at both walls: from x = 0.25 at speed 1, impacts at 0.75 (right),
    // then each crossing of the unit gap takes 1/speed with the speed halved at each wall.
    let model = Box2d::new(1.0, 0.0, 0.5, 0.5);
    let options = SimulationOptions {
        t_end: 20.0,
        ..Default::default()
    };
    let run = Simulation::new(&model, &[0.25, 1.0], &[1.0, 0.0], options)
        .unwrap()
        .run(&mut ());
    assert_eq!(run.outcome, Outcome::Finished);
    let expected = [(1, 0.75), (0, 2.75), (1, 6.75), (0, 14.75)];
    assert_eq!(run.events.len(), expected.len());
    for (event, (wall, t)) in run.events.iter().zip(expected) {
        assert_eq!(event.kind, EventKind::Impact);
        assert_eq!(event.constraint, wall);
        assert!((event.t - t).abs() < 1e-12, "{} vs {t}", event.t);
        assert!((event.after.q_dot[0] + 0.5 * event.before.q_dot[0]).abs() < 1e-14);
    }
    assert!(run.zeno.is_empty());
}

#[test]
fn wall_impacts_between_floor_bounces_and_a_zeno_point_on_the_floor() {
    // Thrown sideways in a narrow box: the walls are hit in flight several times while the
    // floor bounces die out; the floor's Zeno point is reached and the particle then slides.
    let model = Box2d::new(0.3, 9.81, 0.9, 0.5);
    let options = SimulationOptions {
        t_end: 1.6,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&model, &[0.1, 1.0], &[1.0, 0.0], options)
        .unwrap()
        .run(&mut trajectory);
    let walls = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Impact && e.constraint < 2)
        .count();
    assert!(walls >= 3, "{walls} wall impacts");
    assert_eq!(run.zeno.len(), 1);
    assert_eq!(run.zeno[0].constraint, 2);
    for e in run.events.iter().filter(|e| e.kind == EventKind::Impact) {
        let (vx, vy) = (e.before.q_dot[0], e.before.q_dot[1]);
        let (wx, wy) = (e.after.q_dot[0], e.after.q_dot[1]);
        if e.constraint == 2 {
            // The floor reverses ẏ by e and leaves ẋ alone.
            assert!((wy + 0.5 * vy).abs() < 1e-12 && (wx - vx).abs() < 1e-15);
        } else {
            assert!((wx + 0.9 * vx).abs() < 1e-12 && (wy - vy).abs() < 1e-15);
        }
    }
    for p in &trajectory.points {
        assert!(p.h.iter().all(|&h| h >= -1e-9), "{p:?}");
    }
    // It slides on the floor after the Zeno point, and reaches no wall before t_end.
    assert_eq!(run.outcome, Outcome::Finished);
}

#[test]
fn a_wall_reached_while_sliding_on_the_floor_stops_with_a_clear_error() {
    // Sliding on the floor (reached at once: dropped from rest at y = 0 it chatters) toward
    // the right wall at speed 0.5: contact with both at t = 1.6. Simultaneous contacts are not
    // supported yet, so the run stops there, keeping everything before it.
    let model = Box2d::new(1.0, 9.81, 0.9, 0.5);
    let options = SimulationOptions {
        t_end: 5.0,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&model, &[0.2, 0.0], &[0.5, 0.0], options)
        .unwrap()
        .run(&mut trajectory);
    let Outcome::Failed(error) = &run.outcome else {
        panic!("expected a failure, got {:?}", run.outcome);
    };
    let Error::SimultaneousContact { t, first, second } = error else {
        panic!("{error:?}");
    };
    assert_eq!((first.as_str(), second.as_str()), ("floor", "right"));
    assert!((t - 1.6).abs() < 1e-9, "{t}");
    let message = error.to_string();
    assert!(
        message.contains("'floor'")
            && message.contains("'right'")
            && message.contains("not supported")
    );
    // Everything up to the contact is kept, on the floor, and the last sample is the contact.
    assert_eq!(run.t_final, *t);
    assert!(matches!(run.final_mode, Mode::Constrained(_)));
    let last = trajectory.points.last().unwrap();
    assert_eq!(last.t, *t);
    assert!(
        (last.q[0] - 1.0).abs() < 1e-9 && last.q[1].abs() < 1e-12,
        "{last:?}"
    );
}
