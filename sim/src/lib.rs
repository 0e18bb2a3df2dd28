//! Verilator driver for generated units: the `rtlvec` vector format, the
//! port-list contract with the generator, a cached build of the generic
//! C++ harness, and a streaming cross-check against golden models.
//!
//! Typical use:
//! ```no_run
//! use sim::{cross_check, default_cache_root, CheckOptions, Harness, RandomStimulus};
//! # fn main() -> Result<(), sim::SimError> {
//! let h = Harness::from_port_file("out/mulcmp.ports.json".as_ref(), &default_cache_root())?;
//! let stim = RandomStimulus::new(&h.ports().inputs);
//! let golden = |i: &[u64], o: &mut [u64]| {
//!     let (ab, cd) = (i[0] * i[1], i[2] * i[3]);
//!     o[0] = (ab < cd) as u64;
//!     o[1] = (ab == cd) as u64;
//! };
//! let report = cross_check(&h, &golden, &stim, &CheckOptions::default())?;
//! println!("{report}");
//! # Ok(()) }
//! ```
#![warn(missing_docs)]

pub mod check;
pub mod error;
pub mod harness;
pub mod hash;
pub mod ports;
pub mod vectors;

pub use check::{
    cross_check, describe_mismatch, mix64, replay, CheckOptions, CheckReport, Golden, Mismatch,
    Progress, ProgressFn, RandomStimulus, Stimulus, WorkerReport,
};
pub use error::{Location, SimError};
pub use harness::{default_cache_root, lint, verilator_version, Harness, RunOptions, RunStats};
pub use ports::{Port, PortList, ReadyPorts};
pub use vectors::{
    binary_to_text, convert_file, text_to_binary, BinReader, BinWriter, TextReader, TextWriter,
    VecFormat,
};
pub use vectors::{detect_format, output_problem, temp_beside, through_links, write_atomically};
