//! Command-line grammar (clap) and dispatch: the commands and their flags
//! are in [`crate::commands`].

use clap::{Parser, Subcommand};

use crate::commands::{
    compare, export, grid, info, pack_friction, render, rheology, run, slider, sweep,
};
use crate::CliError;

/// floe: sea-ice floes with rate-and-state friction.
#[derive(Debug, Parser)]
#[command(name = "floe", version, about, propagate_version = true)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Top-level commands.
#[derive(Debug, Subcommand)]
#[allow(missing_docs)] // A variant's help is its Args' doc comment.
pub enum Command {
    /// Spring-slider experiments of Lishman, Sammonds & Feltham (2011).
    #[command(subcommand)]
    Slider(slider::Command),
    #[command(allow_negative_numbers = true)]
    Run(run::Args),
    #[command(allow_negative_numbers = true)]
    Info(info::Args),
    #[command(allow_negative_numbers = true)]
    Compare(compare::Args),
    #[command(allow_negative_numbers = true)]
    Sweep(sweep::Args),
    #[command(allow_negative_numbers = true)]
    Rheology(rheology::Args),
    #[command(allow_negative_numbers = true)]
    PackFriction(pack_friction::Args),
    #[command(allow_negative_numbers = true)]
    Grid(grid::Args),
    #[command(allow_negative_numbers = true)]
    Render(render::Args),
    Export(export::Args),
}

/// Runs a parsed command; returns what to print on standard output.
pub fn execute(cli: Cli) -> Result<String, CliError> {
    if !matches!(cli.command, Command::Run(_)) {
        crate::processes::refuse_several()?;
    }
    match cli.command {
        Command::Slider(command) => command.run(),
        Command::Run(args) => args.run(),
        Command::Info(args) => args.run(),
        Command::Compare(args) => args.run(),
        Command::Sweep(args) => args.run(),
        Command::Rheology(args) => args.run(),
        Command::PackFriction(args) => args.run(),
        Command::Grid(args) => args.run(),
        Command::Render(args) => args.run(),
        Command::Export(args) => args.run(),
    }
}
