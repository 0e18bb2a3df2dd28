//! Box testers the traversal can use. Every box test of the golden-model
//! renderer goes through one of these; the choice is the renderer's `--box` option.
//!
//! | tester | single ray | bundle |
//! |---|---|---|
//! | [`Golden`] | `silhouette::eval` (binary32, conservative), hit = `any_hit` | same unit, AllHit / AllMiss / Mixed |
//! | [`Exact`] | `exact::ray_box::ray_hits_box` (rationals) | not used (bundles are split) |
//! | [`Slab`] | plain `f32` slab test (reciprocal direction), for speed comparison | not used |
//! | `rtl::RtlTester` | the Verilated silhouette unit | the same unit |

use golden_model::exact::ray_box::{ray_hits_box, BoxIn, RayIn};
use golden_model::float::FloatFormat;
use golden_model::silhouette::{eval, BundleIn, Config, OriginMode, Rounding, Verdict};

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
}

/// A bundle box test: the silhouette unit's inputs (binary32 bits), shared
/// origin when `o_lo == o_hi`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BundleBox {
    /// the unit's input record (`t_min` = +0)
    pub input: BundleIn,
    /// every ray has the same origin (use the shared-origin unit)
    pub shared: bool,
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

/// The unit's input record for a single ray (shared-origin unit).
pub fn ray_input(x: &RayBox) -> BundleIn {
    BundleIn::ray(x.p_min, x.p_max, x.o, x.d, 0, x.t_max)
}

impl BoxTester for Golden {
    fn ray(&self, x: &RayBox) -> bool {
        eval(&self.shared, &ray_input(x)).any_hit
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
