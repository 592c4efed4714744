//! The output directory, whose files are complete or absent: each is written to a temporary
//! name, synced, and renamed once complete. A run renames its files only at its very end, so
//! a run killed midway leaves the previous run's files as they were (and a hidden partial file,
//! which the next run overwrites).

use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};

use anyhow::Context;

/// The directory a run writes to.
pub struct OutputDir {
    dir: PathBuf,
}

impl OutputDir {
    /// Creates `dir` (and its parents). Files already there stay as they are: a temporary file
    /// left by a killed run is overwritten when the same file is written again.
    pub fn prepare(dir: &Path) -> anyhow::Result<Self> {
        fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the output directory {}", dir.display()))?;
        Ok(Self::existing(dir))
    }

    /// Removes the files `names` of this directory, if they exist.
    pub fn remove(&self, names: impl IntoIterator<Item = String>) -> anyhow::Result<()> {
        for name in names {
            let old = self.dir.join(name);
            match fs::remove_file(&old) {
                Err(error) if error.kind() != io::ErrorKind::NotFound => {
                    return Err(error)
                        .with_context(|| format!("cannot remove the old {}", old.display()))
                }
                _ => {}
            }
        }
        Ok(())
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
        let partial = self.dir.join(partial_name(name));
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

/// The temporary name of the file `name` while it is written.
fn partial_name(name: &str) -> String {
    format!(".{name}.partial")
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

    /// The file is complete: it is synced to disk, and stays under its temporary name until
    /// [`PartialFile::publish`].
    pub fn finish(self, file: File) -> anyhow::Result<Self> {
        file.sync_all()
            .with_context(|| format!("cannot write {}", self.target.display()))?;
        Ok(self)
    }

    /// Renames the finished file to its final name.
    pub fn publish(mut self) -> anyhow::Result<()> {
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

    /// [`PartialFile::finish`], then [`PartialFile::publish`].
    pub fn commit(self, file: File) -> anyhow::Result<()> {
        self.finish(file)?.publish()
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
