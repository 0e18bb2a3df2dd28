//! `rtl-gen`: generate, lint, simulate and cross-check ray-tracing intersection units.

use clap::{Parser, Subcommand};
use rtl_gen::flow::{self, FlowError, Generated};
use rtl_gen::params::ParamKind;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "rtl-gen",
    version,
    about = "Generates Verilog for ray-tracing intersection units and cross-checks it in Verilator against bit-accurate golden models.",
    long_about = "Generates Verilog for ray-tracing intersection units and cross-checks it in Verilator against bit-accurate golden models.\n\n\
Every emitted module has clk (rising edge), rst (synchronous, active high), in_valid and out_valid: \
a transaction presented with in_valid high comes out with out_valid high exactly `latency` cycles later \
(one per clock, no backpressure). `rtl-gen list` shows the units and their parameters."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct UnitArgs {
    /// Unit to generate (see `rtl-gen list`).
    unit: String,
    /// Parameter as key=value; repeat for several. Unset parameters take their defaults.
    #[arg(short, long = "param", value_name = "KEY=VALUE")]
    params: Vec<String>,
}

#[derive(Subcommand)]
enum Command {
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
        /// Do not draw a progress bar.
        #[arg(long)]
        no_progress: bool,
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
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::List => {
            list();
            Ok(true)
        }
        Command::Emit {
            unit,
            out,
            clock_period_ns,
        } => emit(&unit, &out, clock_period_ns),
        Command::Check {
            unit,
            vectors,
            seed,
            out,
            cache,
            no_progress,
        } => check(&unit, vectors, seed, out, cache, !no_progress),
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
        } => transform_accuracy(&format, &dot, points, random, random_points, seed),
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
    for entry in flow::catalog() {
        let u = entry.unit;
        println!("{}: {}", u.name(), u.summary());
        for p in u.params() {
            let range = match p.kind {
                ParamKind::Int { min, max } => format!("{min}..={max}"),
                ParamKind::Choice(words) => words.join(" | "),
            };
            println!(
                "    {:<10} {:<12} default {:<6} {}",
                p.name, range, p.default, p.doc
            );
        }
    }
}

fn emit(unit: &UnitArgs, out: &PathBuf, period: f64) -> Result<bool, FlowError> {
    if !(period.is_finite() && period > 0.0) {
        return Err(FlowError::Params(rtl_gen::params::ParamError::Combination(
            format!("--clock-period-ns must be a positive number of nanoseconds, got {period}"),
        )));
    }
    let g = flow::generate(&unit.unit, &unit.params)?;
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

fn check(
    unit: &UnitArgs,
    vectors: u64,
    seed: u64,
    out: Option<PathBuf>,
    cache: Option<PathBuf>,
    progress: bool,
) -> Result<bool, FlowError> {
    let g = flow::generate(&unit.unit, &unit.params)?;
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
    let tb = g.testbench();
    let eval_vectors = vectors.min(EVALUATOR_VECTORS);
    let eval = g.evaluate(tb.as_ref(), eval_vectors, seed);
    println!("  evaluator   {eval}");
    let t = Instant::now();
    let harness = sim::Harness::build(&g.ports, &dir, &cache_dir(cache))?;
    println!("  harness     ready in {:.1} s", t.elapsed().as_secs_f64());
    let replay_hint = format!(
        "rtl-gen replay {} {} --seed {seed} --index {{index}} --vcd mismatch.vcd",
        g.unit,
        g.param_args()
    );
    let opts = sim::CheckOptions {
        vectors,
        seed,
        progress,
        replay_hint: Some(replay_hint),
        ..Default::default()
    };
    let report = sim::cross_check(&harness, tb.as_ref(), tb.as_ref(), &opts)?;
    println!("{report}");
    Ok(report.mismatches == 0 && eval.mismatches == 0)
}

fn replay(
    unit: &UnitArgs,
    seed: u64,
    index: u64,
    vcd: &PathBuf,
    out: Option<PathBuf>,
    cache: Option<PathBuf>,
) -> Result<bool, FlowError> {
    let g = flow::generate(&unit.unit, &unit.params)?;
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
    let opts = accuracy::StudyOptions {
        fmt,
        styles,
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
