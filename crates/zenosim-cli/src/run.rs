//! `zenosim run`: check everything, then simulate, streaming the trajectory to
//! `trajectory.csv`, and write `summary.json` last.

use std::fmt::Write as _;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

use anyhow::{anyhow, Context};
use zenosim::{Execution, HybridLagrangian, Outcome, OutputGrid, Simulation, SimulationOptions};
use zenosim_model::ModelFile;
use zenosim_runs::json_layout;
use zenosim_runs::message::{failure, message, output_cap, plural};
use zenosim_runs::number::number;
use zenosim_runs::summary::{
    constraint_names, friction_columns, status, EnergyBalanceJson, Record, Summary, TrajectoryJson,
};
use zenosim_runs::Status;

use crate::cli::RunArgs;
use crate::output::{OutputDir, PartialFile};
use crate::plot;
use crate::plot::short;
use crate::progress::Progress;
use crate::report;
use crate::signals;
use crate::trajectory::TrajectoryWriter;
use crate::{
    print_error, print_report, Classify, Failure, EXIT_FAILED, EXIT_OK, EXIT_ZENO_STALLED,
};

/// The trajectory's file name.
pub const TRAJECTORY: &str = "trajectory.csv";
/// The summary's file name.
pub const SUMMARY: &str = "summary.json";
/// The name of the model file's copy, kept beside the results (`zenosim animate` reads it).
pub const MODEL: &str = "model.toml";
/// The summary's levels written one entry per line: the top level and the lists in it (one
/// event per line).
const SUMMARY_INDENT: usize = 2;

