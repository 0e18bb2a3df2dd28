//! The one shared rounder: [`RawFloat`] → packed bits of a format.

use super::format::{FloatFormat, RoundingMode};
use super::raw::{Class, RawFloat};

/// Rounds `raw` to `fmt` in `mode` and packs it.
///
/// * NaN → the canonical NaN; ±inf → ±inf; zero → zero of `raw.sign`.
/// * Finite: the exact value `(sig + s)·2^exp` is rounded to F + 1
///   significant bits at the exponent `max(floor(log2|v|), emin)` (so tiny
///   values round on the subnormal grid: gradual underflow); a carry out of
///   rounding moves to the next binade; a result above the largest finite
///   value overflows per mode (RNE → ±inf, RTZ → ±max, RUP → +inf / -max,
///   RDN → +max / -inf). A result that rounds to zero keeps `raw.sign`.
#[inline]
pub fn round(fmt: FloatFormat, raw: RawFloat, mode: RoundingMode) -> u64 {
    match raw.class {
        Class::NaN => return fmt.canonical_nan(),
        Class::Inf => return fmt.inf(raw.sign),
        Class::Zero => return fmt.zero(raw.sign),
        Class::Finite => {}
    }
    let f = fmt.frac_bits() as i32;
    if raw.sig == 0 {
        debug_assert!(!raw.sticky, "RawFloat: sig == 0 with sticky");
        return fmt.zero(raw.sign);
    }
    debug_assert!(
        !raw.sticky || raw.sig >> (f + 1) != 0,
        "RawFloat: sticky needs sig >= 2^(F+1)"
    );

    // Exponent of the leading one, and of the result's lowest kept bit.
    let sig_len = (u128::BITS - raw.sig.leading_zeros()) as i32;
    let lead_exp = raw.exp + sig_len - 1;
    let mut res_exp = lead_exp.max(fmt.emin());
    let shift = res_exp - f - raw.exp;

    // kept: the F+1 (or fewer, if subnormal) bits at and above the result lsb.
    let (mut kept, round_bit, sticky) = if shift <= 0 {
        // Exact: no bit of sig is below the result lsb (and sticky is clear).
        (raw.sig << (-shift) as u32, false, raw.sticky)
    } else {
        let (kept, round_bit, below) = split_at(raw.sig, shift as u32);
        (kept, round_bit, below || raw.sticky)
    };

    let increment = match mode {
        RoundingMode::NearestEven => round_bit && (sticky || kept & 1 == 1),
        RoundingMode::TowardZero => false,
        RoundingMode::Up => !raw.sign && (round_bit || sticky),
        RoundingMode::Down => raw.sign && (round_bit || sticky),
    };
    kept += increment as u128;
    if kept >> (f + 1) != 0 {
        // Carry out of rounding: 1.11..1 + ulp = 10.00..0.
        kept >>= 1;
        res_exp += 1;
    }

    if res_exp > fmt.emax() {
        return overflow(fmt, raw.sign, mode);
    }
    // kept < 2^F only when res_exp == emin: subnormal (or zero), biased exponent 0.
    let biased = if kept >> f == 0 {
        0
    } else {
        (res_exp + fmt.bias()) as u64
    };
    let magnitude = (biased << f) | (kept as u64 & fmt.frac_mask());
    fmt.with_sign(raw.sign, magnitude)
}

/// The result of a finite value too large for `fmt`, per IEEE 754 7.4.
pub fn overflow(fmt: FloatFormat, negative: bool, mode: RoundingMode) -> u64 {
    let to_inf = match mode {
        RoundingMode::NearestEven => true,
        RoundingMode::TowardZero => false,
        RoundingMode::Up => !negative,
        RoundingMode::Down => negative,
    };
    if to_inf {
        fmt.inf(negative)
    } else {
        fmt.max_finite(negative)
    }
}

/// Splits `x` at bit `shift >= 1`: `(x >> shift, bit shift-1, any lower bit)`.
/// Shifts of 128 or more keep nothing.
#[inline]
pub(crate) fn split_at(x: u128, shift: u32) -> (u128, bool, bool) {
    debug_assert!(shift >= 1);
    if shift > u128::BITS {
        return (0, false, x != 0);
    }
    let kept = x.checked_shr(shift).unwrap_or(0);
    let round_bit = (x >> (shift - 1)) & 1 == 1;
    let below = x & ((1u128 << (shift - 1)) - 1) != 0;
    (kept, round_bit, below)
}

/// `(x >> shift, whether any shifted-out bit was set)`, for any `shift`.
#[inline]
pub(crate) fn shift_right_sticky(x: u128, shift: u32) -> (u128, bool) {
    if shift == 0 {
        return (x, false);
    }
    let (kept, round_bit, below) = split_at(x, shift);
    (kept, round_bit || below)
}

/// The IEEE 754 sign of an exact zero sum (6.3). `all_zero` is
/// `Some(sign)` when every term of the sum is a zero of that same sign (then
/// the sum is that zero, e.g. (-0) + (-0) = -0); otherwise (opposite-signed
/// zeros, or nonzero terms that cancel exactly) the sum is +0, except -0
/// when rounding toward -inf.
#[inline]
pub(crate) fn exact_zero_sum_sign(all_zero: Option<bool>, mode: RoundingMode) -> bool {
    all_zero.unwrap_or(mode == RoundingMode::Down)
}
