//! Ray and bundle stimulus shared by the box testers' testbenches
//! (`silhouette`, `slab`, `triangle`).
//!
//! First a fixed list of corner cases (rays from a grid of origins on,
//! inside and around the box [0,1]³ along every direction with components in
//! {−1, −0, +0, 1}: through edges and corners, along faces, from faces and
//! from inside; flat, point, unbounded and empty boxes; every input slot set
//! to ±∞, NaN, ±0, ±max and the smallest subnormal; direction and origin
//! intervals: one-sided, touching zero, straddling zero, inverted), visited
//! in a strided order so that every prefix samples all of it. Then seeded
//! random cases: realistic scenes, random magnitudes from subnormal to near
//! overflow, grazing rays aimed at an edge or a corner and moved by a few
//! ulps, face-parallel rays with the origin on or one ulp off the plane,
//! origins on or inside the box, special-value sprinkles, small-integer
//! scenes full of exact ties, and raw random bits; each one, in a random
//! share of the vectors, widened into a bundle (direction spread by ulps or
//! relatively, sometimes straddling zero; origin boxes in bounded mode).

use super::stimulus::VectorRng;
use golden_model::float::random::{point_of_box, rand_box, rand_scale, rand_val, Random};
use golden_model::float::{add, nudge, ordered, sub, to_f64, total_key, FloatFormat, RoundingMode};
use golden_model::silhouette::BundleIn;

const RNE: RoundingMode = RoundingMode::NearestEven;

pub use golden_model::float::from_f64;

/// Kinds of random single-ray cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// box in [−1,1]³, origin in [−4,4]³, direction of length about 1
    Realistic,
    /// random box, origin and direction at random magnitudes
    Random,
    /// aimed at an edge or a corner, then moved by a few ulps
    Grazing,
    /// a zero (or −0) direction component, origin on or one ulp off a face plane
    AlongFace,
    /// origin on a face, an edge or a corner
    OriginOnBox,
    /// origin inside the box
    OriginInside,
    /// infinities, NaNs, empty and flat boxes, reversed segments sprinkled on a case
    Specials,
    /// every coordinate from {−2, −1, −0.5, −0, 0, 0.5, 1, 2}: many exact ties
    SmallInts,
    /// every input random bits
    AnyBits,
}

/// The kinds, in the order the random phase cycles through them.
pub const KINDS: [Kind; 9] = [
    Kind::Realistic,
    Kind::Random,
    Kind::Grazing,
    Kind::AlongFace,
    Kind::OriginOnBox,
    Kind::OriginInside,
    Kind::Specials,
    Kind::SmallInts,
    Kind::AnyBits,
];

/// One ray case: box, origin, direction, segment (raw bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RayCase {
    /// box lower corner
    pub p_min: [u64; 3],
    /// box upper corner
    pub p_max: [u64; 3],
    /// origin
    pub o: [u64; 3],
    /// direction
    pub d: [u64; 3],
    /// segment start
    pub t_min: u64,
    /// segment end
    pub t_max: u64,
}

/// Sprinkles one to three special values on a case.
fn sprinkle(fmt: FloatFormat, rng: &mut VectorRng, c: &mut RayCase) {
    for _ in 0..1 + rng.below(3) {
        let i = rng.below(3) as usize;
        let nan = fmt.canonical_nan() | (rng.below(2) * fmt.sign_bit()) | rng.below(2);
        match rng.below(14) {
            0 => c.p_min[i] = fmt.inf(true),
            1 => c.p_max[i] = fmt.inf(false),
            2 => c.p_min[i] = fmt.inf(rng.chance(1, 2)),
            3 => c.p_max[i] = fmt.inf(rng.chance(1, 2)),
            4 => std::mem::swap(&mut c.p_min[i], &mut c.p_max[i]),
            5 => c.p_max[i] = c.p_min[i],
            6 => c.o[i] = fmt.inf(rng.chance(1, 2)),
            7 => c.d[i] = fmt.inf(rng.chance(1, 2)),
            8 => c.t_max = fmt.inf(rng.chance(1, 2)),
            9 => c.t_min = fmt.inf(rng.chance(1, 2)),
            10 => std::mem::swap(&mut c.t_min, &mut c.t_max),
            11 => c.d = [fmt.zero(false), fmt.zero(true), fmt.zero(rng.chance(1, 2))],
            12 => {
                let k = rng.below(14) as usize;
                match k {
                    0..=2 => c.p_min[k] = nan,
                    3..=5 => c.p_max[k - 3] = nan,
                    6..=8 => c.o[k - 6] = nan,
                    9..=11 => c.d[k - 9] = nan,
                    12 => c.t_min = nan,
                    _ => c.t_max = nan,
                }
            }
            _ => c.p_min[i] = fmt.max_finite(true),
        }
    }
}

