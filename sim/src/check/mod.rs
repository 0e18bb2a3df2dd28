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

mod model;
mod replay;
mod report;

pub use model::{mix64, Golden, RandomStimulus, Stimulus};
pub use replay::replay;
use report::shell_quote;
pub use report::{CheckOptions, CheckReport, Mismatch, Progress, ProgressFn, WorkerReport};

/// Vectors per batch: big enough to amortise dynamic calls and buffer
/// handling, small enough to stay in L2.
const BATCH: usize = 4096;

/// How much harness stderr is kept for error messages.
const STDERR_KEEP: usize = 64 * 1024;

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
            golden: compared.golden,
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
    /// time spent in the golden model alone
    golden: Duration,
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
        golden: Duration::ZERO,
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
        let golden_start = Instant::now();
        golden.eval_batch(inp, n_in, exp, n_out);
        out.golden += golden_start.elapsed();
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

/// Describes one mismatch of a cross-check and writes its vector to a replay file.
fn mismatch(
    h: &Harness,
    opts: &CheckOptions,
    index: u64,
    inputs: &[u64],
    expected: &[u64],
    got: &[u64],
) -> Mismatch {
    let dir = opts
        .mismatch_dir
        .clone()
        .unwrap_or_else(|| std::env::temp_dir().join("rtl-sim-mismatches"));
    let stem = format!("{}-seed{:x}-vec{index}", h.ports().top, opts.seed);
    let hint = opts.replay_hint.as_ref().map(|hint| {
        hint.replace("{index}", &index.to_string())
            .replace("{seed}", &opts.seed.to_string())
    });
    describe_mismatch(h, &dir, &stem, hint, index, inputs, expected, got)
}

/// Describes vector `index` on which `h` answered `got` and the golden model
/// `expected`, and writes the vector to `dir/<stem>.rtlvec` for a replay with
/// a VCD trace (`hint`, a caller's own replay command, listed first). Used by
/// the cross-check and by callers that stream their own vectors.
#[allow(clippy::too_many_arguments)]
pub fn describe_mismatch(
    h: &Harness,
    dir: &Path,
    stem: &str,
    hint: Option<String>,
    index: u64,
    inputs: &[u64],
    expected: &[u64],
    got: &[u64],
) -> Mismatch {
    let ports = h.ports();
    let file = dir.join(format!("{stem}.rtlvec"));
    let vcd = dir.join(format!("{stem}.vcd"));
    let written = write_vector(dir, &file, &ports.inputs, inputs);
    let mut replay: Vec<String> = hint.into_iter().collect();
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
