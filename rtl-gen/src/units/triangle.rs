//! `triangle`: a watertight ray/triangle test in Woop, Benthin and Wald's
//! formulation (2013), every product, difference and sum rounded once in one
//! rounding mode (`round`) and in one internal format ([`internal_format`]:
//! the unit's fraction width, an exponent range in which every value of the
//! datapath is zero or normal for finite inputs), so two triangles sharing
//! an edge subtract the same two rounded products in opposite order and see
//! opposite signs (or both zero) in every mode, for every finite input
//! (issues #16, #42; golden twin `golden_model::triangle`, docs/triangle.md).
//!
//! Inputs per ray: the origin `o`, the axis `kz` of the direction's largest
//! component and the shear constants `s = (d_kx/d_kz, d_ky/d_kz, 1/d_kz)`,
//! precomputed once per ray as the slab's reciprocal direction is; per
//! triangle its vertices `a`, `b`, `c`; the segment `t_min..t_max`.
//!
//! 1. `p = P − o` per vertex, rounded into the internal format;
//!    `kx = kz + 1`, `ky = kz + 2` (mod 3) select components; the shear
//!    constants and the bounds are widened into it exactly;
//! 2. ray space: `X = p_kx − RN(s_x·p_kz)`, `Y = p_ky − RN(s_y·p_kz)`, and
//!    `p_kz` itself (the scale `s_z` is applied once, to `T`);
//! 3. edge functions, two rounded products and one rounded difference:
//!    `U = RN(C_X·B_Y) − RN(C_Y·B_X)`, `V = RN(A_X·C_Y) − RN(A_Y·C_X)`,
//!    `W = RN(B_X·A_Y) − RN(B_Y·A_X)` (a directed edge `P → Q` gives
//!    `RN(Q_X·P_Y) − RN(Q_Y·P_X)`; the neighbour across it subtracts the
//!    same two rounded products the other way: the opposite sign, or both
//!    zero, which is what makes the test watertight);
//! 4. inside unless some edge function is negative and another positive
//!    (zero counts as inside); `det = (U + V) + W`,
//!    `T = s_z·((U·a_kz + V·b_kz) + W·c_kz)`, each operation rounded;
//! 5. `r = 1/det`, `t = T·r`, `u = V·r`, `v = W·r` in the internal format;
//!    `hit` iff inside, `det ≠ 0` and
//!    `t_min ≤ t ≤ t_max` (compared there) and `|t|` below `2^(emax+1)` of
//!    the unit's format; `t`, `u`, `v` rounded into the unit's format (exact
//!    in its normal range), +0 without a hit; `invalid` (and no hit) for a
//!    non-finite `o`, `s` or vertex, a NaN bound, `kz = 3`, all three edge
//!    functions zero (the ray in the triangle's plane as far as the rounded
//!    products tell: `det = 0` cannot hit a sliver the ray may cross, so the
//!    caller decides), or a hit whose `t` the format cannot hold.
//!
//! `outputs=full` outputs `t`, `u`, `v` (above); `outputs=tnum` outputs
//! `t_num = T` and `t_den = det` (values of the internal format, +0 without
//! a hit) and `outputs=hit` neither: both test the segment without a
//! division, by exact comparisons of products (`t_min·|det| <= T·sgn(det)
//! <= t_max·|det|`, and a hit with `|T| >= 2^(emax+1)·|det|` flagged), so
//! they need no reciprocal and no multipliers of `t`, `u`, `v`. The unit is
//! built as one datapath; `stages` registers are placed by the delay model
//! ([`crate::retime::balance`]), so `pipeline=plan` and `pipeline=balanced`
//! give the same registers.

use super::ports::{self, Record, Visit, Walk};
use super::{Description, AXES};
use crate::arith::float::add::{
    add_normal_module, add_same_sign_normal_module, sub_widening_normal_module,
};
use crate::arith::float::compare::compare;
use crate::arith::float::convert::convert_module;
use crate::arith::float::mul::{mul_module, mul_normal_module};
use crate::arith::float::product_compare::{
    factor_normal, product_term, single_term, start_product, term_le, Factor,
};
use crate::arith::float::unpack::unpack;
use crate::arith::float::{Format, Rounding};
use crate::arith::ports::{rounded, Operand, Pair, Source};
use crate::arith::recip::recip_module;
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;
use crate::retime::Products;

