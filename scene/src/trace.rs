//! Two-level traversal of rays and ray bundles through the [`Accel`], with
//! every box test through a [`BoxTester`] (golden silhouette unit by default),
//! and every instance transform, cull test and (with `--tri golden`) triangle
//! test through the tester's [`Units`] (their golden models unless the
//! tester brings its own, as the RTL in the loop does). The default triangle
//! test is the watertight test in f64 ([`intersect`]).
//!
//! A traversal is depth first, nearer child first (ordered by the distance of
//! the child box centre along the first active ray: a heuristic, not a test).
//! Closest hits are the minimum of `(t, instance, primitive)`, so the result
//! does not depend on traversal order; boxes are tested against the segment
//! `[0, t_best·(1 + 2⁻²⁰)]` (rounded up), so every triangle whose computed `t`
//! ties or beats the best one is still reached with any conservative box test.

use crate::bvh::{f32_up, Accel, InstanceXf, PLANES_K};
use crate::render::unit_by_division;
use crate::scene::Scene;
use crate::stats::{KindStats, RayKind, Stats};
use crate::tester::{BoxTester, BundleBox, RayBox};
use crate::units::{ChildTestIn, RayTermsIn, Units};
use crate::wide::{Boxes, WideAccel};
use glam::{DVec3, Mat3, Vec3};
use golden_model::cull::bvh::{Mesh, NodeKind};
use golden_model::cull::tester::{box_interval, slab_reciprocal, NormalTerm};
use golden_model::float::FloatFormat;
use golden_model::silhouette::{BundleIn, Verdict};
use golden_model::transform::{InstanceTransform, WorldRay};
use golden_model::triangle as golden_triangle;

/// Closest hit so far (`inst == NONE`: none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// ray parameter (units of the ray direction, the same in world and model space)
    pub t: f64,
    /// instance
    pub inst: u32,
    /// triangle of the instance's mesh
    pub prim: u32,
}

/// No instance.
pub const NONE: u32 = u32::MAX;

impl Hit {
    /// Whether something was hit.
    pub fn is_hit(&self) -> bool {
        self.inst != NONE
    }
}

/// A ray in flight.
#[derive(Debug, Clone, Copy)]
pub struct TRay {
    /// world origin
    pub o_w: Vec3,
    /// world direction (any length)
    pub d_w: Vec3,
    /// current-space origin bits (world at the top level, model below)
    pub o: [u64; 3],
    /// current-space direction bits
    pub d: [u64; 3],
    /// segment end (`+inf` for closest-hit rays)
    pub t_max: f64,
    /// any-hit ray: stop at the first hit (shadow and AO rays)
    pub any: bool,
    /// best hit so far (for any-hit rays: the first one found)
    pub hit: Hit,
    /// finished (any-hit ray with a hit)
    pub done: bool,
    /// `slab_reciprocal(d)` of the model-space direction, set with it when
    /// the ray enters an instance (for the conservative slab beside the
    /// cull unit)
    pub(crate) inv_d: [u64; 3],
    /// `golden_model::triangle::shear(d)` of the model-space direction, set
    /// with it when the ray enters an instance (`--tri golden`)
    pub(crate) shear: (u32, [u64; 3]),
}

impl TRay {
    /// Brings the world ray into instance `x`'s model space through the
    /// transform unit of `units` (golden model or RTL; ray id `id`), with
    /// the slab's reciprocal direction.
    pub fn enter_instance(&mut self, units: &dyn Units, x: &InstanceXf, id: u64) {
        let m = units.transform(
            &WorldRay {
                origin: bits3(self.o_w),
                dir: bits3(self.d_w),
                t_min: 0,
                t_max: bits(f32::INFINITY),
                id,
            },
            &InstanceTransform {
                linear: x.inv_bits,
                translation: x.t_bits,
                rotation_hint: false,
            },
        );
        self.o = m.origin;
        self.d = m.dir;
        self.inv_d = slab_reciprocal(FloatFormat::BINARY32, &self.d);
    }
}

fn bits(v: f32) -> u64 {
    v.to_bits() as u64
}

