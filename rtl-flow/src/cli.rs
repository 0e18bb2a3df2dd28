//! The `rtl-gen` subcommands that generate, lint, simulate and cross-check
//! units ([`Command`], run by [`main`]); the `rtl-gen` binary (crate
//! `rtl-tool`) puts them beside the renderer's and the cost tools'.

use crate::report::{self, RunReport, Shard};
use crate::{byo, regress, FlowError, Generated};
use clap::Subcommand;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rtl_gen::params::ParamKind;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct UnitArgs {
    /// Unit to generate (see `rtl-gen list`).
    unit: String,
    /// Parameter as key=value; repeat for several. Unset parameters take their defaults.
    #[arg(short, long = "param", value_name = "KEY=VALUE")]
    params: Vec<String>,
    /// Float units: shorthand for exp_bits/frac_bits: binary16, binary32, binary64,
    /// bfloat16, or eXmY (e.g. e6m9).
    #[arg(long, value_name = "FORMAT")]
    format: Option<String>,
    /// Float units: shorthand for round=...: rne|rtz|rdn|rup, or TestFloat's names
    /// near_even, minMag, min, max (also nearest, zero, down, up).
    #[arg(long, value_name = "MODE")]
    round: Option<String>,
}

impl UnitArgs {
    /// `--param` values plus the ones `--format` and `--round` stand for.
    fn all_params(&self) -> Result<Vec<String>, FlowError> {
        let mut params = self.params.clone();
        if let Some(f) = &self.format {
            let (e, m) = float_format(f).ok_or_else(|| {
                bad_usage(format!(
                    "--format {f}: expected binary16, binary32, binary64, bfloat16 or eXmY"
                ))
            })?;
            params.push(format!("exp_bits={e}"));
            params.push(format!("frac_bits={m}"));
        }
        if let Some(r) = &self.round {
            let mode = match r.as_str() {
                "rne" | "near_even" | "nearest" => "rne",
                "rtz" | "minMag" | "zero" => "rtz",
                "rdn" | "min" | "down" => "rdn",
                "rup" | "max" | "up" => "rup",
                "dyn" => "dyn",
                other => {
                    return Err(bad_usage(format!(
                    "--round {other}: expected rne|rtz|rdn|rup (or near_even, minMag, min, max); \
                         near_maxMag and odd rounding are not implemented"
                )))
                }
            };
            params.push(format!("round={mode}"));
        }
        Ok(params)
    }

    /// Builds and emits the unit with these parameters.
    fn generate(&self) -> Result<Generated, FlowError> {
        crate::generate(&self.unit, &self.all_params()?)
    }
}

/// (exponent bits, fraction bits) of a format name.
fn float_format(name: &str) -> Option<(u32, u32)> {
    golden_model::float::FloatFormat::parse_name(name)
}

#[derive(clap::Args)]
pub struct ScaleArgs {
    /// Harness processes run in parallel, each fed by its own golden-model threads
    /// (default: all cores).
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Run only shard K of N (1-based): the vectors whose index i has i mod N = K-1, corner
    /// vectors included. N jobs with K = 1..N together run exactly the unsharded set; combine
    /// their --report files with `rtl-gen merge-reports`.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
}

