//! The output directory, whose files are complete or absent: each is written to a temporary
//! name and renamed once complete.

use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};

use anyhow::Context;

/// The directory a run writes to.
pub struct OutputDir {
    dir: PathBuf,
}

impl OutputDir {
    /// Creates `dir` (and its parents) and removes the files of `stale` that an earlier run
    /// left (its `summary.json`, its plots), so that the files beside a `summary.json` always
    /// belong to it.
    pub fn prepare(dir: &Path, stale: &[String]) -> anyhow::Result<Self> {
        fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the output directory {}", dir.display()))?;
        for name in stale {
            let old = dir.join(name);
            match fs::remove_file(&old) {
                Err(error) if error.kind() != io::ErrorKind::NotFound => {
                    return Err(error).with_context(|| {
                        format!("cannot remove the old {} before the run", old.display())
                    })
                }
                _ => {}
            }
        }
        Ok(Self::existing(dir))
    }

    /// The directory `dir`, as it is (to add files to a run's output).
    pub fn existing(dir: &Path) -> Self {
        Self {
            dir: dir.to_path_buf(),
        }
    }

    /// The path of the file `name` in this directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Starts writing the file `name`, under the temporary name `.<name>.partial`.
    pub fn create(&self, name: &str) -> anyhow::Result<(PartialFile, File)> {
        let partial = self.dir.join(format!(".{name}.partial"));
        let target = self.dir.join(name);
        let file = File::create(&partial)
            .with_context(|| format!("cannot create {}", partial.display()))?;
        Ok((
            PartialFile {
                partial,
                target,
                committed: false,
            },
            file,
        ))
    }
}

/// A file being written under its temporary name; removed unless committed.
pub struct PartialFile {
    partial: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl PartialFile {
    /// The final path.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The file is complete: it is synced to disk and renamed to its final name.
    pub fn commit(mut self, file: File) -> anyhow::Result<()> {
        file.sync_all()
            .with_context(|| format!("cannot write {}", self.target.display()))?;
        drop(file);
        fs::rename(&self.partial, &self.target).with_context(|| {
            format!(
                "cannot rename {} to {}",
                self.partial.display(),
                self.target.display()
            )
        })?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for PartialFile {
    fn drop(&mut self) {
        if !self.committed {
            // Best effort: the error that got here is the one to report.
            let _ = fs::remove_file(&self.partial);
        }
    }
}
