//! The command line: what `zenosim` accepts, parsed and checked by clap (bad arguments exit 2).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use zenosim::ZenoStrategy;
use zenosim_model::Override;
use zenosim_runs::sweep::{Axis, RunSettings, Shard};

use crate::plot::{Format, MapSpec, Plane, PlaneScale};
use crate::size::{Bytes, DEFAULT_MAX_OUTPUT};

/// Simulate a Lagrangian hybrid system with impacts, written in a model file, through its Zeno
/// points and on past them.
#[derive(Debug, Parser)]
#[command(
    name = "zenosim",
    version,
    after_help = "Exit status: 0 finished; 1 the simulation failed (what was computed is kept) or \
                  the output could not be written; 2 a bad model or bad arguments; 3 the run \
                  stopped at a Zeno point (--zeno off)."
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a model and write its trajectory (trajectory.csv) and record (summary.json).
    #[command(
        after_help = "Output, in DIR (default: out/<model name>, relative to the current \
directory; characters of the name other than letters, digits, '-', '_' and '.' become '_'):
  trajectory.csv  t,mode,<q...>,<q_dot...>,h_<constraint>...,lambda_<constraint>...,energy: a row at
                  every accepted step (or every --dt) and the states just before and just after
                  every event; numbers in shortest round-trip form. With friction, f_<constraint>
                  (the tangential force) before energy for each constraint with friction, and
                  mode ends with ;stick:<names> and ;slip:<names> where held contacts stick or slip
  summary.json    the outcome, the final state, the Zeno points, the events, the hybrid time
                  domain, the work counters and the constraints' formulas h (non-finite numbers
                  are written as null)
  model.toml      the model file's text, as read (`zenosim animate DIR` draws it)
DIR is locked while the run writes into it: a second zenosim writing into DIR fails at once.
Each file is written to a temporary name of its own (.<file>.<pid>-<n>.partial, created
exclusively: never through a symlink) and renamed when complete, at the end of the run: until
then the previous run's files stay as they were, so a run that is killed leaves them untouched
(and a hidden .partial file that the next command writing into DIR removes). The old plots go
and the old summary.json is moved aside just before the new files are renamed, back to back,
summary.json last, so its presence means the files are complete and belong together (a SIGKILL
in the microseconds of the renames leaves no summary.json). A write that fails (a full disk)
stops the run at once. trajectory.csv is capped at --max-output (1GiB by default): the first row
past it stops the run at its next step, as failed (status \"failed\", exit status 1); the file
keeps the rows up to the cap and ends with the final state, one row past it. Ctrl-C (SIGINT)
or SIGTERM stops the run at its next step and writes everything computed up to there, status
\"interrupted\", exit status 130 (143 for SIGTERM); a second Ctrl-C stops at once, leaving the
previous results as they were and no temporary file.
With --plot, the plots are drawn from these files once they are complete, as `zenosim plot DIR`
draws them (see `zenosim plot --help`); with --report, report.html is written from them, as
`zenosim report DIR` writes it.

Exit status: 0 finished; 1 the simulation failed or reached a limit or the output cap (the files
are still completed, status \"failed\") or the output could not be written; 2 a bad model or
bad arguments (nothing is written); 3 the run stopped at a Zeno point (--zeno off); 130 (143)
interrupted by Ctrl-C (SIGTERM)."
    )]
    Run(RunArgs),
    /// Draw the plots of a run from its output directory (summary.json and trajectory.csv).
    #[command(after_help = PLOT_HELP)]
    Plot(PlotArgs),
    /// Write report.html into a run's output directory: the mechanism animated, the plots
    /// interactive, the events and the Zeno points, in one file that works offline.
    #[command(after_help = REPORT_HELP)]
    Report(ReportArgs),
    /// Animate a run's mechanism, as its model's [drawing] shows it, into a GIF file.
    #[command(after_help = ANIMATE_HELP)]
    Animate(AnimateArgs),
    /// Run a model at every point of a grid of parameters or initial values, in parallel, and
    /// write one row per run (CSV): its status, impacts, Zeno time and final state.
    #[command(after_help = SWEEP_HELP)]
    Sweep(SweepArgs),
    /// Join the shards of a sweep (`zenosim sweep --shard K/N`) into the file a single sweep
    /// would have written.
    #[command(after_help = MERGE_HELP)]
    Merge(MergeArgs),
    /// Check a model and print what zenosim derives from it at the initial state.
    #[command(after_help = "Exit status: 0 the model is valid; 2 it is not (or bad arguments).")]
    Check(CheckArgs),
    /// Time a model's runs, at its own tolerances or at several, and report each run's outcome
    /// and wall time as JSON (on stdout).
    #[command(after_help = BENCH_HELP)]
    Bench(BenchArgs),
    /// Draw work–precision diagrams (error against wall time and against right-hand-side
    /// evaluations) from a JSON file of measured points, as bench/run writes it.
    #[command(after_help = WORK_PRECISION_HELP)]
    WorkPrecision(WorkPrecisionArgs),
}

