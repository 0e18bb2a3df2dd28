//! Shared generators for the silhouette tests: a small deterministic RNG,
//! float construction in any format, and adversarial ray / bundle makers.
#![allow(dead_code)]

use golden_model::exact::ray_box::{corner_rays, BoxIn, RayIn};
use golden_model::float::random;
pub use golden_model::float::random::Random;
pub use golden_model::float::random::{between, rand_scale, rand_val};
use golden_model::float::{add, mul, sub, FloatFormat, RoundingMode};
pub use golden_model::float::{nudge, ordered, to_f64, total_key};
use golden_model::silhouette::BundleIn;

/// splitmix64.
#[derive(Clone)]
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    pub fn below(&mut self, n: u64) -> u64 {
        ((self.next() as u128 * n as u128) >> 64) as u64
    }
}

impl Random for Rng {
    fn next_u64(&mut self) -> u64 {
        self.next()
    }
    fn below(&mut self, n: u64) -> u64 {
        Rng::below(self, n)
    }
}

/// A random nonempty box at `scale` (sometimes flat on an axis).
pub fn rand_box(fmt: FloatFormat, rng: &mut Rng, scale: i32) -> BoxIn {
    let (p_min, p_max) = random::rand_box(fmt, rng, scale);
    BoxIn { p_min, p_max }
}

/// A point chosen on the box: each coordinate a bound, or a value inside.
pub fn point_on_box(fmt: FloatFormat, rng: &mut Rng, bx: &BoxIn, boundary_axes: u32) -> [u64; 3] {
    random::point_of_box(fmt, rng, &bx.p_min, &bx.p_max, boundary_axes)
}

pub const RNE: RoundingMode = RoundingMode::NearestEven;

pub use golden_model::float::from_f64;

/// The kinds of single-ray cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// random box, origin, direction
    Random,
    /// aimed at an edge or corner point, then perturbed by a few ulps
    Grazing,
    /// a zero (or -0) direction component with the origin on / next to a face plane
    AlongFace,
    /// the origin on a face, edge or corner
    OriginOnBox,
    /// the origin inside the box
    OriginInside,
    /// inf / NaN / empty-box / empty-segment sprinkles on any of the above
    Specials,
}

pub const KINDS: [Kind; 6] = [
    Kind::Random,
    Kind::Grazing,
    Kind::AlongFace,
    Kind::OriginOnBox,
    Kind::OriginInside,
    Kind::Specials,
];

/// One adversarial single-ray case.
pub fn gen_ray(fmt: FloatFormat, rng: &mut Rng, kind: Kind) -> (BoxIn, RayIn) {
    let scale = rand_scale(fmt, rng);
    let mut bx = rand_box(fmt, rng, scale);
    let far = scale + rng.range(-1, 3) as i32;
    let mut o = [0, 1, 2].map(|_| rand_val(fmt, rng, far, 2));
    let mut d = [0, 1, 2].map(|_| {
        let sc = rng.range(-4, 4) as i32;
        rand_val(fmt, rng, sc, 3)
    });
    match kind {
        Kind::Random | Kind::Specials => {}
        Kind::Grazing => {
            // Aim from o at an edge (two bound coordinates) or a corner.
            let axes = [3u32, 5, 6, 7][rng.below(4) as usize];
            let target = point_on_box(fmt, rng, &bx, axes);
            for i in 0..3 {
                d[i] = sub(fmt, target[i], o[i], RNE);
            }
            // Sometimes make the aim exact: o = target - d with a small d.
            if rng.chance(1, 3) {
                for i in 0..3 {
                    d[i] = rand_val(fmt, rng, scale - 2, 1);
                    o[i] = sub(fmt, target[i], d[i], RNE);
                }
            }
            for i in 0..3 {
                if rng.chance(1, 2) {
                    d[i] = nudge(fmt, d[i], rng.range(-2, 2));
                }
                if rng.chance(1, 4) {
                    o[i] = nudge(fmt, o[i], rng.range(-1, 1));
                }
            }
        }
        Kind::AlongFace => {
            let i = rng.below(3) as usize;
            d[i] = fmt.zero(rng.chance(1, 2));
            if rng.chance(1, 3) {
                let j = (i + 1 + rng.below(2) as usize) % 3;
                d[j] = fmt.zero(rng.chance(1, 2));
            }
            let on = if rng.chance(1, 2) {
                bx.p_min[i]
            } else {
                bx.p_max[i]
            };
            o[i] = nudge(fmt, on, [0, 0, 0, -1, 1][rng.below(5) as usize]);
        }
        Kind::OriginOnBox => {
            let axes = 1 + rng.below(7) as u32;
            o = point_on_box(fmt, rng, &bx, axes);
        }
        Kind::OriginInside => {
            o = point_on_box(fmt, rng, &bx, 0);
        }
    }
    if rng.chance(1, 10) {
        // zero components anywhere
        let i = rng.below(3) as usize;
        d[i] = fmt.zero(rng.chance(1, 2));
    }
    let t_min = match rng.below(8) {
        0 => fmt.inf(true),
        1 => rand_val(fmt, rng, 0, 3),
        2 => fmt.zero(true),
        _ => fmt.zero(false),
    };
    let t_max = match rng.below(6) {
        0 | 1 => {
            let sc = rng.range(-3, 6) as i32;
            rand_val(fmt, rng, sc, 2) & !fmt.sign_bit()
        }
        2 => rand_val(fmt, rng, 0, 8),
        _ => fmt.inf(false),
    };
    let mut ray = RayIn { o, d, t_min, t_max };
    if kind == Kind::Specials {
        specials(fmt, rng, &mut bx, &mut ray);
    }
    (bx, ray)
}

