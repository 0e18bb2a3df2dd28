//! Building the generic Verilator harness for a design, with a
//! content-addressed build cache, and running it on vector files.

use std::env;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Output, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use crate::error::SimError;
use crate::hash::Fnv128;
use crate::ports::PortList;

/// The harness source, embedded so that no path lookup can go wrong.
pub const HARNESS_SOURCE: &str = include_str!("../../verilator/harness.cpp");

/// Verilator options every harness is built with, besides `--top-module`,
/// the sources, the build directory and the [`variant_flags`]. All of them
/// enter the cache key.
pub const VERILATOR_FLAGS: &[&str] = &[
    "--cc",
    "--exe",
    "--build",
    "-O3",
    "--x-assign",
    "fast",
    "--x-initial",
    "fast",
    // A fixed class name lets one harness.cpp include any design.
    "--prefix",
    "Vdut",
];

/// Designs whose Verilog is larger than this are compiled with cheaper C++
/// optimisation: for the big float units, `-O3` took 3 to 5 times as long to
/// compile as `-O1` for a simulation speed that 1,000,000 vectors do not need.
pub const LARGE_DESIGN_BYTES: usize = 48 * 1024;

/// Flags that depend on the build variant: tracing (only for replays with a
/// VCD, since the trace code roughly doubles the C++ to compile) and the C++
/// optimisation level (by design size). Part of the cache key.
pub fn variant_flags(traced: bool, source_bytes: usize) -> Vec<String> {
    let mut flags = Vec::new();
    if traced {
        flags.push("--trace".to_string());
    }
    // Verilator's makefile defaults to -Os; -O3 measured 1.7x faster
    // simulation for a 3-stage multiply-compare, which small designs keep.
    let opt = if source_bytes <= LARGE_DESIGN_BYTES {
        "OPT_FAST=-O3 OPT_GLOBAL=-O3 OPT_SLOW=-O1"
    } else {
        "OPT_FAST=-O1 OPT_GLOBAL=-O1 OPT_SLOW=-O0"
    };
    flags.push("-MAKEFLAGS".to_string());
    flags.push(opt.to_string());
    flags
}

/// Name of the harness executable inside a cache entry.
pub const BINARY_NAME: &str = "rtl_harness";

/// Bumped when the layout of a cache entry changes.
const CACHE_FORMAT: &str = "sim harness cache 1";

/// Exit code of the harness for bad usage or a bad input stream.
pub const EXIT_USAGE: i32 = 2;
/// Exit code of the harness when the design broke the latency/handshake.
pub const EXIT_PROTOCOL: i32 = 3;
/// Exit code of the harness for an I/O error on its output or VCD.
pub const EXIT_IO: i32 = 4;

/// Where harness builds are cached unless the caller says otherwise:
/// `$RTL_GEN_CACHE`, else `$CARGO_TARGET_DIR/rtl-cache`, else the
/// workspace's `target/rtl-cache`.
pub fn default_cache_root() -> PathBuf {
    let set = |k: &str| env::var_os(k).filter(|v| !v.is_empty()).map(PathBuf::from);
    if let Some(p) = set("RTL_GEN_CACHE") {
        return p;
    }
    if let Some(p) = set("CARGO_TARGET_DIR") {
        return p.join("rtl-cache");
    }
    // This crate lives at <workspace>/sim.
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest
        .parent()
        .unwrap_or(manifest)
        .join("target")
        .join("rtl-cache")
}

/// Runs an external tool to completion, capturing its output; a missing
/// program becomes [`SimError::ToolMissing`].
fn run_tool(program: &str, args: &[&str], cwd: Option<&Path>) -> Result<Output, SimError> {
    let mut cmd = Command::new(program);
    cmd.args(args).stdin(Stdio::null());
    if let Some(dir) = cwd {
        cmd.current_dir(dir);
    }
    cmd.output().map_err(|e| tool_error(program, e))
}

fn tool_error(program: &str, e: io::Error) -> SimError {
    if e.kind() == io::ErrorKind::NotFound {
        SimError::ToolMissing {
            tool: program.to_owned(),
            hint: "install Verilator 5 (Debian/Ubuntu: `apt-get install verilator`) and make \
                   sure it is on PATH"
                .to_owned(),
        }
    } else {
        SimError::io(format!("running {program}"), e)
    }
}

