//! The plots' look: sizes, colours and the formatting of numbers written on them.

use plotters::style::RGBColor;

/// Caption text size (plotters' line height, in pixels).
pub const TITLE_SIZE: u32 = 24;
/// Axis descriptions.
pub const LABEL_SIZE: u32 = 18;
/// Tick labels, legends and notes.
pub const TEXT_SIZE: u32 = 15;

/// Lines of the data.
pub const LINE_WIDTH: u32 = 2;

/// The series' colours, in turn: 20 that tell apart on white (Tableau's palette without its red
/// and pink, kept for marks, then darker and lighter hues), no two closer than 50 in RGB.
pub const PALETTE: [RGBColor; 20] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
    RGBColor(188, 189, 34),
    RGBColor(127, 127, 127),
    RGBColor(0, 0, 128),
    RGBColor(0, 128, 128),
    RGBColor(230, 171, 2),
    RGBColor(0, 80, 40),
    RGBColor(100, 170, 255),
    RGBColor(255, 187, 120),
    RGBColor(152, 223, 138),
    RGBColor(60, 60, 60),
    RGBColor(84, 39, 143),
    RGBColor(128, 0, 0),
    RGBColor(90, 90, 30),
    RGBColor(0, 200, 120),
];

/// Impact marks.
pub const IMPACT: RGBColor = RGBColor(214, 39, 40);
/// Lift-off marks.
pub const LIFTOFF: RGBColor = RGBColor(227, 119, 194);
/// A contact's friction state changing: to stick (filled squares) or to slip (hollow ones).
pub const GRIP: RGBColor = RGBColor(170, 0, 220);
/// The switch to the constrained motion, and a stall.
pub const SWITCH: RGBColor = RGBColor(0, 0, 0);
/// The curves `h = 0`, in turn.
pub const SURFACES: [RGBColor; 3] = [
    RGBColor(160, 160, 160),
    RGBColor(196, 156, 107),
    RGBColor(120, 144, 180),
];
/// The major grid lines.
pub const GRID: RGBColor = RGBColor(222, 222, 222);
/// The minor grid lines.
pub const GRID_MINOR: RGBColor = RGBColor(242, 242, 242);

/// The colour of series `k`.
pub fn color(k: usize) -> RGBColor {
    PALETTE[k % PALETTE.len()]
}

/// `x` with `digits` significant digits, in plain or scientific notation by magnitude.
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i32;
    if (-4..6).contains(&magnitude) {
        let decimals = (digits as i32 - 1 - magnitude).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.prec$e}", prec = digits.saturating_sub(1))
    }
}

/// `x` with 6 significant digits, trailing zeros dropped: times written on the plots.
pub fn short(x: f64) -> String {
    trim(&significant(x, 6))
}

/// A tick label: `x` to 10 significant digits (the ticks' own rounding noise dropped), trailing
/// zeros dropped; scientific notation for very small or large magnitudes.
pub fn tick(x: &f64) -> String {
    trim(&significant(*x, 10))
}

/// `text`'s mantissa without trailing zeros (and without a trailing point).
pub fn trim(text: &str) -> String {
    let (mantissa, exponent) = text.split_at(text.find('e').unwrap_or(text.len()));
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.')
    } else {
        mantissa
    };
    format!("{mantissa}{exponent}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_their_significant_digits() {
        assert_eq!(significant(2.045615054893623, 6), "2.04562");
        assert_eq!(significant(0.6000123, 4), "0.6000");
        assert_eq!(significant(123.456, 4), "123.5");
        assert_eq!(significant(-0.00123456, 3), "-0.00123");
        assert_eq!(significant(1.5e-9, 3), "1.50e-9");
        assert_eq!(significant(0.0, 3), "0");
        assert_eq!(color(0), color(PALETTE.len()));
    }

    /// Regression: the palette had 8 colours, so the 9th series of a model had the 1st one's
    /// colour (the issue saw colours repeat every 10 series). 20 series are told apart: no two
    /// colours, nor a colour and the impact or lift-off marks, are close.
    #[test]
    fn colours_repeated_every_few_series() {
        let distance = |a: RGBColor, b: RGBColor| {
            let d = |x: u8, y: u8| (f64::from(x) - f64::from(y)).powi(2);
            (d(a.0, b.0) + d(a.1, b.1) + d(a.2, b.2)).sqrt()
        };
        for i in 0..20 {
            for j in 0..i {
                let d = distance(color(i), color(j));
                assert!(d >= 45.0, "series {i} and {j}: {d}");
            }
            for mark in [IMPACT, LIFTOFF, GRIP] {
                assert!(distance(color(i), mark) >= 60.0, "series {i}");
            }
        }
    }

    #[test]
    fn ticks_and_times_drop_trailing_zeros() {
        assert_eq!(short(6.0), "6");
        assert_eq!(short(2.045609045904176), "2.04561");
        assert_eq!(tick(&(0.1 + 0.2)), "0.3");
        assert_eq!(tick(&2.5), "2.5");
        assert_eq!(tick(&-4.0), "-4");
        assert_eq!(tick(&1e-5), "1e-5");
        assert_eq!(tick(&0.001), "0.001");
        assert_eq!(tick(&1.5e7), "1.5e7");
        assert_eq!(tick(&0.0), "0");
    }
}
