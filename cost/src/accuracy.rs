//! Accuracy of each configuration on shared workloads, against the exact
//! references of `golden-model` (never against another rounded model).
//!
//! Workloads (generated in binary64, then rounded to the format under test,
//! so every format sees the same geometry up to its own rounding; the exact
//! reference judges the rounded inputs, so every rate is exactly defined):
//!
//! * `random`: box centre uniform in [−1, 1]³, half extents in [0.01, 0.5],
//!   origin uniform in [−4, 4]³, unit direction, segment [0, +∞);
//! * `grazing` (adversarial): the ray is aimed at a uniform point of a random
//!   edge of the box, then every direction component is moved by −2..=2
//!   ulps of the format: about half of these rays hit, all within a few ulps
//!   of the boundary;
//! * `scene`: rays of `cull::stats::random_rays` for a shipped mesh (origin on
//!   a sphere around it, aimed into its box), traversed through the mesh's
//!   BVH by the exact test; every node whose parent the exact ray hits is
//!   one box test (at most 96 per ray). Node boxes are rounded outward
//!   (min down, max up), as a scene builder stores them.
//!
//! Metrics: false-hit rate = false hits / exact misses; false misses (a hit
//! the tester loses: for the silhouette tester this is a wrongful cull and
//! must be 0, and so for the conservative slab; the RNE slab baseline has
//! some, reported); uncertain = `any_hit ∧
//! ¬all_hit` on a single ray. Bundles (scene and random): direction
//! intervals `d·(1 ± s)` around each ray with a shared origin; resolved =
//! AllHit or AllMiss (no per-ray tests needed); a verdict contradicted by
//! one of the bundle's corner rays or 4 interior rays (exact reference) is
//! wrong and must never happen. Transform: `transform::accuracy::run` (the
//! issue #5 study) on random instances, relative error of the two-step and
//! the conventional method near (|O − T| = 0.01) and far (1000) from the
//! instance. Cull planes: `cull::stats::trace` with the exact check of every
//! culled leaf (wrongful culls must be 0) and the triangle tests saved.

use golden_model::cull::bvh::{parse_obj, Bvh, Mesh, NodeKind};
use golden_model::exact::ray_box::{corner_rays, ray_hits_box, BoxIn, RayIn};
use golden_model::float::{convert, FloatFormat, RoundingMode};
use golden_model::silhouette::{self, BundleIn, OriginMode, Rounding, Verdict};
use golden_model::slab::{self, SlabIn};
use golden_model::transform::accuracy::{from_f64, Rng};
use golden_model::transform::recip;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A ray/box case in binary64 before rounding.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    /// box lower corner
    pub lo: [f64; 3],
    /// box upper corner
    pub hi: [f64; 3],
    /// origin
    pub o: [f64; 3],
    /// direction
    pub d: [f64; 3],
    /// ulps to add to each direction component after rounding (grazing)
    pub nudge: [i8; 3],
}

/// Counts of one tester on one workload in one format.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct RayStats {
    /// cases
    pub n: u64,
    /// exact hits
    pub hits: u64,
    /// tester says hit, exact says miss
    pub false_hits: u64,
    /// tester says miss, exact says hit (wrongful culls)
    pub false_misses: u64,
    /// single-ray `any_hit ∧ ¬all_hit` (silhouette only)
    pub uncertain: u64,
}

impl RayStats {
    /// false hits / exact misses
    pub fn false_hit_rate(&self) -> f64 {
        self.false_hits as f64 / (self.n - self.hits).max(1) as f64
    }
    /// false misses / exact hits
    pub fn false_miss_rate(&self) -> f64 {
        self.false_misses as f64 / self.hits.max(1) as f64
    }
}

/// Bundle verdicts of the silhouette tester.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct BundleStats {
    /// bundles
    pub n: u64,
    /// AllHit
    pub all_hit: u64,
    /// AllMiss
    pub all_miss: u64,
    /// Mixed
    pub mixed: u64,
    /// verdicts contradicted by a checked ray (must be 0)
    pub wrong: u64,
}

impl BundleStats {
    /// Fraction resolved without per-ray tests.
    pub fn resolved(&self) -> f64 {
        (self.all_hit + self.all_miss) as f64 / self.n.max(1) as f64
    }
}

