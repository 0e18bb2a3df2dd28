//! `rtl-bringup`: emits the FPGA bring-up wrapper of a unit (UART front end,
//! `cost::bringup`) and its board top, lints them with Verilator.

use clap::Parser;
use cost::bringup::{board_top, Bringup};
use std::path::PathBuf;
use std::process::ExitCode;

/// Emit the UART bring-up wrapper of a unit, lint it, write a board top.
#[derive(Parser)]
#[command(name = "rtl-bringup")]
struct Cli {
    /// unit name (`rtl-gen list`)
    unit: String,
    /// parameter key=value (repeatable)
    #[arg(short = 'p', value_name = "KEY=VALUE")]
    params: Vec<String>,
    /// clock cycles per UART bit (12 MHz / 115200 baud = 104)
    #[arg(long, default_value_t = 104)]
    cycles_per_bit: u32,
    /// name of the board top (power-on reset + wrapper)
    #[arg(long, default_value = "bringup_top")]
    top: String,
    /// output directory
    #[arg(long)]
    out: PathBuf,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let g = match rtl_flow::generate(&cli.unit, &cli.params) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("rtl-bringup: {e}");
            return ExitCode::from(2);
        }
    };
    let b = Bringup::new(&g, cli.cycles_per_bit);
    let run = || -> Result<(), String> {
        let paths = b.write(&cli.out).map_err(|e| e.to_string())?;
        b.lint(&cli.out)
            .map_err(|r| format!("lint warnings:\n{r}"))?;
        let top = cli.out.join(format!("{}.v", cli.top));
        std::fs::write(&top, board_top(&b.module, &cli.top)).map_err(|e| e.to_string())?;
        for p in paths.iter().chain([&top]) {
            println!("{}", p.display());
        }
        Ok(())
    };
    match run() {
        Ok(()) => {
            eprintln!(
                "{}: {} input bytes, {} output bytes, unit latency {}, lint clean",
                b.module.name,
                cost::bringup::record_bytes(b.in_widths.iter().copied()),
                cost::bringup::record_bytes(b.out_widths.iter().copied()),
                g.module.latency
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("rtl-bringup: {e}");
            ExitCode::from(2)
        }
    }
}
