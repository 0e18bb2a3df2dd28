//! The accuracy study of the seed's FIG. 7 (`docs/transform.md` §5): ray
//! origins at growing offsets from an instance's translation `T`, transformed
//! to model space by (i) the exact reference rounded once, (ii) the
//! conventional single inverse matrix with nine FMAs, (iii) the two-step
//! method; absolute and relative errors of (ii) and (iii) against (i).
//!
//! Matrices: the seed's M1–M3, built as the seed describes them (rotation
//! about an axis, then scale, then translation: `R = S · Rot`, computed in
//! binary64 and rounded to the format; the printed inverses are not used),
//! and random ones. Both methods get the same `R⁻¹`, each entry the exact
//! inverse rounded once ([`super::exact::scene_builder_inverse`]); the
//! conventional `u = −R⁻¹·T` is also exact and rounded once, the most
//! favourable choice for the baseline.

use super::exact::{exact_inverse, inverse_entries, reference_origin, scene_builder_translation};
use super::{conventional_origin, dot, invert_hw, two_step_origin, DotStyle};
use crate::float::{to_f64, FloatFormat, RoundingMode};
use std::fmt::Write as _;

/// An instance transform as the seed specifies its examples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// rotation axis (any length)
    pub axis: [f64; 3],
    /// rotation angle in degrees (right-handed about `axis`)
    pub angle_deg: f64,
    /// per-axis scale, applied after the rotation
    pub scale: [f64; 3],
    /// translation, applied last
    pub translation: [f64; 3],
}

/// The seed's three example matrices (FIG. 7a–c, paragraphs 33, 36, 38).
pub const SEED_MATRICES: [(&str, Placement); 3] = [
    (
        "M1",
        Placement {
            axis: [-0.484658, 0.310767, -0.817637],
            angle_deg: 166.0,
            scale: [5.062899, 1.343523, 1.331195],
            translation: [-6139.630859, -918.470093, 49161.503906],
        },
    ),
    (
        "M2",
        Placement {
            axis: [0.506287, 0.219681, 0.833915],
            angle_deg: 328.0,
            scale: [-1.337073, -0.625314, 1.900729],
            translation: [2.952133, 1.276896, -44.617302],
        },
    ),
    (
        "M3",
        Placement {
            axis: [-0.490687, 0.033258, -0.870701],
            angle_deg: 243.0,
            scale: [4.662860, 0.188493, 0.213617],
            translation: [-12816.281250, 16287.140625, -115868.531250],
        },
    ),
];

/// The rotation matrix (row-major) about `axis` by `angle_deg` (Rodrigues).
pub fn rotation(axis: [f64; 3], angle_deg: f64) -> [f64; 9] {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = axis.map(|a| a / n);
    let th = angle_deg.to_radians();
    let (s, c) = th.sin_cos();
    let t = 1.0 - c;
    [
        c + x * x * t,
        x * y * t - z * s,
        x * z * t + y * s,
        y * x * t + z * s,
        c + y * y * t,
        y * z * t - x * s,
        z * x * t - y * s,
        z * y * t + x * s,
        c + z * z * t,
    ]
}

pub use crate::float::from_f64;

/// The forward transform `(R, T)` of a placement in `fmt`:
/// `R = diag(scale) · rotation(axis, angle)` in binary64, each entry rounded.
pub fn forward(fmt: FloatFormat, p: &Placement) -> ([u64; 9], [u64; 3]) {
    let rot = rotation(p.axis, p.angle_deg);
    let r = std::array::from_fn(|k| from_f64(fmt, p.scale[k / 3] * rot[k]));
    (r, p.translation.map(|t| from_f64(fmt, t)))
}

