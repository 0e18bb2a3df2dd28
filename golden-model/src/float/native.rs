//! Native fast paths, bit-identical to the generic operators (issue #20).
//!
//! The generic operators (unpack, exact `RawFloat`, the shared rounder) stay
//! the reference; the functions here compute the same bits with hardware
//! floats where that is provably exact, and answer `None` (the caller then
//! takes the generic path) for the operand classes they do not handle.
//! `golden-model/tests/fast_paths.rs` checks them against the generic path.

use super::format::{FloatFormat, RoundingMode};

/// Whether every value of `fmt` is exactly an `f32` (E <= 8, F <= 23): then
/// [`to_f32`] is exact, and so is the `f64` product of two such values
/// (at most 48 significand bits, exponents within `2^-298 .. 2^256`).
#[inline]
pub fn fits_f32(fmt: FloatFormat) -> bool {
    fmt.exp_bits() <= 8 && fmt.frac_bits() <= 23
}

/// The value of `bits` (format `fmt`, [`fits_f32`]) as an `f32`, exactly:
/// signed zeros and infinities kept, any NaN → a NaN. Bits above
/// `fmt.width()` are ignored.
#[inline]
pub fn to_f32(fmt: FloatFormat, bits: u64) -> f32 {
    debug_assert!(fits_f32(fmt));
    if fmt == FloatFormat::BINARY32 {
        return f32::from_bits(bits as u32);
    }
    let f = fmt.frac_bits();
    if fmt.exp_bits() == 8 {
        // binary32's exponent field and bias, a shorter fraction: every
        // pattern (subnormals, infinities and NaNs included) is the binary32
        // pattern with the fraction's low bits zero
        let sign = ((bits & fmt.sign_bit() != 0) as u32) << 31;
        return f32::from_bits(sign | ((bits & fmt.mask() & !fmt.sign_bit()) as u32) << (23 - f));
    }
    let sign = ((bits & fmt.sign_bit() != 0) as u32) << 31;
    let biased = ((bits >> f) & fmt.exp_all_ones()) as u32;
    let frac = (bits & fmt.frac_mask()) as u32;
    if biased == fmt.exp_all_ones() as u32 {
        // infinity or NaN (a nonzero fraction stays nonzero)
        return f32::from_bits(sign | 0xff << 23 | frac << (23 - f));
    }
    if biased != 0 {
        // normal: the same value with binary32's bias (E <= 8, so in range)
        let e = biased as i32 - fmt.bias() + 127;
        return f32::from_bits(sign | (e as u32) << 23 | frac << (23 - f));
    }
    // zero or subnormal: frac · 2^(emin − F), exact in f64 and in f32
    let mag = (frac as f64 * pow2_f64(fmt.emin() - f as i32)) as f32;
    f32::from_bits(sign | mag.to_bits())
}

