//! Multiplication: the exact product of the significands (2F + 2 bits, from
//! the pipelined integer multiplier), then the shared rounder.
//!
//! Mixed widths ([`mul_mixed_raw`], [`mul_mixed_module`]): operands of two
//! formats `(Ea, Fa)` and `(Eb, Fb)`, each unpacked in its own format, the
//! `(Fa + 1) × (Fb + 1)` significand product, rounded into a third format.
//! The product is the same exact value as after widening both operands
//! exactly into one format, so the rounding is bit-identical to that of
//! `mul` in the wide format, without its `(F + 1)²` multiplier.

use super::bits::add_const;
use super::round::{class_of, finish_rounded, finish_rounded_range, Range, Raw, ROUND_STEPS};
use super::unpack::unpack;
use super::{sint_width, spread, Format, Rm, RoundSel, Rounding};
use crate::arith::int::umul_module;
use crate::arith::ports::{product, Pair, PairPorts};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Logical steps of the exact product (both belong to the integer multiplier).
pub const MUL_RAW_STEPS: u32 = 2;

/// Width of the exponent of [`mul_raw`]'s result.
pub fn mul_exp_width(fmt: Format) -> u32 {
    mul_mixed_exp_width(fmt, fmt)
}

/// Width of the exponent of [`mul_mixed_raw`]'s result.
pub fn mul_mixed_exp_width(fa: Format, fb: Format) -> u32 {
    let ka = fa.bias() + fa.frac_bits as i64;
    let kb = fb.bias() + fb.frac_bits as i64;
    let hi = |f: Format, k: i64| f.exp_ones() as i64 - 1 - k;
    sint_width(2 - ka - kb, hi(fa, ka) + hi(fb, kb))
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
    mul_mixed_raw(m, fmt, fmt, a, b, mul_stages, inst)
}

/// The exact product `a · b` of an `fa` encoding `a` and an `fb` encoding
/// `b` as a raw value (never sticky): significand `sig_a · sig_b`
/// (Fa + Fb + 2 bits, from a `(Fa + 1) × (Fb + 1)` multiplier), exponent
/// `(eff_a − bias_a − Fa) + (eff_b − bias_b − Fb)`. Stages as [`mul_raw`].
#[track_caller]
pub fn mul_mixed_raw(
    m: &mut ModuleBuilder,
    fa: Format,
    fb: Format,
    a: Sig,
    b: Sig,
    mul_stages: u32,
    inst: &str,
) -> Raw {
    let ua = m.scope("a", |m| unpack(m, fa, a));
    let ub = m.scope("b", |m| unpack(m, fb, b));
    let sign = m.xor(ua.sign, ub.sign);
    let inf_zero = m.and(ua.inf, ub.zero);
    let zero_inf = m.and(ua.zero, ub.inf);
    let invalid = m.or(inf_zero, zero_inf);
    let any_nan = m.or(ua.nan, ub.nan);
    let nan = m.or(any_nan, invalid);
    let nan = m.name(nan, "nan");
    let inf = m.or(ua.inf, ub.inf);
    let inf = m.name(inf, "inf");
    let class = class_of(m, nan, inf);
    let xw = mul_mixed_exp_width(fa, fb);
    let iw = fa.exp_bits.max(fb.exp_bits) + 2;
    let ea = crate::arith::int::zext(m, ua.eff_exp, iw);
    let eb = crate::arith::int::zext(m, ub.eff_exp, iw);
    let esum = m.add(ea, eb);
    let k = fa.bias() + fa.frac_bits as i64 + fb.bias() + fb.frac_bits as i64;
    let exp = add_const(m, esum, -k, xw);
    let exp = m.name(exp, "prod_exp");
    let mul = umul_module(fa.frac_bits + 1, fb.frac_bits + 1, mul_stages);
    let p = product(m, inst, &mul, ua.sig, ub.sig);
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
    mul_range_module(fmt, mode, Range::Any, stages)
}

/// Module name of the multiplier whose operands and product stay in the
/// normal range ([`mul_normal_module`]).
pub fn mul_normal_name(fmt: Format, mode: RoundSel, stages: u32) -> String {
    format!("fmul_{}_{mode}_normal_s{stages}", fmt.tag())
}

/// [`mul_module`] for operands that are zero or normal and a product that
/// neither underflows nor overflows (the caller guarantees it; outside that
/// the result is unspecified): the product of two normal significands has
/// at most one leading zero, so the rounder shifts by one bit at most and
/// builds no subnormal or overflow path. Equal to [`mul_module`] wherever
/// the guarantee holds.
pub fn mul_normal_module(fmt: Format, mode: impl Into<RoundSel>, stages: u32) -> Arc<Module> {
    mul_range_module(fmt, mode, Range::Normal { lead: 1 }, stages)
}

fn mul_range_module(
    fmt: Format,
    mode: impl Into<RoundSel>,
    range: Range,
    stages: u32,
) -> Arc<Module> {
    let mode: RoundSel = mode.into();
    let (name, promise) = match range {
        Range::Any => (mul_name(fmt, mode, stages), ""),
        Range::Normal { .. } => (
            mul_normal_name(fmt, mode, stages),
            " Operands zero or normal, the product in the normal range (guaranteed by the caller).",
        ),
    };
    let mut m = fmt.operator_module(
        name,
        format!(
            "Floating-point a * b in {}, rounded {mode}.{promise}",
            fmt.tag()
        ),
        stages,
    );
    m.param("round", mode);
    let Pair { a, b, rm } = declare_inputs(&mut m, &PairPorts::rounded(fmt.ty(), mode));
    let rm = Rm::new(mode, rm);
    let plan = spread(stages, MUL_RAW_STEPS + ROUND_STEPS);
    let (raw_cuts, round_cuts) = plan.split_at(MUL_RAW_STEPS as usize);
    let raw = mul_raw(&mut m, fmt, a, b, raw_cuts.iter().sum(), "u_mul");
    let rs: u32 = round_cuts.iter().sum();
    finish_rounded_range(m, fmt, &rm, &raw, range, rs, "multiplier")
}

