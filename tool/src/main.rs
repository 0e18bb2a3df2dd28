//! `rtl-gen`: the one command of the project. Its subcommands are the
//! flow's (`rtl_flow::cli`: list, emit, check, sim, golden, vectors,
//! convert, merge-reports, replay, transform-accuracy), the renderer's
//! (`scene::cli`: render, hybrid, rtl-loop, bench, wide), the cost tools'
//! (`cost::cli`: synth, fit, boxes, cull, depth, per-ray, dot-styles,
//! charts, bringup) and `fpga`, which runs `scripts/fpga.sh`. It is the
//! workspace's only binary.

use clap::{Parser, Subcommand};
use std::path::Path;
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
    /// ulx3s, orangecrab; the script's header has the details). Its last line is
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
        Command::Fpga { args } => fpga(&args),
    }
}

/// Runs scripts/fpga.sh of this checkout with `args`, its bring-up step
/// through this binary; passes its exit status on.
fn fpga(args: &[String]) -> ExitCode {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let script = root.join("scripts/fpga.sh");
    if !script.is_file() {
        eprintln!(
            "error: {} not found (rtl-gen fpga runs in its checkout)",
            script.display()
        );
        return ExitCode::from(2);
    }
    let mut cmd = std::process::Command::new("bash");
    cmd.arg(&script).args(args).current_dir(&root);
    if let Ok(me) = std::env::current_exe() {
        cmd.env("RTL_GEN", me);
    }
    match cmd.status() {
        Ok(s) => ExitCode::from(s.code().map_or(2, |c| c.clamp(0, 255) as u8)),
        Err(e) => {
            eprintln!("error: running {}: {e}", script.display());
            ExitCode::from(2)
        }
    }
}
