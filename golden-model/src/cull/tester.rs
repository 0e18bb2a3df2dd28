//! The cull-plane tester, bit for bit (seed 001, issue #13). Specification
//! and proofs: `docs/cull.md`. Steps in the order the RTL performs them.
//!
//! Two units, as the seed stores the planes (one normal per sibling set,
//! kept with the parent, and one distance per child):
//!
//! * [`ray_terms`] (unit `cull_ray`), once per ray and parent: for each of
//!   the parent's K normals, a lower bound `no_lo` of `n·(o − r)` (`r` the
//!   parent box's lower corner, the point the distances are measured from),
//!   the sign of a lower bound `b_lo` of `n·d`, and `1/|b_lo|` rounded down
//!   and up in the *crossing format* (ray exponent, plane fraction plus
//!   [`CROSSING_GUARD_BITS`], at most the ray fraction);
//! * [`eval`] (unit `cull`), once per child: the child's K distances `w`,
//!   the ray terms and the box interval `[t_lo, t_hi]` from the box test
//!   beside it (the conservative slab: entry rounded down, exit rounded up),
//!   folded into `keep`.
//!
//! Every rounded value is rounded the way that only widens the interval,
//! so `keep = 0` only when the exact segment misses the region.

use crate::float::native::{
    add_down_up_f32, add_down_up_f32_n, mul_f32, round_exact_f64_down_up, select_f32, to_f32,
};
use crate::float::{
    add_down_up, add_down_up_generic, add_generic, classify, convert, dot3_floor,
    dot3_floor_generic, dot3_floor_operands, le, lt, mul_generic, Class, Dot3Operand, DownUp,
    FloatFormat, RoundingMode,
};
use crate::transform::{recip, recip_f64, recip_generic};

const RDN: RoundingMode = RoundingMode::Down;
const RUP: RoundingMode = RoundingMode::Up;
const RNE: RoundingMode = RoundingMode::NearestEven;

/// Fraction bits the crossing format has beyond the plane format. With the
/// plane format's own precision (0 guard bits) `n·d` and its reciprocal
/// lose a fifth of the culls (teapot, K = 4, e5m10 planes: 41.0 % of leaf
/// visits removed against 46.7 % with 8 guard bits; 46.0 % with 4, 46.5 %
/// with 6; docs/cull.md §3).
pub const CROSSING_GUARD_BITS: u32 = 8;

/// The renderer's plane format (binary16) and the crossing format it gives
/// with binary32 rays (e8m18): the binary32 fast paths are called with
/// these as constants, so that the compiler specialises them for the
/// renderer.
const B16: FloatFormat = FloatFormat::BINARY16;
const E8M18: FloatFormat = match FloatFormat::new(8, 18) {
    Ok(f) => f,
    Err(_) => panic!("e8m18"),
};

/// The parameters of one tester instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Ray and box format `(E, F)`.
    pub ray: FloatFormat,
    /// Plane format `(Ep, Fp)`, with `Ep <= E` and `Fp <= F`.
    pub plane: FloatFormat,
    /// Number of planes (shared normals) per node, 1..=8.
    pub k: usize,
}

/// Why a configuration is rejected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ConfigError {
    /// The plane format is not contained in the ray format.
    PlaneFormat,
    /// `k` outside 1..=8.
    K(usize),
}

impl std::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ConfigError::PlaneFormat => write!(
                f,
                "the plane format must not have more exponent or fraction bits than the ray format"
            ),
            ConfigError::K(k) => write!(f, "k = {k} outside 1..=8"),
        }
    }
}

impl std::error::Error for ConfigError {}

impl Config {
    /// A configuration, or why it is invalid.
    pub fn new(ray: FloatFormat, plane: FloatFormat, k: usize) -> Result<Config, ConfigError> {
        if plane.exp_bits() > ray.exp_bits() || plane.frac_bits() > ray.frac_bits() {
            return Err(ConfigError::PlaneFormat);
        }
        if !(1..=8).contains(&k) {
            return Err(ConfigError::K(k));
        }
        Ok(Config { ray, plane, k })
    }
    /// The crossing format `(E, min(F, Fp + CROSSING_GUARD_BITS))`: `b_lo`
    /// and the reciprocals.
    pub fn crossing(&self) -> FloatFormat {
        FloatFormat::new(
            self.ray.exp_bits(),
            (self.plane.frac_bits() + CROSSING_GUARD_BITS).min(self.ray.frac_bits()),
        )
        .expect("a format between the plane and the ray format exists")
    }
}

