//! Correctly rounded reciprocal `1 / x`, the one division of the hardware
//! inversion (`docs/transform.md` §3). It follows the float model's contract
//! (`docs/float.md`): exact quotient with a sticky bit, then the shared
//! rounder.

use crate::float::native::{round_exact_f64_to, rounds_natively, to_f32};
use crate::float::{round, unpack, Class, FloatFormat, RawFloat, RoundingMode};

/// `1 / x` rounded once in `mode`.
///
/// Specials: NaN → canonical NaN; `1/±0 = ±inf`; `1/±inf = ±0`. For finite
/// nonzero `x = sig · 2^exp` the quotient `q = floor(2^k / sig)` with
/// `k = F + 3 + bitlen(sig)` has at least F + 3 bits, the remainder sets the
/// sticky bit, and the rounder rounds `q · 2^(−exp − k)` (subnormal and
/// overflowing results included: the reciprocal of a tiny subnormal is ∞ in
/// RNE).
///
/// Formats that [`rounds_natively`] in `mode` (values of them are `f32`s)
/// take [`recip_f64`]; otherwise, when `k < 64` (F <= 29), the quotient and
/// remainder are formed in `u64` (the same values, so the same bits);
/// [`recip_generic`] is the `u128` reference.
#[inline]
pub fn recip(fmt: FloatFormat, x: u64, mode: RoundingMode) -> u64 {
    if rounds_natively(fmt, mode) {
        return round_exact_f64_to(fmt, recip_f64(fmt, x), mode);
    }
    let r = unpack(fmt, x);
    if r.class == Class::Finite {
        let k = fmt.frac_bits() + 3 + (128 - r.sig.leading_zeros());
        if k < 64 {
            let (num, sig) = (1u64 << k, r.sig as u64);
            let (q, sticky) = (num / sig, num % sig != 0);
            let raw = RawFloat {
                sign: r.sign,
                class: Class::Finite,
                exp: -r.exp - k as i32,
                sig: q as u128,
                sticky,
            };
            return round(fmt, raw, mode);
        }
    }
    recip_generic(fmt, x, mode)
}

/// `1/x` for `x` of a format whose values are `f32`s
/// ([`fits_f32`](crate::float::native::fits_f32)), as the
/// `f64` quotient `q`, which every rounding to binary32 or to a binary32
/// subgrid rounds as the exact quotient (specials included: `1/±0 = ±∞`,
/// `1/±∞ = ±0`, NaN).
///
/// Why: for `x = X·2^a` and a grid point `g = G·2^c` (`X`, `G` integers of
/// at most 24 and 25 bits, midpoints included) near `1/x`, `1 − g·x` is a
/// multiple of `2^(a+c)` with `X·G < 2^49` and `g·x ≈ 1`, so it is 0 or at
/// least `2^-50` in magnitude: `1/x` is a grid point or lies at a relative
/// distance of at least `2^-50` from every one, while `|q − 1/x| ≤ 2^-53 |1/x|`.
/// So no grid point or midpoint lies between `q` and `1/x`, and `q` is one
/// only when `1/x` is; quotients beyond the binary32 range (tiny `x`) are
/// `f64` values too.
#[inline(always)]
pub(crate) fn recip_f64(fmt: FloatFormat, x: u64) -> f64 {
    1.0 / to_f32(fmt, x) as f64
}

/// The reference [`recip`] (`u128` quotient).
pub fn recip_generic(fmt: FloatFormat, x: u64, mode: RoundingMode) -> u64 {
    let r = unpack(fmt, x);
    let raw = match r.class {
        Class::NaN => RawFloat::NAN,
        Class::Zero => RawFloat::special(r.sign, Class::Inf),
        Class::Inf => RawFloat::special(r.sign, Class::Zero),
        Class::Finite => {
            let k = fmt.frac_bits() + 3 + (128 - r.sig.leading_zeros());
            let num = 1u128 << k;
            let q = num / r.sig;
            let rem = num % r.sig;
            RawFloat {
                sign: r.sign,
                class: Class::Finite,
                exp: -r.exp - k as i32,
                sig: q,
                sticky: rem != 0,
            }
        }
    };
    round(fmt, raw, mode)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary32_reciprocals_match_f32_division() {
        let f = FloatFormat::BINARY32;
        let mut s = 0x1234_5678_9abc_def0u64;
        for i in 0..200_000u32 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let x = match i {
                0 => 0.0f32,
                1 => -0.0,
                2 => f32::INFINITY,
                3 => f32::from_bits(1),
                4 => f32::MAX,
                5 => f32::MIN_POSITIVE,
                _ => f32::from_bits((s >> 32) as u32),
            };
            let got = recip(f, x.to_bits() as u64, RoundingMode::NearestEven);
            let want = 1.0f32 / x;
            if want.is_nan() {
                assert_eq!(got, f.canonical_nan());
            } else {
                assert_eq!(got, want.to_bits() as u64, "1/{x:e}");
            }
        }
    }
}