/// Sprinkles infinities, NaNs, empty and degenerate boxes on a case.
pub fn specials(fmt: FloatFormat, rng: &mut Rng, bx: &mut BoxIn, ray: &mut RayIn) {
    for _ in 0..1 + rng.below(3) {
        let i = rng.below(3) as usize;
        let nan = fmt.canonical_nan() | (rng.below(2) * fmt.sign_bit());
        match rng.below(14) {
            0 => bx.p_min[i] = fmt.inf(true),
            1 => bx.p_max[i] = fmt.inf(false),
            2 => bx.p_min[i] = fmt.inf(rng.chance(1, 2)),
            3 => bx.p_max[i] = fmt.inf(rng.chance(1, 2)),
            4 => std::mem::swap(&mut bx.p_min[i], &mut bx.p_max[i]), // maybe empty
            5 => bx.p_max[i] = bx.p_min[i],
            6 => ray.o[i] = fmt.inf(rng.chance(1, 2)),
            7 => ray.d[i] = fmt.inf(rng.chance(1, 2)),
            8 => ray.t_max = fmt.inf(rng.chance(1, 2)),
            9 => ray.t_min = fmt.inf(rng.chance(1, 2)),
            10 => std::mem::swap(&mut ray.t_min, &mut ray.t_max),
            11 => ray.d = [fmt.zero(false), fmt.zero(true), fmt.zero(rng.chance(1, 2))],
            12 => {
                let which = rng.below(16) as usize;
                let slot: &mut u64 = match which {
                    0..=2 => &mut bx.p_min[which],
                    3..=5 => &mut bx.p_max[which - 3],
                    6..=8 => &mut ray.o[which - 6],
                    9..=11 => &mut ray.d[which - 9],
                    12 | 13 => &mut ray.t_min,
                    _ => &mut ray.t_max,
                };
                *slot = nan;
            }
            _ => bx.p_min[i] = fmt.max_finite(true),
        }
    }
}

/// A bundle around a generated ray: direction bounds `d ± δ` (same sign
/// unless `allow_mixed`), origin bounds `o ± ε` in bounded mode.
pub fn gen_bundle(
    fmt: FloatFormat,
    rng: &mut Rng,
    kind: Kind,
    bounded: bool,
    allow_mixed: bool,
) -> (BoxIn, BundleIn) {
    let (bx, ray) = gen_ray(fmt, rng, kind);
    let mut d_lo = ray.d;
    let mut d_hi = ray.d;
    let mut o_lo = ray.o;
    let mut o_hi = ray.o;
    let spread = rng.below(4);
    for i in 0..3 {
        let (a, b) = match spread {
            0 => (ray.d[i], ray.d[i]),
            1 => (
                nudge(fmt, ray.d[i], -(rng.below(4) as i64)),
                nudge(fmt, ray.d[i], rng.below(4) as i64),
            ),
            _ => {
                // relative spread 2^-k
                let k = rng.range(1, 8) as i32;
                let dv = to_f64(fmt, ray.d[i]);
                let delta = from_f64(fmt, dv.abs() * 2f64.powi(-k) * rng.unit());
                (
                    sub(fmt, ray.d[i], delta, RNE),
                    add(fmt, ray.d[i], delta, RNE),
                )
            }
        };
        let (mut a, mut b) = ordered(fmt, a, b);
        if !allow_mixed {
            // keep the sign of the centre (a zero centre stays a one-sided interval)
            let neg_centre = ray.d[i] & fmt.sign_bit() != 0;
            if neg_centre && total_key(fmt, b) > total_key(fmt, fmt.zero(true)) {
                b = fmt.zero(true);
            }
            if !neg_centre && total_key(fmt, a) < total_key(fmt, fmt.zero(false)) {
                a = fmt.zero(false);
            }
        } else if rng.chance(1, 8) {
            // straddle zero
            a = nudge(fmt, fmt.zero(true), -(rng.below(3) as i64) - 1);
            b = nudge(fmt, fmt.zero(false), rng.below(3) as i64 + 1);
        }
        d_lo[i] = a;
        d_hi[i] = b;
        if bounded && rng.chance(2, 3) {
            let ov = to_f64(fmt, ray.o[i]);
            let bxw = (to_f64(fmt, bx.p_max[i]) - to_f64(fmt, bx.p_min[i])).abs();
            let eps = from_f64(
                fmt,
                (ov.abs() * 2f64.powi(-(rng.range(2, 20) as i32)) + bxw * 0.1) * rng.unit(),
            );
            let lo = sub(fmt, ray.o[i], eps, RNE);
            let hi = add(fmt, ray.o[i], eps, RNE);
            if total_key(fmt, lo) <= total_key(fmt, hi) {
                o_lo[i] = lo;
                o_hi[i] = hi;
            }
        }
    }
    let b = BundleIn {
        p_min: bx.p_min,
        p_max: bx.p_max,
        o_lo,
        o_hi,
        d_lo,
        d_hi,
        t_min: ray.t_min,
        t_max: ray.t_max,
    };
    (bx, b)
}