/// Generates `n` cases of a workload (`random` or `grazing`) from `seed`.
pub fn synthetic(kind: &str, n: usize, seed: u64) -> Vec<Case> {
    let mut rng = Rng::new(seed ^ 0x5eed_0008);
    (0..n)
        .map(|_| {
            let c = [(); 3].map(|_| rng.range(-1.0, 1.0));
            let h = [(); 3].map(|_| rng.range(0.01, 0.5));
            let lo = [0, 1, 2].map(|i| c[i] - h[i]);
            let hi = [0, 1, 2].map(|i| c[i] + h[i]);
            let o = loop {
                let o = [(); 3].map(|_| rng.range(-4.0, 4.0));
                if (0..3).any(|i| o[i] < lo[i] || o[i] > hi[i]) {
                    break o;
                }
            };
            if kind == "grazing" {
                let free = (rng.next_u64() % 3) as usize;
                let target: [f64; 3] = std::array::from_fn(|i| {
                    if i == free {
                        rng.range(lo[i], hi[i])
                    } else if rng.next_u64() & 1 == 0 {
                        lo[i]
                    } else {
                        hi[i]
                    }
                });
                let d = [0, 1, 2].map(|i| target[i] - o[i]);
                let nudge = [(); 3].map(|_| (rng.next_u64() % 5) as i8 - 2);
                Case {
                    lo,
                    hi,
                    o,
                    d,
                    nudge,
                }
            } else {
                Case {
                    lo,
                    hi,
                    o,
                    d: rng.direction(),
                    nudge: [0; 3],
                }
            }
        })
        .collect()
}

/// Loads an OBJ mesh.
pub fn load_mesh(path: &Path) -> Result<Mesh, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse_obj(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Scene cases: `rays` random rays of `mesh`, each against the BVH nodes an
/// exact traversal visits (binary64 exact: the f32 boxes and rays).
pub fn scene_cases(mesh: &Mesh, rays: usize, seed: u64) -> Vec<Case> {
    let bvh = Bvh::build(mesh, 4);
    let fmt = FloatFormat::BINARY32;
    let b = |v: f32| v.to_bits() as u64;
    let mut out = Vec::new();
    for r in golden_model::cull::stats::random_rays(mesh, rays, seed) {
        let ray = RayIn {
            o: r.o.map(b),
            d: r.d.map(b),
            t_min: 0,
            t_max: b(f32::INFINITY),
        };
        let mut stack = vec![0usize];
        let mut tested = 0;
        while let Some(id) = stack.pop() {
            if tested >= 96 || bvh.nodes.is_empty() {
                break;
            }
            tested += 1;
            let node = bvh.nodes[id];
            out.push(Case {
                lo: node.min.map(|x| x as f64),
                hi: node.max.map(|x| x as f64),
                o: r.o.map(|x| x as f64),
                d: r.d.map(|x| x as f64),
                nudge: [0; 3],
            });
            let bx = BoxIn {
                p_min: node.min.map(b),
                p_max: node.max.map(b),
            };
            if ray_hits_box(fmt, &bx, &ray).hit {
                if let NodeKind::Inner { left, right } = node.kind {
                    stack.push(left as usize);
                    stack.push(right as usize);
                }
            }
        }
    }
    out
}

fn nudge(fmt: FloatFormat, x: u64, k: i8) -> u64 {
    // Moves a finite nonzero value k ulps away from (k > 0) or toward zero.
    if k == 0 || x & !fmt.sign_bit() == 0 {
        return x;
    }
    let mag = (x & !fmt.sign_bit()) as i64 + k as i64;
    let mag = mag.clamp(1, fmt.max_finite(false) as i64) as u64;
    (x & fmt.sign_bit()) | mag
}

/// The case rounded to `fmt`: box outward, origin and direction to nearest
/// (then nudged), segment [0, +∞).
pub fn round_case(fmt: FloatFormat, c: &Case) -> (BoxIn, RayIn) {
    let f64b = FloatFormat::BINARY64;
    let dn = |x: f64| convert(f64b, fmt, x.to_bits(), RoundingMode::Down);
    let up = |x: f64| convert(f64b, fmt, x.to_bits(), RoundingMode::Up);
    let d = [0, 1, 2].map(|i| nudge(fmt, from_f64(fmt, c.d[i]), c.nudge[i]));
    (
        BoxIn {
            p_min: c.lo.map(dn),
            p_max: c.hi.map(up),
        },
        RayIn {
            o: c.o.map(|x| from_f64(fmt, x)),
            d,
            t_min: fmt.zero(false),
            t_max: fmt.inf(false),
        },
    )
}

/// Single-ray statistics of every box tester on one workload.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RayStatsAll {
    /// silhouette tester, conservative, shared origin: `any_hit` of
    /// `BundleIn::ray` (the `hit` output of `mode=ray`, and the AnyHit bit of
    /// `mode=bundle` on a single ray: one number serves both modes)
    pub silhouette: RayStats,
    /// slab baseline, RNE products, `inv_d = RNE(1/d)` (`slab`, the default
    /// `rounding=nearest`)
    pub slab: RayStats,
    /// conservative slab (`slab -p rounding=conservative`):
    /// `golden_model::slab::eval_conservative` with `inv_d = RTZ(1/d)`, the
    /// reciprocal `rtl-flow/src/slab.rs` feeds it
    pub slab_conservative: RayStats,
}