/// Which way a ray crosses a plane, from the sign of `b_lo ≤ n·d`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Crossing {
    /// `b_lo = 0`: treated as parallel (the plane culls iff the origin is
    /// strictly on its empty side).
    #[default]
    Parallel = 0,
    /// `b_lo > 0`: the ray enters the empty side; the crossing is an exit.
    Exit = 1,
    /// `b_lo < 0`: the ray leaves the empty side; the crossing is an entry.
    Entry = 2,
}

impl Crossing {
    /// The 2-bit port encoding.
    pub fn code(self) -> u64 {
        self as u64
    }
    /// From the port encoding (3 reads as parallel, as in the RTL).
    pub fn from_code(c: u64) -> Crossing {
        match c & 3 {
            1 => Crossing::Exit,
            2 => Crossing::Entry,
            _ => Crossing::Parallel,
        }
    }
}

/// The per-ray inputs of [`ray_terms`] for one parent.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct RayIn {
    /// ray origin (ray format)
    pub o: [u64; 3],
    /// ray direction (any length; zero components allowed)
    pub d: [u64; 3],
    /// the parent box's lower corner: the children's distances are measured from it
    pub r: [u64; 3],
    /// the parent's shared normals, `k` of them (plane format; missing ones read as 0)
    pub normals: Vec<[u64; 3]>,
}

/// What [`ray_terms`] computes for one normal (the `cull` unit's inputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct NormalTerm {
    /// `≤ n·(o − r)`, ray format; NaN when the ray or a normal is invalid
    pub no_lo: u64,
    /// `≤ 1/|b_lo|`, crossing format
    pub rcp_lo: u64,
    /// `≥ 1/|b_lo|`, crossing format
    pub rcp_hi: u64,
    /// the sign of `b_lo`
    pub dir: Crossing,
}

/// [`ray_terms`]' result, with its intermediate values.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RayTerms {
    /// per normal
    pub terms: Vec<NormalTerm>,
    /// `b_lo ≤ n·d` per normal (crossing format)
    pub b_lo: Vec<u64>,
    /// a NaN or infinity in `o`, `d`, `r` or a normal
    pub invalid: bool,
}

/// The per-child inputs of [`eval`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ChildIn {
    /// `≤` the segment's entry into the child's box (ray format)
    pub t_lo: u64,
    /// `≥` its exit
    pub t_hi: u64,
    /// the child's distance per normal (plane format): `n·(x − r) ≤ w` is the
    /// non-empty side; `k` of them (missing ones read as +0)
    pub w: Vec<u64>,
    /// the parent's ray terms, `k` of them (missing ones read as parallel, `no_lo = 0`)
    pub terms: Vec<NormalTerm>,
}

/// [`eval`]'s result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CullOut {
    /// The segment may meet the part of the box on the non-empty side of
    /// every plane: test the node's contents.
    pub keep: bool,
    /// Some input is NaN, or infinite where only finite values are allowed
    /// (then `keep = 1`).
    pub invalid: bool,
}

impl CullOut {
    /// The output port packed: bit 0 keep, 1 invalid.
    pub fn to_bits(&self) -> u64 {
        self.keep as u64 | (self.invalid as u64) << 1
    }
}

/// Per-plane intermediate values of [`eval`] (ray format).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PlaneTrace {
    /// `D ≥ w − no_lo`
    pub dist: u64,
    /// `q = RUP(D · rcp)`: exit bound `q`, entry bound `−q`
    pub q: u64,
    /// parallel with `D < 0`: the plane culls on its own
    pub par_cull: bool,
}

/// Every intermediate value of [`eval`], for debugging the RTL.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Trace {
    /// per plane
    pub planes: Vec<PlaneTrace>,
    /// planes apply (`t_lo ≥ 0`)
    pub planes_on: bool,
    /// the largest entry after the planes
    pub lo: u64,
    /// the smallest exit after the planes
    pub hi: u64,
    /// the outputs
    pub out: CullOut,
}