/// The `triangle` unit.
pub struct Triangle;

crate::choice! {
    /// What the triangle unit outputs.
    pub enum Outputs {
        /// hit and invalid only (the segment test of tnum)
        Hit = "hit",
        /// also t as a numerator and a denominator (no divider)
        Tnum = "tnum",
        /// also t and the barycentrics
        Full = "full",
    }
}

crate::choice! {
    /// How `outputs=hit|tnum` test the segment `t_min <= T/det <= t_max`.
    pub enum Segment {
        /// exact comparisons of products (two 24x24 products at binary32)
        Exact = "exact",
        /// conservative comparisons of base-2 logarithms (no product)
        Log = "log",
    }
}

crate::params! {
    /// The triangle unit's parameters.
    pub struct TriangleParams {
        /// exponent bits E (2..=11; at most 8 have an internal format)
        exp_bits: u32 [2..=11] = 8,
        /// fraction bits F (1 + E + F <= 64)
        frac_bits: u32 [1..=52] = 23,
        /// rounding of every operation: to nearest even, toward zero, toward +inf, toward
        /// -inf (each keeps the test watertight)
        round: Rounding = Rounding::Rne,
        /// hit: hit and invalid only; tnum: also t_num and t_den (t = t_num / t_den in the
        /// internal format, the segment test by products, no divider); full: also t and the
        /// barycentrics u (of b) and v (of c)
        outputs: Outputs = Outputs::Full,
        /// pipeline stages (latency in cycles), placed by the delay model
        stages: u32 [0..=48] = 6,
        /// split: products wider than 18 bits cut into 18x18 blocks and their sum when
        /// stages are placed (ECP5's MULT18X18D, registers between blocks and sum); whole:
        /// each product one multiplication (a 7-series DSP48E1 takes 25x18 and sums a wider
        /// product's pieces in its cascade: half the DSP48 and no LUT adders)
        products: Products = Products::Split,
        /// hit|tnum only: exact (t_min*|det| <= T*sgn(det) <= t_max*|det| by exact products) or
        /// log (conservative: base-2 logarithms as exponent and top 8 fraction bits, a margin
        /// for Mitchell's error; never rejects a t in the segment, accepts up to about 1.2x
        /// beyond a bound and flags |t| within that factor below the format's range invalid:
        /// the caller re-decides after dividing; no multiplier)
        segment: Segment = Segment::Exact,
    }
}

/// The internal format of the datapath for the unit's format `fmt`: the
/// same fraction width and the smallest exponent width (at least `fmt`'s)
/// in whose normal range every nonzero value of steps 1-4 lies for finite
/// inputs, so every rounding there is the rounding of an unbounded exponent
/// (a rounded value keeps its exact value's sign, in every mode) and the
/// operators build no subnormal or overflow logic (docs/triangle.md §2). With `g = emin − F`: differences are
/// multiples of `2^g` below `2^(emax+2)`, ray-space coordinates multiples of
/// `2^(2g)` below `2^(2·emax+4)`, edge functions and `det` multiples of
/// `2^(4g)` below `2^(4·emax+11)`, `T` a multiple of `2^(6g)` below
/// `2^(6·emax+14)`; so the internal bias is the smallest with
/// `emin' ≤ 6g` and `emax' ≥ 6·emax + 16`. `Err` when no supported
/// format has that range (more than 8 exponent bits, or 8 with more than 44 fraction bits).
pub fn internal_format(fmt: Format) -> Result<Format, String> {
    let (emin, emax, f) = (fmt.emin(), fmt.emax(), fmt.frac_bits as i64);
    let g = emin - f;
    let bias = (6 * emax + 16).max(1 - 6 * g);
    let e = (fmt.exp_bits..=11)
        .find(|&e| (1i64 << (e - 1)) > bias)
        .ok_or_else(|| {
            format!(
                "{}: the triangle unit's internal format needs an exponent bias of at least \
                 {bias}, more than 11 exponent bits (formats of up to 7 exponent bits, and of 8 \
                 with at most 44 fraction bits, have one)",
                fmt.tag()
            )
        })?;
    Format::new(e, fmt.frac_bits)
}

