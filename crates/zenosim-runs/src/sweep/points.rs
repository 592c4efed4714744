//! The points of a sweep: its axes combined as a Cartesian product or zipped.

use super::{Axis, SweepError};

/// How the axes combine into points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Combine {
    /// Every combination of the axes' values, the first axis varying slowest (as nested loops
    /// in the order the axes are given).
    #[default]
    Product,
    /// The i-th values of all the axes together (all of the same length).
    Zip,
}

/// The points of a sweep, numbered from 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Points {
    axes: Vec<Axis>,
    combine: Combine,
    len: usize,
}

impl Points {
    /// The points of `axes` (at least one, each name once) combined by `combine`.
    pub fn new(axes: Vec<Axis>, combine: Combine) -> Result<Self, SweepError> {
        if axes.is_empty() {
            return Err(SweepError::NoAxes);
        }
        for (i, axis) in axes.iter().enumerate() {
            if axes[..i].iter().any(|a| a.name() == axis.name()) {
                return Err(SweepError::Duplicate {
                    name: axis.name().to_string(),
                });
            }
        }
        let len = match combine {
            Combine::Product => axes
                .iter()
                .try_fold(1usize, |n, a| n.checked_mul(a.len()))
                .ok_or(SweepError::TooManyPoints)?,
            Combine::Zip => {
                let len = axes[0].len();
                if axes.iter().any(|a| a.len() != len) {
                    let lengths = axes
                        .iter()
                        .map(|a| format!("{} has {}", a.name(), a.len()))
                        .collect::<Vec<_>>()
                        .join(", ");
                    return Err(SweepError::ZipLengths { lengths });
                }
                len
            }
        };
        Ok(Self { axes, combine, len })
    }

    /// The axes, in order.
    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    /// How they combine.
    pub fn combine(&self) -> Combine {
        self.combine
    }

    /// The axes' names, in order.
    pub fn names(&self) -> Vec<&str> {
        self.axes.iter().map(Axis::name).collect()
    }

    /// How many points there are.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are none (never: every axis has a value).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The values of point `index` (< [`Points::len`]), one per axis in order.
    pub fn point(&self, index: usize) -> Vec<f64> {
        match self.combine {
            Combine::Zip => self.axes.iter().map(|a| a.values()[index]).collect(),
            Combine::Product => {
                let mut values = vec![0.0; self.axes.len()];
                let mut rest = index;
                for (value, axis) in values.iter_mut().zip(&self.axes).rev() {
                    *value = axis.values()[rest % axis.len()];
                    rest /= axis.len();
                }
                values
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis(name: &str, values: &[f64]) -> Axis {
        Axis::new(name, values.to_vec()).unwrap()
    }

    #[test]
    fn a_product_varies_the_first_axis_slowest() {
        let points = Points::new(
            vec![axis("a", &[1.0, 2.0]), axis("b", &[10.0, 20.0, 30.0])],
            Combine::Product,
        )
        .unwrap();
        assert_eq!(points.len(), 6);
        let all: Vec<_> = (0..6).map(|i| points.point(i)).collect();
        let mut nested = Vec::new();
        for a in [1.0, 2.0] {
            for b in [10.0, 20.0, 30.0] {
                nested.push(vec![a, b]);
            }
        }
        assert_eq!(all, nested);
    }

    #[test]
    fn zipped_axes_go_together() {
        let points = Points::new(
            vec![axis("a", &[1.0, 2.0, 3.0]), axis("b", &[4.0, 5.0, 6.0])],
            Combine::Zip,
        )
        .unwrap();
        assert_eq!(points.len(), 3);
        assert_eq!(points.point(1), vec![2.0, 5.0]);
        let error = Points::new(
            vec![axis("a", &[1.0, 2.0]), axis("b", &[4.0, 5.0, 6.0])],
            Combine::Zip,
        )
        .unwrap_err()
        .to_string();
        assert!(error.contains("a has 2, b has 3"), "{error}");
    }

    #[test]
    fn axes_are_checked() {
        let no_axes = Points::new(vec![], Combine::Product).unwrap_err();
        assert!(matches!(no_axes, SweepError::NoAxes));
        let twice = Points::new(vec![axis("a", &[1.0]), axis("a", &[2.0])], Combine::Zip);
        assert!(twice
            .unwrap_err()
            .to_string()
            .contains("`a` is varied twice"));
        // 257^8 ≈ 1.9e19 points: more than a 64-bit count holds.
        let axes = (0..8)
            .map(|i| Axis::range(format!("a{i}"), 0.0, 1.0, 257).unwrap())
            .collect();
        let huge = Points::new(axes, Combine::Product);
        assert!(matches!(huge, Err(SweepError::TooManyPoints)));
    }
}
