//! The population runner (src/population).

mod checkpoint;
mod common;
mod release;
mod runner;