/// What `zenosim sweep --help` says of its file and exit status.
const SWEEP_HELP: &str = "Each --vary adds an axis: NAME=START:STOP:COUNT (COUNT evenly spaced \
values from START to STOP, both included, as numpy.linspace) or NAME=V1,V2,... (numbers). NAME \
is a parameter or an initial value (a coordinate x or a velocity x_dot) of the model. The \
points are every combination of the axes' values, the first axis varying slowest (or, with \
--zip, the axes' i-th values together). Each point is the model file with those values, run \
with the file's settings (changed by --t-end, --zeno, --rtol, --atol) and no trajectory kept; \
a point whose values the model refuses (a restitution of 1.5, a start below a constraint) is a \
row of status invalid, and the sweep goes on.

The file (default: out/<model name>/sweep.csv, or sweep-K-of-N.csv with --shard K/N):
  # zenosim sweep v1 zenosim=VERSION sweep=HASH points=TOTAL shard=K/N model=NAME
  index,<varied names...>,status,impacts,t_zeno,t_switch,t_final,final_<q>...,final_<q>_dot...,message
one row per run, in the order of the points (index from 0). status: finished, zeno_stalled \
(--zeno off), failed or invalid. t_zeno, t_switch: of the first Zeno point, NaN where there is \
none. Numbers in shortest round-trip form, NaN where there is no value. The first line says \
which sweep (HASH: of the model file and the sweep's axes and settings) and which shard; read \
the file with pandas as pd.read_csv(path, skiprows=1). It is written to a temporary name \
(.<file>.<pid>-<n>.partial) and renamed when complete. Ctrl-C (or SIGTERM) stops the runs \
under way and writes the rows done, exit status 130 (143); a second Ctrl-C stops at once, \
writing nothing (the previous file stays as it was). The file is capped at --max-output (1GiB \
by default): a sweep whose rows cannot fit even at a character a field is refused before it \
runs; one whose rows turn out longer keeps the rows that fit, whole and in order, and exits 1 \
(`zenosim merge` refuses such a file as incomplete).

--shard K/N runs the points i with i % N = K - 1 (interleaved, so that the shards take \
similar times): one part per job of a cluster's array (Slurm, Kubernetes indexed Jobs); \
`zenosim merge` joins the parts.

--plot X,Y,QUANTITY draws a map of a column (t_zeno, t_switch, impacts, t_final, final_<q>...) \
over two varied names X and Y of a product (other axes with one value at most), a cell per \
run coloured by the value with a colour bar, the runs without a value (NaN: no Zeno point, or \
invalid) in grey, hatched; written beside the file as <file stem>.svg (or .png with --format \
png).

Exit status: 0 every run finished or stopped at a Zeno point; 1 a run failed or a point was \
invalid (the file is still written, complete, their rows saying why), the file reached the \
output cap, or the output could not be written; 2 a bad model or bad arguments (nothing is \
written).";

/// What `zenosim merge --help` says.
const MERGE_HELP: &str = "The parts are the files of `zenosim sweep ... --shard K/N` for K = \
1..N, in any order. Merge checks that they come from the same sweep (the first lines' model, \
sweep hash, points and zenosim version agree), that every shard is given once, and that each \
holds exactly its rows; it writes, to a temporary name renamed when complete, exactly the file \
one unsharded `zenosim sweep` would have written.

Exit status: 0 merged; 1 the output could not be written; 2 a part is missing, given twice, \
from another sweep, incomplete or not a sweep file (the message names the file), or bad \
arguments.";

/// `zenosim sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// The model file (TOML).
    #[arg(value_name = "MODEL.toml")]
    pub model: PathBuf,

    /// An axis: NAME=START:STOP:COUNT or NAME=V1,V2,...; repeatable (one axis each).
    #[arg(long = "vary", value_name = "NAME=VALUES", required = true, value_parser = parse_axis)]
    pub vary: Vec<Axis>,

    /// Combine the axes' i-th values (all axes the same length) instead of every combination.
    #[arg(long)]
    pub zip: bool,

    /// The sweep's file [default: out/<model name>/sweep.csv, or sweep-K-of-N.csv with
    /// --shard].
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,

    /// Run only the K-th of N interleaved parts (1 ≤ K ≤ N), to be joined by `zenosim merge`.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<Shard>,

    /// The number of runs at once [default: one per core].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub workers: Option<u32>,

    /// The settings of every run.
    #[command(flatten)]
    pub settings: SettingArgs,

    /// The most bytes the sweep's file may take: bytes, or K, M, G, T (powers of 1024: 100K,
    /// 2GiB), or KB, MB, GB (of 1000). A sweep whose rows cannot fit is refused before it
    /// runs; one whose rows turn out longer keeps those that fit and exits 1.
    #[arg(long, value_name = "SIZE", default_value = DEFAULT_MAX_OUTPUT,
          allow_negative_numbers = true, value_parser = parse_size)]
    pub max_output: Bytes,

    /// Draw a map of QUANTITY (a column: t_zeno, impacts, final_x...) over the varied names X
    /// and Y, beside the file.
    #[arg(long, value_name = "X,Y,QUANTITY", value_parser = parse_map)]
    pub plot: Option<MapSpec>,

    /// With --plot: the map's format [default: svg].
    #[arg(long, value_enum, value_name = "svg|png")]
    pub format: Option<Format>,

    /// Bounds on the model file's formulas.
    #[command(flatten)]
    pub formulas: FormulaLimits,
}

