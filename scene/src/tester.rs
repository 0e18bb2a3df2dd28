//! Box testers the traversal can use. Every box test of the golden-model
//! renderer goes through one of these; the choice is the renderer's `--box` option.
//!
//! | tester | single ray | bundle |
//! |---|---|---|
//! | [`Golden`] | `silhouette::eval` (binary32, conservative), hit = `any_hit` | same unit, AllHit / AllMiss / Mixed |
//! | [`Exact`] | `exact::ray_box::ray_hits_box` (rationals) | not used (bundles are split) |
//! | [`Slab`] | plain `f32` slab test (reciprocal direction), for speed comparison | not used |
//! | [`Reduced`] | the silhouette unit in a reduced format `eXmY` (`--box-format`): ray and box rounded outward, bounded-origin unit | same, bounds rounded outward |
//! | [`Checked`] | wraps a tester; every single-ray miss is checked against [`Exact`] on the unrounded binary32 ray | the wrapped tester |
//! | `rtl::RtlTester` | the Verilated silhouette unit | the same unit |

use crate::units::{GoldenUnits, Units};
use golden_model::exact::ray_box::{ray_hits_box, BoxIn, RayIn};
use golden_model::float::{convert, sub, FloatFormat, RoundingMode};
use golden_model::silhouette::{any_hit, eval, BundleIn, Config, OriginMode, Rounding, Verdict};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// One box test of a single ray: box, origin, direction (binary32 bits), segment `[0, t_max]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RayBox {
    /// box lower corner
    pub p_min: [u64; 3],
    /// box upper corner
    pub p_max: [u64; 3],
    /// origin
    pub o: [u64; 3],
    /// direction
    pub d: [u64; 3],
    /// segment end (binary32 bits; may be +inf)
    pub t_max: u64,
    /// a top-level test: the box and the origin are world coordinates (else
    /// the instance's model space)
    pub world: bool,
}

/// A bundle box test: the silhouette unit's inputs (binary32 bits), shared
/// origin when `o_lo == o_hi`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BundleBox {
    /// the unit's input record (`t_min` = +0)
    pub input: BundleIn,
    /// every ray has the same origin (use the shared-origin unit)
    pub shared: bool,
    /// a top-level test in world coordinates (see [`RayBox::world`])
    pub world: bool,
}

/// A box tester.
pub trait BoxTester: Sync {
    /// May the ray's segment meet the box? Must never answer false for a hit.
    fn ray(&self, x: &RayBox) -> bool;
    /// AllHit / AllMiss / Mixed for a bundle (testers without bundle support
    /// answer Mixed, which splits the bundle).
    fn bundle(&self, x: &BundleBox) -> Verdict;
    /// Whether [`BoxTester::bundle`] is meaningful.
    fn supports_bundles(&self) -> bool;
    /// Short name for reports.
    fn name(&self) -> &'static str;
    /// The transform, cull and triangle units the traversal uses beside
    /// this tester: their golden models unless the tester brings its own
    /// (the RTL in the loop).
    fn units(&self) -> &dyn Units {
        GoldenUnits::get()
    }
}

/// The silhouette unit's golden model, binary32, conservative rounding.
#[derive(Debug, Clone, Copy)]
pub struct Golden {
    shared: Config,
    bounded: Config,
}

impl Default for Golden {
    fn default() -> Self {
        let f = FloatFormat::BINARY32;
        Golden {
            shared: Config::new(f, OriginMode::Shared, Rounding::Conservative).unwrap(),
            bounded: Config::new(f, OriginMode::Bounded, Rounding::Conservative).unwrap(),
        }
    }
}

impl Golden {
    /// The shared-origin unit's configuration (single rays, shared-origin bundles).
    pub fn shared(&self) -> Config {
        self.shared
    }
    /// The bounded-origin unit's configuration (other bundles).
    pub fn bounded(&self) -> Config {
        self.bounded
    }
}

/// The unit's input record for a single ray (shared-origin unit).
pub fn ray_input(x: &RayBox) -> BundleIn {
    BundleIn::ray(x.p_min, x.p_max, x.o, x.d, 0, x.t_max)
}