/// Resolved parameters.
#[derive(Debug, Clone, Copy)]
pub struct Config {
    /// the format of the inputs and of `t`, `u`, `v`
    pub fmt: Format,
    /// the format of the datapath ([`internal_format`])
    pub wide: Format,
    /// the rounding of every operation
    pub round: Rounding,
    /// what the unit outputs
    pub outputs: Outputs,
    /// pipeline registers
    pub stages: u32,
    /// how the retimer flattens products
    pub products: Products,
    /// how `hit` and `tnum` test the segment
    pub segment: Segment,
}

impl Config {
    /// `t`, `u`, `v` outputs (`outputs=full`), and the divider they need.
    pub fn full(&self) -> bool {
        self.outputs == Outputs::Full
    }
}

/// Module name.
pub fn triangle_name(cfg: &Config) -> String {
    let out = match cfg.outputs {
        Outputs::Hit => "hit",
        Outputs::Tnum => "tnum",
        Outputs::Full => "full",
    };
    let round = match cfg.round {
        Rounding::Rne => String::new(),
        r => format!("_{}", r.word()),
    };
    let products = match cfg.products {
        Products::Split => "",
        Products::Whole => "_whole",
    };
    let segment = match cfg.segment {
        Segment::Exact => "",
        Segment::Log => "_logseg",
    };
    format!(
        "triangle_{}{round}_{out}{products}{segment}_s{}",
        cfg.fmt.tag(),
        cfg.stages
    )
}

/// The data inputs: `o_* kz s_* a_* b_* c_* t_min t_max` (`*` = x, y, z;
/// `kz` is 2 bits, the others floats).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TriangleIn<T> {
    /// the ray's origin
    pub o: [T; 3],
    /// the direction's largest axis (the shear's z)
    pub kz: T,
    /// the shear constants
    pub s: [T; 3],
    /// first vertex
    pub a: [T; 3],
    /// second vertex
    pub b: [T; 3],
    /// third vertex
    pub c: [T; 3],
    /// the segment's start
    pub t_min: T,
    /// the segment's end
    pub t_max: T,
}

impl<T: Copy> Record<T> for TriangleIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(cfg.fmt.width());
        TriangleIn {
            o: w.xyz("o", ty, |r| r.o),
            kz: w.one("kz", Ty::UInt(2), |r| r.kz),
            s: w.xyz("s", ty, |r| r.s),
            a: w.xyz("a", ty, |r| r.a),
            b: w.xyz("b", ty, |r| r.b),
            c: w.xyz("c", ty, |r| r.c),
            t_min: w.one("t_min", ty, |r| r.t_min),
            t_max: w.one("t_max", ty, |r| r.t_max),
        }
    }
}

/// The data outputs: `hit invalid` and, with `outputs=full`, `t u v` (0
/// without a hit).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TriangleOut<T> {
    /// the segment hits the triangle
    pub hit: T,
    /// a non-finite input or `kz = 3`
    pub invalid: T,
    /// the hit's `t`, and its barycentric weights of `b` and `c`
    /// (`outputs=full`)
    pub t_u_v: Option<[T; 3]>,
    /// the hit's `t` as `T` and `det`, values of the internal format
    /// (`outputs=tnum`)
    pub t_num_den: Option<[T; 2]>,
}

impl<T: Copy> Record<T> for TriangleOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(cfg.fmt.width());
        let field =
            |k: usize| move |r: &Self| r.t_u_v.expect("a full unit's record has t, u, v")[k];
        TriangleOut {
            hit: w.one("hit", Ty::Bool, |r| r.hit),
            invalid: w.one("invalid", Ty::Bool, |r| r.invalid),
            t_u_v: cfg.full().then(|| {
                [
                    w.one("t", ty, field(0)),
                    w.one("u", ty, field(1)),
                    w.one("v", ty, field(2)),
                ]
            }),
            t_num_den: (cfg.outputs == Outputs::Tnum).then(|| {
                let wide = Ty::UInt(cfg.wide.width());
                let num = |k: usize| {
                    move |r: &Self| r.t_num_den.expect("a tnum unit's record has t_num, t_den")[k]
                };
                [w.one("t_num", wide, num(0)), w.one("t_den", wide, num(1))]
            }),
        }
    }
}