/// `verilator --version`, asked once per process.
pub fn verilator_version() -> Result<String, SimError> {
    static VERSION: OnceLock<String> = OnceLock::new();
    if let Some(v) = VERSION.get() {
        return Ok(v.clone());
    }
    let out = run_tool("verilator", &["--version"], None)?;
    if !out.status.success() {
        return Err(SimError::Build {
            message: format!("`verilator --version` {}", describe_exit(out.status)),
            output_tail: combined(&out),
        });
    }
    let v = String::from_utf8_lossy(&out.stdout).trim().to_owned();
    Ok(VERSION.get_or_init(|| v).clone())
}

fn combined(out: &Output) -> String {
    let mut s = String::from_utf8_lossy(&out.stdout).into_owned();
    s.push_str(&String::from_utf8_lossy(&out.stderr));
    s
}

/// Says how a process ended, in words.
pub(crate) fn describe_exit(status: ExitStatus) -> String {
    match status.code() {
        Some(EXIT_USAGE) => "exited with code 2 (bad usage or input stream)".into(),
        Some(EXIT_PROTOCOL) => "exited with code 3 (latency/handshake violation)".into(),
        Some(EXIT_IO) => "exited with code 4 (I/O error)".into(),
        Some(c) => format!("exited with code {c}"),
        None => {
            #[cfg(unix)]
            {
                use std::os::unix::process::ExitStatusExt;
                if let Some(sig) = status.signal() {
                    return format!("was killed by signal {sig}");
                }
            }
            "ended abnormally".into()
        }
    }
}

/// The last part of a build log: lines that look like diagnostics (which
/// make's noise tends to push out of the tail) and then the last lines.
fn log_tail(log: &str) -> String {
    const TAIL: usize = 40;
    const DIAGNOSTICS: usize = 20;
    let lines: Vec<&str> = log.lines().collect();
    let tail_start = lines.len().saturating_sub(TAIL);
    let mut out = String::new();
    let diags: Vec<&str> = lines[..tail_start]
        .iter()
        .filter(|l| l.starts_with("%Error") || l.starts_with("%Warning") || l.contains("error:"))
        .take(DIAGNOSTICS)
        .copied()
        .collect();
    if !diags.is_empty() {
        for l in diags {
            out.push_str(l);
            out.push('\n');
        }
        out.push_str("...\n");
    }
    for l in &lines[tail_start..] {
        out.push_str(l);
        out.push('\n');
    }
    out
}

/// Options of one harness run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Trace every signal into this VCD file.
    pub vcd: Option<PathBuf>,
    /// Insert pseudo-random idle cycles, from this seed.
    pub bubbles: Option<u64>,
    /// Valid/ready units: the seed of the random stalls on both sides
    /// (the harness's default when `None`).
    pub stalls: Option<u64>,
    /// Valid/ready units: the chance in percent of each stall (harness
    /// default 30 when `None`); 0 is never stalled, at full rate.
    pub stall_percent: Option<u64>,
}

impl RunOptions {
    fn apply(&self, cmd: &mut Command) {
        if let Some(v) = &self.vcd {
            cmd.arg("--vcd").arg(v);
        }
        if let Some(seed) = self.bubbles {
            cmd.arg("--bubbles").arg(seed.to_string());
        }
        if let Some(seed) = self.stalls {
            cmd.arg("--stalls").arg(seed.to_string());
        }
        if let Some(p) = self.stall_percent {
            cmd.arg("--stall-percent").arg(p.to_string());
        }
    }
}

/// What the harness reports on stderr at the end of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct RunStats {
    /// Clock cycles simulated, reset and drain included.
    pub cycles: u64,
    /// Transactions (input records) driven.
    pub transactions: u64,
    /// Idle cycles inserted between transactions.
    pub bubbles: u64,
    /// Valid/ready units: cycles with `out_ready` low.
    pub stalls: u64,
}

impl RunStats {
    /// Finds the `cycles=N transactions=M bubbles=B` line in harness stderr.
    pub fn parse(stderr: &str) -> Option<RunStats> {
        let line = stderr.lines().rev().find(|l| l.starts_with("cycles="))?;
        let mut stats = RunStats::default();
        for kv in line.split_ascii_whitespace() {
            let (k, v) = kv.split_once('=')?;
            let v: u64 = v.parse().ok()?;
            match k {
                "cycles" => stats.cycles = v,
                "transactions" => stats.transactions = v,
                "bubbles" => stats.bubbles = v,
                "stalls" => stats.stalls = v,
                _ => {}
            }
        }
        Some(stats)
    }
}

