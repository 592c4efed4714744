//! SIGINT and SIGTERM: the first stops the run (or sweep) at its next step, and the command
//! writes everything computed up to there with status `interrupted` (exit status 128 + the
//! signal: 130 for SIGINT, 143 for SIGTERM); a second one stops the process at once, removing
//! the temporary files it was writing, so that the previous results stay as they were.
//!
//! The handler only does what a signal handler may: atomic loads and stores, `unlink` and
//! `_exit`. The paths it removes are registered as C strings that are never freed (a command
//! writes a handful of files), so that the handler never reads freed memory; they are
//! registered only once the handlers are installed, so that a command without them (`zenosim
//! plot`), or a process drawing plots again and again (the fuzz target), leaks nothing.

use std::ffi::{c_char, c_int, CString};
use std::path::Path;
use std::ptr;
use std::sync::atomic::{AtomicBool, AtomicI32, AtomicPtr, Ordering};

/// Set by the first SIGINT or SIGTERM: the cancel flag of runs and sweeps.
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The signal that set [`INTERRUPTED`].
static SIGNAL: AtomicI32 = AtomicI32::new(0);

/// Set while the files of a command are renamed into place ([`committing`]): a second signal
/// then waits for the renames, which take milliseconds, instead of leaving half of them.
static COMMITTING: AtomicBool = AtomicBool::new(false);

/// A second signal that came while [`COMMITTING`]: the process ends once the renames are done.
static DEFERRED: AtomicI32 = AtomicI32::new(0);

/// Set by [`install`]: until then no handler reads [`PARTIALS`], and nothing is registered.
static INSTALLED: AtomicBool = AtomicBool::new(false);

/// The temporary files being written, removed by a second signal. A slot holds a leaked C
/// string or null.
static PARTIALS: [AtomicPtr<c_char>; 32] = [const { AtomicPtr::new(ptr::null_mut()) }; 32];

/// Installs the handlers: by the commands that stop at the flag (`run`, `sweep`), once they
/// start; the others keep the default (a Ctrl-C ends them at once).
pub fn install() {
    INSTALLED.store(true, Ordering::SeqCst);
    #[cfg(unix)]
    for signal in [libc::SIGINT, libc::SIGTERM] {
        // SAFETY: the handler is an `extern "C" fn(c_int)` that only makes async-signal-safe
        // calls; `signal` replaces the disposition of a signal this process does not otherwise
        // use.
        unsafe {
            libc::signal(
                signal,
                handler as extern "C" fn(c_int) as libc::sighandler_t,
            );
        }
    }
}

#[cfg(unix)]
extern "C" fn handler(signal: c_int) {
    if SIGNAL
        .compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst)
        .is_ok()
    {
        INTERRUPTED.store(true, Ordering::SeqCst);
        return;
    }
    // The second signal: at once, leaving no temporary file; after the renames under way.
    if COMMITTING.load(Ordering::SeqCst) {
        DEFERRED.store(signal, Ordering::SeqCst);
        return;
    }
    for slot in &PARTIALS {
        let path = slot.load(Ordering::SeqCst);
        if !path.is_null() {
            // SAFETY: a registered path is a valid C string that is never freed.
            unsafe {
                libc::unlink(path);
            }
        }
    }
    // SAFETY: `_exit` ends the process without running anything else.
    unsafe { libc::_exit(128 + signal) }
}

/// Runs `renames` (the files of a command put in place, the old ones removed) without a second
/// signal stopping it midway; if one came, the process ends after it.
pub fn committing<T>(renames: impl FnOnce() -> T) -> T {
    COMMITTING.store(true, Ordering::SeqCst);
    let result = renames();
    COMMITTING.store(false, Ordering::SeqCst);
    let deferred = DEFERRED.load(Ordering::SeqCst);
    if deferred != 0 {
        std::process::exit(128 + deferred);
    }
    result
}

/// The signal that interrupted the command, if one did.
pub fn received() -> Option<i32> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        signal => Some(signal),
    }
}

/// The exit status of a command interrupted by `signal`: 128 + its number.
pub fn exit_status(signal: i32) -> u8 {
    u8::try_from(128 + signal).unwrap_or(u8::MAX)
}

/// The name of `signal`, for messages.
pub fn name(signal: i32) -> &'static str {
    #[cfg(unix)]
    match signal {
        libc::SIGINT => return "SIGINT",
        libc::SIGTERM => return "SIGTERM",
        _ => {}
    }
    let _ = signal;
    "a signal"
}

/// A temporary file, registered to be removed by a second signal until it is dropped.
pub struct Registered(Option<usize>);

/// Registers `path` as being written (when the handlers are installed and a slot is free; a
/// path that is not registered is left to the next command to remove).
#[cfg(unix)]
pub fn register(path: &Path) -> Registered {
    use std::os::unix::ffi::OsStrExt;
    if !INSTALLED.load(Ordering::SeqCst) {
        // No handler to read it: a Ctrl-C ends the command at once.
        return Registered(None);
    }
    let Ok(c_path) = CString::new(path.as_os_str().as_bytes()) else {
        return Registered(None);
    };
    let raw = c_path.into_raw();
    for (k, slot) in PARTIALS.iter().enumerate() {
        if slot
            .compare_exchange(ptr::null_mut(), raw, Ordering::SeqCst, Ordering::SeqCst)
            .is_ok()
        {
            return Registered(Some(k));
        }
    }
    // SAFETY: `raw` came from `into_raw` just above and was not stored anywhere.
    drop(unsafe { CString::from_raw(raw) });
    Registered(None)
}

/// Registers nothing where there are no signals to handle.
#[cfg(not(unix))]
pub fn register(_path: &Path) -> Registered {
    Registered(None)
}

impl Drop for Registered {
    fn drop(&mut self) {
        if let Some(k) = self.0 {
            // The string is leaked, not freed: the handler may be reading it now.
            PARTIALS[k].store(ptr::null_mut(), Ordering::SeqCst);
        }
    }
}
