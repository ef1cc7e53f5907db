//! The `pseudorigid` command (see [`pseudorigid::cli`]).

use clap::Parser;
use pseudorigid::cli::{Cli, execute};
use std::process::ExitCode;

fn main() -> ExitCode {
    match execute(Cli::parse()) {
        Ok(line) => {
            println!("{line}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("pseudorigid: {e}");
            ExitCode::FAILURE
        }
    }
}
