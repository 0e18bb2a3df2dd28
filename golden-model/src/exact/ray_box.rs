//! Exact ray (segment) versus axis-aligned box, by the slab method in exact
//! rational arithmetic: the semantics `docs/silhouette.md` defines, computed
//! a different way from the silhouette model (per-axis parameter intervals
//! intersected, no cross-multiplied edge tests, no rounding).
//!
//! Semantics: the box is the closed set `{x ∈ ℝ³ : p_min ≤ x ≤ p_max}`
//! (infinite bounds allowed), the ray is `{o + t·d : t ∈ ℝ, t_min ≤ t ≤ t_max}`
//! with `o`, `d` finite; hit ⟺ the two sets meet (touching counts).
//! NaN in any input: miss, `nan`. Infinite `o` or `d`: miss, `invalid`.

use std::cmp::Ordering;

use dashu::integer::IBig;

use super::extended::{ExactCmp, Extended};
use crate::float::FloatFormat;

/// A float input decoded exactly.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Exact {
    /// Not a number.
    NaN,
    /// -infinity.
    NegInf,
    /// +infinity.
    PosInf,
    /// The finite value `m · 2^e` (both zeros give `m = 0`).
    Fin {
        /// signed integer significand
        m: i64,
        /// power of two
        e: i32,
    },
}

/// Decodes `bits` of `fmt` (bits above the width ignored), independently of
/// the crate's float operators.
pub fn decode(fmt: FloatFormat, bits: u64) -> Exact {
    let f = fmt.frac_bits();
    let e_bits = fmt.exp_bits();
    let bits = bits & (u64::MAX >> (64 - (1 + e_bits + f)));
    let negative = (bits >> (e_bits + f)) & 1 == 1;
    let biased = ((bits >> f) & ((1u64 << e_bits) - 1)) as i32;
    let frac = bits & ((1u64 << f) - 1);
    let bias = (1i32 << (e_bits - 1)) - 1;
    if biased == (1 << e_bits) - 1 {
        return match (frac, negative) {
            (0, false) => Exact::PosInf,
            (0, true) => Exact::NegInf,
            _ => Exact::NaN,
        };
    }
    let (mag, e) = if biased == 0 {
        (frac, 1 - bias - f as i32)
    } else {
        (frac | (1u64 << f), biased - bias - f as i32)
    };
    let m = if negative { -(mag as i64) } else { mag as i64 };
    Exact::Fin { m, e }
}

impl Exact {
    fn is_nan(&self) -> bool {
        matches!(self, Exact::NaN)
    }
    fn is_finite(&self) -> bool {
        matches!(self, Exact::Fin { .. })
    }
    /// The value as an extended rational with denominator a power of two.
    fn to_ext(&self) -> Ext {
        match *self {
            Exact::NaN => panic!("NaN has no value"),
            Exact::NegInf => Ext::NegInf,
            Exact::PosInf => Ext::PosInf,
            Exact::Fin { m, e } => Ext::Fin(Q::dyadic(IBig::from(m), e)),
        }
    }
    fn dyadic(&self) -> (IBig, i32) {
        match *self {
            Exact::Fin { m, e } => (IBig::from(m), e),
            _ => panic!("not finite"),
        }
    }
    fn sign(&self) -> Ordering {
        match *self {
            Exact::NaN => panic!("NaN has no sign"),
            Exact::NegInf => Ordering::Less,
            Exact::PosInf => Ordering::Greater,
            Exact::Fin { m, .. } => m.cmp(&0),
        }
    }
}

/// A rational `num / den` with `den > 0` (not reduced: comparisons
/// cross-multiply, so no gcd is ever taken).
#[derive(Debug, Clone)]
struct Q {
    num: IBig,
    den: IBig,
}

impl Q {
    fn dyadic(m: IBig, e: i32) -> Q {
        if e >= 0 {
            Q {
                num: m << e as usize,
                den: IBig::ONE,
            }
        } else {
            Q {
                num: m,
                den: IBig::ONE << (-e) as usize,
            }
        }
    }
    /// `(m1·2^e1) / (m2·2^e2)`, `m2 != 0`.
    fn quotient(m1: IBig, e1: i32, m2: IBig, e2: i32) -> Q {
        let (m1, m2) = if m2 < IBig::ZERO {
            (-m1, -m2)
        } else {
            (m1, m2)
        };
        if e1 >= e2 {
            Q {
                num: m1 << (e1 - e2) as usize,
                den: m2,
            }
        } else {
            Q {
                num: m1,
                den: m2 << (e2 - e1) as usize,
            }
        }
    }
}

impl ExactCmp for Q {
    fn exact_cmp(&self, other: &Q) -> Ordering {
        (&self.num * &other.den).cmp(&(&other.num * &self.den))
    }
}

/// An extended rational: -inf, a rational, or +inf.
type Ext = Extended<Q>;

/// `(p - o) / d` for finite `o`, nonzero finite `d`, any non-NaN `p`.
fn param(p: &Exact, o: &Exact, d: &Exact) -> Ext {
    let d_pos = d.sign() == Ordering::Greater;
    match p {
        Exact::PosInf => {
            if d_pos {
                Ext::PosInf
            } else {
                Ext::NegInf
            }
        }
        Exact::NegInf => {
            if d_pos {
                Ext::NegInf
            } else {
                Ext::PosInf
            }
        }
        Exact::NaN => unreachable!(),
        Exact::Fin { .. } => {
            let (mp, ep) = p.dyadic();
            let (mo, eo) = o.dyadic();
            let e = ep.min(eo);
            let diff = (mp << (ep - e) as usize) - (mo << (eo - e) as usize);
            let (md, ed) = d.dyadic();
            Ext::Fin(Q::quotient(diff, e, md, ed))
        }
    }
}

