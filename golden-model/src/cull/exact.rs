//! Exact reference for the cull tester and the builder: dyadic rationals in
//! big integers (`dashu`), no float operator of this crate on the path
//! (inputs are decoded by [`crate::exact::ray_box::decode`]).
//!
//! Two questions, answered exactly on the float inputs:
//! * [`region_hit`]: does the segment `{o + t·d : t_min ≤ t ≤ t_max}` meet
//!   the closed box intersected with every plane's closed non-empty side
//!   `{x : n·(x − r) ≤ w}` (`r` the reference point the distances are
//!   measured from: the parent box's lower corner)? A tester that culls must
//!   get `false` here (soundness: this region contains the node's geometry).
//! * [`segment_hits_triangle`]: does the segment meet a triangle?

use std::cmp::Ordering;

use dashu::base::BitTest;
use dashu::integer::IBig;

use crate::exact::extended::{ExactCmp, Extended};
use crate::exact::ray_box::{decode, Exact};
use crate::float::{round, Class, FloatFormat, RawFloat, RoundingMode};

/// The exact value `m · 2^e`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Dyadic {
    /// signed significand
    pub m: IBig,
    /// power of two
    pub e: i32,
}

impl Dyadic {
    /// Zero.
    pub fn zero() -> Dyadic {
        Dyadic {
            m: IBig::ZERO,
            e: 0,
        }
    }
    /// From a decoded finite float (panics on NaN or infinity).
    pub fn from_exact(x: &Exact) -> Dyadic {
        match *x {
            Exact::Fin { m, e } => Dyadic {
                m: IBig::from(m),
                e,
            },
            _ => panic!("not finite"),
        }
    }
    /// The finite `bits` of `fmt`; `None` for NaN or infinity.
    pub fn from_bits(fmt: FloatFormat, bits: u64) -> Option<Dyadic> {
        match decode(fmt, bits) {
            Exact::Fin { m, e } => Some(Dyadic {
                m: IBig::from(m),
                e,
            }),
            _ => None,
        }
    }
    /// From an `f32`.
    pub fn from_f32(v: f32) -> Dyadic {
        Dyadic::from_bits(FloatFormat::BINARY32, v.to_bits() as u64).expect("finite f32")
    }
    fn align(&self, other: &Dyadic) -> (IBig, IBig, i32) {
        let e = self.e.min(other.e);
        (
            &self.m << (self.e - e) as usize,
            &other.m << (other.e - e) as usize,
            e,
        )
    }
    /// `self + other`, exact.
    pub fn add(&self, other: &Dyadic) -> Dyadic {
        let (a, b, e) = self.align(other);
        Dyadic { m: a + b, e }
    }
    /// `self − other`, exact.
    pub fn sub(&self, other: &Dyadic) -> Dyadic {
        let (a, b, e) = self.align(other);
        Dyadic { m: a - b, e }
    }
    /// `self · other`, exact.
    pub fn mul(&self, other: &Dyadic) -> Dyadic {
        Dyadic {
            m: &self.m * &other.m,
            e: self.e + other.e,
        }
    }
    /// `self / 2`, exact.
    pub fn half(&self) -> Dyadic {
        Dyadic {
            m: self.m.clone(),
            e: self.e - 1,
        }
    }
    /// `-self`.
    pub fn neg(&self) -> Dyadic {
        Dyadic {
            m: -self.m.clone(),
            e: self.e,
        }
    }
    /// The sign of the value.
    pub fn signum(&self) -> Ordering {
        self.m.cmp(&IBig::ZERO)
    }
    /// Exact comparison.
    pub fn cmp_exact(&self, other: &Dyadic) -> Ordering {
        let (a, b, _) = self.align(other);
        a.cmp(&b)
    }
    /// Rounded to `fmt` in `mode` (by the crate's one rounder, fed the top 128
    /// bits and a sticky bit).
    pub fn round_to(&self, fmt: FloatFormat, mode: RoundingMode) -> u64 {
        let neg = self.m < IBig::ZERO;
        let mag = if neg { -self.m.clone() } else { self.m.clone() };
        if mag == IBig::ZERO {
            return fmt.zero(false);
        }
        let bits = mag.bit_len();
        let (sig, exp, sticky) = if bits <= 128 {
            (u128::try_from(&mag).expect("fits"), self.e, false)
        } else {
            let sh = bits - 128;
            let top = &mag >> sh;
            let back = &top << sh;
            (
                u128::try_from(&top).expect("fits"),
                self.e + sh as i32,
                back != mag,
            )
        };
        let raw = RawFloat {
            sign: neg,
            class: Class::Finite,
            exp,
            sig,
            sticky,
        };
        round(fmt, raw, mode)
    }
    /// Approximate value.
    pub fn to_f64(&self) -> f64 {
        let bits = self.m.bit_len();
        let sh = bits.saturating_sub(60);
        let top: i64 = i64::try_from(&(&self.m >> sh)).expect("fits");
        top as f64 * 2f64.powi(self.e + sh as i32)
    }
}

