//! Golden model of the two-step inverse transform unit (seed 003, issue #5).
//! The specification is `docs/transform.md`; this file performs its steps in
//! the same order with the golden float operators, so the RTL can match it
//! bit for bit.
//!
//! A world-space ray (origin `O_w`, direction `D_w`, `t_min`, `t_max`, id)
//! goes to model space with the instance's forward transform `M = [R | T]`:
//!
//! * step 1, reverse translation: `X = fl(O_w − T)` (three subtractions);
//! * step 2, inverse linear map: `O_m = R⁻¹ · X`, `D_m = R⁻¹ · D_w`, each
//!   row a three-term dot product in one of three [`DotStyle`]s;
//! * `t_min`, `t_max` and the id pass through bit for bit (the direction is
//!   not normalised, so `t` keeps its meaning).
//!
//! `R⁻¹` is either supplied ([`InverseSource::PreInverted`], computed by the
//! scene builder as the exact rational inverse rounded once, see
//! [`exact::scene_builder_inverse`]) or computed from `R` by the unit
//! ([`InverseSource::Hardware`]: adjugate, determinant, one reciprocal,
//! scaling; [`invert_hw`]). A singular or non-finite transform raises
//! [`ModelRay::singular`] and the six vector outputs are the canonical NaN.
//!
//! The conventional baseline, `O_m = S·O_w + u` with one inverse matrix
//! `[S | u]` and nine FMAs, is [`conventional_origin`]; [`accuracy`] compares
//! both against the exact reference.
//!
//! ```
//! use golden_model::float::{FloatFormat, RoundingMode};
//! use golden_model::transform::{transform, Config, DotStyle, InverseSource, InstanceTransform, WorldRay};
//! let b = |x: f32| x.to_bits() as u64;
//! let cfg = Config { fmt: FloatFormat::BINARY32, mode: RoundingMode::NearestEven,
//!                    dot: DotStyle::Fma, source: InverseSource::PreInverted };
//! // R = 2·I, so R⁻¹ = I/2; T = (10, 20, 30).
//! let half = [b(0.5), 0, 0, 0, b(0.5), 0, 0, 0, b(0.5)];
//! let inst = InstanceTransform { linear: half, translation: [b(10.0), b(20.0), b(30.0)], rotation_hint: false };
//! let ray = WorldRay { origin: [b(12.0), b(20.0), b(29.0)], dir: [b(1.0), b(0.0), b(-4.0)],
//!                      t_min: b(0.0), t_max: b(100.0), id: 7 };
//! let m = transform(&cfg, &ray, &inst);
//! assert_eq!(m.origin, [b(1.0), b(0.0), b(-0.5)]);
//! assert_eq!(m.dir, [b(0.5), b(0.0), b(-2.0)]);
//! assert_eq!((m.t_min, m.t_max, m.id, m.singular), (b(0.0), b(100.0), 7, false));
//! ```

pub mod accuracy;
pub mod exact;
mod recip;

pub(crate) use recip::recip_f64;
pub use recip::{recip, recip_generic};

use crate::float::{add, classify, convert, dot3, fma, mul, sub, Class, FloatFormat, RoundingMode};

/// How a three-term dot product `a0·b0 + a1·b1 + a2·b2` is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DotStyle {
    /// Separate multipliers and adders, fixed order:
    /// `add(add(mul(a0,b0), mul(a1,b1)), mul(a2,b2))` (five roundings).
    Separate,
    /// Chained FMA: `fma(a2, b2, fma(a1, b1, mul(a0, b0)))` (three roundings).
    Fma,
    /// Fused three-term dot product, one rounding ([`crate::float::dot3`]).
    Dot3,
    /// Every matrix-vector product in the [`wide_format`] `(E + 1, 2F + 2)`:
    /// operands widened (exactly), the origin's `O − T` subtracted there
    /// (exact unless the exponents differ by more than `F + 2`, then within
    /// `2^-(2F+3)` relative), a fused dot product rounded once in the wide
    /// format, then rounded to the format. Where `O − T` is exact, within one
    /// ulp of the correctly rounded `R⁻¹·(O − T)` (two roundings, the first
    /// `F + 2` bits finer; a rounded `O − T` followed by cancellation is not);
    /// the inversion (`inverse=hw`) as [`DotStyle::Dot3`].
    Wide,
}