impl BoxTester for Golden {
    fn ray(&self, x: &RayBox) -> bool {
        any_hit(&self.shared, &ray_input(x))
    }
    fn bundle(&self, x: &BundleBox) -> Verdict {
        let cfg = if x.shared {
            &self.shared
        } else {
            &self.bounded
        };
        eval(cfg, &x.input).verdict()
    }
    fn supports_bundles(&self) -> bool {
        true
    }
    fn name(&self) -> &'static str {
        "golden"
    }
}

/// Exact rational box test (the reference of `docs/silhouette.md`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Exact;

impl BoxTester for Exact {
    fn ray(&self, x: &RayBox) -> bool {
        ray_hits_box(
            FloatFormat::BINARY32,
            &BoxIn {
                p_min: x.p_min,
                p_max: x.p_max,
            },
            &RayIn {
                o: x.o,
                d: x.d,
                t_min: 0,
                t_max: x.t_max,
            },
        )
        .hit
    }
    fn bundle(&self, _: &BundleBox) -> Verdict {
        Verdict::Mixed
    }
    fn supports_bundles(&self) -> bool {
        false
    }
    fn name(&self) -> &'static str {
        "exact"
    }
}

/// Plain f32 slab test: `t = (p − o)·(1/d)`, min/max, one compare (the
/// baseline of `golden-model/src/slab.rs`, in native f32 with Rust's
/// NaN-ignoring `min`/`max`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Slab;

/// The native slab test on f32 values.
#[inline]
pub fn slab_f32(
    p_min: &[f32; 3],
    p_max: &[f32; 3],
    o: &[f32; 3],
    inv_d: &[f32; 3],
    t_max: f32,
) -> bool {
    let mut t0 = 0.0f32;
    let mut t1 = t_max;
    for i in 0..3 {
        let a = (p_min[i] - o[i]) * inv_d[i];
        let b = (p_max[i] - o[i]) * inv_d[i];
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    t0 <= t1
}

impl BoxTester for Slab {
    fn ray(&self, x: &RayBox) -> bool {
        let f = |b: u64| f32::from_bits(b as u32);
        let d = x.d.map(f);
        slab_f32(
            &x.p_min.map(f),
            &x.p_max.map(f),
            &x.o.map(f),
            &d.map(|v| 1.0 / v),
            f(x.t_max),
        )
    }
    fn bundle(&self, _: &BundleBox) -> Verdict {
        Verdict::Mixed
    }
    fn supports_bundles(&self) -> bool {
        false
    }
    fn name(&self) -> &'static str {
        "slab"
    }
}

/// The silhouette unit in a reduced format (`render --box-format eXmY`,
/// `rtl-gen fit`), as the hardware would see a binary32 ray and box:
///
/// * the box is rounded outward (`p_min` down, `p_max` up);
/// * the ray enters the format **as an interval**: each origin and
///   direction component rounded down and up, `t_max` up, `t_min = 0`, and
///   the whole set is tested by the bounded-origin, direction-interval unit
///   (`mode=bundle origin=bounded rounding=conservative`): its AnyHit is
///   false only if every ray of the set misses, and the true ray is one of
///   them, so a miss of the reduced test is a miss of the unrounded ray;
/// * bundles: every bound rounded outward the same way (AllMiss stays
///   proven for every ray; AllHit on the enlarged box only makes rays enter
///   a node, never skip one);
/// * a value beyond the format's range (rounded to an infinity) answers
///   hit / Mixed: the unit would read it as invalid and answer miss.
///
/// Coordinates: below the instance boxes, the instance's model space (after
/// the two-step inverse transform), so a mesh far from the world origin keeps
/// its small model-space coordinates; the instance boxes (top level) relative
/// to a **scene anchor** `a` (binary32, the centre of the top-level root box:
/// [`Reduced::with_world_anchor`]), as a scene stored around its own centre:
/// `p − a` and `o − a` are formed in binary64 rounded outward (once per ray
/// for the origin, once per box when the tree is built), then rounded outward
/// into the format. Directions and `t` are not translated.
#[derive(Debug, Clone, Copy)]
pub struct Reduced {
    fmt: FloatFormat,
    cfg: Config,
    /// binary64 bits of the scene anchor (top-level tests only)
    anchor: [u64; 3],
}

