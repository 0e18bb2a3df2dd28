//! A lower bound of a three-term dot product of mixed formats, rounded down
//! once: the cull-plane ray unit's `n·(o − r)` and `n·d` (docs/cull.md §3.2).
//!
//! Cheaper than the correctly rounded [`super::dot3`]: no sort, no
//! normalisation before the sum, one rounder. The products are exact; the
//! window's lowest bit is the lowest bit of the product whose lowest bit
//! weighs most, every other product is truncated toward −∞ at that bit, the
//! truncated products are summed exactly and the sum is rounded down. Every
//! step can only lower the value, so the result never exceeds the exact dot
//! product.

use super::format::{FloatFormat, RoundingMode};
use super::native::{round_exact_f64_to, rounds_natively};
use super::raw::{Class, RawFloat};
use super::round::round;
use super::unpack::unpack;

/// `z ≤ a0·b0 + a1·b1 + a2·b2` for `a_i` in `fa`, `b_i` in `fb`, `z` in `to`:
///
/// 1. a NaN operand gives the canonical NaN; operands stand for reals, an
///    infinity for an unbounded one, so a product with a zero factor is 0
///    (also `0 · ∞`), any other product with an infinite factor is ±∞ by the
///    signs, and the result is that infinity (both signs: NaN);
/// 2. each product exactly, `p_i = ±M_i · 2^(e_i)` with `M_i` the product of
///    the significands (hidden bit included, `(Fa + 1) + (Fb + 1)` bits) and
///    `e_i` the sum of the operands' lsb exponents (`max(biased, 1) − bias − F`);
/// 3. `L` = the largest `e_i` of the nonzero products (none: the result is +0);
/// 4. `S = Σ floor(p_i / 2^L)` exactly (the product at `L` is exact, the
///    others lose the bits below `2^L`, rounded toward −∞);
/// 5. `z = RDN(S · 2^L)` in `to`; `S = 0` gives +0.
///
/// Both fraction widths must be at most 52 (the sum fits an `i128`).
///
/// When `Fa + Fb <= 58` and no operand is NaN or infinite, steps 2 to 4 run
/// in `u64` / `i64` without allocation ([`dot3_floor_narrow`]) and step 5 is
/// the same rounder on the same value; otherwise [`dot3_floor_generic`].
#[inline]
pub fn dot3_floor(
    fa: FloatFormat,
    fb: FloatFormat,
    to: FloatFormat,
    a: [u64; 3],
    b: [u64; 3],
) -> u64 {
    const B16: FloatFormat = FloatFormat::BINARY16;
    const B32: FloatFormat = FloatFormat::BINARY32;
    let narrow = if (fa, fb) == (B16, B32) {
        // the renderer's planes and rays: the same code with constant formats
        dot3_floor_narrow(B16, B32, to, a, b)
    } else if fa.frac_bits() + fb.frac_bits() <= 58 {
        dot3_floor_narrow(fa, fb, to, a, b)
    } else {
        None
    };
    narrow.unwrap_or_else(|| dot3_floor_generic(fa, fb, to, a, b))
}

/// [`dot3_floor`] for `Fa + Fb <= 58` and finite operands (`None` if an
/// operand is NaN or infinite): steps 2 to 5 on [`Operand`]s.
#[inline(always)]
fn dot3_floor_narrow(
    fa: FloatFormat,
    fb: FloatFormat,
    to: FloatFormat,
    a: [u64; 3],
    b: [u64; 3],
) -> Option<u64> {
    let mut x = [Operand::default(); 3];
    let mut y = [Operand::default(); 3];
    for i in 0..3 {
        x[i] = Operand::of(fa, a[i])?;
        y[i] = Operand::of(fb, b[i])?;
    }
    Some(dot3_floor_operands(to, &x, &y))
}

/// A finite operand of [`dot3_floor`] as its step 2 reads it: the value
/// `sig · 2^lsb`, `sig` the signed significand with its hidden bit and `lsb`
/// the operand's lsb exponent (`max(biased, 1) − bias − F`); a zero has
/// `lsb = ZERO_LSB`, far below every real one, so that products with a zero
/// factor drop out of step 3 without a test. Callers that reuse an operand
/// in several dot products decode it once.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Operand {
    pub sig: i64,
    pub lsb: i32,
}

/// The lsb exponent of a zero [`Operand`]: a sum with it stays below
/// `ZERO_LSB / 2`, every real lsb exponent (at least −2 · 1074 − 52) above.
const ZERO_LSB: i32 = -(1 << 29);