/// One random single-ray case of `kind`.
pub fn gen_ray(fmt: FloatFormat, rng: &mut VectorRng, kind: Kind) -> RayCase {
    let mut c = RayCase::default();
    match kind {
        Kind::AnyBits => {
            let w = fmt.width();
            let any = |rng: &mut VectorRng| rng.bits(w);
            c.p_min = [any(rng), any(rng), any(rng)];
            c.p_max = [any(rng), any(rng), any(rng)];
            c.o = [any(rng), any(rng), any(rng)];
            c.d = [any(rng), any(rng), any(rng)];
            c.t_min = any(rng);
            c.t_max = any(rng);
            return c;
        }
        Kind::SmallInts => {
            const POOL: [f64; 8] = [-2.0, -1.0, -0.5, -0.0, 0.0, 0.5, 1.0, 2.0];
            let pick = |rng: &mut VectorRng| from_f64(fmt, POOL[rng.below(8) as usize]);
            for i in 0..3 {
                let (a, b) = (pick(rng), pick(rng));
                let (a, b) = ordered(fmt, a, b);
                c.p_min[i] = a;
                c.p_max[i] = b;
                c.o[i] = pick(rng);
                c.d[i] = pick(rng);
            }
            c.t_min = [fmt.zero(false), fmt.inf(true), pick(rng)][rng.below(3) as usize];
            c.t_max = [fmt.inf(false), pick(rng)][rng.below(2) as usize];
            return c;
        }
        Kind::Realistic => {
            for i in 0..3 {
                let a = from_f64(fmt, rng.unit() * 2.0 - 1.0);
                let b = from_f64(fmt, rng.unit() * 2.0 - 1.0);
                let (a, b) = ordered(fmt, a, b);
                c.p_min[i] = a;
                c.p_max[i] = b;
                c.o[i] = from_f64(fmt, rng.unit() * 8.0 - 4.0);
            }
            let v = [0, 1, 2].map(|_| rng.unit() * 2.0 - 1.0);
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-9);
            c.d = v.map(|x| from_f64(fmt, x / len));
            c.t_min = fmt.zero(false);
            c.t_max = if rng.chance(1, 2) {
                fmt.inf(false)
            } else {
                from_f64(fmt, rng.unit() * 10.0)
            };
            return c;
        }
        _ => {}
    }
    let scale = rand_scale(fmt, rng);
    (c.p_min, c.p_max) = rand_box(fmt, rng, scale);
    let far = scale + rng.range(-1, 3) as i32;
    c.o = [0, 1, 2].map(|_| rand_val(fmt, rng, far, 2));
    c.d = [0, 1, 2].map(|_| {
        let s = rng.range(-4, 4) as i32;
        rand_val(fmt, rng, s, 3)
    });
    match kind {
        Kind::Grazing => {
            let axes = [3u32, 5, 6, 7][rng.below(4) as usize];
            let target = point_of_box(fmt, rng, &c.p_min, &c.p_max, axes);
            for i in 0..3 {
                c.d[i] = sub(fmt, target[i], c.o[i], RNE);
            }
            if rng.chance(1, 3) {
                // an exact aim: o = target − d with a small d
                for i in 0..3 {
                    c.d[i] = rand_val(fmt, rng, scale - 2, 1);
                    c.o[i] = sub(fmt, target[i], c.d[i], RNE);
                }
            }
            for i in 0..3 {
                if rng.chance(1, 2) {
                    c.d[i] = nudge(fmt, c.d[i], rng.range(-2, 2));
                }
                if rng.chance(1, 4) {
                    c.o[i] = nudge(fmt, c.o[i], rng.range(-1, 1));
                }
            }
        }
        Kind::AlongFace => {
            let i = rng.below(3) as usize;
            c.d[i] = fmt.zero(rng.chance(1, 2));
            if rng.chance(1, 3) {
                let j = (i + 1 + rng.below(2) as usize) % 3;
                c.d[j] = fmt.zero(rng.chance(1, 2));
            }
            let on = if rng.chance(1, 2) {
                c.p_min[i]
            } else {
                c.p_max[i]
            };
            c.o[i] = nudge(fmt, on, [0, 0, 0, -1, 1][rng.below(5) as usize]);
        }
        Kind::OriginOnBox => {
            let axes = 1 + rng.below(7) as u32;
            c.o = point_of_box(fmt, rng, &c.p_min, &c.p_max, axes);
        }
        Kind::OriginInside => c.o = point_of_box(fmt, rng, &c.p_min, &c.p_max, 0),
        _ => {}
    }
    if rng.chance(1, 10) {
        let i = rng.below(3) as usize;
        c.d[i] = fmt.zero(rng.chance(1, 2));
    }
    c.t_min = match rng.below(8) {
        0 => fmt.inf(true),
        1 => rand_val(fmt, rng, 0, 3),
        2 => fmt.zero(true),
        _ => fmt.zero(false),
    };
    c.t_max = match rng.below(6) {
        0 | 1 => {
            let s = rng.range(-3, 6) as i32;
            rand_val(fmt, rng, s, 2) & !fmt.sign_bit()
        }
        2 => rand_val(fmt, rng, 0, 8),
        _ => fmt.inf(false),
    };
    if kind == Kind::Specials {
        sprinkle(fmt, rng, &mut c);
    }
    c
}

