//! `rtl-cost`: the cost subcommands of `rtl-gen` (synth, fit, boxes, cull,
//! depth, per-ray, dot-styles, charts) under their earlier name.

use clap::Parser;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "rtl-cost",
    about = "Hardware cost against accuracy of the generated units (the same as the cost subcommands of `rtl-gen`)"
)]
struct Cli {
    #[command(subcommand)]
    command: cost::cli::Command,
}

fn main() -> ExitCode {
    cost::cli::main(Cli::parse().command)
}
