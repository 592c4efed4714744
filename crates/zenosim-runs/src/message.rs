//! What happened in a run, in a sentence: the `message` of `summary.json` and of a sweep's rows.

use zenosim::{ActiveSet, Error, Execution, Mode, Outcome};

use crate::number::number;

/// `count` `what`, with an English plural (`1 impact`, `3 impacts`).
pub fn plural(count: usize, what: &str) -> String {
    if count == 1 {
        format!("1 {what}")
    } else {
        format!("{count} {what}s")
    }
}

/// What happened in `run`, in a sentence; `constraints` names the model's constraints in order.
pub fn message(run: &Execution, constraints: &[String]) -> String {
    let name = |index: usize| constraints.get(index).map_or("?", String::as_str);
    let impacts = plural(run.stats.impacts as usize, "impact");
    let outcome = outcome(run, constraints, &impacts);
    match held_at_start(run) {
        Some(set) => {
            let names: Vec<String> = set.iter().map(|i| format!("'{}'", name(i))).collect();
            format!(
                "started at rest on {}: held from t = 0; {outcome}",
                names.join(" and ")
            )
        }
        None => outcome,
    }
}

/// The constraints a run started at rest on, held from `t = 0`, if any.
pub fn held_at_start(run: &Execution) -> Option<ActiveSet> {
    match run.intervals.first()? {
        i if i.start == 0.0 => match i.mode {
            Mode::Constrained(set) => Some(set),
            Mode::Free => None,
        },
        _ => None,
    }
}

/// What became of `run`, in a sentence.
fn outcome(run: &Execution, constraints: &[String], impacts: &str) -> String {
    let name = |index: usize| constraints.get(index).map_or("?", String::as_str);
    match &run.outcome {
        Outcome::Finished => format!(
            "finished at t = {} after {impacts} and {}",
            number(run.t_final),
            plural(run.zeno.len(), "Zeno point")
        ),
        Outcome::ZenoStalled { constraint, t_zeno } => format!(
            "stalled at the Zeno point of constraint '{}', τ∞ ≈ {}, after {impacts}: with \
             zeno = off the plain hybrid system cannot go past it (use --zeno auto to carry the \
             execution on)",
            name(*constraint),
            number(*t_zeno)
        ),
        Outcome::Failed(error) => format!("failed: {} (after {impacts})", failure(error)),
        Outcome::Interrupted => {
            format!("interrupted at t = {} after {impacts}", number(run.t_final))
        }
    }
}

/// What happened in `run` when its trajectory's file `file` reached the output cap `cap` (as
/// `1 GiB`) and stopped it: a failure, saying what to do.
pub fn output_cap(run: &Execution, file: &str, cap: &str) -> String {
    format!(
        "failed: at t = {}: {file} reached the output cap of {cap}, which stopped the run; its \
         rows up to the cap and the final state are kept; raise the cap (--max-output SIZE), or \
         write fewer rows: a coarser dt (--dt) or an earlier t_end (--t-end) (after {})",
        number(run.t_final),
        plural(run.stats.impacts as usize, "impact")
    )
}

/// Why a run failed, saying how to raise a limit (on the command line: a model file's
/// `[simulation]` may lower a limit, never raise it past the default).
pub fn failure(error: &Error) -> String {
    match error {
        Error::Limit { what, .. } => {
            format!("{error} (--max-{what} N; a model file's max_{what} may only lower the limit)")
        }
        _ => error.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plurals() {
        assert_eq!(plural(0, "impact"), "0 impacts");
        assert_eq!(plural(1, "impact"), "1 impact");
        assert_eq!(plural(26, "Zeno point"), "26 Zeno points");
    }
}