impl DotStyle {
    /// Every style, in parameter order.
    pub const ALL: [DotStyle; 4] = [
        DotStyle::Separate,
        DotStyle::Fma,
        DotStyle::Dot3,
        DotStyle::Wide,
    ];

    /// The parameter word: `separate`, `fma`, `dot3`, `wide`.
    pub fn word(self) -> &'static str {
        match self {
            DotStyle::Separate => "separate",
            DotStyle::Fma => "fma",
            DotStyle::Dot3 => "dot3",
            DotStyle::Wide => "wide",
        }
    }

    /// The style named by `word`.
    pub fn parse(word: &str) -> Option<DotStyle> {
        DotStyle::ALL.into_iter().find(|s| s.word() == word)
    }
}

/// Where `R⁻¹` comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InverseSource {
    /// The instance supplies `R⁻¹` (computed by the scene builder).
    PreInverted,
    /// The instance supplies `R`; the unit inverts it ([`invert_hw`]).
    Hardware,
}

/// Numeric configuration of the unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Config {
    /// float format of every input and output vector component
    pub fmt: FloatFormat,
    /// rounding mode of every operation
    pub mode: RoundingMode,
    /// dot-product style of the matrix-vector products (and of the inversion)
    pub dot: DotStyle,
    /// where `R⁻¹` comes from
    pub source: InverseSource,
}

/// A ray in world space; every field is a bit pattern of the format except `id`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct WorldRay {
    /// origin `O_w`
    pub origin: [u64; 3],
    /// direction `D_w` (not normalised)
    pub dir: [u64; 3],
    /// passed through
    pub t_min: u64,
    /// passed through
    pub t_max: u64,
    /// passed through (any bits)
    pub id: u64,
}

/// The instance transform as the unit receives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InstanceTransform {
    /// row-major 3×3: `R⁻¹` for [`InverseSource::PreInverted`], `R` for
    /// [`InverseSource::Hardware`]
    pub linear: [u64; 9],
    /// the forward translation `T` (not negated)
    pub translation: [u64; 3],
    /// only with [`InverseSource::Hardware`]: `R` is a pure rotation, use
    /// `R⁻¹ = Rᵀ` (no arithmetic); ignored for pre-inverted input
    pub rotation_hint: bool,
}

/// The ray in model space.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ModelRay {
    /// `O_m = R⁻¹·fl(O_w − T)`
    pub origin: [u64; 3],
    /// `D_m = R⁻¹·D_w`
    pub dir: [u64; 3],
    /// `t_min` of the world ray, same bits
    pub t_min: u64,
    /// `t_max` of the world ray, same bits
    pub t_max: u64,
    /// id of the world ray, same bits
    pub id: u64,
    /// the transform is singular or not finite: `origin` and `dir` are the
    /// canonical NaN and the ray must be handled another way (the seed
    /// transforms the geometry instead)
    pub singular: bool,
}

/// The format [`DotStyle::Wide`] computes in: `(E + 1, 2F + 2)`; `None`
/// when that exceeds 64 bits.
pub fn wide_format(fmt: FloatFormat) -> Option<FloatFormat> {
    FloatFormat::new(fmt.exp_bits() + 1, 2 * fmt.frac_bits() + 2).ok()
}

fn wide(fmt: FloatFormat) -> FloatFormat {
    wide_format(fmt).expect("dot=wide is refused for formats whose wide format exceeds 64 bits")
}

/// `x` of `fmt` in the wide format (exact).
fn widen(fmt: FloatFormat, mode: RoundingMode, x: u64) -> u64 {
    convert(fmt, wide(fmt), x, mode)
}

/// `a · b` with `a` of `fmt` and `b` already in the wide format, fused and
/// rounded there, then rounded to `fmt` ([`DotStyle::Wide`]).
fn wide_dot(fmt: FloatFormat, mode: RoundingMode, a: [u64; 3], b_wide: [u64; 3]) -> u64 {
    let w = wide(fmt);
    let y = dot3(w, a.map(|x| widen(fmt, mode, x)), b_wide, mode);
    convert(w, fmt, y, mode)
}