/// The binary32 bits of `v`'s components, as the units take them.
pub(crate) fn bits3(v: Vec3) -> [u64; 3] {
    v.to_array().map(bits)
}

impl TRay {
    /// A new ray with segment `[0, t_max]`.
    pub fn new(o: Vec3, d: Vec3, t_max: f64, any: bool) -> TRay {
        TRay {
            o_w: o,
            d_w: d,
            o: bits3(o),
            d: bits3(d),
            t_max,
            any,
            hit: Hit {
                t: t_max,
                inst: NONE,
                prim: NONE,
            },
            done: false,
            // set on entering an instance, the only place they are read below
            inv_d: [0; 3],
            shear: (0, [0; 3]),
        }
    }
    /// The end of the segment the box tests use (binary32 bits, rounded up).
    pub fn box_t_max(&self) -> u64 {
        let t = if self.any || !self.hit.is_hit() {
            self.t_max
        } else {
            self.hit.t * (1.0 + 1.0 / (1u64 << 20) as f64)
        };
        bits(if t.is_infinite() {
            f32::INFINITY
        } else {
            f32_up(t)
        })
    }
}

/// Bundle traversal options (seed 000).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BundleOpts {
    /// build and test bundles at all
    pub enabled: bool,
    /// maximum rays per bundle (4, 16, 32, 64)
    pub max_size: usize,
    /// splitting metric: fewer active rays than this are tested one by one
    pub min_size: usize,
    /// splitting metric and builder threshold: largest allowed range of a
    /// normalised direction component
    pub max_spread: f32,
    /// builder threshold: largest allowed origin box extent, relative to the scene size
    pub max_origin_extent: f32,
    /// open bundles kept by the builder
    pub open: usize,
}

impl Default for BundleOpts {
    fn default() -> Self {
        BundleOpts {
            enabled: true,
            max_size: 16,
            min_size: 3,
            max_spread: 0.2,
            max_origin_extent: 0.02,
            open: 8,
        }
    }
}

/// The ray/triangle test the leaves run (`render --tri`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TriTest {
    /// the software watertight test in f64 on the binary32 data ([`intersect`])
    #[default]
    F64,
    /// the `triangle` unit's golden model at binary32 (`golden_model::triangle`)
    Golden,
    /// the `triangle` unit with `outputs=tnum`: the segment test in the unit
    /// (exact products, no division), `t = T/det` finished in software once
    /// per hit (`golden_model::triangle::finish_t`, the unit's `full` rounding)
    GoldenTnum,
    /// the exact rational test (`golden_model::triangle::exact`)
    Exact,
}

/// How rays are traced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceOpts {
    /// use the cull planes
    pub planes: bool,
    /// bundles
    pub bundles: BundleOpts,
    /// transform rays with plain f32 arithmetic instead of the golden model
    /// (the f32 slab baseline renderer)
    pub f32_transform: bool,
    /// the ray/triangle test
    pub tri: TriTest,
}

impl TraceOpts {
    /// Single rays without cull planes (the reference of the wide traversal,
    /// which traces that way).
    pub fn single_rays() -> TraceOpts {
        TraceOpts {
            planes: false,
            bundles: BundleOpts {
                enabled: false,
                ..BundleOpts::default()
            },
            ..TraceOpts::default()
        }
    }
}

impl Default for TraceOpts {
    fn default() -> Self {
        TraceOpts {
            planes: true,
            bundles: BundleOpts::default(),
            f32_transform: false,
            tri: TriTest::F64,
        }
    }
}

/// The ray terms of one node's shared normals, per ray, computed when a
/// child's cull test first asks for them (a ray that never reaches a cull
/// test below the node costs nothing), in a list from the thread's
/// [`Scratch`] (no allocation once the lists have grown).
struct LazyTerms<'n> {
    normals: &'n [[u64; 3]],
    /// the node's lower corner (binary32 bits)
    r_min: [u64; 3],
    /// planes on and the node has normals
    on: bool,
    /// the terms computed so far (ray index, terms), returned to the
    /// scratch by [`LazyTerms::finish`]
    computed: TermsList,
}

