//! Golden model of the silhouette-edge ray / bundle versus box tester
//! (seed 000, issue #4). The specification, with proofs, is
//! `docs/silhouette.md`; this file performs its steps in the same order with
//! the golden float operators, so the RTL can match it bit for bit.
//!
//! One function, [`eval`], tests a bundle (direction bounds `d_lo..d_hi`,
//! origin `o_lo` or bounds `o_lo..o_hi`) and yields AllHit and AnyHit in
//! parallel; a single ray is a bundle whose bounds coincide
//! ([`BundleIn::ray`]), and its hit bit is `any_hit`.
//!
//! ```
//! use golden_model::float::FloatFormat;
//! use golden_model::silhouette::{eval, BundleIn, Config, OriginMode, Rounding, Verdict};
//! let cfg = Config::new(FloatFormat::BINARY32, OriginMode::Shared, Rounding::Conservative).unwrap();
//! let b = |x: f32| x.to_bits() as u64;
//! // The seed README's edge-2 example: o = (2,-1,2), box [0,1]^3, d = (-1.5,1.5,-1.5).
//! let x = BundleIn::ray(
//!     [b(0.0); 3], [b(1.0); 3],
//!     [b(2.0), b(-1.0), b(2.0)], [b(-1.5), b(1.5), b(-1.5)],
//!     b(0.0), f32::INFINITY.to_bits() as u64,
//! );
//! let out = eval(&cfg, &x);
//! assert!(out.any_hit && out.all_hit);
//! assert_eq!(out.verdict(), Verdict::AllHit);
//! ```

use crate::float::{
    add_down_up_generic, add_generic, classify, convert, le, lt, mul_exact, Class,
    ExactProductFormat, FloatFormat, FormatError, RoundingMode,
};

/// Whether the rays of a bundle share one origin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OriginMode {
    /// One origin `o_lo` (the `o_hi` input is ignored, not even NaN-checked).
    Shared,
    /// Per-axis origin bounds `o_lo ≤ o ≤ o_hi`.
    Bounded,
}

/// How the differences `p − o` are rounded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rounding {
    /// Directed: AnyHit (and the single-ray hit) can only gain hits, AllHit
    /// can only lose them. The default and the only policy with guarantees.
    Conservative,
    /// Round to nearest even, the same value for AllHit and AnyHit (for the
    /// accuracy charts: may miss true hits).
    Nearest,
}

/// The parameters of one tester instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Input format `(E, F)` and product format `(E + 2, 2F + 1)`.
    pub prod: ExactProductFormat,
    /// Shared or bounded origin.
    pub origin: OriginMode,
    /// Rounding policy of the differences.
    pub rounding: Rounding,
}

impl Config {
    /// A configuration, or why `fmt` has no exact-product format.
    pub fn new(
        fmt: FloatFormat,
        origin: OriginMode,
        rounding: Rounding,
    ) -> Result<Config, FormatError> {
        Ok(Config {
            prod: ExactProductFormat::new(fmt)?,
            origin,
            rounding,
        })
    }
    /// The input format.
    #[inline]
    pub fn fmt(&self) -> FloatFormat {
        self.prod.narrow()
    }
    /// The product (comparison) format.
    pub fn wide(&self) -> FloatFormat {
        self.prod.wide()
    }
}

/// One transaction's inputs, raw bits of the input format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BundleIn {
    /// box lower corner
    pub p_min: [u64; 3],
    /// box upper corner
    pub p_max: [u64; 3],
    /// origin (shared mode) or lower origin bound (bounded mode)
    pub o_lo: [u64; 3],
    /// upper origin bound (bounded mode only)
    pub o_hi: [u64; 3],
    /// lower direction bound per axis
    pub d_lo: [u64; 3],
    /// upper direction bound per axis
    pub d_hi: [u64; 3],
    /// segment start, in units of the direction
    pub t_min: u64,
    /// segment end, in units of the direction
    pub t_max: u64,
}