/// Runs the model of `args`; the exit status, or why nothing (or not everything) was written.
pub fn run(args: &RunArgs) -> Result<u8, Failure> {
    // Ctrl-C and SIGTERM stop the run(s) at the next step, keeping what was computed.
    signals::install();
    // Everything is checked before the output directory is touched.
    if !args.plot && (args.format.is_some() || args.plane.is_some() || args.plane_scale.is_some()) {
        return Err(anyhow!(
            "--format, --plane and --plane-scale say how to draw the plots: add --plot to draw them"
        ))
        .bad_input();
    }
    let (file, source) = args.input.load_with_source(&args.formulas).bad_input()?;
    if let Some(plane) = &args.plane {
        let names: Vec<String> = file
            .model
            .coordinate_names()
            .into_iter()
            .chain(file.velocity_names())
            .collect();
        plane
            .columns(&names)
            .with_context(|| format!("{}", args.input.model.display()))
            .bad_input()?;
    }
    let options = options(&file, args);
    let simulation = Simulation::new(&file.model, &file.initial.q, &file.initial.q_dot, options)
        .map_err(|error| {
            anyhow!(
                "{}: cannot simulate this model: {error}",
                args.input.model.display()
            )
        })
        .bad_input()?;
    let dir = args.out.clone().unwrap_or_else(|| default_dir(&file.name));

    // The previous run's files stay as they are until this run's are complete.
    let out = OutputDir::prepare(&dir).output()?;
    let constraints = constraint_names(&file);
    // The constraints with friction: a column of tangential force each.
    let friction = friction_columns(&file.model);
    // A model with forces, time or moving surfaces: the energy balance's columns too.
    let autonomous = file.model.is_autonomous();

    let (csv_partial, csv_file) = out.create(TRAJECTORY).output()?;
    let mut writer = TrajectoryWriter::new(
        csv_file,
        &file.model.coordinate_names(),
        &file.velocity_names(),
        &constraints,
        &friction,
        !autonomous,
        args.max_output.0,
        Progress::new(options.t_end),
    );
    let execution = simulation.run(&mut writer);
    // A write error (a full disk) stopped the run at once too, but nothing can be kept then.
    let written = writer
        .finish()
        .with_context(|| format!("cannot write {}", csv_partial.target().display()))
        .output()?;
    let (rows, capped) = (written.rows, written.capped);
    // What the cap leaves for summary.json: the trajectory and the model file count first.
    let csv_bytes = written.out.metadata().map_or(0, |m| m.len());
    let left = args
        .max_output
        .0
        .saturating_sub(csv_bytes)
        .saturating_sub(source.len() as u64);
    let csv_finished = csv_partial.finish(written.out).output()?;

    // The cap stopped the run (as Ctrl-C would, at its next step): a failure, like a limit.
    let (status, message) = if capped {
        let cap = args.max_output.to_string();
        (
            Status::Failed.word(),
            output_cap(&execution, TRAJECTORY, &cap),
        )
    } else {
        (
            status(&execution.outcome),
            message(&execution, &constraints),
        )
    };
    let mut summary = Record {
        file: &file,
        options: &options,
        run: &execution,
        constraint_names: &constraints,
        message: message.clone(),
        trajectory: TrajectoryJson {
            file: TRAJECTORY,
            rows,
        },
    }
    .summary();
    summary.status = status;
    // summary.json within the cap too: its lists cut to the first items that fit.
    let summary_capped = fit_summary(&mut summary, left).output()?;
    let message = match summary.truncated {
        Some(totals) if !capped => {
            let cap = args.max_output.to_string();
            summary.status = Status::Failed.word();
            summary.message = format!(
                "{message}; then {SUMMARY} reached the output cap of {cap} (--max-output): it \
                 lists the first {} of the {} events and {} of the {} intervals",
                summary.events.kept(),
                totals.events,
                summary.intervals.kept(),
                totals.intervals,
            );
            summary.message.clone()
        }
        _ => message,
    };
    let status = summary.status;
    let balance = summary.energy_balance;
    let summary_finished = write_summary(&out, &summary)?;
    // The model file as it was read, so that the folder says what was run.
    let (model_partial, mut model_file) = out.create(MODEL).output()?;
    model_file
        .write_all(source.as_bytes())
        .with_context(|| format!("cannot write {}", model_partial.target().display()))
        .output()?;
    let model_finished = model_partial.finish(model_file).output()?;

    // Both files are complete. The previous run's plots go, then its summary, and the
    // trajectory and the summary take their final names, back to back, the summary last: a
    // summary.json is only ever beside the files it describes (a SIGKILL in the microseconds
    // between the old summary leaving and the new one arriving leaves no summary at all).
    let summary_path = summary_finished.target().to_path_buf();
    signals::committing(|| {
        out.remove(plot::plot_files())?;
        out.remove([report::REPORT.to_string()])?;
        out.replace(SUMMARY, [csv_finished, model_finished, summary_finished])
    })
    .output()?;

    // The plots, from the files just completed, exactly as `zenosim plot` draws them.
    let plots = if args.plot {
        plot::draw_scaled(
            &dir,
            args.format.unwrap_or_default(),
            args.plane.as_ref(),
            args.plane_scale.unwrap_or_default(),
        )
    } else {
        Ok(Vec::new())
    };
    // The report, from the same files, exactly as `zenosim report` writes it.
    let report_file = if args.report {
        report::write(&dir, args.formulas.limits()).map(Some)
    } else {
        Ok(None)
    };
    let mut files = vec![
        (out.path(TRAJECTORY), Some(rows)),
        (out.path(MODEL), None),
        (summary_path, None),
    ];
    files.extend(plots.iter().flatten().map(|path| (path.clone(), None)));
    files.extend(
        report_file
            .iter()
            .flatten()
            .map(|path| (path.clone(), None)),
    );
    let balance = (!autonomous).then_some(&balance);
    print_report(&report(
        &message,
        status,
        &file,
        &execution,
        &constraints,
        balance,
        &files,
    ));
    let code = match &execution.outcome {
        _ if summary_capped && !capped => {
            print_error(&format!(
                "{} reached the output cap of {} (--max-output): the run's {} events and {} \
                 intervals do not fit; it lists the first of them and says so (status failed, \
                 `truncated`). Raise the cap (e.g. --max-output {}), or stop the run earlier \
                 (--t-end, --max-events)",
                out.path(SUMMARY).display(),
                args.max_output,
                execution.events.len(),
                execution.intervals.len(),
                args.max_output.doubled().flag(),
            ));
            EXIT_FAILED
        }
        _ if capped => {
            let trajectory = out.path(TRAJECTORY);
            print_error(&format!(
                "the run stopped at t = {}: {} reached the output cap of {} (--max-output); it \
                 holds {rows} rows, those up to the cap and the final state, and summary.json \
                 says so (status failed). Raise the cap (e.g. --max-output {}), or write fewer \
                 rows: a coarser --dt, or an earlier --t-end",
                number(execution.t_final),
                trajectory.display(),
                args.max_output,
                args.max_output.doubled().flag(),
            ));
            EXIT_FAILED
        }
        Outcome::Finished => EXIT_OK,
        Outcome::ZenoStalled { .. } => EXIT_ZENO_STALLED,
        Outcome::Failed(error) => {
            print_error(&format!(
                "the simulation failed {}; what was computed up to then is in {}",
                failure(error),
                dir.display()
            ));
            EXIT_FAILED
        }
        Outcome::Interrupted => {
            let signal = signals::received();
            print_error(&format!(
                "the run was interrupted{} at t = {}; what was computed up to then is in {}",
                signal.map_or(String::new(), |s| format!(" by {}", signals::name(s))),
                number(execution.t_final),
                dir.display()
            ));
            signal.map_or(EXIT_FAILED, signals::exit_status)
        }
    };
    // A plot or a report that could not be written is an output failure, said after the run's
    // own outcome.
    plots?;
    report_file?;
    Ok(code)
}

