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

use crate::float::native::{add_down_up_f32, f32_bits, mul_f32, select_u32};
use crate::float::{
    add_generic, le, lt, max, min, mul, mul_generic, sub, total_key, FloatFormat, RoundingMode,
};

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
        // the cull unit's slab, beside every cull test of the renderer
        eval_conservative_b32(x)
    } else {
        eval_conservative_generic(fmt, x)
    }
}

/// [`eval_conservative`] for binary32 on `f32` values, bit-identical to
/// [`eval_conservative_generic`] (`tests/fast_paths.rs`): the directed sums
/// by the two-sum adder, the products exact in `f64` and rounded once,
/// comparisons as IEEE comparisons (NaN unordered, −0 = +0); `maximum` /
/// `minimum` by the total order (−0 < +0) with any NaN winning, and a NaN
/// result written as the canonical NaN, as the generic operators do.
/// Branch-free: the mirror, the reciprocal bound and the parallel slab are
/// selected by masks (their conditions follow the data and would be
/// mispredicted).
fn eval_conservative_b32(x: &SlabIn) -> SlabOut {
    const INF: u32 = 0x7f80_0000;
    const NEG_INF: u32 = 0xff80_0000;
    let sel = select_u32;
    // IEEE 754-2019 maximum / minimum (a NaN result is some NaN)
    let key = |a: u32| total_key(FloatFormat::BINARY32, a as u64);
    let extreme = |a: u32, b: u32, larger: bool| {
        let nan = f32::from_bits(a).is_nan() | f32::from_bits(b).is_nan();
        let a_wins = (key(a) > key(b)) == larger;
        sel(nan, f32::NAN.to_bits(), sel(a_wins, a, b))
    };
    let mut t_enter = x.t_min as u32;
    let mut t_exit = x.t_max as u32;
    for i in 0..3 {
        let c = x.inv_d[i] as u32;
        let mirror = c >> 31 != 0;
        let sign = c & 1 << 31;
        let (p_min, p_max) = (x.p_min[i] as u32, x.p_max[i] as u32);
        let lo = f32::from_bits(sel(mirror, p_max, p_min) ^ sign);
        let hi = f32::from_bits(sel(mirror, p_min, p_max) ^ sign);
        let o = f32::from_bits(x.o[i] as u32 ^ sign);
        let a = c & !(1 << 31);
        let parallel = a == INF;
        // the next float above `a` (`a` itself for ∞ and NaN)
        let b = a + (a < INF) as u32;
        let u = add_down_up_f32(lo, -o).0;
        let w = add_down_up_f32(hi, -o).1;
        let ru = f32::from_bits(sel(u < 0.0, b, a));
        let rw = f32::from_bits(sel(0.0 < w, b, a));
        let near = mul_f32(u, ru, RoundingMode::Down).to_bits();
        let far = mul_f32(w, rw, RoundingMode::Up).to_bits();
        let inside = (u <= 0.0) & (0.0 <= w);
        let near = sel(parallel, sel(inside, NEG_INF, INF), near);
        let far = sel(parallel, sel(inside, INF, NEG_INF), far);
        t_enter = extreme(t_enter, near, true);
        t_exit = extreme(t_exit, far, false);
    }
    let (t_enter, t_exit) = (f32::from_bits(t_enter), f32::from_bits(t_exit));
    SlabOut {
        hit: t_enter <= t_exit,
        t_enter: f32_bits(t_enter),
        t_exit: f32_bits(t_exit),
    }
}

/// The reference [`eval_conservative`]: the generic float operators, any format.
pub fn eval_conservative_generic(fmt: FloatFormat, x: &SlabIn) -> SlabOut {
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
        let u = add_generic(fmt, lo, o ^ sign, down);
        let v = add_generic(fmt, hi, o ^ sign, up);
        let (near, far) = if a == inf {
            if le(fmt, u, zero) && le(fmt, zero, v) {
                (fmt.inf(true), inf)
            } else {
                (inf, fmt.inf(true))
            }
        } else {
            let ru = if lt(fmt, u, zero) { b } else { a };
            let rv = if lt(fmt, zero, v) { b } else { a };
            (mul_generic(fmt, u, ru, down), mul_generic(fmt, v, rv, up))
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
