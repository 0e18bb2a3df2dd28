//! Bit-level helpers of the float operators, composed from the DSL's
//! primitives: leading-zero count, right shift with sticky (jamming),
//! signed resizing and small arithmetic conveniences.

use crate::arith::int::{sext, zext};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Ty;

/// Width of the count [`lzc`] returns for a `w`-bit operand: enough for 0..=w.
pub fn lzc_width(w: u32) -> u32 {
    (w + 1).next_power_of_two().trailing_zeros()
}

/// Number of leading zeros of `x` (`w` bits, unsigned), `w` when `x` is zero;
/// UInt of [`lzc_width`]`(w)` bits.
///
/// `x` is padded on the right with a one and zeros to a power of two P >= w + 1
/// (so the count of an all-zero `x` is `w`), then counted by a balanced tree:
/// each node of two halves returns `(all_zero, count)`, the count being
/// `{0, count_hi}` when the high half has a one and `{1, count_lo}` otherwise.
#[track_caller]
pub fn lzc(m: &mut ModuleBuilder, x: Sig) -> Sig {
    let x = m.as_uint(x);
    let w = x.width();
    let p = (w + 1).next_power_of_two();
    let pad = p - w;
    let mut parts = vec![x, m.uint(1, 1)];
    if pad > 1 {
        parts.push(m.uint(pad - 1, 0));
    }
    let padded = m.cat(&parts);
    let (_, count) = m.scope("lzc", |m| lzc_tree(m, padded, "top"));
    m.name(count, "lzc")
}

/// `(all_zero, count)` of a power-of-two-wide value; `at` names the node
/// by its path from the top (`top_hi_lo`).
#[track_caller]
fn lzc_tree(m: &mut ModuleBuilder, x: Sig, at: &str) -> (Sig, Sig) {
    let w = x.width();
    if w == 2 {
        let hi = m.bit_at(x, 1);
        let any = m.any_set(x);
        let zero = m.not(any);
        let count = m.not(hi);
        let count = m.as_uint(count);
        return (
            m.name(zero, &format!("{at}_zero")),
            m.name(count, &format!("{at}_count")),
        );
    }
    let half = w / 2;
    let hi = m.slice(x, w - 1, half);
    let lo = m.slice(x, half - 1, 0);
    let (zh, ch) = lzc_tree(m, hi, &format!("{at}_hi"));
    let (zl, cl) = lzc_tree(m, lo, &format!("{at}_lo"));
    let zero = m.and(zh, zl);
    let zero_bit = m.uint(1, 0);
    let one_bit = m.uint(1, 1);
    let when_hi = m.cat(&[zero_bit, ch]);
    let when_lo = m.cat(&[one_bit, cl]);
    let count = m.mux(zh, when_lo, when_hi);
    (
        m.name(zero, &format!("{at}_zero")),
        m.name(count, &format!("{at}_count")),
    )
}

/// `x >> amount` (logical, width of `x`) with every bit shifted out ORed into
/// the result's least significant bit ("jamming": [`shr_sticky`]'s sticky bit).
/// `amount` is any UInt; an amount of `width(x)` or more leaves only the
/// sticky bit.
#[track_caller]
pub fn shr_jam(m: &mut ModuleBuilder, x: Sig, amount: Sig) -> Sig {
    let (shifted, sticky) = shr_sticky(m, x, amount);
    let sticky = m.as_uint(sticky);
    let sticky = zext(m, sticky, shifted.width());
    let r = m.or(shifted, sticky);
    m.name(r, "jam")
}

/// `x >> amount` (logical, width of `x`) and, separately, whether any bit was shifted out.
#[track_caller]
pub fn shr_sticky(m: &mut ModuleBuilder, x: Sig, amount: Sig) -> (Sig, Sig) {
    let x = m.as_uint(x);
    let w = x.width();
    let shifted = m.shr(x, amount);
    let ones = m.uint(w, crate::eval::mask(u128::MAX, w));
    let kept_mask = m.shl(ones, amount);
    let lost_mask = m.not(kept_mask);
    let lost = m.and(x, lost_mask);
    let sticky = m.any_set(lost);
    (shifted, sticky)
}

