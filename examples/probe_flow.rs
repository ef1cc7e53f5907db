//! Probe an OpenFOAM case by hand: u and ∇u at listed points (the same as
//! `pseudorigid probe`; see [`pseudorigid::cli::probe`] for the file formats).
//!
//! ```text
//! cargo run --release --example probe_flow -- CASE_DIR TIME POINTS.csv OUT.csv [--cellwise]
//! ```

use pseudorigid::cli::probe::probe;
use std::path::Path;

const USAGE: &str = "usage: probe_flow CASE_DIR TIME|latest POINTS.csv OUT.csv [--cellwise]";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (cellwise, args) = match args.split_last() {
        Some((last, rest)) if last == "--cellwise" => (true, rest),
        _ => (false, args.as_slice()),
    };
    let [case_dir, time, points, out] = args else {
        return Err(USAGE.into());
    };
    eprintln!(
        "{}",
        probe(Path::new(case_dir), time, Path::new(points), Path::new(out), cellwise)?
    );
    Ok(())
}
