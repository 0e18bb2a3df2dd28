//! The units the generator offers, each with its parameters.

pub mod cull;
pub mod cull_ray;
pub mod float_ops;
pub mod mulcmp;
pub mod ports;
pub mod silhouette;
pub mod slab;
pub mod transform;
pub mod triangle;

use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// A unit described once: its parameters, the typed configuration parsed
/// once from them (an error for an impossible combination, no fallbacks),
/// and the generator of a configuration. The testbench above this crate
/// takes the same typed configuration (`rtl_flow::catalog`), so nothing
/// parses the parameters a second time. Every description is a [`Unit`].
pub trait Description: Sync {
    /// The typed configuration.
    type Config;
    /// name used on the command line
    const NAME: &'static str;
    /// one-line description
    const SUMMARY: &'static str;
    /// accepted parameters
    const PARAMS: &'static [ParamSpec];
    /// The configuration of resolved parameters.
    fn config(&self, p: &Params) -> Result<Self::Config, ParamError>;
    /// The top module of a configuration.
    fn generate(&self, cfg: &Self::Config) -> Module;
}

impl<D: Description> Unit for D {
    fn name(&self) -> &'static str {
        D::NAME
    }
    fn summary(&self) -> &'static str {
        D::SUMMARY
    }
    fn params(&self) -> &'static [ParamSpec] {
        D::PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        Ok(self.generate(&self.config(p)?))
    }
}

/// A generatable unit as the command line sees it: a name, its parameters,
/// and the builder ([`Description`]s, and the float operators' one generic
/// description).
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

/// The axes of a vector, in port order.
pub const AXES: [&str; 3] = ["x", "y", "z"];