/// `zenosim merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shards' files.
    #[arg(value_name = "PART.csv", required = true)]
    pub parts: Vec<PathBuf>,

    /// The merged file.
    #[arg(long, value_name = "FILE.csv", required = true)]
    pub out: PathBuf,
}

/// What `zenosim bench --help` says of its report.
const BENCH_HELP: &str = "Each run is timed in this process with no output written (the \
simulation's own time): once untimed, then repeatedly until --min-time has passed (at least 3 \
times); the median, fastest and slowest are reported. Loading the file (reading, parsing, \
checking, compiling its derivatives) is timed apart, as load_time_s.

The report on stdout: {\"zenosim\", \"model\", \"coordinates\", \"parameters\", \"initial\", \
\"constraints\", \"load_time_s\": {median, min, max, repeats}, \"runs\": [one per tolerance: \
{\"settings\", \"status\", \"message\", \"final\", \"zeno\", \"events\": {impact, zeno, liftoff}, \
\"stats\", \"wall_time_s\"}]}; settings, final, zeno and stats as in summary.json (see \
`zenosim run --help`). A line per tolerance goes to stderr as it is measured.

Exit status: 0 every run finished; 1 a run failed (the report is still written); 2 a bad model \
or bad arguments; 3 a run stopped at a Zeno point (--zeno off).";

/// What `zenosim work-precision --help` says of its input.
const WORK_PRECISION_HELP: &str = "The input (bench/run writes it as \
bench/results/work-precision.json):
  {\"title\": \"...\", \"subtitle\": \"...\", \"panels\": [{\"title\": \"...\", \"error\": \"what the error is\",
   \"series\": [{\"label\": \"...\", \"points\": [{\"error\": E, \"wall_time_s\": T, \"rhs_evals\": N,
   \"tolerance\": TOL (optional), \"epsilon\": EPS (optional)}, ...]}, ...]}, ...]}
Each panel is a row of two log–log plots: the error against the wall time and against the
right-hand-side evaluations, a line per series through its points in order of cost. An error of
exactly 0 is drawn on the plot's floor with an open marker.

Exit status: 0 the diagram is written; 1 it could not be written; 2 the input is missing or
malformed (the message names the file, the line and the key), or bad arguments.";

/// `zenosim bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The model file and what changes it.
    #[command(flatten)]
    pub input: ModelInput,

    /// The stop time [default: the file's simulation.t_end, else 10].
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = positive)]
    pub t_end: Option<f64>,

    /// How to pass Zeno points: auto, off or ε, as for `zenosim run` [default: the file's].
    #[arg(long, value_name = "auto|off|EPS", allow_negative_numbers = true, value_parser = zeno)]
    pub zeno: Option<ZenoStrategy>,

    /// Run once per tolerance, with rtol = atol = each, e.g. 1e-4,1e-6,1e-8 [default: once,
    /// at the file's rtol and atol].
    #[arg(long, value_name = "TOL,...", value_delimiter = ',', num_args = 1..,
          allow_negative_numbers = true, value_parser = positive)]
    pub tolerances: Option<Vec<f64>>,

    /// Repeat each run until this many seconds have passed (it runs 3 times at least; at most
    /// a day).
    #[arg(long, value_name = "SECONDS", default_value_t = 0.5, allow_negative_numbers = true,
          value_parser = seconds)]
    pub min_time: f64,

    /// Bounds on the model file's formulas.
    #[command(flatten)]
    pub formulas: FormulaLimits,
}

