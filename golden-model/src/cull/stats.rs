//! Traversal counts with and without cull planes, for the figures of
//! `docs/cull.md` (`cargo run --release -p golden-model --example cull_stats`).
//!
//! Every node whose box the ray's segment may meet (the tester's `box_hit`)
//! is visited; without planes a visited leaf costs one leaf visit and one
//! triangle test per triangle. With planes, a node the tester culls is not
//! entered (its subtree is skipped). No early termination: the segment is
//! `[0, +inf)` and every leaf it may reach is counted, so the figures do not
//! depend on traversal order.

use super::builder::CullPlanes;
use super::bvh::{Bvh, Mesh, NodeKind};
use super::exact::{segment_hits_triangle, Dyadic};
use super::tester::{
    box_interval, eval, ray_terms, slab_reciprocal, ChildIn, Config, RayIn, RayTerms,
};
use crate::float::FloatFormat;

/// Totals over a set of rays.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// rays traced
    pub rays: u64,
    /// leaves visited without planes
    pub leaf_visits: u64,
    /// triangle tests without planes
    pub tri_tests: u64,
    /// leaves visited with planes
    pub leaf_visits_planes: u64,
    /// triangle tests with planes
    pub tri_tests_planes: u64,
    /// nodes (inner or leaf) culled by their planes
    pub culled_nodes: u64,
    /// node tests (box + planes) performed with planes
    pub node_tests_planes: u64,
    /// culled leaves checked exactly against their triangles
    pub checked_leaves: u64,
    /// culled leaves whose triangles the exact segment meets (must be 0)
    pub wrongful_culls: u64,
}

impl Counts {
    /// Adds another total.
    pub fn add(&mut self, o: &Counts) {
        self.rays += o.rays;
        self.leaf_visits += o.leaf_visits;
        self.tri_tests += o.tri_tests;
        self.leaf_visits_planes += o.leaf_visits_planes;
        self.tri_tests_planes += o.tri_tests_planes;
        self.culled_nodes += o.culled_nodes;
        self.node_tests_planes += o.node_tests_planes;
        self.checked_leaves += o.checked_leaves;
        self.wrongful_culls += o.wrongful_culls;
    }
    /// Fraction of leaf visits the planes remove.
    pub fn leaf_saving(&self) -> f64 {
        1.0 - self.leaf_visits_planes as f64 / self.leaf_visits.max(1) as f64
    }
    /// Fraction of triangle tests the planes remove.
    pub fn tri_saving(&self) -> f64 {
        1.0 - self.tri_tests_planes as f64 / self.tri_tests.max(1) as f64
    }
}

/// A ray in `f32`.
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    /// origin
    pub o: [f32; 3],
    /// direction
    pub d: [f32; 3],
}

fn bits(v: f32) -> u64 {
    v.to_bits() as u64
}

/// Traces one ray (segment `[0, +inf)`); with `check`, every culled leaf is
/// tested exactly against its triangles. A node is visited when the
/// conservative slab may hit its box; its children are tested with the ray
/// terms of its shared normals (computed once for both) and their distances.
pub fn trace(
    cfg: &Config,
    mesh: &Mesh,
    bvh: &Bvh,
    planes: &CullPlanes,
    ray: &Ray,
    check: bool,
) -> Counts {
    assert_eq!(cfg.ray, FloatFormat::BINARY32, "meshes are f32");
    let mut c = Counts {
        rays: 1,
        ..Counts::default()
    };
    if bvh.nodes.is_empty() {
        return c;
    }
    let walk = Walk {
        cfg,
        mesh,
        bvh,
        planes,
        o: ray.o.map(bits),
        d: ray.d.map(bits),
        inv_d: slab_reciprocal(cfg.ray, &ray.d.map(bits)),
        ray,
        check,
    };
    let root = walk.terms(&planes.root_normals, &bvh.nodes[0].min);
    walk.visit(0, root.as_ref(), false, &mut c);
    c
}