impl LazyTerms<'_> {
    /// How many rays' terms were computed (`cull_ray` transactions); the
    /// list goes back to `scratch`.
    fn finish(self, scratch: &mut Scratch) -> u64 {
        let n = self.computed.len() as u64;
        scratch.terms.push(self.computed);
        n
    }

    /// The terms of ray `i` (`r`), the first `k` entries.
    fn get(&mut self, units: &dyn Units, i: usize, r: &TRay) -> &[NormalTerm; 8] {
        // computed in place (no copy of the terms)
        let (normals, r_min) = (self.normals, self.r_min);
        let x = RayTermsIn {
            o: &r.o,
            d: &r.d,
            r_min: &r_min,
            normals,
        };
        match self.computed.iter().position(|x| x.0 == i) {
            Some(p) => &self.computed[p].1,
            None => {
                self.computed.push((i, [NormalTerm::default(); 8]));
                let t = &mut self.computed.last_mut().unwrap().1;
                units.cull_ray(&x, t);
                t
            }
        }
    }
}

/// The ray terms of a node's normals for several rays (ray index, terms).
type TermsList = Vec<(usize, [NormalTerm; 8])>;

/// Spare lists of one thread's traversals, recycled so that a traversal
/// allocates nothing once the lists have grown.
#[derive(Default)]
struct Scratch {
    /// ray lists
    rays: Vec<Vec<usize>>,
    /// [`LazyTerms`]' lists
    terms: Vec<TermsList>,
}

impl Scratch {
    /// A spare ray list holding `idxs`.
    fn list_of(&mut self, idxs: &[usize]) -> Vec<usize> {
        let mut v = self.rays.pop().unwrap_or_default();
        v.clear();
        v.extend_from_slice(idxs);
        v
    }
}

