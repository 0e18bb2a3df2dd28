//! Golden model of the classic slab tester, the baseline most ray-tracing
//! hardware uses: the reciprocal direction `inv_d` is precomputed (an input),
//! then per axis `t = (p − o)·inv_d`, entry/exit by min/max, and one compare.
//! Every operation rounds to nearest even; min/max are IEEE 754-2019
//! `minimum`/`maximum` (a NaN propagates), so `0·∞` turns into a miss.
//!
//! Steps (raw bits of one format), for each axis i:
//! 1. `u_i = p_min_i − o_i`, `v_i = p_max_i − o_i` (RNE);
//! 2. `t0_i = u_i · inv_d_i`, `t1_i = v_i · inv_d_i` (RNE);
//! 3. `near_i = min(t0_i, t1_i)`, `far_i = max(t0_i, t1_i)`;
//!
//! then `t_enter = max(max(max(t_min, near_0), near_1), near_2)`,
//! `t_exit = min(min(min(t_max, far_0), far_1), far_2)`, and
//! `hit = t_enter <= t_exit` (false if either is NaN).
//!
//! Where it fails (see `docs/silhouette.md` and the tests): a zero direction
//! component gives `inv_d = ±∞`; with the origin on that slab's plane,
//! `0·∞ = NaN` and the ray, which touches the box, misses. Grazing rays:
//! the two rounded `t` of an edge can swap order, so a ray through an edge
//! or a corner of the box misses; and a ray just outside can hit.
//!
//! [`eval_conservative`] is the conservative slab (`slab -p
//! rounding=conservative`, docs/silhouette.md §6): directed rounding so that
//! the test can only gain hits, `inv_d` read as `1/d` rounded toward zero and
//! widened by one ulp, and a zero direction component (`inv_d = ±∞`) handled
//! as a parallel slab instead of `0·∞`.

use crate::float::{le, lt, max, min, mul, sub, FloatFormat, RoundingMode};

/// One slab-test transaction, raw bits of one format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SlabIn {
    /// box lower corner
    pub p_min: [u64; 3],
    /// box upper corner
    pub p_max: [u64; 3],
    /// ray origin
    pub o: [u64; 3],
    /// precomputed reciprocal direction (`1/d_i`, ±∞ for a zero component;
    /// rounded toward zero for [`eval_conservative`])
    pub inv_d: [u64; 3],
    /// segment start
    pub t_min: u64,
    /// segment end
    pub t_max: u64,
}

/// One slab-test result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlabOut {
    /// `t_enter <= t_exit`.
    pub hit: bool,
    /// the rounded entry parameter (NaN after `0·∞`)
    pub t_enter: u64,
    /// the rounded exit parameter
    pub t_exit: u64,
}

/// Evaluates one slab test in `fmt`.
pub fn eval(fmt: FloatFormat, x: &SlabIn) -> SlabOut {
    let rne = RoundingMode::NearestEven;
    let mut t_enter = x.t_min & fmt.mask();
    let mut t_exit = x.t_max & fmt.mask();
    for i in 0..3 {
        let u = sub(fmt, x.p_min[i], x.o[i], rne);
        let v = sub(fmt, x.p_max[i], x.o[i], rne);
        let t0 = mul(fmt, u, x.inv_d[i], rne);
        let t1 = mul(fmt, v, x.inv_d[i], rne);
        t_enter = max(fmt, t_enter, min(fmt, t0, t1));
        t_exit = min(fmt, t_exit, max(fmt, t0, t1));
    }
    SlabOut {
        hit: le(fmt, t_enter, t_exit),
        t_enter,
        t_exit,
    }
}

/// Evaluates one conservative slab test in `fmt` (docs/silhouette.md §6).
///
/// Contract on `inv_d_i`: `1/d_i` rounded toward zero (IEEE RTZ, so a finite
/// `d_i` never gives ±∞, and `1/±0 = ±∞`). Under it, a segment that meets the
/// box (exact rational semantics) always gives `hit`.
///
/// Per axis, with `c = inv_d_i`:
/// 1. mirror if the sign bit of `c` is set: `lo = −p_max`, `hi = −p_min`,
///    `o' = −o` (else `lo = p_min`, `hi = p_max`, `o' = o`), so the
///    reciprocal is `r = |1/d| ≥ 0`, entry plane `lo`, exit plane `hi`;
/// 2. `a = |c|`, `b` = the next float above `a` (`b = a` for ∞ and NaN):
///    `a ≤ r ≤ b` for an RTZ reciprocal;
/// 3. `u = RDN(lo − o')`, `v = RUP(hi − o')`;
/// 4. `a = +∞` (parallel, `d_i = ±0`): `near = −∞`, `far = +∞` if
///    `u ≤ 0 ≤ v` (that is `p_min ≤ o ≤ p_max`), else `near = +∞`,
///    `far = −∞`;
/// 5. otherwise `near = RDN(u · (u < 0 ? b : a))`,
///    `far = RUP(v · (v > 0 ? b : a))`;
///
/// then `t_enter`, `t_exit` and `hit` as in [`eval`] (IEEE 754-2019 maximum /
/// minimum, NaN propagates, `hit = t_enter <= t_exit`).
pub fn eval_conservative(fmt: FloatFormat, x: &SlabIn) -> SlabOut {
    if fmt == FloatFormat::BINARY32 {
        // the cull unit's slab: the same code with a constant format (the
        // float operators then take their binary32 paths without dispatch)
        eval_conservative_in(FloatFormat::BINARY32, x)
    } else {
        eval_conservative_in(fmt, x)
    }
}

/// [`eval_conservative`] in `fmt`.
#[inline(always)]
fn eval_conservative_in(fmt: FloatFormat, x: &SlabIn) -> SlabOut {
    let (down, up) = (RoundingMode::Down, RoundingMode::Up);
    let sign = fmt.sign_bit();
    let zero = fmt.zero(false);
    let inf = fmt.inf(false);
    let mut t_enter = x.t_min & fmt.mask();
    let mut t_exit = x.t_max & fmt.mask();
    for i in 0..3 {
        let c = x.inv_d[i] & fmt.mask();
        let mirror = c & sign != 0;
        let (lo, hi, o) = if mirror {
            (x.p_max[i] ^ sign, x.p_min[i] ^ sign, x.o[i] ^ sign)
        } else {
            (x.p_min[i], x.p_max[i], x.o[i])
        };
        let a = c & !sign;
        let b = if a < inf { a + 1 } else { a };
        let u = sub(fmt, lo, o, down);
        let v = sub(fmt, hi, o, up);
        let (near, far) = if a == inf {
            if le(fmt, u, zero) && le(fmt, zero, v) {
                (fmt.inf(true), inf)
            } else {
                (inf, fmt.inf(true))
            }
        } else {
            let ru = if lt(fmt, u, zero) { b } else { a };
            let rv = if lt(fmt, zero, v) { b } else { a };
            (mul(fmt, u, ru, down), mul(fmt, v, rv, up))
        };
        t_enter = max(fmt, t_enter, near);
        t_exit = min(fmt, t_exit, far);
    }
    SlabOut {
        hit: le(fmt, t_enter, t_exit),
        t_enter,
        t_exit,
    }
}
