//! The cull-plane tester, bit for bit (seed 001, issue #6). Specification
//! and proofs: `docs/cull.md`. Steps in the order the RTL performs them.

use crate::float::{
    add, add_down_up, classify, convert, le, lt, mul, mul_exact, Class, ExactProductFormat,
    FloatFormat, FormatError, RoundingMode,
};

const RDN: RoundingMode = RoundingMode::Down;
const RUP: RoundingMode = RoundingMode::Up;

/// The parameters of one tester instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Ray and box format `(E, F)` and its exact-product format `(E + 2, 2F + 1)`.
    pub prod: ExactProductFormat,
    /// Plane format `(Ep, Fp)`, with `Ep <= E` and `Fp <= F`.
    pub plane: FloatFormat,
    /// Number of planes per node, 1..=8.
    pub k: usize,
}

/// Why a configuration is rejected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ConfigError {
    /// The ray format has no exact-product format.
    Format(FormatError),
    /// The plane format is not contained in the ray format.
    PlaneFormat,
    /// `k` outside 1..=8.
    K(usize),
}

impl std::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ConfigError::Format(e) => write!(f, "{e}"),
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
        let prod = ExactProductFormat::new(ray).map_err(ConfigError::Format)?;
        if plane.exp_bits() > ray.exp_bits() || plane.frac_bits() > ray.frac_bits() {
            return Err(ConfigError::PlaneFormat);
        }
        if !(1..=8).contains(&k) {
            return Err(ConfigError::K(k));
        }
        Ok(Config { prod, plane, k })
    }
    /// The ray (and box) format.
    pub fn fmt(&self) -> FloatFormat {
        self.prod.narrow()
    }
    /// The product (comparison) format.
    pub fn wide(&self) -> FloatFormat {
        self.prod.wide()
    }
}

/// One cull plane: the points `x` with `n·(x − c) > w` (c the box centroid)
/// are empty. Raw bits of the plane format. `n = 0, w = 0` is the null plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Plane {
    /// normal, pointing to the empty side (need not be normalised)
    pub n: [u64; 3],
    /// distance of the plane from the box centroid along `n` (in units of |n|)
    pub w: u64,
}

/// One transaction's inputs.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CullIn {
    /// box lower corner (ray format)
    pub p_min: [u64; 3],
    /// box upper corner
    pub p_max: [u64; 3],
    /// ray origin
    pub o: [u64; 3],
    /// ray direction (any length; zero components allowed)
    pub d: [u64; 3],
    /// segment start, in units of `d`
    pub t_min: u64,
    /// segment end (may be +inf)
    pub t_max: u64,
    /// the planes, `k` of them (missing ones read as null planes)
    pub planes: Vec<Plane>,
}

/// One transaction's outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CullOut {
    /// The segment may meet the box (conservative slab test).
    pub box_hit: bool,
    /// The segment may meet the part of the box on the non-empty side of
    /// every plane: test the node's contents. `box_hit && !keep` = culled.
    pub keep: bool,
    /// Some input is NaN, or infinite where only finite values are allowed
    /// (then `box_hit = keep = 1`).
    pub invalid: bool,
}

impl CullOut {
    /// The planes (not the box) reject the ray.
    pub fn culled(&self) -> bool {
        self.box_hit && !self.keep
    }
    /// The output port packed: bit 0 box_hit, 1 keep, 2 invalid.
    pub fn to_bits(&self) -> u64 {
        self.box_hit as u64 | (self.keep as u64) << 1 | (self.invalid as u64) << 2
    }
}

/// A ratio `num / den` with `den > 0` finite; `den2` doubles the denominator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frac {
    /// numerator, ray format, may be infinite
    pub num: u64,
    /// denominator, ray format, positive and finite
    pub den: u64,
    /// the denominator is `2·den`
    pub den2: bool,
}

/// Per-plane intermediate values (ray format unless noted).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PlaneTrace {
    /// `P ≥ −2A`: upper bound of minus twice the origin's height above the plane
    pub p_hi: u64,
    /// `B_lo ≤ B = n·d`
    pub b_lo: u64,
    /// the plane is usable (P finite and B_lo > −inf, planes enabled)
    pub usable: bool,
    /// parallel (B_lo = 0) with the origin strictly on the empty side
    pub par_cull: bool,
}

