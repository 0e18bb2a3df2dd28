//! Fused multiply-add `a · b + c`, rounded once.

use super::add::sum_of_two;
use super::format::{FloatFormat, RoundingMode};
use super::mul::product_of;
use super::native::f32_bits;
use super::round::round;
use super::unpack::unpack;

/// `a · b + c` computed exactly and rounded once in `mode`.
///
/// Specials: any NaN → NaN; inf · 0 → NaN (whatever `c` is); a·b = ±inf and
/// c = ∓inf → NaN; otherwise an infinite product or addend gives that
/// infinity. An exact zero result follows the addition rule with the
/// product's sign = sign(a) XOR sign(b): (+0) + (+0) = +0, (-0) + (-0) = -0,
/// any other exact zero is +0, or -0 in RDN.
///
/// Binary32 in RNE is `f32::mul_add` (IEEE fusedMultiplyAdd, one rounding),
/// everything else [`fma_generic`].
#[inline]
pub fn fma(fmt: FloatFormat, a: u64, b: u64, c: u64, mode: RoundingMode) -> u64 {
    if fmt == FloatFormat::BINARY32 && mode == RoundingMode::NearestEven {
        let v = |x: u64| f32::from_bits(x as u32);
        return f32_bits(v(a).mul_add(v(b), v(c)));
    }
    fma_generic(fmt, a, b, c, mode)
}

/// The reference [`fma`]: exact product and sum, shared rounder.
pub fn fma_generic(fmt: FloatFormat, a: u64, b: u64, c: u64, mode: RoundingMode) -> u64 {
    let product = product_of(unpack(fmt, a), unpack(fmt, b));
    round(fmt, sum_of_two(product, unpack(fmt, c), mode), mode)
}
