//! A cross-check's options, progress, mismatches and reports.

use super::*;

/// Where a cross-check stands, passed to [`CheckOptions::on_progress`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Vectors compared so far, over all workers.
    pub done: u64,
    /// Vectors this check runs in total.
    pub total: u64,
    /// Mismatching vectors found so far.
    pub mismatches: u64,
}

/// A progress callback: called after every compared batch (a few thousand
/// vectors) by whichever worker finished it, so it must be cheap and
/// thread-safe (a progress bar's `set_position` is).
#[derive(Clone)]
pub struct ProgressFn(pub Arc<dyn Fn(&Progress) + Send + Sync>);

impl ProgressFn {
    /// Wraps a closure.
    pub fn new(f: impl Fn(&Progress) + Send + Sync + 'static) -> ProgressFn {
        ProgressFn(Arc::new(f))
    }
}

impl fmt::Debug for ProgressFn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("ProgressFn(..)")
    }
}

/// Options of [`cross_check`].
///
/// The check runs the vectors with indices `first + k·stride` for
/// `k in 0..vectors`: the whole sequence by default, one shard of it with
/// `first = K`, `stride = N` (shard K of N, 0-based). Vector indices in
/// reports, replay commands and replay files are always these global
/// indices, so a mismatch found by a shard replays with the same command as
/// in an unsharded run.
#[derive(Clone, Debug)]
pub struct CheckOptions {
    /// Number of vectors to run.
    pub vectors: u64,
    /// Stimulus seed.
    pub seed: u64,
    /// Index of the first vector.
    pub first: u64,
    /// Distance between the indices of consecutive vectors (at least 1).
    pub stride: u64,
    /// Harness processes run in parallel, each fed and checked by its own
    /// threads; worker `w` of `J` runs every `J`-th vector from the `w`-th.
    /// 0 means 1.
    pub jobs: usize,
    /// Print progress to stderr about once a second.
    pub progress: bool,
    /// Called after every compared batch (for a progress bar).
    pub on_progress: Option<ProgressFn>,
    /// The caller's command to replay one vector; `{index}` and `{seed}`
    /// are substituted.
    pub replay_hint: Option<String>,
    /// Insert pseudo-random idle cycles (harness `--bubbles SEED`).
    pub bubbles: Option<u64>,
    /// How many mismatches to describe in full (the count is always exact).
    pub keep_mismatches: usize,
    /// Where failing vectors are written for replay; default
    /// `<temp dir>/rtl-sim-mismatches`.
    pub mismatch_dir: Option<PathBuf>,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            vectors: 1_000_000,
            seed: 0,
            first: 0,
            stride: 1,
            jobs: 1,
            progress: false,
            on_progress: None,
            replay_hint: None,
            bubbles: None,
            keep_mismatches: 10,
            mismatch_dir: None,
        }
    }
}

impl CheckOptions {
    /// The global index of the `k`-th vector of this check.
    pub fn index(&self, k: u64) -> u64 {
        self.first + k * self.stride.max(1)
    }
}

/// One vector on which RTL and golden model disagree.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mismatch {
    /// Vector index (also the record number in the input stream).
    pub index: u64,
    /// The inputs, by port.
    pub inputs: Vec<(String, u64)>,
    /// Golden-model outputs, by port.
    pub expected: Vec<(String, u64)>,
    /// RTL outputs, by port.
    pub got: Vec<(String, u64)>,
    /// The single-vector input file written for replay, if writing worked.
    pub vector_file: Option<PathBuf>,
    /// Shell commands that replay this vector with a VCD trace.
    pub replay: String,
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "mismatch at vector {}", self.index)?;
        write!(f, "  inputs: ")?;
        for (i, (n, v)) in self.inputs.iter().enumerate() {
            let sep = if i == 0 { "" } else { " " };
            write!(f, "{sep}{n}={v:#x}")?;
        }
        writeln!(f)?;
        let name_w = self
            .expected
            .iter()
            .map(|(n, _)| n.len())
            .max()
            .unwrap_or(0)
            .max(6);
        let val_w = self
            .expected
            .iter()
            .chain(&self.got)
            .map(|(_, v)| format!("{v:#x}").len())
            .max()
            .unwrap_or(0)
            .max(8);
        writeln!(f, "  {:name_w$}  {:val_w$}  got", "output", "expected")?;
        for ((n, e), (_, g)) in self.expected.iter().zip(&self.got) {
            let (es, gs) = (format!("{e:#x}"), format!("{g:#x}"));
            if e == g {
                writeln!(f, "  {n:name_w$}  {es:val_w$}  {gs}")?;
            } else {
                writeln!(
                    f,
                    "  {n:name_w$}  {es:val_w$}  {gs:val_w$}  <- differs in bits {:#x}",
                    e ^ g
                )?;
            }
        }
        for (i, line) in self.replay.lines().enumerate() {
            let label = if i == 0 { "replay:" } else { "    or:" };
            writeln!(f, "  {label} {line}")?;
        }
        Ok(())
    }
}

