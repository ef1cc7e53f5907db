//! The `pseudorigid` command as the command-line tests run it: one call, its output, the files
//! a finished run writes and the chunks of a checkpoint folder.

use std::path::Path;
use std::process::{Command, Output};

/// The command built for the tests.
pub const BIN: &str = env!("CARGO_BIN_EXE_pseudorigid");

/// Run the command in `dir` with `args`.
pub fn pseudorigid(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN).current_dir(dir).args(args).output().unwrap()
}

/// The standard output of a call that must have succeeded (else its standard error).
pub fn ok(out: Output) -> String {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// The files a finished run writes into `out`, by name.
pub fn results(out: &Path) -> Vec<(String, Vec<u8>)> {
    [
        "records.parquet",
        "frames.parquet",
        "particles.pvd",
        "vtk/trajectories.vtp",
    ]
    .iter()
    .map(|f| (f.to_string(), std::fs::read(out.join(f)).unwrap()))
    .collect()
}

/// Chunks of a checkpoint folder (none if it does not exist yet).
pub fn chunks(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |d| {
        d.filter_map(Result::ok)
            .filter(|e| e.file_name().to_string_lossy().starts_with("chunk-"))
            .count()
    })
}
