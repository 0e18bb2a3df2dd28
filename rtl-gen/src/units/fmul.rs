//! `fmul`: float a * b, rounded once

use super::fcommon::{format, rounding, wrap, EXP_BITS, FRAC_BITS, ROUND, STAGES};
use super::Unit;
use crate::arith::float::mul;
use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// The `fmul` unit.
pub struct FMul;

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, ROUND, STAGES];

impl Unit for FMul {
    fn name(&self) -> &'static str {
        "fmul"
    }
    fn summary(&self) -> &'static str {
        "float a * b, rounded once"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "fmul")?;
        Ok(wrap(mul::mul_module(fmt, rounding(p), p.u32("stages"))))
    }
}