/// Builds the unit for `cfg`.
pub fn build(cfg: &Config) -> Module {
    let fmt = cfg.fmt;
    let wf = cfg.wide;
    let mode = cfg.round;
    let mut m = ModuleBuilder::with_handshake(triangle_name(cfg));
    m.describe(
        "Watertight ray/triangle test (Woop, Benthin, Wald 2013), every operation rounded in \
         `round` into an internal format in whose normal range every value of the datapath \
         lies for finite input: vertices minus o, sheared into ray space by (kz, s), edge \
         functions as the difference of two rounded products (a shared edge subtracts the same \
         products in opposite order: opposite signs), det and T as rounded sums of rounded \
         products, t = T * (1/det); hit iff \
         the edge functions agree in sign, det != 0 and t_min <= t <= t_max; t, u (weight of b), \
         v (weight of c) are 0 without a hit; invalid for non-finite input, kz = 3, all three \
         edge functions zero (the caller decides: det = 0 cannot hit a sliver the ray may \
         cross) or a hit whose t the format cannot hold.",
    );
    let TriangleIn {
        o,
        kz,
        s,
        a,
        b,
        c,
        t_min,
        t_max,
    } = ports::declare_inputs(&mut m, cfg);
    let verts = [a, b, c];

    // invalid: a non-finite o, s or vertex, a NaN bound, kz = 3
    let mut invalid = m.all_ones(kz);
    let points = [("o", o), ("s", s), ("a", a), ("b", b), ("c", c)];
    for (p, xyz) in points {
        for (axis, x) in AXES.iter().zip(xyz) {
            let bad = m.scope(&format!("{p}_{axis}"), |m| {
                let u = unpack(m, fmt, x);
                let bad = m.or(u.nan, u.inf);
                m.name(bad, "not_finite")
            });
            invalid = m.or(invalid, bad);
        }
    }
    for (name, x) in [("t_min", t_min), ("t_max", t_max)] {
        let u = m.scope(name, |m| unpack(m, fmt, x));
        invalid = m.or(invalid, u.nan);
    }
    let invalid = m.name(invalid, "invalid_input");

    // steps 1-2: each vertex in ray space
    let one_2 = m.uint(2, 1);
    let two_2 = m.uint(2, 2);
    let kz1 = m.eq(kz, one_2);
    let kz2 = m.eq(kz, two_2);
    // component (kz + k) mod 3 of p (kz = 3 reads as 0, as in the golden model)
    let pick = |m: &mut ModuleBuilder, p: &[Sig; 3], k: usize| {
        let x = m.mux(kz1, p[(1 + k) % 3], p[k % 3]);
        m.mux(kz2, p[(2 + k) % 3], x)
    };
    // the datapath in wf: differences rounded into it, the shear constants
    // and the bounds widened exactly
    // steps 1-4 never leave wf's normal range (internal_format), so their
    // operators build no subnormal or overflow logic
    let sub = sub_widening_normal_module(fmt, wf, mode, 0);
    let wsub = add_normal_module(wf, mode, true, 0);
    let wadd = add_normal_module(wf, mode, false, 0);
    let mul = mul_normal_module(wf, mode, 0);
    let widen = convert_module(fmt, wf, mode, 0);
    let s = [0, 1, 2].map(|i| {
        rounded(
            &mut m,
            &format!("u_widen_s_{}", AXES[i]),
            &widen,
            &Source::new(s[i]),
        )
    });
    // [X, Y, p_kz] per vertex: the shear by s_z is applied once, to T
    let mut ray_space = Vec::new();
    for (v, p) in ["a", "b", "c"].iter().zip(&verts) {
        let rel = [0, 1, 2].map(|i| {
            rounded(
                &mut m,
                &format!("u_{v}_minus_o_{}", AXES[i]),
                &sub,
                &Pair::new(p[i], o[i]),
            )
        });
        let pz = pick(&mut m, &rel, 0);
        let px = pick(&mut m, &rel, 1);
        let py = pick(&mut m, &rel, 2);
        let pz = m.name(pz, &format!("{v}_along_z"));
        let shear = |m: &mut ModuleBuilder, axis: &str, sk: Sig, pk: Sig| {
            let along = rounded(
                m,
                &format!("u_{v}_shear_{axis}_product"),
                &mul,
                &Pair::new(sk, pz),
            );
            rounded(
                m,
                &format!("u_{v}_shear_{axis}"),
                &wsub,
                &Pair::new(pk, along),
            )
        };
        let sx = shear(&mut m, "x", s[0], px);
        let sy = shear(&mut m, "y", s[1], py);
        ray_space.push([sx, sy, pz]);
    }
    let (a, b, c) = (ray_space[0], ray_space[1], ray_space[2]);

    // step 3: RN(Q_X·P_Y) − RN(Q_Y·P_X) for the directed edge P → Q (the
    // neighbour subtracts the same two rounded products the other way)
    let edge = |m: &mut ModuleBuilder, name: &str, p: [Sig; 3], q: [Sig; 3]| {
        let qx_py = rounded(
            m,
            &format!("u_edge_{name}_qx_py"),
            &mul,
            &Pair::new(q[0], p[1]),
        );
        let qy_px = rounded(
            m,
            &format!("u_edge_{name}_qy_px"),
            &mul,
            &Pair::new(q[1], p[0]),
        );
        rounded(
            m,
            &format!("u_edge_{name}"),
            &wsub,
            &Pair::new(qx_py, qy_px),
        )
    };
    let e_u = edge(&mut m, "bc", b, c);
    let e_v = edge(&mut m, "ca", c, a);
    let e_w = edge(&mut m, "ab", a, b);

    // step 4: signs (zero counts as inside; an edge function is never NaN
    // for finite input, and non-finite input is invalid whatever it gives),
    // det and T as rounded products and sums
    let mut negative = m.bool(false);
    let mut positive = m.bool(false);
    for (name, e) in [("e_u", e_u), ("e_v", e_v), ("e_w", e_w)] {
        let (lt0, gt0) = m.scope(name, |m| {
            let sign = m.msb(e);
            let mag = m.slice(e, wf.width() - 2, 0);
            let nonzero = m.any_set(mag);
            let not_sign = m.not(sign);
            let lt0 = m.and(sign, nonzero);
            let gt0 = m.and(not_sign, nonzero);
            (m.name(lt0, "below_zero"), m.name(gt0, "above_zero"))
        });
        negative = m.or(negative, lt0);
        positive = m.or(positive, gt0);
    }
    let mixed = m.and(negative, positive);
    let inside = m.not(mixed);
    let inside = m.name(inside, "inside_edges");
    // det matters only inside (a hit needs it), where U, V, W agree in
    // sign: its adders add magnitudes and never cancel
    let det_add = add_same_sign_normal_module(wf, mode, 0);
    let u_plus_v = rounded(&mut m, "u_det_uv", &det_add, &Pair::new(e_u, e_v));
    let det = rounded(&mut m, "u_det", &det_add, &Pair::new(u_plus_v, e_w));
    let weigh = |m: &mut ModuleBuilder, name: &str, e: Sig, z: Sig| {
        rounded(m, &format!("u_t_{name}"), &mul, &Pair::new(e, z))
    };
    let u_za = weigh(&mut m, "u_za", e_u, a[2]);
    let v_zb = weigh(&mut m, "v_zb", e_v, b[2]);
    let w_zc = weigh(&mut m, "w_zc", e_w, c[2]);
    let uv_z = rounded(&mut m, "u_t_uv", &wadd, &Pair::new(u_za, v_zb));
    let weighted = rounded(&mut m, "u_t_weighted", &wadd, &Pair::new(uv_z, w_zc));
    let t_num = rounded(&mut m, "u_t_num", &mul, &Pair::new(s[2], weighted));
    let det_zero = m.scope("det", |m| unpack(m, wf, det).zero);

    let (bound_min, bound_max) = (t_min, t_max);
    let t_min = rounded(&mut m, "u_widen_t_min", &widen, &Source::new(t_min));
    let t_max = rounded(&mut m, "u_widen_t_max", &widen, &Source::new(t_max));
    let (t_rounded, after_min, before_max, far) = if cfg.full() {
        // step 5: t in wf, compared with the bounds there
        let recip = recip_module(wf, mode, 0);
        // t, u, v can be subnormal in wf: the general multiplier
        let mul = mul_module(wf, mode, 0);
        let r = rounded(&mut m, "u_recip_det", &recip, &Operand { x: det });
        let t = rounded(&mut m, "u_t", &mul, &Pair::new(t_num, r));
        let (_, after_min, _) = m.scope("t_from_min", |m| compare(m, wf, t_min, t));
        let (_, before_max, _) = m.scope("t_to_max", |m| compare(m, wf, t, t_max));
        // |t| beyond fmt's largest finite value (fmt's emax + 1 in wf)
        let t_mag = m.slice(t, wf.width() - 2, 0);
        let beyond = (wf.bias() + fmt.emax() + 1) as u128;
        let first_beyond = m.uint(wf.width() - 1, beyond << wf.frac_bits);
        let far = m.ge(t_mag, first_beyond);
        (Some((t, r, mul)), after_min, before_max, far)
    } else {
        // step 5 without a division: t_min·|det| <= T·sgn(det) <= t_max·|det|
        // and 2^(emax+1)·|det| <= |T| (a t beyond fmt), exact products
        let (after_min, before_max, far) = match cfg.segment {
            Segment::Exact => segment_by_products(&mut m, cfg, det, t_num, t_min, t_max),
            Segment::Log => segment_by_logs(&mut m, cfg, det, t_num, bound_min, bound_max),
        };
        (None, after_min, before_max, far)
    };
    let far = m.name(far, "t_beyond_format");
    let valid = m.not(invalid);
    let det_ok = m.not(det_zero);
    let mut candidate = m.and(valid, inside);
    candidate = m.and(candidate, det_ok);
    candidate = m.and(candidate, after_min);
    candidate = m.and(candidate, before_max);
    let candidate = m.name(candidate, "hit_candidate");
    // a hit whose t the format cannot hold is flagged, not reported
    let flagged = m.and(candidate, far);
    // all three edge functions zero (det = 0 without mixed signs): the ray may
    // cross a sliver within rounding of its plane, which det = 0 cannot hit;
    // flagged for the caller, not missed (a closed mesh that flat would leak)
    let undecided = m.and(valid, inside);
    let undecided = m.and(undecided, det_zero);
    let undecided = m.name(undecided, "edges_all_zero");
    let flagged = m.or(flagged, undecided);
    let invalid = m.or(invalid, flagged);
    let invalid = m.name(invalid, "invalid_found");
    let near = m.not(far);
    let hit = m.and(candidate, near);
    let hit = m.name(hit, "hit_found");
    let t_u_v = t_rounded.map(|(t, r, mul)| {
        let u = rounded(&mut m, "u_bary_u", &mul, &Pair::new(e_v, r));
        let v = rounded(&mut m, "u_bary_v", &mul, &Pair::new(e_w, r));
        let narrow = convert_module(wf, fmt, mode, 0);
        let out_zero = m.uint(fmt.width(), 0);
        [("t", t), ("u", u), ("v", v)].map(|(name, x)| {
            let x = rounded(
                &mut m,
                &format!("u_narrow_{name}"),
                &narrow,
                &Source::new(x),
            );
            m.mux(hit, x, out_zero)
        })
    });
    let t_num_den = (cfg.outputs == Outputs::Tnum).then(|| {
        let out_zero = m.uint(wf.width(), 0);
        [t_num, det].map(|x| m.mux(hit, x, out_zero))
    });
    let outputs = TriangleOut {
        hit,
        invalid,
        t_u_v,
        t_num_den,
    };
    ports::declare_outputs(&mut m, cfg, &outputs);
    let datapath = m.finish().expect("triangle datapath is well formed");
    if cfg.stages == 0 {
        return datapath;
    }
    let (mut module, _) = crate::retime::balance_with(&datapath, cfg.stages, cfg.products)
        .expect("the triangle datapath is feed-forward");
    module.name = datapath.name.clone();
    module
}

