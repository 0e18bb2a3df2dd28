//! `frecip`: float 1 / x, rounded once (restoring division). The slab
//! tester's per-ray reciprocal, so its cost can be charted beside the box
//! test (issue #19).

use super::fcommon::{format, wrap, EXP_BITS, FRAC_BITS, STAGES};
use super::Unit;
use crate::arith::float::Rounding;
use crate::arith::recip::recip_module;
use crate::ir::Module;
use crate::params::{ParamError, ParamKind, ParamSpec, Params};

/// The `frecip` unit.
pub struct FRecip;

/// `round`: one fixed mode (the divider has no `rm` port).
const ROUND: ParamSpec = ParamSpec {
    name: "round",
    doc: "rounding mode: to nearest even, toward zero, toward +inf, toward -inf",
    kind: ParamKind::Choice(Rounding::WORDS),
    default: "rne",
};

const PARAMS: &[ParamSpec] = &[EXP_BITS, FRAC_BITS, ROUND, STAGES];

/// The rounding mode of resolved parameters.
pub fn mode(p: &Params) -> Rounding {
    Rounding::parse(p.word("round")).expect("round is a declared choice")
}

impl Unit for FRecip {
    fn name(&self) -> &'static str {
        "frecip"
    }
    fn summary(&self) -> &'static str {
        "float 1 / x, rounded once (restoring division)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "frecip")?;
        Ok(wrap(recip_module(fmt, mode(p), p.u32("stages"))))
    }
}