/// Module name of the mixed-width multiplier.
pub fn mul_mixed_name(fa: Format, fb: Format, to: Format, mode: Rounding, stages: u32) -> String {
    format!(
        "fmul_{}_x_{}_to_{}_{mode}_s{stages}",
        fa.tag(),
        fb.tag(),
        to.tag()
    )
}

/// Records the three formats of a mixed-width operator (operands `a` in
/// `fa`, `b` in `fb`, result in `to`) as module parameters.
pub fn mixed_format_params(
    m: &mut ModuleBuilder,
    fa: Format,
    fb: Format,
    to: Format,
) -> &mut ModuleBuilder {
    m.param("exp_bits_a", fa.exp_bits)
        .param("frac_bits_a", fa.frac_bits)
        .param("exp_bits_b", fb.exp_bits)
        .param("frac_bits_b", fb.frac_bits)
        .param("to_exp_bits", to.exp_bits)
        .param("to_frac_bits", to.frac_bits)
}

/// `z = a · b` for `a` in `fa` and `b` in `fb`, rounded once into `to` in
/// `mode`, `stages` pipeline registers (the plan of [`mul_module`]). Equal
/// to widening both operands exactly into a common format and multiplying
/// there, rounded into `to`.
pub fn mul_mixed_module(
    fa: Format,
    fb: Format,
    to: Format,
    mode: Rounding,
    stages: u32,
) -> Arc<Module> {
    let mut m = ModuleBuilder::new(mul_mixed_name(fa, fb, to, mode, stages));
    m.describe(format!(
        "Floating-point a * b, a in {}, b in {} ({} x {} significand product), rounded {mode} into {}.",
        fa.tag(),
        fb.tag(),
        fa.frac_bits + 1,
        fb.frac_bits + 1,
        to.tag()
    ));
    mixed_format_params(&mut m, fa, fb, to)
        .param("round", mode)
        .param("stages", stages);
    let ports = PairPorts {
        a: fa.ty(),
        b: fb.ty(),
        rm: false,
    };
    let Pair { a, b, .. } = declare_inputs(&mut m, &ports);
    let plan = spread(stages, MUL_RAW_STEPS + ROUND_STEPS);
    let (raw_cuts, round_cuts) = plan.split_at(MUL_RAW_STEPS as usize);
    let raw = mul_mixed_raw(&mut m, fa, fb, a, b, raw_cuts.iter().sum(), "u_mul");
    let rs: u32 = round_cuts.iter().sum();
    finish_rounded(m, to, &Rm::fixed(mode), &raw, rs, "mixed multiplier")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Evaluator;
    use crate::golden_twin::{golden_format, golden_mode};
    use golden_model::float::{convert, mul, RoundingMode};

    /// The product's exponent (the sum of each operand's `eff − bias − F`,
    /// eff 1 ..= 2^E − 2) takes no more bits than its range: binary32 spans
    /// −298 to 208 (10 signed bits), e5m10 −48 to 10 (7), e2m1 −2 to 0 (2),
    /// e5m10 × binary32 −173 to 109 (9).
    #[test]
    fn the_product_exponent_is_as_narrow_as_its_range() {
        let f = |e, m| Format::new(e, m).unwrap();
        assert_eq!(mul_exp_width(f(8, 23)), 10);
        assert_eq!(mul_exp_width(f(5, 10)), 7);
        assert_eq!(mul_exp_width(f(2, 1)), 2);
        assert_eq!(mul_mixed_exp_width(f(5, 10), f(8, 23)), 9);
    }

    /// The mixed-width product against the golden model's product of both
    /// operands widened exactly into `to` (which contains both formats):
    /// every pair of a small pair of formats in every mode, random pairs of
    /// the cull unit's formats.
    #[test]
    fn mixed_product_is_the_widened_product() {
        let f = |e, m| Format::new(e, m).unwrap();
        let cases = [
            (f(3, 2), f(4, 3), f(4, 3), true),
            (f(8, 23), f(8, 18), f(8, 23), false),
            (f(5, 10), f(8, 23), f(8, 23), false),
            (f(5, 10), f(8, 18), f(8, 18), false),
            (f(4, 3), f(5, 10), f(5, 10), false),
        ];
        let mut s = 0x2545_f491_4f6c_dd1du64;
        for (fa, fb, to, exhaustive) in cases {
            let (ga, gb, gt) = (golden_format(fa), golden_format(fb), golden_format(to));
            for mode in Rounding::ALL {
                let module = mul_mixed_module(fa, fb, to, mode, 0);
                let mut ev = Evaluator::new(&module);
                let n: u64 = if exhaustive {
                    1 << (fa.width() + fb.width())
                } else {
                    20_000
                };
                for i in 0..n {
                    let (a, b) = if exhaustive {
                        (i & ga.mask(), i >> fa.width())
                    } else {
                        s ^= s << 13;
                        s ^= s >> 7;
                        s ^= s << 17;
                        (s & ga.mask(), (s >> 32) & gb.mask())
                    };
                    let got = ev.eval(&[a as u128, b as u128])[0] as u64;
                    let wa = convert(ga, gt, a, RoundingMode::NearestEven);
                    let wb = convert(gb, gt, b, RoundingMode::NearestEven);
                    let want = mul(gt, wa, wb, golden_mode(mode));
                    assert_eq!(got, want, "{}: {a:#x} * {b:#x}", module.name);
                }
            }
        }
    }
}
