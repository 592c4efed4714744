//! An axis of a sweep: a name and the values it takes.

use std::str::FromStr;

use super::SweepError;

/// The most values an axis takes (80 MB of them): a sweep of more runs is split into shards.
pub const MAX_VALUES: usize = 10_000_000;

/// A parameter or initial value of the model and the values it takes, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    name: String,
    values: Vec<f64>,
}

impl Axis {
    /// `name` taking `values`, at least one, each finite.
    pub fn new(name: impl Into<String>, values: Vec<f64>) -> Result<Self, SweepError> {
        let name = name.into();
        if values.is_empty() {
            return Err(SweepError::EmptyAxis { name });
        }
        if let Some(&value) = values.iter().find(|v| !v.is_finite()) {
            return Err(SweepError::NotFinite { name, value });
        }
        Ok(Self { name, values })
    }

    /// `count` evenly spaced values (at most [`MAX_VALUES`]) from `start` to `stop`, both included (`count = 1`:
    /// `start` alone). The values are those of numpy's `linspace`: `start + i·step` with
    /// `step = (stop − start)/(count − 1)`, the last one `stop` exactly.
    pub fn range(
        name: impl Into<String>,
        start: f64,
        stop: f64,
        count: usize,
    ) -> Result<Self, SweepError> {
        if count > MAX_VALUES {
            return Err(SweepError::TooManyPoints);
        }
        let values = match count {
            0 => Vec::new(),
            1 => vec![start],
            _ => {
                let step = (stop - start) / (count - 1) as f64;
                (0..count)
                    .map(|i| {
                        if i + 1 == count {
                            stop
                        } else {
                            start + i as f64 * step
                        }
                    })
                    .collect()
            }
        };
        Self::new(name, values)
    }

    /// The name varied.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The values it takes, in order.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// How many values it takes.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether it takes none (never, for an axis made by [`Axis::new`]).
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

/// `NAME=START:STOP:COUNT` or `NAME=V1,V2,...`, as `--vary` writes an axis.
impl FromStr for Axis {
    type Err = SweepError;

    fn from_str(spec: &str) -> Result<Self, SweepError> {
        let syntax = |reason: String| SweepError::AxisSyntax {
            spec: spec.to_string(),
            reason,
        };
        let Some((name, values)) = spec.split_once('=') else {
            return Err(syntax("there is no `=`".to_string()));
        };
        let name = name.trim();
        if name.is_empty() {
            return Err(syntax("the name before `=` is missing".to_string()));
        }
        let number = |text: &str| {
            let text = text.trim();
            match text.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                Ok(_) => Err(syntax(format!("`{text}` is not a finite number"))),
                Err(_) if text.is_empty() => Err(syntax("a value is missing".to_string())),
                Err(_) => Err(syntax(format!("`{text}` is not a number"))),
            }
        };
        if values.contains(':') {
            let parts: Vec<&str> = values.split(':').collect();
            let [start, stop, count] = parts[..] else {
                return Err(syntax(format!(
                    "a range has three parts START:STOP:COUNT, not {}",
                    parts.len()
                )));
            };
            let count = match count.trim().parse::<usize>() {
                Ok(n) if (1..=MAX_VALUES).contains(&n) => n,
                _ => {
                    return Err(syntax(format!(
                        "the count `{}` is not a whole number from 1 to {MAX_VALUES}",
                        count.trim()
                    )))
                }
            };
            Self::range(name, number(start)?, number(stop)?, count)
        } else {
            let values = values.split(',').map(number).collect::<Result<_, _>>()?;
            Self::new(name, values)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis(spec: &str) -> Axis {
        spec.parse().unwrap_or_else(|e| panic!("{spec}: {e}"))
    }

    fn error(spec: &str) -> String {
        spec.parse::<Axis>().unwrap_err().to_string()
    }

    #[test]
    fn ranges_include_both_ends() {
        let a = axis("e=0.1:0.9:5");
        assert_eq!(a.name(), "e");
        // i·0.2 + 0.1 in floating point (numpy.linspace computes them the same way), the last
        // one 0.9 exactly.
        assert_eq!(
            a.values(),
            &[0.1, 0.30000000000000004, 0.5, 0.7000000000000001, 0.9]
        );
        assert_eq!(axis("x = 2:3:1").values(), &[2.0]);
        assert_eq!(axis("x=1:-1:3").values(), &[1.0, 0.0, -1.0]);
        let long = axis("y=0:1:1000");
        assert_eq!(long.len(), 1000);
        assert_eq!(long.values()[999], 1.0);
    }

    #[test]
    fn lists_keep_their_order() {
        assert_eq!(axis("x_dot=0.5, -1,2e-3").values(), &[0.5, -1.0, 0.002]);
        assert_eq!(axis("h0=3").values(), &[3.0]);
    }

    #[test]
    fn bad_axes_say_what_is_wrong_and_how_to_write_one() {
        let e = error("e");
        assert!(e.contains("`e`: there is no `=`"), "{e}");
        assert!(e.contains("NAME=START:STOP:COUNT"), "{e}");
        assert!(error("=1,2").contains("the name before `=` is missing"));
        assert!(error("e=0.1,x").contains("`x` is not a number"));
        assert!(error("e=0.1,,2").contains("a value is missing"));
        assert!(error("e=").contains("a value is missing"));
        assert!(error("e=inf").contains("`inf` is not a finite number"));
        assert!(error("e=0:1").contains("three parts START:STOP:COUNT, not 2"));
        assert!(error("e=0:1:0").contains("the count `0` is not a whole number from 1 to"));
        assert!(error("e=0:1:10000001").contains("from 1 to 10000000"));
        assert!(error("e=0:1:2.5").contains("the count `2.5`"));
        assert!(error("e=a:1:3").contains("`a` is not a number"));
        let huge = error("e=-1e308:1e308:3");
        assert!(huge.contains("finite"), "{huge}");
    }
}
