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
