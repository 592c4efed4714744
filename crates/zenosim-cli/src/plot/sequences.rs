//! The impact sequences of a run and their flight times, for the Zeno diagnostic: one sequence
//! per Zeno point (over all of its constraints, where it has several); a run without one has a
//! sequence per run of three impacts or more on one constraint (ended by a lift-off, an impact
//! on another constraint or the run's end).

use super::record::{Record, ZenoRecord};

/// The impacts of one sequence on one constraint, and the Zeno point it reached, if any.
#[derive(Debug)]
pub struct Sequence<'a> {
    /// The constraint.
    pub constraint: &'a str,
    /// The impact times `τ_1, τ_2, …`.
    pub times: Vec<f64>,
    /// The Zeno point it reached (its index among the run's), if any.
    pub zeno: Option<(usize, &'a ZenoRecord)>,
}

/// The sequences to diagnose: those that reached a Zeno point, or, if none did, every sequence
/// of three impacts or more.
pub fn sequences(record: &Record) -> Vec<Sequence<'_>> {
    let mut reached = Vec::new();
    let mut plain = Vec::new();
    let mut zeno = record.zeno.iter().enumerate();
    let mut current: Option<(&str, Vec<f64>)> = None;
    // Every impact since the last Zeno point or lift-off, for a Zeno point over several
    // constraints (a groove's walls in turn).
    let mut since: Vec<(&str, f64)> = Vec::new();
    for e in &record.events {
        let constraint = e.constraint.as_str();
        match e.kind.as_str() {
            "impact" => {
                if current.as_ref().is_some_and(|(c, _)| *c != constraint) {
                    close(&mut current, &mut plain);
                }
                current
                    .get_or_insert_with(|| (constraint, Vec::new()))
                    .1
                    .push(e.t);
                since.push((constraint, e.t));
            }
            "zeno" => {
                let z = zeno.next();
                let times = accumulated(z, &mut current, &since);
                since.clear();
                reached.push(Sequence {
                    constraint,
                    times,
                    zeno: z,
                });
            }
            _ => {
                close(&mut current, &mut plain);
                since.clear();
            }
        }
    }
    // A stall has no event: the last Zeno point is where the run stopped.
    if let Some(z) = zeno.next() {
        let times = accumulated(Some(z), &mut current, &since);
        reached.push(Sequence {
            constraint: &z.1.constraint,
            times,
            zeno: Some(z),
        });
    }
    close(&mut current, &mut plain);
    if reached.is_empty() {
        plain
    } else {
        reached
    }
}

/// The impact times of the sequence that reached the Zeno point `z`: the run on its constraint
/// (taken from `current`), or, for a Zeno point over several constraints, the last impacts in
/// `since` that reached any of them.
fn accumulated(
    z: Option<(usize, &ZenoRecord)>,
    current: &mut Option<(&str, Vec<f64>)>,
    since: &[(&str, f64)],
) -> Vec<f64> {
    let run = current.take().map(|(_, times)| times).unwrap_or_default();
    let Some((_, z)) = z.filter(|(_, z)| z.constraints.len() > 1) else {
        return run;
    };
    let inside = |c: &str| z.constraints.iter().any(|name| name == c);
    let first = since
        .iter()
        .rposition(|(c, _)| !inside(c))
        .map_or(0, |k| k + 1);
    since[first..].iter().map(|&(_, t)| t).collect()
}

/// Ends the sequence `current`, kept in `plain` if it has three impacts or more.
fn close<'a>(current: &mut Option<(&'a str, Vec<f64>)>, plain: &mut Vec<Sequence<'a>>) {
    if let Some((constraint, times)) = current.take() {
        if times.len() >= 3 {
            plain.push(Sequence {
                constraint,
                times,
                zeno: None,
            });
        }
    }
}

/// A geometric line through the flight times: `Δ(i) = Δ_a r^(i − i_a)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// The ratio `r`.
    pub ratio: f64,
    /// A point `(i_a, Δ_a)` of the line.
    pub anchor: (f64, f64),
    /// The first and last flights `i` it was fitted to: where it is drawn.
    pub span: (f64, f64),
}

