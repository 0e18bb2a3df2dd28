//! Throughput of the golden models on one core (issue #20), fast path and
//! generic reference side by side, binary32, realistic inputs (boxes in
//! [-1,1]^3, origins in [-4,4]^3, unit directions).
//!
//! `cargo run --release -p golden-model --example golden_speed [-- SECONDS [FILTER]]`
//! prints one line per unit (whose name contains FILTER): M tests/s (one
//! test = one call).

use golden_model::cull::{self, ChildIn, RayIn as CullRay};
use golden_model::float::FloatFormat;
use golden_model::silhouette::{self, BundleIn, Config, OriginMode, Rounding};
use golden_model::slab::{self, SlabIn};
use golden_model::transform::{self, DotStyle, InstanceTransform, InverseSource, WorldRay};
use std::hint::black_box;
use std::time::{Duration, Instant};

const F32: FloatFormat = FloatFormat::BINARY32;
const N: usize = 4096;

/// splitmix64.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// uniform in [lo, hi)
    fn f(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }
}

fn b(x: f32) -> u64 {
    x.to_bits() as u64
}

fn ray(rng: &mut Rng) -> ([f32; 3], [f32; 3]) {
    let o = [0; 3].map(|_| rng.f(-4.0, 4.0));
    let t = [0; 3].map(|_| rng.f(-1.0, 1.0));
    let d = [0, 1, 2].map(|i| t[i] - o[i]);
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    (o, d.map(|x| x / l))
}

/// Calls `f` on every input, round after round, for `secs`; M calls/s.
fn rate<T>(inputs: &[T], secs: f64, mut f: impl FnMut(&T) -> bool) -> f64 {
    let start = Instant::now();
    let mut calls = 0u64;
    while start.elapsed() < Duration::from_secs_f64(secs) {
        for x in inputs {
            black_box(f(black_box(x)));
        }
        calls += inputs.len() as u64;
    }
    calls as f64 / start.elapsed().as_secs_f64() / 1e6
}

fn main() {
    let secs: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let only = std::env::args().nth(2).unwrap_or_default();
    let mut rng = Rng(20);

    let rays: Vec<BundleIn> = (0..N)
        .map(|_| {
            let c = [0; 3].map(|_| rng.f(-1.0, 1.0));
            let h = [0; 3].map(|_| rng.f(0.0, 0.5));
            let (o, d) = ray(&mut rng);
            BundleIn::ray(
                [0, 1, 2].map(|i| b(c[i] - h[i])),
                [0, 1, 2].map(|i| b(c[i] + h[i])),
                o.map(b),
                d.map(b),
                0,
                b(f32::INFINITY),
            )
        })
        .collect();
    let sil = Config::new(F32, OriginMode::Shared, Rounding::Conservative).unwrap();
    let run = |what: &str| what.contains(only.as_str());
    let line = |what: &str, m: f64| println!("{what:<48} {m:>8.2} M tests/s");
    let what = "silhouette binary32 single ray, eval";
    if run(what) {
        line(
            what,
            rate(&rays, secs, |x| silhouette::eval(&sil, x).any_hit),
        );
    }
    let what = "silhouette binary32 single ray, eval_generic";
    if run(what) {
        line(
            what,
            rate(&rays, secs, |x| silhouette::eval_generic(&sil, x).any_hit),
        );
    }

    // the conservative slab beside every cull test: the same boxes and rays,
    // the reciprocal direction rounded toward zero as the contract says
    let slabs: Vec<SlabIn> = rays
        .iter()
        .map(|x| SlabIn {
            p_min: x.p_min,
            p_max: x.p_max,
            o: x.o_lo,
            inv_d: x
                .d_lo
                .map(|d| transform::recip(F32, d, golden_model::float::RoundingMode::TowardZero)),
            t_min: 0,
            t_max: x.t_max,
        })
        .collect();
    let what = "conservative slab binary32, eval_conservative";
    if run(what) {
        line(
            what,
            rate(&slabs, secs, |x| slab::eval_conservative(F32, x).hit),
        );
    }
    let what = "conservative slab binary32, eval_conservative_generic";
    if run(what) {
        line(
            what,
            rate(&slabs, secs, |x| {
                slab::eval_conservative_generic(F32, x).hit
            }),
        );
    }

    let ccfg = cull::Config::new(F32, FloatFormat::BINARY16, 4).unwrap();
    let h16 = |x: f32| {
        golden_model::float::convert(
            F32,
            FloatFormat::BINARY16,
            b(x),
            golden_model::float::RoundingMode::NearestEven,
        )
    };
    let cull_rays: Vec<CullRay> = (0..N)
        .map(|_| {
            let (o, d) = ray(&mut rng);
            CullRay {
                o: o.map(b),
                d: d.map(b),
                r: [0; 3].map(|_| b(rng.f(-1.0, 1.0))),
                normals: (0..4).map(|_| ray(&mut rng).1.map(h16)).collect(),
            }
        })
        .collect();
    line(
        "cull_ray (ray_terms), K = 4",
        rate(&cull_rays, secs, |x| cull::ray_terms(&ccfg, x).invalid),
    );
    line(
        "cull_ray (normal_terms_into, no allocation), K = 4",
        rate(&cull_rays, secs, |x| {
            let mut t = [cull::tester::NormalTerm::default(); 8];
            cull::tester::normal_terms_into(
                &ccfg,
                &x.o,
                &x.d,
                &x.r,
                &x.normals,
                &mut t,
                &mut [0; 8],
            )
        }),
    );
    let children: Vec<ChildIn> = cull_rays
        .iter()
        .map(|x| {
            let t = cull::ray_terms(&ccfg, x);
            let t_lo = rng.f(0.0, 3.0);
            ChildIn {
                t_lo: b(t_lo),
                t_hi: b(t_lo + rng.f(0.0, 1.0)),
                w: (0..4).map(|_| h16(rng.f(-0.5, 1.0))).collect(),
                terms: t.terms,
            }
        })
        .collect();
    let what = "cull (eval), K = 4";
    if run(what) {
        line(what, rate(&children, secs, |x| cull::eval(&ccfg, x).keep));
    }

    let xcfg = transform::Config {
        fmt: F32,
        mode: golden_model::float::RoundingMode::NearestEven,
        dot: DotStyle::Fma,
        source: InverseSource::PreInverted,
    };
    let xf: Vec<(WorldRay, InstanceTransform)> = (0..N)
        .map(|_| {
            let (o, d) = ray(&mut rng);
            (
                WorldRay {
                    origin: o.map(b),
                    dir: d.map(b),
                    t_min: 0,
                    t_max: b(f32::INFINITY),
                    id: 0,
                },
                InstanceTransform {
                    linear: [0; 9].map(|_| b(rng.f(-2.0, 2.0))),
                    translation: [0; 3].map(|_| b(rng.f(-3.0, 3.0))),
                    rotation_hint: false,
                },
            )
        })
        .collect();
    line(
        "transform (pre-inverted, fma dot), binary32",
        rate(&xf, secs, |(r, i)| {
            transform::transform(&xcfg, r, i).singular
        }),
    );
}