/// `a0·b0 + a1·b1 + a2·b2` in `style` (see [`DotStyle`] for the exact order).
pub fn dot(fmt: FloatFormat, mode: RoundingMode, style: DotStyle, a: [u64; 3], b: [u64; 3]) -> u64 {
    match style {
        DotStyle::Wide => wide_dot(fmt, mode, a, b.map(|x| widen(fmt, mode, x))),
        DotStyle::Separate => {
            let p = [0, 1, 2].map(|i| mul(fmt, a[i], b[i], mode));
            add(fmt, add(fmt, p[0], p[1], mode), p[2], mode)
        }
        DotStyle::Fma => {
            let s = mul(fmt, a[0], b[0], mode);
            let s = fma(fmt, a[1], b[1], s, mode);
            fma(fmt, a[2], b[2], s, mode)
        }
        DotStyle::Dot3 => dot3(fmt, a, b, mode),
    }
}

/// `m · v` for a row-major 3×3 `m`, each row a [`dot`].
pub fn mat_vec(
    fmt: FloatFormat,
    mode: RoundingMode,
    style: DotStyle,
    m: &[u64; 9],
    v: [u64; 3],
) -> [u64; 3] {
    [0, 1, 2].map(|i| dot(fmt, mode, style, [m[3 * i], m[3 * i + 1], m[3 * i + 2]], v))
}

/// `p·q − r·s`, the 2×2 determinant of a cofactor, in `style`:
/// `sub(mul(p,q), mul(r,s))`, `fma(p, q, −mul(r,s))`, or
/// `dot3([p, r, +0], [q, −s, +0])`.
pub fn det2(
    fmt: FloatFormat,
    mode: RoundingMode,
    style: DotStyle,
    p: u64,
    q: u64,
    r: u64,
    s: u64,
) -> u64 {
    match style {
        DotStyle::Separate => sub(fmt, mul(fmt, p, q, mode), mul(fmt, r, s, mode), mode),
        DotStyle::Fma => fma(fmt, p, q, fmt.negate(mul(fmt, r, s, mode)), mode),
        DotStyle::Dot3 | DotStyle::Wide => dot3(fmt, [p, r, 0], [q, fmt.negate(s), 0], mode),
    }
}

/// The result of [`invert_hw`], with its intermediate values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct HwInverse {
    /// row-major `R⁻¹` (for the rotation hint: `Rᵀ`)
    pub inv: [u64; 9],
    /// row-major adjugate (zeros with the rotation hint)
    pub adj: [u64; 9],
    /// `det R` (zero with the rotation hint)
    pub det: u64,
    /// `fl(1 / det)` (zero with the rotation hint)
    pub recip: u64,
    /// an input is not finite, `det` is zero or not finite, an entry of
    /// `inv` is not finite, or a value of the sequence (a cofactor, `det`,
    /// `recip`, an entry of `inv`) is ±max finite, where a directed mode
    /// leaves an overflow
    pub singular: bool,
}

/// `R⁻¹` computed from `R` by the fixed sequence the hardware performs:
///
/// 1. adjugate, `adj[i][j] = det2(R[j+1][i+1], R[j+2][i+2], R[j+1][i+2], R[j+2][i+1])`
///    (indices mod 3, [`det2`] in `style`);
/// 2. `det = dot(R[0][·], (adj[0][0], adj[1][0], adj[2][0]))` in `style`;
/// 3. `recip = fl(1 / det)`, correctly rounded ([`recip`]);
/// 4. `inv[i][j] = mul(adj[i][j], recip)`.
///
/// With `rotation_hint`, `inv = Rᵀ` and nothing is computed. `singular` as in
/// [`HwInverse`] (with the hint: only a non-finite input).
pub fn invert_hw(
    fmt: FloatFormat,
    mode: RoundingMode,
    style: DotStyle,
    r: &[u64; 9],
    rotation_hint: bool,
) -> HwInverse {
    let inputs_finite = r.iter().all(|&x| fmt.is_finite(x));
    // the wide style widens only the matrix-vector products
    let style = match style {
        DotStyle::Wide => DotStyle::Dot3,
        other => other,
    };
    let at = |i: usize, j: usize| r[3 * (i % 3) + (j % 3)];
    if rotation_hint {
        let inv = std::array::from_fn(|k| at(k % 3, k / 3));
        return HwInverse {
            inv,
            adj: [0; 9],
            det: 0,
            recip: 0,
            singular: !inputs_finite,
        };
    }
    let adj: [u64; 9] = std::array::from_fn(|k| {
        let (i, j) = (k / 3, k % 3);
        det2(
            fmt,
            mode,
            style,
            at(j + 1, i + 1),
            at(j + 2, i + 2),
            at(j + 1, i + 2),
            at(j + 2, i + 1),
        )
    });
    let det = dot(
        fmt,
        mode,
        style,
        [r[0], r[1], r[2]],
        [adj[0], adj[3], adj[6]],
    );
    let rc = recip(fmt, det, mode);
    let inv = adj.map(|a| mul(fmt, a, rc, mode));
    let det_ok = classify(fmt, det) == Class::Finite;
    // the directed modes round an overflow to ±max finite, not ±∞: a value at
    // ±max finite anywhere in the sequence may be a silent overflow
    let saturated = |x: u64| x & !fmt.sign_bit() == fmt.max_finite(false);
    let overflowed = adj
        .iter()
        .chain(&inv)
        .chain([&det, &rc])
        .any(|&x| saturated(x));
    let singular =
        !inputs_finite || !det_ok || overflowed || !inv.iter().all(|&x| fmt.is_finite(x));
    HwInverse {
        inv,
        adj,
        det,
        recip: rc,
        singular,
    }
}

