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
//!   the next command writing into the directory removes (only names of that form: another
//!   program's `.thesis.docx.partial` is not zenosim's to remove).
//! - **Only regular files are replaced.** A final name that is a directory, a FIFO, a device
//!   or a socket is refused before anything is written (`--out /dev/null` would otherwise
//!   replace the device by a file, for a command run as root); a symlink there is replaced
//!   itself, never followed.
//! - **Files that belong together appear together.** A run's files replace the previous ones
//!   by renames back to back ([`OutputDir::replace`]): the old `summary.json` is moved aside,
//!   the trajectory and the new summary renamed into place, and only then is the directory
//!   synced and are the old files deleted. A folder is without `summary.json` only for the
//!   microseconds of those renames, all that a SIGKILL can catch (a trajectory alone, which
//!   no reader takes for a complete run). A crash of the machine before the sync keeps the
//!   previous files or, on file systems that journal their metadata in order (ext4, XFS),
//!   the renames done up to then.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Weak};
use std::time::{Duration, Instant};

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

    /// Puts the finished `files` in place of the previous ones, `retired` first out of sight
    /// (the previous file that vouches for the others, `summary.json`): it is moved aside, the
    /// files are renamed to their final names in their order, back to back, and the directory
    /// is synced once. Between `retired` leaving and the last file arriving there are only
    /// those renames, microseconds: the previous files that `files` replace are hard-linked
    /// aside beforehand, so that no rename frees a file's blocks (milliseconds for a large
    /// one), and they and `retired` are deleted after the sync. Those not renamed after an
    /// error are removed.
    pub fn replace(
        &self,
        retired: &str,
        files: impl IntoIterator<Item = PartialFile>,
    ) -> anyhow::Result<()> {
        let files: Vec<PartialFile> = files.into_iter().collect();
        let mut aside = Aside(Vec::new());
        for file in &files {
            let name = file.target.file_name().and_then(|n| n.to_str());
            if let Some(name) = name.filter(|&name| name != retired) {
                // Best effort: where hard links fail, the rename frees the old file itself.
                if let Some(link) = self.set_aside(name, |from, to| fs::hard_link(from, to)) {
                    aside.0.push(link);
                }
            }
        }
        // The renames, back to back.
        if let Some(moved) = self.set_aside(retired, |from, to| fs::rename(from, to)) {
            aside.0.push(moved);
        } else if fs::symlink_metadata(self.dir.join(retired)).is_ok() {
            self.remove([retired.to_string()])?;
        }
        for mut file in files {
            file.rename()?;
        }
        sync(&self.lock, &self.dir)
    }

    /// Moves or links (`how`) the file `name` to a temporary name of its own, which it returns;
    /// `None` if there is no such file or it cannot be done.
    fn set_aside(
        &self,
        name: &str,
        how: impl Fn(&Path, &Path) -> io::Result<()>,
    ) -> Option<PathBuf> {
        let from = self.dir.join(name);
        loop {
            let n = NEXT_PARTIAL.fetch_add(1, Ordering::Relaxed);
            let to = self.dir.join(partial_name(name, n));
            match how(&from, &to) {
                Ok(()) => {
                    #[cfg(test)]
                    tests::trace(format!("aside {name}"));
                    return Some(to);
                }
                Err(error) if error.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(_) => return None,
            }
        }
    }

    /// The path of the file `name` in this directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Starts writing the file `name`, under a temporary name of its own, created exclusively.
    pub fn create(&self, name: &str) -> anyhow::Result<(PartialFile, File)> {
        let target = self.dir.join(name);
        replaceable(&target)?;
        let (partial, registered, file) = loop {
            let n = NEXT_PARTIAL.fetch_add(1, Ordering::Relaxed);
            let partial = self.dir.join(partial_name(name, n));
            // Registered before it exists, so that a second signal arriving between the
            // creation and the registration cannot leave it behind (unlinking a name not yet
            // created does nothing).
            let registered = signals::register(&partial);
            #[cfg(test)]
            tests::trace(format!("register {name}"));
            // `create_new`: O_CREAT | O_EXCL, which fails on any existing entry, a symlink
            // included, instead of following it.
            match OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&partial)
            {
                Ok(file) => {
                    #[cfg(test)]
                    tests::trace(format!("create {name}"));
                    break (partial, registered, file);
                }
                // Not ours: dropping the registration keeps a second signal off that entry.
                Err(error) if error.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(error) => {
                    return Err(error)
                        .with_context(|| format!("cannot create {}", partial.display()))
                }
            }
        };
        Ok((
            PartialFile {
                _registered: registered,
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
            if is_ours(name) && !name.contains(&ours) {
                // `remove_file` removes a symlink itself, never what it points to.
                let _ = fs::remove_file(entry.path());
            }
        }
    }
}

