//! `rtl-cost`: synthesis reports, accuracy, charts, scene fitting, bring-up.

use clap::{Parser, Subcommand};
use cost::synth::{self, SynthOptions};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "rtl-cost",
    about = "Hardware cost against accuracy of the generated units"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Synthesise one unit: Yosys synth / synth_ice40 / synth_ecp5, ltp, nextpnr-ice40 where it fits
    Synth {
        /// unit name (`rtl-gen list`)
        unit: String,
        /// parameter key=value (repeatable)
        #[arg(short = 'p', value_name = "KEY=VALUE")]
        params: Vec<String>,
        /// skip place and route
        #[arg(long)]
        no_pnr: bool,
        /// skip synth_ecp5
        #[arg(long)]
        no_ecp5: bool,
        /// flatten before mapping (slower, a little smaller)
        #[arg(long)]
        flat: bool,
        /// nextpnr target frequency, MHz
        #[arg(long, default_value_t = 12.0)]
        target_mhz: f64,
        /// write the JSON report here
        #[arg(long)]
        json: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<(), Box<dyn std::error::Error>> {
    match cli.cmd {
        Cmd::Synth {
            unit,
            params,
            no_pnr,
            no_ecp5,
            flat,
            target_mhz,
            json,
        } => {
            let g = rtl_gen::flow::generate(&unit, &params)?;
            let o = SynthOptions {
                pnr: !no_pnr,
                ecp5: !no_ecp5,
                flat,
                target_mhz,
                ..Default::default()
            };
            let r = synth::run(&g, &o)?;
            println!("{}\n{}", synth::table_header(), synth::table_row(&r));
            if let Some(p) = &r.pnr {
                if !p.note.is_empty() {
                    println!("place and route: {}", p.note);
                }
            }
            let text = serde_json::to_string_pretty(&r)?;
            match json {
                Some(path) => std::fs::write(path, text + "\n")?,
                None => {}
            }
        }
    }
    Ok(())
}
