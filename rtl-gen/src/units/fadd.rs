//! `fadd`: float a + b (or a - b with `op=sub`), rounded once.

use super::fcommon::{format, rounding, wrap, EXP_BITS, FRAC_BITS, ROUND, STAGES};
use super::Unit;
use crate::arith::float::add;
use crate::ir::Module;
use crate::params::{ParamError, ParamKind, ParamSpec, Params};

/// The `fadd` unit.
pub struct FAdd;

const PARAMS: &[ParamSpec] = &[
    EXP_BITS,
    FRAC_BITS,
    ROUND,
    ParamSpec {
        name: "op",
        doc: "add: a + b; sub: a - b",
        kind: ParamKind::Choice(&["add", "sub"]),
        default: "add",
    },
    STAGES,
];

impl Unit for FAdd {
    fn name(&self) -> &'static str {
        "fadd"
    }
    fn summary(&self) -> &'static str {
        "float a + b or a - b, rounded once"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, "fadd")?;
        let sub = p.word("op") == "sub";
        Ok(wrap(add::add_module(
            fmt,
            rounding(p),
            sub,
            p.u32("stages"),
        )))
    }
}
