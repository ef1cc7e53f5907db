//! The code fingerprint sealed into checkpoints and result caches
//! (`population::seal::VERSION`): the crate version and a hash of every file under `src/`. A
//! cached run or a checkpoint written by other code (the same version number, a different
//! source) is then refused, not returned as this code's results: the bifurcation figures'
//! run cache was keyed by the version number alone and handed earlier code's records to new
//! code.
//!
//! The hash is 64-bit FNV-1a (Fowler, Noll & Vo) over each file's path relative to `src/` and
//! its bytes, in sorted path order, each part preceded by its length: the same sources give
//! the same fingerprint on every machine. Written out here (five lines) rather than taken
//! from the `fnv` crate, which a build script would compile a second time, for the host.

use std::path::{Path, PathBuf};

/// FNV-1a's 64-bit offset basis and prime.
const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const PRIME: u64 = 0x0000_0100_0000_01b3;

fn fnv1a(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h = (h ^ u64::from(b)).wrapping_mul(PRIME);
    }
    h
}

/// Every file under `dir`, recursively (the source tree: no links out of it).
fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("build.rs: cannot read {}: {e}", dir.display()));
    for entry in entries {
        let path = entry
            .unwrap_or_else(|e| panic!("build.rs: in {}: {e}", dir.display()))
            .path();
        if path.is_dir() {
            files(&path, out);
        } else {
            out.push(path);
        }
    }
}

fn main() {
    let src = Path::new("src");
    println!("cargo:rerun-if-changed=src");
    let mut paths = Vec::new();
    files(src, &mut paths);
    paths.sort();
    let mut h = OFFSET;
    for path in &paths {
        let relative = path
            .strip_prefix(src)
            .unwrap_or(path)
            .to_string_lossy()
            .replace('\\', "/");
        let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("build.rs: cannot read {}: {e}", path.display()));
        for part in [relative.as_bytes(), bytes.as_slice()] {
            h = fnv1a(h, &(part.len() as u64).to_le_bytes());
            h = fnv1a(h, part);
        }
    }
    println!("cargo:rustc-env=PSEUDORIGID_SOURCE_HASH={h:016x}");
}
