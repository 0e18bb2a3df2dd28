//! Streaming cross-check of a built harness against a golden model.
//!
//! Three activities run at once: a thread generates vectors and streams
//! them into the harness's stdin; the harness simulates; the calling thread
//! reads the harness's results, regenerates each vector from its index (the
//! stimulus is deterministic, so nothing is queued between the two threads),
//! runs the golden model and compares every output bit for bit.

use std::fmt;
use std::io::{self, Read};
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::{ChildStderr, ChildStdin, ChildStdout, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

use crate::error::SimError;
use crate::harness::{describe_exit, Harness, RunStats};
use crate::ports::{Port, PortList};
use crate::vectors::{BinReader, BinWriter};

/// Vectors per batch: big enough to amortise dynamic calls and buffer
/// handling, small enough to stay in L2.
const BATCH: usize = 4096;

/// How much harness stderr is kept for error messages.
const STDERR_KEEP: usize = 64 * 1024;

/// A bit-accurate reference model of the unit.
pub trait Golden: Send + Sync {
    /// Computes one value per output port, in port-list order, for one
    /// vector of inputs in port-list order.
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]);

    /// Evaluates consecutive vectors (`n_in` inputs and `n_out` outputs
    /// each). The default loops over [`Golden::eval`], statically
    /// dispatched; override it to vectorise.
    fn eval_batch(&self, inputs: &[u64], n_in: usize, outputs: &mut [u64], n_out: usize) {
        for (i, o) in inputs
            .chunks_exact(n_in)
            .zip(outputs.chunks_exact_mut(n_out))
        {
            self.eval(i, o);
        }
    }
}

impl<F> Golden for F
where
    F: Fn(&[u64], &mut [u64]) + Send + Sync,
{
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        self(inputs, outputs)
    }
}

/// A deterministic source of input vectors.
pub trait Stimulus: Send + Sync {
    /// Writes vector number `index` of the sequence selected by `seed` into
    /// `inputs` (one value per input port, each within its width). Must
    /// return the same vector for the same `(seed, index)`; corner cases
    /// first, then random, is the usual pattern.
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]);

    /// Writes consecutive vectors from index `first`, `n_in` values each.
    /// The default loops over [`Stimulus::vector`].
    fn vectors(&self, seed: u64, first: u64, n_in: usize, inputs: &mut [u64]) {
        for (k, v) in inputs.chunks_exact_mut(n_in).enumerate() {
            self.vector(seed, first + k as u64, v);
        }
    }

    /// Writes the vectors `first`, `first + stride`, `first + 2·stride`, ...
    /// (`n_in` values each): the slice of the index space one worker or one
    /// shard runs. The default calls [`Stimulus::vectors`] for `stride == 1`
    /// and loops over [`Stimulus::vector`] otherwise.
    fn vectors_strided(&self, seed: u64, first: u64, stride: u64, n_in: usize, inputs: &mut [u64]) {
        if stride == 1 {
            return self.vectors(seed, first, n_in, inputs);
        }
        for (k, v) in inputs.chunks_exact_mut(n_in).enumerate() {
            self.vector(seed, first + k as u64 * stride, v);
        }
    }
}

impl<F> Stimulus for F
where
    F: Fn(u64, u64, &mut [u64]) + Send + Sync,
{
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        self(seed, index, inputs)
    }
}

