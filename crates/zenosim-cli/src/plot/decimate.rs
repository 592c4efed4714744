//! Decimation for drawing: a run of 10⁶ rows becomes a few thousand points per line that draw
//! the same picture, computed as the rows stream past (memory does not grow with the run).
//!
//! - Time series: the time axis is cut into columns finer than a pixel; each column keeps, per
//!   series, its first and last points and its lowest and highest, in their order. The line
//!   through them covers the same pixels as the line through every point.
//! - Paths in a plane: a point is kept when it leaves the cell (finer than a pixel) of the last
//!   point kept.

/// A point of a time series, with its row number to keep the order of points at equal `t` (the
/// two rows of an event).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Sample {
    row: u64,
    t: f64,
    y: f64,
}

/// What a column keeps of one series.
#[derive(Clone, Copy, Debug)]
struct Column {
    first: Sample,
    last: Sample,
    low: Sample,
    high: Sample,
}

impl Column {
    fn new(s: Sample) -> Self {
        Self {
            first: s,
            last: s,
            low: s,
            high: s,
        }
    }

    fn add(&mut self, s: Sample) {
        self.last = s;
        if s.y < self.low.y {
            self.low = s;
        }
        if s.y > self.high.y {
            self.high = s;
        }
    }
}

/// Several time series sampled at the same times, decimated column by column over
/// `[t_start, t_end]` (times outside go to the first or last column).
pub struct TimeDecimator {
    t_start: f64,
    scale: f64,
    columns: usize,
    series: usize,
    /// `columns × series`, column-major: the series of column 0, then of column 1, …
    kept: Vec<Option<Column>>,
    rows: u64,
}

impl TimeDecimator {
    /// `series` series over `[t_start, t_end]` in `columns` columns.
    pub fn new(series: usize, t_start: f64, t_end: f64, columns: usize) -> Self {
        let columns = columns.max(1);
        let span = t_end - t_start;
        let scale = if span > 0.0 && span.is_finite() {
            columns as f64 / span
        } else {
            0.0
        };
        Self {
            t_start,
            scale,
            columns,
            series,
            kept: vec![None; columns * series],
            rows: 0,
        }
    }

    /// Adds a row: `values[s]` is series `s` at `t`. Non-finite values are left out.
    pub fn push(&mut self, t: f64, values: &[f64]) {
        let row = self.rows;
        self.rows += 1;
        if !t.is_finite() {
            return;
        }
        let column = ((t - self.t_start) * self.scale).clamp(0.0, (self.columns - 1) as f64);
        let base = column as usize * self.series;
        for (slot, &y) in self.kept[base..base + self.series].iter_mut().zip(values) {
            if !y.is_finite() {
                continue;
            }
            let s = Sample { row, t, y };
            match slot {
                Some(column) => column.add(s),
                None => *slot = Some(Column::new(s)),
            }
        }
    }

    /// Series `s` decimated: `(t, y)` in the order of the rows.
    pub fn series(&self, s: usize) -> Vec<(f64, f64)> {
        let mut points = Vec::new();
        for column in self.kept.iter().skip(s).step_by(self.series).flatten() {
            let mut four = [column.first, column.low, column.high, column.last];
            four.sort_by_key(|p| p.row);
            let mut previous = None;
            for p in four {
                if previous != Some(p.row) {
                    points.push((p.t, p.y));
                    previous = Some(p.row);
                }
            }
        }
        points
    }

    /// The least and greatest finite values of series `s`, if it has any.
    pub fn range(&self, s: usize) -> Option<(f64, f64)> {
        self.kept
            .iter()
            .skip(s)
            .step_by(self.series)
            .flatten()
            .fold(None, |range, c| {
                let (low, high) = range.unwrap_or((c.low.y, c.high.y));
                Some((low.min(c.low.y), high.max(c.high.y)))
            })
    }
}

/// A path in a plane, thinned to one point per cell of a grid `cells × cells` over its bounding
/// box, as it grows.
pub struct PathDecimator {
    points: Vec<(f64, f64)>,
    cells: f64,
    /// The length at which the kept points are thinned next.
    limit: usize,
    bounds: Option<Bounds>,
}

/// A bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// The least and greatest `x`.
    pub x: (f64, f64),
    /// The least and greatest `y`.
    pub y: (f64, f64),
}

impl Bounds {
    fn of(x: f64, y: f64) -> Self {
        Self {
            x: (x, x),
            y: (y, y),
        }
    }

