//! `fmul_exact`: exact float product a * b as a value of the format (E + 2, 2F + 1)

use super::fcommon::{format, wrap, EXP_BITS, FRAC_BITS, STAGES};
use super::Unit;
use crate::arith::float::mul_exact;
use crate::ir::Module;
use crate::params::{ParamError, ParamSpec, Params};

/// The `fmul_exact` unit.
pub struct FMulExact;

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, STAGES];

impl Unit for FMulExact {
    fn name(&self) -> &'static str {
        "fmul_exact"
    }
    fn summary(&self) -> &'static str {
        "exact float product a * b as a value of the format (E + 2, 2F + 1)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "fmul_exact")?;
        mul_exact::exact_product_format(fmt)
            .map_err(|e| ParamError::Combination(format!("fmul_exact: {e}")))?;
        Ok(wrap(mul_exact::mul_exact_module(fmt, p.u32("stages"))))
    }
}
