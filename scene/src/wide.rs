//! Wide BVHs with compressed nodes (issue 36, step 1; `docs/wide.md`): each
//! binary SAH tree of the [`Accel`] (every BLAS and the TLAS) collapsed into
//! nodes of N = 2, 4 or 8 child slots by an SAH-driven collapse, every node
//! encoded by `golden_model::wide` (a frame, q-bit child boxes rounded
//! outward), and a traversal that counts the node bytes a ray fetches.
//!
//! **Collapse** (Ylitie, Karras, Laine 2017, without leaf merging): the
//! binary leaves are kept as they are (their triangle tests are the same in
//! every collapse), so the SAH cost of a wide tree is `Σ area(wide node)`
//! (one node fetch and N child tests per visit, a visit as likely as its
//! area). A dynamic programme over the binary tree finds the wide tree of
//! least cost: `F(n, j)`, the least cost of covering the subtree of `n`
//! with at most `j` slots of one wide node, is 0 for a leaf and otherwise
//! `min(area(n) + F_N(n), min_k F(l, k) + F(r, j − k))`, where `F_N(n) =
//! min_k F(l, k) + F(r, N − k)` fills the wide node opened at `n`. Which
//! grandchildren are pulled up follows from the areas, not from a fixed
//! two-level merge; for N = 2 the binary tree comes back unchanged.
//!
//! **Layout**: wide nodes breadth first (root 0); a node's inner children
//! are consecutive from its `child_base`, its leaf slots' primitives
//! consecutive in [`WideBvh::prims`] from its `prim_base`.
//!
//! **Traversal** ([`WideTracer`]): per node, every valid slot's box is tested
//! by the conservative slab (`golden_model::slab::eval_conservative`,
//! binary32) against the decoded box rounded outward to binary32
//! ([`Boxes::Compressed`]) or against the exact binary32 child box
//! ([`Boxes::Exact`], the baseline); hit children nearer first. A
//! conservative test never misses a child the ray truly reaches, and the
//! decoded box contains the exact one, so both find the same nearest hit as
//! the binary BVH (docs/scene.md §3's argument; tested).

use crate::bvh::Accel;
use crate::render::Cam;
use crate::scene::Scene;
use crate::trace::{intersect, Hit, TRay};
use crate::units::GoldenUnits;
use golden_model::cull::bvh::{Bvh, Mesh, NodeKind};
use golden_model::cull::tester::slab_reciprocal;
use golden_model::float::FloatFormat;
use golden_model::slab::{eval_conservative, SlabIn};
use golden_model::wide::{encode, ChildBox, ChildKind, ChildRef, Node, WideFormat, MAX_CHILDREN};
use rayon::prelude::*;

/// An axis-aligned binary32 box `(min, max)`.
pub type Box32 = ([f32; 3], [f32; 3]);

/// One wide tree: compressed nodes and, per slot, the boxes the traversal tests.
#[derive(Debug, Clone)]
pub struct WideBvh {
    /// the node shape
    pub format: WideFormat,
    /// compressed nodes, breadth first, root 0 (empty for an empty tree)
    pub nodes: Vec<Node>,
    /// per node and slot: the exact child box (the binary node's binary32
    /// box; zero in empty slots)
    pub exact: Vec<[Box32; MAX_CHILDREN]>,
    /// per node and slot: the decoded box rounded outward to binary32
    pub decoded: Vec<[Box32; MAX_CHILDREN]>,
    /// primitive (triangle or instance) indices, grouped by leaf slot
    pub prims: Vec<u32>,
}

/// The least-cost collapse of a binary tree into nodes of at most `n` slots.
struct Collapse {
    /// per binary node and slot budget `j` (index `j − 1`): 0 keeps the
    /// node as one slot, `k > 0` gives `k` slots to its left child and
    /// `j − k` to its right
    choice: Vec<[u8; MAX_CHILDREN]>,
    /// per inner binary node: the slots its left child gets when a wide
    /// node is opened there (`n − k` go right)
    open: Vec<u8>,
}

