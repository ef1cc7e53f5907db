//! The integration tests of `pseudorigid`, as one crate (one binary, one link of the library).
//!
//! The module tree mirrors `src/`: the tests of `src/x/y.rs` are in `tests/suite/x/y.rs` (or
//! `tests/suite/x/y/mod.rs`), e.g. `src/flow/openfoam/` → `flow::openfoam`, `src/studies/cavity/`
//! → `studies::cavity`, `src/integrator/radau5.rs` → `integrator::radau5`. Run one module with
//! `cargo test --test suite studies::cavity`, one test with its full path and `--exact`.
//!
//! - `common`: shared helpers (proptest strategies, independent reference computations,
//!   generated OpenFOAM cases in `common::build`); `population::common` is the population tests'
//!   settling-pipe set-up.
//! - `integrator::every_scheme`: the one harness run over every integrator; the tests of the
//!   integrator module itself are in `integrator` (`mod.rs`).
//! - `scene::run`: the `pseudorigid` command as a user runs it (killed, resumed, sharded).
//! - `cross`: tests that cut across the modules: whole-run physical properties
//!   (`cross::properties`), hard cases (`cross::hard_cases`), observed convergence orders of every
//!   integrator (`cross::convergence`), the seeded fuzzing of the public API (`cross::fuzz_api`),
//!   and the Slurm scripts of `cases/bifurcation/slurm` (`cross::slurm`).
//!
//! Modules of an optional layer are compiled only with its feature (`mesh`, `plot`, `parallel`,
//! `cli`), so `cargo check --no-default-features --all-targets` builds the rest. Snapshots live in
//! `snapshots/` next to the module that asserts them, proptest regressions next to their file;
//! the shipped test data stay in `tests/data`.
//!
//! All tests share one process and run on parallel threads: none may set environment variables,
//! change the current directory or install a process-wide panic hook that drops other tests'
//! messages (`cross::fuzz_api` silences only its own `fuzz-…` worker threads), and every scratch
//! folder is named after its test (under `CARGO_TARGET_TMPDIR`, or the system's temporary folder
//! with the process id), so no two tests share one. A test that needs a process of its own
//! spawns one: `population::checkpoint` re-runs this binary on its ignored `child_run`,
//! `scene::run` runs the `pseudorigid` command.

mod common;

mod contact;
mod cross;
mod diagnostics;
mod driver;
mod ellipsoid;
mod flow;
mod hydro;
mod integrator;
mod material;
#[cfg(feature = "plot")]
mod output;
mod particle;
#[cfg(feature = "parallel")]
mod population;
mod reference;
#[cfg(feature = "cli")]
mod scene;
mod studies;
