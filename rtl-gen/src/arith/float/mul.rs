//! Multiplication: the exact product of the significands (2F + 2 bits, from
//! the pipelined integer multiplier), then the shared rounder.

use super::bits::add_const;
use super::round::{class_of, finish_rounded, Raw, ROUND_STEPS};
use super::unpack::unpack;
use super::{sint_width, spread, Format, Rm, RoundSel};
use crate::arith::int::umul_module;
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use std::sync::Arc;

/// Logical steps of the exact product (both belong to the integer multiplier).
pub const MUL_RAW_STEPS: u32 = 2;

/// Width of the exponent of [`mul_raw`]'s result.
pub fn mul_exp_width(fmt: Format) -> u32 {
    let k = fmt.bias() + fmt.frac_bits as i64;
    sint_width(2 * (1 - k), 2 * (fmt.exp_ones() as i64 - 1 - k))
}

/// The exact product `a · b` as a raw value (never sticky): significand
/// `sig_a · sig_b` (2F + 2 bits), exponent `(eff_a - bias - F) + (eff_b - bias - F)`.
/// The multiplier instance `inst` has `mul_stages` registers; the raw value
/// belongs to the stage `mul_stages` after the current one, and this
/// function closes those stages.
#[track_caller]
pub fn mul_raw(
    m: &mut ModuleBuilder,
    fmt: Format,
    a: Sig,
    b: Sig,
    mul_stages: u32,
    inst: &str,
) -> Raw {
    let f = fmt.frac_bits;
    let ua = unpack(m, fmt, a);
    let ub = unpack(m, fmt, b);
    let sign = m.xor(ua.sign, ub.sign);
    let inf_zero = m.and(ua.inf, ub.zero);
    let zero_inf = m.and(ua.zero, ub.inf);
    let invalid = m.or(inf_zero, zero_inf);
    let any_nan = m.or(ua.nan, ub.nan);
    let nan = m.or(any_nan, invalid);
    let inf = m.or(ua.inf, ub.inf);
    let class = class_of(m, nan, inf);
    let xw = mul_exp_width(fmt);
    let iw = fmt.exp_bits + 2;
    let ea = crate::arith::int::zext(m, ua.eff_exp, iw);
    let eb = crate::arith::int::zext(m, ub.eff_exp, iw);
    let esum = m.add(ea, eb);
    let exp = add_const(m, esum, -2 * (fmt.bias() + f as i64), xw);
    let exp = m.name(exp, "prod_exp");
    let mul = umul_module(f + 1, f + 1, mul_stages);
    let p = m
        .instance(inst, &mul, &[("a", ua.sig), ("b", ub.sig)])
        .get("p")
        .expect("multiplier has output p");
    for _ in 0..mul_stages {
        m.stage();
    }
    let no_sticky = m.bool(false);
    Raw {
        sign,
        class,
        exp,
        sig: p,
        sticky: no_sticky,
    }
}

/// Module name of the multiplier.
pub fn mul_name(fmt: Format, mode: RoundSel, stages: u32) -> String {
    format!("fmul_{}_{mode}_s{stages}", fmt.tag())
}

/// `z = a · b` in `fmt`, rounded in `mode`, `stages` pipeline registers.
pub fn mul_module(fmt: Format, mode: impl Into<RoundSel>, stages: u32) -> Arc<Module> {
    let mode: RoundSel = mode.into();
    let mut m = fmt.operator_module(
        mul_name(fmt, mode, stages),
        format!("Floating-point a * b in {}, rounded {mode}.", fmt.tag()),
        stages,
    );
    m.param("round", mode);
    let a = m.input("a", Ty::UInt(fmt.width()));
    let b = m.input("b", Ty::UInt(fmt.width()));
    let rm = Rm::declare(&mut m, mode);
    let plan = spread(stages, MUL_RAW_STEPS + ROUND_STEPS);
    let (raw_cuts, round_cuts) = plan.split_at(MUL_RAW_STEPS as usize);
    let raw = mul_raw(&mut m, fmt, a, b, raw_cuts.iter().sum(), "u_mul");
    let rs: u32 = round_cuts.iter().sum();
    finish_rounded(m, fmt, &rm, &raw, rs, "multiplier")
}
