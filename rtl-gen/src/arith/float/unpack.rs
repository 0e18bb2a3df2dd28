//! Unpack and classify: the fields of an encoding, its class, its exact
//! value as significand and exponent, and the normalised form the fused
//! operators use.

use super::bits::{add_const, lzc, ssub, to_sint};
use super::{finish_operator, sint_width, Format};
use crate::arith::ports::{Fields, Operand};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// 2-bit class encoding of the RTL (the golden model's `Class`): zero.
pub const CLASS_ZERO: u128 = 0;
/// Class code of a nonzero finite value.
pub const CLASS_FINITE: u128 = 1;
/// Class code of an infinity.
pub const CLASS_INF: u128 = 2;
/// Class code of a NaN.
pub const CLASS_NAN: u128 = 3;

/// The decoded fields of one operand.
#[derive(Debug, Clone, Copy)]
pub struct Unpacked {
    /// sign bit, Bool
    pub sign: Sig,
    /// biased exponent field, UInt(E)
    pub exp_field: Sig,
    /// fraction field, UInt(F)
    pub frac: Sig,
    /// NaN (any payload), Bool
    pub nan: Sig,
    /// ±infinity, Bool
    pub inf: Sig,
    /// ±0, Bool
    pub zero: Sig,
    /// exponent field zero and fraction nonzero, Bool
    pub sub: Sig,
    /// significand with the hidden bit, UInt(F + 1): `{exp_field != 0, frac}`
    pub sig: Sig,
    /// effective biased exponent `max(exp_field, 1)`, UInt(E)
    pub eff_exp: Sig,
}

/// Decodes the `fmt` encoding `x` (UInt of the format's width); the fields
/// are named after their role (`sign`, `is_nan`, `sig`, ...), so a module
/// that unpacks several operands calls it in a scope per operand.
#[track_caller]
pub fn unpack(m: &mut ModuleBuilder, fmt: Format, x: Sig) -> Unpacked {
    let (e, f) = (fmt.exp_bits, fmt.frac_bits);
    // named as they are made, so that the values derived from them say so
    let sign = m.msb(x);
    let sign = m.name(sign, "sign");
    let exp_field = m.slice(x, e + f - 1, f);
    let exp_field = m.name(exp_field, "exp_field");
    let frac = m.slice(x, f - 1, 0);
    let frac = m.name(frac, "frac");
    let exp_ones = m.all_ones(exp_field);
    let exp_any = m.any_set(exp_field);
    let exp_zero = m.not(exp_any);
    let exp_zero = m.name(exp_zero, "exp_zero");
    let frac_any = m.any_set(frac);
    let frac_zero = m.not(frac_any);
    let nan = m.and(exp_ones, frac_any);
    let inf = m.and(exp_ones, frac_zero);
    let zero = m.and(exp_zero, frac_zero);
    let sub = m.and(exp_zero, frac_any);
    let hidden = m.as_uint(exp_any);
    let sig = m.cat(&[hidden, frac]);
    let one = m.uint(e, 1);
    let eff_exp = m.mux(exp_zero, one, exp_field);
    Unpacked {
        sign,
        exp_field,
        frac,
        nan: m.name(nan, "is_nan"),
        inf: m.name(inf, "is_inf"),
        zero: m.name(zero, "is_zero"),
        sub: m.name(sub, "is_sub"),
        sig: m.name(sig, "sig"),
        eff_exp: m.name(eff_exp, "eff_exp"),
    }
}

/// The 2-bit class code of an unpacked operand.
#[track_caller]
pub fn class_code(m: &mut ModuleBuilder, u: &Unpacked) -> Sig {
    // finite -> 01, NaN -> 11: the low bit is set unless zero or infinity
    let inf_or_nan = m.or(u.inf, u.nan);
    let hi = m.as_uint(inf_or_nan);
    let zero_or_inf = m.or(u.zero, u.inf);
    let lo_bit = m.not(zero_or_inf);
    let lo = m.as_uint(lo_bit);
    m.cat(&[hi, lo])
}

