//! Golden model of `triangle`: a watertight ray/triangle test in Woop,
//! Benthin and Wald's formulation (2013, "Watertight ray/triangle
//! intersection"), every product, difference and sum rounded once in one
//! internal format ([`internal_format`]: the unit's fraction width and an
//! exponent range in whose normal range every value of the datapath lies
//! for finite inputs), to nearest even ([`eval`]) or in any rounding mode
//! ([`eval_with`]); and an exact rational reference ([`exact`]).
//!
//! Per ray (software, [`shear`]): `kz` is the axis of the largest `|d|`
//! (the first on ties), `kx = kz + 1`, `ky = kz + 2` (mod 3), and
//! `s = (d_kx / d_kz, d_ky / d_kz, 1 / d_kz)` each correctly rounded.
//! Per triangle (the unit, [`eval`]), in the internal format, `RN` the
//! rounding in the mode:
//!
//! 1. each vertex relative to the origin, `p = P − o` (three subtractions,
//!    the inputs widened exactly);
//! 2. sheared into ray space, `X = p_kx − RN(s_x·p_kz)`,
//!    `Y = p_ky − RN(s_y·p_kz)`, and `p_kz` (the scale `s_z` is applied
//!    once, to `T`);
//! 3. the edge functions, two rounded products and a rounded difference:
//!    `U = RN(C_X·B_Y) − RN(C_Y·B_X)`, `V = RN(A_X·C_Y) − RN(A_Y·C_X)`,
//!    `W = RN(B_X·A_Y) − RN(B_Y·A_X)`;
//! 4. inside unless some of `U, V, W` is negative and some positive;
//!    `det = (U + V) + W` and `T = s_z·((U·a_kz + V·b_kz) + W·c_kz)`, every
//!    operation rounded; `det = 0` is a miss (mixed signs, or a repeated
//!    vertex), or `invalid` when `U = V = W = 0` (below);
//! 5. `r = 1/det`, `t = T·r`, barycentrics `u = V·r` (of B), `v = W·r` (of
//!    C); hit iff inside, `det ≠ 0` and `t_min ≤ t ≤ t_max`; `t`, `u`, `v`
//!    rounded into the unit's format.
//!
//! **Why it is watertight.** A vertex's sheared coordinates depend only on
//! the vertex and the ray, so two triangles sharing it compute the same
//! `X, Y`. Each edge function depends only on its directed edge
//! (`P → Q` gives `RN(Q_X·P_Y) − RN(Q_Y·P_X)`), and the neighbour across an
//! edge walks it the other way: it subtracts the same two rounded products
//! in the opposite order. In the internal format nothing underflows or
//! overflows, so a rounded difference has the sign of the exact difference
//! of the two rounded products, in any mode: the two triangles see opposite
//! signs or both a zero, and zero counts as inside for both. So no ray falls
//! between them. The signs are those of the rounded products, not of the
//! exact edge function: where the two products round to the same value
//! (a ray within about an ulp of the edge's line in ray space) both
//! triangles see a zero and both may hit. Woop et al. recompute such a zero
//! in double precision; the unit does not, except where it would lose a hit:
//! when all three edge functions are zero `det` is 0 and the triangle cannot
//! be hit, though the ray may cross it (a sliver within rounding of the
//! ray's plane; every face of a closed mesh that flat can be so, and the ray
//! would escape it), so that case is flagged `invalid` for the caller to
//! decide (docs/triangle.md §2).
//!
//! Outputs when there is no hit: `t = u = v = +0`. `invalid` (with a miss)
//! for a NaN or infinite `o`, `s` or vertex coordinate, a NaN `t_min` or
//! `t_max`, `kz = 3`, all three edge functions zero, or a hit whose `t` lies
//! beyond the format's finite range.

use crate::float::{add, classify, convert, le, lt, mul, sub, Class, FloatFormat, RoundingMode};
use crate::transform::recip;

const RNE: RoundingMode = RoundingMode::NearestEven;

/// One transaction of the unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TriIn {
    /// ray origin
    pub o: [u64; 3],
    /// the axis of the largest direction component (0, 1, 2; 3 is invalid)
    pub kz: u32,
    /// the ray's shear constants `d_kx/d_kz`, `d_ky/d_kz`, `1/d_kz`
    pub s: [u64; 3],
    /// vertices
    pub a: [u64; 3],
    /// vertices
    pub b: [u64; 3],
    /// vertices
    pub c: [u64; 3],
    /// segment start
    pub t_min: u64,
    /// segment end
    pub t_max: u64,
}