/// `zenosim work-precision`.
#[derive(Debug, Args)]
pub struct WorkPrecisionArgs {
    /// The measured points (JSON).
    #[arg(value_name = "POINTS.json")]
    pub input: PathBuf,

    /// The diagram's file: .svg or .png [default: the input's name with .svg].
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// `zenosim run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The model file and what changes it.
    #[command(flatten)]
    pub input: ModelInput,

    /// The output directory [default: out/<model name>].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// The run's settings.
    #[command(flatten)]
    pub settings: SettingArgs,

    /// Sample the trajectory every DT from the dense output instead of at every step
    /// [default: the file's simulation.dt, else every step].
    #[arg(long, value_name = "DT", allow_negative_numbers = true, value_parser = positive)]
    pub dt: Option<f64>,

    /// Draw the plots into the output directory once the run's files are complete (see
    /// `zenosim plot --help`).
    #[arg(long)]
    pub plot: bool,

    /// With --plot: the plots' format [default: svg].
    #[arg(long, value_enum, value_name = "svg|png")]
    pub format: Option<Format>,

    /// Write report.html into the output directory once the run's files are complete: the
    /// mechanism animated and the plots interactive (see `zenosim report --help`).
    #[arg(long)]
    pub report: bool,

    /// With --plot: the configuration plot's axes, two coordinates or velocities X,Y
    /// [default: the two coordinates the first constraint depends on].
    #[arg(long, value_name = "X,Y", value_parser = parse_plane)]
    pub plane: Option<Plane>,

    /// With --plot: the configuration plot's scales: `equal` (a unit as long on both axes
    /// when both are coordinates) or `free` (each axis fitted to the path) [default: equal].
    #[arg(long, value_enum, value_name = "equal|free")]
    pub plane_scale: Option<PlaneScale>,

    /// The most events (impacts, switches, lift-offs) before the run stops as failed
    /// [default: the file's simulation.max_events, else 100000].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_events: Option<u64>,

    /// The most accepted steps before the run stops as failed [default: the file's
    /// simulation.max_steps, else 10000000].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_steps: Option<u64>,

    /// The most bytes trajectory.csv may take: bytes, or K, M, G, T (powers of 1024: 100K,
    /// 2GiB), or KB, MB, GB (of 1000). When reached, the run stops there as failed, keeping
    /// its rows up to the cap and its final state. Not settable in the model file.
    #[arg(long, value_name = "SIZE", default_value = DEFAULT_MAX_OUTPUT,
          allow_negative_numbers = true, value_parser = parse_size)]
    pub max_output: Bytes,

    /// Bounds on the model file's formulas.
    #[command(flatten)]
    pub formulas: FormulaLimits,
}

/// The settings `run` and `sweep` change on the command line: the stop time, the Zeno strategy
/// and the tolerances (each by default the file's).
#[derive(Clone, Copy, Debug, Args)]
pub struct SettingArgs {
    /// The stop time [default: the file's simulation.t_end, else 10].
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = positive)]
    pub t_end: Option<f64>,

    /// How to pass Zeno points: "auto" (switch once the remaining bounces are below the
    /// integration tolerance), "off" (stop at the Zeno point; `zenosim run` exits 3) or a number
    /// ε (the paper's rule: switch when |h| ≤ ε and |A q̇| ≤ ε) [default: the file's
    /// simulation.zeno, else auto].
    #[arg(long, value_name = "auto|off|EPS", allow_negative_numbers = true, value_parser = zeno)]
    pub zeno: Option<ZenoStrategy>,

    /// The relative tolerance [default: the file's simulation.rtol, else 1e-10].
    #[arg(long, value_name = "R", allow_negative_numbers = true, value_parser = positive)]
    pub rtol: Option<f64>,

    /// The absolute tolerance [default: the file's simulation.atol, else 1e-10].
    #[arg(long, value_name = "A", allow_negative_numbers = true, value_parser = positive)]
    pub atol: Option<f64>,
}

