//! `zenosim merge PART... --out FILE.csv`: the shards of a sweep joined into the file a single
//! unsharded `zenosim sweep` would have written, byte for byte, after checking that they come
//! from the same sweep and that none is missing or given twice.
//!
//! The shards are interleaved (point `i` is in shard `i % N + 1`), so the rows are read from
//! the parts in turn, one at a time: memory stays flat however large the sweep.

use std::io::BufWriter;

use anyhow::{anyhow, Context};

use crate::cli::MergeArgs;
use crate::output::{split, OutputDir};
use crate::sweep_file::{Part, Rewriter};
use crate::{print_report, Classify, Failure, EXIT_OK};

/// `zenosim merge`.
pub fn merge(args: &MergeArgs) -> Result<u8, Failure> {
    let mut parts = open(&args.parts).bad_input()?;
    let first = &parts[0];
    let identity = first.identity.whole();
    let header = first.header.clone();
    let count = first.identity.shard.count();

    let (dir, name) = split(&args.out).bad_input()?;
    let out = OutputDir::prepare(&dir).output()?;
    let (partial, file) = out.create(&name).output()?;
    let target = partial.target().display().to_string();
    let shown = args.out.display().to_string();
    let mut writer = Rewriter::new(BufWriter::new(file), &identity, &header)
        .with_context(|| format!("cannot write {target}"))
        .output()?;
    // A row whose run was stopped (status `interrupted`) is not a result: its shard is to be
    // run again.
    let status = header.iter().position(|name| name == b"status");
    let mut record = csv::ByteRecord::new();
    for index in 0..identity.points {
        let part = &mut parts[index % count];
        let (line, path, shard) = (
            part.line(),
            part.path.display().to_string(),
            part.identity.shard,
        );
        let expected = |what: &str| {
            anyhow!(
                "{path}:{line}: {what} where shard {shard} of {} points has the row of point \
                 {index}: the file is incomplete or was edited; run this shard again",
                identity.points,
            )
        };
        if !part.next(&mut record).bad_input()? {
            return Err(expected("the file ends")).bad_input();
        }
        let found = std::str::from_utf8(record.get(0).unwrap_or_default())
            .ok()
            .and_then(|i| i.parse::<usize>().ok());
        if found != Some(index) {
            let what = format!(
                "a row of index `{}`",
                String::from_utf8_lossy(record.get(0).unwrap_or_default())
            );
            return Err(expected(&what)).bad_input();
        }
        if status.and_then(|c| record.get(c)) == Some(b"interrupted".as_slice()) {
            return Err(anyhow!(
                "{path}:{line}: the run of point {index} was interrupted (status \
                 `interrupted`): shard {shard} is incomplete; run this shard again"
            ))
            .bad_input();
        }
        writer
            .row(&record)
            .with_context(|| format!("cannot write {target}"))
            .output()?;
    }
    for part in &mut parts {
        let line = part.line();
        if part.next(&mut record).bad_input()? {
            return Err(anyhow!(
                "{}:{line}: a row more than shard {} of {} points has: the file was edited or \
                 belongs to another sweep; run this shard again",
                part.path.display(),
                part.identity.shard,
                identity.points
            ))
            .bad_input();
        }
    }
    let file = writer
        .finish()
        .and_then(|w| w.into_inner().map_err(|e| e.into_error()))
        .with_context(|| format!("cannot write {target}"))
        .output()?;
    partial.commit(file).output()?;
    print_report(&format!(
        "{}: merged {count} shards of the sweep {:016x} ({} runs)\n  wrote    {shown}\n",
        identity.model, identity.sweep, identity.points
    ));
    Ok(EXIT_OK)
}

/// Opens every part and checks that together they are one whole sweep: the same sweep, every
/// shard once. The parts come back in shard order.
fn open(paths: &[std::path::PathBuf]) -> anyhow::Result<Vec<Part>> {
    let parts = paths
        .iter()
        .map(|p| Part::open(p))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let Some(first) = parts.first() else {
        return Err(anyhow!("give the files of the shards to merge"));
    };
    let (one, count) = (&first.identity, first.identity.shard.count());
    for part in &parts[1..] {
        let other = &part.identity;
        let differs = if other.sweep != one.sweep || other.model != one.model {
            Some(format!(
                "it is from the sweep {:016x} of the model {}, {} from the sweep {:016x} of \
                 the model {}",
                other.sweep,
                other.model,
                first.path.display(),
                one.sweep,
                one.model
            ))
        } else if other.points != one.points || other.zenosim != one.zenosim {
            Some(format!(
                "it has {} points, run by zenosim {}; {} has {}, run by zenosim {}",
                other.points,
                other.zenosim,
                first.path.display(),
                one.points,
                one.zenosim
            ))
        } else if other.shard.count() != count {
            Some(format!(
                "it is shard {} but {} is shard {}: the sweep was split in different ways",
                other.shard,
                first.path.display(),
                one.shard
            ))
        } else if part.header != first.header {
            Some(format!(
                "its header differs from that of {}",
                first.path.display()
            ))
        } else {
            None
        };
        if let Some(why) = differs {
            return Err(anyhow!(
                "{}: not a shard of the same sweep as the others: {why}; merge the shards of \
                 one sweep only",
                part.path.display()
            ));
        }
    }
    let (sweep, model) = (one.sweep, one.model.clone());
    // The missing shards, found without a slot per shard (the count comes from the files,
    // which may lie): at most parts.len() + 10 numbers are looked at.
    let given: std::collections::HashSet<usize> =
        parts.iter().map(|p| p.identity.shard.number()).collect();
    let mut missing: Vec<String> = (1..=count)
        .filter(|k| !given.contains(k))
        .take(11)
        .map(|k| format!("{k}/{count}"))
        .collect();
    if missing.len() > 10 {
        missing.truncate(10);
        missing.push("…".to_string());
    }
    if !missing.is_empty() {
        return Err(anyhow!(
            "shard{s} {} of the sweep {sweep:016x} ({model}) {are} missing: run {them} with \
             `zenosim sweep ... --shard K/{count}` and give {their} file{s} too",
            missing.join(", "),
            s = if missing.len() == 1 { "" } else { "s" },
            are = if missing.len() == 1 { "is" } else { "are" },
            them = if missing.len() == 1 { "it" } else { "them" },
            their = if missing.len() == 1 { "its" } else { "their" },
        ));
    }
    let mut slots: Vec<Option<Part>> = (0..count).map(|_| None).collect();
    for part in parts {
        let k = part.identity.shard.number() - 1;
        if let Some(earlier) = &slots[k] {
            return Err(anyhow!(
                "{}: shard {} is given twice, here and as {}: give each shard once",
                part.path.display(),
                part.identity.shard,
                earlier.path.display()
            ));
        }
        slots[k] = Some(part);
    }
    Ok(slots.into_iter().flatten().collect())
}
