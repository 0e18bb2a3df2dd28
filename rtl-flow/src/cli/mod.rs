//! The `rtl-gen` subcommands that generate, lint, simulate and cross-check
//! units ([`Command`], run by [`main`]); the `rtl-gen` binary (crate
//! `rtl-tool`) puts them beside the renderer's and the cost tools'.
//!
//! `args.rs` holds the argument groups the subcommands share, `check.rs` the
//! runs through Verilator and the golden model (check, sim, golden, replay,
//! TestFloat), `files.rs` the vector and report files (vectors, convert,
//! merge-reports), `accuracy.rs` the inverse transform's accuracy study.

mod accuracy;
mod args;
mod check;
mod files;

use crate::{FlowError, Generated};
pub use args::{FileArgs, ReportArgs, ScaleArgs, UnitArgs};
use clap::Subcommand;
use std::path::PathBuf;
use std::process::ExitCode;

/// The flow's subcommands.
#[derive(Subcommand)]
pub enum Command {
    /// List the units and their parameters.
    List,
    /// Write a unit's Verilog (one file per module), its port list (JSON), timing constraints (SDC),
    /// a FuseSoC CAPI2 core file (.core: lint and sim targets) and a filelist (.f).
    Emit {
        #[command(flatten)]
        unit: UnitArgs,
        /// Output directory.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Clock period written into the SDC file, in nanoseconds.
        #[arg(long, default_value_t = 10.0, value_name = "NS")]
        clock_period_ns: f64,
        /// Write a `// src: file:line` comment above each assignment: the generator line that
        /// built the value.
        #[arg(long)]
        source_lines: bool,
        /// Also write a cocotb test (test_<top>.py, cocotb 2.x with its Python runner) with the
        /// unit's vectors (<top>.vectors.txt, as `rtl-gen vectors` writes them) and their golden
        /// results (<top>.golden.txt, as `rtl-gen golden` writes them); random stalls on both
        /// sides with handshake=ready. Run it with `python3 test_<top>.py`.
        #[arg(long)]
        cocotb: bool,
        /// Vectors of the cocotb test.
        #[arg(long, default_value_t = 1000, value_name = "N", requires = "cocotb",
              value_parser = clap::value_parser!(u64).range(1..))]
        cocotb_vectors: u64,
        /// Seed of the cocotb test's random vectors.
        #[arg(long, default_value_t = 1, requires = "cocotb")]
        cocotb_seed: u64,
    },
    /// Generate a unit, lint it with `verilator --lint-only -Wall`, simulate it in Verilator and
    /// compare every output of every valid cycle with the golden model.
    Check {
        #[command(flatten)]
        unit: UnitArgs,
        /// Number of vectors (corner cases first, then seeded random ones); a check of none
        /// would pass on nothing.
        #[arg(long, default_value_t = 1_000_000, value_parser = clap::value_parser!(u64).range(1..))]
        vectors: u64,
        /// Seed of the random vectors.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Where the generated files go (default: out/<module>).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Directory of cached Verilator builds (default: $RTL_GEN_CACHE or target/rtl-cache).
        #[arg(long, value_name = "DIR")]
        cache: Option<PathBuf>,
        /// Do not draw a progress bar (none is drawn when stderr is not a terminal either).
        #[arg(long)]
        no_progress: bool,
        #[command(flatten)]
        scale: ScaleArgs,
        #[command(flatten)]
        reports: ReportArgs,
        /// Check the cases of a TestFloat-format file (`-` = stdin) instead of generated
        /// vectors: one case a line, operands, expected result, flags, in hex (float operators).
        #[arg(long, value_name = "FILE|-")]
        testfloat: Option<String>,
        /// With --testfloat: a NaN result must equal the expected NaN bit for bit
        /// (default: any NaN matches any NaN).
        #[arg(long, requires = "testfloat")]
        nan_exact: bool,
        /// With --testfloat: the output compared with the expected result (default: the only
        /// output, else `z`; e.g. `lt` for fcmp, `min` for fminmax).
        #[arg(long, value_name = "PORT", requires = "testfloat")]
        result: Option<String>,
    },
    /// Run a vector file through the Verilated RTL and write every output of every
    /// transaction to a results file (inputs echoed, outputs added). Also runs the golden
    /// model and reports mismatches, unless --rtl-only.
    Sim {
        #[command(flatten)]
        unit: UnitArgs,
        #[command(flatten)]
        files: FileArgs,
        /// Skip the golden model: only simulate and write the results.
        #[arg(long)]
        rtl_only: bool,
        /// Simulate the Verilog in DIR (files named as the generated ones, e.g. a hand-edited
        /// copy, or the design of a `rtl-gen prove --verilog` counterexample) instead of the
        /// generated files.
        #[arg(long, value_name = "DIR")]
        verilog: Option<PathBuf>,
        /// Where the generated files go (default: out/<module>).
        #[arg(long, value_name = "DIR")]
        dir: Option<PathBuf>,
        /// Directory of cached Verilator builds.
        #[arg(long, value_name = "DIR")]
        cache: Option<PathBuf>,
        #[command(flatten)]
        reports: ReportArgs,
    },
    /// Run a vector file through the golden model alone (no Verilator) and write a results
    /// file (inputs echoed, outputs added), to diff against another model.
    Golden {
        #[command(flatten)]
        unit: UnitArgs,
        #[command(flatten)]
        files: FileArgs,
        #[command(flatten)]
        reports: ReportArgs,
    },
    /// Write an input vector file from the unit's own stimulus (corner cases first, then seeded
    /// random vectors): the input format of any unit, and a starting point for your own.
    Vectors {
        #[command(flatten)]
        unit: UnitArgs,
        /// Number of vectors.
        #[arg(long, default_value_t = 10)]
        count: u64,
        /// Index of the first vector (the stimulus starts with corner cases).
        #[arg(long, default_value_t = 0)]
        first: u64,
        /// Seed of the random vectors.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output file: binary for .rtlvec/.bin, else text.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
    },
    /// Convert a vector file between the text and the binary (rtlvec) format; the direction
    /// follows from the input's content.
    Convert {
        /// Input vector file (text or rtlvec).
        input: PathBuf,
        /// Output file, written in the other format.
        output: PathBuf,
        /// Check the ports against this unit's port list (text headers may then omit widths).
        #[arg(long, value_name = "UNIT")]
        unit: Option<String>,
        /// Parameter of --unit as key=value; repeat for several.
        #[arg(short, long = "param", value_name = "KEY=VALUE", requires = "unit")]
        params: Vec<String>,
        /// With --unit: the file holds results (inputs then outputs) instead of inputs.
        #[arg(long, requires = "unit")]
        results: bool,
    },
    /// Combine the JSON reports of the shards of one check (`--shard K/N --report`) into one
    /// verdict: every shard exactly once, same unit, parameters, Verilog, seed and vectors.
    MergeReports {
        /// Shard reports (JSON).
        #[arg(required = true, value_name = "REPORT.json")]
        reports: Vec<PathBuf>,
        /// Write the merged report here.
        #[arg(long, value_name = "FILE.json")]
        out: Option<PathBuf>,
        /// Write the merged verdict as JUnit XML here.
        #[arg(long, value_name = "FILE")]
        junit: Option<PathBuf>,
    },
    /// Run one vector of a check again, with a VCD trace, and print both results.
    Replay {
        #[command(flatten)]
        unit: UnitArgs,
        /// Seed of the check that failed.
        #[arg(long)]
        seed: u64,
        /// Index of the failing vector.
        #[arg(long)]
        index: u64,
        /// VCD file to write.
        #[arg(long, default_value = "replay.vcd", value_name = "FILE")]
        vcd: PathBuf,
        /// Where the generated files go (default: out/<module>).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Directory of cached Verilator builds.
        #[arg(long, value_name = "DIR")]
        cache: Option<PathBuf>,
    },
    /// Print the accuracy study of the inverse transform (seed 003, FIG. 7): conventional
    /// single inverse matrix against the two-step method, errors against the exact reference.
    TransformAccuracy {
        /// Float format: eEmF (e.g. e8m23) or binary16, binary32, binary64, bfloat16.
        #[arg(long, default_value = "e8m23")]
        format: String,
        /// Dot-product style of the two-step method: separate, fma, dot3 or all.
        #[arg(long, default_value = "fma")]
        dot: String,
        /// Origins per offset for each of M1-M3.
        #[arg(long, default_value_t = 10_000)]
        points: usize,
        /// Random matrices.
        #[arg(long, default_value_t = 1000)]
        random: usize,
        /// Origins per offset for each random matrix.
        #[arg(long, default_value_t = 100)]
        random_points: usize,
        /// Seed of the random matrices and origins.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// How R^-1 (and the conventional u) are obtained: exact (scene builder, rounded
        /// once) or hw (computed in the format, as the unit's inverse=hw does).
        #[arg(long, default_value = "exact")]
        inverse: String,
    },
}