/// The segment test of `outputs=hit|tnum`, without a division: `(after_min,
/// before_max, far)` for `t_min·|det| <= T' <= t_max·|det|` and
/// `2^(emax+1)·|det| <= |T'|`, `T' = T·sgn(det)`, each an exact comparison of
/// products (`det`, `T`, the bounds in the internal format).
fn segment_by_products(
    m: &mut ModuleBuilder,
    cfg: &Config,
    det: Sig,
    t_num: Sig,
    t_min: Sig,
    t_max: Sig,
) -> (Sig, Sig, Sig) {
    let wf = cfg.wide;
    // det, T, the widened bounds and the limit are zero or normal in wf
    // (internal_format), or the transaction is invalid
    let factor = factor_normal;
    let det_f = factor(m, wf, det, "det_factor");
    let unsigned = m.bool(false);
    let det_abs = Factor {
        sign: unsigned,
        ..det_f
    };
    // T' = T with the sign of det folded in, and |T|
    let t_f = factor(m, wf, t_num, "t_num_factor");
    let t_sign = m.xor(t_f.sign, det_f.sign);
    let t_signed = Factor {
        sign: t_sign,
        ..t_f
    };
    let t_abs = Factor {
        sign: unsigned,
        ..t_f
    };
    let t_signed = single_term(m, wf, &t_signed, "t_signed");
    let t_abs = single_term(m, wf, &t_abs, "t_abs");
    let limit = (wf.bias() + cfg.fmt.emax() + 1) as u128;
    let limit = m.uint(wf.width(), limit << wf.frac_bits);
    let bound = |m: &mut ModuleBuilder, name: &str, x: Sig| {
        let f = factor(m, wf, x, &format!("{name}_factor"));
        let p = start_product(m, wf, &f, &det_abs, 0, &format!("u_{name}_det"));
        product_term(m, wf, &p, &format!("{name}_det"))
    };
    let min_det = bound(m, "t_min", t_min);
    let max_det = bound(m, "t_max", t_max);
    let limit_det = bound(m, "limit", limit);
    let after_min = m.scope("t_from_min", |m| term_le(m, &min_det, &t_signed));
    let before_max = m.scope("t_to_max", |m| term_le(m, &t_signed, &max_det));
    let far = m.scope("t_far", |m| term_le(m, &limit_det, &t_abs));
    (after_min, before_max, far)
}