/// splitmix64: the study's own small generator (reproducible from `seed`).
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x5851_f42d_4c95_7f2d)
    }
    /// 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// ±1.
    pub fn sign(&mut self) -> f64 {
        if self.next_u64() & 1 == 0 {
            1.0
        } else {
            -1.0
        }
    }
    /// A uniformly distributed unit vector.
    pub fn direction(&mut self) -> [f64; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

/// A random placement: uniform axis and angle, scales `±10^U(−1, 1)`,
/// translation components `±10^U(0, 5)` (the range of the seed's examples).
pub fn random_placement(rng: &mut Rng) -> Placement {
    Placement {
        axis: rng.direction(),
        angle_deg: rng.range(0.0, 360.0),
        scale: [(); 3].map(|_| rng.sign() * 10f64.powf(rng.range(-1.0, 1.0))),
        translation: [(); 3].map(|_| rng.sign() * 10f64.powf(rng.range(0.0, 5.0))),
    }
}

/// Options of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyOptions {
    /// format of every value
    pub fmt: FloatFormat,
    /// rounding mode of every operation and of the reference
    pub mode: RoundingMode,
    /// dot-product styles of the two-step method (one table each)
    pub styles: Vec<DotStyle>,
    /// origins per offset for each of M1–M3
    pub points: usize,
    /// random matrices (the "random" set)
    pub random_matrices: usize,
    /// origins per offset for each random matrix
    pub random_points: usize,
    /// offsets `|O_w − T|`
    pub offsets: Vec<f64>,
    /// seed of the random origins and matrices
    pub seed: u64,
    /// how both methods obtain `R⁻¹` (and the conventional `u`)
    pub inverse: StudyInverse,
}

/// Where the study's inverse matrices come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StudyInverse {
    /// the scene builder's: every entry of `R⁻¹` and of `u = −R⁻¹·T` exact,
    /// rounded once
    Exact,
    /// computed in the format at run time: `R⁻¹` by [`super::invert_hw`] in
    /// the two-step method's dot style; the conventional method's `S` by
    /// `invert_hw` in the fma style and `u_i = −dot_fma(S[i][·], T)`
    Hardware,
}

impl Default for StudyOptions {
    fn default() -> Self {
        StudyOptions {
            fmt: FloatFormat::BINARY32,
            mode: RoundingMode::NearestEven,
            styles: vec![DotStyle::Fma],
            points: 10_000,
            random_matrices: 1000,
            random_points: 100,
            offsets: default_offsets(),
            seed: 1,
            inverse: StudyInverse::Exact,
        }
    }
}

/// 0, 1e-3, 1e-2, …, 1e5.
pub fn default_offsets() -> Vec<f64> {
    std::iter::once(0.0)
        .chain((-3..=5).map(|k| 10f64.powi(k)))
        .collect()
}

/// Max and median of absolute and relative errors over a set of origins.
///
/// Per origin: `abs = max_k |out_k − ref_k|` (components in binary64),
/// `rel = abs / max_k |ref_k|`; when the reference is the zero vector, `rel`
/// is 0 if `abs` is 0 and +∞ otherwise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorStats {
    /// largest absolute error
    pub max_abs: f64,
    /// median absolute error
    pub med_abs: f64,
    /// largest relative error
    pub max_rel: f64,
    /// median relative error
    pub med_rel: f64,
    /// origins whose result differs from the reference in value (±0 equal)
    pub inexact: usize,
    /// largest normwise relative error against the real value of the stored
    /// matrix times `O_w − T` (0.5 ulp, about 6e-8 at binary32, for a
    /// correctly rounded result)
    pub max_rel_stored: f64,
    /// median of the same
    pub med_rel_stored: f64,
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    v[v.len() / 2]
}

#[derive(Debug, Default, Clone)]
struct Acc {
    abs: Vec<f64>,
    rel: Vec<f64>,
    inexact: usize,
    /// normwise relative error against the real `M·(O_w − T)` of the stored `M`
    rel_stored: Vec<f64>,
}