impl Operand {
    /// `v` in `f` decoded; `None` for an infinity or NaN.
    #[inline(always)]
    pub fn of(f: FloatFormat, v: u64) -> Option<Operand> {
        let frac_bits = f.frac_bits();
        let biased = (v >> frac_bits) & f.exp_all_ones();
        if biased == f.exp_all_ones() {
            return None;
        }
        let frac = v & f.frac_mask();
        let sig = if biased == 0 {
            frac
        } else {
            frac | 1 << frac_bits
        } as i64;
        let lsb = biased.max(1) as i32 - f.bias() - frac_bits as i32;
        Some(Operand {
            sig: if v & f.sign_bit() != 0 { -sig } else { sig },
            lsb: if sig == 0 { ZERO_LSB } else { lsb },
        })
    }
}

/// Steps 2 to 5 of [`dot3_floor`] on decoded finite operands whose
/// significand products are below `2^60` (`Fa + Fb <= 58`): each floored
/// term is below `2^60` in magnitude, so `S` fits an `i64`.
#[inline(always)]
pub(crate) fn dot3_floor_operands(to: FloatFormat, a: &[Operand; 3], b: &[Operand; 3]) -> u64 {
    // (array literals, not `map`: this must inline into the callers' loops)
    let m = [
        a[0].sig * b[0].sig,
        a[1].sig * b[1].sig,
        a[2].sig * b[2].sig,
    ];
    let e = [
        a[0].lsb + b[0].lsb,
        a[1].lsb + b[1].lsb,
        a[2].lsb + b[2].lsb,
    ];
    let lsb = e[0].max(e[1]).max(e[2]);
    if lsb < ZERO_LSB / 2 {
        // every product has a zero factor
        return to.zero(false);
    }
    let mut sum = 0i64;
    for i in 0..3 {
        // an arithmetic shift is the floor; |m| < 2^60, so 63 places leave 0
        // or −1 (a zero product, far below L, stays 0)
        sum += m[i] >> (lsb - e[i]).min(63) as u32;
    }
    if rounds_natively(to, RoundingMode::Down)
        && sum.unsigned_abs() <= 1 << 53
        && (-1022..=960).contains(&lsb)
    {
        // S and 2^L are f64 values and so is their product (|S·2^L| < 2^1014,
        // a multiple of 2^-1022): round the exact value natively.
        let v = sum as f64 * f64::from_bits(((lsb + 1023) as u64) << 52);
        return round_exact_f64_to(to, v, RoundingMode::Down);
    }
    let raw = RawFloat::exact(sum < 0, sum.unsigned_abs() as u128, lsb);
    round(to, raw, RoundingMode::Down)
}

