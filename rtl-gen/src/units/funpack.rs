//! `funpack`: float unpack/classify: sign, class (0 zero, 1 finite, 2 inf, 3 NaN), exponent of the lsb, significand

use super::fcommon::{format, wrap, EXP_BITS, FRAC_BITS, STAGES};
use super::Unit;
use crate::arith::float::unpack;
use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// The `funpack` unit.
pub struct FUnpack;

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, STAGES];

impl Unit for FUnpack {
    fn name(&self) -> &'static str {
        "funpack"
    }
    fn summary(&self) -> &'static str {
        "float unpack/classify: sign, class (0 zero, 1 finite, 2 inf, 3 NaN), exponent of the lsb, significand"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "funpack")?;
        Ok(wrap(unpack::unpack_module(fmt, p.u32("stages"))))
    }
}