/// A built harness for one design: the executable and its port list.
#[derive(Clone, Debug)]
pub struct Harness {
    ports: PortList,
    entry: PathBuf,
    binary: PathBuf,
    key: String,
    cached: bool,
    build_time: Duration,
    traced: bool,
    /// design directory and cache root, to build the traced variant on demand
    source: Option<(PathBuf, PathBuf)>,
}

/// Distinguishes concurrent temporary build directories of one process.
static BUILD_COUNTER: AtomicU64 = AtomicU64::new(0);

impl Harness {
    /// Loads `<top>.ports.json` and builds (or finds in the cache) its
    /// harness; the Verilog files are taken relative to the port list.
    pub fn from_port_file(port_file: &Path, cache_root: &Path) -> Result<Harness, SimError> {
        let ports = PortList::load(port_file)?;
        let dir = port_file.parent().unwrap_or(Path::new("."));
        Harness::build(&ports, dir, cache_root)
    }

    /// Builds the harness for `ports` from the Verilog files in `dir`, or
    /// reuses the cache entry `cache_root/<key>` when one exists (see
    /// [`Harness::cache_key`]).
    pub fn build(ports: &PortList, dir: &Path, cache_root: &Path) -> Result<Harness, SimError> {
        Harness::build_variant(ports, dir, cache_root, false)
    }

    /// The same design built with `--trace`, for replays that write a VCD.
    /// Built (and cached) on first use.
    pub fn traced(&self) -> Result<Harness, SimError> {
        if self.traced {
            return Ok(self.clone());
        }
        let (dir, cache_root) = self.source.as_ref().ok_or_else(|| {
            SimError::Invalid(format!(
                "the harness {} was not built from sources, so it has no traced variant",
                self.binary.display()
            ))
        })?;
        Harness::build_variant(&self.ports, dir, cache_root, true)
    }

    /// True if this harness can write a VCD (`--vcd`).
    pub fn is_traced(&self) -> bool {
        self.traced
    }

