//! IEEE 754-2019 `minimum` and `maximum`: NaN if either operand is NaN, and
//! -0 orders below +0.

use super::format::FloatFormat;
use super::order::total_key;

/// The smaller of `a` and `b` (-0 < +0); the canonical NaN if either is NaN.
#[inline]
pub fn min(fmt: FloatFormat, a: u64, b: u64) -> u64 {
    pick(fmt, a, b, true)
}

/// The larger of `a` and `b` (-0 < +0); the canonical NaN if either is NaN.
#[inline]
pub fn max(fmt: FloatFormat, a: u64, b: u64) -> u64 {
    pick(fmt, a, b, false)
}

#[inline]
fn pick(fmt: FloatFormat, a: u64, b: u64, smaller: bool) -> u64 {
    if fmt.is_nan(a) || fmt.is_nan(b) {
        return fmt.canonical_nan();
    }
    let (a, b) = (a & fmt.mask(), b & fmt.mask());
    let a_first = (total_key(fmt, a) <= total_key(fmt, b)) == smaller;
    if a_first {
        a
    } else {
        b
    }
}