/// What the unit answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TriOut {
    /// the segment meets the triangle
    pub hit: bool,
    /// a non-finite input or `kz = 3` (then `hit` is false)
    pub invalid: bool,
    /// distance along the ray (+0 without a hit)
    pub t: u64,
    /// barycentric weight of B (+0 without a hit)
    pub u: u64,
    /// barycentric weight of C (+0 without a hit)
    pub v: u64,
}

/// `(kx, ky)` for `kz`.
pub fn other_axes(kz: u32) -> (usize, usize) {
    let kz = kz as usize % 3;
    ((kz + 1) % 3, (kz + 2) % 3)
}

/// The per-ray precomputation: `kz` and the shear constants, each the
/// correctly rounded quotient. A zero direction gives `kz = 0` and NaN or
/// infinite constants (the unit then flags `invalid`).
pub fn shear(fmt: FloatFormat, d: [u64; 3]) -> (u32, [u64; 3]) {
    let mag = |x: u64| x & !fmt.sign_bit();
    let mut kz = 0;
    for k in 1..3 {
        // larger magnitude, compared on the bits of finite values
        if classify(fmt, d[k]) != Class::NaN && mag(d[k]) > mag(d[kz]) {
            kz = k;
        }
    }
    let (kx, ky) = other_axes(kz as u32);
    let ratio = |num: u64| quotient(fmt, num, d[kz]);
    (
        kz as u32,
        [ratio(d[kx]), ratio(d[ky]), ratio(fmt.one(false))],
    )
}

/// `n / d` correctly rounded to nearest even; NaN unless both are finite
/// and `d ≠ 0`.
fn quotient(fmt: FloatFormat, n: u64, d: u64) -> u64 {
    use crate::transform::exact::{decode, round_ratio};
    if fmt == FloatFormat::BINARY32 {
        // an f64 quotient rounded again to binary32 is the correctly rounded
        // one (53 >= 2·24 + 2 bits: double rounding is innocuous for ÷)
        let (x, y) = (f32::from_bits(n as u32), f32::from_bits(d as u32));
        if x.is_finite() && y.is_finite() && y != 0.0 {
            return ((x as f64 / y as f64) as f32).to_bits() as u64;
        }
    }
    match (decode(fmt, n), decode(fmt, d)) {
        (Some((mn, en)), Some((md, ed))) if md != dashu::integer::IBig::ZERO => {
            round_ratio(fmt, RNE, &mn, &md, en - ed)
        }
        _ => fmt.canonical_nan(),
    }
}

/// The unit's answer for `x`, bit for bit, every operation rounded to
/// nearest even (the renderer's unit).
pub fn eval(fmt: FloatFormat, x: &TriIn) -> TriOut {
    eval_with(fmt, RNE, x)
}

/// The internal format of the unit for `fmt`: the same fraction width, the
/// smallest exponent width (at least `fmt`'s) in whose normal range every
/// nonzero value of steps 1-4 lies for finite inputs, so every rounding in
/// it is the rounding of an unbounded exponent (a rounded value has its
/// exact value's sign, in every mode); `None` if no supported
/// format (exponent at most 11 bits, width at most 64) has that range
/// (more than 8 exponent bits, or 8 with more than 44 fraction bits).
///
/// With `g = emin − F` (the grid of `fmt`'s subnormals) and `M = 2^(emax+1)`:
/// a difference `P − o` is a multiple of `2^g` below `2M`; the ray-space
/// coordinates multiples of `2^(2g)` below `4M²`; the edge functions and
/// `det` multiples of `2^(4g)` below `2^7·M⁴`; `T` a multiple of `2^(6g)`
/// below `2^8·M⁶`; `1/det` below `2^(−4g)`. The internal bias is the
/// smallest with `emin' ≤ 6g` (every nonzero value normal) and
/// `emax' ≥ 6·emax + 16`.
pub fn internal_format(fmt: FloatFormat) -> Option<FloatFormat> {
    let (emin, emax, f) = (fmt.emin() as i64, fmt.emax() as i64, fmt.frac_bits() as i64);
    let g = emin - f;
    let bias_needed = (6 * emax + 16).max(1 - 6 * g);
    (fmt.exp_bits()..=FloatFormat::MAX_EXP_BITS)
        .find(|&e| (1i64 << (e - 1)) > bias_needed)
        .and_then(|e| FloatFormat::new(e, fmt.frac_bits()).ok())
}

/// The values of the datapath for one transaction, in the internal format.
struct Datapath {
    /// the internal format
    w: FloatFormat,
    /// a non-finite input, a NaN bound or `kz = 3`
    invalid: bool,
    /// the edge functions agree in sign (none NaN) and `det ≠ 0`
    inside: bool,
    /// all three edge functions are zero (`det = 0` without mixed signs): the
    /// ray lies in the triangle's plane as far as the rounded products tell,
    /// a triangle seen edge-on or a sliver it crosses; flagged `invalid`
    undecided: bool,
    /// `V` and `W`, the numerators of the barycentric weights of B and C
    e_v: u64,
    e_w: u64,
    /// `det = U + V + W`
    det: u64,
    /// `T = U·A_Z + V·B_Z + W·C_Z`
    t_num: u64,
}