struct Walk<'a> {
    cfg: &'a Config,
    mesh: &'a Mesh,
    bvh: &'a Bvh,
    planes: &'a CullPlanes,
    o: [u64; 3],
    d: [u64; 3],
    inv_d: [u64; 3],
    ray: &'a Ray,
    check: bool,
}

impl Walk<'_> {
    /// The ray terms of a set of shared normals (`None` for none).
    fn terms(&self, normals: &[[u64; 3]], r_min: &[f32; 3]) -> Option<RayTerms> {
        (!normals.is_empty()).then(|| {
            ray_terms(
                self.cfg,
                &RayIn {
                    o: self.o,
                    d: self.d,
                    r: r_min.map(bits),
                    normals: normals.to_vec(),
                },
            )
        })
    }

    /// `terms`: the parent's ray terms (`None` at the root or when the
    /// parent has no normals); `culled_above`: an ancestor was culled.
    fn visit(&self, id: usize, terms: Option<&RayTerms>, culled_above: bool, c: &mut Counts) {
        let node = self.bvh.nodes[id];
        let f = self.cfg.ray;
        let Some((t_lo, t_hi)) = box_interval(
            f,
            &node.min.map(bits),
            &node.max.map(bits),
            &self.o,
            &self.inv_d,
            0,
            bits(f32::INFINITY),
        ) else {
            return;
        };
        if !culled_above {
            c.node_tests_planes += 1;
        }
        let culled_here = !culled_above
            && terms.is_some_and(|t| {
                !eval(
                    self.cfg,
                    &ChildIn {
                        t_lo,
                        t_hi,
                        w: self.planes.w[id].clone(),
                        terms: t.terms.clone(),
                    },
                )
                .keep
            });
        c.culled_nodes += culled_here as u64;
        let culled = culled_above || culled_here;
        match node.kind {
            NodeKind::Leaf { count, .. } => {
                c.leaf_visits += 1;
                c.tri_tests += count as u64;
                if !culled {
                    c.leaf_visits_planes += 1;
                    c.tri_tests_planes += count as u64;
                } else if self.check {
                    c.checked_leaves += 1;
                    let o = self.ray.o.map(Dyadic::from_f32);
                    let d = self.ray.d.map(Dyadic::from_f32);
                    let hit = self.bvh.leaf_tris(id).iter().any(|&t| {
                        let v = self.mesh.corners(t).map(|p| p.map(Dyadic::from_f32));
                        segment_hits_triangle(&o, &d, &Dyadic::zero(), None, &v)
                    });
                    c.wrongful_culls += hit as u64;
                }
            }
            NodeKind::Inner { left, right } => {
                let mine = if culled {
                    None
                } else {
                    self.terms(&self.planes.normals[id], &node.min)
                };
                for child in [left, right] {
                    self.visit(child as usize, mine.as_ref(), culled, c);
                }
            }
        }
    }
}

/// splitmix64, for reproducible ray sets.
#[derive(Debug, Clone)]
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Random rays for a mesh: the origin uniform on a sphere around the mesh
/// (radius 1.5 × the half diagonal of its box), aimed at a uniform point of
/// its box.
pub fn random_rays(mesh: &Mesh, n: usize, seed: u64) -> Vec<Ray> {
    let (lo, hi) = mesh.bounds();
    let c = [0, 1, 2].map(|i| (lo[i] as f64 + hi[i] as f64) / 2.0);
    let h = [0, 1, 2].map(|i| (hi[i] as f64 - lo[i] as f64) / 2.0);
    let r = 1.5 * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| {
            let z = 2.0 * rng.unit() - 1.0;
            let phi = 2.0 * std::f64::consts::PI * rng.unit();
            let s = (1.0 - z * z).sqrt();
            let o = [
                c[0] + r * s * phi.cos(),
                c[1] + r * s * phi.sin(),
                c[2] + r * z,
            ];
            let t = [0, 1, 2].map(|i| lo[i] as f64 + (hi[i] as f64 - lo[i] as f64) * rng.unit());
            Ray {
                o: o.map(|x| x as f32),
                d: [0, 1, 2].map(|i| (t[i] - o[i]) as f32),
            }
        })
        .collect()
}
