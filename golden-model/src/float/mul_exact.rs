//! Exact multiplication: the full product as a value of the wider format
//! (E + 2, 2F + 1), never rounded.

use super::format::{FloatFormat, FormatError, RoundingMode};
use super::mul::mul_raw;
use super::round::round;

/// A format and its exact-product format `(E + 2, 2F + 1)`, checked once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExactProductFormat {
    narrow: FloatFormat,
    wide: FloatFormat,
}

impl ExactProductFormat {
    /// The pair for operands of `narrow`, or why `(E + 2, 2F + 1)` is not a
    /// supported format (e.g. binary64: it would need 119 bits).
    pub const fn new(narrow: FloatFormat) -> Result<ExactProductFormat, FormatError> {
        match narrow.exact_product_format() {
            Ok(wide) => Ok(ExactProductFormat { narrow, wide }),
            Err(e) => Err(e),
        }
    }
    /// The operand format (E, F).
    #[inline]
    pub const fn narrow(self) -> FloatFormat {
        self.narrow
    }
    /// The product format (E + 2, 2F + 1).
    #[inline]
    pub const fn wide(self) -> FloatFormat {
        self.wide
    }
}

/// The exact product `a · b` of two `p.narrow()` values, as bits of
/// `p.wide()`. No rounding happens: every such product is representable
/// (see docs/float.md, "Exact multiply"). Specials as in `mul`:
/// inf · 0 → canonical NaN, NaN → canonical NaN, signed zeros and infinities.
pub fn mul_exact(p: ExactProductFormat, a: u64, b: u64) -> u64 {
    let raw = mul_raw(p.narrow, a, b);
    // Any mode gives the same bits since the product is exact; RNE by convention.
    round(p.wide, raw, RoundingMode::NearestEven)
}
