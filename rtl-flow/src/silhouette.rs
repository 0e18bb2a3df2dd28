//! Stimulus and golden-model adapter for `silhouette`: the vectors of
//! [`super::rays`] (corner cases, then seeded random rays, a random share
//! of them widened into bundles) in the unit's port order.

use super::fstim::golden_format;
use super::rays::{bundle_of, coprime_stride, corner_cases, gen_ray, Kind, KINDS};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float::random::Random;
use golden_model::silhouette::{eval, BundleIn, Config, OriginMode, Rounding};
use rtl_gen::units::silhouette::{self as unit, Mode, Origin, Policy};
use rtl_gen::units::{port_at, port_at3};

/// Vectors and golden model of one `silhouette` configuration.
pub struct SilhouetteBench {
    cfg: Config,
    corners: Vec<BundleIn>,
    stride: u64,
    ports: Ports,
    /// the golden value of each output port, in port order
    outputs: Vec<Verdict>,
}

/// Which field of the golden model's result an output port carries.
#[derive(Clone, Copy)]
enum Verdict {
    AllHit,
    /// also a single ray's `hit` (a ray is a bundle whose bounds coincide)
    AnyHit,
    Nan,
    Invalid,
    MixedSign,
}

impl Verdict {
    fn of(name: &str) -> Verdict {
        match name {
            "hit" | "any_hit" => Verdict::AnyHit,
            "all_hit" => Verdict::AllHit,
            "nan" => Verdict::Nan,
            "invalid" => Verdict::Invalid,
            "mixed_sign" => Verdict::MixedSign,
            other => panic!("silhouette output `{other}` has no golden value"),
        }
    }
}

/// Where each field of a [`BundleIn`] goes among the unit's inputs, looked
/// up by name in the unit's own list (`Config::input_names`), so a port
/// added to the unit cannot shift the others. A ray's lower and upper
/// bounds share ports.
struct Ports {
    p_min: [usize; 3],
    p_max: [usize; 3],
    o_lo: [usize; 3],
    o_hi: [usize; 3],
    d_lo: [usize; 3],
    d_hi: [usize; 3],
    t_min: usize,
    t_max: usize,
}

impl Ports {
    fn of(u: &unit::Config) -> Ports {
        let names = u.input_names();
        let three = |g: &str| port_at3(&names, g);
        let (o_lo, o_hi, d_lo, d_hi) = match (u.mode, u.origin) {
            (Mode::Ray, _) => (three("o"), three("o"), three("d"), three("d")),
            (Mode::Bundle, Origin::Shared) => {
                (three("o_lo"), three("o_lo"), three("d_lo"), three("d_hi"))
            }
            (Mode::Bundle, Origin::Bounded) => {
                (three("o_lo"), three("o_hi"), three("d_lo"), three("d_hi"))
            }
        };
        Ports {
            p_min: three("p_min"),
            p_max: three("p_max"),
            o_lo,
            o_hi,
            d_lo,
            d_hi,
            t_min: port_at(&names, "t_min"),
            t_max: port_at(&names, "t_max"),
        }
    }
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
            ports: Ports::of(u),
            outputs: u.output_names().iter().map(|n| Verdict::of(n)).collect(),
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
        let p = &self.ports;
        let mut put3 = |at: &[usize; 3], x: &[u64; 3]| (0..3).for_each(|i| v[at[i]] = x[i]);
        // the upper bounds first: in ray mode the lower ones overwrite them
        put3(&p.o_hi, &b.o_hi);
        put3(&p.d_hi, &b.d_hi);
        put3(&p.p_min, &b.p_min);
        put3(&p.p_max, &b.p_max);
        put3(&p.o_lo, &b.o_lo);
        put3(&p.d_lo, &b.d_lo);
        v[p.t_min] = b.t_min;
        v[p.t_max] = b.t_max;
    }

    /// Reads a transaction from port order.
    pub fn from_ports(&self, v: &[u64]) -> BundleIn {
        let p = &self.ports;
        let three = |at: &[usize; 3]| at.map(|k| v[k]);
        BundleIn {
            p_min: three(&p.p_min),
            p_max: three(&p.p_max),
            o_lo: three(&p.o_lo),
            o_hi: three(&p.o_hi),
            d_lo: three(&p.d_lo),
            d_hi: three(&p.d_hi),
            t_min: v[p.t_min],
            t_max: v[p.t_max],
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
        for (o, v) in outputs.iter_mut().zip(&self.outputs) {
            *o = match v {
                Verdict::AllHit => out.all_hit,
                Verdict::AnyHit => out.any_hit,
                Verdict::Nan => out.nan,
                Verdict::Invalid => out.invalid,
                Verdict::MixedSign => out.mixed_sign,
            } as u64;
        }
    }
}

impl sim::Stimulus for SilhouetteBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let b = self.case(seed, index);
        self.to_ports(&b, v);
    }
}

impl Testbench for SilhouetteBench {}