/// The ray terms of one parent's normals (unit `cull_ray`).
///
/// 1. `u = o − r` per axis, rounded down and up (`add_down_up`);
/// 2. per normal the lower bounds `no_lo ≤ n·u` (ray format) and `b_lo ≤ n·d`
///    (crossing format), each one fused three-term dot product
///    ([`dot3_floor`]: exact products, truncated toward −∞ at the lsb of the
///    product whose lsb weighs most, summed exactly, rounded down once); for
///    `n·u` each product takes the factor that bounds it from below (`u_hi`
///    where `n_i` is negative, else `u_lo`); `d` enters exactly;
/// 3. `rcp_lo = RDN(1/|b_lo|)`, `rcp_hi = RUP(1/|b_lo|)` (both +∞ for
///    `b_lo = 0`).
///
/// An invalid input gives `no_lo = NaN` for every normal (so `eval` keeps).
pub fn ray_terms(cfg: &Config, x: &RayIn) -> RayTerms {
    ray_terms_parts(cfg, &x.o, &x.d, &x.r, &x.normals)
}

/// [`ray_terms`] on borrowed parts of a [`RayIn`] (the normals not copied).
pub fn ray_terms_parts(
    cfg: &Config,
    o: &[u64; 3],
    d: &[u64; 3],
    r: &[u64; 3],
    normals: &[[u64; 3]],
) -> RayTerms {
    let mut terms = vec![NormalTerm::default(); cfg.k];
    let mut b_lo = vec![0; cfg.k];
    let invalid = normal_terms_into(cfg, o, d, r, normals, &mut terms, &mut b_lo);
    RayTerms {
        terms,
        b_lo,
        invalid,
    }
}

/// [`ray_terms`] without allocation: the first `cfg.k` entries of the
/// arrays are the terms and the `b_lo` values, then `invalid`.
#[inline]
pub fn normal_terms(
    cfg: &Config,
    o: &[u64; 3],
    d: &[u64; 3],
    r: &[u64; 3],
    normals: &[[u64; 3]],
) -> ([NormalTerm; 8], [u64; 8], bool) {
    let mut t = ([NormalTerm::default(); 8], [0u64; 8], false);
    t.2 = normal_terms_into(cfg, o, d, r, normals, &mut t.0, &mut t.1);
    t
}

/// [`ray_terms`] into the first `cfg.k` entries of `terms` and `b_lo`
/// (callers that keep the terms write them in place); returns `invalid`.
///
/// Binary32 rays with valid inputs take [`normal_terms_f32`], bit-identical
/// to [`normal_terms_generic`] (`tests/fast_paths.rs`); other inputs the
/// same steps with the dispatching operators.
#[inline]
pub fn normal_terms_into(
    cfg: &Config,
    o: &[u64; 3],
    d: &[u64; 3],
    r: &[u64; 3],
    normals: &[[u64; 3]],
    terms: &mut [NormalTerm],
    b_lo: &mut [u64],
) -> bool {
    let (terms, b_lo) = (&mut terms[..cfg.k], &mut b_lo[..cfg.k]);
    if cfg.ray == FloatFormat::BINARY32 && normal_terms_f32(cfg, o, d, r, normals, terms, b_lo) {
        return false;
    }
    normal_terms_steps(cfg, o, d, r, normals, false, terms, b_lo)
}

/// The reference [`normal_terms`]: the generic float operators, step by step.
pub fn normal_terms_generic(
    cfg: &Config,
    o: &[u64; 3],
    d: &[u64; 3],
    r: &[u64; 3],
    normals: &[[u64; 3]],
) -> ([NormalTerm; 8], [u64; 8], bool) {
    let mut t = ([NormalTerm::default(); 8], [0u64; 8], false);
    let k = cfg.k;
    t.2 = normal_terms_steps(cfg, o, d, r, normals, true, &mut t.0[..k], &mut t.1[..k]);
    t
}

/// Normal `j` of `normals` (missing ones read as 0).
fn normal(normals: &[[u64; 3]], j: usize) -> [u64; 3] {
    normals.get(j).copied().unwrap_or_default()
}