/// The splitmix64 finaliser: a fast, well-mixed 64-bit hash for building
/// index-addressed stimulus.
#[inline]
pub fn mix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Generic stimulus: [`RandomStimulus::CORNERS`] corner vectors (all zero,
/// all ones, all one-valued, alternating bit patterns, maximum/zero mixes),
/// then uniformly random values within each port's width.
#[derive(Clone, Debug)]
pub struct RandomStimulus {
    masks: Vec<u64>,
}

impl RandomStimulus {
    /// Number of leading corner-case vectors.
    pub const CORNERS: u64 = 7;

    /// Stimulus for these input ports.
    pub fn new(inputs: &[Port]) -> RandomStimulus {
        RandomStimulus {
            masks: inputs.iter().map(Port::mask).collect(),
        }
    }
}

impl Stimulus for RandomStimulus {
    #[inline]
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        let base = mix64(seed ^ index.wrapping_mul(0xd1b5_4a32_d192_ed03));
        for (k, (v, &m)) in inputs.iter_mut().zip(&self.masks).enumerate() {
            *v = m & match index {
                0 => 0,
                1 => u64::MAX,
                2 => 1,
                3 => 0x5555_5555_5555_5555,
                4 => 0xaaaa_aaaa_aaaa_aaaa,
                5 if k % 2 == 0 => u64::MAX,
                5 => 0,
                6 if k % 2 == 0 => 0,
                6 => u64::MAX,
                _ => mix64(base.wrapping_add(k as u64)),
            };
        }
    }
}

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
fn shell_quote(s: &str) -> String {
    if !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"/._-+=:,@".contains(&b))
    {
        s.to_owned()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

/// One worker's share of a check: vectors `first + k·stride`, `k < count`.
#[derive(Clone, Copy, Debug)]
struct Slice {
    first: u64,
    stride: u64,
    count: u64,
}

/// State the workers of one check share.
struct Shared {
    done: AtomicU64,
    mismatches: AtomicU64,
    /// Set when a worker failed: the others stop at their next batch.
    abort: AtomicBool,
    last_print: Mutex<Instant>,
}

/// Why a worker stopped without a result.
enum Stop {
    Failed(SimError),
    /// Another worker failed first.
    Aborted,
}

impl From<SimError> for Stop {
    fn from(e: SimError) -> Self {
        Stop::Failed(e)
    }
}

/// What one worker returns.
struct WorkerOut {
    report: WorkerReport,
    bubbles: u64,
    kept: Vec<Mismatch>,
}

/// Runs `opts.vectors` vectors through the harness and compares every
/// output with the golden model, in `opts.jobs` harness processes at once.
/// Mismatches are counted and reported, not errors; errors are a failed
/// harness (its stderr included), a result count different from the vector
/// count, or unusable stimulus/golden values. When one worker fails, the
/// others stop and the first failure is returned.
pub fn cross_check(
    h: &Harness,
    golden: &dyn Golden,
    stim: &dyn Stimulus,
    opts: &CheckOptions,
) -> Result<CheckReport, SimError> {
    let ports = h.ports();
    let stride = opts.stride.max(1);
    let jobs = (opts.jobs.max(1) as u64).min(opts.vectors.max(1));
    let started = Instant::now();
    let shared = Shared {
        done: AtomicU64::new(0),
        mismatches: AtomicU64::new(0),
        abort: AtomicBool::new(false),
        last_print: Mutex::new(started),
    };
    let outs: Vec<Result<WorkerOut, Stop>> = thread::scope(|s| {
        let handles: Vec<_> = (0..jobs)
            .map(|w| {
                let slice = Slice {
                    first: opts.first + w * stride,
                    stride: stride * jobs,
                    count: (opts.vectors.saturating_sub(w)).div_ceil(jobs),
                };
                let shared = &shared;
                s.spawn(move || {
                    let r = panic::catch_unwind(AssertUnwindSafe(|| {
                        run_worker(h, golden, stim, opts, slice, shared)
                    }));
                    if !matches!(r, Ok(Ok(_))) {
                        shared.abort.store(true, Ordering::Relaxed);
                    }
                    r
                })
            })
            .collect();
        let joined: Vec<_> = handles
            .into_iter()
            .map(|t| t.join().unwrap_or_else(|p| panic::resume_unwind(p)))
            .collect();
        joined
            .into_iter()
            .map(|r| r.unwrap_or_else(|p| panic::resume_unwind(p)))
            .collect()
    });
    let mut workers = Vec::new();
    let mut kept = Vec::new();
    let (mut cycles, mut bubbles) = (0, 0);
    let mut failure = None;
    for out in outs {
        match out {
            Ok(o) => {
                cycles += o.report.cycles;
                bubbles += o.bubbles;
                workers.push(o.report);
                kept.extend(o.kept);
            }
            Err(Stop::Failed(e)) => {
                failure.get_or_insert(e);
            }
            Err(Stop::Aborted) => {}
        }
    }
    if let Some(e) = failure {
        return Err(e);
    }
    // Each worker kept its lowest-index mismatches, so the lowest overall
    // are among them, whatever the number of workers.
    kept.sort_by_key(|m| m.index);
    kept.truncate(opts.keep_mismatches);
    let mut kept = kept.into_iter();
    Ok(CheckReport {
        top: ports.top.clone(),
        vectors: workers.iter().map(|w| w.vectors).sum(),
        seed: opts.seed,
        first: opts.first,
        stride,
        mismatches: workers.iter().map(|w| w.mismatches).sum(),
        first_mismatch: kept.next(),
        more_mismatches: kept.collect(),
        elapsed: started.elapsed(),
        cycles,
        bubbles,
        workers,
    })
}

/// One harness process: a feeder thread, a stderr reader, and the calling
/// thread comparing.
fn run_worker(
    h: &Harness,
    golden: &dyn Golden,
    stim: &dyn Stimulus,
    opts: &CheckOptions,
    slice: Slice,
    shared: &Shared,
) -> Result<WorkerOut, Stop> {
    let ports = h.ports();
    let started = Instant::now();
    let mut cmd = h.command();
    if let Some(seed) = opts.bubbles {
        cmd.arg("--bubbles").arg(seed.to_string());
    }
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| SimError::io(format!("starting {}", h.binary().display()), e))?;
    let stdin = child.stdin.take().expect("piped stdin");
    // Held here, not by the checker, so that the harness cannot see a
    // closed pipe (and exit with an I/O error of our making) before it is
    // killed: an exit code then always is the harness's own verdict.
    let mut stdout = child.stdout.take().expect("piped stdout");
    let stderr = child.stderr.take().expect("piped stderr");

    let (fed, compared, killed, status, stderr_text) = thread::scope(|s| {
        let feeder = s.spawn(|| feed(stdin, &ports.inputs, stim, opts.seed, slice));
        let err_reader = s.spawn(|| read_tail(stderr));
        let compared = panic::catch_unwind(AssertUnwindSafe(|| {
            compare(&mut stdout, h, golden, stim, opts, slice, shared)
        }));
        // A checker that stopped early (error, abort or panic in the golden
        // model) no longer drains the harness, which would then block the
        // feeder and this scope forever: end the harness instead.
        let killed = !matches!(compared, Ok(Ok(_))) && child.kill().is_ok();
        let compared = compared.unwrap_or_else(|p| {
            let _ = child.wait();
            panic::resume_unwind(p)
        });
        let fed = feeder.join().unwrap_or_else(|p| panic::resume_unwind(p));
        let status = child.wait();
        let stderr_text = err_reader
            .join()
            .unwrap_or_else(|p| panic::resume_unwind(p));
        (fed, compared, killed, status, stderr_text)
    });
    let status = status.map_err(|e| SimError::io("waiting for the harness", e))?;
    let harness_err = |message: String| {
        Stop::Failed(SimError::Harness {
            message,
            stderr: stderr_text.clone(),
        })
    };

    // Report the root cause: bad stimulus first, then a harness that failed
    // on its own, then what the checker saw; a broken pipe is only ever a
    // symptom of the harness stopping.
    let fed_pipe_err = match fed {
        Ok(()) => None,
        Err(SimError::Io { source, context }) if source.kind() == io::ErrorKind::BrokenPipe => {
            Some(SimError::Io { source, context })
        }
        Err(e) => return Err(Stop::Failed(e)),
    };
    // An exit code is the harness's own verdict even if we also killed it
    // (it exited first); a signal counts unless it was ours.
    if !status.success() && (status.code().is_some() || !killed) {
        return Err(harness_err(format!(
            "harness for `{}` {}",
            ports.top,
            describe_exit(status)
        )));
    }
    let compared = match compared {
        Ok(c) => c,
        Err(Stop::Aborted) => return Err(Stop::Aborted),
        Err(Stop::Failed(SimError::Invalid(m))) => return Err(Stop::Failed(SimError::Invalid(m))),
        Err(Stop::Failed(e)) => return Err(harness_err(format!("reading harness results: {e}"))),
    };
    if let Some(e) = fed_pipe_err {
        return Err(harness_err(format!("sending vectors to the harness: {e}")));
    }
    if compared.results != slice.count {
        return Err(harness_err(format!(
            "harness for `{}` returned {} results for {} vectors",
            ports.top, compared.results, slice.count
        )));
    }
    let stats = RunStats::parse(&stderr_text)
        .ok_or_else(|| harness_err("harness did not report `cycles=...`".into()))?;
    if stats.transactions != slice.count {
        return Err(harness_err(format!(
            "harness reports {} transactions for {} vectors sent",
            stats.transactions, slice.count
        )));
    }
    Ok(WorkerOut {
        report: WorkerReport {
            first: slice.first,
            stride: slice.stride,
            vectors: slice.count,
            mismatches: compared.mismatches,
            elapsed: started.elapsed(),
            cycles: stats.cycles,
        },
        bubbles: stats.bubbles,
        kept: compared.kept,
    })
}

