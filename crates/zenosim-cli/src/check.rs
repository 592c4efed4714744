//! `zenosim check`: validate a model and print what zenosim derives from it at the initial
//! state.

use anyhow::anyhow;
use zenosim::{Derived, HybridLagrangian, OutputGrid, Simulation, SimulationOptions, ZenoStrategy};
use zenosim_model::ModelFile;
use zenosim_runs::number::number;
use zenosim_runs::summary::method_name;

use crate::cli::CheckArgs;
use crate::{print_report, Classify, Failure, EXIT_OK};

/// Checks the model of `args` and prints the report; exit 0, or a bad-input failure.
pub fn check(args: &CheckArgs) -> Result<u8, Failure> {
    let file = args.input.load(&args.formulas).bad_input()?;
    let options = file.options();
    let (q0, q_dot0) = (&file.initial.q, &file.initial.q_dot);
    Simulation::new(&file.model, q0, q_dot0, options)
        .map_err(|error| {
            anyhow!(
                "{}: cannot simulate this model: {error}",
                args.input.model.display()
            )
        })
        .bad_input()?;
    let derived = Derived::new(&file.model)
        .map_err(|error| anyhow!("{}: {error}", args.input.model.display()))
        .bad_input()?;
    print_report(&report(&file, &options, &derived));
    Ok(EXIT_OK)
}

fn report(
    file: &ModelFile,
    options: &SimulationOptions,
    derived: &Derived<'_, impl HybridLagrangian>,
) -> String {
    let model = &file.model;
    let coordinates = model.coordinate_names();
    let velocities = file.velocity_names();
    let (q0, q_dot0) = (&file.initial.q, &file.initial.q_dot);
    let n = model.dimension();
    let mut s = String::new();
    // Writing to a String cannot fail.
    let mut line = |text: String| {
        s.push_str(&text);
        s.push('\n');
    };

    line(format!("model        {}", file.name));
    if let Some(description) = &file.description {
        line(format!("description  {description}"));
    }
    line(format!("dimension    {n}"));
    line(format!("coordinates  {}", coordinates.join(", ")));
    line(format!("velocities   {}", velocities.join(", ")));
    if file.parameters.is_empty() {
        line("parameters   (none)".to_string());
    } else {
        line("parameters".to_string());
        let width = file
            .parameters
            .iter()
            .map(|(p, _)| p.len())
            .max()
            .unwrap_or(0);
        for (name, value) in &file.parameters {
            line(format!("  {name:<width$} = {}", number(*value)));
        }
    }

    line("initial state".to_string());
    let width = velocities.iter().map(String::len).max().unwrap_or(0);
    for i in 0..n {
        line(format!(
            "  {:<width$} = {:<24} {:<width$} = {}",
            coordinates[i],
            number(q0[i]),
            velocities[i],
            number(q_dot0[i])
        ));
    }

    let (mass, positive) = derived.mass_matrix(q0, q_dot0);
    line(format!(
        "mass matrix M(q0) = ∂²L/∂q̇² ({})",
        if positive {
            "positive definite"
        } else {
            "NOT positive definite"
        }
    ));
    for row in matrix(&mass, n) {
        line(format!("  {row}"));
    }
    line(format!(
        "energy       {} (q̇ᵀ ∂L/∂q̇ − L at the initial state)",
        number(derived.energy(q0, q_dot0))
    ));

    line("constraints (admissible side h ≥ 0)".to_string());
    for (index, c) in model.constraints().iter().enumerate() {
        let (h, a) = derived.constraint(index, q0);
        line(format!("  {}", c.name));
        line(format!("    h(q0)       = {}", number(h)));
        line(format!("    A(q0)       = [{}]", join(&a)));
        // ḣ = A q̇ + ∂h/∂t: A q̇ where the surface does not move.
        let label = if model.is_autonomous() {
            "A q̇        "
        } else {
            "ḣ (at t = 0)"
        };
        line(format!(
            "    {label} = {}",
            number(derived.normal_velocity(index, q0, q_dot0))
        ));
        line(format!("    restitution = {}", number(c.restitution)));
        if model.has_zeno_reset(index) {
            line("    zeno_reset  = the model's own R∞".to_string());
        }
    }

    line("simulation".to_string());
    line(format!("  t_end      = {}", number(options.t_end)));
    line(format!(
        "  rtol       = {}",
        number(options.tolerances.rtol)
    ));
    line(format!(
        "  atol       = {}",
        number(options.tolerances.atol)
    ));
    line(format!(
        "  zeno       = {}",
        match options.zeno {
            ZenoStrategy::Auto => "auto".to_string(),
            ZenoStrategy::Off => "off".to_string(),
            ZenoStrategy::Epsilon(eps) => format!("ε rule, ε = {}", number(eps)),
        }
    ));
    line(format!("  method     = {}", method_name(options.method)));
    line(format!(
        "  output     = {}",
        match options.output {
            OutputGrid::Steps => "every accepted step".to_string(),
            OutputGrid::Uniform(dt) => format!("every dt = {}", number(dt)),
        }
    ));
    line(format!(
        "  max_step   = {}",
        if options.max_step.is_finite() {
            number(options.max_step)
        } else {
            "none".to_string()
        }
    ));
    line(format!("  max_events = {}", options.max_events));
    line(format!("  max_steps  = {}", options.max_steps));
    line("ok: the model is valid".to_string());
    s
}

fn join(values: &[f64]) -> String {
    let mut s = String::new();
    for (i, v) in values.iter().enumerate() {
        if i > 0 {
            s.push_str(", ");
        }
        s.push_str(&number(*v));
    }
    s
}

/// The rows of the `n × n` row-major matrix `m`, in right-aligned columns.
fn matrix(m: &[f64], n: usize) -> Vec<String> {
    let cells: Vec<String> = m.iter().map(|&x| number(x)).collect();
    let width = cells.iter().map(|c| c.chars().count()).max().unwrap_or(0);
    cells
        .chunks(n.max(1))
        .map(|row| {
            let cells: Vec<String> = row.iter().map(|c| format!("{c:>width$}")).collect();
            format!("[ {} ]", cells.join("  "))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrices_are_aligned() {
        assert_eq!(
            matrix(&[1.0, 0.0, 0.0, 12.5], 2),
            vec!["[    1     0 ]", "[    0  12.5 ]"]
        );
    }
}