impl Reduced {
    /// The tester for `fmt`, or why the unit has no such format.
    pub fn new(fmt: FloatFormat) -> Result<Reduced, String> {
        let cfg = Config::new(fmt, OriginMode::Bounded, Rounding::Conservative)
            .map_err(|e| format!("box format {fmt}: {e}"))?;
        Ok(Reduced {
            fmt,
            cfg,
            anchor: [0; 3],
        })
    }
    /// Top-level tests relative to the anchor `a` (binary32 coordinates).
    pub fn with_world_anchor(self, a: [f32; 3]) -> Reduced {
        Reduced {
            anchor: a.map(|x| (x as f64).to_bits()),
            ..self
        }
    }
    /// The scene anchor the renderer and `fit` use: the centre of the
    /// top-level root box, rounded to binary32.
    pub fn scene_anchor(accel: &crate::bvh::Accel) -> [f32; 3] {
        let root = &accel.tlas.nodes[0];
        crate::bvh::centre(root.min.into(), root.max.into()).to_array()
    }
    /// `b` (binary32 bits) rounded in `mode`, or `None` if it leaves the
    /// format's finite range while `b` is finite.
    fn round(&self, b: u64, mode: RoundingMode) -> Option<u64> {
        let f32f = FloatFormat::BINARY32;
        let r = convert(f32f, self.fmt, b, mode);
        Some(r).filter(|&r| finite(self.fmt, r) || !finite(f32f, b))
    }
    /// A coordinate on `axis` (binary32 bits) minus the anchor's, rounded in
    /// `mode` (binary64 first, then the format: two roundings the same way).
    fn round_at(&self, axis: usize, b: u64, mode: RoundingMode) -> Option<u64> {
        let (f32f, f64f) = (FloatFormat::BINARY32, FloatFormat::BINARY64);
        if !finite(f32f, b) {
            return self.round(b, mode);
        }
        let wide = convert(f32f, f64f, b, mode);
        let rel = sub(f64f, wide, self.anchor[axis], mode);
        let r = convert(f64f, self.fmt, rel, mode);
        Some(r).filter(|&r| finite(self.fmt, r))
    }
    /// A binary32 bundle record with every bound rounded outward; positions
    /// relative to the anchor when `world`.
    fn enclose(&self, x: &BundleIn, world: bool) -> Option<BundleIn> {
        let (down, up) = (RoundingMode::Down, RoundingMode::Up);
        let vec = |v: [u64; 3], mode: RoundingMode, position: bool| -> Option<[u64; 3]> {
            let one = |i: usize| {
                if position && world {
                    self.round_at(i, v[i], mode)
                } else {
                    self.round(v[i], mode)
                }
            };
            Some([one(0)?, one(1)?, one(2)?])
        };
        Some(BundleIn {
            p_min: vec(x.p_min, down, true)?,
            p_max: vec(x.p_max, up, true)?,
            o_lo: vec(x.o_lo, down, true)?,
            o_hi: vec(x.o_hi, up, true)?,
            d_lo: vec(x.d_lo, down, false)?,
            d_hi: vec(x.d_hi, up, false)?,
            t_min: self.round(x.t_min, down)?,
            t_max: self.round(x.t_max, up)?,
        })
    }
}

impl BoxTester for Reduced {
    fn ray(&self, x: &RayBox) -> bool {
        match self.enclose(&ray_input(x), x.world) {
            Some(r) => eval(&self.cfg, &r).any_hit,
            None => true,
        }
    }
    fn bundle(&self, x: &BundleBox) -> Verdict {
        match self.enclose(&x.input, x.world) {
            Some(r) => eval(&self.cfg, &r).verdict(),
            None => Verdict::Mixed,
        }
    }
    fn supports_bundles(&self) -> bool {
        true
    }
    fn name(&self) -> &'static str {
        "reduced"
    }
}

