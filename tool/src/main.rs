//! `rtl-gen`: the one command of the project. Its subcommands are the
//! flow's (`rtl_flow::cli`: list, emit, check, sim, golden, vectors,
//! convert, merge-reports, replay, transform-accuracy), the renderer's
//! (`scene::cli`: render, hybrid, rtl-loop, bench, wide), the cost tools'
//! (`cost::cli`: synth, fit, boxes, cull, depth, per-ray, dot-styles,
//! charts, bringup) and `fpga`, which runs `scripts/fpga.sh`. It is the
//! workspace's only binary.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "rtl-gen",
    version,
    about = rtl_flow::cli::ABOUT,
    long_about = rtl_flow::cli::LONG_ABOUT
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    #[command(flatten)]
    Flow(rtl_flow::cli::Command),
    #[command(flatten)]
    Scene(scene::cli::Command),
    #[command(flatten)]
    Cost(cost::cli::Command),
    /// Build an FPGA bitstream of a unit behind the UART bring-up wrapper and report whether
    /// timing is met: runs scripts/fpga.sh [BOARD] [UNIT [-p KEY=VALUE]...] (boards icebreaker,
    /// ulx3s, orangecrab; the script's header has the details). Without `-p stages=N` it picks
    /// pipeline=balanced and the fewest stages that meet the board clock (the delay model's
    /// guess, +2 while timing fails, then down as a met build's Fmax suggests; at most four
    /// builds) and prints the choice. Its last line is
    /// `timing: met|FAILED at <MHz> MHz (target <MHz> MHz)`; exit 3 when timing fails.
    Fpga {
        /// board, unit and -p KEY=VALUE parameters, as scripts/fpga.sh takes them
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Flow(c) => rtl_flow::cli::main(c),
        Command::Scene(c) => scene::cli::main(c),
        Command::Cost(c) => cost::cli::main(c),
        Command::Fpga { args } => cost::fpga::main(&args),
    }
}
