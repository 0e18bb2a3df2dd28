//! Hardware cost against accuracy of the generated units (issue #8): the
//! synthesis runner ([`synth`], the pinned yowasp Yosys 0.70 and nextpnr-ice40 /
//! nextpnr-ecp5 of scripts/fpga-requirements.txt), accuracy on shared
//! workloads ([`accuracy`]), charts ([`charts`]), the cull-plane units'
//! cost ([`cull`]), the transform's dot styles ([`dot_styles`]), the hardware cost
//! per ray ([`per_ray`]), scene-fitted formats
//! ([`fit`]), the FPGA bring-up wrapper ([`bringup`]), its bitstream at the board
//! clock ([`fpga`]) and its host side over a serial port ([`board`]).
#![warn(missing_docs)]

pub mod accuracy;
pub mod board;
pub mod boxes;
pub mod bringup;
pub mod charts;
pub mod cli;
pub mod cull;
pub mod depth;
pub mod dot_styles;
pub mod fit;
pub mod fit_wide;
pub mod fpga;
pub mod per_ray;
pub mod prove;
pub mod prove_sound;
pub mod shell;
pub mod sweep;
pub mod synth;
