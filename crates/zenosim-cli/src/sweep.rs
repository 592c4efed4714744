//! `zenosim sweep`: a model run at every point of a grid of its parameters or initial values,
//! in parallel, one row per run in a CSV file (see `sweep_file`), and optionally a map of a
//! quantity over two of the varied names.

use std::fmt::Write as _;
use std::io::BufWriter;
use std::path::PathBuf;

use anyhow::{anyhow, Context};
use zenosim_runs::message::plural;
use zenosim_runs::sweep::{Combine, Points, Row, Shard, Sweep};
use zenosim_runs::Status;

use crate::cli::SweepArgs;
use crate::output::{split, OutputDir};
use crate::plot::{self, MapSpec};
use crate::progress::RunsDone;
use crate::run::default_dir;
use crate::signals;
use crate::sweep_file::{self, Identity};
use crate::{print_error, print_report, Classify, Failure, EXIT_FAILED, EXIT_OK};

/// `zenosim sweep MODEL --vary ...`.
pub fn sweep(args: &SweepArgs) -> Result<u8, Failure> {
    // Ctrl-C and SIGTERM stop the run(s) at the next step, keeping what was computed.
    signals::install();
    // Everything is checked before anything runs or is written.
    if args.plot.is_none() && args.format.is_some() {
        return Err(anyhow!(
            "--format says how to draw the map: add --plot X,Y,QUANTITY"
        ))
        .bad_input();
    }
    let display = args.model.display().to_string();
    let source = crate::input::read_source(&args.model, &display).bad_input()?;
    let combine = if args.zip {
        Combine::Zip
    } else {
        Combine::Product
    };
    let points = Points::new(args.vary.clone(), combine)
        .map_err(anyhow::Error::from)
        .bad_input()?;
    let settings = args.settings.settings();
    let sweep = Sweep::new(&display, &source, args.formulas.limits(), points, settings)
        .map_err(anyhow::Error::from)
        .bad_input()?;
    let shard = args.shard.unwrap_or(Shard::WHOLE);
    let columns = sweep.columns();
    if let Some(map) = &args.plot {
        check_map(map, &sweep, shard, &columns).bad_input()?;
    }
    let path = args
        .out
        .clone()
        .unwrap_or_else(|| default_path(&sweep, shard));
    let (dir, name) = split(&path).bad_input()?;
    let format = args.format.unwrap_or_default();
    let map_path = path.with_extension(format.extension());
    if args.plot.is_some() && map_path == path {
        return Err(anyhow!(
            "--out {}: the map would be written over the sweep's file; name the file .csv",
            path.display()
        ))
        .bad_input();
    }

    sweep
        .check_runs(shard)
        .map_err(anyhow::Error::from)
        .bad_input()?;
    let identity = Identity::of(&sweep, shard);
    let total = shard.len_of(sweep.points().len());
    let least = sweep_file::least_size(&identity, &columns, total);
    if least > args.max_output.0 {
        return Err(anyhow!(
            "--max-output {}: the sweep's {} would take at least {least} bytes in {} (a \
             character a field), more than the cap; raise the cap well above that (rows are \
             usually several times longer), or split the sweep into parts (--shard K/N)",
            args.max_output,
            plural(total, "row"),
            path.display(),
        ))
        .bad_input();
    }
    // The output is opened (and its folder locked) before the runs: a bad --out is said at
    // once, not after hours of runs.
    let out = OutputDir::prepare(&dir).output()?;
    let (partial, file) = out.create(&name).output()?;
    let target = partial.target().to_path_buf();

    let bar = RunsDone::new(total);
    let workers = args.workers.map(|w| w as usize);
    let table = sweep
        .run(
            shard,
            workers,
            |done, _| bar.set(done),
            &signals::INTERRUPTED,
        )
        .map_err(|e| anyhow!(e))
        .output()?;
    bar.finish();

    let max_bytes = args.max_output.0;
    let (file, kept) = sweep_file::write(
        BufWriter::new(file),
        &identity,
        &columns,
        &table.rows,
        max_bytes,
    )
    .and_then(|(w, kept)| Ok((w.into_inner().map_err(|e| e.into_error())?, kept)))
    .with_context(|| format!("cannot write {}", target.display()))
    .output()?;
    partial.commit(file).output()?;
    let capped = kept < table.rows.len();

    let mut written = vec![path.clone()];
    let map = match &args.plot {
        Some(spec) => {
            let drawn = plot::draw_map(&sweep, spec, &columns, &table.rows, format, &map_path);
            if drawn.is_ok() {
                written.push(map_path);
            }
            drawn
        }
        None => Ok(()),
    };
    print_report(&report(&sweep, shard, &table.rows, &written));
    let not_run = |s: Status| table.rows.iter().filter(|r| r.status == s).count();
    let (failed, invalid) = (not_run(Status::Failed), not_run(Status::Invalid));
    let mut not_done = Vec::new();
    if failed > 0 {
        not_done.push(format!("{} failed", plural(failed, "run")));
    }
    if invalid > 0 {
        not_done.push(format!(
            "{} invalid (values the model refuses)",
            plural(invalid, "point")
        ));
    }
    let code = if capped {
        print_error(&format!(
            "{} reached the output cap of {} (--max-output): it holds the rows of the first {} \
             of {}, the others are lost; raise the cap (e.g. --max-output {}), or split the \
             sweep into parts (--shard K/N)",
            path.display(),
            args.max_output,
            plural(kept, "run"),
            table.total,
            args.max_output.doubled().flag()
        ));
        EXIT_FAILED
    } else if let (true, Some(signal)) = (table.interrupted, signals::received()) {
        print_error(&format!(
            "the sweep was interrupted by {} after {} of {}: the rows done are in {}",
            signals::name(signal),
            plural(table.rows.len(), "run"),
            table.total,
            path.display()
        ));
        signals::exit_status(signal)
    } else if not_done.is_empty() {
        EXIT_OK
    } else {
        print_error(&format!(
            "{}: their rows say why (column message) in {}",
            not_done.join(" and "),
            path.display()
        ));
        EXIT_FAILED
    };
    // A map that could not be drawn is an output failure, said after the runs' own outcome.
    map?;
    Ok(code)
}