/// A single ray (or segment), raw bits of one format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RayIn {
    /// origin
    pub o: [u64; 3],
    /// direction (need not be normalised; may have zero components)
    pub d: [u64; 3],
    /// start of the segment, in units of `d`
    pub t_min: u64,
    /// end of the segment, in units of `d`
    pub t_max: u64,
}

/// An axis-aligned box, raw bits of one format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoxIn {
    /// lower corner
    pub p_min: [u64; 3],
    /// upper corner
    pub p_max: [u64; 3],
}

/// The exact answer for one ray.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExactResult {
    /// The segment meets the closed box (false whenever a flag is set).
    pub hit: bool,
    /// Some input is NaN.
    pub nan: bool,
    /// No NaN, but `o` or `d` has an infinite component.
    pub invalid: bool,
}

/// The exact answer for `ray` against `bx`, both in `fmt`.
pub fn ray_hits_box(fmt: FloatFormat, bx: &BoxIn, ray: &RayIn) -> ExactResult {
    let dec = |b: u64| decode(fmt, b);
    let p_min = bx.p_min.map(dec);
    let p_max = bx.p_max.map(dec);
    let o = ray.o.map(dec);
    let d = ray.d.map(dec);
    let t_min = dec(ray.t_min);
    let t_max = dec(ray.t_max);
    let all: Vec<&Exact> = p_min
        .iter()
        .chain(&p_max)
        .chain(&o)
        .chain(&d)
        .chain([&t_min, &t_max])
        .collect();
    if all.iter().any(|x| x.is_nan()) {
        return ExactResult {
            hit: false,
            nan: true,
            invalid: false,
        };
    }
    if !o.iter().chain(&d).all(Exact::is_finite) {
        return ExactResult {
            hit: false,
            nan: false,
            invalid: true,
        };
    }
    let miss = ExactResult {
        hit: false,
        nan: false,
        invalid: false,
    };
    // The parameter interval [lo, hi] of the points of the segment inside
    // every slab seen so far; a slab with d_i = 0 either keeps it or empties it.
    let mut lo = t_min.to_ext();
    let mut hi = t_max.to_ext();
    for i in 0..3 {
        if d[i].sign() == Ordering::Equal {
            let inside = p_min[i].to_ext().exact_cmp(&o[i].to_ext()) != Ordering::Greater
                && o[i].to_ext().exact_cmp(&p_max[i].to_ext()) != Ordering::Greater;
            if !inside {
                return miss;
            }
            continue;
        }
        // Also covers p_min > p_max: entry > exit then, and lo ≤ hi fails.
        let ta = param(&p_min[i], &o[i], &d[i]);
        let tb = param(&p_max[i], &o[i], &d[i]);
        let (enter, exit) = if d[i].sign() == Ordering::Greater {
            (ta, tb)
        } else {
            (tb, ta)
        };
        lo = lo.max(enter);
        hi = hi.min(exit);
    }
    // Redundant with the interval logic (an inverted or infinitely far slab
    // gives an empty interval), but the empty-box rule stated directly.
    for i in 0..3 {
        if p_min[i].to_ext().exact_cmp(&p_max[i].to_ext()) == Ordering::Greater
            || p_min[i] == Exact::PosInf
            || p_max[i] == Exact::NegInf
        {
            return miss;
        }
    }
    // A real parameter must exist: lo ≤ hi with lo < +inf and hi > -inf.
    let hit = Ext::interval_nonempty(&lo, &hi);
    ExactResult {
        hit,
        nan: false,
        invalid: false,
    }
}

/// Every corner ray of a bundle's parameter box: each direction component at
/// `d_lo[i]` or `d_hi[i]`, each origin component at `o_lo[i]` or `o_hi[i]`
/// (duplicates removed), sharing `t_min`, `t_max`.
pub fn corner_rays(
    o_lo: [u64; 3],
    o_hi: [u64; 3],
    d_lo: [u64; 3],
    d_hi: [u64; 3],
    t_min: u64,
    t_max: u64,
) -> Vec<RayIn> {
    let mut out: Vec<RayIn> = Vec::with_capacity(64);
    for dm in 0..8u32 {
        for om in 0..8u32 {
            let pick = |lo: [u64; 3], hi: [u64; 3], m: u32| {
                [0, 1, 2].map(|i| if m >> i & 1 == 1 { hi[i] } else { lo[i] })
            };
            let r = RayIn {
                o: pick(o_lo, o_hi, om),
                d: pick(d_lo, d_hi, dm),
                t_min,
                t_max,
            };
            if !out.contains(&r) {
                out.push(r);
            }
        }
    }
    out
}

/// `(all_hit, any_hit)` of the exact test over an explicit list of rays.
pub fn rays_all_any(fmt: FloatFormat, bx: &BoxIn, rays: &[RayIn]) -> (bool, bool) {
    let mut all = true;
    let mut any = false;
    for r in rays {
        let h = ray_hits_box(fmt, bx, r).hit;
        all &= h;
        any |= h;
    }
    (all, any)
}