    fn build_variant(
        ports: &PortList,
        dir: &Path,
        cache_root: &Path,
        traced: bool,
    ) -> Result<Harness, SimError> {
        let started = Instant::now();
        // Absolute, so that the binary path in replay commands works from
        // any directory.
        let cache_root = &std::path::absolute(cache_root).map_err(|e| {
            SimError::io(
                format!("resolving cache directory {}", cache_root.display()),
                e,
            )
        })?;
        let BuildInputs {
            key,
            sources,
            inc,
            version,
            flags,
        } = BuildInputs::gather(ports, dir, traced)?;
        let entry = cache_root.join(&key);
        let binary = entry.join(BINARY_NAME);
        let make = |cached| Harness {
            ports: ports.clone(),
            entry: entry.clone(),
            binary: binary.clone(),
            key: key.clone(),
            cached,
            build_time: started.elapsed(),
            traced,
            source: Some((dir.to_path_buf(), cache_root.to_path_buf())),
        };
        if binary.is_file() {
            return Ok(make(true));
        }

        fs::create_dir_all(cache_root).map_err(|e| {
            SimError::io(
                format!("creating cache directory {}", cache_root.display()),
                e,
            )
        })?;
        // Build in a private directory and rename it into place, so that a
        // cache entry is either complete or absent, even with concurrent or
        // interrupted builds.
        let tmp = cache_root.join(format!(
            ".build-{key}-{}-{}",
            std::process::id(),
            BUILD_COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let result = build_in(&tmp, ports, &sources, &inc, &version, &key, &flags);
        if let Err(e) = result {
            // Keep the failed build for inspection, replacing an older one.
            let failed = cache_root.join(format!("{key}.failed"));
            let _ = fs::remove_dir_all(&failed);
            let _ = fs::rename(&tmp, &failed);
            return Err(match e {
                SimError::Build {
                    message,
                    output_tail,
                } => SimError::Build {
                    message: format!("{message}; build directory kept at {}", failed.display()),
                    output_tail,
                },
                other => other,
            });
        }
        match fs::rename(&tmp, &entry) {
            Ok(()) => Ok(make(false)),
            // Another builder finished the same key first: theirs is as good.
            Err(_) if binary.is_file() => {
                let _ = fs::remove_dir_all(&tmp);
                Ok(make(true))
            }
            Err(e) => {
                let _ = fs::remove_dir_all(&tmp);
                Err(SimError::io(
                    format!(
                        "moving the finished build into {} (an incomplete entry from an \
                         older version? delete it)",
                        entry.display()
                    ),
                    e,
                ))
            }
        }
    }

    /// The cache key of a design: FNV-1a 128 over everything that affects
    /// the executable (the Verilog contents, the port list, the harness
    /// source, `verilator --version`, the build flags and `$CXX`).
    pub fn cache_key(ports: &PortList, dir: &Path) -> Result<String, SimError> {
        Ok(BuildInputs::gather(ports, dir, false)?.key)
    }

    /// Wraps an existing harness executable built for `ports`, such as a
    /// cache entry's `rtl_harness` or a stand-in for testing.
    pub fn from_parts(ports: PortList, binary: PathBuf) -> Result<Harness, SimError> {
        ports.validate()?;
        let entry = binary.parent().map(Path::to_path_buf).unwrap_or_default();
        Ok(Harness {
            ports,
            entry,
            binary,
            key: String::new(),
            cached: true,
            build_time: Duration::ZERO,
            // a stand-in may or may not trace; `--vcd` tells at run time
            traced: true,
            source: None,
        })
    }

    /// The port list the harness was built for.
    pub fn ports(&self) -> &PortList {
        &self.ports
    }

    /// Path of the harness executable.
    pub fn binary(&self) -> &Path {
        &self.binary
    }

    /// The cache entry directory (sources, `ports.inc`, build log).
    pub fn dir(&self) -> &Path {
        &self.entry
    }

    /// The cache key: 32 hex digits of FNV-1a 128.
    pub fn key(&self) -> &str {
        &self.key
    }

    /// True when [`Harness::build`] found the executable in the cache.
    pub fn was_cached(&self) -> bool {
        self.cached
    }

    /// Time [`Harness::build`] took, lookup included.
    pub fn build_time(&self) -> Duration {
        self.build_time
    }

    /// A command running the harness executable, without arguments.
    pub fn command(&self) -> Command {
        Command::new(&self.binary)
    }

    /// Runs the harness from file `input` to file `output`.
    pub fn run(
        &self,
        input: &Path,
        output: &Path,
        opts: &RunOptions,
    ) -> Result<RunStats, SimError> {
        let mut cmd = self.command();
        cmd.arg("--in").arg(input).arg("--out").arg(output);
        opts.apply(&mut cmd);
        let out = cmd
            .stdin(Stdio::null())
            .output()
            .map_err(|e| SimError::io(format!("running {}", self.binary.display()), e))?;
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        if !out.status.success() {
            return Err(SimError::Harness {
                message: format!(
                    "harness for `{}` {}",
                    self.ports.top,
                    describe_exit(out.status)
                ),
                stderr,
            });
        }
        RunStats::parse(&stderr).ok_or_else(|| SimError::Harness {
            message: "harness did not report `cycles=... transactions=...`".into(),
            stderr,
        })
    }

    /// Runs in-memory input records (each in the input ports' order)
    /// through the harness, by way of `<stem>.in.rtlvec` and
    /// `<stem>.out.rtlvec` (removed afterwards, also on error), and returns
    /// the run's statistics and the output records, flat: one record per
    /// transaction, in the output ports' order; an error unless there is
    /// exactly one output record per input record.
    pub fn run_records<'a>(
        &self,
        records: impl IntoIterator<Item = &'a [u64]>,
        stem: &Path,
        opts: &RunOptions,
    ) -> Result<(RunStats, Vec<u64>), SimError> {
        let with = |ext: &str| {
            let mut name = stem.as_os_str().to_owned();
            name.push(ext);
            PathBuf::from(name)
        };
        let (fin, fout) = (with(".in.rtlvec"), with(".out.rtlvec"));
        let result = (|| {
            let mut w = crate::BinWriter::create(&fin, &self.ports.inputs)?;
            let mut written = 0usize;
            for r in records {
                w.write_record(r)?;
                written += 1;
            }
            w.finish()?;
            let stats = self.run(&fin, &fout, opts)?;
            let mut rd = crate::BinReader::open(&fout)?;
            rd.expect_ports(&self.ports.outputs)?;
            let mut record = vec![0u64; self.ports.outputs.len()];
            let mut outputs = Vec::with_capacity(stats.transactions as usize * record.len());
            let mut read = 0usize;
            while rd.read_record(&mut record)? {
                outputs.extend_from_slice(&record);
                read += 1;
            }
            if read != written {
                return Err(SimError::Invalid(format!(
                    "the harness for `{}` returned {read} output records for {written} input \
                     records",
                    self.ports.top
                )));
            }
            Ok((stats, outputs))
        })();
        let _ = fs::remove_file(&fin);
        let _ = fs::remove_file(&fout);
        result
    }
}

/// Everything a build depends on, read once so that the hashed bytes are
/// the built bytes.
struct BuildInputs {
    key: String,
    sources: Vec<(String, Vec<u8>)>,
    inc: String,
    version: String,
    flags: Vec<String>,
}

impl BuildInputs {
    fn gather(ports: &PortList, dir: &Path, traced: bool) -> Result<BuildInputs, SimError> {
        ports.validate()?;
        let version = verilator_version()?;
        let mut sources = Vec::with_capacity(ports.files.len());
        for (i, (rel, path)) in ports.files.iter().zip(ports.file_paths(dir)).enumerate() {
            let text = fs::read(&path).map_err(|e| {
                SimError::io(
                    format!(
                        "reading Verilog file {} (files[{i}] of the port list of `{}`)",
                        path.display(),
                        ports.top
                    ),
                    e,
                )
            })?;
            sources.push((rel.clone(), text));
        }
        let inc = ports.ports_inc();
        let mut h = Fnv128::new();
        h.item(CACHE_FORMAT.as_bytes())
            .item(HARNESS_SOURCE.as_bytes())
            .item(inc.as_bytes())
            .item(ports.to_json().as_bytes())
            .item(version.as_bytes());
        let source_bytes = sources.iter().map(|(_, text)| text.len()).sum();
        let flags = variant_flags(traced, source_bytes);
        for f in VERILATOR_FLAGS
            .iter()
            .copied()
            .chain(flags.iter().map(String::as_str))
        {
            h.item(f.as_bytes());
        }
        // The C++ compiler make will use is part of the toolchain too.
        h.item(env::var("CXX").unwrap_or_default().as_bytes());
        for (rel, text) in &sources {
            h.item(rel.as_bytes()).item(text);
        }
        Ok(BuildInputs {
            key: h.hex(),
            sources,
            inc,
            version,
            flags,
        })
    }
}

/// Writes the build inputs into `tmp` and runs Verilator there.
fn build_in(
    tmp: &Path,
    ports: &PortList,
    sources: &[(String, Vec<u8>)],
    inc: &str,
    version: &str,
    key: &str,
    flags: &[String],
) -> Result<(), SimError> {
    let io = |what: &str, p: &Path, e| SimError::io(format!("{what} {}", p.display()), e);
    let _ = fs::remove_dir_all(tmp);
    let src = tmp.join("src");
    fs::create_dir_all(&src).map_err(|e| io("creating", &src, e))?;
    // Build from copies of exactly the bytes that were hashed, so the
    // executable matches its key even if the files change meanwhile.
    let mut names = Vec::new();
    for (i, (rel, text)) in sources.iter().enumerate() {
        let base = Path::new(rel)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| format!("file{i}.v"));
        let name = if names.contains(&base) {
            format!("{i}_{base}")
        } else {
            base
        };
        let path = src.join(&name);
        fs::write(&path, text).map_err(|e| io("writing", &path, e))?;
        names.push(name);
    }
    let write = |name: &str, text: &str| {
        let p = tmp.join(name);
        fs::write(&p, text).map_err(|e| io("writing", &p, e))
    };
    write("harness.cpp", HARNESS_SOURCE)?;
    write("ports.inc", inc)?;
    write(&format!("{}.ports.json", ports.top), &ports.to_json())?;

