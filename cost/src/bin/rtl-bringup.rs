//! `rtl-bringup`: `rtl-gen bringup` under its earlier name: emits the FPGA
//! bring-up wrapper of a unit (UART front end, `cost::bringup`) and its board
//! top, lints them with Verilator.

use clap::Parser;
use std::process::ExitCode;

/// Emit the UART bring-up wrapper of a unit, lint it, write a board top.
#[derive(Parser)]
#[command(name = "rtl-bringup")]
struct Cli {
    #[command(flatten)]
    args: cost::cli::BringupArgs,
}

fn main() -> ExitCode {
    cost::cli::bringup(&Cli::parse().args)
}