/// A NaN or infinity in `o`, `d`, `r` or one of the `k` normals (missing
/// normals read as 0).
#[inline(always)]
fn inputs_invalid(
    (f, pf, k): (FloatFormat, FloatFormat, usize),
    o: &[u64; 3],
    d: &[u64; 3],
    r: &[u64; 3],
    normals: &[[u64; 3]],
) -> bool {
    // NaN or infinity: the exponent field all ones
    let bad = |fmt: FloatFormat, v: u64| v & fmt.mask() & !fmt.sign_bit() >= fmt.inf(false);
    let mut invalid = false;
    for i in 0..3 {
        invalid |= bad(f, o[i]) | bad(f, d[i]) | bad(f, r[i]);
    }
    for n in &normals[..k.min(normals.len())] {
        invalid |= bad(pf, n[0]) | bad(pf, n[1]) | bad(pf, n[2]);
    }
    invalid
}

/// The crossing direction of `b_lo` (crossing format `cf`).
fn crossing_of(cf: FloatFormat, b_lo: u64) -> Crossing {
    if b_lo & cf.mask() & !cf.sign_bit() == 0 {
        Crossing::Parallel
    } else if b_lo & cf.sign_bit() == 0 {
        Crossing::Exit
    } else {
        Crossing::Entry
    }
}

/// The operators [`normal_terms_steps`] runs, generic or dispatching: a sum rounded down and up,
type AddDownUp = fn(FloatFormat, u64, u64) -> DownUp;
/// ... a dot product rounded down,
type Dot3Floor = fn(FloatFormat, FloatFormat, FloatFormat, [u64; 3], [u64; 3]) -> u64;
/// ... and a reciprocal.
type Recip = fn(FloatFormat, u64, RoundingMode) -> u64;

/// The steps of [`ray_terms`] with the generic operators (`generic`) or the
/// dispatching ones (their fast paths where they have one), into `terms`
/// and `b_los` (`cfg.k` entries each); returns `invalid`.
#[allow(clippy::too_many_arguments)]
fn normal_terms_steps(
    cfg: &Config,
    o: &[u64; 3],
    d: &[u64; 3],
    r: &[u64; 3],
    normals: &[[u64; 3]],
    generic: bool,
    terms: &mut [NormalTerm],
    b_los: &mut [u64],
) -> bool {
    let (f, cf, pf) = (cfg.ray, cfg.crossing(), cfg.plane);
    let (add_du, dot, rcp): (AddDownUp, Dot3Floor, Recip) = if generic {
        (add_down_up_generic, dot3_floor_generic, recip_generic)
    } else {
        (add_down_up, dot3_floor, recip)
    };
    let invalid = inputs_invalid((f, pf, cfg.k), o, d, r, normals);
    let u = [0, 1, 2].map(|i| add_du(f, o[i], f.negate(r[i])));
    for j in 0..cfg.k {
        let n = normal(normals, j).map(|v| v & pf.mask());
        let u_lo = [0, 1, 2].map(|i| {
            if n[i] & pf.sign_bit() != 0 {
                u[i].up
            } else {
                u[i].down
            }
        });
        let no_lo = dot(pf, f, f, n, u_lo);
        let b_lo = dot(pf, f, cf, n, *d);
        let mag = b_lo & !cf.sign_bit() & cf.mask();
        terms[j] = NormalTerm {
            no_lo: if invalid { f.canonical_nan() } else { no_lo },
            rcp_lo: rcp(cf, mag, RDN),
            rcp_hi: rcp(cf, mag, RUP),
            dir: crossing_of(cf, b_lo),
        };
        b_los[j] = b_lo;
    }
    invalid
}

/// [`normal_terms_into`] for binary32 rays (so the plane and the crossing
/// formats, contained in the ray format, are binary32 subgrids with E <= 8)
/// into `terms` and `b_los` (`k` entries each); false (take the steps) for an
/// invalid input or an infinite `o − r` bound. The ray's operands are
/// decoded once for all normals and both dot products
/// ([`dot3_floor_operands`], the narrow path of [`dot3_floor`]); `1/|b_lo|`
/// is one `f64` division ([`recip_f64`]) rounded both ways
/// ([`round_exact_f64_down_up`]).
fn normal_terms_f32(
    cfg: &Config,
    o: &[u64; 3],
    d: &[u64; 3],
    r: &[u64; 3],
    normals: &[[u64; 3]],
    terms: &mut [NormalTerm],
    b_los: &mut [u64],
) -> bool {
    let (pf, cf) = (cfg.plane, cfg.crossing());
    let k = cfg.k;
    if (pf, cf) == (B16, E8M18) {
        // the renderer's planes: the same code with constant formats
        normal_terms_f32_in(B16, E8M18, k, o, d, r, normals, terms, b_los)
    } else {
        normal_terms_f32_in(pf, cf, k, o, d, r, normals, terms, b_los)
    }
    .is_some()
}

