//! What the plots of one run show: its record, its decimated trajectory, the plane chosen for
//! the configuration plot and the curves `h = 0` in it.

use std::path::Path;

use super::chart::drawable;
use super::contour::zero_set;
use super::decimate::Bounds;
use super::record::Record;
use super::trajectory_file::{self, Trajectory};

/// Grid cells across the plane plot's box for the curves `h = 0`.
const CONTOUR_CELLS: (usize, usize) = (300, 200);

/// A run, ready to draw.
pub struct Scene {
    /// `summary.json`.
    pub record: Record,
    /// `trajectory.csv`, decimated.
    pub trajectory: Trajectory,
    /// The columns of `(q, q̇)` on the plane plot's axes.
    pub plane: (usize, usize),
    /// The plane plot's box: the path's, with a margin.
    pub plane_box: Bounds,
    /// The curves `h = 0` of the constraints that depend on the plane's coordinates only.
    pub curves: Vec<Curve>,
    /// The plane plot's scales.
    pub scale: PlaneScale,
}

/// The scales of the configuration plane's axes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum PlaneScale {
    /// A unit as long on both axes when both are coordinates (the plane's true shape).
    #[default]
    Equal,
    /// Each axis fitted to the path.
    Free,
}

/// A constraint's curve `h = 0` in the plane.
pub struct Curve {
    /// The constraint's name.
    pub constraint: String,
    /// Its pieces, as polylines.
    pub lines: Vec<Vec<(f64, f64)>>,
}

impl Scene {
    /// Reads the trajectory at `csv` of the run `record`, for the plane of columns `plane`.
    pub fn load(csv: &Path, record: Record, plane: (usize, usize)) -> anyhow::Result<Self> {
        let trajectory = trajectory_file::read(csv, &record, plane)?;
        let bounds = trajectory.path_bounds.unwrap_or(Bounds {
            x: (-1.0, 1.0),
            y: (-1.0, 1.0),
        });
        let plane_box = Bounds {
            x: pad(bounds.x, 0.05, 0.05),
            y: pad(bounds.y, 0.05, 0.05),
        };
        let curves = curves(&record, plane, plane_box);
        Ok(Self {
            record,
            trajectory,
            plane,
            plane_box,
            curves,
            scale: PlaneScale::default(),
        })
    }

    /// The name of column `k` of `(q, q̇)`.
    pub fn name(&self, k: usize) -> &str {
        self.record.columns().nth(k).map_or("?", String::as_str)
    }
}

/// The columns the plane plot shows when none is chosen: the two coordinates the first
/// constraint that reads exactly two depends on; else the last two coordinates; else (one
/// coordinate) the coordinate and its velocity, a phase plane.
pub fn default_plane(record: &Record) -> (usize, usize) {
    let two = record.constraints.iter().find_map(|name| {
        let h = record.constraint_function(name)?;
        match *h.slots() {
            [a, b] => Some((a, b)),
            _ => None,
        }
    });
    let n = record.coordinates.len();
    two.unwrap_or(if n >= 2 { (n - 2, n - 1) } else { (0, 1) })
}

/// The curves `h = 0` in the plane of columns `plane` over `bounds`, for each constraint whose
/// `h` reads no coordinate but the plane's.
pub fn curves(record: &Record, plane: (usize, usize), bounds: Bounds) -> Vec<Curve> {
    let n = record.coordinates.len();
    record
        .constraints
        .iter()
        .filter_map(|name| {
            let h = record.constraint_function(name)?;
            let on_axes = |slot: &usize| *slot == plane.0 || *slot == plane.1;
            if h.slots().is_empty() || !h.slots().iter().all(on_axes) {
                return None;
            }
            let mut q = vec![0.0; n];
            let lines = zero_set(
                |x, y| {
                    // Velocities (columns n and up) are not arguments of h.
                    if plane.0 < n {
                        q[plane.0] = x;
                    }
                    if plane.1 < n {
                        q[plane.1] = y;
                    }
                    h.eval(&q)
                },
                bounds.x,
                bounds.y,
                CONTOUR_CELLS.0,
                CONTOUR_CELLS.1,
            );
            Some(Curve {
                constraint: name.clone(),
                lines,
            })
        })
        .collect()
}