#[derive(clap::Args)]
pub struct ReportArgs {
    /// Write a JSON report: unit, parameters, generator version, Verilog hash, seed, shard,
    /// vectors, mismatches with the first failing vector, vectors/s, wall time.
    #[arg(long, value_name = "FILE.json")]
    report: Option<PathBuf>,
    /// Write the verdict as JUnit XML (one test case).
    #[arg(long, value_name = "FILE")]
    junit: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct FileArgs {
    /// Input vectors: text (a header line of port names, one transaction a line, values in
    /// 0x-hex or decimal) or binary rtlvec, told apart by content.
    #[arg(long = "in", value_name = "FILE")]
    input: PathBuf,
    /// Results file: inputs then outputs of every transaction; binary for .rtlvec/.bin,
    /// text for .txt/.vec/.tsv/.text, else the input's format. Written only when complete.
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
}

/// The flow's subcommands.
#[derive(Subcommand)]
pub enum Command {
    /// List the units and their parameters.
    List,
    /// Write a unit's Verilog (one file per module), its port list (JSON) and timing constraints (SDC).
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
    },
    /// Generate a unit, lint it with `verilator --lint-only -Wall`, simulate it in Verilator and
    /// compare every output of every valid cycle with the golden model.
    Check {
        #[command(flatten)]
        unit: UnitArgs,
        /// Number of vectors (corner cases first, then seeded random ones).
        #[arg(long, default_value_t = 1_000_000)]
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
        /// Float format, eEmF (e.g. e8m23 = binary32).
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
(one per clock, no backpressure). `rtl-gen list` shows the units and their parameters.";

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
        } => emit(&unit, &out, clock_period_ns, source_lines),
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
            Some(source) => check_testfloat(
                &unit,
                &source,
                nan_exact,
                result.as_deref(),
                out,
                cache,
                &reports,
            ),
            None => check(
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
            dir,
            cache,
            reports,
        } => sim_file(&unit, &files, !rtl_only, dir, cache, &reports),
        Command::Golden {
            unit,
            files,
            reports,
        } => golden_file(&unit, &files, &reports),
        Command::Vectors {
            unit,
            count,
            first,
            seed,
            out,
        } => write_vectors(&unit, count, first, seed, &out),
        Command::Convert {
            input,
            output,
            unit,
            params,
            results,
        } => convert(&input, &output, unit, &params, results),
        Command::MergeReports {
            reports,
            out,
            junit,
        } => merge_reports(&reports, out, junit),
        Command::Replay {
            unit,
            seed,
            index,
            vcd,
            out,
            cache,
        } => replay(&unit, seed, index, &vcd, out, cache),
        Command::TransformAccuracy {
            format,
            dot,
            points,
            random,
            random_points,
            seed,
            inverse,
        } => transform_accuracy(&format, &dot, points, random, random_points, seed, &inverse),
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
                let range = match p.kind {
                    ParamKind::Int { min, max } => format!("{min}..={max}"),
                    ParamKind::Choice(words) => words.join("|"),
                };
                (format!("{}={range} [{}]", p.name, p.default), p.doc)
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
) -> Result<bool, FlowError> {
    if !(period.is_finite() && period > 0.0) {
        return Err(FlowError::Params(rtl_gen::params::ParamError::Combination(
            format!("--clock-period-ns must be a positive number of nanoseconds, got {period}"),
        )));
    }
    let mut g = unit.generate()?;
    if source_lines {
        let options = rtl_gen::emit::EmitOptions { source_lines };
        g.files = rtl_gen::emit::emit_with(&g.module, rtl_gen::GENERATOR, options);
    }
    for path in g.write(out, period)? {
        println!("wrote {}", path.display());
    }
    println!(
        "{}: latency {} cycle(s), II 1",
        g.module.name, g.module.latency
    );
    Ok(true)
}

fn out_dir(g: &Generated, out: Option<PathBuf>) -> PathBuf {
    out.unwrap_or_else(|| PathBuf::from("out").join(&g.module.name))
}

fn cache_dir(cache: Option<PathBuf>) -> PathBuf {
    cache.unwrap_or_else(sim::default_cache_root)
}

/// Vectors also run through the (slow) IR evaluator, as a third opinion.
const EVALUATOR_VECTORS: u64 = 20_000;

fn bad_usage(message: String) -> FlowError {
    FlowError::Params(rtl_gen::params::ParamError::Combination(message))
}

/// Writes the requested reports; a report that cannot be written is an error.
fn write_reports(report: &RunReport, args: &ReportArgs) -> Result<(), FlowError> {
    if let Some(path) = &args.report {
        report.save(path)?;
        println!("  report      {}", path.display());
    }
    if let Some(path) = &args.junit {
        report.save_junit(path)?;
        println!("  junit       {}", path.display());
    }
    Ok(())
}

/// Runs `body`; if it fails, the reports still get written, with the error.
fn with_reports(
    mut base: RunReport,
    args: &ReportArgs,
    body: impl FnOnce(&mut RunReport) -> Result<bool, FlowError>,
) -> Result<bool, FlowError> {
    match body(&mut base) {
        Ok(passed) => {
            write_reports(&base, args)?;
            Ok(passed)
        }
        Err(e) => {
            base.error = Some(e.to_string());
            base.update_verdict();
            if let Err(w) = write_reports(&base, args) {
                eprintln!("error: {w}");
            }
            Err(e)
        }
    }
}