/// Widens a ray into a bundle: direction bounds spread by a few ulps or
/// relatively (sign kept, unless `allow_mixed` picks a straddling interval),
/// origin bounds in `bounded` mode.
pub fn bundle_of(
    fmt: FloatFormat,
    rng: &mut VectorRng,
    c: &RayCase,
    bounded: bool,
    allow_mixed: bool,
) -> BundleIn {
    let mut b = BundleIn::ray(c.p_min, c.p_max, c.o, c.d, c.t_min, c.t_max);
    let how = rng.below(4);
    for i in 0..3 {
        let d = c.d[i];
        let (lo, hi) = match how {
            0 => (d, d),
            1 => (
                nudge(fmt, d, -(rng.below(4) as i64)),
                nudge(fmt, d, rng.below(4) as i64),
            ),
            _ => {
                let k = rng.range(1, 8) as i32;
                let delta = from_f64(fmt, to_f64(fmt, d).abs() * 2f64.powi(-k) * rng.unit());
                (sub(fmt, d, delta, RNE), add(fmt, d, delta, RNE))
            }
        };
        let (mut lo, mut hi) = ordered(fmt, lo, hi);
        if allow_mixed && rng.chance(1, 10) {
            lo = nudge(fmt, fmt.zero(true), -(rng.below(3) as i64) - 1);
            hi = nudge(fmt, fmt.zero(false), rng.below(3) as i64 + 1);
        } else {
            // keep the sign of the centre (a zero centre stays one-sided)
            let negative = d & fmt.sign_bit() != 0;
            if negative && total_key(fmt, hi) > total_key(fmt, fmt.zero(true)) {
                hi = fmt.zero(true);
            }
            if !negative && total_key(fmt, lo) < total_key(fmt, fmt.zero(false)) {
                lo = fmt.zero(false);
            }
        }
        b.d_lo[i] = lo;
        b.d_hi[i] = hi;
        if bounded && rng.chance(2, 3) {
            let ov = to_f64(fmt, c.o[i]);
            let width = (to_f64(fmt, c.p_max[i]) - to_f64(fmt, c.p_min[i])).abs();
            let k = rng.range(2, 20) as i32;
            let eps = (ov.abs() * 2f64.powi(-k) + width * 0.1) * rng.unit();
            let eps = from_f64(fmt, if eps.is_finite() { eps } else { 1.0 });
            let (a, z) = match rng.below(4) {
                0 => (c.o[i], add(fmt, c.o[i], eps, RNE)),
                1 => (sub(fmt, c.o[i], eps, RNE), c.o[i]),
                _ => (sub(fmt, c.o[i], eps, RNE), add(fmt, c.o[i], eps, RNE)),
            };
            b.o_lo[i] = a;
            b.o_hi[i] = z;
        }
    }
    b
}