/// The reference [`dot3_floor`], for every format and operand.
pub fn dot3_floor_generic(
    fa: FloatFormat,
    fb: FloatFormat,
    to: FloatFormat,
    a: [u64; 3],
    b: [u64; 3],
) -> u64 {
    assert!(
        fa.frac_bits() <= 52 && fb.frac_bits() <= 52,
        "dot3_floor: fraction widths up to 52"
    );
    let x = a.map(|v| unpack(fa, v));
    let y = b.map(|v| unpack(fb, v));
    if x.iter().chain(&y).any(|r| r.class == Class::NaN) {
        return to.canonical_nan();
    }
    // operands stand for reals, ∞ for an unbounded one: a zero factor gives 0
    let is_zero = |r: &RawFloat| r.class == Class::Zero || (r.class == Class::Finite && r.sig == 0);
    let inf_sign = |i: usize| {
        let inf = x[i].class == Class::Inf || y[i].class == Class::Inf;
        (inf && !is_zero(&x[i]) && !is_zero(&y[i])).then_some(x[i].sign != y[i].sign)
    };
    let pos_inf = (0..3).any(|i| inf_sign(i) == Some(false));
    let neg_inf = (0..3).any(|i| inf_sign(i) == Some(true));
    match (pos_inf, neg_inf) {
        (true, true) => return to.canonical_nan(),
        (true, false) => return to.inf(false),
        (false, true) => return to.inf(true),
        (false, false) => {}
    }
    let terms: Vec<(bool, u128, i32)> = (0..3)
        .map(|i| {
            (
                x[i].sign != y[i].sign,
                x[i].sig * y[i].sig,
                x[i].exp + y[i].exp,
            )
        })
        .filter(|&(_, m, _)| m != 0)
        .collect();
    let Some(lsb) = terms.iter().map(|&(_, _, e)| e).max() else {
        return to.zero(false);
    };
    let sum: i128 = terms
        .iter()
        .map(|&(neg, m, e)| {
            let v = if neg { -(m as i128) } else { m as i128 };
            // an arithmetic shift is the floor; |v| < 2^106, so 127 places leave 0 or −1
            v >> (lsb - e).min(127) as u32
        })
        .sum();
    let raw = RawFloat::exact(sum < 0, sum.unsigned_abs(), lsb);
    round(to, raw, RoundingMode::Down)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::float::{add, mul};

    const RDN: RoundingMode = RoundingMode::Down;

    fn f(e: u32, m: u32) -> FloatFormat {
        FloatFormat::new(e, m).unwrap()
    }

    #[test]
    fn exact_sums_are_exact_and_bounds_are_below() {
        let b32 = FloatFormat::BINARY32;
        let h = FloatFormat::BINARY16;
        let one_h = 0x3c00;
        let bits = |v: f32| v.to_bits() as u64;
        // 1·1.5 + 1·2.25 + 0·7 = 3.75 exactly
        let z = dot3_floor(
            h,
            b32,
            b32,
            [one_h, one_h, 0],
            [bits(1.5), bits(2.25), bits(7.0)],
        );
        assert_eq!(f32::from_bits(z as u32), 3.75);
        // 1 − 2^-60: the small term is truncated toward −∞ at 2^-33 (the
        // lsb of the 11 × 24-bit product of 1), then rounded down: 1 − 2^-24
        let z = dot3_floor(
            h,
            b32,
            b32,
            [one_h, 0xbc00, 0],
            [bits(1.0), bits(2f32.powi(-60)), 0],
        );
        assert_eq!(f32::from_bits(z as u32), 1.0 - 2f32.powi(-24));
        // all products zero: +0
        assert_eq!(
            dot3_floor(h, b32, b32, [0, 0x8000, one_h], [bits(3.0), bits(1.0), 0]),
            0
        );
        // specials: ±∞ by the signs, 0·∞ = 0, both infinities or a NaN: NaN
        let inf = b32.inf(false);
        let z = |a, b| dot3_floor(h, b32, b32, a, b);
        assert_eq!(z([0xbc00, 0, 0], [inf, 0, 0]), b32.inf(true));
        assert_eq!(z([0x8000, one_h, 0], [inf, bits(2.0), 0]), bits(2.0));
        assert_eq!(z([one_h, 0xbc00, 0], [inf, inf, 0]), b32.canonical_nan());
        assert_eq!(z([one_h, 0x7e00, 0], [0, 0, 0]), b32.canonical_nan());
    }

    /// Never above the exact value, never below the two-rounding chain of
    /// the previous design by more than the chain's own error allows: on
    /// small formats, against the rounded-down chain (products and sums
    /// rounded down), which is itself a lower bound; here the exact value is
    /// compared through an f64 (exact for these widths).
    #[test]
    fn lower_bound_of_the_exact_dot_product() {
        let (fa, fb) = (f(3, 2), f(4, 3));
        let to = f(4, 3);
        let val = |fmt: FloatFormat, v: u64| {
            let r = unpack(fmt, v);
            let m = r.sig as f64 * 2f64.powi(r.exp);
            if r.sign {
                -m
            } else {
                m
            }
        };
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut tighter = 0;
        for _ in 0..200_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let a = [0, 1, 2].map(|i| (s >> (6 * i)) & fa.mask());
            let b = [0, 1, 2].map(|i| (s >> (18 + 8 * i)) & fb.mask());
            let z = dot3_floor(fa, fb, to, a, b);
            let finite =
                |fmt: FloatFormat, v: u64| !matches!(unpack(fmt, v).class, Class::NaN | Class::Inf);
            if !(a.iter().all(|&v| finite(fa, v)) && b.iter().all(|&v| finite(fb, v))) {
                continue;
            }
            let exact: f64 = (0..3).map(|i| val(fa, a[i]) * val(fb, b[i])).sum();
            let zv = match unpack(to, z).class {
                Class::Inf => f64::NEG_INFINITY,
                _ => val(to, z),
            };
            assert!(zv <= exact, "{a:?} {b:?}: {zv} > {exact}");
            // the chain of the previous design, every step rounded down
            let wide = f(4, 5);
            let w = |fmt: FloatFormat, v: u64| crate::float::convert(fmt, wide, v, RDN);
            let p = [0, 1, 2].map(|i| mul(wide, w(fa, a[i]), w(fb, b[i]), RDN));
            let chain = add(wide, add(wide, p[0], p[1], RDN), p[2], RDN);
            let chain = crate::float::convert(wide, to, chain, RDN);
            let cv = match unpack(to, chain).class {
                Class::Inf => f64::NEG_INFINITY,
                Class::NaN => continue,
                _ => val(to, chain),
            };
            tighter += (zv > cv) as u32;
        }
        assert!(
            tighter > 0,
            "the fused bound is sometimes tighter than the chain"
        );
    }
}
