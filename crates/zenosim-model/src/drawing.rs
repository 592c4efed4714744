//! A model's drawing: named points as formulas of the time, the coordinates and the parameters,
//! and the shapes between them, as the report and the animation draw the mechanism.
//!
//! The `[drawing]` section of a model file is read by the loader (`load/drawing.rs`); this file
//! holds what it becomes and how its points are evaluated.

use crate::expr::Expression;

/// `[drawing]`: the mechanism as drawn by the report and the animation.
///
/// Its points are formulas of the time `t`, the coordinates and the parameters (the parameters
/// folded in at load, after `--set`); [`Drawing::evaluate`] places every point at a time and a
/// configuration, and [`Drawing::shapes`] says what to draw between them.
#[derive(Clone, Debug)]
pub struct Drawing {
    /// The points' names, in the file's order (a surface's sampled curve adds its own points,
    /// named `<constraint>#<k>`).
    names: Vec<String>,
    /// 2 or 3.
    dimension: usize,
    /// The formulas: point `k` reads `formulas[points[k].first..][..dimension]`.
    formulas: Vec<Expression>,
    points: Vec<Point>,
    shapes: Vec<Shape>,
    trace: Option<usize>,
    /// The model's number of coordinates `n`: the formulas read `q` from slots `0..n`, `t` from
    /// slot `2n` and a curve's parameter `s` from slot `2n + 1`.
    coordinates: usize,
}

/// One point of a [`Drawing`]: where its formulas start, and the value of a curve's parameter
/// `s` for the points sampled along a curve (0 for the others, which do not read it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Point {
    pub(crate) first: usize,
    pub(crate) s: f64,
}

/// What a [`Drawing`] draws between its points.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A segment between two points (indices into `points()`).
    Segment {
        /// The first point.
        from: usize,
        /// The second point.
        to: usize,
    },
    /// A polyline through points; `closed` joins the last to the first.
    Polyline {
        /// The points, in order.
        points: Vec<usize>,
        /// Whether the last point is joined to the first.
        closed: bool,
    },
    /// A circle of a radius (evaluated at load, from the parameters) centred at a point.
    Circle {
        /// The centre.
        center: usize,
        /// The radius, > 0, in the drawing's units.
        radius: f64,
    },
    /// A constraint's surface `h = 0`, drawn as a polyline through points; highlighted while
    /// the constraint is held.
    Surface {
        /// The constraint's index in the model.
        constraint: usize,
        /// The points, in order.
        points: Vec<usize>,
    },
}

/// Why a [`Drawing`] could not be evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DrawingError {
    /// A point's formula is not finite (NaN or infinite) there.
    #[error(
        "the drawing's point `{point}` has coordinate {axis} = {value} at t = {t} (not finite)"
    )]
    NotFinite {
        /// The point's name.
        point: String,
        /// Which of its coordinates (0 for x, 1 for y, 2 for z).
        axis: usize,
        /// The value.
        value: f64,
        /// The time.
        t: f64,
    },
    /// `q` or `out` has the wrong length.
    #[error("the drawing needs {expected} {what}, got {got}")]
    Length {
        /// `"coordinates"` or `"output values"`.
        what: &'static str,
        /// How many it needs.
        expected: usize,
        /// How many it was given.
        got: usize,
    },
}

impl Drawing {
    /// A drawing of these parts, checked by the loader.
    pub(crate) fn new(
        names: Vec<String>,
        dimension: usize,
        formulas: Vec<Expression>,
        points: Vec<Point>,
        shapes: Vec<Shape>,
        trace: Option<usize>,
        coordinates: usize,
    ) -> Self {
        debug_assert_eq!(names.len(), points.len());
        debug_assert!(points.iter().all(|p| p.first + dimension <= formulas.len()));
        Self {
            names,
            dimension,
            formulas,
            points,
            shapes,
            trace,
            coordinates,
        }
    }

    /// The points' names, in the file's order.
    pub fn points(&self) -> &[String] {
        &self.names
    }

    /// 2 for points given as pairs, 3 for triples.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    /// The shapes, in the file's order (drawn in that order, the later ones on top).
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// The point whose path is traced by default, if the file names one (`trace = "…"`).
    pub fn trace(&self) -> Option<usize> {
        self.trace
    }

    /// The index of the point named `name`.
    pub fn point(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// Whether some point moves with the time `t` itself (not only through the coordinates).
    pub fn reads_time(&self) -> bool {
        let t = 2 * self.coordinates;
        self.formulas.iter().any(|f| f.reads(t))
    }

    /// The operations of one evaluation of every point: what the loader counts against
    /// `Limits::max_operations`.
    pub fn operations(&self) -> usize {
        self.points
            .iter()
            .map(|p| {
                self.formulas[p.first..p.first + self.dimension]
                    .iter()
                    .map(Expression::operations)
                    .sum::<usize>()
            })
            .sum()
    }

    /// Point `k`'s position at time `t` and coordinates `q`, into `out[..dimension]`: what
    /// [`Drawing::evaluate`] gives it, at the cost of that point alone (a trace followed at
    /// every row of a trajectory).
    ///
    /// # Panics
    ///
    /// If `k` is not a point's index.
    pub fn evaluate_point(
        &self,
        k: usize,
        t: f64,
        q: &[f64],
        out: &mut [f64],
    ) -> Result<(), DrawingError> {
        let n = self.coordinates;
        if q.len() != n {
            return Err(DrawingError::Length {
                what: "coordinates",
                expected: n,
                got: q.len(),
            });
        }
        if out.len() < self.dimension {
            return Err(DrawingError::Length {
                what: "output values",
                expected: self.dimension,
                got: out.len(),
            });
        }
        let point = self.points[k];
        let mut vars = vec![0.0; 2 * n + 2];
        vars[..n].copy_from_slice(q);
        vars[2 * n] = t;
        vars[2 * n + 1] = point.s;
        let formulas = &self.formulas[point.first..point.first + self.dimension];
        for (j, (formula, slot)) in formulas.iter().zip(out.iter_mut()).enumerate() {
            let value: f64 = formula.eval(&vars);
            if !value.is_finite() {
                return Err(DrawingError::NotFinite {
                    point: self.names[k].clone(),
                    axis: j,
                    value,
                    t,
                });
            }
            *slot = value;
        }
        Ok(())
    }

    /// Every point's position at time t and coordinates q: out[k * dimension + j]; an error
    /// (not a panic) where a formula is not finite, or where `q` or `out` has the wrong length.
    pub fn evaluate(&self, t: f64, q: &[f64], out: &mut [f64]) -> Result<(), DrawingError> {
        let n = self.coordinates;
        if q.len() != n {
            return Err(DrawingError::Length {
                what: "coordinates",
                expected: n,
                got: q.len(),
            });
        }
        let needed = self.names.len() * self.dimension;
        if out.len() < needed {
            return Err(DrawingError::Length {
                what: "output values",
                expected: needed,
                got: out.len(),
            });
        }
        // The slots: q (0..n), the velocities (n..2n, never read), t (2n), s (2n + 1).
        let mut vars = vec![0.0; 2 * n + 2];
        vars[..n].copy_from_slice(q);
        vars[2 * n] = t;
        for (k, point) in self.points.iter().enumerate() {
            vars[2 * n + 1] = point.s;
            for j in 0..self.dimension {
                let value: f64 = self.formulas[point.first + j].eval(&vars);
                if !value.is_finite() {
                    return Err(DrawingError::NotFinite {
                        point: self.names[k].clone(),
                        axis: j,
                        value,
                        t,
                    });
                }
                out[k * self.dimension + j] = value;
            }
        }
        Ok(())
    }
}
