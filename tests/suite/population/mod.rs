//! The population runner (src/population).

#[cfg(feature = "mesh")]
mod adequacy;
mod batch;
mod binomial;
mod checkpoint;
#[cfg(feature = "parquet")]
mod columns;
mod common;
mod gci;
mod injection;
mod release;
mod runner;
