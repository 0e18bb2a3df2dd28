//! `ffma`: fused float multiply-add a * b + c, rounded once

use super::fcommon::{format, rounding, wrap, EXP_BITS, FRAC_BITS, ROUND, STAGES};
use super::Unit;
use crate::arith::float::fma;
use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// The `ffma` unit.
pub struct FFma;

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, ROUND, STAGES];

impl Unit for FFma {
    fn name(&self) -> &'static str {
        "ffma"
    }
    fn summary(&self) -> &'static str {
        "fused float multiply-add a * b + c, rounded once"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "ffma")?;
        Ok(wrap(fma::fma_module(fmt, rounding(p), p.u32("stages"))))
    }
}
