//! `render`: the renderer's subcommands of `rtl-gen` (render, hybrid,
//! rtl-loop, bench) under their earlier name: `render X ...` is
//! `rtl-gen X ...`.

use clap::Parser;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    about = "Render scenes through the golden models of the ray-tracing units (the same as `rtl-gen render|hybrid|rtl-loop|bench`)"
)]
struct Cli {
    #[command(subcommand)]
    command: scene::cli::Command,
}

fn main() -> ExitCode {
    scene::cli::main(Cli::parse().command)
}
