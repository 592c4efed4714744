//! The cap on what a command writes (`--max-output`): a number of bytes, written and read as
//! `1GiB`, `100K`, `2G` or plain bytes.

use std::fmt;
use std::str::FromStr;

/// The default cap on a run's `trajectory.csv` and a sweep's file: 1 GiB. It is over 7000 times
/// the largest file a shipped model writes (`models/table.toml`, 132 KB), and holds 5 to 10
/// million rows of a small model (100 to 200 bytes each) or a million of a 20-coordinate one,
/// more than `zenosim plot`, pandas or a spreadsheet read comfortably; while a hostile or
/// mistaken model (a 6.4 KB file wrote 21 GB within the default step limit) stops within
/// seconds instead of filling the disk.
/// (Written as `--help` shows it.)
pub const DEFAULT_MAX_OUTPUT: &str = "1GiB";

/// A number of bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Bytes(pub u64);

/// The units: a suffix (lower case), its multiple. `K`, `KiB`, `M`, ... are powers of 1024,
/// `KB`, `MB`, ... of 1000 (as GNU coreutils read them).
const UNITS: [(&str, u64); 13] = [
    ("", 1),
    ("b", 1),
    ("k", 1 << 10),
    ("kib", 1 << 10),
    ("kb", 1_000),
    ("m", 1 << 20),
    ("mib", 1 << 20),
    ("mb", 1_000_000),
    ("g", 1 << 30),
    ("gib", 1 << 30),
    ("gb", 1_000_000_000),
    ("t", 1 << 40),
    ("tib", 1 << 40),
];

impl FromStr for Bytes {
    type Err = String;

    /// `N` bytes, or `N` and a unit: `K`/`KiB` (1024), `M`/`MiB`, `G`/`GiB`, `T`/`TiB`, or
    /// `KB` (1000), `MB`, `GB`; case aside, and a decimal number (`1.5G`) rounded down.
    fn from_str(text: &str) -> Result<Self, String> {
        let text = text.trim();
        let split = text
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(text.len());
        let (number, unit) = text.split_at(split);
        let bad = || {
            format!(
                "`{text}` is not a size: write bytes, or a number and K, M, G or T (powers of \
                 1024: 100K, 2GiB), or KB, MB, GB (powers of 1000)"
            )
        };
        let unit = unit.trim().to_ascii_lowercase();
        let multiple = UNITS
            .iter()
            .find(|(suffix, _)| *suffix == unit)
            .map(|&(_, multiple)| multiple)
            .ok_or_else(bad)?;
        let bytes = if number.contains('.') {
            let x: f64 = number.parse().map_err(|_| bad())?;
            let bytes = x * multiple as f64;
            if bytes >= u64::MAX as f64 {
                return Err(format!("`{text}` is more bytes than can be counted"));
            }
            bytes.floor() as u64
        } else {
            let n: u64 = number.parse().map_err(|_| bad())?;
            n.checked_mul(multiple)
                .ok_or_else(|| format!("`{text}` is more bytes than can be counted"))?
        };
        if bytes == 0 {
            return Err(format!(
                "`{text}` is no room at all: the cap must be at least 1 byte"
            ));
        }
        Ok(Self(bytes))
    }
}

impl Bytes {
    /// Twice this size (a cap to suggest when this one was reached), at most `u64::MAX`.
    pub fn doubled(self) -> Self {
        Self(self.0.saturating_mul(2))
    }

    /// As a command line writes it: [`Bytes`]'s `Display` without the space (`2GiB`, `1000`).
    pub fn flag(self) -> String {
        self.to_string()
            .replace(" bytes", "")
            .replace(" byte", "")
            .replace(' ', "")
    }
}

impl fmt::Display for Bytes {
    /// In the largest binary unit that divides it exactly (`1 GiB`, `100 KiB`), else in bytes.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.0;
        for (unit, shift) in [("TiB", 40), ("GiB", 30), ("MiB", 20), ("KiB", 10)] {
            if n >= 1 << shift && n.is_multiple_of(1 << shift) {
                return write!(f, "{} {unit}", n >> shift);
            }
        }
        if n == 1 {
            write!(f, "1 byte")
        } else {
            write!(f, "{n} bytes")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_in_bytes_and_units() {
        let read = |text: &str| text.parse::<Bytes>().map(|b| b.0);
        assert_eq!(read("1000"), Ok(1000));
        assert_eq!(read("100K"), Ok(102_400));
        assert_eq!(read("100k"), Ok(102_400));
        assert_eq!(read("100KiB"), Ok(102_400));
        assert_eq!(read("100KB"), Ok(100_000));
        assert_eq!(read("2GiB"), Ok(2 << 30));
        assert_eq!(read("2 G"), Ok(2 << 30));
        assert_eq!(read("3M"), Ok(3 << 20));
        assert_eq!(read("5MB"), Ok(5_000_000));
        assert_eq!(read("1T"), Ok(1 << 40));
        assert_eq!(read("1.5K"), Ok(1536));
        assert_eq!(read("512B"), Ok(512));
        for bad in [
            "",
            "K",
            "-1",
            "0",
            "0K",
            "1e9",
            "1Q",
            "1 KiBs",
            "1..5K",
            "99999999999T",
        ] {
            assert!(read(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn sizes_print_in_the_unit_that_divides_them() {
        assert_eq!(DEFAULT_MAX_OUTPUT.parse(), Ok(Bytes(1 << 30)));
        assert_eq!(Bytes(1 << 30).to_string(), "1 GiB");
        assert_eq!(Bytes(102_400).to_string(), "100 KiB");
        assert_eq!(Bytes(3 << 20).to_string(), "3 MiB");
        assert_eq!(Bytes(100_000).to_string(), "100000 bytes");
        assert_eq!(Bytes(1).to_string(), "1 byte");
        assert_eq!(Bytes(1 << 30).doubled().flag(), "2GiB");
        assert_eq!(Bytes(100_000).flag(), "100000");
        assert_eq!(Bytes(1).flag(), "1");
        for text in ["1 GiB", "100 KiB", "100000 bytes"] {
            let size: Bytes = text.replace(" bytes", "").parse().unwrap();
            assert_eq!(size.to_string(), text);
        }
    }
}
