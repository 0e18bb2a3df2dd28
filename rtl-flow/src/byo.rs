//! Bring your own vectors: run a vector file (text or binary, see
//! `docs/vectors.md`) through the Verilated RTL and/or the golden model and
//! write a results file, the inputs echoed and the outputs added.
//!
//! Input files are validated record by record before anything runs (unknown
//! or missing port, value wider than its port, wrong field count, truncated
//! binary record: errors name the file, line or record, and field). The
//! results file is written all or nothing (a temporary file renamed on
//! success), so a failed run never leaves a half-written file behind.

use super::report::{hex_values, FailingVector, RunReport};
use super::{FlowError, Generated, Testbench};
use sim::{BinReader, BinWriter, Port, SimError, TextReader, TextWriter, VecFormat};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What runs the vectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Verilator; with `compare`, the golden model too, and mismatches are
    /// reported (the results hold the RTL's outputs).
    Rtl {
        /// also run the golden model and compare
        compare: bool,
    },
    /// The golden model alone (no Verilator).
    Golden,
}

/// How many mismatches are described in full.
pub const SHOWN_MISMATCHES: usize = 10;

/// A mismatch of a file run.
#[derive(Clone, Debug)]
pub struct FileMismatch {
    /// record number (0-based)
    pub index: u64,
    /// `FILE line L` or `FILE record R`
    pub location: String,
    /// inputs, outputs of the golden model, outputs of the RTL
    pub inputs: Vec<(String, u64)>,
    /// golden model
    pub expected: Vec<(String, u64)>,
    /// RTL
    pub got: Vec<(String, u64)>,
}

impl std::fmt::Display for FileMismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let j = |v: &[(String, u64)]| {
            v.iter()
                .map(|(n, x)| format!("{n}={x:#x}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        writeln!(f, "mismatch at vector {} ({})", self.index, self.location)?;
        writeln!(f, "  inputs: {}", j(&self.inputs))?;
        for ((n, e), (_, g)) in self.expected.iter().zip(&self.got) {
            let mark = if e == g { "" } else { "   <- differs" };
            writeln!(f, "  {n:<12} golden {e:#x}  rtl {g:#x}{mark}")?;
        }
        Ok(())
    }
}

/// What a file run did.
pub struct FileOutcome {
    /// records run
    pub vectors: u64,
    /// records where RTL and golden model differ
    pub mismatches: u64,
    /// the first [`SHOWN_MISMATCHES`] mismatches
    pub shown: Vec<FileMismatch>,
    /// format of the results file
    pub format: VecFormat,
    /// for `--report` and `--junit`
    pub report: RunReport,
}

/// The results format for `out`: `.rtlvec`/`.bin` binary, `.txt`/`.vec`/
/// `.tsv`/`.text` text, anything else the input's format.
pub fn results_format(out: &Path, input: VecFormat) -> VecFormat {
    match out.extension().and_then(|e| e.to_str()) {
        Some("rtlvec" | "bin") => VecFormat::Binary,
        Some("txt" | "vec" | "tsv" | "text") => VecFormat::Text,
        _ => input,
    }
}

/// A vector file opened for reading its inputs, in port-list order.
enum Input {
    Text(TextReader<BufReader<File>>),
    Binary(BinReader<File>),
}

impl Input {
    fn open(path: &Path, ports: &[Port]) -> Result<(Input, VecFormat), SimError> {
        Ok(match sim::detect_format(path)? {
            VecFormat::Text => (
                Input::Text(TextReader::open(path, Some(ports))?),
                VecFormat::Text,
            ),
            VecFormat::Binary => {
                let r = BinReader::open(path)?;
                r.expect_ports(ports)?;
                (Input::Binary(r), VecFormat::Binary)
            }
        })
    }

    fn read(&mut self, values: &mut [u64]) -> Result<bool, SimError> {
        match self {
            Input::Text(r) => r.read_record(values),
            Input::Binary(r) => r.read_record(values),
        }
    }

    /// Where the record just read came from.
    fn place(&self) -> u64 {
        match self {
            Input::Text(r) => r.line(),
            Input::Binary(r) => r.records().saturating_sub(1),
        }
    }
}

enum Output {
    Text(TextWriter<File>),
    Binary(BinWriter<File>),
}

impl Output {
    fn new(f: File, name: &str, ports: &[Port], format: VecFormat) -> Result<Output, SimError> {
        Ok(match format {
            VecFormat::Text => Output::Text(TextWriter::new(f, name, ports)?),
            VecFormat::Binary => Output::Binary(BinWriter::new(f, name, ports)?),
        })
    }