/// `num / den` with `den > 0`, unreduced: the exact parameter where a
/// segment crosses a slab or plane.
#[derive(Debug, Clone)]
pub struct DyadicRatio {
    /// numerator
    pub num: Dyadic,
    /// denominator, positive
    pub den: Dyadic,
}

impl ExactCmp for DyadicRatio {
    fn exact_cmp(&self, other: &DyadicRatio) -> Ordering {
        self.num
            .mul(&other.den)
            .cmp_exact(&other.num.mul(&self.den))
    }
}

/// A segment parameter: −∞, a ratio of dyadics, or +∞.
pub type Ext = Extended<DyadicRatio>;

impl Ext {
    /// A dyadic value.
    pub fn of(d: Dyadic) -> Ext {
        Ext::Fin(DyadicRatio {
            num: d,
            den: Dyadic { m: IBig::ONE, e: 0 },
        })
    }
    /// `num / den` for `den != 0`.
    pub fn ratio(num: Dyadic, den: Dyadic) -> Ext {
        if den.signum() == Ordering::Less {
            Ext::Fin(DyadicRatio {
                num: num.neg(),
                den: den.neg(),
            })
        } else {
            Ext::Fin(DyadicRatio { num, den })
        }
    }
}

/// The exact answers for one tester input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RegionResult {
    /// Inputs the tester reports as invalid (no exact answer).
    pub invalid: bool,
    /// The segment meets the closed box.
    pub box_hit: bool,
    /// The segment meets the box ∩ every plane's non-empty side.
    pub region_hit: bool,
}

/// One exact region question: a box, a segment and planes relative to `r`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct RegionIn {
    /// box lower corner (ray format)
    pub p_min: [u64; 3],
    /// box upper corner
    pub p_max: [u64; 3],
    /// ray origin
    pub o: [u64; 3],
    /// ray direction
    pub d: [u64; 3],
    /// segment start
    pub t_min: u64,
    /// segment end (may be +inf)
    pub t_max: u64,
    /// the point the distances are measured from (ray format)
    pub r: [u64; 3],
    /// plane normals (plane format), pointing to the empty side
    pub normals: Vec<[u64; 3]>,
    /// plane distances (plane format), one per normal
    pub w: Vec<u64>,
}