impl BundleIn {
    /// A single ray as a bundle whose bounds coincide.
    pub fn ray(
        p_min: [u64; 3],
        p_max: [u64; 3],
        o: [u64; 3],
        d: [u64; 3],
        t_min: u64,
        t_max: u64,
    ) -> BundleIn {
        BundleIn {
            p_min,
            p_max,
            o_lo: o,
            o_hi: o,
            d_lo: d,
            d_hi: d,
            t_min,
            t_max,
        }
    }
}

/// One transaction's outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Out {
    /// AllHit: every ray of the bundle hits the box (proven).
    pub all_hit: bool,
    /// AnyHit: false only if every ray of the bundle misses (proven); for a
    /// single ray, the conservative hit bit.
    pub any_hit: bool,
    /// Some input that the mode reads is NaN (then both hit bits are 0).
    pub nan: bool,
    /// No NaN, but an origin or direction bound is infinite, or a lower
    /// bound exceeds its upper bound (then both hit bits are 0).
    pub invalid: bool,
    /// Valid input whose direction bounds straddle zero on some axis
    /// (`d_lo < 0 < d_hi`): all_hit = 0, any_hit = box and segment nonempty.
    pub mixed_sign: bool,
}

/// The three-valued bundle result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Verdict {
    /// Every ray hits.
    AllHit,
    /// Every ray misses.
    AllMiss,
    /// Not decided: test the rays one by one.
    Mixed,
}

impl Out {
    /// AllHit, AllMiss or Mixed (`all_hit` wins; the model never sets both
    /// `all_hit` and `!any_hit`).
    pub fn verdict(&self) -> Verdict {
        if self.all_hit {
            Verdict::AllHit
        } else if !self.any_hit {
            Verdict::AllMiss
        } else {
            Verdict::Mixed
        }
    }
}

/// The six silhouette edges: `(i, j)` pairs the entry (near) plane of axis
/// `i` with the exit (far) plane of axis `j`. Index k of the edge arrays in
/// [`Trace`] is this order.
pub const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];

/// Per-axis intermediate values (raw bits of the input format).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AxisTrace {
    /// s_i: the axis is mirrored (direction bounds negative).
    pub neg: bool,
    /// near plane in mirrored coordinates: `p_min` or `-p_max`.
    pub near: u64,
    /// far plane in mirrored coordinates: `p_max` or `-p_min`.
    pub far: u64,
    /// `-ô_lo`: negated lower origin bound in mirrored coordinates.
    pub m_lo: u64,
    /// `-ô_hi`: negated upper origin bound in mirrored coordinates.
    pub m_hi: u64,
    /// smallest `|d_i|` of the bundle.
    pub a: u64,
    /// largest `|d_i|` of the bundle.
    pub b: u64,
    /// AnyHit entry numerator: `near + m_hi`, rounded down (RNE if Nearest).
    pub n_any: u64,
    /// AnyHit exit numerator: `far + m_lo`, rounded up.
    pub x_any: u64,
    /// AllHit entry numerator: `near + m_lo`, rounded up.
    pub n_all: u64,
    /// AllHit exit numerator: `far + m_hi`, rounded down.
    pub x_all: u64,
}

/// The comparisons of one test (AllHit or AnyHit); products are raw bits of
/// the wide format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TestTrace {
    /// edge k, left product `N_i · |d_j|sel`.
    pub edge_l: [u64; 6],
    /// edge k, right product `X_j · |d_i|sel`.
    pub edge_r: [u64; 6],
    /// edge k passes: `edge_l <= edge_r`.
    pub edge_ok: [bool; 6],
    /// axis i distance product `t_max · |d_i|sel`.
    pub dist_r: [u64; 3],
    /// axis i passes the distance check: `widen(N_i) <= dist_r`.
    pub dist_ok: [bool; 3],
    /// axis i direction product `t_min · |d_i|sel`.
    pub dir_l: [u64; 3],
    /// axis i passes the direction check: `dir_l <= widen(X_i)`.
    pub dir_ok: [bool; 3],
    /// All twelve comparisons pass.
    pub pass: bool,
}

/// Every intermediate value of one transaction, for debugging the RTL stage
/// by stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Trace {
    /// per axis
    pub axis: [AxisTrace; 3],
    /// the box or the segment is empty
    pub empty: bool,
    /// the AnyHit comparisons
    pub any: TestTrace,
    /// the AllHit comparisons
    pub all: TestTrace,
    /// the outputs
    pub out: Out,
}

