//! The units the generator offers, each with its parameters.

pub mod cull;
pub mod cull_ray;
pub mod float_ops;
pub mod mulcmp;
pub mod node;
pub mod node_child;
pub mod node_sort;
pub mod raycull;
pub mod silhouette;
pub mod slab;
pub mod tilerange;
pub mod transform;
pub mod triangle;

use crate::ir::Module;
use crate::params::{ParamError, ParamSet, ParamSpec, Params};

/// A unit described once: its parameters (one typed table, [`crate::params!`]),
/// the configuration checked from them (an error for an impossible
/// combination, no fallbacks), and the generator of a configuration. The
/// testbench above this crate takes the same configuration
/// (`rtl_flow::catalog`), so nothing reads the parameters a second time.
/// Every description is a [`Unit`]; the top module's header is the table's.
pub trait Description: Sync {
    /// The typed parameters.
    type Params: ParamSet;
    /// The checked configuration.
    type Config;
    /// name used on the command line
    const NAME: &'static str;
    /// one-line description
    const SUMMARY: &'static str;
    /// The configuration of typed parameters, or why they cannot be built.
    fn config(&self, p: &Self::Params) -> Result<Self::Config, ParamError>;
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
        D::Params::SPECS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        build_typed(self, D::Params::from_params(p))
    }
    fn build_datapath(&self, p: &Params) -> Result<Option<Module>, ParamError> {
        let mut typed = D::Params::from_params(p);
        match typed.stages_mut() {
            Some(stages) => *stages = 0,
            None => return Ok(None),
        }
        build_typed(self, typed).map(Some)
    }
}

/// The top module of typed parameters, its header written from them.
pub fn build_typed<D: Description>(unit: &D, p: D::Params) -> Result<Module, ParamError> {
    let mut module = unit.generate(&unit.config(&p)?);
    module.params = p.header();
    Ok(module)
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
    /// builds the top module for checked parameters
    fn build(&self, params: &Params) -> Result<Module, ParamError>;
    /// builds the unit's datapath: the same parameters with `stages` = 0
    /// (what `pipeline=balanced` cuts into stages); `None` for a unit
    /// without `stages`
    fn build_datapath(&self, params: &Params) -> Result<Option<Module>, ParamError>;
}

pub use crate::ports::{self, AXES};