/// The explicit rays of a bundle to check: every corner of the parameter box
/// plus `n_random` float rays drawn inside the bounds.
pub fn bundle_rays(
    fmt: FloatFormat,
    rng: &mut Rng,
    b: &BundleIn,
    bounded: bool,
    n_random: usize,
) -> Vec<RayIn> {
    let o_hi = if bounded { b.o_hi } else { b.o_lo };
    let mut rays = corner_rays(b.o_lo, o_hi, b.d_lo, b.d_hi, b.t_min, b.t_max);
    for _ in 0..n_random {
        let o = [0, 1, 2].map(|i| between(fmt, rng, b.o_lo[i], o_hi[i]));
        let d = [0, 1, 2].map(|i| between(fmt, rng, b.d_lo[i], b.d_hi[i]));
        rays.push(RayIn {
            o,
            d,
            t_min: b.t_min,
            t_max: b.t_max,
        });
    }
    rays
}

/// Whether every input of a bundle is ordered and finite where it must be
/// (so the per-ray enumeration is meaningful).
pub fn bundle_well_formed(fmt: FloatFormat, b: &BundleIn, bounded: bool) -> bool {
    let o_hi = if bounded { b.o_hi } else { b.o_lo };
    (0..3).all(|i| {
        let fin = |v: u64| (v & fmt.mask() & !fmt.sign_bit()) < fmt.inf(false);
        fin(b.d_lo[i])
            && fin(b.d_hi[i])
            && fin(b.o_lo[i])
            && fin(o_hi[i])
            && total_key(fmt, b.d_lo[i]) <= total_key(fmt, b.d_hi[i])
            && total_key(fmt, b.o_lo[i]) <= total_key(fmt, o_hi[i])
    })
}

/// Correctly rounded `1/d` (RNE) for formats with F ≤ 24 and E ≤ 10, via
/// binary64 (double rounding is innocuous for division at 53 ≥ 2p + 2).
pub fn recip(fmt: FloatFormat, d: u64) -> u64 {
    assert!(fmt.frac_bits() <= 24 && fmt.exp_bits() <= 10);
    let v = to_f64(fmt, d);
    from_f64(fmt, 1.0 / v)
}

/// `x · y` in `fmt`, RNE (generator convenience).
pub fn fmul(fmt: FloatFormat, x: u64, y: u64) -> u64 {
    mul(fmt, x, y, RNE)
}

/// The formats the tests sweep (all have an exact-product format).
pub fn formats() -> Vec<FloatFormat> {
    vec![
        FloatFormat::BINARY32,
        FloatFormat::BINARY16,
        FloatFormat::BFLOAT16,
        FloatFormat::new(4, 3).unwrap(),
        FloatFormat::new(6, 9).unwrap(),
    ]
}

/// One case of the realistic binary32 scene distribution: a box in
/// [-1,1]^3 of random size, an origin in [-4,4]^3, a unit direction (aimed
/// near the box half the time), t_min = 0, t_max = inf or finite.
pub fn realistic_scene_case(rng: &mut Rng) -> (BoxIn, RayIn) {
    let f = |x: f64| from_f64(FloatFormat::BINARY32, x);
    let c = [0; 3].map(|_| rng.unit() * 2.0 - 1.0);
    let h = [0; 3].map(|_| rng.unit().powi(3) * 0.5);
    let bx = BoxIn {
        p_min: [0, 1, 2].map(|i| f(c[i] - h[i])),
        p_max: [0, 1, 2].map(|i| f(c[i] + h[i])),
    };
    let o = [0; 3].map(|_| rng.unit() * 8.0 - 4.0);
    let target: [f64; 3] = if rng.chance(1, 2) {
        [0, 1, 2].map(|i| c[i] + (rng.unit() * 2.0 - 1.0) * h[i] * 1.5)
    } else {
        [0; 3].map(|_| rng.unit() * 2.0 - 1.0)
    };
    let mut d = [0, 1, 2].map(|i| target[i] - o[i]);
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    d = d.map(|x| x / len);
    let t_max = if rng.chance(1, 2) {
        f64::INFINITY
    } else {
        rng.unit() * 10.0
    };
    let r = RayIn {
        o: o.map(f),
        d: d.map(f),
        t_min: f(0.0),
        t_max: f(t_max),
    };
    (bx, r)
}

/// Environment variable: number of cases for the long loops (default given).
pub fn cases(default: u64) -> u64 {
    std::env::var("SILHOUETTE_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}