impl SettingArgs {
    /// The changes to the file's settings.
    pub fn settings(&self) -> RunSettings {
        RunSettings {
            t_end: self.t_end,
            zeno: self.zeno,
            rtol: self.rtol,
            atol: self.atol,
        }
    }
}

/// The model file and the changes `--set` makes to it: what `run`, `check` and `bench` read.
#[derive(Debug, Args)]
pub struct ModelInput {
    /// The model file (TOML).
    #[arg(value_name = "MODEL.toml")]
    pub model: PathBuf,

    /// Set a parameter or an initial value (a number or a formula of the parameters); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_override)]
    pub sets: Vec<Override>,
}

impl ModelInput {
    /// Reads and checks the model file, its formulas bounded by `formulas`, with `--set` applied
    /// (every error names the file).
    pub fn load(&self, formulas: &FormulaLimits) -> anyhow::Result<zenosim_model::ModelFile> {
        crate::input::load(&self.model, &self.sets, formulas.limits())
    }

    /// [`ModelInput::load`], with the file's text.
    pub fn load_with_source(
        &self,
        formulas: &FormulaLimits,
    ) -> anyhow::Result<(zenosim_model::ModelFile, String)> {
        crate::input::load_with_source(&self.model, &self.sets, formulas.limits())
    }
}

/// How long and how deep a model file's formulas may be, and how much work differentiating
/// them may take (they bound the time, memory and stack that a hostile or broken file can take).
#[derive(Clone, Copy, Debug, Args)]
pub struct FormulaLimits {
    /// The longest formula accepted, in characters.
    #[arg(long, value_name = "N", default_value_t = zenosim_model::expr::DEFAULT_MAX_LENGTH as u32,
          value_parser = clap::value_parser!(u32).range(1..))]
    pub max_formula_length: u32,

    /// The deepest nesting accepted in a formula (parentheses, calls, signs and operators).
    #[arg(long, value_name = "N", default_value_t = zenosim_model::expr::DEFAULT_MAX_DEPTH as u32,
          value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub max_formula_depth: u32,

    /// The most operations that differentiating the model's formulas may take (it grows with
    /// their size; loading stops with an error past it).
    #[arg(long, value_name = "N", default_value_t = zenosim_model::expr::DEFAULT_MAX_OPERATIONS as u64,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub max_derivative_operations: u64,
}

impl FormulaLimits {
    /// As the model crate's limits.
    pub fn limits(&self) -> zenosim_model::Limits {
        zenosim_model::Limits {
            max_length: self.max_formula_length as usize,
            max_depth: self.max_formula_depth as usize,
            max_operations: usize::try_from(self.max_derivative_operations).unwrap_or(usize::MAX),
        }
    }
}

/// What `zenosim plot --help` says of the files and the exit status.
const PLOT_HELP: &str = "Plots, written into DIR as <name>.svg (or .png with --format png):
  figure         the paper's Figs. 4 and 5: velocities, displacements and the configuration
                 plane, one above the other
  velocities     q_dot against t, one line per coordinate
  displacements  q against t
  energy         the energy against t
  plane          one coordinate against another (--plane), over the curves h = 0 of the
                 constraints that depend on those two only
  zeno           the Zeno diagnostic: flight times between impacts against the impact index, on
                 a log scale, with the fitted ratio and the estimate of τ∞; a panel per Zeno point
  friction       for a model with friction only: the tangential forces f_<constraint> against t
On every time plot impacts (dots), lift-offs (triangles) and, with friction, contacts starting to
stick (filled squares) and to slip (hollow squares) are marked along the time axis, and
each switch to the constrained motion (or the stall, with --zeno off, or where a failed run
stopped) is a vertical line, labelled where the label overprints no other; more than 40
switches (or switches a few pixels apart) are a rug of short marks along the top, counted in the
legend. Long runs are decimated for drawing (per pixel column, its first, last, lowest and
highest points); more than 500 marks of a kind are thinned to one per pixel column. The plane of
two coordinates has equal scales (--plane-scale free: each axis fitted to the path). Each file
is written to a temporary name and renamed when complete. In SVG, each part is a group <g class=\"series|impacts|liftoffs|stick|slip|switch|stall|...\"
data-name=\"...\">.

