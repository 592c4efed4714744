//! The first root of a function that starts positive: the landings of the closed forms.

/// The first root after 0 of `f`, which is positive just after 0: bracketed by a scan in steps
/// of `dt`, then bisected to the last bit. Used on closed-form flights, whose roots are the
/// impacts (their first sample must lie inside the flight: `dt` a fraction of its length).
pub(super) fn first_root(f: impl Fn(f64) -> f64, dt: f64) -> f64 {
    let (mut a, mut b) = (0.0, dt);
    while f(b) > 0.0 {
        a = b;
        b += dt;
    }
    loop {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            return m;
        }
        if f(m) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
}

/// Flights summed until the next is below `1e-17` of the time reached: the rest of a
/// geometric tail is then below rounding.
pub(super) fn vanishing(flight_scale: f64, t: f64) -> bool {
    flight_scale < 1e-17 * t
}