    let jobs = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
        .to_string();
    let mut args: Vec<String> = VERILATOR_FLAGS.iter().map(|s| s.to_string()).collect();
    args.extend(flags.iter().cloned());
    args.extend(
        [
            "--top-module",
            &ports.top,
            "--Mdir",
            "obj_dir",
            "-o",
            BINARY_NAME,
            "-j",
            &jobs,
        ]
        .map(String::from),
    );
    args.extend(names.iter().map(|n| format!("src/{n}")));
    args.push("harness.cpp".into());
    let arg_refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = run_tool("verilator", &arg_refs, Some(tmp))?;
    let log = combined(&out);
    let log_path = tmp.join("build.log");
    fs::write(&log_path, format!("verilator {}\n{log}", args.join(" ")))
        .map_err(|e| io("writing", &log_path, e))?;
    let built = tmp.join("obj_dir").join(BINARY_NAME);
    if !out.status.success() || !built.is_file() {
        return Err(SimError::Build {
            message: format!(
                "building the Verilator harness for `{}` failed: verilator {}",
                ports.top,
                describe_exit(out.status)
            ),
            output_tail: log_tail(&log),
        });
    }
    let binary = tmp.join(BINARY_NAME);
    fs::rename(&built, &binary).map_err(|e| io("moving", &built, e))?;
    let manifest = serde_json::json!({
        "key": key,
        "format": CACHE_FORMAT,
        "top": ports.top,
        "verilator": version,
        "flags": VERILATOR_FLAGS.iter().map(|s| s.to_string()).chain(flags.iter().cloned()).collect::<Vec<_>>(),
        "sources": names,
    });
    write("manifest.json", &format!("{manifest:#}\n"))
}