/// A progress bar on stderr, or a hidden one with --no-progress or when
/// stderr is not a terminal.
fn progress_bar(total: u64, show: bool) -> ProgressBar {
    if !show || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{wide_bar}] {human_pos}/{human_len} vectors, eta {eta} {msg}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar
}

#[allow(clippy::too_many_arguments)]
fn check(
    unit: &UnitArgs,
    vectors: u64,
    seed: u64,
    out: Option<PathBuf>,
    cache: Option<PathBuf>,
    progress: bool,
    scale: &ScaleArgs,
    reports: &ReportArgs,
) -> Result<bool, FlowError> {
    let shard = match &scale.shard {
        Some(s) => Shard::parse(s).map_err(bad_usage)?,
        None => Shard::ALL,
    };
    let jobs = match scale.jobs {
        Some(0) => return Err(bad_usage("--jobs must be at least 1".into())),
        Some(n) => n,
        None => regress::all_cores(),
    };
    let g = unit.generate()?;
    let mut base = RunReport::new("check", &g);
    base.seed = Some(seed);
    base.total_vectors = vectors;
    base.shard = shard;
    with_reports(base, reports, |report| {
        let dir = out_dir(&g, out);
        g.write(&dir, 10.0)?;
        println!(
            "rtl-gen check {} ({})",
            g.unit,
            rtl_gen::emit::lower::params_line(g.params.values())
        );
        println!(
            "  module      {} (latency {} cycle(s), II 1)",
            g.module.name, g.module.latency
        );
        println!("  files       {}", dir.display());
        sim::lint(&g.ports, &dir)?;
        println!("  lint        verilator --lint-only -Wall: clean");
        let t = Instant::now();
        let harness = sim::Harness::build(&g.ports, &dir, &cache_dir(cache))?;
        println!("  harness     ready in {:.1} s", t.elapsed().as_secs_f64());
        if shard.count > 1 {
            println!(
                "  shard       {shard}: {} of {vectors} vectors (indices {} + {}k)",
                shard.len(vectors),
                shard.first(),
                shard.count
            );
        }
        println!("  jobs        {jobs} harness process(es)");
        let bar = progress_bar(shard.len(vectors), progress);
        let on_bar = bar.clone();
        let mut run = regress::CheckRun::new(vectors, seed);
        run.shard = shard;
        run.jobs = jobs;
        run.evaluator_vectors = EVALUATOR_VECTORS;
        let last_message = std::sync::Mutex::new(Instant::now());
        run.on_progress = Some(sim::ProgressFn::new(move |p: &sim::Progress| {
            on_bar.set_position(p.done);
            // The message (rate, mismatches) at most five times a second.
            let Ok(mut last) = last_message.try_lock() else {
                return;
            };
            if last.elapsed().as_millis() < 200 && p.done < p.total {
                return;
            }
            *last = Instant::now();
            let rate = p.done as f64 / on_bar.elapsed().as_secs_f64().max(1e-9);
            let failing = match p.mismatches {
                0 => String::new(),
                n => format!(", {n} mismatches"),
            };
            on_bar.set_message(format!("{:.2} M vectors/s{failing}", rate / 1e6));
        }));
        let tb = g.testbench();
        let outcome = regress::run_check(&g, &harness, tb.as_ref(), &run);
        bar.finish_and_clear();
        let outcome = outcome?;
        println!("  evaluator   {}", outcome.evaluator);
        println!("{}", outcome.check);
        *report = outcome.report;
        Ok(report.passed)
    })
}

fn sim_file(
    unit: &UnitArgs,
    files: &FileArgs,
    compare: bool,
    dir: Option<PathBuf>,
    cache: Option<PathBuf>,
    reports: &ReportArgs,
) -> Result<bool, FlowError> {
    let g = unit.generate()?;
    let mut base = RunReport::new("sim", &g);
    base.input = Some(files.input.display().to_string());
    with_reports(base, reports, |report| {
        let dir = out_dir(&g, dir);
        g.write(&dir, 10.0)?;
        let harness = sim::Harness::build(&g.ports, &dir, &cache_dir(cache))?;
        let tb = g.testbench();
        let mode = byo::Mode::Rtl { compare };
        let o = byo::run_file(
            &g,
            Some(&harness),
            tb.as_ref(),
            &files.input,
            &files.out,
            mode,
        )?;
        print_file_outcome(&o, &files.out);
        *report = o.report;
        Ok(report.passed)
    })
}

