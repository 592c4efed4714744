//! Reading a model file: at most [`MAX_FILE_BYTES`], UTF-8, then parsed and checked.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use anyhow::{anyhow, Context};
use zenosim_model::{Limits, ModelFile, Override};

/// The largest model file read (1 MiB): model files are a few kilobytes; anything larger is a
/// wrong file, and refusing it early keeps a mistaken path from filling memory.
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// Reads `path` (at most `MAX_FILE_BYTES + 1` bytes) and parses it with `overrides` applied,
/// its formulas bounded by `limits`. Every error names the file.
pub fn load(path: &Path, overrides: &[Override], limits: Limits) -> anyhow::Result<ModelFile> {
    let display = path.display().to_string();
    let source = read_source(path, &display)?;
    zenosim_model::parse_model_with(&display, &source, overrides, limits)
        .map_err(|error| anyhow!(error))
}

/// The text of the model file `path` (named `display` in messages): at most
/// [`MAX_FILE_BYTES`], UTF-8.
pub fn read_source(path: &Path, display: &str) -> anyhow::Result<String> {
    let file = File::open(path).with_context(|| format!("cannot read the model file {display}"))?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .with_context(|| format!("cannot read the model file {display}"))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(anyhow!(
            "{display}: the file is larger than 1 MiB; a model file is a few kilobytes: check \
             that this is the right file"
        ));
    }
    String::from_utf8(bytes).map_err(|error| {
        let valid = &error.as_bytes()[..error.utf8_error().valid_up_to()];
        // `valid` is UTF-8 by construction; the column counts characters, as the model
        // crate's messages do.
        let text = String::from_utf8_lossy(valid);
        let line = text.matches('\n').count() + 1;
        let column = text.rsplit('\n').next().unwrap_or("").chars().count() + 1;
        anyhow!(
            "{display}:{line}:{column}: the file is not valid UTF-8 (byte 0x{:02x}); save it \
             as UTF-8",
            error.as_bytes()[valid.len()]
        )
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
        let mut file = tempfile::NamedTempFile::new().unwrap();
        file.write_all(&vec![b'#'; MAX_FILE_BYTES as usize + 1])
            .unwrap();
        let error = read_source(file.path(), "big.toml")
            .unwrap_err()
            .to_string();
        assert!(error.contains("larger than 1 MiB"), "{error}");
        let mut file = tempfile::NamedTempFile::new().unwrap();
        file.write_all(&vec![b'#'; MAX_FILE_BYTES as usize])
            .unwrap();
        assert!(read_source(file.path(), "ok.toml").is_ok());
    }

    #[test]
    fn missing_files_are_named() {
        let error =
            read_source(Path::new("/nonexistent/m.toml"), "/nonexistent/m.toml").unwrap_err();
        assert!(format!("{error:#}").contains("/nonexistent/m.toml"));
    }
}
