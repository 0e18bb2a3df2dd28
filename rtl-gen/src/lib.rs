//! `rtl-gen`: a hardware-construction DSL embedded in Rust that emits
//! synthesizable Verilog-2005 for ray-tracing intersection datapaths.
//!
//! Layers, each depending only on those before it:
//! [`ir`] (types, operations, modules) ← [`builder`] (the DSL) ← [`arith`]
//! (operators) ← [`units`] (what users generate); [`retime`] and
//! [`handshake`] (the valid/ready wrapper) transform a unit's module.
//! [`emit`] and [`eval`] read the IR only. The crate depends on nothing else in the workspace: the
//! flow that ties a unit to its golden model and to Verilator, and the
//! `rtl-gen` command, are the `rtl-flow` crate above it.
#![warn(missing_docs)]

pub mod arith;
pub mod builder;
pub mod emit;
pub mod eval;
#[cfg(test)]
mod golden_twin;
pub mod handshake;
pub mod ir;
pub mod params;
pub mod ports;
pub mod retime;
pub mod units;

/// The generator's name and version, written into every emitted file.
pub const GENERATOR: &str = concat!("rtl-gen ", env!("CARGO_PKG_VERSION"));
