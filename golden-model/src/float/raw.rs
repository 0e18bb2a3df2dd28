//! `RawFloat`: the exact (or exact-with-sticky) result every operator hands
//! to the one shared rounder. Its fields are tabled in `docs/float.md`; the
//! constants below are the numbers in that table, checked by a test.

/// What kind of value a [`RawFloat`] (or an unpacked operand) is.
/// The discriminants are the 2-bit `class` encoding of the RTL.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Class {
    /// ±0 (the sign is in [`RawFloat::sign`]).
    Zero = 0,
    /// A nonzero finite value `(sig + s) · 2^exp`, see [`RawFloat`].
    Finite = 1,
    /// ±infinity.
    Inf = 2,
    /// Not a number (sign, exp, sig, sticky are ignored).
    NaN = 3,
}

/// An unrounded value. For `class == Finite` its magnitude is
///
/// `|v| = (sig + s) · 2^exp`, with `s = 0` if `!sticky`, and `0 < s < 1` if
/// `sticky` (the exact value lies strictly between two consecutive integers
/// times `2^exp`).
///
/// `sig` is an unnormalised integer: its leading one may be at any bit
/// position; the rounder finds it. Two rules bind every producer:
/// * `sticky` ⇒ `sig ≥ 2^(F+1)` (at least F + 2 significant bits, so the
///   round bit of the target format is a real bit of `sig` and `sticky`
///   only ever stands for bits below it);
/// * `sig == 0` ⇒ `!sticky`; such a value rounds to a zero of `sign`.
///
/// For `Zero`, `Inf` and `NaN` only `sign` matters (and not for `NaN`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct RawFloat {
    /// `true` = negative.
    pub sign: bool,
    /// Zero, finite, infinite or NaN.
    pub class: Class,
    /// Weight of bit 0 of `sig`: a two's-complement exponent.
    pub exp: i32,
    /// Integer significand, unnormalised.
    pub sig: u128,
    /// The exact magnitude exceeds `sig · 2^exp` (by less than `2^exp`).
    pub sticky: bool,
}

/// Width in bits of [`RawFloat::sign`].
pub const RAW_SIGN_BITS: u32 = 1;
/// Width in bits of the [`RawFloat::class`] encoding.
pub const RAW_CLASS_BITS: u32 = 2;
/// Width in bits of [`RawFloat::exp`] (signed).
pub const RAW_EXP_BITS: u32 = i32::BITS;
/// Width in bits of [`RawFloat::sig`].
pub const RAW_SIG_BITS: u32 = u128::BITS;
/// Width in bits of [`RawFloat::sticky`].
pub const RAW_STICKY_BITS: u32 = 1;
/// With `sticky` set, `sig` has at least `frac_bits + RAW_STICKY_MIN_EXTRA_BITS`
/// significant bits (F + 2: the F + 1 kept bits and the round bit).
pub const RAW_STICKY_MIN_EXTRA_BITS: u32 = 2;

impl RawFloat {
    /// The canonical NaN-to-be (rounds to the format's canonical NaN).
    pub const NAN: RawFloat = RawFloat::special(false, Class::NaN);

    /// A zero, infinity or NaN of the given sign.
    pub const fn special(sign: bool, class: Class) -> RawFloat {
        RawFloat {
            sign,
            class,
            exp: 0,
            sig: 0,
            sticky: false,
        }
    }

    /// The exact finite value `(-1)^sign · sig · 2^exp` (zero if `sig == 0`).
    pub const fn exact(sign: bool, sig: u128, exp: i32) -> RawFloat {
        RawFloat {
            sign,
            class: if sig == 0 { Class::Zero } else { Class::Finite },
            exp,
            sig,
            sticky: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn class_encoding_fits_its_width() {
        for c in [Class::Zero, Class::Finite, Class::Inf, Class::NaN] {
            assert!((c as u32) < (1 << RAW_CLASS_BITS));
        }
        assert_eq!(RAW_SIG_BITS, 128);
        assert_eq!(RAW_EXP_BITS, 32);
    }
}
