//! The aligned two-term sum shared by the fused operators (`fma`, `dot3`):
//! two signed terms, each an integer significand whose top bit has a known
//! weight, are placed in a fixed window under the larger weight (the
//! anchor) and added or subtracted; bits of the other term that fall below
//! the window are jammed into its least significant bit.
//!
//! Why jamming is exact enough: the caller chooses the window so that a term
//! loses bits only when its leading one is at least three places below the
//! anchor term's, so the sum keeps its leading one within two places of the
//! anchor, and its rounding (guard) position stays at least two places above
//! the window's bit 0. A jammed result is an odd multiple of that bit's
//! weight `u` and lies in the same open interval `(k·2u, (k+1)·2u)` as the
//! exact sum; every rounding boundary is a multiple of `2u`, so both round
//! alike in every mode. Jamming a sum that already carries a jammed bit (a
//! later step of `dot3`) keeps the property, since the intervals nest.

use super::bits::{abs, add_const, shr_jam, to_sint};
use super::round::Raw;
use super::sint_width;
use crate::arith::int::zext;
use crate::builder::{ModuleBuilder, Sig};

/// One signed term: `(-1)^sign · sig · 2^(top - width(sig) + 1)`.
#[derive(Debug, Clone, Copy)]
pub struct Term {
    /// Bool
    pub sign: Sig,
    /// UInt significand (may have leading zeros)
    pub sig: Sig,
    /// SInt: weight exponent of the top bit of `sig`
    pub top: Sig,
}

/// A sum in a window: `(-1)^sign · sig · 2^(top - width(sig) + 1)`.
#[derive(Debug, Clone, Copy)]
pub struct Sum {
    /// Bool: sign of the result (of the first term when the sum is zero)
    pub sign: Sig,
    /// UInt(window) magnitude, possibly with a jammed lsb
    pub sig: Sig,
    /// SInt: weight exponent of the window's top bit (the carry position)
    pub top: Sig,
    /// Bool: the terms have opposite signs
    pub eff_sub: Sig,
}

impl Sum {
    /// The sum as the rounder's raw value, with the `sign` and `class` the
    /// caller settles (the fused operators sign zero and infinite results
    /// differently). Bit 0 of the window weighs `top - (window - 1)`; no
    /// sticky bit, since what fell below the window is jammed into it.
    /// `exp_width` as given to [`sum_two`].
    #[track_caller]
    pub fn to_raw(&self, m: &mut ModuleBuilder, sign: Sig, class: Sig, exp_width: u32) -> Raw {
        let window = self.sig.width();
        let exp = add_const(m, self.top, -(window as i64 - 1), exp_width + 1);
        let sticky = m.bool(false);
        Raw {
            sign,
            class,
            exp,
            sig: self.sig,
            sticky,
        }
    }
}

/// Adds `x` and `y` in a `window`-bit field whose top bit is a carry bit and
/// whose next bit has the weight of the larger `top`: each term is placed
/// with its top bit there (`window >= width + 1` for both), the other shifted
/// right by the difference and jammed. `exp_width` is the width of the
/// exponents (both `top`s are resized to it); `cut` pipeline registers go
/// between the alignment and the addition.
#[track_caller]
pub fn sum_two(
    m: &mut ModuleBuilder,
    x: Term,
    y: Term,
    window: u32,
    exp_width: u32,
    cut: u32,
) -> Sum {
    assert!(window > x.sig.width() && window > y.sig.width());
    let xt = to_sint(m, x.top, exp_width);
    let yt = to_sint(m, y.top, exp_width);
    let x_big = m.ge(xt, yt);
    let x_big = m.name(x_big, "x_big");
    let anchor = m.mux(x_big, xt, yt);
    let anchor = m.name(anchor, "anchor");
    let dx = m.sub(anchor, xt);
    let dx = m.as_uint(dx);
    let dx = m.name(dx, "x_shift");
    let dy = m.sub(anchor, yt);
    let dy = m.as_uint(dy);
    let dy = m.name(dy, "y_shift");
    let place = |m: &mut ModuleBuilder, s: Sig| {
        let low = window - 1 - s.width();
        let hi = m.uint(1, 0);
        if low == 0 {
            m.cat(&[hi, s])
        } else {
            let lo = m.uint(low, 0);
            m.cat(&[hi, s, lo])
        }
    };
    let xa = m.scope("x", |m| {
        let xe = place(m, x.sig);
        let xe = m.name(xe, "placed");
        let xa = shr_jam(m, xe, dx);
        m.name(xa, "aligned")
    });
    let ya = m.scope("y", |m| {
        let ye = place(m, y.sig);
        let ye = m.name(ye, "placed");
        let ya = shr_jam(m, ye, dy);
        m.name(ya, "aligned")
    });
    let eff_sub = m.xor(x.sign, y.sign);
    let eff_sub = m.name(eff_sub, "eff_sub");
    let top = add_const(
        m,
        anchor,
        1,
        sint_width(-(1i64 << (exp_width - 1)), 1i64 << (exp_width - 1)),
    );
    for _ in 0..cut {
        m.stage();
    }
    let s_add = m.add(xa, ya);
    let s_add = zext(m, s_add, window);
    let s_add = m.name(s_add, "added");
    let diff = m.sub(xa, ya);
    let diff = m.name(diff, "diff");
    let neg = m.msb(diff);
    let mag = abs(m, diff, window);
    let mag = m.name(mag, "diff_mag");
    let sig = m.mux(eff_sub, mag, s_add);
    let sig = m.name(sig, "sum");
    let neg_sub = m.and(eff_sub, neg);
    let sign = m.mux(neg_sub, y.sign, x.sign);
    let sign = m.name(sign, "sign");
    Sum {
        sign,
        sig,
        top,
        eff_sub,
    }
}