/// `x` (bits of `f`) is finite.
fn finite(f: FloatFormat, x: u64) -> bool {
    x & f.mask() & !f.sign_bit() < f.inf(false)
}

/// A tester whose single-ray misses are checked against the exact test of
/// the unrounded binary32 ray (`fit`'s zero-false-miss rule, measured on
/// the renderer's own tests): counts misses and false misses. A miss
/// the binary32 unit ([`Golden`], proven conservative and checked against
/// the exact test on 10^7 cases by its own tests) also reports is an exact
/// miss; every other miss, and one miss in [`Checked::SAMPLE`] regardless, is
/// tested with [`Exact`] (`exact_checks`), so the rational test runs where
/// the two units disagree and on a sample. With [`Checked::exact_all`] every
/// miss is tested exactly (slow).
///
/// With a budget of box tests (single-ray plus bundle tests), a render that
/// exceeds it is cut short: from then on every test answers miss (AllMiss),
/// [`Checked::over_budget`] is set and nothing more is counted, so a format
/// far too coarse for the scene is rejected in the time of a good one.
#[derive(Debug)]
pub struct Checked<T> {
    /// the tester answering
    pub inner: T,
    /// single-ray misses
    pub misses: AtomicU64,
    /// misses the exact test calls hits
    pub false_misses: AtomicU64,
    /// misses tested with the exact test
    pub exact_checks: AtomicU64,
    /// test every miss exactly, not only where the binary32 unit hits
    pub exact_all: bool,
    /// single-ray and bundle tests so far
    box_tests: AtomicU64,
    budget: u64,
    over: AtomicBool,
    binary32: Golden,
}

impl<T> Checked<T> {
    /// One single-ray miss in this many is tested exactly even where the
    /// binary32 unit agrees.
    pub const SAMPLE: u64 = 64;
    /// Wraps `inner`; the render is cut short after `budget` box tests.
    pub fn with_budget(inner: T, budget: u64) -> Checked<T> {
        Checked {
            inner,
            misses: AtomicU64::new(0),
            false_misses: AtomicU64::new(0),
            exact_checks: AtomicU64::new(0),
            exact_all: false,
            box_tests: AtomicU64::new(0),
            budget,
            over: AtomicBool::new(false),
            binary32: Golden::default(),
        }
    }
    /// The budget was exceeded (the render's answers are void).
    pub fn over_budget(&self) -> bool {
        self.over.load(Ordering::Relaxed)
    }
    /// Counts one box test; false once over the budget.
    fn spend(&self) -> bool {
        if self.over.load(Ordering::Relaxed) {
            return false;
        }
        if self.box_tests.fetch_add(1, Ordering::Relaxed) >= self.budget {
            self.over.store(true, Ordering::Relaxed);
            return false;
        }
        true
    }
}

impl<T: BoxTester> BoxTester for Checked<T> {
    fn ray(&self, x: &RayBox) -> bool {
        if !self.spend() {
            return false;
        }
        let hit = self.inner.ray(x);
        if !hit {
            let k = self.misses.fetch_add(1, Ordering::Relaxed);
            if self.exact_all || k.is_multiple_of(Self::SAMPLE) || self.binary32.ray(x) {
                self.exact_checks.fetch_add(1, Ordering::Relaxed);
                if Exact.ray(x) {
                    self.false_misses.fetch_add(1, Ordering::Relaxed);
                }
            }
        }
        hit
    }
    fn bundle(&self, x: &BundleBox) -> Verdict {
        if !self.spend() {
            return Verdict::AllMiss;
        }
        self.inner.bundle(x)
    }
    fn supports_bundles(&self) -> bool {
        self.inner.supports_bundles()
    }
    fn name(&self) -> &'static str {
        self.inner.name()
    }
    fn units(&self) -> &dyn Units {
        self.inner.units()
    }
}