/// Steps 1-4 in the internal format (`None` when `fmt` has none).
fn datapath(fmt: FloatFormat, mode: RoundingMode, x: &TriIn) -> Option<Datapath> {
    let w = internal_format(fmt)?;
    let wide = |v: u64| convert(fmt, w, v, mode);
    let zero = w.zero(false);
    let all = x.o.iter().chain(&x.s).chain(&x.a).chain(&x.b).chain(&x.c);
    let invalid = all.clone().any(|&v| !fmt.is_finite(v))
        || fmt.is_nan(x.t_min)
        || fmt.is_nan(x.t_max)
        || x.kz > 2;
    let (kx, ky) = other_axes(x.kz);
    let kz = x.kz as usize % 3;
    let s = x.s.map(wide);
    // steps 1-2: each vertex in ray space (the difference rounded into w),
    // `[X, Y, p_kz]`: the shear by s_z is applied once, to T
    let sheared = |p: &[u64; 3]| {
        let r = [0, 1, 2].map(|i| sub(w, wide(p[i]), wide(x.o[i]), mode));
        let (px, py, pz) = (r[kx], r[ky], r[kz]);
        [
            sub(w, px, mul(w, s[0], pz, mode), mode),
            sub(w, py, mul(w, s[1], pz, mode), mode),
            pz,
        ]
    };
    let (a, b, c) = (sheared(&x.a), sheared(&x.b), sheared(&x.c));
    // step 3: RN(Q_X·P_Y) − RN(Q_Y·P_X) for the directed edge P → Q (the
    // neighbour subtracts the same two rounded products the other way)
    let edge = |p: &[u64; 3], q: &[u64; 3]| {
        sub(w, mul(w, q[0], p[1], mode), mul(w, q[1], p[0], mode), mode)
    };
    let (u, v, e_w) = (edge(&b, &c), edge(&c, &a), edge(&a, &b));
    // step 4: zero counts as inside (an edge function is never NaN for
    // finite input, and non-finite input is invalid whatever it gives)
    let edges = [u, v, e_w];
    let negative = edges.iter().any(|&e| lt(w, e, zero));
    let positive = edges.iter().any(|&e| lt(w, zero, e));
    let det = add(w, add(w, u, v, mode), e_w, mode);
    let weighted = add(
        w,
        add(w, mul(w, u, a[2], mode), mul(w, v, b[2], mode), mode),
        mul(w, e_w, c[2], mode),
        mode,
    );
    let t_num = mul(w, s[2], weighted, mode);
    let det_zero = classify(w, det) == Class::Zero;
    // no edge function of either sign against another (zero counts as inside)
    let agree = !(negative && positive);
    Some(Datapath {
        w,
        invalid,
        inside: agree && !det_zero,
        undecided: !invalid && agree && det_zero,
        e_v: v,
        e_w,
        det,
        t_num,
    })
}

/// The unit's answer for `x` with every operation rounded in `mode`
/// (watertight in every mode; the shear constants are inputs, rounded to
/// nearest by [`shear`]) with `outputs=full` (`outputs=hit|tnum`:
/// [`eval_tnum`]). The datapath runs in [`internal_format`]: the
/// inputs are widened exactly, `t`, `u`, `v` rounded back into `fmt` (exact
/// in `fmt`'s normal range: the fraction width is the same). A hit whose
/// `t` lies beyond `fmt`'s finite range is no hit and flagged `invalid`;
/// for a format without an internal format every transaction is `invalid`.
pub fn eval_with(fmt: FloatFormat, mode: RoundingMode, x: &TriIn) -> TriOut {
    let Some(d) = datapath(fmt, mode, x) else {
        return TriOut {
            invalid: true,
            ..TriOut::default()
        };
    };
    let w = d.w;
    let wide = |v: u64| convert(fmt, w, v, mode);
    // step 5: t in w, compared with the bounds there
    let r = recip(w, d.det, mode);
    let t = mul(w, d.t_num, r, mode);
    let candidate = !d.invalid && d.inside && le(w, wide(x.t_min), t) && le(w, t, wide(x.t_max));
    // a hit beyond the format's finite range: no t to report
    let far = candidate && lt(w, wide(fmt.max_finite(false)), t & !w.sign_bit());
    if !candidate || far {
        return TriOut {
            invalid: d.invalid || d.undecided || far,
            ..TriOut::default()
        };
    }
    let narrow = |v: u64| convert(w, fmt, v, mode);
    TriOut {
        hit: true,
        invalid: d.invalid,
        t: narrow(t),
        u: narrow(mul(w, d.e_v, r, mode)),
        v: narrow(mul(w, d.e_w, r, mode)),
    }
}