/// Every intermediate value, for debugging the RTL.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Trace {
    /// per axis: direction component is zero
    pub zero: [bool; 3],
    /// per axis: mirrored (negative direction)
    pub neg: [bool; 3],
    /// entry numerators (RDN), mirrored coordinates
    pub n: [u64; 3],
    /// exit numerators (RUP)
    pub x: [u64; 3],
    /// lower bounds of `(near − ô) + (far − ô)`
    pub m_lo: [u64; 3],
    /// upper bounds
    pub m_hi: [u64; 3],
    /// per plane
    pub planes: Vec<PlaneTrace>,
    /// the largest entry of the box interval
    pub lo_box: Frac,
    /// the smallest exit of the box interval
    pub hi_box: Frac,
    /// the largest entry after the planes
    pub lo: Frac,
    /// the smallest exit after the planes
    pub hi: Frac,
    /// planes are applied (`t_min ≥ 0`)
    pub planes_on: bool,
    /// the outputs
    pub out: CullOut,
}

/// Evaluates one transaction.
pub fn eval(cfg: &Config, x: &CullIn) -> CullOut {
    eval_trace(cfg, x).out
}

/// `a ≤ b` for ratios, exactly: `a.num · b.den ≤ b.num · a.den` in the
/// product format (the factor 2 of a doubled denominator is exact there).
pub fn frac_le(cfg: &Config, a: &Frac, b: &Frac) -> bool {
    let w = cfg.wide();
    let l = dbl_if(w, mul_exact(cfg.prod, a.num, b.den), b.den2);
    let r = dbl_if(w, mul_exact(cfg.prod, b.num, a.den), a.den2);
    le(w, l, r)
}

/// `2·v` in the product format when `on` (exact: products never come near
/// the top of its range, nor into its subnormals).
pub fn dbl_if(w: FloatFormat, v: u64, on: bool) -> u64 {
    if on {
        let two = (w.bias() as u64 + 1) << w.frac_bits();
        mul(w, v, two, RoundingMode::NearestEven)
    } else {
        v
    }
}