/// [`normal_terms_f32`] with the plane and crossing formats `pf`, `cf` and
/// `k` planes.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn normal_terms_f32_in(
    pf: FloatFormat,
    cf: FloatFormat,
    k: usize,
    o: &[u64; 3],
    d: &[u64; 3],
    r: &[u64; 3],
    normals: &[[u64; 3]],
    terms: &mut [NormalTerm],
    b_los: &mut [u64],
) -> Option<()> {
    const B32: FloatFormat = FloatFormat::BINARY32;
    // An invalid input shows as an operand that does not decode: a NaN or
    // infinite d or normal, or an o or r that makes o − r NaN or infinite.
    let v = |x: u64| f32::from_bits(x as u32);
    let (down, up) = add_down_up_f32_n([v(o[0]), v(o[1]), v(o[2])], [-v(r[0]), -v(r[1]), -v(r[2])]);
    let op = |x: f32| Dot3Operand::of(B32, x.to_bits() as u64);
    let mut u_down = [Dot3Operand::default(); 3];
    let mut u_up = [Dot3Operand::default(); 3];
    let mut dd = [Dot3Operand::default(); 3];
    for i in 0..3 {
        u_down[i] = op(down[i])?;
        u_up[i] = op(up[i])?;
        dd[i] = Dot3Operand::of(B32, d[i])?;
    }
    for j in 0..k {
        let nj = normal(normals, j);
        let mut n = [Dot3Operand::default(); 3];
        let mut u_lo = u_down;
        for i in 0..3 {
            n[i] = Dot3Operand::of(pf, nj[i])?;
            if n[i].sig < 0 {
                u_lo[i] = u_up[i];
            }
        }
        let b_lo = dot3_floor_operands(cf, &n, &dd);
        terms[j].no_lo = dot3_floor_operands(B32, &n, &u_lo);
        terms[j].dir = crossing_of(cf, b_lo);
        b_los[j] = b_lo;
    }
    // the K divisions back to back, so that they overlap in the divider
    let mut q = [0f64; 8];
    for j in 0..k {
        q[j] = recip_f64(cf, b_los[j] & !cf.sign_bit());
    }
    for j in 0..k {
        (terms[j].rcp_lo, terms[j].rcp_hi) = round_exact_f64_down_up(cf, q[j]);
    }
    Some(())
}

/// Evaluates one child (unit `cull`).
#[inline]
pub fn eval(cfg: &Config, x: &ChildIn) -> CullOut {
    eval_parts(cfg, x.t_lo, x.t_hi, &x.w, &x.terms)
}

/// [`eval`] on borrowed parts of a [`ChildIn`] (no allocation on the fast
/// path): binary32 ray formats take the native path, bit-identical to
/// [`eval_generic`] (`tests/fast_paths.rs`), others [`eval_generic`].
pub fn eval_parts(cfg: &Config, t_lo: u64, t_hi: u64, w: &[u64], terms: &[NormalTerm]) -> CullOut {
    if cfg.ray == FloatFormat::BINARY32 {
        eval_f32(cfg, t_lo, t_hi, w, terms)
    } else {
        eval_generic(
            cfg,
            &ChildIn {
                t_lo,
                t_hi,
                w: w.to_vec(),
                terms: terms.to_vec(),
            },
        )
    }
}

/// The reference [`eval`]: the generic float operators, step by step.
pub fn eval_generic(cfg: &Config, x: &ChildIn) -> CullOut {
    eval_trace(cfg, x).out
}

/// [`eval_trace`]'s outputs for a binary32 ray format (so the plane and the
/// crossing formats, contained in it, are exact `f32`s), on values:
/// comparisons are IEEE comparisons; `D = RUP(w - no_lo)` by the two-sum
/// directed adder; `q = RUP(D · rcp)` from the exact f64 product. An invalid
/// input returns before any arithmetic (the generic `keep` is forced to 1
/// then); afterwards no value is NaN, `w` is finite and `no_lo < +inf`.
fn eval_f32(cfg: &Config, t_lo: u64, t_hi: u64, w: &[u64], terms: &[NormalTerm]) -> CullOut {
    let (pf, cf) = (cfg.plane, cfg.crossing());
    if (pf, cf) == (B16, E8M18) {
        // the renderer's planes: the same code with constant formats
        eval_f32_in(B16, E8M18, cfg.k, t_lo, t_hi, w, terms)
    } else {
        eval_f32_in(pf, cf, cfg.k, t_lo, t_hi, w, terms)
    }
}