/// Single-ray statistics of the silhouette tester (conservative, shared
/// origin), the RNE slab (`inv_d` correctly rounded) and the conservative
/// slab (`inv_d` rounded toward zero, directed products).
pub fn ray_stats(fmt: FloatFormat, cases: &[Case]) -> RayStatsAll {
    let cfg = silhouette::Config::new(fmt, OriginMode::Shared, Rounding::Conservative)
        .expect("format has an exact-product format");
    let mut all = RayStatsAll::default();
    for c in cases {
        let (bx, ray) = round_case(fmt, c);
        let exact = ray_hits_box(fmt, &bx, &ray).hit;
        let out = silhouette::eval(
            &cfg,
            &BundleIn::ray(bx.p_min, bx.p_max, ray.o, ray.d, ray.t_min, ray.t_max),
        );
        let slab_in = |round: RoundingMode| SlabIn {
            p_min: bx.p_min,
            p_max: bx.p_max,
            o: ray.o,
            inv_d: ray.d.map(|d| recip(fmt, d, round)),
            t_min: ray.t_min,
            t_max: ray.t_max,
        };
        let s = slab::eval(fmt, &slab_in(RoundingMode::NearestEven));
        let sc = slab::eval_conservative(fmt, &slab_in(RoundingMode::TowardZero));
        for (st, hit, unc) in [
            (
                &mut all.silhouette,
                out.any_hit,
                out.any_hit && !out.all_hit,
            ),
            (&mut all.slab, s.hit, false),
            (&mut all.slab_conservative, sc.hit, false),
        ] {
            st.n += 1;
            st.hits += exact as u64;
            st.false_hits += (hit && !exact) as u64;
            st.false_misses += (!hit && exact) as u64;
            st.uncertain += unc as u64;
        }
    }
    all
}

/// Bundle statistics: each case becomes a bundle of directions
/// `d·(1 ± spread)` (per component, bounds ordered) with a shared origin.
pub fn bundle_stats(fmt: FloatFormat, cases: &[Case], spread: f64, seed: u64) -> BundleStats {
    let cfg = silhouette::Config::new(fmt, OriginMode::Shared, Rounding::Conservative)
        .expect("format has an exact-product format");
    let mut rng = Rng::new(seed ^ 0xb0d1e);
    let mut st = BundleStats::default();
    for c in cases {
        let (bx, ray) = round_case(fmt, c);
        let d64 = c.d;
        let a = d64.map(|d| d * (1.0 - spread));
        let b = d64.map(|d| d * (1.0 + spread));
        let lo64 = [0, 1, 2].map(|i| a[i].min(b[i]));
        let hi64 = [0, 1, 2].map(|i| a[i].max(b[i]));
        let f64b = FloatFormat::BINARY64;
        let d_lo = lo64.map(|x| convert(f64b, fmt, x.to_bits(), RoundingMode::Down));
        let d_hi = hi64.map(|x| convert(f64b, fmt, x.to_bits(), RoundingMode::Up));
        let out = silhouette::eval(
            &cfg,
            &BundleIn {
                p_min: bx.p_min,
                p_max: bx.p_max,
                o_lo: ray.o,
                o_hi: ray.o,
                d_lo,
                d_hi,
                t_min: ray.t_min,
                t_max: ray.t_max,
            },
        );
        let mut rays = corner_rays(ray.o, ray.o, d_lo, d_hi, ray.t_min, ray.t_max);
        for _ in 0..4 {
            let d = [0, 1, 2].map(|i| from_f64(fmt, lo64[i] + (hi64[i] - lo64[i]) * rng.unit()));
            rays.push(RayIn { d, ..ray });
        }
        let hits: Vec<bool> = rays.iter().map(|r| ray_hits_box(fmt, &bx, r).hit).collect();
        st.n += 1;
        match out.verdict() {
            Verdict::AllHit => {
                st.all_hit += 1;
                st.wrong += hits.iter().any(|h| !h) as u64;
            }
            Verdict::AllMiss => {
                st.all_miss += 1;
                st.wrong += hits.iter().any(|h| *h) as u64;
            }
            Verdict::Mixed => st.mixed += 1,
        }
    }
    st
}

