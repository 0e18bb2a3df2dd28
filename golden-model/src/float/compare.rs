//! IEEE 754 comparisons: `lt`, `le`, `eq` (quiet: NaN is unordered → false;
//! -0 == +0). They work on any format, e.g. on exact products in the wide
//! format of `mul_exact`.

use super::format::FloatFormat;

/// `a < b`; false if either is NaN.
#[inline]
pub fn lt(fmt: FloatFormat, a: u64, b: u64) -> bool {
    ordered(fmt, a, b) && order_key(fmt, a) < order_key(fmt, b)
}

/// `a <= b`; false if either is NaN.
#[inline]
pub fn le(fmt: FloatFormat, a: u64, b: u64) -> bool {
    ordered(fmt, a, b) && order_key(fmt, a) <= order_key(fmt, b)
}

/// `a == b`; false if either is NaN; -0 == +0.
pub fn eq(fmt: FloatFormat, a: u64, b: u64) -> bool {
    ordered(fmt, a, b) && order_key(fmt, a) == order_key(fmt, b)
}

/// Neither operand is NaN.
#[inline]
fn ordered(fmt: FloatFormat, a: u64, b: u64) -> bool {
    !fmt.is_nan(a) && !fmt.is_nan(b)
}

/// A signed integer in the order of the (non-NaN) values, with -0 and +0
/// both mapped to 0: `+magnitude` or `-magnitude`, where magnitude is the
/// bits without the sign (IEEE encodings are monotonic in magnitude).
#[inline]
pub(crate) fn order_key(fmt: FloatFormat, bits: u64) -> i64 {
    let magnitude = (bits & fmt.mask() & !fmt.sign_bit()) as i64;
    if bits & fmt.sign_bit() != 0 {
        -magnitude
    } else {
        magnitude
    }
}