/// Cuts the lists of `summary` (Zeno points, events, intervals: the first `k` of each, the
/// largest `k` that fits) so that its file takes at most `budget` bytes, and records how many
/// there were (`truncated`); whether it had to. Each size is counted by writing the summary
/// into a counter (a few passes, only where the whole does not fit).
fn fit_summary(summary: &mut Summary<'_>, budget: u64) -> anyhow::Result<bool> {
    let size = |summary: &Summary<'_>| -> anyhow::Result<u64> {
        let mut counter = Counter(0);
        json_layout::to_writer(&mut counter, summary, SUMMARY_INDENT)?;
        Ok(counter.0 + 1)
    };
    if size(summary)? <= budget {
        return Ok(false);
    }
    let totals = zenosim_runs::summary::TruncatedJson {
        zeno: summary.zeno.len(),
        events: summary.events.len(),
        intervals: summary.intervals.len(),
    };
    summary.truncated = Some(totals);
    let keep = |summary: &mut Summary<'_>, k: usize| {
        summary.zeno.keep(k);
        summary.events.keep(k);
        summary.intervals.keep(k);
    };
    // The largest k that fits, by bisection (0 always is kept: the rest is small).
    let (mut fits, mut too_many) = (0, totals.zeno.max(totals.events).max(totals.intervals));
    while too_many - fits > 1 {
        let mid = fits + (too_many - fits) / 2;
        keep(summary, mid);
        if size(summary)? <= budget {
            fits = mid;
        } else {
            too_many = mid;
        }
    }
    keep(summary, fits);
    Ok(true)
}

/// A writer that only counts the bytes written to it.
struct Counter(u64);