/// `out/<model>/sweep.csv`, or `sweep-K-of-N.csv` for a shard.
fn default_path(sweep: &Sweep, shard: Shard) -> PathBuf {
    let name = if shard == Shard::WHOLE {
        "sweep.csv".to_string()
    } else {
        format!("sweep-{}-of-{}.csv", shard.number(), shard.count())
    };
    default_dir(sweep.model()).join(name)
}

/// Refuses a map that cannot be drawn, before anything runs.
fn check_map(map: &MapSpec, sweep: &Sweep, shard: Shard, columns: &[String]) -> anyhow::Result<()> {
    let points = sweep.points();
    let names = points.names();
    for axis in [&map.x, &map.y] {
        if !names.contains(&axis.as_str()) {
            return Err(anyhow!(
                "--plot {map}: `{axis}` is not varied; the map's axes are two of the varied \
                 names: {}",
                names.join(", ")
            ));
        }
    }
    let quantities: Vec<&str> = columns
        .iter()
        .map(String::as_str)
        .filter(|c| !matches!(*c, "index" | "status" | "message"))
        .collect();
    if !quantities.contains(&map.quantity.as_str()) {
        return Err(anyhow!(
            "--plot {map}: `{}` is not a column of the sweep's file; a quantity is one of {}",
            map.quantity,
            quantities.join(", ")
        ));
    }
    if points.combine() == Combine::Zip {
        return Err(anyhow!(
            "--plot {map}: a map needs every combination of {} and {}: drop --zip",
            map.x,
            map.y
        ));
    }
    if let Some(other) = points
        .axes()
        .iter()
        .find(|a| a.name() != map.x && a.name() != map.y && a.len() > 1)
    {
        return Err(anyhow!(
            "--plot {map}: `{}` takes {} values, so each cell of the map would hold {} runs; \
             vary only {} and {} (others with one value), or draw one map per value",
            other.name(),
            other.len(),
            other.len(),
            map.x,
            map.y
        ));
    }
    if shard != Shard::WHOLE {
        return Err(anyhow!(
            "--plot {map}: a shard holds only some of the points; draw the map from an \
             unsharded sweep"
        ));
    }
    Ok(())
}

/// The report: how the runs ended, and the files written.
fn report(sweep: &Sweep, shard: Shard, rows: &[Row], written: &[PathBuf]) -> String {
    let mut text = String::new();
    let of = if shard == Shard::WHOLE {
        String::new()
    } else {
        format!(" (shard {shard} of {} points)", sweep.points().len())
    };
    let _ = writeln!(text, "{}: {}{of}", sweep.model(), plural(rows.len(), "run"));
    let counts: Vec<String> = Status::ALL
        .iter()
        .map(|&s| (s, rows.iter().filter(|r| r.status == s).count()))
        .filter(|(_, n)| *n > 0)
        .map(|(s, n)| format!("{n} {s}"))
        .collect();
    let zeno = rows.iter().filter(|r| !r.t_zeno.is_nan()).count();
    let _ = writeln!(
        text,
        "  status:  {}; {zeno} reached a Zeno point",
        if counts.is_empty() {
            "no runs".to_string()
        } else {
            counts.join(", ")
        }
    );
    for path in written {
        let _ = writeln!(text, "  wrote    {}", path.display());
    }
    text
}
