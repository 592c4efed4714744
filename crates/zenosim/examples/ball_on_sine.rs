//! The paper's Example 6: a ball bouncing on `x3 = sin(x2)` with `e = 0.6`, carried past its
//! Zeno point (Ames et al. 2006, Fig. 5).
//!
//! `cargo run --release -p zenosim --example ball_on_sine [auto|off|EPSILON]` prints the
//! execution's summary and writes `ball-on-sine.svg`: displacements against time, and the
//! path in the (x2, x3) plane over the surface.

use std::fmt::Write as _;
use zenosim::models::BallOnSine;
use zenosim::{
    EventKind, OutputGrid, Point, Simulation, SimulationOptions, Trajectory, ZenoStrategy,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let zeno = match std::env::args().nth(1).as_deref() {
        None | Some("auto") => ZenoStrategy::Auto,
        Some("off") => ZenoStrategy::Off,
        Some(other) => ZenoStrategy::Epsilon(
            other
                .parse()
                .map_err(|_| format!("'{other}': give auto, off or a threshold ε like 1e-3"))?,
        ),
    };
    let example = BallOnSine::paper();
    let options = SimulationOptions {
        t_end: example.t_end,
        zeno,
        // Sampled every 2 ms from the dense output, for the picture.
        output: OutputGrid::Uniform(0.002),
        ..Default::default()
    };
    let sim = Simulation::new(&example.model, &example.q0, &example.q_dot0, options)?;
    let mut trajectory = Trajectory::default();
    let run = sim.run(&mut trajectory);

    println!("{} (t = {})", run.outcome, run.t_final);
    println!("{} impacts", run.stats.impacts);
    for z in &run.zeno {
        println!(
            "{} Zeno point: switched at t = {:.12}, τ∞ ≈ {:.12}, flight-time ratio {:.6}",
            z.kind.name(),
            z.t_switch,
            z.t_zeno,
            z.ratio.unwrap_or(f64::NAN)
        );
    }
    let s = run.stats;
    println!(
        "{} steps ({} rejected), {} evaluations of the equations of motion",
        s.steps, s.rejected_steps, s.rhs_evals
    );
    let switch = run
        .events
        .iter()
        .find(|e| e.kind == EventKind::Zeno)
        .map(|e| e.t);
    std::fs::write(
        "ball-on-sine.svg",
        figure(&trajectory.points, switch, example.t_end),
    )?;
    println!("wrote ball-on-sine.svg");
    Ok(())
}

/// A two-panel figure in the layout of the paper's Fig. 5.
fn figure(points: &[Point], switch: Option<f64>, t_end: f64) -> String {
    let (width, panel) = (720.0, 260.0);
    let mut svg = String::new();
    let _ = write!(
        svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{h}" font-family="sans-serif" font-size="12"><rect width="100%" height="100%" fill="white"/>"##,
        h = 2.0 * panel + 60.0
    );
    // Top: x2 and x3 against t.
    let top = Frame {
        x0: 60.0,
        y0: 30.0,
        w: width - 90.0,
        h: panel - 40.0,
        xs: (0.0, t_end),
        ys: (-4.0, 2.5),
    };
    top.axes(&mut svg, "t", "x2, x3");
    if let Some(t) = switch {
        let x = top.x(t);
        let _ = write!(
            svg,
            r##"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#888" stroke-dasharray="4 3"/><text x="{}" y="{}" fill="#555">switch to the constraint</text>"##,
            top.y0,
            top.y0 + top.h,
            x + 4.0,
            top.y0 + 14.0
        );
    }
    for (i, colour, name) in [(1, "#1f77b4", "x2"), (2, "#d62728", "x3")] {
        top.line(&mut svg, points.iter().map(|p| (p.t, p.q[i])), colour);
        let _ = write!(
            svg,
            r##"<text x="{}" y="{}" fill="{colour}">{name}</text>"##,
            top.x0 + top.w - 30.0,
            top.y0 + 16.0 * i as f64
        );
    }
    // Bottom: x3 against x2, over the surface x3 = sin(x2).
    let bottom = Frame {
        x0: 60.0,
        y0: panel + 30.0,
        w: width - 90.0,
        h: panel - 40.0,
        xs: (-4.0, 1.5),
        ys: (-1.2, 2.2),
    };
    bottom.axes(&mut svg, "x2", "x3");
    bottom.line(
        &mut svg,
        (0..=400).map(|k| {
            let x = -4.0 + 5.5 * k as f64 / 400.0;
            (x, x.sin())
        }),
        "#999",
    );
    bottom.line(&mut svg, points.iter().map(|p| (p.q[1], p.q[2])), "#2ca02c");
    svg.push_str("</svg>\n");
    svg
}

struct Frame {
    x0: f64,
    y0: f64,
    w: f64,
    h: f64,
    xs: (f64, f64),
    ys: (f64, f64),
}

impl Frame {
    fn x(&self, v: f64) -> f64 {
        self.x0 + (v - self.xs.0) / (self.xs.1 - self.xs.0) * self.w
    }
    fn y(&self, v: f64) -> f64 {
        self.y0 + self.h - (v - self.ys.0) / (self.ys.1 - self.ys.0) * self.h
    }
    fn axes(&self, svg: &mut String, x_label: &str, y_label: &str) {
        let _ = write!(
            svg,
            r##"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="black"/><text x="{}" y="{}" text-anchor="middle">{x_label}</text><text x="{}" y="{}" text-anchor="middle" transform="rotate(-90 {} {})">{y_label}</text>"##,
            self.x0,
            self.y0,
            self.w,
            self.h,
            self.x0 + self.w / 2.0,
            self.y0 + self.h + 28.0,
            self.x0 - 38.0,
            self.y0 + self.h / 2.0,
            self.x0 - 38.0,
            self.y0 + self.h / 2.0
        );
        for k in 0..=4 {
            let (vx, vy) = (
                self.xs.0 + (self.xs.1 - self.xs.0) * k as f64 / 4.0,
                self.ys.0 + (self.ys.1 - self.ys.0) * k as f64 / 4.0,
            );
            let _ = write!(
                svg,
                r##"<text x="{}" y="{}" text-anchor="middle">{vx:.1}</text><text x="{}" y="{}" text-anchor="end">{vy:.1}</text>"##,
                self.x(vx),
                self.y0 + self.h + 14.0,
                self.x0 - 4.0,
                self.y(vy) + 4.0
            );
        }
    }
    fn line(&self, svg: &mut String, points: impl Iterator<Item = (f64, f64)>, colour: &str) {
        let path: Vec<String> = points
            .map(|(a, b)| format!("{:.2},{:.2}", self.x(a), self.y(b)))
            .collect();
        let _ = write!(
            svg,
            r##"<polyline fill="none" stroke="{colour}" stroke-width="1.4" points="{}"/>"##,
            path.join(" ")
        );
    }
}