mod fast;

/// Evaluates one transaction: the native fast path for formats whose values
/// are `f32`s (E <= 8, F <= 23), else [`eval_generic`]; the same outputs
/// for every input.
#[inline]
pub fn eval(cfg: &Config, x: &BundleIn) -> Out {
    if crate::float::native::fits_f32(cfg.fmt()) {
        fast::eval(cfg, x)
    } else {
        eval_generic(cfg, x)
    }
}

/// `eval(cfg, x).any_hit` (a single ray's hit bit) without the AllHit test:
/// the fast path skips it; the same bit for every input.
#[inline]
pub fn any_hit(cfg: &Config, x: &BundleIn) -> bool {
    if crate::float::native::fits_f32(cfg.fmt()) {
        fast::any_hit(cfg, x)
    } else {
        eval_generic(cfg, x).any_hit
    }
}

/// Evaluates one transaction with the generic float operators (the reference
/// the fast path of [`eval`] is checked against).
pub fn eval_generic(cfg: &Config, x: &BundleIn) -> Out {
    eval_trace(cfg, x).out
}

/// Evaluates one transaction and returns every intermediate value.
pub fn eval_trace(cfg: &Config, x: &BundleIn) -> Trace {
    let f = cfg.fmt();
    let w = cfg.wide();
    let o_hi = match cfg.origin {
        OriginMode::Shared => x.o_lo,
        OriginMode::Bounded => x.o_hi,
    };
    let cls = |v: u64| classify(f, v);
    let is_inf = |v: u64, negative: bool| v & f.mask() == f.inf(negative);
    let zero = f.zero(false);

    // Step 1: classify the inputs.
    let mut read: Vec<u64> = Vec::with_capacity(20);
    read.extend(
        x.p_min
            .iter()
            .chain(&x.p_max)
            .chain(&x.o_lo)
            .chain(&x.d_lo)
            .chain(&x.d_hi),
    );
    if cfg.origin == OriginMode::Bounded {
        read.extend(&x.o_hi);
    }
    read.extend([x.t_min, x.t_max]);
    let nan = read.iter().any(|&v| cls(v) == Class::NaN);
    let mut invalid = false;
    for (i, &o_hi) in o_hi.iter().enumerate() {
        for v in [x.o_lo[i], o_hi, x.d_lo[i], x.d_hi[i]] {
            invalid |= cls(v) == Class::Inf;
        }
        invalid |= !le(f, x.d_lo[i], x.d_hi[i]);
        invalid |= !le(f, x.o_lo[i], o_hi);
    }
    invalid &= !nan;
    let mut empty = !le(f, x.t_min, x.t_max) || is_inf(x.t_min, false) || is_inf(x.t_max, true);
    for i in 0..3 {
        empty |=
            !le(f, x.p_min[i], x.p_max[i]) || is_inf(x.p_min[i], false) || is_inf(x.p_max[i], true);
    }
    let neg: [bool; 3] = [0, 1, 2].map(|i| lt(f, x.d_lo[i], zero));
    let pos: [bool; 3] = [0, 1, 2].map(|i| lt(f, zero, x.d_hi[i]));
    let mixed = (0..3).any(|i| neg[i] && pos[i]);

    // Step 2: mirror each axis with negative directions (sign flips only).
    let flip = |v: u64, s: bool| if s { v ^ f.sign_bit() } else { v };
    let abs = |v: u64| v & !f.sign_bit() & f.mask();
    let mut axis = [AxisTrace::default(); 3];
    for i in 0..3 {
        let s = neg[i];
        let a_t = &mut axis[i];
        a_t.neg = s;
        if s {
            a_t.near = flip(x.p_max[i], true);
            a_t.far = flip(x.p_min[i], true);
            // ô = -o, so ô_lo = -o_hi and ô_hi = -o_lo; m = -ô.
            a_t.m_lo = o_hi[i] & f.mask();
            a_t.m_hi = x.o_lo[i] & f.mask();
            a_t.a = abs(x.d_hi[i]);
            a_t.b = abs(x.d_lo[i]);
        } else {
            a_t.near = x.p_min[i] & f.mask();
            a_t.far = x.p_max[i] & f.mask();
            a_t.m_lo = flip(x.o_lo[i], true) & f.mask();
            a_t.m_hi = flip(o_hi[i], true) & f.mask();
            a_t.a = abs(x.d_lo[i]);
            a_t.b = abs(x.d_hi[i]);
        }

        // Step 3: the entry / exit numerators.
        match cfg.rounding {
            Rounding::Conservative => {
                // One exact sum each, rounded both ways (shared mode: m_lo == m_hi,
                // so `n_big`/`n_small` and `x_big`/`x_small` are the same sums).
                let n_big = add_down_up_generic(f, a_t.near, a_t.m_lo); // near - ô_lo: largest N
                let n_small = add_down_up_generic(f, a_t.near, a_t.m_hi); // near - ô_hi: smallest N
                let x_big = add_down_up_generic(f, a_t.far, a_t.m_lo); // far - ô_lo: largest X
                let x_small = add_down_up_generic(f, a_t.far, a_t.m_hi); // far - ô_hi: smallest X
                a_t.n_any = n_small.down;
                a_t.x_any = x_big.up;
                a_t.n_all = n_big.up;
                a_t.x_all = x_small.down;
            }
            Rounding::Nearest => {
                let rne = RoundingMode::NearestEven;
                a_t.n_any = add_generic(f, a_t.near, a_t.m_hi, rne);
                a_t.x_any = add_generic(f, a_t.far, a_t.m_lo, rne);
                a_t.n_all = add_generic(f, a_t.near, a_t.m_lo, rne);
                a_t.x_all = add_generic(f, a_t.far, a_t.m_hi, rne);
            }
        }
    }

    // Step 4: products and comparisons, AnyHit (best corner) and AllHit
    // (worst corner). `sel(v, lo_if_neg)`: the |d| bound picked by v's sign bit.
    let sign = |v: u64| v & f.sign_bit() != 0;
    let mulz = |a: u64, b: u64| {
        if cls(a) == Class::Zero || cls(b) == Class::Zero {
            0
        } else {
            mul_exact(cfg.prod, a, b)
        }
    };
    let widen = |v: u64| convert(f, w, v, RoundingMode::NearestEven);
    let test = |all: bool| {
        let mut t = TestTrace::default();
        let n = |i: usize| if all { axis[i].n_all } else { axis[i].n_any };
        let xx = |i: usize| if all { axis[i].x_all } else { axis[i].x_any };
        // Bound of |d_k| that makes v·|d_k| largest (want_max) or smallest.
        let pick = |v: u64, k: usize, want_max: bool| {
            if sign(v) != want_max {
                axis[k].b
            } else {
                axis[k].a
            }
        };
        for (k, &(i, j)) in EDGES.iter().enumerate() {
            // AllHit: largest left side, smallest right side; AnyHit: the opposite.
            t.edge_l[k] = mulz(n(i), pick(n(i), j, all));
            t.edge_r[k] = mulz(xx(j), pick(xx(j), i, !all));
            t.edge_ok[k] = le(w, t.edge_l[k], t.edge_r[k]);
        }
        for i in 0..3 {
            t.dist_r[i] = mulz(x.t_max, pick(x.t_max, i, !all));
            t.dist_ok[i] = le(w, widen(n(i)), t.dist_r[i]);
            t.dir_l[i] = mulz(x.t_min, pick(x.t_min, i, all));
            t.dir_ok[i] = le(w, t.dir_l[i], widen(xx(i)));
        }
        t.pass = t
            .edge_ok
            .iter()
            .chain(&t.dist_ok)
            .chain(&t.dir_ok)
            .all(|&b| b);
        t
    };
    let any = test(false);
    let all = test(true);

    // Step 5: combine.
    let ok = !nan && !invalid && !empty;
    let out = Out {
        all_hit: ok && !mixed && all.pass,
        any_hit: ok && (mixed || any.pass),
        nan,
        invalid,
        mixed_sign: !nan && !invalid && mixed,
    };
    Trace {
        axis,
        empty,
        any,
        all,
        out,
    }
}
