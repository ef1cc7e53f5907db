//! The population runner (src/population).

mod batch;
mod checkpoint;
mod common;
mod injection;
mod release;
mod runner;