impl Collapse {
    fn new(bvh: &Bvh, n: usize) -> Collapse {
        let len = bvh.nodes.len();
        let mut cost = vec![[0f64; MAX_CHILDREN]; len];
        let mut choice = vec![[0u8; MAX_CHILDREN]; len];
        let mut open = vec![0u8; len];
        // children have larger indices than their parent: a reverse walk sees them first
        for id in (0..len).rev() {
            let node = &bvh.nodes[id];
            let NodeKind::Inner { left, right } = node.kind else {
                continue; // a leaf costs nothing in any collapse
            };
            let (l, r) = (left as usize, right as usize);
            let (cl, cr) = (cost[l], cost[r]);
            let split = |j: usize| {
                (1..j)
                    .map(|k| (cl[k - 1] + cr[j - k - 1], k as u8))
                    .fold((f64::INFINITY, 0u8), |a, b| if b.0 < a.0 { b } else { a })
            };
            let e = [0, 1, 2].map(|i| (node.max[i] as f64 - node.min[i] as f64).max(0.0));
            let area = 2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
            let (fill, k_open) = split(n);
            open[id] = k_open;
            let own = area + fill;
            cost[id][0] = own;
            for j in 2..=n {
                let (c, k) = split(j);
                // keeping the node whole wins ties: fewer slots for the same cost
                (cost[id][j - 1], choice[id][j - 1]) = if c < own { (c, k) } else { (own, 0) };
            }
        }
        Collapse { choice, open }
    }

    /// The binary nodes in the slots of the wide node opened at `id`, in
    /// left-to-right order (a leaf `id`: itself, the root of a one-leaf tree).
    fn slots(&self, bvh: &Bvh, id: usize, n: usize) -> Vec<usize> {
        let mut out = Vec::with_capacity(n);
        match bvh.nodes[id].kind {
            NodeKind::Inner { left, right } => {
                let k = self.open[id] as usize;
                self.expand(bvh, left as usize, k, &mut out);
                self.expand(bvh, right as usize, n - k, &mut out);
            }
            NodeKind::Leaf { .. } => out.push(id),
        }
        out
    }

    /// The slot roots covering the subtree of `id` with at most `j` slots.
    fn expand(&self, bvh: &Bvh, id: usize, j: usize, out: &mut Vec<usize>) {
        match (bvh.nodes[id].kind, self.choice[id][j - 1]) {
            (NodeKind::Inner { left, right }, k) if k > 0 => {
                self.expand(bvh, left as usize, k as usize, out);
                self.expand(bvh, right as usize, j - k as usize, out);
            }
            _ => out.push(id),
        }
    }
}

impl WideBvh {
    /// Collapses `bvh` into wide nodes of `format` and encodes them; an
    /// unencodable node is an error naming it.
    pub fn build(bvh: &Bvh, format: WideFormat) -> Result<WideBvh, String> {
        let n = format.children();
        let mut w = WideBvh {
            format,
            nodes: Vec::new(),
            exact: Vec::new(),
            decoded: Vec::new(),
            prims: Vec::new(),
        };
        if bvh.nodes.is_empty() {
            return Ok(w);
        }
        let plan = Collapse::new(bvh, n);
        // breadth first: the binary node each wide node was opened at
        let mut queue = vec![0usize];
        let mut next = 0;
        while next < queue.len() {
            let at = queue[next];
            next += 1;
            let roots = plan.slots(bvh, at, n);
            let child_base = queue.len() as u32;
            let prim_base = w.prims.len() as u32;
            let mut slots = Vec::with_capacity(roots.len());
            let mut exact = [([0f32; 3], [0f32; 3]); MAX_CHILDREN];
            for (i, &c) in roots.iter().enumerate() {
                let b = &bvh.nodes[c];
                exact[i] = (b.min, b.max);
                let kind = match b.kind {
                    NodeKind::Inner { .. } => {
                        queue.push(c);
                        ChildKind::Inner
                    }
                    NodeKind::Leaf { count, .. } => {
                        w.prims.extend_from_slice(bvh.leaf_tris(c));
                        ChildKind::Leaf(count)
                    }
                };
                let child = ChildBox {
                    min: b.min.map(f64::from),
                    max: b.max.map(f64::from),
                };
                slots.push(Some((child, kind)));
            }
            let node = encode(format, &slots, child_base, prim_base)
                .map_err(|e| format!("wide node {} (binary node {at}): {e}", w.nodes.len()))?;
            let mut decoded = [([0f32; 3], [0f32; 3]); MAX_CHILDREN];
            for (i, d) in decoded.iter_mut().enumerate().take(roots.len()) {
                let (lo, hi) = node
                    .decoded_outward(format, i, FloatFormat::BINARY32)
                    .expect("a valid slot");
                *d = (
                    lo.map(|b| f32::from_bits(b as u32)),
                    hi.map(|b| f32::from_bits(b as u32)),
                );
            }
            w.nodes.push(node);
            w.exact.push(exact);
            w.decoded.push(decoded);
        }
        Ok(w)
    }

