//! The integration tests of `pseudorigid`, as one crate (one binary, one link of the library).
//!
//! The module tree mirrors `src/`: the tests of `src/x/y.rs` are in `tests/suite/x/y.rs` (or
//! `tests/suite/x/y/mod.rs`), e.g. `src/flow/openfoam/` → `flow::openfoam`, `src/scenes/cavity/`
//! → `scenes::cavity`, `src/integrator/radau5.rs` → `integrator::radau5`. Run one module with
//! `cargo test --test suite scenes::cavity`, one test with its full path and `--exact`.
//!
//! - `common`: shared helpers (proptest strategies, independent reference computations,
//!   generated OpenFOAM cases in `common::build`); `population::common` is the population tests'
//!   settling-pipe set-up.
//! - `integrator::every_scheme`: the one harness run over every integrator; the tests of the
//!   integrator module itself are in `integrator` (`mod.rs`).
//! - `cli::run`: the `pseudorigid` command as a user runs it (killed, resumed, sharded).
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
//! All tests share one process: none may set environment variables or change the current
//! directory, and scratch folders carry the test's name (and the process id) so that no two
//! tests share one.

mod common;

#[cfg(feature = "cli")]
mod cli;
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
#[cfg(feature = "parallel")]
mod population;
mod reference;
mod scenes;
