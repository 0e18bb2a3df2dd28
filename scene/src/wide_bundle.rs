//! Would a bundle mode of the node tester pay (issue 36, step 3)? An upper
//! bound measured on camera rays, before any bundle unit is built.
//!
//! Each ray of a `tile × tile` pixel bundle is traced alone through the wide
//! BVH with the `node` unit's model, and every node test it makes is logged
//! (the node, the ray's origin in the tree's space, which slots hit). A
//! bundle traversal would visit the union of its rays' nodes. At a node that
//! `k ≥ 2` of the bundle's rays test, an **oracle** bundle test (as tight as
//! the single-ray tests and never wrong) answers for all `k` in one
//! transaction when every slot is hit by all of them or by none (seed 000's
//! AllHit / AllMiss per child); otherwise the bundle test was spent and the
//! `k` rays are tested one by one. Any real, conservative bundle test says
//! "mixed" at least as often and has to give each ray its own entry order,
//! so the single-ray tests it saves are at most these, and the break-even
//! cost below is an upper bound on what a bundle node test may cost.

use crate::bvh::Accel;
use crate::render::Cam;
use crate::scene::Scene;
use crate::stats::{RayKind, Stats};
use crate::tester::Exact;
use crate::trace::{TRay, TraceOpts, Tracer};
use crate::units::{ChildTestIn, GoldenUnits, NodeTestIn, RayTermsIn, Units};
use crate::wide::{Boxes, WideAccel};
use golden_model::cull::tester::NormalTerm;
use golden_model::node::NodeOut;
use golden_model::transform::{InstanceTransform, ModelRay, WorldRay};
use golden_model::triangle::{TriIn, TriNum, TriOut};
use rayon::prelude::*;
use std::collections::HashMap;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::sync::Mutex;

/// The golden units, with every node test logged as (node and ray origin,
/// hit slots).
struct NodeLog {
    tests: Mutex<Vec<(u64, u8)>>,
}

impl Units for NodeLog {
    fn transform(&self, ray: &WorldRay, inst: &InstanceTransform) -> ModelRay {
        GoldenUnits::get().transform(ray, inst)
    }
    fn cull_ray(&self, x: &RayTermsIn, terms: &mut [NormalTerm]) {
        GoldenUnits::get().cull_ray(x, terms)
    }
    fn cull(&self, x: &ChildTestIn) -> bool {
        GoldenUnits::get().cull(x)
    }
    fn triangle(&self, x: &TriIn) -> TriOut {
        GoldenUnits::get().triangle(x)
    }
    fn triangle_tnum(&self, x: &TriIn) -> TriNum {
        GoldenUnits::get().triangle_tnum(x)
    }
    fn node(&self, x: &NodeTestIn) -> NodeOut {
        let out = GoldenUnits::get().node(x);
        // the node by its record, the tree's space by the ray's origin there (a
        // bundle's rays share it; two instances of one mesh do not)
        let mut h = DefaultHasher::new();
        let n = x.node;
        (n.origin, n.exp, n.valid, n.lo, n.hi, x.ray.o).hash(&mut h);
        let hits = out
            .slots
            .iter()
            .filter(|s| s.hit)
            .fold(0u8, |m, s| m | 1 << s.child);
        self.tests
            .lock()
            .expect("the log is not poisoned")
            .push((h.finish(), hits));
        out
    }
}

/// Node tests of the camera rays, alone and with an oracle bundle test.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BundleBound {
    /// camera rays
    pub rays: u64,
    /// node tests of the rays traced alone
    pub single_tests: u64,
    /// oracle bundle tests (one per node that two or more rays of a bundle test)
    pub bundle_tests: u64,
    /// of those, the ones that answer for every ray (no slot split)
    pub resolved: u64,
    /// single-ray node tests left beside the bundle tests
    pub single_after: u64,
}

impl BundleBound {
    /// The cost of a bundle node test, in single node tests, at which bundles
    /// break even: below it they save, above it they cost.
    pub fn break_even(&self) -> f64 {
        (self.single_tests - self.single_after) as f64 / self.bundle_tests.max(1) as f64
    }

    /// The share of bundle tests that answer for every ray (AllHit or AllMiss
    /// on every slot).
    pub fn resolved_share(&self) -> f64 {
        self.resolved as f64 / self.bundle_tests.max(1) as f64
    }

    /// Node tests per ray alone, and bundle plus single tests per ray with
    /// the oracle.
    pub fn per_ray(&self) -> (f64, f64, f64) {
        let r = self.rays.max(1) as f64;
        (
            self.single_tests as f64 / r,
            self.bundle_tests as f64 / r,
            self.single_after as f64 / r,
        )
    }
}

/// [`BundleBound`] of the `w`×`h` camera rays through `wide` (the `node`
/// unit's model), bundled in `tile × tile` pixel tiles.
pub fn bundle_bound(
    scene: &Scene,
    accel: &Accel,
    wide: &WideAccel,
    w: u32,
    h: u32,
    tile: u32,
) -> BundleBound {
    let cam = Cam::new(scene, w, h);
    let tiles: Vec<(u32, u32)> = (0..h.div_ceil(tile))
        .flat_map(|ty| (0..w.div_ceil(tile)).map(move |tx| (tx * tile, ty * tile)))
        .collect();
    tiles
        .par_iter()
        .map(|&(x0, y0)| {
            let log = NodeLog {
                tests: Mutex::new(Vec::new()),
            };
            let mut tracer = Tracer::new(scene, accel, &Exact, TraceOpts::default())
                .with_wide(wide, Boxes::Node);
            tracer.units = &log;
            // per node of the bundle's union: the rays' hit slots
            let mut nodes: HashMap<u64, Vec<u8>> = HashMap::new();
            let mut b = BundleBound::default();
            for y in y0..(y0 + tile).min(h) {
                for x in x0..(x0 + tile).min(w) {
                    let mut rays = vec![TRay::new(cam.o, cam.dir(x, y), f64::INFINITY, false)];
                    tracer.trace(&mut rays, &[0], RayKind::Primary, &mut Stats::default());
                    b.rays += 1;
                    let mut tests = log.tests.lock().expect("the log is not poisoned");
                    for (node, hits) in tests.drain(..) {
                        nodes.entry(node).or_default().push(hits);
                    }
                }
            }
            for masks in nodes.values() {
                let k = masks.len() as u64;
                b.single_tests += k;
                if k < 2 {
                    b.single_after += k;
                    continue;
                }
                b.bundle_tests += 1;
                if masks.iter().all(|&m| m == masks[0]) {
                    b.resolved += 1;
                } else {
                    b.single_after += k;
                }
            }
            b
        })
        .reduce(BundleBound::default, |a, b| BundleBound {
            rays: a.rays + b.rays,
            single_tests: a.single_tests + b.single_tests,
            bundle_tests: a.bundle_tests + b.bundle_tests,
            resolved: a.resolved + b.resolved,
            single_after: a.single_after + b.single_after,
        })
}
