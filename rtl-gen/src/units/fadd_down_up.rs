//! `fadd_down_up`: float a + b rounded toward -inf (down) and +inf (up) from one exact sum

use super::fcommon::{format, wrap, EXP_BITS, FRAC_BITS, STAGES};
use super::Unit;
use crate::arith::float::add_down_up;
use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// The `fadd_down_up` unit.
pub struct FAddDownUp;

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, STAGES];

impl Unit for FAddDownUp {
    fn name(&self) -> &'static str {
        "fadd_down_up"
    }
    fn summary(&self) -> &'static str {
        "float a + b rounded toward -inf (down) and +inf (up) from one exact sum"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "fadd_down_up")?;
        Ok(wrap(add_down_up::add_down_up_module(fmt, p.u32("stages"))))
    }
}