impl Acc {
    fn push_stored(&mut self, fmt: FloatFormat, out: [u64; 3], real: [f64; 3]) {
        let o = out.map(|x| to_f64(fmt, x));
        let err = (0..3).map(|k| (o[k] - real[k]).abs()).fold(0.0, f64::max);
        let scale = real.iter().map(|x| x.abs()).fold(0.0, f64::max);
        self.rel_stored.push(match (scale > 0.0, err == 0.0) {
            (true, _) => err / scale,
            (false, true) => 0.0,
            (false, false) => f64::INFINITY,
        });
    }
    fn push(&mut self, fmt: FloatFormat, out: [u64; 3], reference: [u64; 3]) {
        let o = out.map(|x| to_f64(fmt, x));
        let r = reference.map(|x| to_f64(fmt, x));
        let abs = (0..3).map(|k| (o[k] - r[k]).abs()).fold(0.0, f64::max);
        let scale = r.iter().map(|x| x.abs()).fold(0.0, f64::max);
        let rel = if scale > 0.0 {
            abs / scale
        } else if abs == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
        self.abs.push(abs);
        self.rel.push(rel);
        self.inexact += (0..3).any(|k| o[k] != r[k]) as usize;
    }
    fn stats(mut self) -> ErrorStats {
        ErrorStats {
            max_abs: self.abs.iter().copied().fold(0.0, f64::max),
            med_abs: median(&mut self.abs),
            max_rel: self.rel.iter().copied().fold(0.0, f64::max),
            med_rel: median(&mut self.rel),
            inexact: self.inexact,
            max_rel_stored: self.rel_stored.iter().copied().fold(0.0, f64::max),
            med_rel_stored: median(&mut self.rel_stored),
        }
    }
}

/// One line of the table: a matrix set at one offset.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// `M1`, `M2`, `M3` or `random`
    pub set: String,
    /// `|O_w − T|` before rounding `O_w`
    pub offset: f64,
    /// origins measured
    pub n: usize,
    /// the conventional method
    pub conventional: ErrorStats,
    /// the two-step method, per style in [`StudyOptions::styles`] order
    pub two_step: Vec<ErrorStats>,
}

/// One matrix prepared for the study.
struct Prepared {
    t: [u64; 3],
    t64: [f64; 3],
    inv_exact: super::exact::ExactInverse,
    /// the conventional method's `S`
    inv: [u64; 9],
    u: [u64; 3],
    /// the two-step method's `R⁻¹`, per style
    inv_two: Vec<[u64; 9]>,
}

fn prepare(o: &StudyOptions, p: &Placement) -> Option<Prepared> {
    let (r, t) = forward(o.fmt, p);
    let inv_exact = exact_inverse(o.fmt, &r)?;
    let (inv, u, inv_two) = match o.inverse {
        StudyInverse::Exact => {
            let inv = inverse_entries(o.fmt, o.mode, &inv_exact);
            let u = scene_builder_translation(o.fmt, o.mode, &inv_exact, t)?;
            (inv, u, vec![inv; o.styles.len()])
        }
        StudyInverse::Hardware => {
            let h = invert_hw(o.fmt, o.mode, DotStyle::Fma, &r, false);
            if h.singular {
                return None;
            }
            let s = h.inv;
            let u = [0, 1, 2].map(|i| {
                let d = dot(
                    o.fmt,
                    o.mode,
                    DotStyle::Fma,
                    [s[3 * i], s[3 * i + 1], s[3 * i + 2]],
                    t,
                );
                d ^ o.fmt.sign_bit()
            });
            let two = o
                .styles
                .iter()
                .map(|&st| invert_hw(o.fmt, o.mode, st, &r, false).inv)
                .collect();
            (s, u, two)
        }
    };
    Some(Prepared {
        t,
        t64: t.map(|x| to_f64(o.fmt, x)),
        inv_exact,
        inv,
        u,
        inv_two,
    })
}