/// What the unit answers with `outputs=tnum`: `t = t_num / t_den`, both in
/// [`internal_format`], not divided.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TriNum {
    /// the segment meets the triangle
    pub hit: bool,
    /// a non-finite input, `kz = 3` or a hit beyond the format's range
    pub invalid: bool,
    /// `T` (+0 without a hit)
    pub t_num: u64,
    /// `det` (+0 without a hit)
    pub t_den: u64,
}

/// How the `outputs=hit|tnum` unit tests the segment without a division.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Segment {
    /// `t_min ≤ T/det ≤ t_max` and `|T/det| ≥ 2^(emax+1)` decided exactly
    /// (products of `T`, `det` and the bounds): [`eval_tnum`].
    #[default]
    Exact,
    /// The same three decisions on approximate base-2 logarithms,
    /// conservatively ([`segment_log`]): every `t` within the segment is
    /// accepted and every `t` beyond the format's range flagged; a `t` up
    /// to a factor ~1.3 outside a bound may be accepted too.
    Log,
}

/// The unit's answer with `outputs=tnum`: the datapath of [`eval_with`]
/// up to `T` and `det`, then the segment test without a division, exact:
/// `t_min ≤ T/det ≤ t_max` as `t_min·|det| ≤ T·sgn(det) ≤ t_max·|det|`, and
/// `|T| ≥ 2^(emax+1)·|det|` (a `t` beyond the format's finite range) flagged
/// `invalid`. Its `hit` can differ from [`eval_with`]'s only where the
/// rounded `t` of the latter and the exact ratio lie on two sides of a
/// bound (within an ulp or two of it); [`finish_t`] gives `full`'s `t`.
/// The same as [`eval_tnum_with`] with [`Segment::Exact`].
pub fn eval_tnum(fmt: FloatFormat, mode: RoundingMode, x: &TriIn) -> TriNum {
    eval_tnum_with(fmt, mode, Segment::Exact, x)
}

/// The unit's answer with `outputs=tnum` and the segment test `segment`:
/// the datapath of [`eval_with`] up to `T` and `det` (the same `invalid`
/// for non-finite input, `kz = 3` or three zero edge functions, the same
/// misses outside the triangle), then the three decisions `after_min`
/// (`t ≥ t_min`), `before_max` (`t ≤ t_max`) and `far`
/// (`|t| ≥ 2^(emax+1)`) of `t = T/det`: exact ([`Segment::Exact`], as
/// [`eval_tnum`]) or approximate and conservative ([`Segment::Log`],
/// [`segment_log`]). Not `after_min && before_max`: no hit (not
/// `invalid`); else `far`: no hit and `invalid`; else a hit with
/// `t_num = T`, `t_den = det`.
///
/// With [`Segment::Log`] a hit of [`Segment::Exact`] is always a hit (the
/// same `T` and `det`), and an `invalid` of it always `invalid`; the log
/// test may also accept a `t` somewhat outside the segment, or flag a hit
/// with `|t|` a little below `2^(emax+1)` `invalid` (factors in
/// [`segment_log`]): the caller, which divides `T/det` once per accepted
/// hit ([`finish_t`]), re-decides the segment on the quotient.
pub fn eval_tnum_with(fmt: FloatFormat, mode: RoundingMode, segment: Segment, x: &TriIn) -> TriNum {
    let Some(d) = datapath(fmt, mode, x) else {
        return TriNum {
            invalid: true,
            ..TriNum::default()
        };
    };
    if d.invalid || !d.inside {
        return TriNum {
            invalid: d.invalid || d.undecided,
            ..TriNum::default()
        };
    }
    // finite and det ≠ 0 here (T and det zero or normal in w)
    let (after_min, before_max, far) = match segment {
        Segment::Exact => segment_exact(fmt, d.w, d.t_num, d.det, x.t_min, x.t_max),
        Segment::Log => segment_log(fmt, d.t_num, d.det, x.t_min, x.t_max),
    };
    if !(after_min && before_max) {
        return TriNum::default();
    }
    if far {
        return TriNum {
            invalid: true,
            ..TriNum::default()
        };
    }
    TriNum {
        hit: true,
        invalid: false,
        t_num: d.t_num,
        t_den: d.det,
    }
}