    fn add(&mut self, x: f64, y: f64) {
        self.x = (self.x.0.min(x), self.x.1.max(x));
        self.y = (self.y.0.min(y), self.y.1.max(y));
    }
}

/// Points kept before the first thinning: a path of up to this many points is drawn whole.
const FIRST_LIMIT: usize = 1 << 16;

impl PathDecimator {
    /// A path thinned to cells of `1/cells` of its bounding box in each direction.
    pub fn new(cells: usize) -> Self {
        Self {
            points: Vec::new(),
            cells: cells.max(1) as f64,
            limit: FIRST_LIMIT,
            bounds: None,
        }
    }

    /// Adds the next point; non-finite points are left out.
    pub fn push(&mut self, x: f64, y: f64) {
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        match &mut self.bounds {
            Some(bounds) => bounds.add(x, y),
            None => self.bounds = Some(Bounds::of(x, y)),
        }
        self.points.push((x, y));
        if self.points.len() >= self.limit {
            self.thin();
            // Thinning again only once the path has doubled keeps the work linear.
            self.limit = self.limit.max(2 * self.points.len());
        }
    }

    /// The bounding box of every point pushed, if any was finite.
    pub fn bounds(&self) -> Option<Bounds> {
        self.bounds
    }

    /// The thinned path.
    pub fn finish(mut self) -> Vec<(f64, f64)> {
        self.thin();
        self.points
    }