thread_local! {
    /// This thread's spare lists.
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// Traces rays through a scene.
pub struct Tracer<'a> {
    /// the acceleration structure
    pub accel: &'a Accel,
    /// the meshes (same indices as the BLAS)
    pub meshes: Vec<&'a Mesh>,
    /// the box tester
    pub tester: &'a dyn BoxTester,
    /// options
    pub opts: TraceOpts,
    /// the transform, cull and triangle units (the box tester's)
    pub(crate) units: &'a dyn Units,
    /// traverse this wide BVH instead ([`Tracer::with_wide`])
    wide: Option<(&'a WideAccel, Boxes)>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Space {
    World,
    Model,
}

/// The watertight ray/triangle test (Woop, Benthin, Wald 2013), evaluated in
/// f64 on the f32 inputs (so every product is exact and each sum rounds once):
/// shear to ray space with the largest direction axis as z, three edge
/// functions of the sheared 2D vertices (hit iff all have the same sign, zero
/// included: a ray through a shared edge or vertex hits at least one of the
/// triangles; both faces hit), then `t = T/det`. Returns `t` if it lies in
/// `[0, t_max]`.
pub fn intersect(o: DVec3, d: DVec3, v: &[[f32; 3]; 3], t_max: f64) -> Option<f64> {
    let ad = d.abs();
    let kz = if ad[0] >= ad[1] && ad[0] >= ad[2] {
        0
    } else if ad[1] >= ad[2] {
        1
    } else {
        2
    };
    let mut kx = (kz + 1) % 3;
    let mut ky = (kx + 1) % 3;
    if d[kz] < 0.0 {
        std::mem::swap(&mut kx, &mut ky);
    }
    if d[kz] == 0.0 {
        return None;
    }
    let sx = d[kx] / d[kz];
    let sy = d[ky] / d[kz];
    let sz = 1.0 / d[kz];
    let [a, b, c] = v.map(|p| Vec3::from(p).as_dvec3() - o);
    let (ax, ay) = (a[kx] - sx * a[kz], a[ky] - sy * a[kz]);
    let (bx, by) = (b[kx] - sx * b[kz], b[ky] - sy * b[kz]);
    let (cx, cy) = (c[kx] - sx * c[kz], c[ky] - sy * c[kz]);
    let u = cx * by - cy * bx;
    let vv = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if (u < 0.0 || vv < 0.0 || w < 0.0) && (u > 0.0 || vv > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + vv + w;
    if det == 0.0 {
        return None;
    }
    let tt = u * (sz * a[kz]) + vv * (sz * b[kz]) + w * (sz * c[kz]);
    let t = tt / det;
    (t >= 0.0 && t <= t_max).then_some(t)
}

/// The segment end of a triangle test: the best hit so far, rounded up to
/// binary32.
fn tri_t_max(r: &TRay) -> u64 {
    if r.hit.t.is_infinite() {
        bits(f32::INFINITY)
    } else {
        bits(f32_up(r.hit.t))
    }
}

/// The `triangle` unit on the model-space ray: `t` of a hit in `[0, best so
/// far]`, or `Err` when the unit flags the test `invalid` (the caller decides
/// it exactly, as a shader would).
fn unit_triangle(
    units: &dyn Units,
    r: &TRay,
    v: &[[f32; 3]; 3],
    tnum: bool,
) -> Result<Option<f64>, Flagged> {
    let x = golden_triangle::TriIn {
        o: r.o,
        kz: r.shear.0,
        s: r.shear.1,
        a: v[0].map(bits),
        b: v[1].map(bits),
        c: v[2].map(bits),
        t_min: bits(0.0),
        t_max: tri_t_max(r),
    };
    let t = if tnum {
        // the unit tests the exact T/det against a bound three ulps above t_max
        // (`full`'s t = RN(T·RN(1/det)) is within 2^-23 (1 + 2^-24) of T/det relative,
        // at most two ulps and a hair); the shader divides once per accepted hit and
        // keeps `full`'s decision, t ≤ t_max
        let wide = golden_triangle::TriIn {
            t_max: golden_model::float::nudge(FloatFormat::BINARY32, x.t_max, 3),
            ..x
        };
        let out = units.triangle_tnum(&wide);
        if out.invalid {
            return Err(Flagged);
        }
        out.hit
            .then(|| {
                golden_triangle::finish_t(
                    FloatFormat::BINARY32,
                    golden_model::float::RoundingMode::NearestEven,
                    out.t_num,
                    out.t_den,
                )
            })
            .filter(|&t| f32::from_bits(t as u32) <= f32::from_bits(x.t_max as u32))
    } else {
        let out = units.triangle(&x);
        if out.invalid {
            return Err(Flagged);
        }
        out.hit.then_some(out.t)
    };
    Ok(t.map(|t| f32::from_bits(t as u32) as f64))
}

/// A triangle test the unit flagged `invalid`: with finite scenes and rays,
/// three zero edge functions (a triangle seen edge-on, or a sliver within
/// rounding of the ray's plane that the ray may cross).
struct Flagged;

/// The exact rational test on the model-space ray: `t` (rounded to f64)
/// of a hit in `[0, best so far]`.
fn exact_triangle(r: &TRay, v: &[[f32; 3]; 3]) -> Option<f64> {
    golden_triangle::exact::intersect(
        FloatFormat::BINARY32,
        r.o,
        r.d,
        v.map(|p| p.map(bits)),
        bits(0.0),
        tri_t_max(r),
    )
    .map(|h| h.t_f64())
}

impl<'a> Tracer<'a> {
    /// A tracer over `accel` built from `scene`.
    pub fn new(
        scene: &'a Scene,
        accel: &'a Accel,
        tester: &'a dyn BoxTester,
        mut opts: TraceOpts,
    ) -> Tracer<'a> {
        if !tester.supports_bundles() {
            opts.bundles.enabled = false;
        }
        Tracer {
            accel,
            meshes: scene.meshes.iter().map(|(_, m)| m).collect(),
            tester,
            opts,
            units: tester.units(),
            wide: None,
        }
    }

    /// The same tracer over the wide BVH `wide` of its [`Accel`]
    /// (`render --wide`): single rays, no planes, each wide node tested by the
    /// `node` unit ([`Boxes::Node`]), the window-and-anchors model
    /// ([`Boxes::Anchored`]) or by the
    /// conservative slab on exact binary32 child boxes ([`Boxes::Exact`]).
    pub fn with_wide(mut self, wide: &'a WideAccel, boxes: Boxes) -> Tracer<'a> {
        self.opts.bundles.enabled = false;
        self.opts.planes = false;
        self.wide = Some((wide, boxes));
        self
    }

    /// Brings ray `r` (id `id`) into instance `x`'s model space: the
    /// transform unit (or plain f32 arithmetic for the f32 baseline), the
    /// slab's reciprocal and, for `--tri golden`, the triangle unit's shear.
    pub(crate) fn enter_model(&self, r: &mut TRay, x: &InstanceXf, id: u64) {
        if self.opts.f32_transform {
            let f = |b: u64| f32::from_bits(b as u32);
            // inv_bits is row-major: its columns-array reading is R⁻ᵀ
            let inv = Mat3::from_cols_array(&x.inv_bits.map(f)).transpose();
            r.o = bits3(inv * (r.o_w - Vec3::from(x.t_bits.map(f))));
            r.d = bits3(inv * r.d_w);
            r.inv_d = slab_reciprocal(FloatFormat::BINARY32, &r.d);
        } else {
            r.enter_instance(self.units, x, id);
        }
        if matches!(self.opts.tri, TriTest::Golden | TriTest::GoldenTnum) {
            r.shear = golden_triangle::shear(FloatFormat::BINARY32, r.d);
        }
    }

    /// The triangles `tris` of mesh `m` (instance `inst`) against the
    /// model-space ray `r`: the nearest hit kept as the minimum of `(t,
    /// instance, triangle)`, an any-hit ray done at its first hit.
    pub(crate) fn leaf(&self, r: &mut TRay, inst: u32, m: &Mesh, tris: &[u32], st: &mut KindStats) {
        let f64_of = |b: [u64; 3]| Vec3::from(b.map(|b| f32::from_bits(b as u32))).as_dvec3();
        let (o, d) = (f64_of(r.o), f64_of(r.d));
        for &t in tris {
            st.tri_tests += 1;
            let v = m.corners(t);
            let mut by_unit = |tnum| {
                unit_triangle(self.units, r, &v, tnum).unwrap_or_else(|Flagged| {
                    st.tri_flagged += 1;
                    exact_triangle(r, &v)
                })
            };
            let found = match self.opts.tri {
                TriTest::F64 => intersect(o, d, &v, r.hit.t),
                TriTest::Golden => by_unit(false),
                TriTest::GoldenTnum => by_unit(true),
                TriTest::Exact => exact_triangle(r, &v),
            };
            if let Some(th) = found {
                if (th, inst, t) < (r.hit.t, r.hit.inst, r.hit.prim) {
                    r.hit = Hit {
                        t: th,
                        inst,
                        prim: t,
                    };
                }
                if r.any {
                    r.done = true;
                    return;
                }
            }
        }
    }

    /// Traces the rays `idxs` of `rays` as one bundle (or one ray; over a
    /// wide BVH, one by one).
    pub fn trace(&self, rays: &mut [TRay], idxs: &[usize], kind: RayKind, st: &mut Stats) {
        let ks = &mut st.kinds[kind as usize];
        ks.rays += idxs.len() as u64;
        if let Some((wide, boxes)) = self.wide {
            for &i in idxs {
                self.trace_wide(wide, boxes, &mut rays[i], i as u64, ks);
            }
        } else if !self.accel.tlas.nodes.is_empty() {
            // lists are recycled across the traversals of one thread
            let mut scratch = SCRATCH.with(|p| std::mem::take(&mut *p.borrow_mut()));
            let list = scratch.list_of(idxs);
            self.visit_tlas(0, list, rays, ks, &mut scratch);
            SCRATCH.with(|p| *p.borrow_mut() = scratch);
        }
        ks.hits += idxs.iter().filter(|&&i| rays[i].hit.is_hit()).count() as u64;
    }

    fn order_children(
        &self,
        l: usize,
        r: usize,
        nodes: &[golden_model::cull::bvh::Node],
        ray: &TRay,
        space: Space,
    ) -> [usize; 2] {
        let (o, d) = match space {
            Space::World => (ray.o_w, ray.d_w),
            Space::Model => (
                Vec3::from(ray.o.map(|b| f32::from_bits(b as u32))),
                Vec3::from(ray.d.map(|b| f32::from_bits(b as u32))),
            ),
        };
        let key = |n: usize| {
            let b = &nodes[n];
            ((Vec3::from(b.min) + Vec3::from(b.max)) * 0.5 - o).dot(d)
        };
        if key(r) < key(l) {
            [r, l]
        } else {
            [l, r]
        }
    }

    /// Visits a TLAS node with the ray list `idxs` (from the thread's
    /// scratch, returned to it).
    fn visit_tlas(
        &self,
        node: usize,
        mut idxs: Vec<usize>,
        rays: &mut [TRay],
        st: &mut KindStats,
        scratch: &mut Scratch,
    ) {
        self.visit_tlas_in(node, &mut idxs, rays, st, scratch);
        scratch.rays.push(idxs);
    }

    /// [`Tracer::visit_tlas`] on a borrowed ray list (filtered in place).
    fn visit_tlas_in(
        &self,
        node: usize,
        surv: &mut Vec<usize>,
        rays: &mut [TRay],
        st: &mut KindStats,
        scratch: &mut Scratch,
    ) {
        surv.retain(|&i| !rays[i].done);
        if surv.is_empty() {
            return;
        }
        let n = self.accel.tlas.nodes[node];
        self.test_box(&n.min, &n.max, surv, rays, Space::World, st);
        if surv.is_empty() {
            return;
        }
        match n.kind {
            NodeKind::Leaf { .. } => {
                for &inst in self.accel.tlas.leaf_tris(node) {
                    self.enter_instance(inst as usize, surv, rays, st, scratch);
                }
            }
            NodeKind::Inner { left, right } => {
                let ord = self.order_children(
                    left as usize,
                    right as usize,
                    &self.accel.tlas.nodes,
                    &rays[surv[0]],
                    Space::World,
                );
                for c in ord {
                    let v = scratch.list_of(surv);
                    self.visit_tlas(c, v, rays, st, scratch);
                }
            }
        }
    }

    fn enter_instance(
        &self,
        inst: usize,
        idxs: &[usize],
        rays: &mut [TRay],
        st: &mut KindStats,
        scratch: &mut Scratch,
    ) {
        let x = &self.accel.instances[inst];
        let mut live = scratch.list_of(idxs);
        live.retain(|&i| !rays[i].done);
        for &i in &live {
            st.transforms += 1;
            self.enter_model(&mut rays[i], x, i as u64);
        }
        let blas = &self.accel.blas[x.mesh];
        let mut root_terms =
            self.lazy_terms(&blas.planes.root_normals, &blas.bvh.nodes[0].min, scratch);
        self.visit_blas(
            inst as u32,
            x.mesh,
            0,
            live,
            &mut root_terms,
            rays,
            st,
            scratch,
        );
        st.cull_ray_terms += root_terms.finish(scratch);
    }

    /// The lazily computed ray terms (unit `cull_ray`) of a node's shared
    /// normals for its rays (model space); off when the planes are off or
    /// there are no normals.
    fn lazy_terms<'n>(
        &self,
        normals: &'n [[u64; 3]],
        r_min: &[f32; 3],
        scratch: &mut Scratch,
    ) -> LazyTerms<'n> {
        let mut computed = scratch.terms.pop().unwrap_or_default();
        computed.clear();
        LazyTerms {
            normals,
            r_min: r_min.map(bits),
            on: self.opts.planes && !normals.is_empty(),
            computed,
        }
    }

    /// `parent_terms`: the ray terms of the normals this node's distances
    /// refer to (its parent's, or the root's own set), by ray index.
    #[allow(clippy::too_many_arguments)]
    fn visit_blas(
        &self,
        inst: u32,
        mesh: usize,
        node: usize,
        idxs: Vec<usize>,
        parent_terms: &mut LazyTerms,
        rays: &mut [TRay],
        st: &mut KindStats,
        scratch: &mut Scratch,
    ) {
        let mut idxs = idxs;
        self.visit_blas_in(inst, mesh, node, &mut idxs, parent_terms, rays, st, scratch);
        scratch.rays.push(idxs);
    }

    /// [`Tracer::visit_blas`] on a borrowed ray list (filtered in place);
    /// the children's lists come from `scratch`.
    #[allow(clippy::too_many_arguments)]
    fn visit_blas_in(
        &self,
        inst: u32,
        mesh: usize,
        node: usize,
        idxs: &mut Vec<usize>,
        parent_terms: &mut LazyTerms,
        rays: &mut [TRay],
        st: &mut KindStats,
        scratch: &mut Scratch,
    ) {
        idxs.retain(|&i| !rays[i].done);
        if idxs.is_empty() {
            return;
        }
        let blas = &self.accel.blas[mesh];
        let n = blas.bvh.nodes[node];
        let surv = idxs;
        self.test_box(&n.min, &n.max, surv, rays, Space::Model, st);
        if surv.is_empty() {
            return;
        }
        let leaf = matches!(n.kind, NodeKind::Leaf { .. });
        if self.opts.planes && parent_terms.on && (leaf || surv.len() == 1) {
            let w = &blas.planes.w[node];
            surv.retain(|&i| {
                let r = &rays[i];
                st.cull_tests += 1;
                // the conservative slab beside the cull unit gives the box interval
                let keep = box_interval(
                    FloatFormat::BINARY32,
                    &n.min.map(bits),
                    &n.max.map(bits),
                    &r.o,
                    &r.inv_d,
                    0,
                    r.box_t_max(),
                )
                .is_some_and(|(t_lo, t_hi)| {
                    let terms = parent_terms.get(self.units, i, r);
                    self.units.cull(&ChildTestIn {
                        t_lo,
                        t_hi,
                        w,
                        terms: &terms[..PLANES_K],
                    })
                });
                if !keep {
                    st.culled_nodes += 1;
                    if let NodeKind::Leaf { count, .. } = n.kind {
                        st.culled_leaves += 1;
                        st.culled_leaf_tris += count as u64;
                    }
                }
                keep
            });
            if surv.is_empty() {
                return;
            }
        }
        match n.kind {
            NodeKind::Leaf { .. } => {
                let m = self.meshes[mesh];
                let tris = blas.bvh.leaf_tris(node);
                for &i in surv.iter() {
                    st.leaf_visits += 1;
                    self.leaf(&mut rays[i], inst, m, tris, st);
                }
            }
            NodeKind::Inner { left, right } => {
                let ord = self.order_children(
                    left as usize,
                    right as usize,
                    &blas.bvh.nodes,
                    &rays[surv[0]],
                    Space::Model,
                );
                let mut terms = self.lazy_terms(&blas.planes.normals[node], &n.min, scratch);
                for c in ord {
                    let v = scratch.list_of(surv);
                    self.visit_blas(inst, mesh, c, v, &mut terms, rays, st, scratch);
                }
                st.cull_ray_terms += terms.finish(scratch);
            }
        }
    }

    /// Box test of a set of rays: one bundle test when bundles apply, else one
    /// test per ray. Keeps in `idxs` the rays that may hit (in order).
    fn test_box(
        &self,
        lo: &[f32; 3],
        hi: &[f32; 3],
        idxs: &mut Vec<usize>,
        rays: &[TRay],
        space: Space,
        st: &mut KindStats,
    ) {
        let p_min = lo.map(bits);
        let p_max = hi.map(bits);
        let od = |r: &TRay| match space {
            Space::World => (bits3(r.o_w), bits3(r.d_w)),
            Space::Model => (r.o, r.d),
        };
        let b = &self.opts.bundles;
        let n = idxs.len();
        if b.enabled && n >= 2 {
            if n < b.min_size {
                st.split_by_metric += 1;
            } else if let Some(bb) = bundle_bounds(idxs, rays, &od, b.max_spread) {
                let x = BundleBox {
                    input: BundleIn {
                        p_min,
                        p_max,
                        ..bb.input
                    },
                    shared: bb.shared,
                    world: space == Space::World,
                };
                st.bundle_tests += 1;
                st.bundle_rays += n as u64;
                match self.tester.bundle(&x) {
                    Verdict::AllHit => {
                        st.all_hit += 1;
                        st.saved_box_tests += n as i64 - 1;
                        return;
                    }
                    Verdict::AllMiss => {
                        st.all_miss += 1;
                        st.saved_box_tests += n as i64 - 1;
                        idxs.clear();
                        return;
                    }
                    Verdict::Mixed => {
                        st.mixed += 1;
                        st.saved_box_tests -= 1;
                    }
                }
            } else {
                st.split_by_metric += 1;
            }
        }
        idxs.retain(|&i| {
            let r = &rays[i];
            let (o, d) = od(r);
            st.ray_box_tests += 1;
            self.tester.ray(&RayBox {
                p_min,
                p_max,
                o,
                d,
                t_max: r.box_t_max(),
                world: space == Space::World,
            })
        })
    }
}