/// The flights the engine measures a Zeno point's ratio over: the last 7 (the geometric mean
/// of 6 ratios, `RATIO_BASELINE` in the engine's `zeno.rs`).
pub const TAIL_FLIGHTS: usize = 7;

impl Fit {
    /// The least-squares line through `(i, ln Δ_i)`, with at least two points.
    pub fn least_squares(flights: &[(f64, f64)]) -> Option<Self> {
        let m = flights.len() as f64;
        if flights.len() < 2 {
            return None;
        }
        let mean_i = flights.iter().map(|f| f.0).sum::<f64>() / m;
        let mean_y = flights.iter().map(|f| f.1.ln()).sum::<f64>() / m;
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for &(i, delta) in flights {
            sxy += (i - mean_i) * (delta.ln() - mean_y);
            sxx += (i - mean_i) * (i - mean_i);
        }
        Some(Self {
            ratio: (sxy / sxx).exp(),
            anchor: (mean_i, mean_y.exp()),
            span: (flights[0].0, flights[flights.len() - 1].0),
        })
    }

    /// `Δ(i)`.
    pub fn at(&self, i: f64) -> f64 {
        self.anchor.1 * self.ratio.powf(i - self.anchor.0)
    }
}

/// The flights of a sequence, measured: what a panel of the diagnostic shows.
pub struct Flights<'a> {
    /// The sequence.
    pub sequence: &'a Sequence<'a>,
    /// `(i, Δ_i)` for the flights of positive length.
    pub flights: Vec<(f64, f64)>,
    /// Flights of zero length, which a log scale cannot show.
    pub zero: usize,
    /// The geometric line through the flights.
    pub fit: Option<Fit>,
    /// The estimate of `τ∞`: the engine's for a Zeno point, else extrapolated.
    pub tau: Option<f64>,
}

impl<'a> Flights<'a> {
    /// The flights of `sequence`, with the fitted line and the estimate of `τ∞`.
    pub fn new(sequence: &'a Sequence<'a>) -> Self {
        let deltas: Vec<(f64, f64)> = sequence
            .times
            .windows(2)
            .enumerate()
            .map(|(k, w)| ((k + 1) as f64, w[1] - w[0]))
            .collect();
        let flights: Vec<(f64, f64)> = deltas.iter().copied().filter(|d| d.1 > 0.0).collect();
        let zero = deltas.len() - flights.len();
        let (fit, tau) = match sequence.zeno {
            // The engine's ratio (the geometric mean of the last flights' ratios) through the
            // last flight, over the flights it was measured on, and its τ∞.
            Some((_, z)) => (
                z.ratio
                    .filter(|r| *r > 0.0 && r.is_finite())
                    .zip(flights.last())
                    .map(|(ratio, &anchor)| {
                        let first = deltas.len().saturating_sub(TAIL_FLIGHTS - 1).max(1);
                        Fit {
                            ratio,
                            anchor,
                            span: (first as f64, anchor.0),
                        }
                    }),
                z.t_zeno,
            ),
            None => {
                let fit = Fit::least_squares(&flights);
                // The flights to come, r Δ + r² Δ + … after the last one, if they shrink.
                let tau = fit.filter(|f| f.ratio < 1.0).and_then(|f| {
                    let (&last, &(_, delta)) = (sequence.times.last()?, flights.last()?);
                    Some(last + delta * f.ratio / (1.0 - f.ratio))
                });
                (fit, tau)
            }
        };
        Self {
            sequence,
            flights,
            zero,
            fit,
            tau,
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A record of one coordinate with the events `(kind, t, constraint)` and the Zeno points
    /// `(constraint, t_switch)` (ratio 0.5, τ∞ 1e-9 later).
    pub fn record(events: &[(&str, f64, &str)], zeno: &[(&str, f64)], status: &str) -> Record {
        let state = serde_json::json!({"q": [0.0], "q_dot": [0.0]});
        let json = serde_json::json!({
            "model": "m", "status": status, "message": "",
            "coordinates": ["x"], "velocities": ["x_dot"], "constraints": ["a", "b"],
            "restitutions": {"a": 0.5, "b": 0.5},
            "settings": {"t_end": 10.0}, "final": {"t": 10.0},
            "zeno": zeno.iter().map(|(c, t)| serde_json::json!({
                "constraint": c, "kind": "genuine", "t_switch": t, "t_zeno": t + 1e-9,
                "impacts": 4, "ratio": 0.5, "point": state
            })).collect::<Vec<_>>(),
            "events": events.iter().map(|(k, t, c)| serde_json::json!({
                "kind": k, "t": t, "constraint": c, "before": state
            })).collect::<Vec<_>>(),
            "intervals": [{"start": 0.0}], "trajectory": {"rows": 0}
        });
        serde_json::from_value(json).unwrap()
    }

    #[test]
    fn sequences_end_at_switches_liftoffs_and_other_constraints() {
        let r = record(
            &[
                ("impact", 1.0, "a"),
                ("impact", 1.5, "a"),
                ("impact", 1.75, "a"),
                ("zeno", 2.0, "a"),
                ("liftoff", 3.0, "a"),
                ("impact", 4.0, "b"),
                ("impact", 4.5, "b"),
                ("zeno", 4.75, "b"),
            ],
            &[("a", 2.0), ("b", 4.75)],
            "finished",
        );
        let s = sequences(&r);
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].times, [1.0, 1.5, 1.75]);
        assert_eq!((s[0].constraint, s[0].zeno.unwrap().0), ("a", 0));
        assert_eq!(s[1].times, [4.0, 4.5]);
        assert_eq!(s[1].zeno.unwrap().0, 1);
    }

