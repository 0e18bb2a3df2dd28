//! Multiplication, rounded once.

use super::format::{FloatFormat, RoundingMode};
use super::native::{f32_bits, mul_f32};
use super::raw::{Class, RawFloat};
use super::round::round;
use super::unpack::unpack;

/// `a · b` in `fmt`, rounded once in `mode`: binary32 natively
/// (`native::mul_f32`), other formats [`mul_generic`].
#[inline]
pub fn mul(fmt: FloatFormat, a: u64, b: u64, mode: RoundingMode) -> u64 {
    if fmt == FloatFormat::BINARY32 {
        let (x, y) = (f32::from_bits(a as u32), f32::from_bits(b as u32));
        return f32_bits(mul_f32(x, y, mode));
    }
    mul_generic(fmt, a, b, mode)
}

/// The reference [`mul`]: exact product, shared rounder.
pub fn mul_generic(fmt: FloatFormat, a: u64, b: u64, mode: RoundingMode) -> u64 {
    round(fmt, mul_raw(fmt, a, b), mode)
}

/// The exact product as a [`RawFloat`] (never sticky).
#[inline]
pub(crate) fn mul_raw(fmt: FloatFormat, a: u64, b: u64) -> RawFloat {
    product_of(unpack(fmt, a), unpack(fmt, b))
}

/// The exact product of two exact values, IEEE 754 special cases included:
/// NaN in → NaN; inf · 0 → NaN; inf · x → inf; 0 · x → 0; the sign of every
/// non-NaN result is the XOR of the operand signs. The significand of a
/// finite product has at most 2F + 2 bits.
#[inline]
pub(crate) fn product_of(x: RawFloat, y: RawFloat) -> RawFloat {
    let sign = x.sign != y.sign;
    match (x.class, y.class) {
        (Class::NaN, _) | (_, Class::NaN) => RawFloat::NAN,
        (Class::Inf, Class::Zero) | (Class::Zero, Class::Inf) => RawFloat::NAN,
        (Class::Inf, _) | (_, Class::Inf) => RawFloat::special(sign, Class::Inf),
        (Class::Zero, _) | (_, Class::Zero) => RawFloat::special(sign, Class::Zero),
        (Class::Finite, Class::Finite) => RawFloat::exact(sign, x.sig * y.sig, x.exp + y.exp),
    }
}
