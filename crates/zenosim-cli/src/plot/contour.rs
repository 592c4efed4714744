//! The zero set of a function of two variables, as polylines: marching squares on a grid, the
//! crossings placed by linear interpolation along the cell edges, and the segments joined into
//! lines (Lorensen and Cline's marching cubes, in two dimensions).

use std::collections::HashMap;

/// A cell edge: horizontal (from node `(i, j)` to `(i+1, j)`) or vertical (to `(i, j+1)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Edge {
    Horizontal(usize, usize),
    Vertical(usize, usize),
}

/// A grid of `f`'s values at the nodes `(x_i, y_j)`, `i ≤ nx`, `j ≤ ny`.
struct Grid {
    x: (f64, f64),
    y: (f64, f64),
    nx: usize,
    ny: usize,
    values: Vec<f64>,
}

impl Grid {
    fn node(&self, i: usize, j: usize) -> (f64, f64) {
        (
            self.x.0 + (self.x.1 - self.x.0) * i as f64 / self.nx as f64,
            self.y.0 + (self.y.1 - self.y.0) * j as f64 / self.ny as f64,
        )
    }

    fn value(&self, i: usize, j: usize) -> f64 {
        self.values[j * (self.nx + 1) + i]
    }

    fn ends(edge: Edge) -> ((usize, usize), (usize, usize)) {
        match edge {
            Edge::Horizontal(i, j) => ((i, j), (i + 1, j)),
            Edge::Vertical(i, j) => ((i, j), (i, j + 1)),
        }
    }

    /// Whether `f` changes sign along `edge` (a NaN end never does).
    fn crossed(&self, edge: Edge) -> bool {
        let (a, b) = Self::ends(edge);
        let (fa, fb) = (self.value(a.0, a.1), self.value(b.0, b.1));
        !(fa.is_nan() || fb.is_nan()) && (fa < 0.0) != (fb < 0.0)
    }

    /// Where `f` crosses zero along `edge`, by linear interpolation.
    fn crossing(&self, edge: Edge) -> (f64, f64) {
        let (a, b) = Self::ends(edge);
        let (fa, fb) = (self.value(a.0, a.1), self.value(b.0, b.1));
        let s = fa / (fa - fb);
        let (pa, pb) = (self.node(a.0, a.1), self.node(b.0, b.1));
        (pa.0 + s * (pb.0 - pa.0), pa.1 + s * (pb.1 - pa.1))
    }

    /// The segments of cell `(i, j)`, as pairs of edges.
    fn cell(&self, i: usize, j: usize, segments: &mut Vec<[Edge; 2]>) {
        let bottom = Edge::Horizontal(i, j);
        let right = Edge::Vertical(i + 1, j);
        let top = Edge::Horizontal(i, j + 1);
        let left = Edge::Vertical(i, j);
        let crossed: Vec<Edge> = [bottom, right, top, left]
            .into_iter()
            .filter(|&e| self.crossed(e))
            .collect();
        match crossed.len() {
            2 => segments.push([crossed[0], crossed[1]]),
            4 => {
                // A saddle: the centre's sign decides which corners the line cuts off.
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let centre: f64 = corners.iter().map(|&(a, b)| self.value(a, b)).sum();
                if (centre < 0.0) == (self.value(i, j) < 0.0) {
                    segments.extend([[bottom, right], [top, left]]);
                } else {
                    segments.extend([[left, bottom], [right, top]]);
                }
            }
            _ => {}
        }
    }
}

/// The curves where `f(x, y) = 0` in the box `x × y`, from an `nx × ny` grid of cells: each a
/// polyline (closed ones end where they start). Where `f` is NaN nothing is drawn.
pub fn zero_set(
    mut f: impl FnMut(f64, f64) -> f64,
    x: (f64, f64),
    y: (f64, f64),
    nx: usize,
    ny: usize,
) -> Vec<Vec<(f64, f64)>> {
    let (nx, ny) = (nx.max(1), ny.max(1));
    let mut grid = Grid {
        x,
        y,
        nx,
        ny,
        values: Vec::with_capacity((nx + 1) * (ny + 1)),
    };
    for j in 0..=ny {
        for i in 0..=nx {
            let (u, v) = grid.node(i, j);
            grid.values.push(f(u, v));
        }
    }
    let mut segments = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            grid.cell(i, j, &mut segments);
        }
    }
    join(&segments)
        .into_iter()
        .map(|edges| edges.into_iter().map(|e| grid.crossing(e)).collect())
        .collect()
}