    /// Keeps the points that leave the cell of the previous point kept, and the last one. The
    /// cells are those of the bounding box so far, finer than (or as fine as) those of the
    /// final one, so an earlier thinning never loses what a later one would keep.
    fn thin(&mut self) {
        let (Some(bounds), Some(&last)) = (self.bounds, self.points.last()) else {
            return;
        };
        let size = |(low, high): (f64, f64)| {
            let span = high - low;
            if span > 0.0 {
                self.cells / span
            } else {
                0.0
            }
        };
        let (sx, sy) = (size(bounds.x), size(bounds.y));
        let cell = |(x, y): (f64, f64)| {
            (
                ((x - bounds.x.0) * sx).floor() as i64,
                ((y - bounds.y.0) * sy).floor() as i64,
            )
        };
        let mut current = None;
        self.points.retain(|&p| {
            let c = cell(p);
            let keep = current != Some(c);
            current = Some(c);
            keep
        });
        if self.points.last() != Some(&last) {
            self.points.push(last);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn few_points_are_kept_as_they_are() {
        let mut d = TimeDecimator::new(2, 0.0, 1.0, 100);
        let rows = [(0.0, [1.0, 5.0]), (0.5, [2.0, 4.0]), (1.0, [3.0, 3.0])];
        for (t, v) in rows {
            d.push(t, &v);
        }
        assert_eq!(d.series(0), [(0.0, 1.0), (0.5, 2.0), (1.0, 3.0)]);
        assert_eq!(d.series(1), [(0.0, 5.0), (0.5, 4.0), (1.0, 3.0)]);
        assert_eq!(d.range(1), Some((3.0, 5.0)));
    }

    #[test]
    fn a_column_keeps_its_first_last_and_extremes_in_order() {
        let mut d = TimeDecimator::new(1, 0.0, 1.0, 1);
        for (k, y) in [0.0, 3.0, -1.0, 2.0, -4.0, 7.0, 1.0]
            .into_iter()
            .enumerate()
        {
            d.push(k as f64 / 10.0, &[y]);
        }
        // First 0, low −4 (row 4), high 7 (row 5), last 1.
        assert_eq!(
            d.series(0),
            [(0.0, 0.0), (0.4, -4.0), (0.5, 7.0), (0.6, 1.0)]
        );
        assert_eq!(d.range(0), Some((-4.0, 7.0)));
    }

    #[test]
    fn an_events_two_rows_at_the_same_time_stay_in_order() {
        // A velocity jump: the row before (−2) then the row after (+1) at t = 0.5.
        let mut d = TimeDecimator::new(1, 0.0, 1.0, 4);
        for (t, y) in [(0.4, -1.9), (0.5, -2.0), (0.5, 1.0), (0.6, 0.9)] {
            d.push(t, &[y]);
        }
        let points = d.series(0);
        let jump = points.iter().position(|&p| p == (0.5, -2.0)).unwrap();
        assert_eq!(points[jump + 1], (0.5, 1.0));
    }

    #[test]
    fn a_million_points_decimate_to_the_same_envelope() {
        let columns = 1000;
        let mut d = TimeDecimator::new(1, 0.0, 1.0, columns);
        let n = 1_000_000;
        let f = |t: f64| (40.0 * t).sin() + 0.3 * (900.0 * t).cos();
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..=n {
            let t = k as f64 / n as f64;
            d.push(t, &[f(t)]);
            low = low.min(f(t));
            high = high.max(f(t));
        }
        let points = d.series(0);
        assert!(points.len() <= 4 * columns, "{}", points.len());
        assert!(points.len() >= 2 * columns);
        assert_eq!(points.first(), Some(&(0.0, f(0.0))));
        assert_eq!(points.last(), Some(&(1.0, f(1.0))));
        assert_eq!(d.range(0), Some((low, high)));
        assert!(points.windows(2).all(|w| w[0].0 <= w[1].0));
        // Every column's extremes are among the points.
        for c in [0, 317, 999] {
            let inside = |t: f64| (t * columns as f64).floor() as usize == c;
            let kept_high = points
                .iter()
                .filter(|p| inside(p.0))
                .map(|p| p.1)
                .fold(f64::NEG_INFINITY, f64::max);
            let true_high = (0..=n)
                .map(|k| k as f64 / n as f64)
                .filter(|&t| inside(t))
                .map(f)
                .fold(f64::NEG_INFINITY, f64::max);
            assert_eq!(kept_high, true_high, "column {c}");
        }
    }

    #[test]
    fn non_finite_values_are_left_out() {
        let mut d = TimeDecimator::new(2, 0.0, 1.0, 10);
        d.push(0.0, &[f64::NAN, 1.0]);
        d.push(f64::NAN, &[1.0, 1.0]);
        d.push(1.0, &[2.0, f64::INFINITY]);
        assert_eq!(d.series(0), [(1.0, 2.0)]);
        assert_eq!(d.series(1), [(0.0, 1.0)]);
        assert_eq!(TimeDecimator::new(1, 0.0, 1.0, 10).range(0), None);
    }

    #[test]
    fn a_zero_length_run_is_one_column() {
        let mut d = TimeDecimator::new(1, 2.0, 2.0, 10);
        d.push(2.0, &[1.0]);
        d.push(2.0, &[3.0]);
        assert_eq!(d.series(0), [(2.0, 1.0), (2.0, 3.0)]);
    }

    #[test]
    fn a_path_keeps_one_point_per_cell_and_its_ends() {
        let mut d = PathDecimator::new(10);
        // A circle walked 100 times over, 10⁶ points: thinned to cells of a tenth of its box.
        let n = 1_000_000;
        for k in 0..n {
            let a = k as f64 * 2e-4 * std::f64::consts::PI;
            d.push(a.cos(), a.sin());
        }
        d.push(f64::NAN, 0.0);
        let bounds = d.bounds().unwrap();
        assert!((bounds.x.0 + 1.0).abs() < 1e-9 && (bounds.x.1 - 1.0).abs() < 1e-12);
        let points = d.finish();
        // The circle crosses at most ~40 of the 10 × 10 cells per turn.
        assert!(points.len() < 100 * 40 + 2, "{}", points.len());
        assert!(points.len() > 100 * 20, "{}", points.len());
        assert_eq!(points[0], (1.0, 0.0));
        let a = (n - 1) as f64 * 2e-4 * std::f64::consts::PI;
        assert_eq!(*points.last().unwrap(), (a.cos(), a.sin()));
        // No two consecutive points share a cell.
        let cell = |(x, y): (f64, f64)| {
            (
                ((x - bounds.x.0) * 10.0 / (bounds.x.1 - bounds.x.0)).floor(),
                ((y - bounds.y.0) * 10.0 / (bounds.y.1 - bounds.y.0)).floor(),
            )
        };
        assert!(points[..points.len() - 1]
            .windows(2)
            .all(|w| cell(w[0]) != cell(w[1])));
    }

    #[test]
    fn a_short_path_is_kept_whole_until_finished() {
        let mut d = PathDecimator::new(1000);
        for (x, y) in [(0.0, 0.0), (1.0, 2.0), (0.5, 0.5)] {
            d.push(x, y);
        }
        assert_eq!(d.finish(), [(0.0, 0.0), (1.0, 2.0), (0.5, 0.5)]);
        assert_eq!(PathDecimator::new(10).finish(), []);
    }
}