impl Write for Counter {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.0 += bytes.len() as u64;
        Ok(bytes.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Writes `summary.json` under its temporary name, complete and synced, to be published.
fn write_summary(out: &OutputDir, summary: &Summary<'_>) -> Result<PartialFile, Failure> {
    let (partial, file) = out.create(SUMMARY).output()?;
    let path = partial.target().to_path_buf();
    let cannot = || format!("cannot write {}", path.display());
    let mut json = BufWriter::new(file);
    json_layout::to_writer(&mut json, summary, SUMMARY_INDENT)
        .map_err(anyhow::Error::from)
        .and_then(|()| Ok(json.write_all(b"\n")?))
        .with_context(cannot)
        .output()?;
    let file = json
        .into_inner()
        .map_err(|error| anyhow!(error.into_error()))
        .with_context(cannot)
        .output()?;
    partial.finish(file).output()
}

/// The file's settings, overridden by the command line's flags.
fn options(file: &ModelFile, args: &RunArgs) -> SimulationOptions {
    let mut options = args.settings.settings().apply(file.options());
    if let Some(dt) = args.dt {
        options.output = OutputGrid::Uniform(dt);
    }
    if let Some(max_events) = args.max_events {
        options.max_events = max_events;
    }
    if let Some(max_steps) = args.max_steps {
        options.max_steps = max_steps;
    }
    options
}

/// `out/<model name>`, the name made a single safe path component: characters other than
/// letters, digits, `-`, `_` and `.` become `_`, and leading dots are dropped.
pub fn default_dir(name: &str) -> PathBuf {
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    let safe = safe.trim_start_matches('.');
    PathBuf::from("out").join(if safe.is_empty() { "model" } else { safe })
}

/// The report printed after a run, with the energy balance when given (a model that is not
/// autonomous).
fn report(
    message: &str,
    status: &str,
    file: &ModelFile,
    run: &Execution,
    constraints: &[String],
    balance: Option<&EnergyBalanceJson>,
    files: &[(PathBuf, Option<u64>)],
) -> String {
    let name = |index: usize| constraints.get(index).map_or("?", String::as_str);
    let mut text = String::new();
    let _ = writeln!(text, "{}: {message}", file.name);
    let _ = writeln!(text, "  status:  {status}");
    let _ = writeln!(
        text,
        "  final:   t = {}, mode {}",
        number(run.t_final),
        run.final_mode.name()
    );
    let _ = writeln!(
        text,
        "  work:    {}, {} ({} rejected)",
        plural(run.stats.impacts as usize, "impact"),
        plural(run.stats.steps as usize, "step"),
        run.stats.rejected_steps
    );
    if let Some(balance) = balance {
        let _ = writeln!(text, "  energy:  {}", energy_line(balance));
    }
    zeno_lines(&mut text, run, &name);
    for (path, rows) in files {
        match rows {
            Some(rows) => {
                let _ = writeln!(text, "  wrote    {} ({rows} rows)", path.display());
            }
            None => {
                let _ = writeln!(text, "  wrote    {}", path.display());
            }
        }
    }
    text
}

/// Zeno points listed one a line up to this many; more are summed up in three lines.
const ZENO_LINES: usize = 3;

/// The report's lines on the Zeno points: one a point, or, for many (a vibrating table's 4000),
/// their count and kinds, the range of their impacts and ratios, and the first and last.
fn zeno_lines<'a>(text: &mut String, run: &Execution, name: &dyn Fn(usize) -> &'a str) {
    let stalled = matches!(run.outcome, Outcome::ZenoStalled { .. });
    let line = |i: usize| {
        let z = &run.zeno[i];
        // With --zeno off the last Zeno point is where the run stopped, not a switch.
        let verb = if stalled && i + 1 == run.zeno.len() {
            "stopped"
        } else {
            "switched"
        };
        format!(
            "{} on '{}' after {}: τ∞ ≈ {}, {verb} at t = {}",
            z.kind.name(),
            name(z.constraint),
            plural(z.impacts, "impact"),
            number(z.t_zeno),
            number(z.t_switch)
        )
    };
    let count = run.zeno.len();
    if count <= ZENO_LINES {
        for i in 0..count {
            let _ = writeln!(text, "  zeno:    {}", line(i));
        }
        return;
    }
    let genuine = run
        .zeno
        .iter()
        .filter(|z| z.kind == zenosim::ZenoKind::Genuine)
        .count();
    let range = |values: &mut dyn Iterator<Item = f64>| {
        let (low, high) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
        if low > high {
            "none".to_string()
        } else if low == high {
            short(low)
        } else {
            format!("{} to {}", short(low), short(high))
        }
    };
    let impacts = range(&mut run.zeno.iter().map(|z| z.impacts as f64));
    let ratios = range(&mut run.zeno.iter().filter_map(|z| z.ratio));
    let _ = writeln!(
        text,
        "  zeno:    {count} Zeno points ({genuine} genuine, {} chattering), {impacts} impacts \
         each, ratios {ratios} (every one in summary.json)",
        count - genuine
    );
    let _ = writeln!(text, "  first:   {}", line(0));
    let _ = writeln!(text, "  last:    {}", line(count - 1));
}

/// The energy balance in a line: `E` from start to end, the terms that are not 0, and the
/// residual.
fn energy_line(b: &EnergyBalanceJson) -> String {
    let mut line = format!("E = {} → {}", short(b.energy_start), short(b.energy_end));
    let terms = [
        ("forces", b.work_forces),
        ("drive", b.work_drive),
        ("moving constraints", b.work_constraints),
        ("friction", b.work_friction.unwrap_or(0.0)),
        ("impact loss", b.impact_loss),
    ];
    let mut sep = ": ";
    for (name, value) in terms.iter().filter(|(_, value)| *value != 0.0) {
        let _ = write!(line, "{sep}{name} {}", short(*value));
        sep = ", ";
    }
    let _ = write!(line, "; residual {}", short(b.residual));
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_energy_line_names_the_terms_that_worked() {
        let balance = EnergyBalanceJson {
            energy_start: 9.81,
            energy_end: 1.234567891,
            work_forces: -3.5,
            work_drive: 0.0,
            work_constraints: 0.0,
            impact_loss: 5.075432109,
            work_friction: None,
            residual: -2.5e-12,
        };
        assert_eq!(
            energy_line(&balance),
            "E = 9.81 → 1.23457: forces -3.5, impact loss 5.07543; residual -2.5e-12"
        );
        let table = EnergyBalanceJson {
            work_forces: 0.0,
            work_constraints: 0.25,
            work_drive: 1.0,
            ..balance
        };
        assert_eq!(
            energy_line(&table),
            "E = 9.81 → 1.23457: drive 1, moving constraints 0.25, impact loss 5.07543; \
             residual -2.5e-12"
        );
    }

    #[test]
    fn default_directories_stay_inside_out() {
        assert_eq!(
            default_dir("ball-on-sine"),
            PathBuf::from("out/ball-on-sine")
        );
        assert_eq!(default_dir("../../etc"), PathBuf::from("out/_.._etc"));
        assert_eq!(default_dir(".."), PathBuf::from("out/model"));
        assert_eq!(default_dir("a b/c"), PathBuf::from("out/a_b_c"));
        assert_eq!(default_dir("bille é"), PathBuf::from("out/bille__"));
    }
}
