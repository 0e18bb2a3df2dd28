//! `rtl-gen board`: the host side of the FPGA bring-up. Streams vectors over
//! a serial port in the bring-up wrapper's protocol ([`crate::bringup`]: one
//! input record of `ceil(width/8)` little-endian bytes per data input, then
//! wait for the whole output record), compares every answer with the unit's
//! golden model and reports as `rtl-gen check` does.
//!
//! The vectors are the unit's own stimulus (`--vectors N --seed S`, the same
//! as `check`, so a mismatch replays in Verilator with `rtl-gen replay`) or a
//! vector file (`--in FILE`, as `sim` reads it). The record layout depends on
//! the unit's format parameters, not on its stages or register placement, so
//! `-p` must name the bitstream's unit and format.
//!
//! The port is opened with the `serialport` crate (8N1, no flow control;
//! built without its libudev feature, which only serves port enumeration).

use crate::bringup::{pack, record_bytes, unpack};
use rtl_flow::report::{hex_values, FailingVector, RunReport};
use rtl_flow::Generated;
use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Where the vectors come from.
#[derive(Debug, Clone)]
pub enum Source {
    /// the unit's own stimulus: vectors `0..vectors` of `seed`
    Stimulus {
        /// how many
        vectors: u64,
        /// stimulus seed
        seed: u64,
    },
    /// a vector file (text or rtlvec)
    File(PathBuf),
}

/// What `rtl-gen board` is told.
#[derive(Debug, Clone)]
pub struct BoardOptions {
    /// serial device, e.g. /dev/ttyUSB0
    pub port: String,
    /// baud rate (the wrapper's bit time: 115 200 for scripts/fpga.sh)
    pub baud: u32,
    /// the vectors
    pub source: Source,
    /// how long to wait for each answer
    pub timeout: Duration,
}

/// Why a board run stopped before its verdict (exit 2).
#[derive(Debug)]
pub enum BoardError {
    /// the port cannot be opened or used
    Port(String),
    /// the board sent less than a whole answer in time
    Timeout(String),
    /// anything else (vector file, unit)
    Other(String),
}

impl std::fmt::Display for BoardError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BoardError::Port(s) | BoardError::Timeout(s) | BoardError::Other(s) => f.write_str(s),
        }
    }
}

impl std::error::Error for BoardError {}

/// Reads exactly `buf.len()` bytes before `deadline`; returns how many
/// arrived when it runs out.
fn read_until(
    port: &mut dyn serialport::SerialPort,
    buf: &mut [u8],
    deadline: Instant,
) -> Result<(), (usize, std::io::Error)> {
    let mut got = 0;
    while got < buf.len() {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err((got, std::io::ErrorKind::TimedOut.into()));
        }
        port.set_timeout(left).map_err(|e| (got, e.into()))?;
        match port.read(&mut buf[got..]) {
            Ok(0) => return Err((got, std::io::ErrorKind::UnexpectedEof.into())),
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err((got, e)),
        }
    }
    Ok(())
}

fn named(ports: &[sim::Port], values: &[u64]) -> Vec<(String, u64)> {
    ports
        .iter()
        .zip(values)
        .map(|(p, &v)| (p.name.clone(), v))
        .collect()
}

