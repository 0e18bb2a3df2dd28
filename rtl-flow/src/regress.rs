//! A check as the CLI runs it, for one shard and several cores: the IR
//! evaluator on the shard's share of the first vectors, then the Verilator
//! cross-check on the shard's vectors in `jobs` harness processes, and the
//! machine-readable report of both.

use super::report::{EvaluatorStats, RunReport, Shard};
use super::{FlowError, Generated, Testbench};
use std::path::PathBuf;

/// What to run.
#[derive(Clone, Debug)]
pub struct CheckRun {
    /// vectors of the whole (unsharded) run: indices `0..vectors`
    pub vectors: u64,
    /// stimulus seed
    pub seed: u64,
    /// the slice of `0..vectors` this run covers
    pub shard: Shard,
    /// harness processes in parallel (0: all cores)
    pub jobs: usize,
    /// vectors with an index below this also run through the IR evaluator
    pub evaluator_vectors: u64,
    /// progress callback for a bar
    pub on_progress: Option<sim::ProgressFn>,
    /// where failing vectors are written for replay
    pub mismatch_dir: Option<PathBuf>,
}

impl CheckRun {
    /// `vectors` from `seed`, unsharded, on every core, 20,000 vectors
    /// through the evaluator.
    pub fn new(vectors: u64, seed: u64) -> CheckRun {
        CheckRun {
            vectors,
            seed,
            shard: Shard::ALL,
            jobs: 0,
            evaluator_vectors: 20_000,
            on_progress: None,
            mismatch_dir: None,
        }
    }
}

/// The number of cores, the default for `--jobs`.
pub fn all_cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// What a check found.
pub struct CheckOutcome {
    /// the Verilator cross-check
    pub check: sim::CheckReport,
    /// the IR evaluator (its `first` index is global)
    pub evaluator: super::EvalReport,
    /// both, for `--report` and `--junit`
    pub report: RunReport,
}

/// The command that replays vector `{index}` of a check of `g` with `seed`
/// (the same for every shard: indices are global).
pub fn replay_hint(g: &Generated, seed: u64) -> String {
    let params = g.param_args();
    let sep = if params.is_empty() { "" } else { " " };
    format!(
        "rtl-gen replay {}{sep}{params} --seed {seed} --index {{index}} --vcd mismatch.vcd",
        g.unit
    )
}

/// Testbench seen through a slice of the index space: its vector `k` is
/// the inner vector `first + k·stride`.
struct Strided<'a> {
    tb: &'a dyn Testbench,
    first: u64,
    stride: u64,
}

impl sim::Golden for Strided<'_> {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        self.tb.eval(inputs, outputs)
    }
    fn eval_batch(&self, inputs: &[u64], n_in: usize, outputs: &mut [u64], n_out: usize) {
        self.tb.eval_batch(inputs, n_in, outputs, n_out)
    }
}

impl sim::Stimulus for Strided<'_> {
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        self.tb
            .vector(seed, self.first + index * self.stride, inputs)
    }
}

impl Testbench for Strided<'_> {}

/// Runs the shard's vectors through the IR evaluator (indices below
/// `evaluator_vectors`) and Verilator (all of them), comparing both with
/// `tb`'s golden model.
pub fn run_check(
    g: &Generated,
    harness: &sim::Harness,
    tb: &dyn Testbench,
    run: &CheckRun,
) -> Result<CheckOutcome, FlowError> {
    let shard = run.shard;
    let strided = Strided {
        tb,
        first: shard.first(),
        stride: shard.count,
    };
    let mut evaluator = g.evaluate(
        &strided,
        shard.len(run.vectors.min(run.evaluator_vectors)),
        run.seed,
    );
    if let Some(first) = &mut evaluator.first {
        first.0 = shard.first() + first.0 * shard.count;
    }
    let jobs = if run.jobs == 0 { all_cores() } else { run.jobs };
    let opts = sim::CheckOptions {
        vectors: shard.len(run.vectors),
        seed: run.seed,
        first: shard.first(),
        stride: shard.count,
        jobs,
        progress: false,
        on_progress: run.on_progress.clone(),
        replay_hint: Some(replay_hint(g, run.seed)),
        mismatch_dir: run.mismatch_dir.clone(),
        ..Default::default()
    };
    let check = sim::cross_check(harness, tb, tb, &opts)?;
    let mut report = RunReport::new("check", g);
    report.seed = Some(run.seed);
    report.total_vectors = run.vectors;
    report.shard = shard;
    report.evaluator = Some(EvaluatorStats {
        vectors: evaluator.vectors,
        mismatches: evaluator.mismatches,
        first_index: evaluator.first.as_ref().map(|f| f.0),
    });
    report.set_check(&check);
    Ok(CheckOutcome {
        check,
        evaluator,
        report,
    })
}