    /// Bytes of all node records.
    pub fn node_bytes(&self) -> u64 {
        self.nodes.len() as u64 * self.format.record_bytes() as u64
    }
}

/// Every tree of an [`Accel`], collapsed and compressed.
#[derive(Debug, Clone)]
pub struct WideAccel {
    /// the node shape
    pub format: WideFormat,
    /// over the instances (world space)
    pub tlas: WideBvh,
    /// one per mesh (model space)
    pub blas: Vec<WideBvh>,
}

impl WideAccel {
    /// Collapses and encodes the TLAS and every BLAS (meshes in parallel).
    pub fn build(accel: &Accel, format: WideFormat) -> Result<WideAccel, String> {
        let blas = accel
            .blas
            .par_iter()
            .enumerate()
            .map(|(m, b)| WideBvh::build(&b.bvh, format).map_err(|e| format!("mesh {m}: {e}")))
            .collect::<Result<Vec<_>, _>>()?;
        let tlas = WideBvh::build(&accel.tlas, format).map_err(|e| format!("TLAS: {e}"))?;
        Ok(WideAccel { format, tlas, blas })
    }

    /// Nodes of every tree.
    pub fn nodes(&self) -> u64 {
        self.tlas.nodes.len() as u64 + self.blas.iter().map(|b| b.nodes.len() as u64).sum::<u64>()
    }
}

/// Which boxes a traversal tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Boxes {
    /// the compressed node's decoded boxes, rounded outward to binary32
    Compressed,
    /// the exact binary32 child boxes (an uncompressed node of the same tree)
    Exact,
}

/// Counters of a wide traversal.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct WideStats {
    /// rays traced
    pub rays: u64,
    /// wide nodes fetched (TLAS and BLAS)
    pub node_visits: u64,
    /// node bytes fetched
    pub bytes: u64,
    /// child box tests (valid slots of the visited nodes)
    pub child_tests: u64,
    /// ray/triangle tests
    pub tri_tests: u64,
    /// instance transforms
    pub transforms: u64,
}

impl WideStats {
    fn add(&mut self, o: &WideStats) {
        self.rays += o.rays;
        self.node_visits += o.node_visits;
        self.bytes += o.bytes;
        self.child_tests += o.child_tests;
        self.tri_tests += o.tri_tests;
        self.transforms += o.transforms;
    }
    /// Per ray.
    pub fn per_ray(&self, v: u64) -> f64 {
        v as f64 / self.rays.max(1) as f64
    }
}

/// Traces rays through a [`WideAccel`].
pub struct WideTracer<'a> {
    /// the binary structure (instances, for the transforms)
    pub accel: &'a Accel,
    /// the wide trees
    pub wide: &'a WideAccel,
    /// the meshes (same indices as the BLAS)
    pub meshes: Vec<&'a Mesh>,
    /// the boxes tested
    pub boxes: Boxes,
}

impl<'a> WideTracer<'a> {
    /// A tracer over `wide`, built from `accel` of `scene`.
    pub fn new(scene: &'a Scene, accel: &'a Accel, wide: &'a WideAccel, boxes: Boxes) -> Self {
        WideTracer {
            accel,
            wide,
            meshes: scene.meshes.iter().map(|(_, m)| m).collect(),
            boxes,
        }
    }

    fn node_bytes(&self) -> u64 {
        match self.boxes {
            Boxes::Compressed => self.wide.format.record_bytes() as u64,
            Boxes::Exact => self.wide.format.baseline_bytes() as u64,
        }
    }