/// Generates the vectors and streams them into the harness.
fn feed(
    stdin: ChildStdin,
    inputs: &[Port],
    stim: &dyn Stimulus,
    seed: u64,
    slice: Slice,
) -> Result<(), SimError> {
    let n_in = inputs.len();
    let mut w = BinWriter::new(stdin, "harness stdin", inputs)?;
    let mut buf = vec![0u64; BATCH * n_in];
    let mut k = 0u64;
    while k < slice.count {
        let n = (slice.count - k).min(BATCH as u64) as usize;
        let vals = &mut buf[..n * n_in];
        let first = slice.first + k * slice.stride;
        stim.vectors_strided(seed, first, slice.stride, n_in, vals);
        for (j, v) in vals.chunks_exact(n_in).enumerate() {
            if let Err(e) = w.write_record(v) {
                return Err(match e {
                    SimError::Format { field, message, .. } => SimError::Invalid(format!(
                        "stimulus (seed {seed:#x}) vector {}, input `{}`: {message}",
                        first + j as u64 * slice.stride,
                        field.unwrap_or_default()
                    )),
                    other => other,
                });
            }
        }
        k += n as u64;
    }
    w.finish().map(drop)
}

/// Reads the harness's stderr to the end, keeping the last part.
fn read_tail(mut stderr: ChildStderr) -> String {
    let mut kept: Vec<u8> = Vec::new();
    let mut chunk = [0u8; 8192];
    loop {
        match stderr.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => {
                kept.extend_from_slice(&chunk[..n]);
                if kept.len() > 2 * STDERR_KEEP {
                    kept.drain(..kept.len() - STDERR_KEEP);
                }
            }
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(_) => break,
        }
    }
    String::from_utf8_lossy(&kept).into_owned()
}