fn measure(
    o: &StudyOptions,
    m: &Prepared,
    offset: f64,
    points: usize,
    rng: &mut Rng,
    conv: &mut Acc,
    two: &mut [Acc],
) {
    for _ in 0..points {
        let v = rng.direction();
        let ow = [0, 1, 2].map(|k| from_f64(o.fmt, m.t64[k] + offset * v[k]));
        let Some(reference) = reference_origin(o.fmt, o.mode, &m.inv_exact, m.t, ow) else {
            continue;
        };
        conv.push(
            o.fmt,
            conventional_origin(o.fmt, o.mode, &m.inv, m.u, ow),
            reference,
        );
        for ((acc, &style), inv) in two.iter_mut().zip(&o.styles).zip(&m.inv_two) {
            let out = two_step_origin(o.fmt, o.mode, style, inv, m.t, ow);
            acc.push(o.fmt, out, reference);
            if let Some(real) = super::exact::stored_product(o.fmt, inv, m.t, ow) {
                acc.push_stored(o.fmt, out, real);
            }
        }
    }
}

/// Runs the study: M1–M3, then the random set, one [`Row`] per set and offset.
pub fn run(o: &StudyOptions) -> Vec<Row> {
    let mut rows = Vec::new();
    let mut rng = Rng::new(o.seed);
    let mut sets: Vec<(String, Vec<Prepared>, usize)> = SEED_MATRICES
        .iter()
        .filter_map(|(name, p)| Some((name.to_string(), vec![prepare(o, p)?], o.points)))
        .collect();
    let mut random = Vec::new();
    while random.len() < o.random_matrices {
        if let Some(m) = prepare(o, &random_placement(&mut rng)) {
            random.push(m);
        }
    }
    if !random.is_empty() {
        sets.push(("random".to_string(), random, o.random_points));
    }
    for (name, mats, points) in &sets {
        for &offset in &o.offsets {
            let mut conv = Acc::default();
            let mut two = vec![Acc::default(); o.styles.len()];
            for m in mats {
                measure(o, m, offset, *points, &mut rng, &mut conv, &mut two);
            }
            rows.push(Row {
                set: name.clone(),
                offset,
                n: conv.abs.len(),
                conventional: conv.stats(),
                two_step: two.into_iter().map(Acc::stats).collect(),
            });
        }
    }
    rows
}

fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".to_string()
    } else if x.is_infinite() {
        "inf".to_string()
    } else {
        format!("{x:.2e}")
    }
}

/// The table as Markdown, one table per two-step style.
pub fn table(o: &StudyOptions, rows: &[Row]) -> String {
    let mut s = String::new();
    for (k, style) in o.styles.iter().enumerate() {
        let _ = writeln!(
            s,
            "two-step with dot style `{}`; conventional = one inverse matrix, 9 FMAs; format {}, {:?}; inverse {}\n",
            style.word(),
            o.fmt,
            o.mode,
            match o.inverse {
                StudyInverse::Exact => "exact, rounded once (scene builder)",
                StudyInverse::Hardware => "computed in the format (invert_hw; conventional u = -S*T by FMA)",
            }
        );
        let _ = writeln!(
            s,
            "| set | offset | n | conv abs max | conv abs med | conv rel max | conv rel med | 2-step abs max | 2-step abs med | 2-step rel max | 2-step rel med | conv ≠ ref | 2-step ≠ ref | 2-step rel max, stored R⁻¹ | 2-step rel med, stored R⁻¹ |"
        );
        let _ = writeln!(
            s,
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for r in rows {
            let (c, t) = (&r.conventional, &r.two_step[k]);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.set,
                if r.offset == 0.0 {
                    "0".to_string()
                } else {
                    format!("{:.0e}", r.offset)
                },
                r.n,
                sci(c.max_abs),
                sci(c.med_abs),
                sci(c.max_rel),
                sci(c.med_rel),
                sci(t.max_abs),
                sci(t.med_abs),
                sci(t.max_rel),
                sci(t.med_rel),
                c.inexact,
                t.inexact,
                sci(t.max_rel_stored),
                sci(t.med_rel_stored),
            );
        }
        s.push('\n');
    }
    s
}