/// Small values of the corner grid.
fn small(fmt: FloatFormat, v: f64) -> u64 {
    from_f64(fmt, v)
}

/// Every `[x, y, z]` with each coordinate from `values`, in the order three
/// nested loops visit them (`x` slowest): the corner cases' grids.
fn grid3<T: Copy>(values: &[T]) -> impl Iterator<Item = [T; 3]> + '_ {
    values.iter().flat_map(move |&x| {
        values
            .iter()
            .flat_map(move |&y| values.iter().map(move |&z| [x, y, z]))
    })
}

/// The corner cases, in a fixed order.
pub fn corner_cases(fmt: FloatFormat, bounded: bool) -> Vec<BundleIn> {
    let s = |v: f64| small(fmt, v);
    let inf = |n: bool| fmt.inf(n);
    let zero3 = [s(0.0); 3];
    let one3 = [s(1.0); 3];
    let mut out = Vec::new();
    let ray = |p_min: [u64; 3], p_max: [u64; 3], o: [u64; 3], d: [u64; 3], t0: u64, t1: u64| {
        BundleIn::ray(p_min, p_max, o, d, t0, t1)
    };
    // 1. The grid: box [0,1]^3; origins on, inside and around it; directions
    //    through edges and corners, along faces, with ±0 components.
    let os = [-1.0, -0.0, 0.0, 0.5, 1.0, 2.0].map(s);
    let ds = [-1.0, -0.0, 0.0, 1.0].map(s);
    for o in grid3(&os) {
        for d in grid3(&ds) {
            out.push(ray(zero3, one3, o, d, s(0.0), inf(false)));
        }
    }
    // 2. Segments that start or end on the box, lines, reversed segments.
    let segments = [
        (s(0.0), s(1.0)),
        (s(1.0), s(2.0)),
        (inf(true), inf(false)),
        (s(-1.0), s(0.0)),
        (s(0.5), s(0.5)),
        (s(1.0), s(0.5)),
        (inf(false), inf(false)),
        (inf(true), inf(true)),
        (s(-0.0), s(0.0)),
    ];
    let os2 = [-1.0, 0.0, 0.5, 2.0].map(s);
    let ds2 = [-1.0, 0.0, 1.0].map(s);
    for (t0, t1) in segments {
        for ox in os2 {
            for oy in os2 {
                for dx in ds2 {
                    for dy in ds2 {
                        out.push(ray(zero3, one3, [ox, oy, s(0.5)], [dx, dy, s(1.0)], t0, t1));
                    }
                }
            }
        }
    }
    // 3. Flat, point, unbounded and empty boxes.
    let boxes = [
        ([s(0.5), s(0.0), s(0.0)], [s(0.5), s(1.0), s(1.0)]),
        ([s(0.5); 3], [s(0.5); 3]),
        ([inf(true), s(0.0), s(0.0)], [s(0.0), s(1.0), inf(false)]),
        ([inf(true); 3], [inf(false); 3]),
        ([s(1.0), s(0.0), s(0.0)], [s(0.0), s(1.0), s(1.0)]),
        ([inf(false), s(0.0), s(0.0)], [inf(false), s(1.0), s(1.0)]),
        ([s(0.0), inf(true), s(0.0)], [s(1.0), inf(true), s(1.0)]),
        ([s(-0.0); 3], [s(0.0); 3]),
    ];
    let os3 = [-1.0, 0.5, 2.0].map(s);
    for (lo, hi) in boxes {
        for o in grid3(&os3) {
            for d in grid3(&ds2) {
                out.push(ray(lo, hi, o, d, s(0.0), inf(false)));
            }
        }
    }
    // 4. Every input slot set to every special value, on a few base cases.
    let specials = [
        inf(false),
        inf(true),
        fmt.canonical_nan(),
        fmt.canonical_nan() | fmt.sign_bit() | 1,
        fmt.zero(false),
        fmt.zero(true),
        fmt.max_finite(false),
        fmt.max_finite(true),
        fmt.min_subnormal(false),
        fmt.min_subnormal(true),
    ];
    let bases = [
        ray(
            zero3,
            one3,
            [s(-1.0), s(0.5), s(0.5)],
            [s(1.0), s(0.0), s(0.0)],
            s(0.0),
            inf(false),
        ),
        ray(
            zero3,
            one3,
            [s(2.0), s(2.0), s(2.0)],
            [s(-1.0), s(-1.0), s(-1.0)],
            s(0.0),
            inf(false),
        ),
        ray(
            zero3,
            one3,
            [s(0.5), s(0.5), s(0.5)],
            [s(0.5), s(-1.0), s(2.0)],
            s(-1.0),
            s(1.0),
        ),
        ray(
            zero3,
            one3,
            [s(2.0), s(0.5), s(0.5)],
            [s(1.0), s(0.0), s(0.0)],
            s(0.0),
            inf(false),
        ),
    ];
    for base in bases {
        for slot in 0..20 {
            for &v in &specials {
                let mut b = base;
                match slot {
                    0..=2 => b.p_min[slot] = v,
                    3..=5 => b.p_max[slot - 3] = v,
                    6..=8 => {
                        b.o_lo[slot - 6] = v;
                        b.o_hi[slot - 6] = v;
                    }
                    9..=11 => {
                        b.d_lo[slot - 9] = v;
                        b.d_hi[slot - 9] = v;
                    }
                    12..=14 => b.d_lo[slot - 12] = v,
                    15..=17 => b.d_hi[slot - 15] = v,
                    18 => b.t_min = v,
                    _ => b.t_max = v,
                }
                out.push(b);
                if bounded && (6..=8).contains(&slot) {
                    let mut b2 = base;
                    b2.o_hi[slot - 6] = v;
                    out.push(b2);
                }
            }
        }
    }
    // 5. Direction intervals: negative, touching zero, zero, positive,
    //    straddling, inverted; origin boxes in bounded mode.
    let dint = [
        (-1.0, -0.5),
        (-1.0, -0.0),
        (-0.0, 0.0),
        (0.0, 0.0),
        (0.0, 1.0),
        (0.5, 1.0),
        (-1.0, 1.0),
        (1.0, 0.5),
    ]
    .map(|(a, b)| (s(a), s(b)));
    let origins = [
        [-1.0, 0.5, 0.5],
        [2.0, 2.0, 2.0],
        [0.5, 0.5, 0.5],
        [-0.5, -0.5, 1.5],
    ]
    .map(|o| o.map(s));
    for o in origins {
        for d in grid3(&dint) {
            let mut b = ray(zero3, one3, o, zero3, s(0.0), inf(false));
            b.d_lo = d.map(|(lo, _)| lo);
            b.d_hi = d.map(|(_, hi)| hi);
            out.push(b);
        }
    }
    if bounded {
        let oint = [
            (0.5, 0.5),
            (-1.0, -0.5),
            (0.25, 0.75),
            (0.5, 2.0),
            (2.0, 3.0),
            (1.0, 0.0),
        ]
        .map(|(a, b)| (s(a), s(b)));
        let dsets = [
            ([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            ([0.5, 0.5, 0.5], [1.0, 1.0, 1.0]),
            ([-1.0, -1.0, 0.5], [-0.5, -0.5, 1.0]),
            ([-0.0, 0.0, 1.0], [0.0, 0.5, 1.0]),
            ([-1.0, 0.5, -1.0], [1.0, 1.0, -0.5]),
        ]
        .map(|(a, b)| (a.map(s), b.map(s)));
        for o in grid3(&oint) {
            for (dl, dh) in dsets {
                let mut b = ray(zero3, one3, zero3, zero3, s(0.0), inf(false));
                b.o_lo = o.map(|(lo, _)| lo);
                b.o_hi = o.map(|(_, hi)| hi);
                b.d_lo = dl;
                b.d_hi = dh;
                out.push(b);
            }
        }
    }
    out
}

/// A stride coprime with `n`, near `n` times the golden ratio, so that the
/// corner cases visited in order `k·stride mod n` spread over the whole list.
pub(crate) fn coprime_stride(n: u64) -> u64 {
    let mut s = ((n as f64) * 0.618_033_988_75) as u64 | 1;
    while gcd(s, n) != 1 {
        s += 2;
    }
    s.max(1)
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}