/// What the checker thread found.
struct Compared {
    results: u64,
    mismatches: u64,
    kept: Vec<Mismatch>,
}

fn compare(
    stdout: &mut ChildStdout,
    h: &Harness,
    golden: &dyn Golden,
    stim: &dyn Stimulus,
    opts: &CheckOptions,
    slice: Slice,
    shared: &Shared,
) -> Result<Compared, Stop> {
    let ports = h.ports();
    let (n_in, n_out) = (ports.inputs.len(), ports.outputs.len());
    let mut rd = BinReader::new(stdout, "harness stdout")?;
    rd.expect_ports(&ports.outputs)?;
    let mut got = vec![0u64; BATCH * n_out];
    let mut exp = vec![0u64; BATCH * n_out];
    let mut inp = vec![0u64; BATCH * n_in];
    let mut out = Compared {
        results: 0,
        mismatches: 0,
        kept: Vec::new(),
    };
    loop {
        if shared.abort.load(Ordering::Relaxed) {
            return Err(Stop::Aborted);
        }
        let n = rd.read_records(&mut got)?;
        if n == 0 {
            return Ok(out);
        }
        let k0 = out.results;
        if k0 + n as u64 > slice.count {
            return Err(Stop::Failed(SimError::Harness {
                message: format!(
                    "harness returned more results than the {} vectors sent",
                    slice.count
                ),
                stderr: String::new(),
            }));
        }
        let (inp, exp, got) = (
            &mut inp[..n * n_in],
            &mut exp[..n * n_out],
            &got[..n * n_out],
        );
        let first = slice.first + k0 * slice.stride;
        stim.vectors_strided(opts.seed, first, slice.stride, n_in, inp);
        golden.eval_batch(inp, n_in, exp, n_out);
        let before = out.mismatches;
        // The whole batch in one comparison; per-vector work only on failure.
        if exp != got {
            for k in 0..n {
                let (e, g) = (&exp[k * n_out..][..n_out], &got[k * n_out..][..n_out]);
                if e == g {
                    continue;
                }
                let index = first + k as u64 * slice.stride;
                check_golden_widths(&ports.outputs, e, index)?;
                out.mismatches += 1;
                if out.kept.len() < opts.keep_mismatches {
                    let m = mismatch(h, opts, index, &inp[k * n_in..][..n_in], e, g);
                    out.kept.push(m);
                }
            }
        }
        out.results += n as u64;
        let done = shared.done.fetch_add(n as u64, Ordering::Relaxed) + n as u64;
        let mismatches = shared
            .mismatches
            .fetch_add(out.mismatches - before, Ordering::Relaxed)
            + (out.mismatches - before);
        let now = Progress {
            done,
            total: opts.vectors,
            mismatches,
        };
        if let Some(cb) = &opts.on_progress {
            (cb.0)(&now);
        }
        if opts.progress {
            print_progress(&ports.top, shared, &now);
        }
    }
}

