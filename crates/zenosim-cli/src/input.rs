//! Reading a model file: at most [`zenosim_model::MAX_FILE_BYTES`], UTF-8, then parsed and
//! checked.

use std::path::Path;

use anyhow::{anyhow, Context};
use zenosim::HybridLagrangian;
use zenosim_model::{Limits, ModelFile, Override, ReadError};

use crate::plot::record::Record;

/// Reads `path` ([`zenosim_model::read_source`]) and parses it with `overrides` applied, its
/// formulas bounded by `limits`. Every error names the file.
pub fn load(path: &Path, overrides: &[Override], limits: Limits) -> anyhow::Result<ModelFile> {
    load_with_source(path, overrides, limits).map(|(file, _)| file)
}

/// [`load`], with the file's text (which `zenosim run` keeps beside its results).
pub fn load_with_source(
    path: &Path,
    overrides: &[Override],
    limits: Limits,
) -> anyhow::Result<(ModelFile, String)> {
    let display = path.display().to_string();
    let source = read_source(path, &display)?;
    let file = zenosim_model::parse_model_with(&display, &source, overrides, limits)
        .map_err(|error| anyhow!(error))?;
    Ok((file, source))
}

/// The model of the run that `record` (its `summary.json`) describes, from the file `path` (the
/// run's `model.toml`, or one given): parsed with the run's values of the file's parameters
/// where they differ from the file's (its `--set`), and refused where its coordinates are not
/// the run's. Every error names the file.
pub fn load_for_run(path: &Path, record: &Record, limits: Limits) -> anyhow::Result<ModelFile> {
    let display = path.display().to_string();
    let source = read_source(path, &display)?;
    let parse = |overrides: &[Override]| {
        zenosim_model::parse_model_with(&display, &source, overrides, limits)
            .map_err(|error| anyhow!(error))
    };
    let file = parse(&[])?;
    let coordinates = file.model.coordinate_names();
    if coordinates != record.coordinates {
        return Err(anyhow!(
            "{display}: its coordinates are {}, the run's are {}: the model file does not belong \
             to this run",
            coordinates.join(", "),
            record.coordinates.join(", ")
        ));
    }
    let overrides: Vec<Override> = file
        .parameters
        .iter()
        .filter_map(|(name, value)| {
            let run = record.parameters.get(name).copied().flatten()?;
            (run.to_bits() != value.to_bits()).then(|| Override {
                name: name.clone(),
                value: format!("{run:?}"),
            })
        })
        .collect();
    if overrides.is_empty() {
        Ok(file)
    } else {
        parse(&overrides)
    }
}

/// The text of the model file `path` (named `display` in messages): at most
/// [`zenosim_model::MAX_FILE_BYTES`], UTF-8 ([`zenosim_model::read_source`]).
pub fn read_source(path: &Path, display: &str) -> anyhow::Result<String> {
    zenosim_model::read_source(path, display).or_else(|error| match error {
        ReadError::Io(error) => {
            Err(error).with_context(|| format!("cannot read the model file {display}"))
        }
        ReadError::Invalid(error) => Err(anyhow!(error)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn non_utf8_is_placed() {
        let mut file = tempfile::NamedTempFile::new().unwrap();
        file.write_all(b"name = \"a\"\nx = \"\xe9t\xe9\"\n")
            .unwrap();
        let error = read_source(file.path(), "m.toml").unwrap_err().to_string();
        assert!(error.starts_with("m.toml:2:6: "), "{error}");
        assert!(error.contains("UTF-8"), "{error}");
    }

    #[test]
    fn large_files_are_refused() {
        let size = zenosim_model::MAX_FILE_BYTES as usize;
        let mut file = tempfile::NamedTempFile::new().unwrap();
        file.write_all(&vec![b'#'; size + 1]).unwrap();
        let error = read_source(file.path(), "big.toml")
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "big.toml: the file is larger than 1 MiB; a model file is a few kilobytes: check \
             that this is the right file"
        );
        let mut file = tempfile::NamedTempFile::new().unwrap();
        file.write_all(&vec![b'#'; size]).unwrap();
        assert!(read_source(file.path(), "ok.toml").is_ok());
    }

    #[test]
    fn missing_files_are_named() {
        let error =
            read_source(Path::new("/nonexistent/m.toml"), "/nonexistent/m.toml").unwrap_err();
        assert!(format!("{error:#}").contains("/nonexistent/m.toml"));
    }
}