    #[test]
    fn a_stall_ends_the_last_sequence() {
        let r = record(
            &[
                ("impact", 1.0, "a"),
                ("impact", 1.5, "a"),
                ("impact", 1.75, "a"),
            ],
            &[("a", 1.9)],
            "zeno_stalled",
        );
        let s = sequences(&r);
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].times.len(), 3);
        assert!(s[0].zeno.is_some());
    }

    #[test]
    fn without_a_zeno_point_every_long_sequence_is_shown() {
        let r = record(
            &[
                ("impact", 1.0, "a"),
                ("impact", 2.0, "a"),
                ("impact", 2.5, "a"),
                ("impact", 3.0, "b"),
                ("impact", 3.5, "b"),
                ("impact", 4.0, "a"),
                ("impact", 5.0, "a"),
                ("impact", 5.2, "a"),
                ("impact", 5.3, "a"),
            ],
            &[],
            "finished",
        );
        let s = sequences(&r);
        assert_eq!(s.len(), 2, "the two impacts on b are too few");
        assert_eq!(s[0].times, [1.0, 2.0, 2.5]);
        assert_eq!(s[1].times, [4.0, 5.0, 5.2, 5.3]);
        assert!(s.iter().all(|s| s.zeno.is_none()));
    }

    #[test]
    fn a_geometric_sequence_fits_its_ratio_and_limit() {
        // Flights 1, 1/2, 1/4, …: τ∞ = 1 + 2 = 3.
        let times: Vec<f64> = (0..8)
            .map(|k| 1.0 + 2.0 * (1.0 - 0.5_f64.powi(k)))
            .collect();
        let s = Sequence {
            constraint: "a",
            times,
            zeno: None,
        };
        let p = Flights::new(&s);
        let fit = p.fit.unwrap();
        assert!((fit.ratio - 0.5).abs() < 1e-12, "{}", fit.ratio);
        assert!((fit.at(1.0) - 1.0).abs() < 1e-12);
        assert!((p.tau.unwrap() - 3.0).abs() < 1e-12);
        assert_eq!((p.flights.len(), p.zero), (7, 0));
        // Zero-length flights are counted, not drawn.
        let s = Sequence {
            constraint: "a",
            times: vec![1.0, 2.0, 2.0, 2.0],
            zeno: None,
        };
        let p = Flights::new(&s);
        assert_eq!((p.flights.len(), p.zero), (1, 2));
        assert_eq!(p.fit, None);
        assert_eq!(p.tau, None);
    }
}
