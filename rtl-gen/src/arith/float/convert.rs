//! Conversion between two formats, rounded once: the source unpacked as an
//! exact raw value (hidden bit, fraction, exponent of its lsb) and rounded
//! by the shared rounder of the target format (which also handles overflow
//! of narrowing conversions and subnormal results). Widening is exact.

use super::round::{class_of, finish_rounded, Raw, ROUND_STEPS};
use super::unpack::{lsb_exp, unpack};
use super::{spread, Format, Rm, RoundSel};
use crate::arith::ports::Source;
use crate::builder::ModuleBuilder;
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Logical steps before the rounder: unpack.
pub const CONVERT_RAW_STEPS: u32 = 1;

/// Module name of the converter.
pub fn convert_name(from: Format, to: Format, mode: RoundSel, stages: u32) -> String {
    format!("fcvt_{}_to_{}_{mode}_s{stages}", from.tag(), to.tag())
}

/// `z = a` converted from `from` to `to`, rounded in `mode` (NaN → the
/// canonical NaN of `to`), `stages` pipeline registers.
pub fn convert_module(
    from: Format,
    to: Format,
    mode: impl Into<RoundSel>,
    stages: u32,
) -> Arc<Module> {
    let mode: RoundSel = mode.into();
    let mut m = ModuleBuilder::new(convert_name(from, to, mode, stages));
    m.describe(format!(
        "Conversion of a {} value to {}, rounded {mode}.",
        from.tag(),
        to.tag()
    ));
    m.param("exp_bits", from.exp_bits)
        .param("frac_bits", from.frac_bits)
        .param("to_exp_bits", to.exp_bits)
        .param("to_frac_bits", to.frac_bits)
        .param("round", mode)
        .param("stages", stages);
    let Source { a, rm } = declare_inputs(&mut m, &(from.ty(), mode.is_port()));
    let rm = Rm::new(mode, rm);
    let plan = spread(stages, CONVERT_RAW_STEPS + ROUND_STEPS);
    let u = m.scope("a", |m| unpack(m, from, a));
    let class = class_of(&mut m, u.nan, u.inf);
    let exp = lsb_exp(&mut m, from, &u);
    let sticky = m.bool(false);
    let raw = Raw {
        sign: u.sign,
        class,
        exp,
        sig: u.sig,
        sticky,
    };
    for _ in 0..plan[0] {
        m.stage();
    }
    let rs: u32 = plan[1..].iter().sum();
    finish_rounded(m, to, &rm, &raw, rs, "converter")
}
