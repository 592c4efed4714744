//! The output directory, whose files are complete or absent, and which one process writes at a
//! time.
//!
//! - **One writer.** A directory is locked (an advisory `flock` on the directory itself) while
//!   a command writes into it; a second `zenosim` writing into it fails at once, saying so,
//!   instead of mixing its files with the first's. Within one process the lock is shared (a run
//!   and the plots it draws).
//! - **Complete files.** Each file is written to a temporary name of its own,
//!   `.<name>.<pid>-<n>.partial`, created exclusively (never an existing file, and never
//!   through a symlink planted under that name), synced, and renamed once complete; the
//!   directory is synced after the renames. A run renames its files only at its very end, so a
//!   run killed midway leaves the previous run's files as they were, and a temporary file that
//!   the next command writing into the directory removes.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Weak};

use anyhow::{anyhow, Context};

use crate::signals;

/// The directory a command writes to, locked while it exists.
pub struct OutputDir {
    dir: PathBuf,
    lock: Arc<DirLock>,
}

/// The lock on one directory: its open handle, `flock`ed.
struct DirLock {
    handle: File,
}

/// The directories this process holds locked (by canonical path), so that the plots a run
/// draws share the run's lock instead of waiting for it.
static HELD: Mutex<Vec<(PathBuf, Weak<DirLock>)>> = Mutex::new(Vec::new());

/// Numbers this process's temporary files apart.
static NEXT_PARTIAL: AtomicU64 = AtomicU64::new(0);

impl OutputDir {
    /// Creates `dir` (and its parents) and locks it. Files already there stay as they are,
    /// but temporary files left by a killed command, which no one is writing now.
    pub fn prepare(dir: &Path) -> anyhow::Result<Self> {
        fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the output directory {}", dir.display()))?;
        Self::existing(dir)
    }

    /// The directory `dir` as it is (to add files to a run's output), locked.
    pub fn existing(dir: &Path) -> anyhow::Result<Self> {
        let lock = lock(dir)?;
        let out = Self {
            dir: dir.to_path_buf(),
            lock,
        };
        out.remove_stale_partials();
        Ok(out)
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

    /// The path of the file `name` in this directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Starts writing the file `name`, under a temporary name of its own, created exclusively.
    pub fn create(&self, name: &str) -> anyhow::Result<(PartialFile, File)> {
        let target = self.dir.join(name);
        let (partial, file) = loop {
            let n = NEXT_PARTIAL.fetch_add(1, Ordering::Relaxed);
            let partial = self.dir.join(partial_name(name, n));
            // `create_new`: O_CREAT | O_EXCL, which fails on any existing entry, a symlink
            // included, instead of following it.
            match OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&partial)
            {
                Ok(file) => break (partial, file),
                Err(error) if error.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(error) => {
                    return Err(error)
                        .with_context(|| format!("cannot create {}", partial.display()))
                }
            }
        };
        Ok((
            PartialFile {
                _registered: signals::register(&partial),
                partial,
                target,
                dir: Arc::clone(&self.lock),
                committed: false,
            },
            file,
        ))
    }

    /// Removes the temporary files of commands that were killed: this process holds the lock,
    /// so no other is writing them. Best effort: one that cannot be removed stays.
    fn remove_stale_partials(&self) {
        let Ok(entries) = fs::read_dir(&self.dir) else {
            return;
        };
        let pid = std::process::id();
        let ours = format!(".{pid}-");
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(name) = name.to_str() else { continue };
            if name.starts_with('.') && name.ends_with(".partial") && !name.contains(&ours) {
                // `remove_file` removes a symlink itself, never what it points to.
                let _ = fs::remove_file(entry.path());
            }
        }
    }
}

/// The directory and the file name of `path` (`.` for a bare name): where a command writing one
/// file (`--out FILE`) writes it.
pub fn split(path: &Path) -> anyhow::Result<(PathBuf, String)> {
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| anyhow!("--out {}: not a file name", path.display()))?;
    Ok((dir, name.to_string()))
}

/// Writes `bytes` to `path` under a temporary name, renamed once complete.
pub fn write_file(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let (dir, name) = split(path)?;
    let out = OutputDir::prepare(&dir)?;
    let (partial, mut file) = out.create(&name)?;
    file.write_all(bytes)
        .with_context(|| format!("cannot write {}", path.display()))?;
    partial.commit(file)
}

/// Locks `dir` for this process, or shares the lock this process already holds on it.
fn lock(dir: &Path) -> anyhow::Result<Arc<DirLock>> {
    let key = fs::canonicalize(dir)
        .with_context(|| format!("cannot open the output directory {}", dir.display()))?;
    let mut held = HELD.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    held.retain(|(_, lock)| lock.strong_count() > 0);
    if let Some(lock) = held
        .iter()
        .find(|(path, _)| *path == key)
        .and_then(|(_, lock)| lock.upgrade())
    {
        return Ok(lock);
    }
    let handle = File::open(&key)
        .with_context(|| format!("cannot open the output directory {}", dir.display()))?;
    match handle.try_lock() {
        Ok(()) => {}
        Err(fs::TryLockError::WouldBlock) => {
            return Err(anyhow!(
                "{}: another zenosim is writing into this directory; wait until it ends, or \
                 write elsewhere (--out)",
                dir.display()
            ))
        }
        Err(fs::TryLockError::Error(error)) => {
            return Err(error)
                .with_context(|| format!("cannot lock the output directory {}", dir.display()))
        }
    }
    let lock = Arc::new(DirLock { handle });
    held.push((key, Arc::downgrade(&lock)));
    Ok(lock)
}

/// The temporary name of the file `name` while this process writes it: hidden, and its own.
fn partial_name(name: &str, n: u64) -> String {
    format!(".{name}.{}-{n}.partial", std::process::id())
}

/// A file being written under its temporary name; removed unless committed.
pub struct PartialFile {
    partial: PathBuf,
    target: PathBuf,
    /// The directory's lock, held until the file is renamed (and synced there).
    dir: Arc<DirLock>,
    committed: bool,
    /// For a second Ctrl-C, which removes the file at once ([`signals`]); unregistered when
    /// the file is dropped, after [`Drop`] has removed it or it was renamed.
    _registered: signals::Registered,
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

    /// Renames the finished file to its final name (a symlink under that name is replaced, not
    /// followed), and syncs the directory so that the rename is on disk.
    pub fn publish(mut self) -> anyhow::Result<()> {
        fs::rename(&self.partial, &self.target).with_context(|| {
            format!(
                "cannot rename {} to {}",
                self.partial.display(),
                self.target.display()
            )
        })?;
        self.committed = true;
        self.dir
            .handle
            .sync_all()
            .with_context(|| format!("cannot write {}", self.target.display()))
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

/// What a CSV writer writes into, one record at a time: its owner reads the record, measures it
/// (against `--max-output`) and takes it ([`Record::take_into`]) before the next.
#[derive(Clone, Default)]
pub struct Record(std::rc::Rc<std::cell::RefCell<Vec<u8>>>);

impl Record {
    /// The length of what was written since the last take, in bytes.
    pub fn len(&self) -> u64 {
        self.0.borrow().len() as u64
    }

    /// Writes what was written since the last take to `out`, and forgets it.
    pub fn take_into(&self, out: &mut impl Write) -> io::Result<()> {
        let mut bytes = self.0.borrow_mut();
        let written = out.write_all(&bytes);
        bytes.clear();
        written
    }

    /// Forgets what was written since the last take.
    pub fn clear(&self) {
        self.0.borrow_mut().clear();
    }
}

impl Write for Record {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}
