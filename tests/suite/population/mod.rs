//! The population runner (src/population).

mod batch;
mod checkpoint;
mod common;
mod release;
mod runner;
