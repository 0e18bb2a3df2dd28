//! `fdot3`: fused float dot product a0*b0 + a1*b1 + a2*b2, exact, rounded once

use super::fcommon::{format, rounding, wrap, EXP_BITS, FRAC_BITS, ROUND, STAGES};
use super::Unit;
use crate::arith::float::dot3;
use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// The `fdot3` unit.
pub struct FDot3;

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, ROUND, STAGES];

impl Unit for FDot3 {
    fn name(&self) -> &'static str {
        "fdot3"
    }
    fn summary(&self) -> &'static str {
        "fused float dot product a0*b0 + a1*b1 + a2*b2, exact, rounded once"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "fdot3")?;
        Ok(wrap(dot3::dot3_module(fmt, rounding(p), p.u32("stages"))))
    }
}
