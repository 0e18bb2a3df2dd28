//! Fused multiply-add `a · b + c`, rounded once.
//!
//! The operands are normalised (subnormals shifted up, so every significand
//! has its leading one at the top), the significands multiplied exactly
//! (2F + 2 bits, leading one at bit 2F + 1 or 2F), and product and addend
//! added by [`sum_two`] in a window of 2F + 6 bits: carry, the anchor
//! term's 2F + 2 bits (the addend's F + 1 bits followed by F + 4 zeros), and
//! 3 guard bits. The product loses bits only if it lies more than 3 places
//! below the addend, the addend only if more than F + 4 places below the
//! product: in both cases the sum keeps its leading one within two places of
//! the anchor, so the jammed bit is F + 1 or more places below the rounding
//! position (see `sum.rs`). 2F + 6 = 110 bits for binary64, within the
//! DSL's 128-bit values.

use super::bits::add_const;
use super::round::{class_of, finish_rounded, ROUND_STEPS};
use super::sum::{sum_two, Term};
use super::unpack::{norm_exp_width, normalize, unpack};
use super::{sint_width, spread, Format, Rm, RoundSel, Rounding};
use crate::arith::int::umul_module;
use crate::arith::ports::{product, Triple};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Logical steps before the rounder: normalise; multiply (2); align; add.
pub const FMA_RAW_STEPS: u32 = 5;

/// Exponent given to a zero term: below every nonzero term's (and every
/// normalised partial sum's) top exponent, so a zero never becomes the anchor.
pub fn zero_term_exp(fmt: Format) -> i64 {
    let f = fmt.frac_bits as i64;
    2 * (fmt.emin() - f) - 2 * f - 8
}

/// Width of the exponents of the fused datapaths.
pub fn fused_exp_width(fmt: Format) -> u32 {
    sint_width(zero_term_exp(fmt) - 4, 2 * fmt.emax() + 4) + 1
}

/// Module name of the fused multiply-add.
pub fn fma_name(fmt: Format, mode: RoundSel, stages: u32) -> String {
    format!("ffma_{}_{mode}_s{stages}", fmt.tag())
}

/// `z = a · b + c` in `fmt`, rounded once in `mode`, `stages` pipeline registers.
pub fn fma_module(fmt: Format, mode: impl Into<RoundSel>, stages: u32) -> Arc<Module> {
    let mode: RoundSel = mode.into();
    let f = fmt.frac_bits;
    let mut m = fmt.operator_module(
        fma_name(fmt, mode, stages),
        format!(
            "Fused multiply-add a * b + c in {}, rounded once {mode}.",
            fmt.tag()
        ),
        stages,
    );
    m.param("round", mode);
    let Triple { a, b, c, rm } = declare_inputs(&mut m, &(fmt.ty(), mode.is_port()));
    let rm = Rm::new(mode, rm);
    let plan = spread(stages, FMA_RAW_STEPS + ROUND_STEPS);
    let ua = m.scope("a", |m| unpack(m, fmt, a));
    let ub = m.scope("b", |m| unpack(m, fmt, b));
    let uc = m.scope("c", |m| unpack(m, fmt, c));

    // specials and signs
    let sp = m.xor(ua.sign, ub.sign);
    let sp = m.name(sp, "prod_sign");
    let inf_zero = m.and(ua.inf, ub.zero);
    let zero_inf = m.and(ua.zero, ub.inf);
    let invalid_mul = m.or(inf_zero, zero_inf);
    let invalid_mul = m.name(invalid_mul, "invalid_mul");
    let nan_ab = m.or(ua.nan, ub.nan);
    let nan_in = m.or(nan_ab, uc.nan);
    let nan_in = m.name(nan_in, "nan_in");
    let p_inf = m.or(ua.inf, ub.inf);
    let p_inf = m.name(p_inf, "prod_inf");
    let eff_sub_sign = m.xor(sp, uc.sign);
    let inf_inf = m.and(p_inf, uc.inf);
    let invalid_add = m.and(inf_inf, eff_sub_sign);
    let invalid_add = m.name(invalid_add, "invalid_add");
    let nan = m.or(nan_in, invalid_mul);
    let nan = m.or(nan, invalid_add);
    let nan = m.name(nan, "nan");
    let inf = m.or(p_inf, uc.inf);
    let inf = m.name(inf, "inf");
    let class = class_of(&mut m, nan, inf);
    let p_zero = m.or(ua.zero, ub.zero);
    let p_zero = m.name(p_zero, "prod_zero");

    // step 1: normalise the operands, product exponent
    let na = m.scope("a", |m| normalize(m, fmt, &ua));
    let nb = m.scope("b", |m| normalize(m, fmt, &ub));
    let nc = m.scope("c", |m| normalize(m, fmt, &uc));
    let xw = fused_exp_width(fmt);
    let min = m.sint(xw, zero_term_exp(fmt) as i128);
    let esum = m.add(na.exp, nb.exp);
    let ep = add_const(&mut m, esum, 1, xw);
    let ep = m.mux(p_zero, min, ep);
    let ep = m.name(ep, "prod_top");
    let ec = super::bits::to_sint(&mut m, nc.exp, xw);
    let ec = m.mux(uc.zero, min, ec);
    let ec = m.name(ec, "addend_top");
    let _ = norm_exp_width(fmt);
    for _ in 0..plan[0] {
        m.stage();
    }

    // steps 2-3: exact product of the significands
    let mul_stages = plan[1] + plan[2];
    let mul = umul_module(f + 1, f + 1, mul_stages);
    let p = product(&mut m, "u_mul", &mul, na.sig, nb.sig);
    for _ in 0..mul_stages {
        m.stage();
    }

    // steps 4-5: align and add
    let window = 2 * f + 6;
    let s = m.scope("sum", |m| {
        sum_two(
            m,
            Term {
                sign: sp,
                sig: p,
                top: ep,
            },
            Term {
                sign: uc.sign,
                sig: nc.sig,
                top: ec,
            },
            window,
            xw,
            plan[3],
        )
    });
    // an exact zero of opposite-signed terms is -0 in RDN, +0 otherwise
    let sum_any = m.any_set(s.sig);
    let sum_zero = m.not(sum_any);
    let cancel = m.and(sum_zero, s.eff_sub);
    let cancel = m.name(cancel, "cancel");
    let zero_sign = rm.is(&mut m, Rounding::Rdn);
    let sign = m.mux(cancel, zero_sign, s.sign);
    // an infinite result has the sign of the infinite term
    let inf_sign = m.mux(p_inf, sp, uc.sign);
    let sign = m.mux(inf, inf_sign, sign);
    let sign = m.name(sign, "z_sign");
    let raw = s.to_raw(&mut m, sign, class, xw);
    for _ in 0..plan[4] {
        m.stage();
    }
    let rs: u32 = plan[5..].iter().sum();
    finish_rounded(m, fmt, &rm, &raw, rs, "fma")
}