/// `(K, C)` of `segment=log` for `frac_bits` fraction bits: logarithms
/// carry `K = min(8, F)` fraction bits, and the margin `C` (in units of
/// `2^-K`) covers twice the error of one: Mitchell's `log2(1 + f) − f`
/// below 0.0860714, truncation below `2^-K` (`C = ⌈0.1721427·2^K⌉ + 2`:
/// 47 at K = 8).
pub fn log_margin(frac_bits: u32) -> (u32, i128) {
    let k = frac_bits.min(8);
    let c = ((1i128 << k) * 1_721_427 + 9_999_999) / 10_000_000 + 2;
    (k, c)
}

/// The segment test of `segment=log`: `(after_min, before_max, far)` from
/// base-2 logarithms, each the biased exponent and the top `K` fraction
/// bits (Mitchell's approximation), of `T`, `det` (in the internal format)
/// and the raw bounds (in the unit's). With `r = log T − log det − log
/// bound` the approximation's `r` lies within `(−1, 2)` errors of one
/// logarithm of the exact one, so comparing `r` with `±C` never rejects a
/// `t` inside the segment (`golden_model::triangle::segment_log`, whose
/// tests prove it against exact fractions). A subnormal bound is moved
/// outward to `±2^emin` or to 0, an infinite one passes or stops all.
fn segment_by_logs(
    m: &mut ModuleBuilder,
    cfg: &Config,
    det: Sig,
    t_num: Sig,
    t_min: Sig,
    t_max: Sig,
) -> (Sig, Sig, Sig) {
    let (fmt, wf) = (cfg.fmt, cfg.wide);
    let f = fmt.frac_bits;
    let (k, c) = log_margin(f);
    // T and det are zero or normal in wf (internal_format)
    let l_t = m.slice(t_num, wf.width() - 2, f - k);
    let l_t = m.name(l_t, "t_num_log");
    let l_d = m.slice(det, wf.width() - 2, f - k);
    let l_d = m.name(l_d, "det_log");
    let q = m.sub(l_t, l_d);
    let q = m.name(q, "t_log");
    let t_exp = m.slice(t_num, wf.width() - 2, f);
    let t_nonzero = m.any_set(t_exp);
    let t_zero = m.not(t_nonzero);
    let (t_sign, det_sign) = (m.msb(t_num), m.msb(det));
    let t_negative = m.xor(t_sign, det_sign);
    let t_positive = m.not(t_negative);
    let width = q.width() + 2;
    let bias = m.sint(width, (fmt.bias() as i128) << k);
    let q_unbiased = m.add(q, bias);
    let above = m.sint(width, c);
    let below = m.sint(width, -c);
    // per bound: is it infinite, its sign, whether it reads as 0, and r
    // compared with ±C
    let bound = |m: &mut ModuleBuilder, x: Sig, name: &str, upper: bool| {
        m.scope(name, |m| {
            // (a NaN bound makes the transaction invalid: its decision is not read)
            let u = unpack(m, fmt, x);
            let (infinite, sign) = (u.inf, u.sign);
            let small = m.or(u.zero, u.sub);
            // ±0, or a subnormal moved toward 0 (down for t_min, up for t_max)
            let toward_zero = if upper { sign } else { m.not(sign) };
            let sub_to_zero = m.and(u.sub, toward_zero);
            let zero = m.or(u.zero, sub_to_zero);
            let zero = m.name(zero, "reads_zero");
            // a subnormal moved away from 0 reads as ±2^emin
            let smallest = m.uint(fmt.exp_bits + k, 1u128 << k);
            let log = m.slice(x, fmt.width() - 2, f - k);
            let log = m.mux(small, smallest, log);
            let log = m.name(log, "log");
            let pad = m.uint(1, 0);
            let log = m.cat(&[pad, log]);
            let log = m.as_sint(log);
            let r = m.sub(q_unbiased, log);
            let r = m.name(r, "log_ratio");
            let gt = m.gt(r, above);
            let lt = m.lt(r, below);
            (infinite, sign, zero, gt, lt)
        })
    };
    let (h_inf, h_neg, h_zero, h_gt, h_lt) = bound(m, t_max, "t_max", true);
    let (l_inf, l_neg, l_zero, l_gt, l_lt) = bound(m, t_min, "t_min", false);
    let decide = |m: &mut ModuleBuilder, name: &str, inf, neg, zero, gt, lt, upper: bool| {
        m.scope(name, |m| {
            let pos = m.not(neg);
            // t = T/det and the bound both positive, both negative, or of
            // opposite signs; toward the bound's side within the margin
            let (same_pos, same_neg, mixed) = if upper {
                // t <= H
                let not_gt = m.not(gt);
                let not_lt = m.not(lt);
                (not_gt, not_lt, t_negative)
            } else {
                // t >= L
                let not_lt = m.not(lt);
                let not_gt = m.not(gt);
                (not_lt, not_gt, t_positive)
            };
            let both_pos = m.and(t_positive, pos);
            let both_neg = m.and(t_negative, neg);
            let x = m.mux(both_neg, same_neg, mixed);
            let x = m.mux(both_pos, same_pos, x);
            // the bound reads as 0: the sign of t decides
            let x = m.mux(zero, mixed, x);
            // t = 0: the bound's sign decides (0 <= H iff H >= 0)
            let at_zero = if upper {
                m.or(pos, zero)
            } else {
                m.or(neg, zero)
            };
            let x = m.mux(t_zero, at_zero, x);
            // an infinite bound passes all or stops all
            let all = if upper { pos } else { neg };
            m.mux(inf, all, x)
        })
    };
    let before_max = decide(m, "t_to_max", h_inf, h_neg, h_zero, h_gt, h_lt, true);
    let after_min = decide(m, "t_from_min", l_inf, l_neg, l_zero, l_gt, l_lt, false);
    // |t| >= 2^(emax+1), with the margin: flagged
    let limit = m.sint(width, (((fmt.emax() + 1) as i128) << k) - c);
    let far = m.scope("t_far", |m| {
        let beyond = m.ge(q, limit);
        m.and(t_nonzero, beyond)
    });
    (after_min, before_max, far)
}

impl Description for Triangle {
    type Params = TriangleParams;
    type Config = Config;
    const NAME: &'static str = "triangle";
    const SUMMARY: &'static str = "watertight ray/triangle test (Woop et al. 2013): hit, t and barycentrics, any rounding mode, edge functions as differences of rounded products";
    fn config(&self, p: &TriangleParams) -> Result<Config, ParamError> {
        let fmt = super::float_ops::format(p.exp_bits, p.frac_bits, Self::NAME)?;
        if p.outputs == Outputs::Full && p.segment == Segment::Log {
            return Err(ParamError::Combination(format!(
                "{}: segment=log applies to outputs=hit|tnum (full compares the divided t)",
                Self::NAME
            )));
        }
        let wide = internal_format(fmt)
            .map_err(|e| ParamError::Combination(format!("{}: {e}", Self::NAME)))?;
        Ok(Config {
            fmt,
            wide,
            round: p.round,
            outputs: p.outputs,
            stages: p.stages,
            products: p.products,
            segment: p.segment,
        })
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}