/// Evaluates one transaction and returns every intermediate value.
pub fn eval_trace(cfg: &Config, x: &CullIn) -> Trace {
    let f = cfg.fmt();
    let w = cfg.wide();
    let pf = cfg.plane;
    let cls = |v: u64| classify(f, v);
    let sign = |v: u64| v & f.sign_bit() != 0;
    let neg_of = |v: u64| (v ^ f.sign_bit()) & f.mask();
    let abs = |v: u64| v & !f.sign_bit() & f.mask();
    let zero = f.zero(false);
    let one = (f.bias() as u64) << f.frac_bits();
    let planes: Vec<Plane> = (0..cfg.k)
        .map(|k| x.planes.get(k).copied().unwrap_or_default())
        .collect();

    // Step 1: classify.
    let mut invalid = false;
    for v in x.p_min.iter().chain(&x.p_max).chain(&x.o).chain(&x.d) {
        invalid |= matches!(cls(*v), Class::NaN | Class::Inf);
    }
    invalid |= matches!(cls(x.t_min), Class::NaN | Class::Inf);
    invalid |= cls(x.t_max) == Class::NaN;
    for p in &planes {
        for v in p.n.iter().chain([&p.w]) {
            invalid |= matches!(classify(pf, *v), Class::NaN | Class::Inf);
        }
    }
    let planes_on = !lt(f, x.t_min, zero);

    // Step 2: mirror, numerators, centroid offsets.
    let mut t = Trace {
        zero: [false; 3],
        neg: [false; 3],
        n: [0; 3],
        x: [0; 3],
        m_lo: [0; 3],
        m_hi: [0; 3],
        planes: Vec::new(),
        lo_box: Frac {
            num: 0,
            den: 0,
            den2: false,
        },
        hi_box: Frac {
            num: 0,
            den: 0,
            den2: false,
        },
        lo: Frac {
            num: 0,
            den: 0,
            den2: false,
        },
        hi: Frac {
            num: 0,
            den: 0,
            den2: false,
        },
        planes_on,
        out: CullOut {
            box_hit: true,
            keep: true,
            invalid,
        },
    };
    let mut slab_ok = true;
    let mut ad = [0u64; 3];
    for i in 0..3 {
        let s = sign(x.d[i]);
        t.neg[i] = s;
        t.zero[i] = cls(x.d[i]) == Class::Zero;
        let (near, far, oo) = if s {
            (neg_of(x.p_max[i]), neg_of(x.p_min[i]), neg_of(x.o[i]))
        } else {
            (
                x.p_min[i] & f.mask(),
                x.p_max[i] & f.mask(),
                x.o[i] & f.mask(),
            )
        };
        ad[i] = abs(x.d[i]);
        let e = add_down_up(f, near, neg_of(oo));
        let xx = add_down_up(f, far, neg_of(oo));
        t.n[i] = e.down;
        t.x[i] = xx.up;
        t.m_lo[i] = add(f, e.down, xx.down, RDN);
        t.m_hi[i] = add(f, e.up, xx.up, RUP);
        if t.zero[i] {
            slab_ok &= le(f, x.p_min[i], x.o[i]) && le(f, x.o[i], x.p_max[i]);
        }
    }

    // Step 3: per plane, P ≥ −2A and B_lo ≤ B, then its ratio.
    let unit = Frac {
        num: x.t_min & f.mask(),
        den: one,
        den2: false,
    };
    let tmax = Frac {
        num: x.t_max & f.mask(),
        den: one,
        den2: false,
    };
    let mut lo_c: Vec<Frac> = vec![unit];
    let mut hi_c: Vec<Frac> = vec![tmax];
    for i in 0..3 {
        if t.zero[i] {
            lo_c.push(unit);
            hi_c.push(tmax);
        } else {
            lo_c.push(Frac {
                num: t.n[i],
                den: ad[i],
                den2: false,
            });
            hi_c.push(Frac {
                num: t.x[i],
                den: ad[i],
                den2: false,
            });
        }
    }
    let mut par_cull = false;
    let mut lo_p = Vec::new();
    let mut hi_p = Vec::new();
    for p in &planes {
        let widen = |v: u64| convert(pf, f, v, RoundingMode::NearestEven);
        let nh: [u64; 3] = [0, 1, 2].map(|i| {
            let v = widen(p.n[i]);
            if t.neg[i] {
                neg_of(v)
            } else {
                v
            }
        });
        let mulz = |a: u64, b: u64| {
            if cls(a) == Class::Zero {
                w.zero(sign(a) != sign(b))
            } else {
                mul_exact(cfg.prod, a, b)
            }
        };
        let q: [u64; 3] = [0, 1, 2].map(|i| {
            let m = if sign(nh[i]) { t.m_lo[i] } else { t.m_hi[i] };
            mulz(nh[i], m)
        });
        let w2 = dbl_if(w, convert(pf, w, p.w, RoundingMode::NearestEven), true);
        let pw = add(w, add(w, add(w, q[0], q[1], RUP), q[2], RUP), w2, RUP);
        let p_hi = convert(w, f, pw, RUP);
        let b: [u64; 3] = [0, 1, 2].map(|i| mulz(nh[i], ad[i]));
        let bw = add(w, add(w, b[0], b[1], RDN), b[2], RDN);
        let b_lo = convert(w, f, bw, RDN);
        let usable = planes_on && p_hi != f.inf(false) && b_lo != f.inf(true);
        let bz = cls(b_lo) == Class::Zero;
        let pc = usable && bz && lt(f, p_hi, zero);
        par_cull |= pc;
        let bpos = usable && !bz && !sign(b_lo);
        let bneg = usable && !bz && sign(b_lo);
        lo_p.push(if bneg {
            Frac {
                num: neg_of(p_hi),
                den: abs(b_lo),
                den2: true,
            }
        } else {
            unit
        });
        hi_p.push(if bpos {
            Frac {
                num: p_hi,
                den: b_lo,
                den2: true,
            }
        } else {
            tmax
        });
        t.planes.push(PlaneTrace {
            p_hi,
            b_lo,
            usable,
            par_cull: pc,
        });
    }

    // Step 4: the largest entry and the smallest exit, then the planes.
    let maxf = |a: Frac, b: Frac| if frac_le(cfg, &a, &b) { b } else { a };
    let minf = |a: Frac, b: Frac| if frac_le(cfg, &a, &b) { a } else { b };
    t.lo_box = maxf(maxf(lo_c[0], lo_c[1]), maxf(lo_c[2], lo_c[3]));
    t.hi_box = minf(minf(hi_c[0], hi_c[1]), minf(hi_c[2], hi_c[3]));
    let box_hit = slab_ok && frac_le(cfg, &t.lo_box, &t.hi_box);
    t.lo = lo_p.iter().fold(t.lo_box, |a, &b| maxf(a, b));
    t.hi = hi_p.iter().fold(t.hi_box, |a, &b| minf(a, b));
    let keep = box_hit && !par_cull && frac_le(cfg, &t.lo, &t.hi);
    t.out = CullOut {
        box_hit: box_hit || invalid,
        keep: keep || invalid,
        invalid,
    };
    t
}