/// Runs the vectors of `o` through the board behind `o.port` and the golden
/// model of `g`; prints what it does and returns the report (its `passed`
/// is the verdict).
pub fn run(g: &Generated, o: &BoardOptions) -> Result<RunReport, BoardError> {
    let tb = g.testbench();
    let ports = &g.ports;
    let in_widths: Vec<u32> = ports.inputs.iter().map(|p| p.width).collect();
    let out_widths: Vec<u32> = ports.outputs.iter().map(|p| p.width).collect();
    let (n_in, n_out) = (
        record_bytes(in_widths.clone()),
        record_bytes(out_widths.clone()),
    );

    // the vectors first: a bad file is reported before the board is touched
    let mut report = RunReport::new("board", g);
    let records: Vec<(Option<String>, Vec<u64>)> = match &o.source {
        Source::Stimulus { vectors, seed } => {
            report.seed = Some(*seed);
            let mut v = vec![0u64; ports.inputs.len()];
            (0..*vectors)
                .map(|i| {
                    tb.vector(*seed, i, &mut v);
                    (None, v.clone())
                })
                .collect()
        }
        Source::File(path) => {
            report.input = Some(path.display().to_string());
            rtl_flow::byo::read_inputs(g, path)
                .map_err(|e| BoardError::Other(e.to_string()))?
                .into_iter()
                .map(|(place, v)| (Some(place), v))
                .collect()
        }
    };
    report.total_vectors = records.len() as u64;

    println!(
        "rtl-gen board {} ({}) on {} at {} baud",
        g.unit,
        rtl_gen::emit::lower::params_line(g.params.values()),
        o.port,
        o.baud
    );
    println!(
        "  module      {}: {n_in} bytes in, {n_out} bytes out a vector (bring-up wrapper protocol)",
        g.module.name
    );
    match &o.source {
        Source::Stimulus { vectors, seed } => {
            println!("  vectors     {vectors} of the unit's stimulus, seed {seed}")
        }
        Source::File(p) => println!("  vectors     {} from {}", records.len(), p.display()),
    }

    let mut port = serialport::new(&o.port, o.baud)
        .timeout(o.timeout)
        .open()
        .map_err(|e| BoardError::Port(format!("cannot open serial port {}: {e}", o.port)))?;
    // bytes left over from an earlier run are not answers to ours
    let _ = port.clear(serialport::ClearBuffer::All);

    let replay = rtl_flow::regress::replay_hint(g, report.seed.unwrap_or(0));
    let started = Instant::now();
    let mut out = Vec::with_capacity(n_in);
    let mut answer = vec![0u8; n_out];
    let mut expected = vec![0u64; ports.outputs.len()];
    for (i, (place, inputs)) in records.iter().enumerate() {
        out.clear();
        pack(inputs, &in_widths, &mut out);
        port.write_all(&out)
            .and_then(|_| port.flush())
            .map_err(|e| BoardError::Port(format!("writing vector {i} to {}: {e}", o.port)))?;
        read_until(port.as_mut(), &mut answer, Instant::now() + o.timeout).map_err(
            |(got, e)| {
                let what = if e.kind() == std::io::ErrorKind::TimedOut {
                    format!("no answer within {:.1} s", o.timeout.as_secs_f64())
                } else {
                    format!("reading: {e}")
                };
                BoardError::Timeout(format!(
                    "the board did not answer vector {i} on {}: {what} ({got} of {n_out} bytes \
                     received). Is the bitstream of `{}` (`rtl-gen fpga <board> {} ...`) \
                     loaded, the port right, and the baud rate the wrapper's?",
                    o.port, g.module.name, g.unit
                ))
            },
        )?;
        if i == 0 {
            // an answer longer than this unit's record: another unit or format on the board
            let byte_time = Duration::from_secs_f64(10.0 / o.baud as f64);
            std::thread::sleep(byte_time * 30 + Duration::from_millis(10));
            let extra = port.bytes_to_read().unwrap_or(0);
            if extra > 0 {
                return Err(BoardError::Other(format!(
                    "the board sent {} bytes for vector 0, {n_out} expected: the bitstream is of \
                     another unit or format than `{}` ({})",
                    n_out as u32 + extra,
                    g.module.name,
                    g.param_args()
                )));
            }
        }
        let got = unpack(&answer, &out_widths);
        tb.eval(inputs, &mut expected);
        if got != expected {
            report.mismatches += 1;
            if report.first_mismatch.is_none() {
                report.first_mismatch = Some(FailingVector {
                    index: i as u64,
                    location: place.clone(),
                    inputs: hex_values(&named(&ports.inputs, inputs)),
                    expected: hex_values(&named(&ports.outputs, &expected)),
                    got: hex_values(&named(&ports.outputs, &got)),
                    replay: place
                        .is_none()
                        .then(|| replay.replace("{index}", &i.to_string())),
                });
            }
        }
        report.vectors += 1;
    }
    let elapsed = started.elapsed().as_secs_f64();
    report.wall_time_s = elapsed;
    report.vectors_per_sec = report.vectors as f64 / elapsed.max(1e-9);
    report.update_verdict();
    if report.passed {
        println!("{}", report.headline());
    } else {
        print!("{}", report.failure_text());
    }
    Ok(report)
}
