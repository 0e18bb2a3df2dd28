//! The fast path of [`super::eval`] for formats whose values are `f32`s
//! (E <= 8, F <= 23, `float::native::fits_f32`): bit-identical outputs to
//! [`super::eval_generic`] for every input (checked by
//! `golden-model/tests/fast_paths.rs`).
//!
//! Why it is the same function: every input is converted exactly to `f32`;
//! classification and the bound checks are IEEE comparisons, which `f32`
//! comparisons are (NaN unordered, -0 == +0); the hit bits are 0 unless the
//! input is valid, non-empty and not mixed-sign, so the products are only
//! formed then, when no operand is NaN and no sum is NaN (origins finite).
//! The sums are the generic directed (or RNE) sums, natively for binary32;
//! each exact product of two such values is an exact `f64` (48 significand
//! bits, `2^-298 ..= 2^256`), so `f64` comparisons of `f64` products equal
//! `le` on `mul_exact` bits. `mulz`'s zero rule (a zero factor gives 0, even
//! against an infinity) is kept.

// `!(a <= b)` is the generic `!le` (true for NaN): kept in that form.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{BundleIn, Config, OriginMode, Out, Rounding, EDGES};
use crate::float::native::{add_down_up_f32, add_down_up_f32_n, to_f32};
use crate::float::{add, add_down_up_generic, FloatFormat, RoundingMode};

/// The numerators of one axis, as values: AnyHit entry / exit, AllHit entry / exit.
#[derive(Clone, Copy, Default)]
struct Num {
    n_any: f32,
    x_any: f32,
    n_all: f32,
    x_all: f32,
}

/// Directed sum `a + b` of two values of `f` (given as exact `f32`s, with
/// their bits for the generic path): `(down, up)`. `B32`: `f` is binary32.
#[inline(always)]
fn sum_du<const B32: bool>(f: FloatFormat, a: f32, b: f32, a_bits: u64, b_bits: u64) -> (f32, f32) {
    if B32 {
        // NaN cannot occur here (origins are finite when the sums are used).
        return add_down_up_f32(a, b);
    }
    sum_du_generic(f, a_bits, b_bits)
}

/// The generic directed sum, as `f32` values.
#[inline(never)]
fn sum_du_generic(f: FloatFormat, a_bits: u64, b_bits: u64) -> (f32, f32) {
    let r = add_down_up_generic(f, a_bits, b_bits);
    (to_f32(f, r.down), to_f32(f, r.up))
}

/// `a + b` rounded to nearest even in `f`.
#[inline(always)]
fn sum_rne<const B32: bool>(f: FloatFormat, a: f32, b: f32, a_bits: u64, b_bits: u64) -> f32 {
    if B32 {
        // Native f32 addition is IEEE RNE; NaN payloads cannot occur here
        // (origins are finite when the sums are used).
        return a + b;
    }
    to_f32(f, add(f, a_bits, b_bits, RoundingMode::NearestEven))
}

/// The exact product as `f64`, 0 when either factor is zero (`mulz`). In
/// the fast path no factor is NaN, so a NaN product is `inf · 0`.
#[inline(always)]
fn mulz(a: f64, b: f64) -> f64 {
    let p = a * b;
    // Branch-free `if p.is_nan() { 0.0 } else { p }`.
    let keep = (!p.is_nan() as u64).wrapping_neg();
    f64::from_bits(p.to_bits() & keep)
}

/// `a` if `v`'s sign bit equals `want_max`, else `b` (the generic `pick`).
#[inline(always)]
fn pick(v: f64, want_max: bool, a: f64, b: f64) -> f64 {
    if v.is_sign_negative() != want_max {
        b
    } else {
        a
    }
}

/// The twelve comparisons of one test (AllHit when `all`), all evaluated.
#[inline(always)]
fn pass(
    all: bool,
    n: &[f64; 3],
    xx: &[f64; 3],
    a: &[f64; 3],
    b: &[f64; 3],
    t_min: f64,
    t_max: f64,
) -> bool {
    let mut ok = true;
    for &(i, j) in EDGES.iter() {
        let l = mulz(n[i], pick(n[i], all, a[j], b[j]));
        let r = mulz(xx[j], pick(xx[j], !all, a[i], b[i]));
        ok &= l <= r;
    }
    for i in 0..3 {
        ok &= n[i] <= mulz(t_max, pick(t_max, !all, a[i], b[i]));
        ok &= mulz(t_min, pick(t_min, all, a[i], b[i])) <= xx[i];
    }
    ok
}

