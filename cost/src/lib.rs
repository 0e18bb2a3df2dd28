//! Hardware cost against accuracy of the generated units (issue #8): the
//! synthesis runner ([`synth`], Yosys and nextpnr-ice40), accuracy on shared
//! workloads ([`accuracy`]), charts ([`charts`]), scene-fitted formats
//! ([`fit`]) and the FPGA bring-up wrapper ([`uart`], [`bringup`]).
#![warn(missing_docs)]

pub mod accuracy;
pub mod bringup;
pub mod charts;
pub mod fit;
pub mod shell;
pub mod sweep;
pub mod synth;
