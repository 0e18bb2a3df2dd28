//! Stimulus and golden-model adapter for `silhouette`: the vectors of
//! [`super::rays`] (corner cases, then seeded random rays, a random share
//! of them widened into bundles) in the unit's port order.

use super::fstim::golden_format;
use super::rays::{bundle_of, coprime_stride, corner_cases, gen_ray, Kind, KINDS};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float::random::Random;
use golden_model::silhouette::{eval, BundleIn, Config, OriginMode, Rounding};
use rtl_gen::units::ports;
use rtl_gen::units::silhouette::{self as unit, Origin, Policy, SilhouetteIn, SilhouetteOut};

/// Vectors and golden model of one `silhouette` configuration.
pub struct SilhouetteBench {
    cfg: Config,
    unit: unit::Config,
    corners: Vec<BundleIn>,
    stride: u64,
}

impl SilhouetteBench {
    /// The testbench of a `silhouette` configuration (mapped onto the
    /// golden model's).
    pub fn new(u: &unit::Config) -> Self {
        let fmt = golden_format(u.fmt);
        let origin = match u.origin {
            Origin::Bounded => OriginMode::Bounded,
            Origin::Shared => OriginMode::Shared,
        };
        let rounding = match u.policy {
            Policy::Nearest => Rounding::Nearest,
            Policy::Conservative => Rounding::Conservative,
        };
        let cfg =
            Config::new(fmt, origin, rounding).expect("exact-product format checked by the unit");
        let corners = corner_cases(fmt, origin == OriginMode::Bounded);
        let stride = coprime_stride(corners.len() as u64);
        SilhouetteBench {
            cfg,
            corners,
            stride,
            unit: *u,
        }
    }

    /// Number of corner-case vectors before the random ones.
    pub fn corner_count(&self) -> u64 {
        self.corners.len() as u64
    }

    fn bounded(&self) -> bool {
        self.cfg.origin == OriginMode::Bounded
    }

    /// The transaction of vector `index` under `seed`.
    pub fn case(&self, seed: u64, index: u64) -> BundleIn {
        let n = self.corner_count();
        if index < n {
            return self.corners[((index as u128 * self.stride as u128) % n as u128) as usize];
        }
        let fmt = self.cfg.fmt();
        let mut rng = VectorRng::new(seed, index);
        let kind = KINDS[rng.below(KINDS.len() as u64) as usize];
        let c = gen_ray(fmt, &mut rng, kind);
        let bundle_share = if self.bounded() { 3 } else { 2 };
        if kind != Kind::AnyBits && rng.chance(bundle_share, 4) {
            bundle_of(fmt, &mut rng, &c, self.bounded(), true)
        } else {
            let mut b = BundleIn::ray(c.p_min, c.p_max, c.o, c.d, c.t_min, c.t_max);
            if kind == Kind::AnyBits {
                let w = fmt.width();
                for i in 0..3 {
                    b.o_hi[i] = if rng.chance(1, 2) {
                        rng.bits(w)
                    } else {
                        b.o_lo[i]
                    };
                    b.d_hi[i] = if rng.chance(1, 2) {
                        rng.bits(w)
                    } else {
                        b.d_lo[i]
                    };
                }
            }
            b
        }
    }

    /// Writes a transaction into port order (ray mode: the lower bounds are
    /// the ray).
    pub fn to_ports(&self, b: &BundleIn, v: &mut [u64]) {
        let record = SilhouetteIn {
            p_min: b.p_min,
            p_max: b.p_max,
            o_lo: b.o_lo,
            o_hi: b.o_hi,
            d_lo: b.d_lo,
            d_hi: b.d_hi,
            t_min: b.t_min,
            t_max: b.t_max,
        };
        ports::pack(&self.unit, &record, v)
    }

    /// Reads a transaction from port order.
    pub fn from_ports(&self, v: &[u64]) -> BundleIn {
        let r: SilhouetteIn<u64> = ports::unpack(&self.unit, v);
        BundleIn {
            p_min: r.p_min,
            p_max: r.p_max,
            o_lo: r.o_lo,
            o_hi: r.o_hi,
            d_lo: r.d_lo,
            d_hi: r.d_hi,
            t_min: r.t_min,
            t_max: r.t_max,
        }
    }

    /// The golden model's configuration.
    pub fn config(&self) -> &Config {
        &self.cfg
    }
}

impl sim::Golden for SilhouetteBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let out = eval(&self.cfg, &self.from_ports(inputs));
        let record = SilhouetteOut {
            all_hit: Some(out.all_hit as u64),
            any_hit: out.any_hit as u64,
            nan: out.nan as u64,
            invalid: out.invalid as u64,
            mixed_sign: Some(out.mixed_sign as u64),
        };
        ports::pack(&self.unit, &record, outputs)
    }
}

impl sim::Stimulus for SilhouetteBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let b = self.case(seed, index);
        self.to_ports(&b, v);
    }
}

impl Testbench for SilhouetteBench {}