/// `(low, high)` widened by `below` and `above` of its span (by 1, or a tenth of its size,
/// when it is a single value), and kept [`drawable`]: finite however large its ends.
pub fn pad((low, high): (f64, f64), below: f64, above: f64) -> (f64, f64) {
    // Halves first: the span of ends near ±f64::MAX is finite only so.
    let half_span = high / 2.0 - low / 2.0;
    let (low, high) = if half_span > 0.0 {
        (
            low - 2.0 * below * half_span,
            high + 2.0 * above * half_span,
        )
    } else {
        let half = if low == 0.0 { 1.0 } else { 0.1 * low.abs() };
        (low - half, high + half)
    };
    let range = drawable((low, high));
    (range.start, range.end)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(coordinates: &[&str], h: &[(&str, &str)]) -> Record {
        let names: Vec<&str> = h.iter().map(|(n, _)| *n).collect();
        let json = serde_json::json!({
            "model": "m", "status": "finished", "message": "",
            "coordinates": coordinates,
            "velocities": coordinates.iter().map(|c| format!("{c}_dot")).collect::<Vec<_>>(),
            "constraints": names,
            "h": h.iter().map(|(n, f)| (n.to_string(), f.to_string())).collect::<std::collections::HashMap<_, _>>(),
            "parameters": {"R": 2.0},
            "settings": {"t_end": 1.0}, "final": {"t": 1.0},
            "zeno": [], "events": [], "intervals": [{"start": 0.0}],
            "trajectory": {"rows": 0}
        });
        serde_json::from_value(json).unwrap()
    }

    #[test]
    fn the_default_plane_is_what_the_first_constraint_reads() {
        let ball = record(&["x1", "x2", "x3"], &[("surface", "x3 - sin(x2)")]);
        assert_eq!(default_plane(&ball), (1, 2));
        let cylinder = record(
            &["x", "y"],
            &[("floor", "y + 1"), ("cyl", "sqrt(x^2+y^2) - R")],
        );
        assert_eq!(default_plane(&cylinder), (0, 1));
        let cart = record(&["theta", "x", "z"], &[("c", "cos(theta)")]);
        assert_eq!(default_plane(&cart), (1, 2), "the last two coordinates");
        let ball = record(&["x"], &[("floor", "x")]);
        assert_eq!(default_plane(&ball), (0, 1), "a phase plane");
    }

    #[test]
    fn curves_are_drawn_for_constraints_of_the_planes_coordinates_only() {
        let r = record(
            &["x", "y", "z"],
            &[("cyl", "sqrt(x^2+y^2) - R"), ("wall", "z - x")],
        );
        let bounds = Bounds {
            x: (-3.0, 3.0),
            y: (-3.0, 3.0),
        };
        let c = curves(&r, (0, 1), bounds);
        assert_eq!(c.len(), 1, "the wall reads z");
        assert_eq!(c[0].constraint, "cyl");
        // The circle of radius R = 2, from the summary's parameters.
        for &(x, y) in c[0].lines.iter().flatten() {
            assert!(((x * x + y * y).sqrt() - 2.0).abs() < 1e-2);
        }
        // In the phase plane (x, x_dot) of a ball on a floor, the floor is the line x = 0.
        let ball = record(&["x"], &[("floor", "x")]);
        let c = curves(&ball, (0, 1), bounds);
        assert_eq!(c.len(), 1);
        assert!(c[0].lines.iter().flatten().all(|p| p.0.abs() < 1e-12));
        // No formula in the summary: no curve.
        let mut old = record(&["x", "y"], &[("cyl", "x - y")]);
        old.h.clear();
        assert!(curves(&old, (0, 1), bounds).is_empty());
    }

    #[test]
    fn padding_widens_and_never_collapses() {
        assert_eq!(pad((0.0, 10.0), 0.1, 0.05), (-1.0, 10.5));
        assert_eq!(pad((2.0, 2.0), 0.1, 0.1), (1.8, 2.2));
        assert_eq!(pad((0.0, 0.0), 0.1, 0.1), (-1.0, 1.0));
    }
}
