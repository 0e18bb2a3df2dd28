//! `fcvt`: conversion of a float from (exp_bits, frac_bits) to (to_exp_bits, to_frac_bits), rounded once.

use super::fcommon::{format_of, rounding, wrap, EXP_BITS, FRAC_BITS, ROUND, STAGES};
use super::Unit;
use crate::arith::float::convert;
use crate::ir::Module;
use crate::params::{ParamError, ParamKind, ParamSpec, Params};

/// The `fcvt` unit.
pub struct FCvt;

const PARAMS: &[ParamSpec] = &[
    EXP_BITS,
    FRAC_BITS,
    ParamSpec {
        name: "to_exp_bits",
        doc: "exponent bits of the result format",
        kind: ParamKind::Int { min: 2, max: 11 },
        default: "5",
    },
    ParamSpec {
        name: "to_frac_bits",
        doc: "fraction bits of the result format",
        kind: ParamKind::Int { min: 1, max: 52 },
        default: "10",
    },
    ROUND,
    STAGES,
];

impl Unit for FCvt {
    fn name(&self) -> &'static str {
        "fcvt"
    }
    fn summary(&self) -> &'static str {
        "float format conversion, rounded once"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let from = format_of(p, "fcvt", "exp_bits", "frac_bits")?;
        let to = format_of(p, "fcvt", "to_exp_bits", "to_frac_bits")?;
        Ok(wrap(convert::convert_module(
            from,
            to,
            rounding(p),
            p.u32("stages"),
        )))
    }
}
