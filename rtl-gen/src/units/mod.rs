//! The units the generator offers, each with its parameters.

pub mod cull;
pub mod cull_ray;
pub mod float_ops;
pub mod mulcmp;
pub mod silhouette;
pub mod slab;
pub mod transform;
pub mod triangle;

use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// A generatable unit: a name, its parameters, and the builder.
pub trait Unit: Sync {
    /// name used on the command line
    fn name(&self) -> &'static str;
    /// one-line description
    fn summary(&self) -> &'static str;
    /// accepted parameters
    fn params(&self) -> &'static [ParamSpec];
    /// builds the top module for resolved parameters
    fn build(&self, params: &Params) -> Result<Module, ParamError>;
}

/// Ports by name: the position of input `name` in a unit's list of input
/// names (the order it declares them in), so neither the generator nor a
/// testbench counts positions.
pub fn input_at(names: &[String], name: &str) -> usize {
    names
        .iter()
        .position(|n| n == name)
        .unwrap_or_else(|| panic!("no input `{name}` (inputs: {names:?})"))
}

/// The positions of the vector inputs `{group}_x`, `{group}_y`, `{group}_z`.
pub fn input_at3(names: &[String], group: &str) -> [usize; 3] {
    ["x", "y", "z"].map(|a| input_at(names, &format!("{group}_{a}")))
}