fn golden_file(unit: &UnitArgs, files: &FileArgs, reports: &ReportArgs) -> Result<bool, FlowError> {
    let g = unit.generate()?;
    let mut base = RunReport::new("golden", &g);
    base.input = Some(files.input.display().to_string());
    with_reports(base, reports, |report| {
        let tb = g.testbench();
        let o = byo::run_file(
            &g,
            None,
            tb.as_ref(),
            &files.input,
            &files.out,
            byo::Mode::Golden,
        )?;
        print_file_outcome(&o, &files.out);
        *report = o.report;
        Ok(true)
    })
}

fn print_file_outcome(o: &byo::FileOutcome, out: &std::path::Path) {
    for m in &o.shown {
        print!("{m}");
    }
    if o.mismatches > o.shown.len() as u64 {
        println!("  ... {} mismatches in all", o.mismatches);
    }
    let format = match o.format {
        sim::VecFormat::Text => "text",
        sim::VecFormat::Binary => "rtlvec",
    };
    println!("wrote {} ({format}, {} records)", out.display(), o.vectors);
    println!("{}", o.report.headline());
}

fn write_vectors(
    unit: &UnitArgs,
    count: u64,
    first: u64,
    seed: u64,
    out: &std::path::Path,
) -> Result<bool, FlowError> {
    let g = unit.generate()?;
    let tb = g.testbench();
    let format = byo::write_stimulus(&g, tb.as_ref(), seed, first, count, out)?;
    let word = match format {
        sim::VecFormat::Text => "text",
        sim::VecFormat::Binary => "rtlvec",
    };
    println!(
        "wrote {} ({word}, {count} vectors of {})",
        out.display(),
        g.module.name
    );
    Ok(true)
}

fn convert(
    input: &std::path::Path,
    output: &std::path::Path,
    unit: Option<String>,
    params: &[String],
    results: bool,
) -> Result<bool, FlowError> {
    let ports = match unit {
        Some(u) => {
            let g = crate::generate(&u, params)?;
            let mut p = g.ports.inputs.clone();
            if results {
                p.extend(g.ports.outputs.iter().cloned());
            }
            Some(p)
        }
        None => None,
    };
    let (format, n) = sim::convert_file(input, output, ports.as_deref())?;
    let word = match format {
        sim::VecFormat::Text => "text",
        sim::VecFormat::Binary => "rtlvec",
    };
    println!("wrote {} ({word}, {n} records)", output.display());
    Ok(true)
}

fn merge_reports(
    paths: &[PathBuf],
    out: Option<PathBuf>,
    junit: Option<PathBuf>,
) -> Result<bool, FlowError> {
    let mut loaded = Vec::new();
    for p in paths {
        loaded.push((
            p.display().to_string(),
            RunReport::load(p).map_err(bad_usage)?,
        ));
    }
    let merged = report::merge(&loaded).map_err(bad_usage)?;
    for (name, r) in &loaded {
        println!(
            "  shard {:<7} {}  ({name})",
            r.shard.to_string(),
            r.headline()
        );
    }
    print!("{}", merged.failure_text());
    if let Some(e) = &merged.error {
        println!("errors in shards:\n{e}");
    }
    write_reports(&merged, &ReportArgs { report: out, junit })?;
    if merged.error.is_some() {
        return Err(bad_usage("a shard stopped with an error".into()));
    }
    Ok(merged.passed)
}