/// The top-level help of `rtl-gen`: what every emitted module looks like.
pub const ABOUT: &str = "Generates Verilog for ray-tracing intersection units and cross-checks it in Verilator against bit-accurate golden models.";

/// [`ABOUT`], then the interface every emitted module has.
pub const LONG_ABOUT: &str = "Generates Verilog for ray-tracing intersection units and cross-checks it in Verilator against bit-accurate golden models.\n\n\
Every emitted module has clk (rising edge), rst (synchronous, active high), in_valid and out_valid: \
a transaction presented with in_valid high comes out with out_valid high exactly `latency` cycles later \
(one per clock, no backpressure). With -p handshake=ready a unit also has in_ready and out_ready \
(valid/ready, the consumer may stall; docs/handshake.md). `rtl-gen list` shows the units and their parameters.";

/// Runs one subcommand: exit 0, 1 (a check failed) or 2 (an error, printed).
pub fn main(command: Command) -> ExitCode {
    let result = match command {
        Command::List => {
            list();
            Ok(true)
        }
        Command::Emit {
            unit,
            out,
            clock_period_ns,
            source_lines,
            cocotb,
            cocotb_vectors,
            cocotb_seed,
        } => emit(
            &unit,
            &out,
            clock_period_ns,
            source_lines,
            cocotb.then_some((cocotb_vectors, cocotb_seed)),
        ),
        Command::Check {
            unit,
            vectors,
            seed,
            out,
            cache,
            no_progress,
            scale,
            reports,
            testfloat,
            nan_exact,
            result,
        } => match testfloat {
            Some(source) => check::check_testfloat(
                &unit,
                &source,
                nan_exact,
                result.as_deref(),
                out,
                cache,
                &reports,
            ),
            None => check::check(
                &unit,
                vectors,
                seed,
                out,
                cache,
                !no_progress,
                &scale,
                &reports,
            ),
        },
        Command::Sim {
            unit,
            files,
            rtl_only,
            verilog,
            dir,
            cache,
            reports,
        } => check::sim_file(
            &unit,
            &files,
            !rtl_only,
            verilog.as_deref(),
            dir,
            cache,
            &reports,
        ),
        Command::Golden {
            unit,
            files,
            reports,
        } => check::golden_file(&unit, &files, &reports),
        Command::Vectors {
            unit,
            count,
            first,
            seed,
            out,
        } => files::write_vectors(&unit, count, first, seed, &out),
        Command::Convert {
            input,
            output,
            unit,
            params,
            results,
        } => files::convert(&input, &output, unit, &params, results),
        Command::MergeReports {
            reports,
            out,
            junit,
        } => files::merge_reports(&reports, out, junit),
        Command::Replay {
            unit,
            seed,
            index,
            vcd,
            out,
            cache,
        } => check::replay(&unit, seed, index, &vcd, out, cache),
        Command::TransformAccuracy {
            format,
            dot,
            points,
            random,
            random_points,
            seed,
            inverse,
        } => accuracy::transform_accuracy(
            &format,
            &dot,
            points,
            random,
            random_points,
            seed,
            &inverse,
        ),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn list() {
    for entry in crate::catalog() {
        let u = entry.unit;
        println!("{}: {}", u.name(), u.summary());
        let rows: Vec<(String, &str)> = crate::param_specs(&entry)
            .iter()
            .map(|p| {
                (
                    format!("{}={} [{}]", p.name, p.range(), p.default),
                    p.help(),
                )
            })
            .collect();
        let width = rows.iter().map(|(head, _)| head.len()).max().unwrap_or(0);
        for (head, doc) in rows {
            println!("    {head:<width$}  {doc}");
        }
        println!();
    }
}

fn emit(
    unit: &UnitArgs,
    out: &std::path::Path,
    period: f64,
    source_lines: bool,
    cocotb: Option<(u64, u64)>,
) -> Result<bool, FlowError> {
    // 1 ps to 1 ms: the SDC's three decimals hold it, and no clock is outside it
    if !(period.is_finite() && (0.001..=1e6).contains(&period)) {
        return Err(FlowError::Params(rtl_gen::params::ParamError::Combination(
            format!(
                "--clock-period-ns must be a number of nanoseconds in 0.001..=1e6, got {period}"
            ),
        )));
    }
    let mut g = unit.generate()?;
    if source_lines {
        let options = rtl_gen::emit::EmitOptions { source_lines };
        g.files = rtl_gen::emit::emit_with(&g.module, rtl_gen::GENERATOR, options);
    }
    let created = (!out.exists()).then_some(out);
    let mut written = g.write(out, period)?;
    let mut rest = || -> Result<(), FlowError> {
        if let Some((vectors, seed)) = cocotb {
            crate::cocotb::write(&g, out, vectors, seed, &mut written)?;
        }
        // FuseSoC and simulator filelists: the packaging a hardware team's flow reads
        for (ext, text) in [
            ("core", crate::package::core_file(&g)),
            ("f", crate::package::filelist(&g)),
        ] {
            let path = out.join(format!("{}.{ext}", g.module.name));
            written.push(path.clone());
            std::fs::write(&path, text).map_err(|e| FlowError::Io(path, e))?;
        }
        Ok(())
    };
    if let Err(e) = rest() {
        crate::remove_written(&written, created);
        return Err(e);
    }
    for path in written {
        println!("wrote {}", path.display());
    }
    println!(
        "{}: latency {} cycle(s), II 1",
        g.module.name, g.module.latency
    );
    Ok(true)
}

pub(super) fn out_dir(g: &Generated, out: Option<PathBuf>) -> PathBuf {
    out.unwrap_or_else(|| PathBuf::from("out").join(&g.module.name))
}

pub(super) fn cache_dir(cache: Option<PathBuf>) -> PathBuf {
    cache.unwrap_or_else(sim::default_cache_root)
}

pub(super) fn bad_usage(message: String) -> FlowError {
    FlowError::Params(rtl_gen::params::ParamError::Combination(message))
}

/// The name of a vector file format, for messages.
pub(super) fn format_word(format: sim::VecFormat) -> &'static str {
    match format {
        sim::VecFormat::Text => "text",
        sim::VecFormat::Binary => "rtlvec",
    }
}