Exit status: 0 the plots are written; 1 a plot could not be written; 2 bad arguments, or DIR
does not hold a complete run (summary.json or trajectory.csv missing or malformed: the message
names the file and the line).";

/// What `zenosim report --help` says of the page and the exit status.
const REPORT_HELP: &str = "The report, DIR/report.html, is one HTML file with everything in it \
(its script, its style and the run's data): it opens in a browser from the disk and fetches \
nothing. It shows:
  the mechanism    drawn from the [drawing] section of DIR/model.toml (the model file the run
                   wrote there, with the run's parameters), played at a chosen speed (1× is
                   real time) and slowed down approaching each Zeno point; a scrubber with the events marked
                   along it; the mode and the constraints held; the trace of a chosen point
  the plots        displacements, velocities and energy against time (and with friction the
                   tangential forces): zoom (wheel), pan (drag), the values under the pointer,
                   series switched on and off
  friction         each contact's stick and slip states along the scrubber and at the current
                   time, and the impacts' normal and tangential impulses in the events' table
  the balance      the run's energy balance, the work of friction included
  the Zeno points  and the events, in tables whose times move the animation there
Without a [drawing] (or without model.toml) the page says so and shows the rest. Long runs are \
decimated as `zenosim plot` decimates them; both rows of every event are kept. The file is \
written to a temporary name and renamed when complete.

Exit status: 0 the report is written; 1 it could not be written; 2 bad arguments, or DIR does \
not hold a complete run (summary.json or trajectory.csv missing or malformed, model.toml \
unreadable or not the run's: the message names the file).";

/// `zenosim report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// The output directory of a run (`zenosim run --out DIR`, by default out/<model name>).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,

    /// Bounds on the model file's formulas (its drawing is read again).
    #[command(flatten)]
    pub formulas: FormulaLimits,
}

/// `zenosim plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// The output directory of a run (`zenosim run --out DIR`, by default out/<model name>).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,

    /// The plots' format.
    #[arg(long, value_enum, value_name = "svg|png", default_value = "svg")]
    pub format: Format,

    /// The configuration plot's axes, two coordinates or velocities X,Y [default: the two
    /// coordinates the first constraint depends on, else the last two coordinates, else the
    /// coordinate and its velocity].
    #[arg(long, value_name = "X,Y", value_parser = parse_plane)]
    pub plane: Option<Plane>,

    /// The configuration plot's scales: `equal` (a unit as long on both axes when both are
    /// coordinates, so that the plane keeps its shape) or `free` (each axis fitted to the path).
    #[arg(long, value_enum, value_name = "equal|free", default_value = "equal")]
    pub plane_scale: PlaneScale,
}

/// What `zenosim animate --help` says of the file and the exit status.
const ANIMATE_HELP: &str = "The model is read from DIR/model.toml (which `zenosim run` writes \
beside its results) with the parameters of DIR/summary.json, so that the run's --set values \
hold; a folder written before model.toml existed needs --model MODEL.toml. The model needs a \
[drawing] section (docs/drawing.md). The trajectory is sampled every --speed/--fps seconds of \
simulated time, along the cubic through its rows' positions and velocities (never across an \
event), each frame showing the \
drawing at that time, its time and mode in the top left corner, the surfaces of the \
constraints held in colour and the path of the drawing's trace point so far. The box is fixed \
over the whole run, with equal scales in x and y (a drawing in space is seen from above its x, \
y plane). A run longer than --max-frames frames is sampled more coarsely to fit, and the report \
says at what speed it then plays. The GIF is written to a temporary name \
(.<file>.<pid>-<n>.partial) and renamed when complete.

Exit status: 0 written; 1 the file could not be written; 2 DIR is not a complete run, the model \
is invalid or has no [drawing], or bad arguments.";

/// `zenosim animate`.
#[derive(Debug, Args)]
pub struct AnimateArgs {
    /// The output directory of a run (`zenosim run --out DIR`, by default out/<model name>).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,

    /// The GIF file to write.
    #[arg(long, value_name = "FILE.gif")]
    pub out: PathBuf,

    /// The model file, for a run folder without model.toml (written by an older zenosim).
    #[arg(long, value_name = "MODEL.toml")]
    pub model: Option<PathBuf>,