/// Number of trailing zeros of `x` (`w` bits, unsigned), `w` when `x` is zero;
/// UInt of [`lzc_width`]`(w)` bits: [`lzc`] of the bits in reverse order.
#[track_caller]
pub fn tzc(m: &mut ModuleBuilder, x: Sig) -> Sig {
    let x = m.as_uint(x);
    let bits: Vec<Sig> = (0..x.width()).map(|i| m.slice(x, i, i)).collect();
    let reversed = m.cat(&bits);
    lzc(m, reversed)
}

/// [`shr_jam`] with the sticky bit from the trailing zeros of `x` (a bit is
/// shifted out iff `x ≠ 0` and `tzc(x) < amount`): a count and a comparison
/// instead of a mask as wide as `x` shifted by `amount`.
#[track_caller]
pub fn shr_jam_tz(m: &mut ModuleBuilder, x: Sig, amount: Sig) -> Sig {
    let x = m.as_uint(x);
    let w = x.width();
    let shifted = m.shr(x, amount);
    let tz = tzc(m, x);
    let cw = tz.width().max(amount.width());
    let tz = zext(m, tz, cw);
    let amount_w = zext(m, amount, cw);
    let below = m.lt(tz, amount_w);
    let nonzero = m.any_set(x);
    let sticky = m.and(below, nonzero);
    let sticky = m.name(sticky, "shifted_out");
    let sticky = m.as_uint(sticky);
    let sticky = zext(m, sticky, w);
    let r = m.or(shifted, sticky);
    m.name(r, "jam")
}

/// `a` (UInt or SInt) as an SInt of `w` bits (zero- or sign-extended; `w` must hold it).
#[track_caller]
pub fn to_sint(m: &mut ModuleBuilder, a: Sig, w: u32) -> Sig {
    match a.ty() {
        Ty::SInt(_) => sext(m, a, w),
        _ => {
            let z = zext(m, a, w);
            m.as_sint(z)
        }
    }
}

/// A signed constant of `w` bits.
#[track_caller]
pub fn sconst(m: &mut ModuleBuilder, w: u32, v: i64) -> Sig {
    m.sint(w, v as i128)
}

/// `a - b` for SInt operands, resized (sign-extended or cut) to `w` bits; the caller
/// guarantees the difference fits.
#[track_caller]
pub fn ssub(m: &mut ModuleBuilder, a: Sig, b: Sig, w: u32) -> Sig {
    let d = m.sub(a, b);
    sext(m, d, w)
}

/// `a + b` for SInt operands, resized to `w` bits; the caller guarantees the sum fits.
#[track_caller]
pub fn sadd(m: &mut ModuleBuilder, a: Sig, b: Sig, w: u32) -> Sig {
    let s = m.add(a, b);
    sext(m, s, w)
}

/// `|a|` of an SInt as a UInt of `w <= width(a)` bits (the caller guarantees
/// the magnitude fits; the most negative value does not occur).
#[track_caller]
pub fn abs(m: &mut ModuleBuilder, a: Sig, w: u32) -> Sig {
    let aw = a.width();
    let neg = m.msb(a);
    let zero = m.sint(aw, 0);
    let negated = m.sub(zero, a);
    let negated = sext(m, negated, aw);
    let r = m.mux(neg, negated, a);
    if w < aw {
        m.slice(r, w - 1, 0)
    } else {
        m.as_uint(r)
    }
}

/// A Bool as a one-bit UInt.
#[track_caller]
pub fn bit(m: &mut ModuleBuilder, b: Sig) -> Sig {
    m.as_uint(b)
}

/// `a + k` (a UInt or SInt, k a constant) as an SInt of `w` bits; the caller
/// guarantees the result fits `w` bits (intermediate widths are chosen here).
#[track_caller]
pub fn add_const(m: &mut ModuleBuilder, a: Sig, k: i64, w: u32) -> Sig {
    let aw = a.width() + 1;
    let kw = super::sint_width(k, k);
    let iw = aw.max(kw).max(w) + 1;
    let a = to_sint(m, a, iw);
    let k = m.sint(iw, k as i128);
    let s = m.add(a, k);
    sext(m, s, w)
}
