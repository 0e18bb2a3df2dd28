//! Addition and subtraction, and the exact two-term sum shared with `fma`.

use super::format::{FloatFormat, RoundingMode};
use super::native::{add_f32, f32_bits};
use super::raw::{Class, RawFloat};
use super::round::{exact_zero_sum_sign, round, shift_right_sticky};
use super::unpack::unpack;

/// `a + b` in `fmt`, rounded once in `mode`: binary32 natively
/// (`native::add_f32`), other formats [`add_generic`].
#[inline]
pub fn add(fmt: FloatFormat, a: u64, b: u64, mode: RoundingMode) -> u64 {
    if fmt == FloatFormat::BINARY32 {
        let (x, y) = (f32::from_bits(a as u32), f32::from_bits(b as u32));
        return f32_bits(add_f32(x, y, mode));
    }
    add_generic(fmt, a, b, mode)
}

/// The reference [`add`]: exact sum, shared rounder.
pub fn add_generic(fmt: FloatFormat, a: u64, b: u64, mode: RoundingMode) -> u64 {
    round(fmt, add_raw(fmt, a, b, mode), mode)
}

/// `a - b` in `fmt`, rounded once in `mode` (= `a + (-b)`, also for NaN `b`).
#[inline]
pub fn sub(fmt: FloatFormat, a: u64, b: u64, mode: RoundingMode) -> u64 {
    add(fmt, a, b ^ fmt.sign_bit(), mode)
}

/// The unrounded `a + b`. `mode` only decides the sign of an exact zero.
#[inline]
pub(crate) fn add_raw(fmt: FloatFormat, a: u64, b: u64, mode: RoundingMode) -> RawFloat {
    sum_of_two(unpack(fmt, a), unpack(fmt, b), mode)
}

/// The unrounded sum of two exact values (any classes), IEEE 754 special
/// cases included: NaN in → NaN; inf + (-inf) → NaN; inf + x → inf;
/// 0 + 0 and exact cancellation per [`exact_zero_sum_sign`].
#[inline]
pub(crate) fn sum_of_two(x: RawFloat, y: RawFloat, mode: RoundingMode) -> RawFloat {
    match (x.class, y.class) {
        (Class::NaN, _) | (_, Class::NaN) => RawFloat::NAN,
        (Class::Inf, Class::Inf) if x.sign != y.sign => RawFloat::NAN,
        (Class::Inf, _) => x,
        (_, Class::Inf) => y,
        (Class::Zero, Class::Zero) => {
            let all_zero = (x.sign == y.sign).then_some(x.sign);
            RawFloat::special(exact_zero_sum_sign(all_zero, mode), Class::Zero)
        }
        (Class::Zero, Class::Finite) => y,
        (Class::Finite, Class::Zero) => x,
        (Class::Finite, Class::Finite) => sum_finite(x, y, mode),
    }
}

/// Bit position of the larger term's leading one in the 128-bit window.
/// Two bits stay free above it: one for the carry of an addition, one spare.
const WINDOW_TOP: u32 = 125;

/// Largest significand length [`sum_finite`] accepts (a product of two
/// binary64 significands).
pub(crate) const MAX_TERM_BITS: u32 = 106;

/// Exact sum of two nonzero exact finite values, each with a significand of
/// at most [`MAX_TERM_BITS`] bits.
///
/// The term with the higher leading one, x, is shifted so that its leading
/// one is at bit [`WINDOW_TOP`]; the window's bit 0 has weight `2^g`. The
/// other term, y, is placed on the same grid; if it has bits below `2^g`,
/// they are dropped into `sticky`. That happens only when y's leading one is
/// more than `WINDOW_TOP - (MAX_TERM_BITS - 1) = 20` bits below x's, so the sum is
/// at least `2^(WINDOW_TOP - 1)` units and keeps far more than F + 2 bits
/// above the sticky: rounding it is the same as rounding the exact sum.
#[inline]
pub(crate) fn sum_finite(x: RawFloat, y: RawFloat, mode: RoundingMode) -> RawFloat {
    debug_assert!(x.class == Class::Finite && y.class == Class::Finite);
    debug_assert!(!x.sticky && !y.sticky);
    let lead = |r: &RawFloat| r.exp + (u128::BITS - r.sig.leading_zeros()) as i32 - 1;
    let (x, y) = if lead(&x) >= lead(&y) { (x, y) } else { (y, x) };
    debug_assert!(x.sig >> MAX_TERM_BITS == 0 && y.sig >> MAX_TERM_BITS == 0);

    let up = WINDOW_TOP - (u128::BITS - 1 - x.sig.leading_zeros());
    let g = x.exp - up as i32;
    let xs = x.sig << up;
    let (ys, lost) = if y.exp >= g {
        (y.sig << (y.exp - g) as u32, false)
    } else {
        shift_right_sticky(y.sig, (g - y.exp) as u32)
    };

    if x.sign == y.sign {
        // (xs + ys + s)·2^g with 0 <= s < 1, s > 0 iff lost.
        return RawFloat {
            sign: x.sign,
            class: Class::Finite,
            exp: g,
            sig: xs + ys,
            sticky: lost,
        };
    }
    if lost {
        // |y| lies strictly between ys and ys + 1 units, so |x| - |y| lies
        // strictly between xs - ys - 1 and xs - ys (and xs >= 2^125 > ys + 1).
        return RawFloat {
            sign: x.sign,
            class: Class::Finite,
            exp: g,
            sig: xs - ys - 1,
            sticky: true,
        };
    }
    // Exact difference; y may be the larger one when the leading ones align.
    let (sign, sig) = if xs >= ys {
        (x.sign, xs - ys)
    } else {
        (y.sign, ys - xs)
    };
    if sig == 0 {
        return RawFloat::special(exact_zero_sum_sign(None, mode), Class::Zero);
    }
    RawFloat {
        sign,
        class: Class::Finite,
        exp: g,
        sig,
        sticky: false,
    }
}
