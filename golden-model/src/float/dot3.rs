//! Fused three-term dot product `a0·b0 + a1·b1 + a2·b2`, exact, then rounded
//! once. The exact sum is formed in a fixed-point accumulator wide enough for
//! any sum of three products of the format.

use super::format::{FloatFormat, RoundingMode};
use super::mul::product_of;
use super::raw::{Class, RawFloat};
use super::round::{exact_zero_sum_sign, round};
use super::unpack::unpack;

/// `a[0]·b[0] + a[1]·b[1] + a[2]·b[2]`, exact, rounded once in `mode`.
///
/// Specials: any NaN operand → NaN; any inf · 0 → NaN; products of both
/// +inf and -inf → NaN; otherwise an infinite product gives that infinity.
/// An exact zero sum is the zero of sign s if all three products are zeros of
/// sign s (the sign of a zero product is the XOR of its factors' signs),
/// otherwise +0, or -0 in RDN — what `((p0 + p1) + p2)` gives in IEEE
/// arithmetic with exact additions.
pub fn dot3(fmt: FloatFormat, a: [u64; 3], b: [u64; 3], mode: RoundingMode) -> u64 {
    round(fmt, dot3_raw(fmt, a, b, mode), mode)
}

fn dot3_raw(fmt: FloatFormat, a: [u64; 3], b: [u64; 3], mode: RoundingMode) -> RawFloat {
    let p = [0, 1, 2].map(|i| product_of(unpack(fmt, a[i]), unpack(fmt, b[i])));
    if p.iter().any(|t| t.class == Class::NaN) {
        return RawFloat::NAN;
    }
    let pos_inf = p.iter().any(|t| t.class == Class::Inf && !t.sign);
    let neg_inf = p.iter().any(|t| t.class == Class::Inf && t.sign);
    match (pos_inf, neg_inf) {
        (true, true) => return RawFloat::NAN,
        (true, false) => return RawFloat::special(false, Class::Inf),
        (false, true) => return RawFloat::special(true, Class::Inf),
        (false, false) => {}
    }

    let mut acc = Accumulator::new(fmt);
    for t in p.iter().filter(|t| t.class == Class::Finite) {
        acc.add(t);
    }
    let sum = acc.into_raw();
    if sum.class == Class::Zero {
        let all_zero = p.iter().all(|t| t.class == Class::Zero);
        let same_sign = p.iter().all(|t| t.sign == p[0].sign);
        let sign = exact_zero_sum_sign((all_zero && same_sign).then_some(p[0].sign), mode);
        return RawFloat::special(sign, Class::Zero);
    }
    sum
}

/// Words of the accumulator for binary64, the widest one.
const ACC_MAX_WORDS: usize = dot3_accumulator_bits(FloatFormat::BINARY64).div_ceil(64) as usize;

/// Width of the exact two's-complement accumulator that `dot3` uses for
/// `fmt`, `4·bias + 2F + 3` bits with bit 0 of weight `2^(2·(emin - F))`:
/// every product is a multiple of `2^(2·(emin - F))` (the square of the
/// smallest subnormal) and below `2^(2·(emax + 1))`, i.e. below
/// `2^(4·bias + 2F)` units; a sum of three needs 2 more bits, and the sign
/// one more. (binary32: 557 bits; binary64: 4199 bits.)
pub const fn dot3_accumulator_bits(fmt: FloatFormat) -> u32 {
    4 * fmt.bias() as u32 + 2 * fmt.frac_bits() + 3
}

/// An exact two's-complement fixed-point number: `words` (little-endian,
/// `n` of them used) times `2^lsb_exp`.
struct Accumulator {
    words: [u64; ACC_MAX_WORDS],
    n: usize,
    lsb_exp: i32,
}

impl Accumulator {
    fn new(fmt: FloatFormat) -> Accumulator {
        Accumulator {
            words: [0; ACC_MAX_WORDS],
            n: dot3_accumulator_bits(fmt).div_ceil(64) as usize,
            lsb_exp: 2 * (fmt.emin() - fmt.frac_bits() as i32),
        }
    }

    /// Adds the exact finite product `t` (significand below 2^106).
    #[inline]
    fn add(&mut self, t: &RawFloat) {
        let pos = (t.exp - self.lsb_exp) as u32;
        let (first, bit) = ((pos / 64) as usize, pos % 64);
        // t.sig << bit, as three words (t.sig has at most 106 bits).
        let low = t.sig << bit;
        let high = if bit == 0 {
            0
        } else {
            (t.sig >> (128 - bit)) as u64
        };
        let parts = [low as u64, (low >> 64) as u64, high];
        let mut carry = false;
        for i in first..self.n {
            let k = i - first;
            let part = if k < 3 { parts[k] } else { 0 };
            if k >= 3 && !carry {
                break;
            }
            let w = &mut self.words[i];
            if t.sign {
                let (d1, b1) = w.overflowing_sub(part);
                let (d2, b2) = d1.overflowing_sub(carry as u64);
                *w = d2;
                carry = b1 || b2;
            } else {
                let (s1, c1) = w.overflowing_add(part);
                let (s2, c2) = s1.overflowing_add(carry as u64);
                *w = s2;
                carry = c1 || c2;
            }
        }
    }

    /// The accumulated value as a [`RawFloat`]: its top 128 bits as `sig`
    /// and any lower set bit as `sticky` (so `sig >= 2^127` when sticky).
    fn into_raw(mut self) -> RawFloat {
        let n = self.n;
        let negative = self.words[n - 1] >> 63 == 1;
        if negative {
            let mut carry = true;
            for w in &mut self.words[..n] {
                let (s, c) = (!*w).overflowing_add(carry as u64);
                *w = s;
                carry = c;
            }
        }
        let Some(top) = (0..n).rev().find(|&i| self.words[i] != 0) else {
            return RawFloat::special(false, Class::Zero);
        };
        let lead = 64 * top as u32 + 63 - self.words[top].leading_zeros();
        let word = |i: usize| if i < n { self.words[i] as u128 } else { 0 };
        let s = lead.saturating_sub(127);
        let (w, b) = ((s / 64) as usize, s % 64);
        let pair = word(w) | (word(w + 1) << 64);
        let sig = if b == 0 {
            pair
        } else {
            (pair >> b) | (word(w + 2) << (128 - b))
        };
        let sticky =
            self.words[..w].iter().any(|&x| x != 0) || (self.words[w] & ((1u64 << b) - 1)) != 0;
        RawFloat {
            sign: negative,
            class: Class::Finite,
            exp: self.lsb_exp + s as i32,
            sig,
            sticky,
        }
    }
}