/// [`eval_f32`] with the plane and crossing formats `pf`, `cf` and `k` planes.
#[inline(always)]
fn eval_f32_in(
    pf: FloatFormat,
    cf: FloatFormat,
    k: usize,
    t_lo: u64,
    t_hi: u64,
    w: &[u64],
    terms: &[NormalTerm],
) -> CullOut {
    let v = |x: u64| f32::from_bits(x as u32);
    let (t_lo, t_hi) = (v(t_lo), v(t_hi));
    let mut invalid = t_lo.is_nan() | t_hi.is_nan();
    // per plane: w, no_lo, rcp_lo, rcp_hi as values (k <= 8)
    let mut p = [(0f32, 0f32, 0f32, 0f32, Crossing::Parallel); 8];
    for (j, pj) in p.iter_mut().enumerate().take(k) {
        let wj = to_f32(pf, w.get(j).copied().unwrap_or_default());
        let tj = terms.get(j).copied().unwrap_or_default();
        let (no_lo, rcp_lo, rcp_hi) = (v(tj.no_lo), to_f32(cf, tj.rcp_lo), to_f32(cf, tj.rcp_hi));
        invalid |= !wj.is_finite();
        invalid |= no_lo.is_nan() | (no_lo == f32::INFINITY);
        invalid |= rcp_lo.is_nan() | rcp_hi.is_nan();
        *pj = (wj, no_lo, rcp_lo, rcp_hi, tj.dir);
    }
    if invalid {
        return CullOut {
            keep: true,
            invalid,
        };
    }
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // the generic `!lt` (NaN: true)
    let planes_on = !(t_lo < 0.0);
    let (mut lo, mut hi) = (t_lo, t_hi);
    let mut par_cull = false;
    // branch-free: the selections follow the data (mispredicted as branches)
    for &(wj, no_lo, rcp_lo, rcp_hi, dir) in &p[..k] {
        let dist = add_down_up_f32(wj, -no_lo).1;
        let q = mul_f32(dist, select_f32(0.0 < dist, rcp_hi, rcp_lo), RUP);
        par_cull |= (dir == Crossing::Parallel) & (dist < 0.0);
        // a NaN q (inf · 0) compares false: the plane is left out
        hi = select_f32((dir == Crossing::Exit) & (q < hi), q, hi);
        lo = select_f32((dir == Crossing::Entry) & (lo < -q), -q, lo);
    }
    let keep = if planes_on {
        !par_cull && lo <= hi
    } else {
        t_lo <= t_hi
    };
    CullOut {
        keep,
        invalid: false,
    }
}