/// A ray's origin and direction bits in the space a tree is traced in.
type RaySpace<'a> = dyn Fn(&TRay) -> ([u64; 3], [u64; 3]) + 'a;

/// The bundle's bounds (box fields left zero), or `None` when the splitting
/// metric says split: a direction component changes sign across the bundle,
/// or the normalised directions spread more than `max_spread` on some axis.
fn bundle_bounds(
    idxs: &[usize],
    rays: &[TRay],
    od: &RaySpace<'_>,
    max_spread: f32,
) -> Option<BundleBox> {
    let f = |b: u64| f32::from_bits(b as u32);
    let (mut o_lo, mut o_hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let (mut d_lo, mut d_hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let (mut n_lo, mut n_hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let mut t_max = 0u64;
    let mut shared = true;
    let first = od(&rays[idxs[0]]).0;
    for &i in idxs {
        let (o, d) = od(&rays[i]);
        shared &= o == first;
        let (o, d) = (Vec3::from(o.map(f)), Vec3::from(d.map(f)));
        let n = unit_by_division!(d);
        // the running bound is min/max's second operand: glam keeps it on
        // ties (±0) and when the new value is NaN
        (o_lo, o_hi) = (o.min(o_lo), o.max(o_hi));
        (d_lo, d_hi) = (d.min(d_lo), d.max(d_hi));
        (n_lo, n_hi) = (n.min(n_lo), n.max(n_hi));
        let tm = rays[i].box_t_max();
        if f(tm) > f(t_max) {
            t_max = tm;
        }
    }
    let sign_change = d_lo.cmplt(Vec3::ZERO) & d_hi.cmpgt(Vec3::ZERO);
    if sign_change.any() || (n_hi - n_lo).cmpgt(Vec3::splat(max_spread)).any() {
        return None;
    }
    Some(BundleBox {
        input: BundleIn {
            p_min: [0; 3],
            p_max: [0; 3],
            o_lo: bits3(o_lo),
            o_hi: bits3(o_hi),
            d_lo: bits3(d_lo),
            d_hi: bits3(d_hi),
            t_min: 0,
            t_max,
        },
        shared,
        world: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::GoldenUnits;

    /// A face of a tetrahedron within 2 ulps of the plane `x = y` that holds
    /// the ray from the origin along `+z` (golden-model/tests/triangle.rs):
    /// the unit flags the test in both output modes, and the exact test,
    /// which the leaf loop then asks, finds the crossing at `t = 0.2571...`.
    #[test]
    fn a_flagged_triangle_test_is_decided_exactly() {
        let p = |v: [u32; 3]| v.map(f32::from_bits);
        let face = [
            p([0x3f80_0029, 0x3f80_0027, 0x3f80_0000]),
            p([0xbf80_002f, 0xbf80_002d, 0xbf80_0000]),
            p([0xbf80_000c, 0xbf80_000a, 0x4000_0000]),
        ];
        let mut r = TRay::new(Vec3::ZERO, Vec3::Z, f64::INFINITY, false);
        r.shear = golden_triangle::shear(FloatFormat::BINARY32, r.d);
        for tnum in [false, true] {
            assert!(
                unit_triangle(GoldenUnits::get(), &r, &face, tnum).is_err(),
                "tnum {tnum}: the unit flags the test"
            );
        }
        let t = exact_triangle(&r, &face).expect("the exact ray crosses the face");
        assert!((t - 0.257_142_857).abs() < 1e-6, "t = {t}");
    }
}
