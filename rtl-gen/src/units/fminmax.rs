//! `fminmax`: float minimum and maximum (IEEE 754-2019: NaN if either is NaN, -0 < +0)

use super::fcommon::{format, wrap, EXP_BITS, FRAC_BITS, STAGES};
use super::Unit;
use crate::arith::float::minmax;
use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// The `fminmax` unit.
pub struct FMinMax;

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, STAGES];

impl Unit for FMinMax {
    fn name(&self) -> &'static str {
        "fminmax"
    }
    fn summary(&self) -> &'static str {
        "float minimum and maximum (IEEE 754-2019: NaN if either is NaN, -0 < +0)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "fminmax")?;
        Ok(wrap(minmax::min_max_module(fmt, p.u32("stages"))))
    }
}