/// The exact segment test of `t = T/det` (`T`, `det` finite in `w`,
/// `det ≠ 0`; the bounds in `fmt`, not NaN): `(t ≥ t_min, t ≤ t_max,
/// |t| ≥ 2^(emax+1))`, as `t_min·|det| ≤ T·sgn(det) ≤ t_max·|det|` and
/// `|T| ≥ 2^(emax+1)·|det|` in big integers.
fn segment_exact(
    fmt: FloatFormat,
    w: FloatFormat,
    t_num: u64,
    det: u64,
    t_min: u64,
    t_max: u64,
) -> (bool, bool, bool) {
    use crate::exact::ray_box::{decode as decode_bound, Exact};
    use crate::transform::exact::decode;
    use dashu::integer::IBig;
    // T' = T·sgn(det) against bound·|det|
    let (tm, te) = decode(w, t_num).expect("T is finite");
    let (dm, de) = decode(w, det).expect("det is finite");
    let (tm, dm) = if dm < IBig::ZERO {
        (-tm, -dm)
    } else {
        (tm, dm)
    };
    // the sign of T' − b·2^k·|det| for the finite bound b·2^k
    let cmp = |b: IBig, k: i64| {
        let (lhs, rhs, e) = (tm.clone(), b * &dm, k + de);
        let shift = |x: IBig, by: i64| x << (by as usize);
        if te >= e {
            shift(lhs, te - e).cmp(&rhs)
        } else {
            lhs.cmp(&shift(rhs, e - te))
        }
    };
    use std::cmp::Ordering::*;
    let at_least = |bound: u64| match decode_bound(fmt, bound) {
        Exact::NegInf => true,
        Exact::PosInf | Exact::NaN => false,
        Exact::Fin { m, e } => cmp(IBig::from(m), e as i64) != Less,
    };
    let at_most = |bound: u64| match decode_bound(fmt, bound) {
        Exact::PosInf => true,
        Exact::NegInf | Exact::NaN => false,
        Exact::Fin { m, e } => cmp(IBig::from(m), e as i64) != Greater,
    };
    // |T'| ≥ 2^(emax+1)·|det|
    let big = |sign: i64| cmp(IBig::from(sign), fmt.emax() as i64 + 1);
    let far = big(1) != Less || big(-1) != Greater;
    (at_least(t_min), at_most(t_max), far)
}

/// The constants `(K, C)` of [`segment_log`] for `fmt`: `K = min(8, F)`
/// fraction bits in each logarithm, and the margin
/// `C = ⌈2^K · 0.1721427⌉ + 2` in units of `2^−K` (47 for `K = 8`, 25 for
/// 7, 14 for 6, 5 for 4): at least `2δ·2^K` with
/// `δ = 0.0860713… + 2^−K` the most by which a truncated Mitchell logarithm
/// (exponent plus the top `K` fraction bits) falls below `log2` of a
/// normal value (`max(log2(1+f) − f) = 0.08607133…` at
/// `f = 1/ln 2 − 1`, plus the truncation, below `2^−K`).
pub fn log_segment_constants(fmt: FloatFormat) -> (u32, i64) {
    let k = fmt.frac_bits().min(8);
    // ⌈2^K · 1721427 / 10^7⌉ + 2, in integers
    let c = ((1i64 << k) * 1_721_427 + 9_999_999) / 10_000_000 + 2;
    (k, c)
}

