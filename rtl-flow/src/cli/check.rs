//! The runs through Verilator and the golden model: `check` (generated
//! vectors or a TestFloat file), `sim` and `golden` (a vector file), `replay`.

use super::args::{FileArgs, ReportArgs, ScaleArgs, UnitArgs};
use super::{bad_usage, cache_dir, format_word, out_dir};
use crate::report::{RunReport, Shard};
use crate::{byo, regress, FlowError, Generated};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Vectors also run through the (slow) IR evaluator, as a third opinion.
const EVALUATOR_VECTORS: u64 = 20_000;

/// Writes the requested reports; a report that cannot be written is an error.
pub(super) fn write_reports(report: &RunReport, args: &ReportArgs) -> Result<(), FlowError> {
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

/// Writes the unit's files into `dir`, says what is checked (`what` after
/// the parameters) and lints the Verilog: the start of every check.
fn write_and_lint(g: &Generated, dir: &Path, what: &str) -> Result<(), FlowError> {
    g.write(dir, 10.0)?;
    println!(
        "rtl-gen check {} ({}){what}",
        g.unit,
        rtl_gen::emit::lower::params_line(g.params.values())
    );
    println!(
        "  module      {} (latency {} cycle(s), II 1)",
        g.module.name, g.module.latency
    );
    println!("  files       {}", dir.display());
    sim::lint(&g.ports, dir)?;
    println!("  lint        verilator --lint-only -Wall: clean");
    Ok(())
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
pub(super) fn check(
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
        write_and_lint(&g, &dir, "")?;
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

pub(super) fn check_testfloat(
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
        write_and_lint(&g, &dir, &format!(" --testfloat {name}"))?;
        let harness = sim::Harness::build(&g.ports, &dir, &cache_dir(cache))?;
        let tb = g.testbench();
        let o = testfloat::run(&g, &harness, tb.as_ref(), &map, &cases, name, nan_exact)?;
        print!("{o}");
        *report = o.report;
        println!("{}", report.headline());
        Ok(report.passed)
    })
}

pub(super) fn sim_file(
    unit: &UnitArgs,
    files: &FileArgs,
    compare: bool,
    verilog: Option<&Path>,
    dir: Option<PathBuf>,
    cache: Option<PathBuf>,
    reports: &ReportArgs,
) -> Result<bool, FlowError> {
    crate::check_outputs(&reports.with(&files.out))?;
    let mut g = unit.generate()?;
    if let Some(v) = verilog {
        let n = g.use_verilog_from(v)?;
        eprintln!(
            "simulating {n} of {} module files from {}",
            g.files.len(),
            v.display()
        );
    }
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

pub(super) fn golden_file(
    unit: &UnitArgs,
    files: &FileArgs,
    reports: &ReportArgs,
) -> Result<bool, FlowError> {
    crate::check_outputs(&reports.with(&files.out))?;
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
    let format = format_word(o.format);
    println!("wrote {} ({format}, {} records)", out.display(), o.vectors);
    println!("{}", o.report.headline());
}

pub(super) fn replay(
    unit: &UnitArgs,
    seed: u64,
    index: u64,
    vcd: &Path,
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
