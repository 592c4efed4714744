//! A shard: the K-th of N interleaved parts of a sweep, for one job of a cluster's array.

use std::fmt;
use std::str::FromStr;

use super::SweepError;

/// The points `i` with `i % count == number − 1`: interleaved, so that every shard takes a
/// similar share of cheap and costly points.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Shard {
    number: usize,
    count: usize,
}

impl Shard {
    /// The whole sweep, `1/1`.
    pub const WHOLE: Shard = Shard {
        number: 1,
        count: 1,
    };

    /// The `number`-th (from 1) of `count` shards.
    pub fn new(number: usize, count: usize) -> Result<Self, SweepError> {
        if count == 0 || number == 0 || number > count {
            return Err(SweepError::Shard {
                spec: format!("{number}/{count}"),
                reason: if count == 0 {
                    "there must be at least one shard".to_string()
                } else {
                    format!("K must be between 1 and {count}")
                },
            });
        }
        Ok(Self { number, count })
    }

    /// K, from 1.
    pub fn number(self) -> usize {
        self.number
    }

    /// N.
    pub fn count(self) -> usize {
        self.count
    }

    /// Whether point `index` belongs to this shard.
    pub fn contains(self, index: usize) -> bool {
        index % self.count == self.number - 1
    }

    /// The indices of this shard's points among `len` points, in order.
    pub fn indices(self, len: usize) -> impl Iterator<Item = usize> + Clone {
        (self.number - 1..len).step_by(self.count)
    }

    /// How many of `len` points belong to this shard.
    pub fn len_of(self, len: usize) -> usize {
        len.saturating_sub(self.number - 1).div_ceil(self.count)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.number, self.count)
    }
}

/// `K/N`.
impl FromStr for Shard {
    type Err = SweepError;

    fn from_str(spec: &str) -> Result<Self, SweepError> {
        let bad = |reason: &str| SweepError::Shard {
            spec: spec.to_string(),
            reason: reason.to_string(),
        };
        let (k, n) = spec.split_once('/').ok_or_else(|| bad("there is no `/`"))?;
        let whole = |text: &str| {
            text.trim()
                .parse::<usize>()
                .map_err(|_| bad(&format!("`{}` is not a whole number", text.trim())))
        };
        let (k, n) = (whole(k)?, whole(n)?);
        Self::new(k, n).map_err(|_| {
            bad(if n == 0 {
                "there must be at least one shard"
            } else {
                "K must be between 1 and N"
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_interleave_and_cover_the_points_once() {
        let len = 10;
        let shards: Vec<Shard> = (1..=3).map(|k| Shard::new(k, 3).unwrap()).collect();
        assert_eq!(shards[0].indices(len).collect::<Vec<_>>(), [0, 3, 6, 9]);
        assert_eq!(shards[1].indices(len).collect::<Vec<_>>(), [1, 4, 7]);
        assert_eq!(shards[2].indices(len).collect::<Vec<_>>(), [2, 5, 8]);
        for i in 0..len {
            assert_eq!(shards.iter().filter(|s| s.contains(i)).count(), 1);
        }
        for s in &shards {
            assert_eq!(s.len_of(len), s.indices(len).count());
            assert!(s.indices(len).all(|i| s.contains(i)));
        }
        // More shards than points: the last ones are empty.
        let s = Shard::new(5, 5).unwrap();
        assert_eq!((s.len_of(3), s.indices(3).count()), (0, 0));
        assert_eq!(Shard::WHOLE.indices(4).collect::<Vec<_>>(), [0, 1, 2, 3]);
    }

    #[test]
    fn shards_read_and_write_as_k_over_n() {
        let s: Shard = " 2 / 3".parse().unwrap();
        assert_eq!((s.number(), s.count()), (2, 3));
        assert_eq!(s.to_string(), "2/3");
        for (spec, reason) in [
            ("2", "there is no `/`"),
            ("0/3", "K must be between 1 and N"),
            ("4/3", "K must be between 1 and N"),
            ("1/0", "at least one shard"),
            ("a/3", "`a` is not a whole number"),
            ("-1/3", "`-1` is not a whole number"),
        ] {
            let e = spec.parse::<Shard>().unwrap_err().to_string();
            assert!(e.contains(reason), "{spec}: {e}");
            assert!(e.contains("K/N"), "{e}");
        }
    }
}