/// Width of [`lsb_exp`]: the weight exponent of the significand's bit 0.
pub fn lsb_exp_width(fmt: Format) -> u32 {
    let f = fmt.frac_bits as i64;
    sint_width(fmt.emin() - f, fmt.emax() - f)
}

/// Exponent of the weight of bit 0 of [`Unpacked::sig`]:
/// `eff_exp - bias - F`, SInt of [`lsb_exp_width`] bits.
#[track_caller]
pub fn lsb_exp(m: &mut ModuleBuilder, fmt: Format, u: &Unpacked) -> Sig {
    let w = lsb_exp_width(fmt);
    add_const(m, u.eff_exp, -(fmt.bias() + fmt.frac_bits as i64), w)
}

/// An operand with its significand normalised (leading one at the top).
#[derive(Debug, Clone, Copy)]
pub struct Normalized {
    /// significand, UInt(F + 1), top bit set unless the operand is zero
    pub sig: Sig,
    /// unbiased exponent of the significand's top bit, SInt of [`norm_exp_width`] bits
    pub exp: Sig,
}

/// Width of [`Normalized::exp`]: holds `emin - F - 1 ..= emax`.
pub fn norm_exp_width(fmt: Format) -> u32 {
    sint_width(fmt.emin() - fmt.frac_bits as i64 - 1, fmt.emax())
}

/// Normalises the significand of a finite operand: a leading-zero count and
/// a left shift (only subnormals move); the exponent of the top bit is
/// `eff_exp - bias - lz`.
#[track_caller]
pub fn normalize(m: &mut ModuleBuilder, fmt: Format, u: &Unpacked) -> Normalized {
    let lz = lzc(m, u.sig);
    let sig = m.shl(u.sig, lz);
    let sig = m.name(sig, "sig_norm");
    let w = norm_exp_width(fmt);
    let iw = (fmt.exp_bits + 2).max(lz.width() + 2).max(w);
    let e = to_sint(m, u.eff_exp, iw);
    let lz_s = to_sint(m, lz, iw);
    let e = ssub(m, e, lz_s, iw);
    let exp = add_const(m, e, -fmt.bias(), w);
    let exp = m.name(exp, "exp_norm");
    Normalized { sig, exp }
}

/// Module name of the unpack/classify operator.
pub fn unpack_name(fmt: Format, stages: u32) -> String {
    format!("funpack_{}_s{stages}", fmt.tag())
}

/// The unpack/classify operator: input `x`; outputs `sign`, `class` (2 bits:
/// 0 zero, 1 finite, 2 infinity, 3 NaN), `exp` (SInt of [`lsb_exp_width`]:
/// the weight exponent of bit 0 of `sig`) and `sig` (UInt(F + 1), with the
/// hidden bit), so a finite value is `(-1)^sign · sig · 2^exp`. As in the
/// golden model, a zero has `exp = emin - F`, and infinities and NaNs have
/// `exp = 0`, `sig = 0`. `stages` registers at the outputs.
pub fn unpack_module(fmt: Format, stages: u32) -> Arc<Module> {
    let mut m = fmt.operator_module(
        unpack_name(fmt, stages),
        format!(
            "Unpack and classify a {} value: sign, class (0 zero, 1 finite, 2 inf, 3 NaN), exponent of the lsb, significand.",
            fmt.tag()
        ),
        stages,
    );
    let Operand { x } = declare_inputs(&mut m, &fmt.ty());
    let u = m.scope("x", |m| unpack(m, fmt, x));
    let class = class_code(&mut m, &u);
    let special = m.or(u.inf, u.nan);
    let e = lsb_exp(&mut m, fmt, &u);
    let e0 = m.sint(e.width(), 0);
    let exp = m.mux(special, e0, e);
    let s0 = m.uint(fmt.frac_bits + 1, 0);
    let sig = m.mux(special, s0, u.sig);
    let fields = Fields {
        sign: u.sign,
        cls: class,
        exp,
        sig,
    };
    finish_operator(m, stages, &(exp.ty(), sig.ty()), &fields, "unpack")
}