/// The `segment=log` test of `t = T/det` (`outputs=hit|tnum`), bit for bit
/// as the hardware does it: `(after_min, before_max, far)`, approximating
/// `t ≥ t_min`, `t ≤ t_max` and `|t| ≥ 2^(emax+1)` by comparisons of
/// base-2 logarithms taken as Mitchell does, the biased exponent followed
/// by the top `K` fraction bits, with the margin `C`
/// ([`log_segment_constants`]).
///
/// `t_num` (`T`) and `det` (`D`) are bit patterns of
/// [`internal_format`]`(fmt)` (`Ew` exponent bits, `fmt`'s `F` fraction
/// bits), each zero or normal, `D ≠ 0` (as the datapath gives them);
/// `t_min` (`L`) and `t_max` (`H`) bit patterns of `fmt` (`Ef` exponent
/// bits, bias `b`), anything but NaN (a NaN bound reads as an infinity;
/// it is `invalid` upstream). Panics if `fmt` has no internal format.
///
/// - `lT = (T >> (F−K)) mod 2^(Ew+K)`, `lD` likewise; `q = lT − lD`;
/// - a bound `X` with exponent field 0 (zero or subnormal) has
///   `lX = 2^K` (the magnitude `2^(1−b)`), else
///   `lX = (X >> (F−K)) mod 2^(Ef+K)`; `rX = q + b·2^K − lX`, about
///   `2^K·log2(|t| / |X|)`;
/// - `H` equal to ±0 or a negative subnormal counts as zero (moved up), a
///   positive subnormal as `2^(1−b)` (moved up); `L` equal to ±0 or a
///   positive subnormal counts as zero (moved down), a negative subnormal
///   as `−2^(1−b)` (moved down);
/// - `before_max`: `H = ±∞` gives `H > 0`; else `T = 0` gives `H ≥ 0` (`H`
///   as counted); else `H` zero gives `t < 0`; else `t, H > 0` gives
///   `rH ≤ C`; `t, H < 0` gives `rH ≥ −C`; opposite signs give `t < 0`;
/// - `after_min` the mirror image (`L = ±∞` gives `L < 0`, `T = 0` gives
///   `L ≤ 0`, `L` zero gives `t > 0`, `t, L > 0` gives `rL ≥ −C`,
///   `t, L < 0` gives `rL ≤ C`, opposite signs `t > 0`);
/// - `far`: `T ≠ 0` and `q ≥ (emax+1)·2^K − C`.
///
/// **Guarantee.** `2^−K·r` exceeds the exact `log2(|t|/|X|)` by more than
/// `−δ` and less than `2δ` (`T`'s logarithm falls short by `[0, δ)`, those
/// of `D` and the bound, subtracted, by `[0, δ)` each), and `2^−K·q`
/// differs from `log2|t|` by less than `δ`; `C ≥ 2δ·2^K`. So, exactly:
/// `before_max` is true whenever `t ≤ t_max`, `after_min` whenever
/// `t ≥ t_min`, and `far` whenever `|t| ≥ 2^(emax+1)`: the test never
/// loses a hit of the exact test nor lets a `t` beyond the format's range
/// through.
///
/// **Where it is loose** (`K = 8`, `C = 47`: `C·2^−K + δ = 0.274`,
/// `C·2^−K + 2δ = 0.364`). A `t` beyond a bound of its own sign may be
/// accepted: where beyond means a larger magnitude (`t > t_max > 0`,
/// `t < t_min < 0`; `T`'s logarithm alone errs that way) by a factor below
/// `2^(C·2^−K + δ)` ≈ 1.21 (about 1.18 attainable; binary32 tests measure
/// 1.174); where it means a smaller magnitude (`0 < t < t_min`,
/// `t_max < t < 0`; those of `det` and the bound err that way) by a factor
/// below `2^(C·2^−K + 2δ)` ≈ 1.29, i.e. `t` down to ≈ 0.78·`t_min`
/// (0.787 attainable and measured: not the 1.2 of the other side). A bound
/// of the other sign than `t`, zero, or infinite is decided exactly, with
/// subnormal bounds moved outward as above (a `t` up to ~1.21 beyond
/// `2^(1−b)` may pass such a bound). `far` may also flag a `t` with
/// `|t| > 2^(emax+1 − C·2^−K − δ)` ≈ `2^(emax+1)/1.21` (measured from
/// 0.842·`2^(emax+1)`): a hit just below the range is then `invalid`. The
/// caller divides once per accepted hit and re-decides on the quotient.
pub fn segment_log(
    fmt: FloatFormat,
    t_num: u64,
    det: u64,
    t_min: u64,
    t_max: u64,
) -> (bool, bool, bool) {
    let w = internal_format(fmt).expect("segment_log: the format has no internal format");
    let (k, c) = log_segment_constants(fmt);
    let f = fmt.frac_bits();
    let (ew, ef) = (w.exp_bits(), fmt.exp_bits());
    let bias_f = fmt.bias() as i64;
    let emax_f = bias_f;
    // biased exponent and top K fraction bits, sign dropped
    let log_w = |v: u64| ((v >> (f - k)) & ((1u64 << (ew + k)) - 1)) as i64;
    let (lt, ld) = (log_w(t_num), log_w(det));
    let sign_w = |v: u64| (v >> (ew + f)) & 1 == 1;
    let s_t = sign_w(t_num) ^ sign_w(det);
    let z_t = (t_num >> f) & ((1u64 << ew) - 1) == 0;
    let q = lt - ld;
    // a bound: (l, sign, denormal, infinite, nonzero fraction)
    let bound = |x: u64| {
        let x = x & fmt.mask();
        let exp = (x >> f) & ((1u64 << ef) - 1);
        let (d, i) = (exp == 0, exp == (1u64 << ef) - 1);
        let l = if d {
            1i64 << k
        } else {
            ((x >> (f - k)) & ((1u64 << (ef + k)) - 1)) as i64
        };
        (l, (x >> (ef + f)) & 1 == 1, d, i, x & fmt.frac_mask() != 0)
    };
    let (l_h, s_h, d_h, i_h, frac_h) = bound(t_max);
    let (l_l, s_l, d_l, i_l, frac_l) = bound(t_min);
    let z_h = d_h && (!frac_h || s_h);
    let z_l = d_l && (!frac_l || !s_l);
    let r_h = q + (bias_f << k) - l_h;
    let r_l = q + (bias_f << k) - l_l;
    let (gt_h, lt_h, gt_l, lt_l) = (r_h > c, r_h < -c, r_l > c, r_l < -c);
    let before_max = if i_h {
        !s_h
    } else if z_t {
        !s_h || z_h
    } else if z_h {
        s_t
    } else if !s_t && !s_h {
        !gt_h
    } else if s_t && s_h {
        !lt_h
    } else {
        s_t
    };
    let after_min = if i_l {
        s_l
    } else if z_t {
        s_l || z_l
    } else if z_l {
        !s_t
    } else if !s_t && !s_l {
        !lt_l
    } else if s_t && s_l {
        !gt_l
    } else {
        !s_t
    };
    let far = !z_t && q >= ((emax_f + 1) << k) - c;
    (after_min, before_max, far)
}