    /// Traces one closest-hit or any-hit ray (its hit is updated).
    pub fn trace(&self, r: &mut TRay, st: &mut WideStats) {
        st.rays += 1;
        let tlas = &self.wide.tlas;
        if tlas.nodes.is_empty() {
            return;
        }
        let o = r.o_w.map(|v| v.to_bits() as u64);
        let inv_d = slab_reciprocal(FloatFormat::BINARY32, &r.d_w.map(|v| v.to_bits() as u64));
        self.walk(tlas, o, inv_d, r, st, &mut |r, insts, st| {
            for &i in insts {
                self.enter_instance(i, r, st);
                if r.done {
                    break;
                }
            }
        });
    }

    /// Depth-first walk of one wide tree with the ray `(o, inv_d)` of its
    /// space; `leaf` handles the primitives of a hit leaf slot.
    fn walk(
        &self,
        bvh: &WideBvh,
        o: [u64; 3],
        inv_d: [u64; 3],
        r: &mut TRay,
        st: &mut WideStats,
        leaf: &mut dyn FnMut(&mut TRay, &[u32], &mut WideStats),
    ) {
        let n = bvh.format.children();
        let bytes = self.node_bytes();
        let mut stack = vec![0u32];
        let mut hits: Vec<(u32, usize)> = Vec::with_capacity(n);
        while let Some(id) = stack.pop() {
            if r.done {
                return;
            }
            let id = id as usize;
            let node = &bvh.nodes[id];
            st.node_visits += 1;
            st.bytes += bytes;
            let t_max = r.box_t_max();
            let boxes = match self.boxes {
                Boxes::Compressed => &bvh.decoded[id],
                Boxes::Exact => &bvh.exact[id],
            };
            hits.clear();
            for (i, b) in boxes.iter().enumerate().take(n) {
                if node.valid >> i & 1 == 0 {
                    continue;
                }
                st.child_tests += 1;
                let out = eval_conservative(
                    FloatFormat::BINARY32,
                    &SlabIn {
                        p_min: b.0.map(|v| v.to_bits() as u64),
                        p_max: b.1.map(|v| v.to_bits() as u64),
                        o,
                        inv_d,
                        t_min: 0,
                        t_max,
                    },
                );
                if out.hit {
                    // nearer first: entry distances (non-negative here) order as their bits
                    hits.push((out.t_enter as u32 & 0x7fff_ffff, i));
                }
            }
            hits.sort_unstable();
            // leaves now, nearest first; inner children pushed far first
            for &(_, i) in &hits {
                if let ChildRef::Leaf { first, count } = node.child(i) {
                    leaf(r, &bvh.prims[first as usize..(first + count) as usize], st);
                    if r.done {
                        return;
                    }
                }
            }
            for &(_, i) in hits.iter().rev() {
                if let ChildRef::Inner(c) = node.child(i) {
                    stack.push(c);
                }
            }
        }
    }

