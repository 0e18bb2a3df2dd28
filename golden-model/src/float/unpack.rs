//! Unpack and classify: raw bits of a format → [`RawFloat`] (exact, no sticky).

use super::format::FloatFormat;
use super::raw::{Class, RawFloat};

/// The class of `bits` in `fmt` (bits above `fmt.width()` are ignored).
pub fn classify(fmt: FloatFormat, bits: u64) -> Class {
    unpack(fmt, bits).class
}

/// Decodes `bits` (bits above `fmt.width()` are ignored) into an exact
/// [`RawFloat`]: for finite nonzero values `sig` is the significand with the
/// hidden bit (`< 2^(F+1)`, `< 2^F` for subnormals) and
/// `exp = max(biased_exp, 1) - bias - F`, so that `|v| = sig · 2^exp`.
#[inline]
pub fn unpack(fmt: FloatFormat, bits: u64) -> RawFloat {
    let f = fmt.frac_bits();
    let sign = bits & fmt.sign_bit() != 0;
    let biased = (bits >> f) & fmt.exp_all_ones();
    let frac = bits & fmt.frac_mask();
    if biased == fmt.exp_all_ones() {
        let class = if frac == 0 { Class::Inf } else { Class::NaN };
        return RawFloat::special(sign, class);
    }
    if biased == 0 {
        // Zero or subnormal: no hidden bit, exponent of emin.
        let exp = fmt.emin() - f as i32;
        return RawFloat::exact(sign, frac as u128, exp);
    }
    let sig = (frac | (1 << f)) as u128;
    let exp = biased as i32 - fmt.bias() - f as i32;
    RawFloat::exact(sign, sig, exp)
}
