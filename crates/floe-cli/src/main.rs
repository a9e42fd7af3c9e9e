//! The `floe` binary: parse, run, print; one message and a non-zero exit on error.

use std::process::ExitCode;

use clap::Parser;
use floe_cli::cli::{execute, Cli};

fn main() -> ExitCode {
    let cli = Cli::parse();
    match execute(cli) {
        Ok(out) => {
            if !out.is_empty() {
                println!("{out}");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