/// The segments joined into chains of edges at their shared edges.
fn join(segments: &[[Edge; 2]]) -> Vec<Vec<Edge>> {
    let mut at: HashMap<Edge, Vec<usize>> = HashMap::new();
    for (k, segment) in segments.iter().enumerate() {
        for &edge in segment {
            at.entry(edge).or_default().push(k);
        }
    }
    let mut used = vec![false; segments.len()];
    let mut chains = Vec::new();
    for start in 0..segments.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let mut chain = segments[start].to_vec();
        // Forward from the second end, then backward from the first.
        for _ in 0..2 {
            while let Some(next) = at[chain.last().expect("a chain has two edges")]
                .iter()
                .copied()
                .find(|&k| !used[k])
            {
                used[next] = true;
                let end = *chain.last().expect("a chain has two edges");
                let [a, b] = segments[next];
                chain.push(if a == end { b } else { a });
            }
            chain.reverse();
        }
        chains.push(chain);
    }
    chains
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circle_is_one_closed_line_on_the_circle() {
        let lines = zero_set(
            |x, y| x * x + y * y - 1.0,
            (-2.0, 2.0),
            (-2.0, 2.0),
            100,
            80,
        );
        assert_eq!(lines.len(), 1);
        let line = &lines[0];
        assert_eq!(line.first(), line.last(), "closed");
        assert!(line.len() > 100);
        for &(x, y) in line {
            let r = (x * x + y * y).sqrt();
            // Linear interpolation on cells of 0.04 × 0.05 errs by about h²/8.
            assert!((r - 1.0).abs() < 2e-3, "r = {r}");
        }
    }

    #[test]
    fn a_sine_surface_is_one_open_line_across_the_box() {
        let lines = zero_set(|x, y| y - x.sin(), (0.0, 6.0), (-1.5, 1.5), 120, 60);
        assert_eq!(lines.len(), 1);
        let line = &lines[0];
        let xs: Vec<f64> = line.iter().map(|p| p.0).collect();
        let (low, high) = (xs[0].min(xs[xs.len() - 1]), xs[0].max(xs[xs.len() - 1]));
        assert!(low < 0.06 && high > 5.94, "{low} … {high}");
        for &(x, y) in line {
            assert!((y - x.sin()).abs() < 2e-3, "({x}, {y})");
        }
    }

    #[test]
    fn separate_pieces_are_separate_lines() {
        let two = |x: f64, y: f64| {
            ((x - 1.0).powi(2) + y * y - 0.25) * ((x + 1.0).powi(2) + y * y - 0.25)
        };
        assert_eq!(zero_set(two, (-2.0, 2.0), (-1.0, 1.0), 80, 40).len(), 2);
        // The floor y = −2 and nothing else: a straight line.
        let floor = zero_set(|_, y| y + 2.0, (-3.0, 3.0), (-2.5, 1.0), 10, 7);
        assert_eq!(floor.len(), 1);
        assert!(floor[0].iter().all(|p| (p.1 + 2.0).abs() < 1e-12));
        assert_eq!(floor[0].len(), 11);
    }

    #[test]
    fn no_zero_no_line_and_nan_is_left_out() {
        assert!(zero_set(|x, y| 1.0 + x * x + y * y, (-1.0, 1.0), (-1.0, 1.0), 10, 10).is_empty());
        let half = |x: f64, y: f64| if x < 0.0 { f64::NAN } else { y };
        let lines = zero_set(half, (-1.0, 1.0), (-1.0, 1.0), 20, 20);
        assert_eq!(lines.len(), 1);
        assert!(lines[0].iter().all(|p| p.0 >= 0.0));
    }

    #[test]
    fn saddles_do_not_cross() {
        // x·y = 0 through cell corners and x·y = 0.01 near them: every line is simple.
        for c in [0.0, 0.01, -0.01] {
            let lines = zero_set(|x, y| x * y - c, (-1.0, 1.0), (-1.0, 1.0), 9, 9);
            for line in &lines {
                let mut seen = std::collections::HashSet::new();
                for p in line {
                    assert!(seen.insert((p.0.to_bits(), p.1.to_bits())), "{c}: {p:?}");
                }
            }
            assert!(!lines.is_empty());
        }
    }
}