/// Transform accuracy in one format: relative error (max, median) of the
/// two-step (chained fma) and conventional methods at one offset.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct TransformErr {
    /// |O_w − T|
    pub offset: f64,
    /// origins measured
    pub n: usize,
    /// two-step max relative error
    pub two_step_max: f64,
    /// two-step median relative error
    pub two_step_med: f64,
    /// conventional max relative error
    pub conv_max: f64,
    /// conventional median relative error
    pub conv_med: f64,
}

/// Runs the transform study on `matrices` random instances, `points` origins
/// each, near (0.01) and far (1000) from the instance.
pub fn transform_err(
    fmt: FloatFormat,
    matrices: usize,
    points: usize,
    seed: u64,
) -> Vec<TransformErr> {
    use golden_model::transform::accuracy::{run, StudyOptions};
    let o = StudyOptions {
        fmt,
        points: 0,
        random_matrices: matrices,
        random_points: points,
        offsets: vec![1e-2, 1e3],
        seed,
        ..Default::default()
    };
    run(&o)
        .into_iter()
        .filter(|r| r.set == "random")
        .map(|r| TransformErr {
            offset: r.offset,
            n: r.n,
            two_step_max: r.two_step[0].max_rel,
            two_step_med: r.two_step[0].med_rel,
            conv_max: r.conventional.max_rel,
            conv_med: r.conventional.med_rel,
        })
        .collect()
}

/// Cull-plane results on a mesh for one plane format.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct CullStats {
    /// plane format exponent bits
    pub plane_exp: u32,
    /// plane format fraction bits
    pub plane_frac: u32,
    /// planes per node
    pub k: usize,
    /// rays traced
    pub rays: u64,
    /// culled leaves whose triangles the exact ray meets (must be 0)
    pub wrongful_culls: u64,
    /// culled leaves checked
    pub checked_leaves: u64,
    /// fraction of triangle tests the planes remove
    pub tri_saving: f64,
}

/// Traces `rays` random rays of `mesh` with K planes of format `plane`.
pub fn cull_stats(mesh: &Mesh, plane: FloatFormat, k: usize, rays: usize, seed: u64) -> CullStats {
    use golden_model::cull::builder::{build_planes, BuildParams};
    use golden_model::cull::stats::{trace, Counts};
    use golden_model::cull::tester::Config;
    let bvh = Bvh::build(mesh, 4);
    let planes = build_planes(
        mesh,
        &bvh,
        &BuildParams {
            plane,
            k,
            samples: 4,
        },
    );
    let cfg = Config::new(FloatFormat::BINARY32, plane, k).expect("plane format fits");
    let mut total = Counts::default();
    for r in golden_model::cull::stats::random_rays(mesh, rays, seed) {
        total.add(&trace(&cfg, mesh, &bvh, &planes, &r, true));
    }
    CullStats {
        plane_exp: plane.exp_bits(),
        plane_frac: plane.frac_bits(),
        k,
        rays: total.rays,
        wrongful_culls: total.wrongful_culls,
        checked_leaves: total.checked_leaves,
        tri_saving: total.tri_saving(),
    }
}
