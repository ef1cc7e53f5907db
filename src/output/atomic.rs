//! Atomic file replacement: write a sibling temporary file, flush it, then rename it over the
//! target. On POSIX file systems `rename` within one folder is atomic.

use super::OutputError;
use std::io::Write;
use std::path::Path;

/// Write `contents` to `path` atomically, creating the parent folder if needed.
pub fn write_atomic(path: impl AsRef<Path>, contents: &[u8]) -> Result<(), OutputError> {
    let path = path.as_ref();
    let io = |p: &Path| {
        let p = p.to_path_buf();
        move |source| OutputError::Io { path: p, source }
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    let result = (|| {
        let mut file = std::fs::File::create(&tmp).map_err(io(&tmp))?;
        file.write_all(contents).map_err(io(&tmp))?;
        file.sync_all().map_err(io(&tmp))?;
        std::fs::rename(&tmp, path).map_err(io(path))
    })();
    if result.is_err() {
        // Best effort: do not leave the temporary file behind; the original error matters.
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