/// [`super::eval`] for a format with `fits_f32`.
#[inline]
pub(super) fn eval(cfg: &Config, x: &BundleIn) -> Out {
    match (
        cfg.fmt() == FloatFormat::BINARY32,
        cfg.origin == OriginMode::Bounded,
    ) {
        (true, false) => eval_as::<true, false, true>(cfg, x),
        (true, true) => eval_as::<true, true, true>(cfg, x),
        (false, false) => eval_as::<false, false, true>(cfg, x),
        (false, true) => eval_as::<false, true, true>(cfg, x),
    }
}

/// [`super::any_hit`] for a format with `fits_f32`.
#[inline]
pub(super) fn any_hit(cfg: &Config, x: &BundleIn) -> bool {
    match (
        cfg.fmt() == FloatFormat::BINARY32,
        cfg.origin == OriginMode::Bounded,
    ) {
        (true, false) => eval_as::<true, false, false>(cfg, x),
        (true, true) => eval_as::<true, true, false>(cfg, x),
        (false, false) => eval_as::<false, false, false>(cfg, x),
        (false, true) => eval_as::<false, true, false>(cfg, x),
    }
    .any_hit
}

/// The fast path; `B32`: the format is binary32 (native sums); `BOUNDED`:
/// the origin mode is bounded (a shared origin then costs no `o_hi` work);
/// `ALL`: the AllHit test is made (else `all_hit` is false, not computed).
fn eval_as<const B32: bool, const BOUNDED: bool, const ALL: bool>(
    cfg: &Config,
    x: &BundleIn,
) -> Out {
    let f = cfg.fmt();
    let v = |b: u64| {
        if B32 {
            f32::from_bits(b as u32)
        } else {
            to_f32(f, b)
        }
    };
    let bounded = BOUNDED;
    let o_hi_bits = if bounded { x.o_hi } else { x.o_lo };
    let p_min = x.p_min.map(v);
    let p_max = x.p_max.map(v);
    let o_lo = x.o_lo.map(v);
    let o_hi = if bounded { x.o_hi.map(v) } else { o_lo };
    let d_lo = x.d_lo.map(v);
    let d_hi = x.d_hi.map(v);
    let t_min = v(x.t_min);
    let t_max = v(x.t_max);

    // Step 1: classify (`|`, not `||`: no branches).
    let mut nan = t_min.is_nan() | t_max.is_nan();
    let mut invalid = false;
    let mut empty = !(t_min <= t_max) | (t_min == f32::INFINITY) | (t_max == f32::NEG_INFINITY);
    let mut mixed = false;
    let mut neg = [false; 3];
    for i in 0..3 {
        nan |= p_min[i].is_nan()
            | p_max[i].is_nan()
            | o_lo[i].is_nan()
            | o_hi[i].is_nan()
            | d_lo[i].is_nan()
            | d_hi[i].is_nan();
        invalid |= o_lo[i].is_infinite()
            | o_hi[i].is_infinite()
            | d_lo[i].is_infinite()
            | d_hi[i].is_infinite()
            | !(d_lo[i] <= d_hi[i])
            | !(o_lo[i] <= o_hi[i]);
        empty |=
            !(p_min[i] <= p_max[i]) | (p_min[i] == f32::INFINITY) | (p_max[i] == f32::NEG_INFINITY);
        neg[i] = d_lo[i] < 0.0;
        mixed |= neg[i] & (0.0 < d_hi[i]);
    }
    invalid &= !nan;
    let ok = !nan && !invalid && !empty;
    let out = |all_pass: bool, any_pass: bool| Out {
        all_hit: ok && !mixed && all_pass,
        any_hit: ok && (mixed || any_pass),
        nan,
        invalid,
        mixed_sign: !nan && !invalid && mixed,
    };
    if !ok || mixed {
        return out(false, false);
    }

    // Steps 2 and 3: mirror, numerators. Here every value is a number and
    // o, d are finite.
    let s = f.sign_bit();
    let mut num = [Num::default(); 3];
    let mut a = [0f64; 3];
    let mut b = [0f64; 3];
    let (mut near, mut far, mut m_lo, mut m_hi) = ([0f32; 3], [0f32; 3], [0f32; 3], [0f32; 3]);
    let (mut near_b, mut far_b, mut m_lo_b, mut m_hi_b) =
        ([0u64; 3], [0u64; 3], [0u64; 3], [0u64; 3]);
    for i in 0..3 {
        if neg[i] {
            near[i] = -p_max[i];
            far[i] = -p_min[i];
            m_lo[i] = o_hi[i];
            m_hi[i] = o_lo[i];
            near_b[i] = x.p_max[i] ^ s;
            far_b[i] = x.p_min[i] ^ s;
            m_lo_b[i] = o_hi_bits[i];
            m_hi_b[i] = x.o_lo[i];
            a[i] = d_hi[i].abs() as f64;
            b[i] = d_lo[i].abs() as f64;
        } else {
            near[i] = p_min[i];
            far[i] = p_max[i];
            m_lo[i] = -o_lo[i];
            m_hi[i] = -o_hi[i];
            near_b[i] = x.p_min[i];
            far_b[i] = x.p_max[i];
            m_lo_b[i] = x.o_lo[i] ^ s;
            m_hi_b[i] = o_hi_bits[i] ^ s;
            a[i] = d_lo[i].abs() as f64;
            b[i] = d_hi[i].abs() as f64;
        }
    }
    if B32 && cfg.rounding == Rounding::Conservative {
        // The sums of all axes at once: near - ô_lo (largest N) and far - ô_hi
        // (smallest X); bounded mode also near - ô_hi and far - ô_lo.
        let cat = |p: [f32; 3], q: [f32; 3]| [p[0], p[1], p[2], q[0], q[1], q[2]];
        let (d1, u1) = add_down_up_f32_n(cat(near, far), cat(m_lo, m_hi));
        let (d2, u2) = if bounded {
            add_down_up_f32_n(cat(near, far), cat(m_hi, m_lo))
        } else {
            (d1, u1)
        };
        for i in 0..3 {
            num[i] = Num {
                n_any: d2[i],
                x_any: u2[3 + i],
                n_all: u1[i],
                x_all: d1[3 + i],
            };
        }
    } else {
        for i in 0..3 {
            let (near, far, m_lo, m_hi) = (near[i], far[i], m_lo[i], m_hi[i]);
            let (near_b, far_b, m_lo_b, m_hi_b) = (near_b[i], far_b[i], m_lo_b[i], m_hi_b[i]);
            num[i] = match cfg.rounding {
                Rounding::Conservative => {
                    let n_big = sum_du::<B32>(f, near, m_lo, near_b, m_lo_b);
                    let x_small = sum_du::<B32>(f, far, m_hi, far_b, m_hi_b);
                    let (n_small, x_big) = if bounded {
                        (
                            sum_du::<B32>(f, near, m_hi, near_b, m_hi_b),
                            sum_du::<B32>(f, far, m_lo, far_b, m_lo_b),
                        )
                    } else {
                        (n_big, x_small)
                    };
                    Num {
                        n_any: n_small.0,
                        x_any: x_big.1,
                        n_all: n_big.1,
                        x_all: x_small.0,
                    }
                }
                Rounding::Nearest => Num {
                    n_any: sum_rne::<B32>(f, near, m_hi, near_b, m_hi_b),
                    x_any: sum_rne::<B32>(f, far, m_lo, far_b, m_lo_b),
                    n_all: sum_rne::<B32>(f, near, m_lo, near_b, m_lo_b),
                    x_all: sum_rne::<B32>(f, far, m_hi, far_b, m_hi_b),
                },
            };
        }
    }

    // Step 4: products and comparisons.
    let n_any = num.map(|v| v.n_any as f64);
    let x_any = num.map(|v| v.x_any as f64);
    let n_all = num.map(|v| v.n_all as f64);
    let x_all = num.map(|v| v.x_all as f64);
    let (t_min, t_max) = (t_min as f64, t_max as f64);
    if a == b {
        // One direction (a single ray): every `pick` gives the same factor,
        // and the segment products are shared by both tests.
        let dist = a.map(|d| mulz(t_max, d));
        let dir = a.map(|d| mulz(t_min, d));
        return out(
            ALL && pass_ray(&n_all, &x_all, &a, &dist, &dir),
            pass_ray(&n_any, &x_any, &a, &dist, &dir),
        );
    }
    out(
        ALL && pass(true, &n_all, &x_all, &a, &b, t_min, t_max),
        pass(false, &n_any, &x_any, &a, &b, t_min, t_max),
    )
}

/// [`pass`] when both direction bounds are `d` on every axis, with the
/// segment products `dist = t_max·d`, `dir = t_min·d` (`mulz`).
#[inline(always)]
fn pass_ray(n: &[f64; 3], xx: &[f64; 3], d: &[f64; 3], dist: &[f64; 3], dir: &[f64; 3]) -> bool {
    let mut ok = true;
    for &(i, j) in EDGES.iter() {
        ok &= mulz(n[i], d[j]) <= mulz(xx[j], d[i]);
    }
    for i in 0..3 {
        ok &= (n[i] <= dist[i]) & (dir[i] <= xx[i]);
    }
    ok
}
