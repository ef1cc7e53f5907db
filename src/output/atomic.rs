//! Atomic file replacement, used for every file the crate writes (CSV tables, SVG figures,
//! compact flow fields, cavity reports).
//!
//! The contents go to a fresh sibling temporary file `.<name>.pseudorigid-tmp-<pid>-<thread>-<n>`
//! (unique per call: process id, thread and a process-wide counter, opened with `create_new`),
//! which is flushed to disk (`fsync`) and renamed over the target; then the folder itself is
//! synced so that the rename survives a power cut. On POSIX file systems `rename` within one
//! folder is atomic, so a reader sees the old file or the new one, never a mixture, and
//! concurrent writers (threads or processes) each replace the file whole.
//!
//! A temporary file outlives its call only when the process is killed mid-write. The next write
//! into the same folder removes such leftovers: temporary files of processes that no longer run
//! (checked through `/proc` where it exists) or, without `/proc`, older than [`STALE_AFTER`].

use super::OutputError;
use std::fs::OpenOptions;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// Marker between the target's name and the writer's identity in a temporary file's name.
const TMP_MARKER: &str = ".pseudorigid-tmp-";

/// Without `/proc`, a temporary file this old is taken to be a leftover (no write of ours
/// takes an hour).
pub const STALE_AFTER: Duration = Duration::from_secs(3600);

/// Calls so far in this process; makes temporary names unique across threads.
static CALLS: AtomicU64 = AtomicU64::new(0);

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Write `contents` to `path` atomically, creating the parent folder if needed.
pub fn write_atomic(path: impl AsRef<Path>, contents: &[u8]) -> Result<(), OutputError> {
    let path = path.as_ref();
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let Some(name) = path.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return Err(io_error(path)(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the path does not name a file",
        )));
    };
    std::fs::create_dir_all(dir).map_err(io_error(dir))?;
    remove_stale_temporaries(dir);
    let tmp = dir.join(temporary_name(&name));
    let result = write_then_rename(&tmp, path, contents);
    if result.is_err() {
        // Best effort: do not leave the temporary file behind; the original error matters.
        let _ = std::fs::remove_file(&tmp);
        return result;
    }
    sync_dir(dir)
}

/// `.<name>.pseudorigid-tmp-<pid>-<thread>-<n>`.
fn temporary_name(name: &str) -> String {
    let thread = format!("{:?}", std::thread::current().id());
    let thread: String = thread.chars().filter(char::is_ascii_digit).collect();
    let n = CALLS.fetch_add(1, Ordering::Relaxed);
    format!(".{name}{TMP_MARKER}{}-{thread}-{n}", std::process::id())
}

fn write_then_rename(tmp: &Path, path: &Path, contents: &[u8]) -> Result<(), OutputError> {
    let mut file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(tmp)
        .map_err(io_error(tmp))?;
    file.write_all(contents).map_err(io_error(tmp))?;
    file.sync_all().map_err(io_error(tmp))?;
    drop(file);
    std::fs::rename(tmp, path).map_err(io_error(path))
}

/// Make the rename durable: fsync the folder that holds the new entry (POSIX; elsewhere the
/// rename is as durable as the platform makes it).
fn sync_dir(dir: &Path) -> Result<(), OutputError> {
    #[cfg(unix)]
    std::fs::File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(io_error(dir))?;
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

/// The process id recorded in a temporary file's name, if it is one of ours.
fn temporary_owner(file_name: &str) -> Option<u32> {
    let (_, identity) = file_name.strip_prefix('.')?.rsplit_once(TMP_MARKER)?;
    identity.split('-').next()?.parse().ok()
}

/// Remove leftovers of killed writers in `dir` (best effort: a failure here must not stop the
/// write, and a concurrent writer may remove the same file first).
fn remove_stale_temporaries(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let proc_root = Path::new("/proc");
    let have_proc = proc_root.join("self").exists();
    let me = std::process::id();
    for entry in entries.filter_map(Result::ok) {
        let name = entry.file_name();
        let Some(owner) = temporary_owner(&name.to_string_lossy()) else {
            continue;
        };
        // Our own process's temporaries belong to writes in flight on other threads.
        if owner == me {
            continue;
        }
        let stale = if have_proc {
            !proc_root.join(owner.to_string()).exists()
        } else {
            entry
                .metadata()
                .and_then(|m| m.modified())
                .ok()
                .and_then(|t| t.elapsed().ok())
                .is_some_and(|age| age > STALE_AFTER)
        };
        if stale {
            let _ = std::fs::remove_file(dir.join(PathBuf::from(&name)));
        }
    }
}
