//! `fcmp`: float comparisons lt, le, eq (IEEE quiet: NaN unordered, -0 == +0)

use super::fcommon::{format, wrap, EXP_BITS, FRAC_BITS, STAGES};
use super::Unit;
use crate::arith::float::compare;
use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// The `fcmp` unit.
pub struct FCmp;

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, STAGES];

impl Unit for FCmp {
    fn name(&self) -> &'static str {
        "fcmp"
    }
    fn summary(&self) -> &'static str {
        "float comparisons lt, le, eq (IEEE quiet: NaN unordered, -0 == +0)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "fcmp")?;
        Ok(wrap(compare::compare_module(fmt, p.u32("stages"))))
    }
}