    /// Frames per second of the animation.
    #[arg(long, value_name = "N", default_value_t = 25,
          value_parser = clap::value_parser!(u32).range(1..=50))]
    pub fps: u32,

    /// Simulated seconds per second of animation: 1 plays in real time; the default, half
    /// speed, gives the bounces of a ball near its Zeno point twice as many frames.
    #[arg(long, value_name = "X", default_value_t = 0.5, value_parser = parse_speed)]
    pub speed: f64,

    /// The most frames written.
    #[arg(long, value_name = "N", default_value_t = 600,
          value_parser = clap::value_parser!(u32).range(2..=10_000))]
    pub max_frames: u32,

    /// The frames' size in pixels, WIDTHxHEIGHT (each from 64 to 2000).
    #[arg(long, value_name = "WxH", default_value = "640x480", value_parser = parse_frame_size)]
    pub size: FrameSize,

    /// Bounds on the model file's formulas.
    #[command(flatten)]
    pub formulas: FormulaLimits,
}

/// A frame's size in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameSize {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
}

fn parse_frame_size(text: &str) -> Result<FrameSize, String> {
    let bad =
        || format!("`{text}` is not WIDTHxHEIGHT with each from 64 to 2000: write e.g. 640x480");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !(64..=2000).contains(&w) || !(64..=2000).contains(&h) {
        return Err(bad());
    }
    Ok(FrameSize {
        width: w,
        height: h,
    })
}

fn parse_speed(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!(
            "`{text}` is not a speed: give simulated seconds per second, > 0 (1 is real time, \
             0.1 ten times slower)"
        )),
    }
}

/// `zenosim check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The model file and what changes it.
    #[command(flatten)]
    pub input: ModelInput,

    /// Bounds on the model file's formulas.
    #[command(flatten)]
    pub formulas: FormulaLimits,
}

fn parse_override(text: &str) -> Result<Override, String> {
    text.parse()
}

fn parse_plane(text: &str) -> Result<Plane, String> {
    text.parse()
}

fn parse_axis(text: &str) -> Result<Axis, String> {
    text.parse()
        .map_err(|e: zenosim_runs::sweep::SweepError| e.to_string())
}

fn parse_shard(text: &str) -> Result<Shard, String> {
    text.parse()
        .map_err(|e: zenosim_runs::sweep::SweepError| e.to_string())
}

fn parse_map(text: &str) -> Result<MapSpec, String> {
    text.parse()
}

fn parse_size(text: &str) -> Result<Bytes, String> {
    text.parse()
}

fn positive(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(_) => Err("must be a finite number > 0".to_string()),
        Err(_) => Err("not a number: write e.g. 6, 0.01 or 1e-10".to_string()),
    }
}

fn non_negative(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        Ok(_) => Err("must be a finite number ≥ 0".to_string()),
        Err(_) => Err("not a number: write e.g. 0.5 or 2".to_string()),
    }
}

/// A duration in seconds, from 0 to a day (`bench --min-time 1e20` overflowed the clock's
/// type and panicked).
fn seconds(text: &str) -> Result<f64, String> {
    match non_negative(text)? {
        x if x <= 86_400.0 => Ok(x),
        _ => Err("at most 86400 (a day): write e.g. 0.5 or 10".to_string()),
    }
}

fn zeno(text: &str) -> Result<ZenoStrategy, String> {
    zenosim_model::parse_zeno(text.trim()).ok_or_else(|| {
        "expected auto, off or a threshold ε > 0 (the paper's rule, e.g. 1e-3)".to_string()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn values_are_checked() {
        assert_eq!(positive("1e-3"), Ok(1e-3));
        assert!(positive("-1").is_err());
        assert!(positive("0").is_err());
        assert!(positive("inf").is_err());
        assert!(positive("NaN").is_err());
        assert!(positive("x").is_err());
        assert_eq!(non_negative("0"), Ok(0.0));
        assert!(non_negative("-0.1").is_err());
        assert!(non_negative("inf").is_err());
        assert_eq!(zeno("off"), Ok(ZenoStrategy::Off));
        assert_eq!(zeno("1e-3"), Ok(ZenoStrategy::Epsilon(1e-3)));
        assert!(zeno("banana").is_err());
        assert!(zeno("-1").is_err());
        assert!(parse_override("x").is_err());
    }
}
