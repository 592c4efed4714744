//! Numbers as zenosim writes them in text (CSV files, messages): the shortest form that reads
//! back to the same `f64`.

use std::fmt::Write as _;

/// Writes `x` into `buf` (cleared first) in its shortest round-trip form: positional (`0.25`,
/// `-3`) for moderate magnitudes, scientific (`1.5e-17`, `2e20`) for very small or large ones,
/// where positional would spell out dozens of zeros; `NaN`, `inf`, `-inf` for non-finite values.
pub fn format_number(buf: &mut String, x: f64) {
    buf.clear();
    let magnitude = x.abs();
    let positional = x == 0.0 || !x.is_finite() || (1e-5..1e16).contains(&magnitude);
    // Writing to a String cannot fail.
    let _ = if positional {
        write!(buf, "{x}")
    } else {
        write!(buf, "{x:e}")
    };
}

/// `x` as [`format_number`] writes it.
pub fn number(x: f64) -> String {
    let mut buf = String::new();
    format_number(&mut buf, x);
    buf
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip() {
        let mut buf = String::new();
        for x in [
            0.0,
            -0.0,
            1.0,
            -2.5,
            0.1 + 0.2,
            1e-5,
            9.99e-6,
            1.5e-17,
            -3.2e-300,
            f64::MIN_POSITIVE,
            5e-324,
            1e16,
            123456789012345.6,
            f64::MAX,
            std::f64::consts::PI,
        ] {
            format_number(&mut buf, x);
            let back: f64 = buf.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x} -> {buf}");
            assert!(buf.len() <= 24, "{buf}");
        }
        format_number(&mut buf, f64::NAN);
        assert_eq!(buf, "NaN");
        format_number(&mut buf, f64::NEG_INFINITY);
        assert_eq!(buf, "-inf");
    }
}
