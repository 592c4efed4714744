//! Reading a model file's text: at most [`MAX_FILE_BYTES`], UTF-8.

use std::fmt;
use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

use crate::error::{Location, ModelError};

/// The largest model file read (1 MiB): model files are a few kilobytes; anything larger is a
/// wrong file, and refusing it early keeps a mistaken path from filling memory.
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// Why a model file's text could not be had.
#[derive(Debug)]
pub enum ReadError {
    /// The file could not be opened or read (missing, a directory, no permission).
    Io(io::Error),
    /// The file is larger than [`MAX_FILE_BYTES`] (a [`Location::File`] error), or not UTF-8
    /// (a [`Location::At`] error at the first bad byte, its column in characters).
    Invalid(ModelError),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(error) => error.fmt(f),
            Self::Invalid(error) => error.fmt(f),
        }
    }
}

impl std::error::Error for ReadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io(error) => Some(error),
            Self::Invalid(error) => Some(error),
        }
    }
}

/// Reads the model file at `path` (at most `MAX_FILE_BYTES + 1` bytes), named `display` in
/// messages, and checks that it is UTF-8, to be given to [`crate::parse_model`].
pub fn read_source(path: &Path, display: &str) -> Result<String, ReadError> {
    let file = File::open(path).map_err(ReadError::Io)?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(ReadError::Io)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(ReadError::Invalid(ModelError {
            file: display.into(),
            location: Location::File,
            message: "the file is larger than 1 MiB; a model file is a few kilobytes: check \
                      that this is the right file"
                .into(),
            help: None,
            snippet: None,
        }));
    }
    String::from_utf8(bytes).map_err(|error| {
        let valid = &error.as_bytes()[..error.utf8_error().valid_up_to()];
        // `valid` is UTF-8 by construction; the column counts characters, as the other
        // messages do.
        let text = String::from_utf8_lossy(valid);
        let line = text.matches('\n').count() + 1;
        let column = text.rsplit('\n').next().unwrap_or("").chars().count() + 1;
        ReadError::Invalid(ModelError {
            file: display.into(),
            location: Location::At {
                line,
                column,
                key: None,
            },
            message: format!(
                "the file is not valid UTF-8 (byte 0x{:02x}); save it as UTF-8",
                error.as_bytes()[valid.len()]
            ),
            help: None,
            snippet: None,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn temp(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("zenosim-source-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::File::create(&path)
            .unwrap()
            .write_all(bytes)
            .unwrap();
        path
    }

    #[test]
    fn non_utf8_is_placed() {
        let path = temp("latin1.toml", b"name = \"a\"\nx = \"\xe9t\xe9\"\n");
        let Err(ReadError::Invalid(error)) = read_source(&path, "m.toml") else {
            panic!("read as UTF-8")
        };
        assert_eq!(error.position(), Some((2, 6)));
        let text = error.to_string();
        assert!(text.starts_with("m.toml:2:6: "), "{text}");
        assert!(text.contains("UTF-8"), "{text}");
    }

    #[test]
    fn large_files_are_refused() {
        let path = temp("big.toml", &vec![b'#'; MAX_FILE_BYTES as usize + 1]);
        let error = read_source(&path, "big.toml").unwrap_err().to_string();
        assert!(error.contains("larger than 1 MiB"), "{error}");
        let path = temp("ok.toml", &vec![b'#'; MAX_FILE_BYTES as usize]);
        assert!(read_source(&path, "ok.toml").is_ok());
    }

    #[test]
    fn missing_files_are_io_errors() {
        let error = read_source(Path::new("/nonexistent/m.toml"), "/nonexistent/m.toml");
        assert!(
            matches!(&error, Err(ReadError::Io(e)) if e.kind() == io::ErrorKind::NotFound),
            "{error:?}"
        );
    }
}