/// The once-a-second stderr line of [`CheckOptions::progress`].
fn print_progress(top: &str, shared: &Shared, now: &Progress) {
    let Ok(mut last) = shared.last_print.try_lock() else {
        return;
    };
    if last.elapsed() < Duration::from_secs(1) {
        return;
    }
    *last = Instant::now();
    eprintln!(
        "sim `{top}`: {}/{} vectors, {} mismatches",
        now.done, now.total, now.mismatches
    );
}

/// A golden value wider than its port can never match the RTL: that is a
/// bug in the model, reported as such instead of as a mismatch.
fn check_golden_widths(outputs: &[Port], values: &[u64], index: u64) -> Result<(), SimError> {
    for (p, &v) in outputs.iter().zip(values) {
        if v & !p.mask() != 0 {
            return Err(SimError::Invalid(format!(
                "golden model returned {v:#x} for output `{}` ({} bits) at vector {index}: \
                 value wider than port",
                p.name, p.width
            )));
        }
    }
    Ok(())
}

fn named(ports: &[Port], values: &[u64]) -> Vec<(String, u64)> {
    ports
        .iter()
        .zip(values)
        .map(|(p, &v)| (p.name.clone(), v))
        .collect()
}

/// Describes one mismatch and writes its vector to a replay file.
fn mismatch(
    h: &Harness,
    opts: &CheckOptions,
    index: u64,
    inputs: &[u64],
    expected: &[u64],
    got: &[u64],
) -> Mismatch {
    let ports = h.ports();
    let dir = opts
        .mismatch_dir
        .clone()
        .unwrap_or_else(|| std::env::temp_dir().join("rtl-sim-mismatches"));
    let stem = format!("{}-seed{:x}-vec{index}", ports.top, opts.seed);
    let file = dir.join(format!("{stem}.rtlvec"));
    let vcd = dir.join(format!("{stem}.vcd"));
    let written = write_vector(&dir, &file, &ports.inputs, inputs);
    let mut replay = Vec::new();
    if let Some(hint) = &opts.replay_hint {
        replay.push(
            hint.replace("{index}", &index.to_string())
                .replace("{seed}", &opts.seed.to_string()),
        );
    }
    // the traced variant is built (once, cached) only when something failed
    match (&written, h.traced()) {
        (Ok(()), Ok(traced)) => replay.push(format!(
            "{} --vcd {} < {}",
            shell_quote(&traced.binary().display().to_string()),
            shell_quote(&vcd.display().to_string()),
            shell_quote(&file.display().to_string())
        )),
        (Ok(()), Err(e)) => replay.push(format!("(no traced harness for a direct replay: {e})")),
        (Err(e), _) => replay.push(format!("(could not write the replay vector: {e})")),
    }
    Mismatch {
        index,
        inputs: named(&ports.inputs, inputs),
        expected: named(&ports.outputs, expected),
        got: named(&ports.outputs, got),
        vector_file: written.ok().map(|()| file),
        replay: replay.join("\n"),
    }
}

fn write_vector(dir: &Path, file: &Path, ports: &[Port], values: &[u64]) -> Result<(), SimError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| SimError::io(format!("creating {}", dir.display()), e))?;
    let mut w = BinWriter::create(file, ports)?;
    w.write_record(values)?;
    w.finish().map(drop)
}