    /// The ray into instance `inst`'s model space (the transform unit's
    /// golden model, as the binary traversal does) and through its BLAS.
    fn enter_instance(&self, inst: u32, r: &mut TRay, st: &mut WideStats) {
        let x = &self.accel.instances[inst as usize];
        st.transforms += 1;
        r.enter_instance(GoldenUnits::get(), x, 0);
        let inv_d = r.inv_d;
        let mesh = self.meshes[x.mesh];
        let blas = &self.wide.blas[x.mesh];
        if blas.nodes.is_empty() {
            return;
        }
        let o64 = r.o.map(|b| f32::from_bits(b as u32) as f64);
        let d64 = r.d.map(|b| f32::from_bits(b as u32) as f64);
        self.walk(blas, r.o, inv_d, r, st, &mut |r, tris, st| {
            for &t in tris {
                st.tri_tests += 1;
                if let Some(th) = intersect(&o64, &d64, &mesh.corners(t), r.hit.t) {
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
        });
    }

    /// The camera's primary rays of a `w`×`h` image (rows in parallel):
    /// per pixel, row-major, the nearest hit, and the counters.
    pub fn primary(&self, scene: &Scene, w: u32, h: u32) -> (Vec<Hit>, WideStats) {
        let cam = Cam::new(scene, w, h);
        let rows: Vec<(Vec<Hit>, WideStats)> = (0..h)
            .into_par_iter()
            .map(|y| {
                let mut st = WideStats::default();
                let hits = (0..w)
                    .map(|x| {
                        let mut r = TRay::new(cam.o, cam.dir(x, y), f64::INFINITY, false);
                        self.trace(&mut r, &mut st);
                        r.hit
                    })
                    .collect();
                (hits, st)
            })
            .collect();
        let mut st = WideStats::default();
        let mut hits = Vec::with_capacity((w * h) as usize);
        for (row, s) in rows {
            hits.extend(row);
            st.add(&s);
        }
        (hits, st)
    }
}

/// One row of [`report`]: a scene's wide BVH of one shape and its camera rays.
#[derive(Debug, Clone)]
pub struct ReportRow {
    /// the node shape
    pub format: WideFormat,
    /// wide nodes (TLAS and every BLAS)
    pub nodes: u64,
    /// the traversal with the decoded child boxes
    pub compressed: WideStats,
    /// the same tree with exact binary32 child boxes
    pub exact: WideStats,
    /// both traversals found the same nearest hit on every pixel
    pub same_hits: bool,
}

impl ReportRow {
    /// Child tests per ray with the decoded boxes over those with exact binary32 boxes.
    pub fn child_test_ratio(&self) -> f64 {
        self.compressed.per_ray(self.compressed.child_tests)
            / self.exact.per_ray(self.exact.child_tests)
    }
}

/// Builds the wide BVH of every shape and traces the `w`×`h` camera rays
/// through it twice (decoded boxes, exact binary32 boxes).
pub fn report(
    scene: &Scene,
    accel: &Accel,
    shapes: &[WideFormat],
    w: u32,
    h: u32,
) -> Result<Vec<ReportRow>, String> {
    shapes
        .iter()
        .map(|&format| {
            let wide = WideAccel::build(accel, format)?;
            let (hq, sq) =
                WideTracer::new(scene, accel, &wide, Boxes::Compressed).primary(scene, w, h);
            let (he, se) = WideTracer::new(scene, accel, &wide, Boxes::Exact).primary(scene, w, h);
            let key = |h: &Hit| (h.inst, h.prim, h.t.to_bits());
            Ok(ReportRow {
                format,
                nodes: wide.nodes(),
                compressed: sq,
                exact: se,
                same_hits: hq.iter().map(key).eq(he.iter().map(key)),
            })
        })
        .collect()
}

/// The table of [`report`] rows of several scenes (markdown), then one line
/// per row `child tests per ray q=<q> / binary32 (N=<n>): <scene> <ratio>`.
pub fn report_table(rows: &[(String, ReportRow)]) -> String {
    let mut s = String::from(
        "| scene | N | q | nodes | bytes/node | node bytes | node visits/ray | bytes/ray | child tests/ray | binary32 boxes: bytes/node | bytes/ray | child tests/ray | child tests q / binary32 | same hits |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (name, r) in rows {
        let (c, e) = (&r.compressed, &r.exact);
        let f = r.format;
        s += &format!(
            "| {name} | {} | {} | {} | {} | {} | {:.2} | {:.0} | {:.2} | {} | {:.0} | {:.2} | {:.4} | {} |\n",
            f.children(),
            f.box_bits(),
            r.nodes,
            f.record_bytes(),
            r.nodes * f.record_bytes() as u64,
            c.per_ray(c.node_visits),
            c.per_ray(c.bytes),
            c.per_ray(c.child_tests),
            f.baseline_bytes(),
            e.per_ray(e.bytes),
            e.per_ray(e.child_tests),
            r.child_test_ratio(),
            if r.same_hits { "yes" } else { "NO" }
        );
    }
    s.push('\n');
    for (name, r) in rows {
        s += &format!(
            "child tests per ray q={} / binary32 (N={}): {name} {:.4}\n",
            r.format.box_bits(),
            r.format.children(),
            r.child_test_ratio()
        );
    }
    s
}