/// `t` from an `outputs=tnum` answer, rounded as `outputs=full` rounds it
/// (`RN(T · RN(1/det))` in the internal format, then into `fmt`): what a
/// shader does once per accepted hit.
pub fn finish_t(fmt: FloatFormat, mode: RoundingMode, t_num: u64, t_den: u64) -> u64 {
    let Some(w) = internal_format(fmt) else {
        return fmt.canonical_nan();
    };
    let t = mul(w, t_num, recip(w, t_den, mode), mode);
    convert(w, fmt, t, mode)
}

/// Exact reference: the closed triangle against the closed segment, in
/// rational arithmetic (Cramer's rule on `o + t·d = A + β(B − A) + γ(C − A)`).
pub mod exact {
    use crate::float::FloatFormat;
    use crate::transform::exact::{align, decode};
    use dashu::integer::IBig;

    /// The exact answer: `Some(t)` as the fraction `t_num / t_den`
    /// (`t_den > 0`) when the segment meets the triangle's interior or
    /// boundary at one point, `None` otherwise (a miss, a degenerate triangle
    /// or a ray in its plane, a non-finite input); with the barycentric
    /// weights of B and C over the same denominator.
    #[derive(Debug, Clone, PartialEq, Eq)]
    pub struct Hit {
        /// numerator of t
        pub t_num: IBig,
        /// denominator of t, u and v (> 0)
        pub t_den: IBig,
        /// exponent: t = t_num / t_den · 2^exp
        pub exp: i64,
        /// numerator of u, the weight of B (u = u_num / t_den)
        pub u_num: IBig,
        /// numerator of v, the weight of C (v = v_num / t_den)
        pub v_num: IBig,
    }

    impl Hit {
        /// `t` as an `f64` (for error measurements).
        pub fn t_f64(&self) -> f64 {
            super::ratio_f64(&self.t_num, &self.t_den) * (self.exp as f64).exp2()
        }
        /// `u` (weight of B) as an `f64`.
        pub fn u_f64(&self) -> f64 {
            super::ratio_f64(&self.u_num, &self.t_den)
        }
        /// `v` (weight of C) as an `f64`.
        pub fn v_f64(&self) -> f64 {
            super::ratio_f64(&self.v_num, &self.t_den)
        }
    }

    /// Points of `fmt` coordinates as integer vectors on one common scale
    /// (`value = integer · 2^E`, `E` the smallest exponent among them, so
    /// differences, cross and dot products compare exactly); `None` if a
    /// coordinate is not finite.
    pub fn points(fmt: FloatFormat, pts: &[[u64; 3]]) -> Option<Vec<[IBig; 3]>> {
        let vals: Option<Vec<(IBig, i64)>> =
            pts.iter().flatten().map(|&v| decode(fmt, v)).collect();
        let (int, _) = align(&vals?);
        Some(
            int.chunks(3)
                .map(|c| [c[0].clone(), c[1].clone(), c[2].clone()])
                .collect(),
        )
    }

    /// `x − y`.
    pub fn sub(x: &[IBig; 3], y: &[IBig; 3]) -> [IBig; 3] {
        [0, 1, 2].map(|i| &x[i] - &y[i])
    }

    /// `x × y`.
    pub fn cross(x: &[IBig; 3], y: &[IBig; 3]) -> [IBig; 3] {
        [
            &x[1] * &y[2] - &x[2] * &y[1],
            &x[2] * &y[0] - &x[0] * &y[2],
            &x[0] * &y[1] - &x[1] * &y[0],
        ]
    }