/// The unit: world ray to model ray, two-step (reverse translation, then the
/// inverse linear map), see the module documentation and `docs/transform.md`.
pub fn transform(cfg: &Config, ray: &WorldRay, inst: &InstanceTransform) -> ModelRay {
    let (fmt, mode) = (cfg.fmt, cfg.mode);
    let t_ok = inst.translation.iter().all(|&x| fmt.is_finite(x));
    let (inv, singular) = match cfg.source {
        InverseSource::PreInverted => {
            let ok = inst.linear.iter().all(|&x| fmt.is_finite(x));
            (inst.linear, !ok)
        }
        InverseSource::Hardware => {
            let h = invert_hw(fmt, mode, cfg.dot, &inst.linear, inst.rotation_hint);
            (h.inv, h.singular)
        }
    };
    let singular = singular || !t_ok;
    let (origin, dir) = if singular {
        ([fmt.canonical_nan(); 3], [fmt.canonical_nan(); 3])
    } else {
        (
            two_step_origin(fmt, mode, cfg.dot, &inv, inst.translation, ray.origin),
            mat_vec(fmt, mode, cfg.dot, &inv, ray.dir),
        )
    };
    let mask = fmt.mask();
    ModelRay {
        origin,
        dir,
        t_min: ray.t_min & mask,
        t_max: ray.t_max & mask,
        id: ray.id,
        singular,
    }
}

/// The conventional baseline for an origin: one inverse matrix `[S | u]`
/// (`u = −S·T`, see [`exact::scene_builder_translation`]) and nine FMAs,
/// row `i`: `fma(S[i][2], o2, fma(S[i][1], o1, fma(S[i][0], o0, u[i])))`.
pub fn conventional_origin(
    fmt: FloatFormat,
    mode: RoundingMode,
    s: &[u64; 9],
    u: [u64; 3],
    o: [u64; 3],
) -> [u64; 3] {
    [0, 1, 2].map(|i| {
        let acc = fma(fmt, s[3 * i], o[0], u[i], mode);
        let acc = fma(fmt, s[3 * i + 1], o[1], acc, mode);
        fma(fmt, s[3 * i + 2], o[2], acc, mode)
    })
}

/// The two-step origin alone: `R⁻¹ · fl(O_w − T)` (no flag, no NaN
/// forcing); with [`DotStyle::Wide`] `O_w − T` is formed in the wide format.
pub fn two_step_origin(
    fmt: FloatFormat,
    mode: RoundingMode,
    style: DotStyle,
    inv: &[u64; 9],
    t: [u64; 3],
    o: [u64; 3],
) -> [u64; 3] {
    if style == DotStyle::Wide {
        let w = wide(fmt);
        let x = [0, 1, 2].map(|k| sub(w, widen(fmt, mode, o[k]), widen(fmt, mode, t[k]), mode));
        return [0, 1, 2]
            .map(|i| wide_dot(fmt, mode, [inv[3 * i], inv[3 * i + 1], inv[3 * i + 2]], x));
    }
    let x = [0, 1, 2].map(|k| sub(fmt, o[k], t[k], mode));
    mat_vec(fmt, mode, style, inv, x)
}