    fn write(&mut self, values: &[u64]) -> Result<(), SimError> {
        match self {
            Output::Text(w) => w.write_record(values),
            Output::Binary(w) => w.write_record(values),
        }
    }

    fn finish(self) -> Result<(), SimError> {
        match self {
            Output::Text(w) => w.finish().map(drop),
            Output::Binary(w) => w.finish().map(drop),
        }
    }
}

/// A temporary file removed when dropped.
struct TempFile(PathBuf);

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

fn named(ports: &[Port], values: &[u64]) -> Vec<(String, u64)> {
    ports
        .iter()
        .zip(values)
        .map(|(p, &v)| (p.name.clone(), v))
        .collect()
}

/// Runs the vectors of `input` and writes `output` (inputs then outputs of
/// every record). `harness` is needed for [`Mode::Rtl`]. On any error the
/// results file is not written (an existing file is left as it was), and
/// the error says so.
pub fn run_file(
    g: &Generated,
    harness: Option<&sim::Harness>,
    tb: &dyn Testbench,
    input: &Path,
    output: &Path,
    mode: Mode,
) -> Result<FileOutcome, FlowError> {
    run_file_inner(g, harness, tb, input, output, mode).map_err(|e| {
        // a unit's ports depend on its parameters (silhouette mode=ray has no
        // d_hi_*): a file naming a port this instance lacks gets them named
        let is_port = |name: &str| {
            g.ports
                .inputs
                .iter()
                .chain(&g.ports.outputs)
                .any(|p| p.name == name)
        };
        let names_absent_port = matches!(
            &e,
            FlowError::Sim(SimError::Format { field: Some(f), .. }) if !is_port(f)
        );
        let context = if names_absent_port {
            format!(
                "\n(these are the ports of `{}`: unit `{}` with {})",
                g.ports.top,
                g.unit,
                g.param_args()
            )
        } else {
            String::new()
        };
        FlowError::Sim(SimError::Invalid(format!(
            "{e}{context}\n(no results file written: {})",
            output.display()
        )))
    })
}

fn run_file_inner(
    g: &Generated,
    harness: Option<&sim::Harness>,
    tb: &dyn Testbench,
    input: &Path,
    output: &Path,
    mode: Mode,
) -> Result<FileOutcome, FlowError> {
    let started = Instant::now();
    let ports = &g.ports;
    let (n_in, n_out) = (ports.inputs.len(), ports.outputs.len());
    let in_name = input.display().to_string();
    let (mut reader, in_format) = Input::open(input, &ports.inputs)?;
    let format = results_format(output, in_format);
    let result_ports: Vec<Port> = ports.inputs.iter().chain(&ports.outputs).cloned().collect();
    let place_word = if in_format == VecFormat::Text {
        "line"
    } else {
        "record"
    };

    // RTL: validate and convert the whole input first (so a bad record is
    // reported before Verilator runs), then one harness run file to file.
    let mut places: Vec<u64> = Vec::new();
    let tmp = std::env::temp_dir().join(format!(
        "rtl-gen-{}-{}-{:?}",
        g.module.name,
        std::process::id(),
        std::thread::current().id()
    ));
    let (tmp_in, tmp_out) = (
        TempFile(tmp.with_extension("in.rtlvec")),
        TempFile(tmp.with_extension("out.rtlvec")),
    );
    let mut rtl: Option<BinReader<File>> = None;
    let mut vals = vec![0u64; n_in];
    if let Mode::Rtl { .. } = mode {
        let h = harness.expect("a harness for Mode::Rtl");
        let mut w = BinWriter::create(&tmp_in.0, &ports.inputs)?;
        while reader.read(&mut vals)? {
            w.write_record(&vals)?;
            places.push(reader.place());
        }
        w.finish()?;
        h.run(&tmp_in.0, &tmp_out.0, &sim::RunOptions::default())?;
        let r = BinReader::open(&tmp_out.0)?;
        r.expect_ports(&ports.outputs)?;
        rtl = Some(r);
        reader = Input::Binary(BinReader::open(&tmp_in.0)?);
    }
    let compare = matches!(mode, Mode::Rtl { compare: true });
    let mut vectors = 0u64;
    let mut mismatches = 0u64;
    let mut shown = Vec::new();
    let mut rec = vec![0u64; n_in + n_out];
    let mut golden = vec![0u64; n_out];
    sim::write_atomically(output, |f, out_name| {
        let mut w = Output::new(f, out_name, &result_ports, format)?;
        loop {
            let (inp, out) = rec.split_at_mut(n_in);
            if !reader.read(inp)? {
                break;
            }
            let place = match places.get(vectors as usize) {
                Some(&p) => p,
                None => reader.place(),
            };
            if let Some(r) = &mut rtl {
                if !r.read_record(out)? {
                    return Err(SimError::Invalid(format!(
                        "the harness returned {vectors} results for more input records"
                    )));
                }
            }
            if compare || mode == Mode::Golden {
                tb.eval(inp, &mut golden);
                for (p, &v) in ports.outputs.iter().zip(&golden) {
                    if v & !p.mask() != 0 {
                        return Err(SimError::Invalid(format!(
                            "golden model returned {v:#x} for output `{}` ({} bits) at \
                             {in_name} {place_word} {place}: value wider than port",
                            p.name, p.width
                        )));
                    }
                }
            }
            if mode == Mode::Golden {
                out.copy_from_slice(&golden);
            } else if compare && golden[..] != out[..] {
                mismatches += 1;
                if shown.len() < SHOWN_MISMATCHES {
                    shown.push(FileMismatch {
                        index: vectors,
                        location: format!("{in_name} {place_word} {place}"),
                        inputs: named(&ports.inputs, inp),
                        expected: named(&ports.outputs, &golden),
                        got: named(&ports.outputs, out),
                    });
                }
            }
            w.write(&rec)?;
            vectors += 1;
        }
        if let Some(r) = &mut rtl {
            if r.read_record(&mut golden)? {
                return Err(SimError::Invalid(format!(
                    "the harness returned more results than the {vectors} input records"
                )));
            }
        }
        w.finish()
    })?;
    let elapsed = started.elapsed().as_secs_f64();
    let kind = match mode {
        Mode::Rtl { .. } => "sim",
        Mode::Golden => "golden",
    };
    let mut report = RunReport::new(kind, g);
    report.total_vectors = vectors;
    report.vectors = vectors;
    report.mismatches = mismatches;
    report.first_mismatch = shown.first().map(|m| FailingVector {
        index: m.index,
        location: Some(m.location.clone()),
        inputs: hex_values(&m.inputs),
        expected: hex_values(&m.expected),
        got: hex_values(&m.got),
        replay: None,
    });
    report.vectors_per_sec = vectors as f64 / elapsed.max(1e-9);
    report.wall_time_s = elapsed;
    report.input = Some(in_name);
    report.output = Some(output.display().to_string());
    if mode == (Mode::Rtl { compare: false }) {
        report
            .notes
            .push("--rtl-only: the golden model was not run".into());
    }
    report.update_verdict();
    Ok(FileOutcome {
        vectors,
        mismatches,
        shown,
        format,
        report,
    })
}

/// The input records of the vector file `input` for `g` (text or rtlvec,
/// validated as `sim` validates them), each with where it came from
/// (`FILE line L` or `FILE record R`): for runs that feed the vectors
/// elsewhere, such as `rtl-gen board`.
pub fn read_inputs(g: &Generated, input: &Path) -> Result<Vec<(String, Vec<u64>)>, FlowError> {
    let (mut reader, format) = Input::open(input, &g.ports.inputs)?;
    let word = match format {
        VecFormat::Text => "line",
        VecFormat::Binary => "record",
    };
    let mut records = Vec::new();
    let mut vals = vec![0u64; g.ports.inputs.len()];
    while reader.read(&mut vals)? {
        let place = format!("{} {word} {}", input.display(), reader.place());
        records.push((place, vals.clone()));
    }
    Ok(records)
}

/// Writes vectors `first..first + count` of the unit's own stimulus (seed
/// `seed`) as an input file for `sim`/`golden`: text unless `out` ends in
/// `.rtlvec`/`.bin`. Returns the format written.
pub fn write_stimulus(
    g: &Generated,
    tb: &dyn Testbench,
    seed: u64,
    first: u64,
    count: u64,
    out: &Path,
) -> Result<VecFormat, FlowError> {
    let ports = &g.ports.inputs;
    let format = results_format(out, VecFormat::Text);
    let mut vals = vec![0u64; ports.len()];
    sim::write_atomically(out, |f, name| {
        let mut w = Output::new(f, name, ports, format)?;
        for i in first..first + count {
            tb.vector(seed, i, &mut vals);
            w.write(&vals)?;
        }
        w.finish()
    })?;
    Ok(format)
}