/// Runs `verilator --lint-only -Wall` on the design; any warning or error
/// fails, with Verilator's full report in the error.
pub fn lint(ports: &PortList, dir: &Path) -> Result<(), SimError> {
    ports.validate()?;
    let files = ports.file_paths(dir);
    for (i, f) in files.iter().enumerate() {
        if !f.is_file() {
            return Err(SimError::io(
                format!(
                    "Verilog file {} (files[{i}] of the port list of `{}`)",
                    f.display(),
                    ports.top
                ),
                io::Error::new(io::ErrorKind::NotFound, "no such file"),
            ));
        }
    }
    let mut args: Vec<String> = ["--lint-only", "-Wall", "--top-module", &ports.top]
        .map(String::from)
        .to_vec();
    args.extend(files.iter().map(|f| f.display().to_string()));
    let arg_refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = run_tool("verilator", &arg_refs, None)?;
    let report = combined(&out);
    if out.status.success() && !report.contains("%Warning") && !report.contains("%Error") {
        Ok(())
    } else {
        Err(SimError::Lint {
            top: ports.top.clone(),
            warnings: report,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_tool_is_a_clear_error() {
        let e = run_tool("verilator-that-does-not-exist-7f3a", &["--version"], None).unwrap_err();
        assert!(matches!(e, SimError::ToolMissing { .. }));
        let msg = e.to_string();
        assert!(
            msg.starts_with("`verilator-that-does-not-exist-7f3a` was not found on PATH"),
            "{msg}"
        );
    }

    #[test]
    fn stats_line_parses() {
        let s = "warning: x\ncycles=107 transactions=100 bubbles=3 stalls=5\n";
        assert_eq!(
            RunStats::parse(s),
            Some(RunStats {
                cycles: 107,
                transactions: 100,
                bubbles: 3,
                stalls: 5
            })
        );
        assert_eq!(RunStats::parse("nothing"), None);
    }

    #[test]
    fn log_tail_keeps_early_diagnostics() {
        let mut log = String::from("%Error: x.v:3:1: syntax error\n");
        for i in 0..100 {
            log.push_str(&format!("make noise {i}\n"));
        }
        let t = log_tail(&log);
        assert!(t.starts_with("%Error: x.v:3:1"));
        assert!(t.contains("make noise 99"));
        assert!(!t.contains("make noise 10\n"));
    }

    #[test]
    fn default_cache_root_ends_in_rtl_cache_or_env() {
        let root = default_cache_root();
        match env::var_os("RTL_GEN_CACHE").filter(|v| !v.is_empty()) {
            Some(v) => assert_eq!(root, PathBuf::from(v)),
            None => assert!(root.ends_with("rtl-cache"), "{}", root.display()),
        }
    }
}