fn replay(
    unit: &UnitArgs,
    seed: u64,
    index: u64,
    vcd: &PathBuf,
    out: Option<PathBuf>,
    cache: Option<PathBuf>,
) -> Result<bool, FlowError> {
    let g = unit.generate()?;
    let dir = out_dir(&g, out);
    g.write(&dir, 10.0)?;
    let harness = sim::Harness::build(&g.ports, &dir, &cache_dir(cache))?;
    let tb = g.testbench();
    let mut inputs = vec![0u64; g.ports.inputs.len()];
    sim::Stimulus::vector(tb.as_ref(), seed, index, &mut inputs);
    let mut expected = vec![0u64; g.ports.outputs.len()];
    sim::Golden::eval(tb.as_ref(), &inputs, &mut expected);
    let got = sim::replay(&harness, &inputs, Some(vcd))?;
    println!("vector {index} of seed {seed} ({}):", g.module.name);
    for (p, v) in g.ports.inputs.iter().zip(&inputs) {
        println!("  in  {:<12} {v:#x}", p.name);
    }
    let mut same = true;
    for ((p, e), r) in g.ports.outputs.iter().zip(&expected).zip(&got) {
        let mark = if e == r { "" } else { "   <-- differs" };
        same &= e == r;
        println!("  out {:<12} golden {e:#x}  rtl {r:#x}{mark}", p.name);
    }
    println!("trace written to {}", vcd.display());
    Ok(same)
}

fn transform_accuracy(
    format: &str,
    dot: &str,
    points: usize,
    random: usize,
    random_points: usize,
    seed: u64,
    inverse: &str,
) -> Result<bool, FlowError> {
    use golden_model::transform::{accuracy, DotStyle};
    let bad = |m: String| FlowError::Params(rtl_gen::params::ParamError::Combination(m));
    let fmt = format
        .strip_prefix('e')
        .and_then(|r| r.split_once('m'))
        .and_then(|(e, f)| Some((e.parse().ok()?, f.parse().ok()?)))
        .ok_or_else(|| bad(format!("--format {format}: expected eEmF, e.g. e8m23")))
        .and_then(|(e, f)| {
            golden_model::float::FloatFormat::new(e, f).map_err(|err| bad(err.to_string()))
        })?;
    let styles = match dot {
        "all" => DotStyle::ALL.to_vec(),
        w => vec![DotStyle::parse(w)
            .ok_or_else(|| bad(format!("--dot {w}: expected separate, fma, dot3 or all")))?],
    };
    let inverse = match inverse {
        "exact" => accuracy::StudyInverse::Exact,
        "hw" => accuracy::StudyInverse::Hardware,
        w => return Err(bad(format!("--inverse {w}: expected exact or hw"))),
    };
    let opts = accuracy::StudyOptions {
        fmt,
        styles,
        inverse,
        points,
        random_matrices: random,
        random_points,
        seed,
        ..Default::default()
    };
    let rows = accuracy::run(&opts);
    print!("{}", accuracy::table(&opts, &rows));
    Ok(true)
}

fn check_testfloat(
    unit: &UnitArgs,
    source: &str,
    nan_exact: bool,
    result: Option<&str>,
    out: Option<PathBuf>,
    cache: Option<PathBuf>,
    reports: &ReportArgs,
) -> Result<bool, FlowError> {
    use crate::testfloat;
    let g = unit.generate()?;
    let map = testfloat::Mapping::for_unit(&g, result).map_err(bad_usage)?;
    let mut base = RunReport::new("testfloat", &g);
    let name = if source == "-" { "<stdin>" } else { source };
    base.input = Some(name.to_string());
    with_reports(base, reports, |report| {
        let result_port = &g.ports.outputs[map.result];
        let cases = if source == "-" {
            let stdin = std::io::stdin().lock();
            testfloat::read_cases(stdin, name, &g.ports.inputs, result_port)?
        } else {
            let f = std::fs::File::open(source)
                .map_err(|e| sim::SimError::io(format!("opening {source}"), e))?;
            let r = std::io::BufReader::new(f);
            testfloat::read_cases(r, name, &g.ports.inputs, result_port)?
        };
        let dir = out_dir(&g, out);
        g.write(&dir, 10.0)?;
        println!(
            "rtl-gen check {} ({}) --testfloat {name}",
            g.unit,
            rtl_gen::emit::lower::params_line(g.params.values())
        );
        println!(
            "  module      {} (latency {} cycle(s), II 1)",
            g.module.name, g.module.latency
        );
        sim::lint(&g.ports, &dir)?;
        println!("  lint        verilator --lint-only -Wall: clean");
        let harness = sim::Harness::build(&g.ports, &dir, &cache_dir(cache))?;
        let tb = g.testbench();
        let o = testfloat::run(&g, &harness, tb.as_ref(), &map, &cases, name, nan_exact)?;
        print!("{o}");
        *report = o.report;
        println!("{}", report.headline());
        Ok(report.passed)
    })
}