    /// `x · y`.
    pub fn dot(x: &[IBig; 3], y: &[IBig; 3]) -> IBig {
        &x[0] * &y[0] + &x[1] * &y[1] + &x[2] * &y[2]
    }

    /// Exact intersection of `{o + t·d : t_min ≤ t ≤ t_max}` with the closed
    /// triangle `abc`; `None` for a miss or anything not a single point.
    pub fn intersect(
        fmt: FloatFormat,
        o: [u64; 3],
        d: [u64; 3],
        tri: [[u64; 3]; 3],
        t_min: u64,
        t_max: u64,
    ) -> Option<Hit> {
        let pts = points(fmt, &[o, d, tri[0], tri[1], tri[2]])?;
        let [o, d, a, b, c] = [0, 1, 2, 3, 4].map(|k| pts[k].clone());
        let (e1, e2, s) = (sub(&b, &a), sub(&c, &a), sub(&o, &a));
        // o + t d = a + β e1 + γ e2  ⇔  [−d e1 e2] (t β γ) = s
        let pv = cross(&d, &e2);
        let det = dot(&e1, &pv);
        if det == IBig::ZERO {
            return None;
        }
        let qv = cross(&s, &e1);
        let beta = dot(&s, &pv);
        let gamma = dot(&d, &qv);
        let t = dot(&e2, &qv);
        // normalise the sign so the denominator is positive
        let (det, beta, gamma, t) = if det < IBig::ZERO {
            (-det, -beta, -gamma, -t)
        } else {
            (det, beta, gamma, t)
        };
        let inside = beta >= IBig::ZERO && gamma >= IBig::ZERO && &beta + &gamma <= det;
        if !inside {
            return None;
        }
        // t = t / det (the coordinates' scale cancels); compare with the bounds
        let within = |bound: u64, below: bool| -> bool {
            match crate::exact::ray_box::decode(fmt, bound) {
                crate::exact::ray_box::Exact::NaN => false,
                crate::exact::ray_box::Exact::PosInf => below,
                crate::exact::ray_box::Exact::NegInf => !below,
                crate::exact::ray_box::Exact::Fin { m, e } => {
                    // t/det <=> m·2^e
                    let (lhs, rhs) = if e >= 0 {
                        (t.clone(), (IBig::from(m) * &det) << (e as usize))
                    } else {
                        (t.clone() << ((-e) as usize), IBig::from(m) * &det)
                    };
                    if below {
                        lhs <= rhs
                    } else {
                        lhs >= rhs
                    }
                }
            }
        };
        (within(t_max, true) && within(t_min, false)).then_some(Hit {
            t_num: t,
            t_den: det,
            exp: 0,
            u_num: beta,
            v_num: gamma,
        })
    }
}

/// `n / d` in `f64` for big integers (a few ulps; for error measurements).
fn ratio_f64(n: &dashu::integer::IBig, d: &dashu::integer::IBig) -> f64 {
    use dashu::base::BitTest;
    // the leading 60 bits of each, and the difference of their scales (so
    // operands far beyond f64's range still give their ratio)
    let top = |x: &dashu::integer::IBig| {
        let shift = x.bit_len().saturating_sub(60);
        let head = i64::try_from(&(x >> shift)).expect("60 bits fit");
        (head as f64, shift as f64)
    };
    let ((hn, sn), (hd, sd)) = (top(n), top(d));
    hn / hd * (sn - sd).exp2()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `quotient`'s contract on both paths (binary32's native one and the
    /// exact one): NaN for a zero or non-finite divisor or a non-finite
    /// dividend, the correctly rounded quotient otherwise.
    #[test]
    fn the_quotient_is_nan_outside_its_contract() {
        let e = FloatFormat::BINARY16;
        for (fmt, one, zero, inf) in [
            (
                FloatFormat::BINARY32,
                1f32.to_bits() as u64,
                0,
                f32::INFINITY.to_bits() as u64,
            ),
            (e, 0x3c00, 0, 0x7c00),
        ] {
            let neg_zero = zero | fmt.sign_bit();
            for (n, d) in [
                (one, zero),
                (one, neg_zero),
                (zero, zero),
                (inf, one),
                (one, inf),
            ] {
                assert!(fmt.is_nan(quotient(fmt, n, d)), "{fmt:?} {n:#x} / {d:#x}");
            }
            assert_eq!(quotient(fmt, one, one), one, "{fmt:?}");
        }
        let third = (1f32 / 3.0).to_bits() as u64;
        let (one, three) = (1f32.to_bits() as u64, 3f32.to_bits() as u64);
        assert_eq!(quotient(FloatFormat::BINARY32, one, three), third);
    }
}