/// Evaluates one child and returns every intermediate value.
///
/// 1. `invalid`: a NaN anywhere, an infinite `w`, or `no_lo = +∞`;
///    `planes_on = !(t_lo < 0)`;
/// 2. per plane `D = RUP(w − no_lo)` (ray format), `q = RUP(D · rcp)` with
///    `rcp = D > 0 ? rcp_hi : rcp_lo` (so `q ≥ D/|b_lo|` whatever the sign
///    of `D`); a NaN `q` (only from `+∞ · 0`) leaves the plane out;
/// 3. exits lower `hi = min(t_hi, q)`, entries raise `lo = max(t_lo, −q)`,
///    a parallel plane with `D < 0` culls;
/// 4. `keep = planes_on ? !par_cull ∧ lo ≤ hi : t_lo ≤ t_hi`, forced to 1
///    when `invalid`.
pub fn eval_trace(cfg: &Config, x: &ChildIn) -> Trace {
    let f = cfg.ray;
    let cf = cfg.crossing();
    let pf = cfg.plane;
    let nan = |fmt: FloatFormat, v: u64| classify(fmt, v) == Class::NaN;
    let w: Vec<u64> = (0..cfg.k)
        .map(|j| x.w.get(j).copied().unwrap_or_default())
        .collect();
    let terms: Vec<NormalTerm> = (0..cfg.k)
        .map(|j| x.terms.get(j).copied().unwrap_or_default())
        .collect();
    let mut invalid = nan(f, x.t_lo) || nan(f, x.t_hi);
    for (wj, tj) in w.iter().zip(&terms) {
        invalid |= matches!(classify(pf, *wj), Class::NaN | Class::Inf);
        invalid |= nan(f, tj.no_lo) || tj.no_lo & f.mask() == f.inf(false);
        invalid |= nan(cf, tj.rcp_lo) || nan(cf, tj.rcp_hi);
    }
    let zero = f.zero(false);
    let planes_on = !lt(f, x.t_lo, zero);
    let mut lo = x.t_lo & f.mask();
    let mut hi = x.t_hi & f.mask();
    let mut par_cull = false;
    let mut planes = Vec::new();
    for (wj, tj) in w.iter().zip(&terms) {
        let dist = add_generic(f, convert(pf, f, *wj, RNE), f.negate(tj.no_lo), RUP);
        let rcp = if lt(f, zero, dist) {
            tj.rcp_hi
        } else {
            tj.rcp_lo
        };
        let q = mul_generic(f, dist, convert(cf, f, rcp, RNE), RUP);
        let usable = !nan(f, q);
        let pc = tj.dir == Crossing::Parallel && lt(f, dist, zero);
        par_cull |= pc;
        match tj.dir {
            Crossing::Exit if usable && lt(f, q, hi) => hi = q,
            Crossing::Entry if usable && lt(f, lo, f.negate(q)) => lo = f.negate(q),
            _ => {}
        }
        planes.push(PlaneTrace {
            dist,
            q,
            par_cull: pc,
        });
    }
    let keep = if planes_on {
        !par_cull && le(f, lo, hi)
    } else {
        le(f, x.t_lo, x.t_hi)
    };
    Trace {
        planes,
        planes_on,
        lo,
        hi,
        out: CullOut {
            keep: keep || invalid,
            invalid,
        },
    }
}

/// `1/d` rounded toward zero per axis: the reciprocal the conservative slab
/// beside the cull unit takes (`golden_model::slab::eval_conservative`).
pub fn slab_reciprocal(fmt: FloatFormat, d: &[u64; 3]) -> [u64; 3] {
    d.map(|v| recip(fmt, v, RoundingMode::TowardZero))
}

/// The conservative slab beside the cull unit: `Some((t_lo, t_hi))`, its
/// entry (rounded down) and exit (rounded up), when the segment may meet the
/// box; `None` when it cannot.
pub fn box_interval(
    fmt: FloatFormat,
    p_min: &[u64; 3],
    p_max: &[u64; 3],
    o: &[u64; 3],
    inv_d: &[u64; 3],
    t_min: u64,
    t_max: u64,
) -> Option<(u64, u64)> {
    let s = crate::slab::eval_conservative(
        fmt,
        &crate::slab::SlabIn {
            p_min: *p_min,
            p_max: *p_max,
            o: *o,
            inv_d: *inv_d,
            t_min,
            t_max,
        },
    );
    s.hit.then_some((s.t_enter, s.t_exit))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The binary32 fast path is taken for a valid ray (the renderer's cull
    /// tests go through it: its results are the generic path's, so only this
    /// sees it switched off) and declined for an invalid one.
    #[test]
    fn binary32_rays_take_the_fast_path_unless_invalid() {
        let b = |x: f32| x.to_bits() as u64;
        let plane = FloatFormat::new(5, 10).expect("binary16");
        let cfg = Config::new(FloatFormat::BINARY32, plane, 2).expect("a valid configuration");
        let normals = [[0x3c00, 0, 0], [0, 0x3c00, 0]];
        let (o, r) = ([b(1.0), b(2.0), b(3.0)], [b(0.5), b(0.25), b(0.0)]);
        let mut terms = [NormalTerm::default(); 2];
        let mut b_los = [0u64; 2];
        let mut fast =
            |d: [u64; 3]| normal_terms_f32(&cfg, &o, &d, &r, &normals, &mut terms, &mut b_los);
        assert!(fast([b(0.5), b(-1.0), b(2.0)]));
        assert!(!fast([b(f32::NAN), b(-1.0), b(2.0)]));
        assert!(!fast([b(f32::INFINITY), b(-1.0), b(2.0)]));
    }
}
