//! Correctly rounded reciprocal `1 / x`, the one division of the hardware
//! inversion (`docs/transform.md` §3). It follows the float model's contract
//! (`docs/float.md`): exact quotient with a sticky bit, then the shared
//! rounder.

use crate::float::native::{round_exact_f64_to, rounds_natively};
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
/// When `k < 64` (F <= 29) the quotient and remainder are formed in `u64`
/// (the same values, so the same bits); [`recip_generic`] is the `u128`
/// reference.
#[inline]
pub fn recip(fmt: FloatFormat, x: u64, mode: RoundingMode) -> u64 {
    let r = unpack(fmt, x);
    if r.class == Class::Finite {
        let k = fmt.frac_bits() + 3 + (128 - r.sig.leading_zeros());
        if k < 64 {
            let (num, sig) = (1u64 << k, r.sig as u64);
            let (q, sticky) = (num / sig, num % sig != 0);
            let exp = -r.exp - k as i32;
            if rounds_natively(fmt, mode) && (-1000..=1000).contains(&exp) {
                // (q + s)·2^exp with 0 < s < 1 iff sticky, and q >= 2^(F+2):
                // (2q + sticky)·2^(exp-1) is exact in f64 and lies in the same
                // open interval between two neighbours of q·2^exp, which holds
                // no point of the result grid nor a midpoint: it rounds alike.
                let w = (2 * q + sticky as u64) as f64
                    * f64::from_bits(((exp - 1 + 1023) as u64) << 52);
                return round_exact_f64_to(fmt, if r.sign { -w } else { w }, mode);
            }
            let raw = RawFloat {
                sign: r.sign,
                class: Class::Finite,
                exp,
                sig: q as u128,
                sticky,
            };
            return round(fmt, raw, mode);
        }
    }
    recip_generic(fmt, x, mode)
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