/// Whether `name` is of the form zenosim gives its temporary files, `.<name>.<pid>-<n>.partial`
/// ([`partial_name`]).
fn is_ours(name: &str) -> bool {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    name.strip_prefix('.')
        .and_then(|n| n.strip_suffix(".partial"))
        .and_then(|stem| stem.rsplit_once('.'))
        .and_then(|(file, tag)| Some((file, tag.split_once('-')?)))
        .is_some_and(|(file, (pid, n))| !file.is_empty() && digits(pid) && digits(n))
}

/// An error unless `target` is absent, a regular file or a symlink: what a rename may replace.
fn replaceable(target: &Path) -> anyhow::Result<()> {
    let Ok(meta) = fs::symlink_metadata(target) else {
        return Ok(());
    };
    let kind = meta.file_type();
    if kind.is_file() || kind.is_symlink() {
        return Ok(());
    }
    let what = if kind.is_dir() {
        "a directory"
    } else {
        special_kind(&kind)
    };
    Err(anyhow!(
        "cannot write {}: it exists and is {what}, not a regular file; zenosim writes a file by \
         replacing it whole, which it does only to regular files: choose another path",
        target.display()
    ))
}

/// What a file that is neither a regular file, a directory nor a symlink is.
#[cfg(unix)]
fn special_kind(kind: &fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_fifo() {
        "a FIFO"
    } else if kind.is_char_device() {
        "a character device"
    } else if kind.is_block_device() {
        "a block device"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

/// What a file that is neither a regular file, a directory nor a symlink is.
#[cfg(not(unix))]
fn special_kind(_: &fs::FileType) -> &'static str {
    "a special file"
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

/// How long a lock that another process holds is waited for. A process that forks (a program
/// that draws in-process while another of its threads starts commands, as the tests do) shares
/// its lock with the child until the child executes its command, for a moment: a lock released
/// and taken again in that moment would otherwise be refused.
const LOCK_PATIENCE: Duration = Duration::from_millis(250);

/// Locks `dir` for this process, or shares the lock this process already holds on it; waits
/// [`LOCK_PATIENCE`] for another process's.
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
    let start = Instant::now();
    loop {
        match handle.try_lock() {
            Ok(()) => break,
            Err(fs::TryLockError::WouldBlock) if start.elapsed() < LOCK_PATIENCE => {
                std::thread::sleep(Duration::from_millis(5));
            }
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
    }
    let lock = Arc::new(DirLock { handle });
    held.push((key, Arc::downgrade(&lock)));
    Ok(lock)
}

/// The previous files set aside by [`OutputDir::replace`], deleted when it ends (a SIGKILL
/// before leaves them to the next command, as temporary files).
struct Aside(Vec<PathBuf>);

impl Drop for Aside {
    fn drop(&mut self) {
        for path in &self.0 {
            #[cfg(test)]
            tests::trace("delete".to_string());
            let _ = fs::remove_file(path);
        }
    }
}

/// Syncs the directory of `lock`, so that the renames in it are on disk.
fn sync(lock: &DirLock, dir: &Path) -> anyhow::Result<()> {
    #[cfg(test)]
    tests::trace("sync".to_string());
    lock.handle
        .sync_all()
        .with_context(|| format!("cannot sync the output directory {}", dir.display()))
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
    /// [`OutputDir::replace`] renames it.
    pub fn finish(self, file: File) -> anyhow::Result<Self> {
        file.sync_all()
            .with_context(|| format!("cannot write {}", self.target.display()))?;
        Ok(self)
    }

    /// Renames the finished file to its final name (a symlink under that name is replaced, not
    /// followed); the directory is still to be synced.
    fn rename(&mut self) -> anyhow::Result<()> {
        #[cfg(test)]
        tests::trace(format!("rename {}", self.target.display()));
        // Checked again: the name may have been taken since the file was created.
        replaceable(&self.target)?;
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

    /// [`PartialFile::finish`], then renames the file to its final name and syncs the
    /// directory (a command that writes one file; [`OutputDir::replace`] for a run's).
    pub fn commit(mut self, file: File) -> anyhow::Result<()> {
        self = self.finish(file)?;
        self.rename()?;
        let dir = self.target.parent().unwrap_or(Path::new("."));
        sync(&self.dir, dir)
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

#[cfg(test)]
mod tests {
    use std::cell::RefCell;

    use super::*;

    thread_local! {
        /// The renames and syncs of this thread, in order.
        static TRACE: RefCell<Vec<String>> = const { RefCell::new(Vec::new()) };
    }

    pub(super) fn trace(what: String) {
        TRACE.with(|trace| trace.borrow_mut().push(what));
    }

    fn traced() -> Vec<String> {
        TRACE.with(|trace| std::mem::take(&mut *trace.borrow_mut()))
    }

    /// Regression (the kill loop of tests/kill.rs, 6 runs in 40): a second Ctrl-C that came
    /// between a temporary file's creation and its registration for removal left the file
    /// (`.summary.json.<pid>-1.partial`) behind. The name is now registered first.
    #[test]
    fn a_second_signal_left_a_partial_created_before_it_was_registered() {
        let dir = tempfile::tempdir().unwrap();
        let out = OutputDir::prepare(dir.path()).unwrap();
        traced();
        let (partial, _file) = out.create("summary.json").unwrap();
        assert_eq!(traced(), ["register summary.json", "create summary.json"]);
        drop(partial);
    }

    /// Regression (the kill loop of tests/kill.rs): a run removed the old summary.json, renamed
    /// its trajectory over the old one (freeing the old file's blocks) and synced the directory
    /// before renaming its summary: for those milliseconds (1 to 10 on ext4 here) the folder
    /// held a trajectory and no summary.json, and a SIGKILL then left it so (26 of 41 SIGKILLs
    /// that landed in the last 40 % of a 60 ms run). Now only renames come between the old
    /// summary leaving and the new one arriving (50 to 130 µs; 1 of 124 such SIGKILLs): the old
    /// trajectory is linked aside before, and the directory synced and the old files deleted
    /// after.
    #[test]
    fn a_sync_between_the_renames_left_no_summary_for_milliseconds() {
        let dir = tempfile::tempdir().unwrap();
        let path = |name: &str| dir.path().join(name);
        fs::write(path("trajectory.csv"), "old trajectory").unwrap();
        fs::write(path("summary.json"), "old summary").unwrap();
        let out = OutputDir::prepare(dir.path()).unwrap();
        let mut finished = Vec::new();
        for name in ["trajectory.csv", "summary.json"] {
            let (partial, mut file) = out.create(name).unwrap();
            file.write_all(format!("new {name}").as_bytes()).unwrap();
            finished.push(partial.finish(file).unwrap());
        }
        traced();
        out.replace("summary.json", finished).unwrap();
        let shown = |name: &str| path(name).display().to_string();
        assert_eq!(
            traced(),
            [
                "aside trajectory.csv".to_string(),
                "aside summary.json".to_string(),
                format!("rename {}", shown("trajectory.csv")),
                format!("rename {}", shown("summary.json")),
                "sync".to_string(),
                "delete".to_string(),
                "delete".to_string(),
            ]
        );
        let mut names: Vec<String> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["summary.json", "trajectory.csv"]);
        assert_eq!(fs::read(path("summary.json")).unwrap(), b"new summary.json");
        assert_eq!(
            fs::read(path("trajectory.csv")).unwrap(),
            b"new trajectory.csv"
        );

        // Into an empty directory: nothing to set aside.
        let empty = tempfile::tempdir().unwrap();
        let out = OutputDir::prepare(empty.path()).unwrap();
        let (partial, file) = out.create("summary.json").unwrap();
        let finished = partial.finish(file).unwrap();
        traced();
        out.replace("summary.json", [finished]).unwrap();
        let shown = empty.path().join("summary.json").display().to_string();
        assert_eq!(traced(), [format!("rename {shown}"), "sync".to_string()]);
    }
}
