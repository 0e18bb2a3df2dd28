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

/// Ports by name: the position of port `name` in a unit's list of input or
/// output names (the order it declares them in), so neither the generator
/// nor a testbench counts positions.
pub fn port_at<S: AsRef<str>>(names: &[S], name: &str) -> usize {
    names
        .iter()
        .position(|n| n.as_ref() == name)
        .unwrap_or_else(|| {
            let all: Vec<&str> = names.iter().map(|n| n.as_ref()).collect();
            panic!("no port `{name}` (ports: {all:?})")
        })
}

/// The positions of the vector ports `{group}_x`, `{group}_y`, `{group}_z`.
pub fn port_at3<S: AsRef<str>>(names: &[S], group: &str) -> [usize; 3] {
    ["x", "y", "z"].map(|a| port_at(names, &format!("{group}_{a}")))
}