/// Runs one vector through the harness, tracing into `vcd` if given, and
/// returns its outputs in port-list order.
pub fn replay(h: &Harness, inputs: &[u64], vcd: Option<&Path>) -> Result<Vec<u64>, SimError> {
    let ports: &PortList = h.ports();
    let mut w = BinWriter::new(Vec::new(), "replay vector", &ports.inputs)?;
    if inputs.len() != ports.inputs.len() {
        return Err(SimError::Invalid(format!(
            "replay: {} input values for {} input ports of `{}`",
            inputs.len(),
            ports.inputs.len(),
            ports.top
        )));
    }
    w.write_record(inputs)?;
    let bytes = w.finish()?;
    let traced;
    let h = match vcd {
        Some(_) if !h.is_traced() => {
            traced = h.traced()?;
            &traced
        }
        _ => h,
    };
    let mut cmd = h.command();
    if let Some(v) = vcd {
        cmd.arg("--vcd").arg(v);
    }
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| SimError::io(format!("starting {}", h.binary().display()), e))?;
    // One record is far below the pipe capacity, so writing before reading
    // cannot deadlock.
    let mut stdin = child.stdin.take().expect("piped stdin");
    let wrote = io::Write::write_all(&mut stdin, &bytes);
    drop(stdin);
    let out = child
        .wait_with_output()
        .map_err(|e| SimError::io("waiting for the harness", e))?;
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    if !out.status.success() {
        return Err(SimError::Harness {
            message: format!(
                "replay on `{}`: harness {}",
                ports.top,
                describe_exit(out.status)
            ),
            stderr,
        });
    }
    wrote.map_err(|e| SimError::io("writing the replay vector to the harness", e))?;
    let parse = || -> Result<Vec<u64>, SimError> {
        let mut rd = BinReader::new(&out.stdout[..], "harness stdout")?;
        rd.expect_ports(&ports.outputs)?;
        let mut values = vec![0; ports.outputs.len()];
        let mut extra = values.clone();
        if !rd.read_record(&mut values)? || rd.read_record(&mut extra)? {
            return Err(SimError::Invalid(format!(
                "expected exactly one result, got {}",
                rd.records()
            )));
        }
        Ok(values)
    };
    parse().map_err(|e| SimError::Harness {
        message: format!("replay on `{}`: {e}", ports.top),
        stderr,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_stimulus_is_deterministic_and_masked() {
        let ports = [Port::new("a", 5), Port::new("b", 64), Port::new("c", 1)];
        let s = RandomStimulus::new(&ports);
        let (mut x, mut y) = ([0; 3], [0; 3]);
        s.vector(7, 1, &mut x);
        assert_eq!(x, [31, u64::MAX, 1]);
        let mut seen_high = false;
        for i in 0..1000 {
            s.vector(7, i, &mut x);
            s.vector(7, i, &mut y);
            assert_eq!(x, y);
            assert!(x[0] < 32 && x[2] < 2);
            seen_high |= x[1] >> 63 == 1 && i >= RandomStimulus::CORNERS;
        }
        assert!(seen_high);
        s.vector(8, 100, &mut y);
        s.vector(7, 100, &mut x);
        assert_ne!(x, y);
    }

    #[test]
    fn batch_defaults_match_single_calls() {
        let ports = [Port::new("a", 16), Port::new("b", 16)];
        let s = RandomStimulus::new(&ports);
        let mut batch = vec![0; 20];
        s.vectors(3, 40, 2, &mut batch);
        for k in 0..10 {
            let mut one = [0; 2];
            s.vector(3, 40 + k, &mut one);
            assert_eq!(&batch[2 * k as usize..][..2], &one);
        }
        let g = |i: &[u64], o: &mut [u64]| o[0] = i[0] + i[1];
        let mut outs = vec![0; 10];
        g.eval_batch(&batch, 2, &mut outs, 1);
        assert_eq!(outs[3], batch[6] + batch[7]);
    }

    #[test]
    fn shell_quoting() {
        assert_eq!(shell_quote("/tmp/a-b_c.rtlvec"), "/tmp/a-b_c.rtlvec");
        assert_eq!(shell_quote("/tmp/a b"), "'/tmp/a b'");
        assert_eq!(shell_quote("it's"), r"'it'\''s'");
    }
}