/// `2^k` for `-1022 <= k <= 1023`.
#[inline]
fn pow2_f64(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// `a + b` (binary32) rounded toward -inf and toward +inf, as the generic
/// `add_down_up` does (a NaN result is some NaN: callers canonicalise).
/// Branch-free.
///
/// The exact sum is `s + e` with `s = fl64(a + b)` and `e` its error (two-sum;
/// no overflow in f64). `t = fl32(s)` (nearest even) is an f64 value too, so
/// when `t != s` the exact sum lies strictly on the same side of `t` as `s`
/// and strictly before the next binary32 value (it is within half an f64
/// spacing of `s`); when `t == s` the sign of `e` says which way. Both at
/// once: the sign of `r = (s − t) + e`. `s − t` is exact (Sterbenz, or `t =
/// 0`); when nonzero it is at least half an f64 spacing of `s`, which bounds
/// `|e|`, with equality only if the exact sum were `t` (then `s = t`): so `r`
/// has the sign of `s − t`, and of `e` when `s = t`. `t = ±∞` from a finite
/// `s` gives `r = ∓∞`.
/// Specials: an infinite or NaN operand makes `s` infinite or NaN and `e`
/// NaN, so no step is taken and both results are `s` (exact). An exact zero
/// sum is -0 down and +0 up, unless both operands are zeros of one sign
/// (f64 sums of f32s round to zero only when exact, and then `s` is +0
/// unless both operands are -0).
#[inline(always)]
pub fn add_down_up_f32(a: f32, b: f32) -> (f32, f32) {
    let (x, y) = (a as f64, b as f64);
    let s = x + y;
    let bv = s - x;
    let e = (x - (s - bv)) + (y - bv);
    let t = s as f32;
    let td = t as f64;
    let r = (s - td) + e;
    let (above, below) = (r < 0.0, r > 0.0);
    let down = step_down(t, above);
    let up = step_up(t, below);
    // exact zero sum that is not (+0) + (+0): -0 down
    let neg_zero = (s == 0.0) & ((a.to_bits() | b.to_bits()) != 0);
    let down = if neg_zero { -0.0 } else { down };
    (down, up)
}

/// `a` if `c`, else `b`, for selections whose condition follows the data:
/// a conditional move, never a branch (a branch there is mispredicted about
/// half the time; without the hint LLVM's x86 back end turns such selects
/// inside loops into branches).
#[inline(always)]
pub fn select_u32(c: bool, a: u32, b: u32) -> u32 {
    std::hint::select_unpredictable(c, a, b)
}

/// [`select_u32`] on `f32` values (their bits: a NaN passes unchanged).
#[inline(always)]
pub fn select_f32(c: bool, a: f32, b: f32) -> f32 {
    f32::from_bits(select_u32(c, a.to_bits(), b.to_bits()))
}

/// `t` one binary32 step toward −∞ if `step`, branch-free: a step away from
/// zero adds 1 to the bits, a step toward zero subtracts 1 (also from +∞,
/// giving the largest finite value; from −0 it gives the smallest negative
/// subnormal). Callers step only a value that lies above the exact one (so
/// never −∞ or a NaN).
#[inline(always)]
fn step_down(t: f32, step: bool) -> f32 {
    let bits = t.to_bits() as i32;
    let away = (bits >> 31) | 1; // +1 for positive t, -1 for negative
    f32::from_bits(bits.wrapping_sub(std::hint::select_unpredictable(step, away, 0)) as u32)
}

/// `t` one binary32 step toward +∞ if `step`, the mirror of [`step_down`]
/// (from −∞ the most negative finite value, from +0 the smallest positive
/// subnormal); `t` lies below the exact value, so it is never +∞, −0 or a NaN.
#[inline(always)]
fn step_up(t: f32, step: bool) -> f32 {
    let bits = t.to_bits() as i32;
    let away = (bits >> 31) | 1;
    f32::from_bits(bits.wrapping_add(std::hint::select_unpredictable(step, away, 0)) as u32)
}

/// [`add_down_up_f32`] on `N` pairs: `(downs, ups)` (a loop the compiler
/// may vectorise).
#[inline(always)]
pub fn add_down_up_f32_n<const N: usize>(a: [f32; N], b: [f32; N]) -> ([f32; N], [f32; N]) {
    let mut down = [0f32; N];
    let mut up = [0f32; N];
    for k in 0..N {
        (down[k], up[k]) = add_down_up_f32(a[k], b[k]);
    }
    (down, up)
}

/// `a + b` (binary32) rounded once in `mode`, as the generic `add` (a NaN
/// result is some NaN).
#[inline(always)]
pub fn add_f32(a: f32, b: f32, mode: RoundingMode) -> f32 {
    match mode {
        // IEEE addition: nearest even, exact zeros +0 unless both -0.
        RoundingMode::NearestEven => a + b,
        RoundingMode::Down => add_down_up_f32(a, b).0,
        RoundingMode::Up => add_down_up_f32(a, b).1,
        RoundingMode::TowardZero => {
            let (d, u) = add_down_up_f32(a, b);
            if d == 0.0 && u == 0.0 {
                // an exact zero: +0 unless both operands are -0 (RTZ rule)
                if a.is_sign_negative() && b.is_sign_negative() && a == 0.0 {
                    -0.0
                } else {
                    0.0
                }
            } else if d >= 0.0 {
                d
            } else {
                u
            }
        }
    }
}

/// `p` rounded once to binary32 in `mode`, where `p` is an exact value
/// (e.g. the `f64` product of two `f32`s): `t = fl32(p)` nearest even is
/// an f64 value, one step toward the rounding direction when it lies on the
/// wrong side of `p`. Infinities and NaN pass; overflow and gradual
/// underflow as IEEE 754 (RUP: -max not -inf, +inf; RDN the mirror; RTZ max).
#[inline(always)]
pub fn round_exact_f64_to_f32(p: f64, mode: RoundingMode) -> f32 {
    let t = p as f32;
    let td = t as f64;
    match mode {
        RoundingMode::NearestEven => t,
        RoundingMode::Up => step_up(t, td < p),
        RoundingMode::Down => step_down(t, td > p),
        RoundingMode::TowardZero => {
            if td.abs() > p.abs() {
                // one step toward zero (keeps the sign; max from an infinity)
                f32::from_bits(t.to_bits() - 1)
            } else {
                t
            }
        }
    }
}

/// `a · b` (binary32) rounded once in `mode`, as the generic `mul` (a NaN
/// result is some NaN). The f64 product of two f32s is exact (48 bits,
/// `2^-298 ..= 2^256`), special cases included (inf · 0 = NaN, signs XOR).
#[inline(always)]
pub fn mul_f32(a: f32, b: f32, mode: RoundingMode) -> f32 {
    round_exact_f64_to_f32(a as f64 * b as f64, mode)
}

/// The bits of a binary32 result, any NaN as the canonical NaN.
#[inline(always)]
pub fn f32_bits(v: f32) -> u64 {
    if v.is_nan() {
        FloatFormat::BINARY32.canonical_nan()
    } else {
        v.to_bits() as u64
    }
}

/// `v` cut to the grid of `to` (E = 8: binary32's exponent field and bias)
/// when `v` is a normal value of that exponent range (`2^-126 <= |v| <
/// 2^128`), in integer operations on the `f64` bits: `(sign, magnitude bits
/// of the truncated value, whether bits were cut)`. The directed results
/// are the magnitude or the next one (a carry into an all-ones exponent
/// field is the infinity, the directed overflow result). `None` for zeros,
/// values below the normal range (where the grid changes), above it, and
/// for infinities and NaN.
#[inline(always)]
fn truncate_normal_f64(to: FloatFormat, v: f64) -> Option<(bool, u64, bool)> {
    debug_assert_eq!(to.exp_bits(), 8);
    let bits = v.to_bits();
    // binary32's biased exponent of v
    let biased = ((bits >> 52) & 0x7ff) as i64 - (1023 - 127);
    if !(1..=254).contains(&biased) {
        return None;
    }
    let cut = 52 - to.frac_bits();
    let field = (biased as u64) << 52 | (bits & ((1 << 52) - 1));
    Some((bits >> 63 != 0, field >> cut, field & ((1 << cut) - 1) != 0))
}

/// Whether [`round_exact_f64_to`] handles `to` in `mode`: binary32 in every
/// mode; other formats with E = 8 (a binary32 subgrid) in directed modes.
#[inline(always)]
pub fn rounds_natively(to: FloatFormat, mode: RoundingMode) -> bool {
    to == FloatFormat::BINARY32
        || (to.exp_bits() == 8 && to.frac_bits() < 23 && mode != RoundingMode::NearestEven)
}

/// The exact value `v` rounded once to `to` in `mode`, as bits, when
/// [`rounds_natively`]: first to binary32 ([`round_exact_f64_to_f32`]);
/// for a narrower fraction then to `to`'s grid in the same direction (a
/// subset of binary32's with the same exponent range, so two directed
/// roundings the same way are one; a carry may reach the infinity, which is
/// the directed overflow result).
#[inline(always)]
pub fn round_exact_f64_to(to: FloatFormat, v: f64, mode: RoundingMode) -> u64 {
    debug_assert!(rounds_natively(to, mode));
    if mode != RoundingMode::NearestEven {
        if let Some((neg, mag, inexact)) = truncate_normal_f64(to, v) {
            let away = inexact
                & match mode {
                    RoundingMode::Up => !neg,
                    RoundingMode::Down => neg,
                    _ => false,
                };
            return to.with_sign(neg, mag + away as u64);
        }
    }
    let t = round_exact_f64_to_f32(v, mode);
    if to == FloatFormat::BINARY32 {
        return f32_bits(t);
    }
    if t.is_nan() {
        return to.canonical_nan();
    }
    let sh = 23 - to.frac_bits();
    let bits = t.to_bits();
    let neg = bits >> 31 != 0;
    let mag = bits & 0x7fff_ffff;
    let low = mag & ((1 << sh) - 1);
    let away = low != 0
        && match mode {
            RoundingMode::Up => !neg,
            RoundingMode::Down => neg,
            _ => false,
        };
    let mag = (mag - low) + ((away as u32) << sh);
    to.with_sign(neg, (mag >> sh) as u64)
}

/// `v` rounded to `to` both toward −∞ and toward +∞, as bits, when
/// [`rounds_natively`] in the directed modes: the upward result is the
/// downward one, or the next value of `to` above it when `v` is not a value
/// of `to` (one rounding instead of two; an overflowing `v` gives the
/// largest finite value down and the infinity up, as the step from it).
#[inline(always)]
pub fn round_exact_f64_down_up(to: FloatFormat, v: f64) -> (u64, u64) {
    if let Some((neg, mag, inexact)) = truncate_normal_f64(to, v) {
        let down = to.with_sign(neg, mag + (neg & inexact) as u64);
        let up = to.with_sign(neg, mag + (!neg & inexact) as u64);
        return (down, up);
    }
    let down = round_exact_f64_to(to, v, RoundingMode::Down);
    // a NaN is not stepped (no value equals it)
    let inexact = (to_f32(to, down) as f64 != v) & !v.is_nan();
    // one step toward +inf: away from zero for a positive `down`, toward zero
    // for a negative one (never -0: that is only the exact result of -0)
    let step = if down & to.sign_bit() == 0 {
        1
    } else {
        u64::MAX
    };
    (down, down.wrapping_add(step * inexact as u64) & to.mask())
}
