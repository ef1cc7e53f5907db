//! Tests that cut across the modules of `src/` (see the crate's doc comment).

mod convergence;
#[cfg(all(feature = "mesh", feature = "plot"))]
mod fuzz_api;
mod hard_cases;
mod properties;
mod slurm;