/// The exact region test (ray format `fmt`, plane format `pf`).
pub fn region_hit(fmt: FloatFormat, pf: FloatFormat, x: &RegionIn) -> RegionResult {
    let invalid = RegionResult {
        invalid: true,
        box_hit: true,
        region_hit: true,
    };
    let fin = |v: u64| Dyadic::from_bits(fmt, v);
    let mut p_min = Vec::new();
    let mut p_max = Vec::new();
    let mut o = Vec::new();
    let mut d = Vec::new();
    let mut r = Vec::new();
    for i in 0..3 {
        let (Some(a), Some(b), Some(c), Some(e), Some(q)) = (
            fin(x.p_min[i]),
            fin(x.p_max[i]),
            fin(x.o[i]),
            fin(x.d[i]),
            fin(x.r[i]),
        ) else {
            return invalid;
        };
        p_min.push(a);
        p_max.push(b);
        o.push(c);
        d.push(e);
        r.push(q);
    }
    let Some(t_min) = fin(x.t_min) else {
        return invalid;
    };
    let t_max = match decode(fmt, x.t_max) {
        Exact::NaN => return invalid,
        Exact::PosInf => Ext::PosInf,
        Exact::NegInf => Ext::NegInf,
        v => Ext::of(Dyadic::from_exact(&v)),
    };
    let mut planes = Vec::new();
    for (nb, &wb) in x.normals.iter().zip(&x.w) {
        let n: Vec<Option<Dyadic>> = nb.iter().map(|&v| Dyadic::from_bits(pf, v)).collect();
        let w = Dyadic::from_bits(pf, wb);
        if n.iter().any(Option::is_none) || w.is_none() {
            return invalid;
        }
        planes.push((
            n.into_iter().map(Option::unwrap).collect::<Vec<_>>(),
            w.unwrap(),
        ));
    }
    let mut lo = Ext::of(t_min);
    let mut hi = t_max;
    let mut empty = false;
    for i in 0..3 {
        match d[i].signum() {
            Ordering::Equal => {
                if p_min[i].cmp_exact(&o[i]) == Ordering::Greater
                    || o[i].cmp_exact(&p_max[i]) == Ordering::Greater
                {
                    empty = true;
                }
            }
            s => {
                let ta = Ext::ratio(p_min[i].sub(&o[i]), d[i].clone());
                let tb = Ext::ratio(p_max[i].sub(&o[i]), d[i].clone());
                let (en, ex) = if s == Ordering::Greater {
                    (ta, tb)
                } else {
                    (tb, ta)
                };
                lo = lo.max(en);
                hi = hi.min(ex);
            }
        }
    }
    let box_hit = !empty && Ext::interval_nonempty(&lo, &hi);
    if !box_hit {
        return RegionResult {
            invalid: false,
            box_hit: false,
            region_hit: false,
        };
    }
    for (n, w) in &planes {
        // s(t) = A + t·B ≤ 0 on the non-empty side.
        let mut a = w.neg();
        let mut b = Dyadic::zero();
        for i in 0..3 {
            a = a.add(&n[i].mul(&o[i].sub(&r[i])));
            b = b.add(&n[i].mul(&d[i]));
        }
        match b.signum() {
            Ordering::Equal => {
                if a.signum() == Ordering::Greater {
                    empty = true;
                }
            }
            Ordering::Greater => hi = hi.min(Ext::ratio(a.neg(), b)),
            Ordering::Less => lo = lo.max(Ext::ratio(a.neg(), b)),
        }
    }
    RegionResult {
        invalid: false,
        box_hit: true,
        region_hit: !empty && Ext::interval_nonempty(&lo, &hi),
    }
}

fn cross(a: &[Dyadic; 3], b: &[Dyadic; 3]) -> [Dyadic; 3] {
    [
        a[1].mul(&b[2]).sub(&a[2].mul(&b[1])),
        a[2].mul(&b[0]).sub(&a[0].mul(&b[2])),
        a[0].mul(&b[1]).sub(&a[1].mul(&b[0])),
    ]
}

fn dot(a: &[Dyadic; 3], b: &[Dyadic; 3]) -> Dyadic {
    a[0].mul(&b[0]).add(&a[1].mul(&b[1])).add(&a[2].mul(&b[2]))
}

fn sub3(a: &[Dyadic; 3], b: &[Dyadic; 3]) -> [Dyadic; 3] {
    [a[0].sub(&b[0]), a[1].sub(&b[1]), a[2].sub(&b[2])]
}

/// Does the closed segment `{o + t·d : t_min ≤ t ≤ t_max}` (`t_max` may be
/// `None` for +inf) meet the closed triangle `v`? Exact. A segment in the
/// triangle's plane is reported as meeting it when its line does (a
/// deliberate over-approximation, counted as a hit by the callers).
pub fn segment_hits_triangle(
    o: &[Dyadic; 3],
    d: &[Dyadic; 3],
    t_min: &Dyadic,
    t_max: Option<&Dyadic>,
    v: &[[Dyadic; 3]; 3],
) -> bool {
    let e1 = sub3(&v[1], &v[0]);
    let e2 = sub3(&v[2], &v[0]);
    let n = cross(&e1, &e2);
    let den = dot(&n, d);
    let num = dot(&n, &sub3(&v[0], o));
    if den.signum() == Ordering::Equal {
        // Parallel: a hit only if the line lies in the plane (then say yes).
        return num.signum() == Ordering::Equal;
    }
    // t = num / den must lie in [t_min, t_max].
    let t = Ext::ratio(num, den);
    if t.exact_cmp(&Ext::of(t_min.clone())) == Ordering::Less {
        return false;
    }
    if let Some(tm) = t_max {
        if t.exact_cmp(&Ext::of(tm.clone())) == Ordering::Greater {
            return false;
        }
    }
    // The line crosses the plane inside the triangle: the three signed
    // volumes (v_i − o, v_{i+1} − o, d) share a sign (zeros allowed).
    let r: Vec<[Dyadic; 3]> = v.iter().map(|p| sub3(p, o)).collect();
    let s: Vec<Ordering> = (0..3)
        .map(|i| dot(&cross(&r[i], &r[(i + 1) % 3]), d).signum())
        .collect();
    !(s.contains(&Ordering::Less) && s.contains(&Ordering::Greater))
}