/// What one worker (one harness process) of a cross-check did.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkerReport {
    /// Global index of its first vector.
    pub first: u64,
    /// Distance between its vector indices.
    pub stride: u64,
    /// Vectors it checked.
    pub vectors: u64,
    /// Mismatching vectors among them.
    pub mismatches: u64,
    /// Wall time from starting its harness to the harness's exit.
    pub elapsed: Duration,
    /// Clock cycles its harness simulated.
    pub cycles: u64,
    /// Time its golden model took alone (its share of `elapsed`).
    pub golden: Duration,
}

impl WorkerReport {
    /// This worker's throughput.
    pub fn vectors_per_sec(&self) -> f64 {
        self.vectors as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}

/// Result of a completed cross-check.
#[derive(Clone, Debug)]
pub struct CheckReport {
    /// Top module.
    pub top: String,
    /// Vectors checked.
    pub vectors: u64,
    /// Stimulus seed.
    pub seed: u64,
    /// Index of the first vector ([`CheckOptions::first`]).
    pub first: u64,
    /// Distance between vector indices ([`CheckOptions::stride`]).
    pub stride: u64,
    /// Vectors with at least one differing output.
    pub mismatches: u64,
    /// The mismatch with the lowest index, in full (the same whatever the
    /// number of workers).
    pub first_mismatch: Option<Mismatch>,
    /// Further mismatches in full, in index order, up to
    /// `keep_mismatches - 1` of them.
    pub more_mismatches: Vec<Mismatch>,
    /// Wall time from starting the harnesses to the last one's exit.
    pub elapsed: Duration,
    /// Clock cycles the harnesses simulated (reset, bubbles, drain included).
    pub cycles: u64,
    /// Idle cycles inserted between transactions.
    pub bubbles: u64,
    /// One entry per harness process, in worker order.
    pub workers: Vec<WorkerReport>,
}

impl CheckReport {
    /// End-to-end throughput.
    pub fn vectors_per_sec(&self) -> f64 {
        self.vectors as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }

    /// True when every vector matched.
    pub fn passed(&self) -> bool {
        self.mismatches == 0
    }
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let verdict = if self.passed() { "PASS" } else { "FAIL" };
        writeln!(
            f,
            "{verdict}: `{}`, {} vectors (seed {:#x}), {} mismatches",
            self.top, self.vectors, self.seed, self.mismatches
        )?;
        if self.first != 0 || self.stride != 1 {
            writeln!(
                f,
                "  vector indices {} + {}·k, k < {}",
                self.first, self.stride, self.vectors
            )?;
        }
        writeln!(
            f,
            "  {} cycles ({} bubbles) in {:.2} s: {:.2} M vectors/s",
            self.cycles,
            self.bubbles,
            self.elapsed.as_secs_f64(),
            self.vectors_per_sec() / 1e6
        )?;
        // which side limits the check: the golden model alone against the whole
        let golden = self.workers.iter().map(|w| w.golden).sum::<Duration>();
        let worker_time = self.workers.iter().map(|w| w.elapsed).sum::<Duration>();
        writeln!(
            f,
            "  golden model alone: {:.2} M vectors/s per worker ({:.0} % of the workers' time)",
            self.vectors as f64 / golden.as_secs_f64().max(1e-9) / 1e6,
            100.0 * golden.as_secs_f64() / worker_time.as_secs_f64().max(1e-9)
        )?;
        if self.workers.len() > 1 {
            let each: Vec<String> = self
                .workers
                .iter()
                .map(|w| format!("{:.2}", w.vectors_per_sec() / 1e6))
                .collect();
            writeln!(
                f,
                "  {} workers, M vectors/s each: {}",
                self.workers.len(),
                each.join(", ")
            )?;
        }
        if let Some(m) = &self.first_mismatch {
            write!(f, "{m}")?;
        }
        if !self.more_mismatches.is_empty() {
            let idx: Vec<String> = self
                .more_mismatches
                .iter()
                .map(|m| m.index.to_string())
                .collect();
            let shown = 1 + self.more_mismatches.len() as u64;
            let rest = if self.mismatches > shown { ", ..." } else { "" };
            writeln!(f, "  further mismatching vectors: {}{rest}", idx.join(", "))?;
        }
        Ok(())
    }
}

/// Quotes a string for a POSIX shell when it needs it.
pub(super) fn shell_quote(s: &str) -> String {
    if !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"/._-+=:,@".contains(&b))
    {
        s.to_owned()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}
