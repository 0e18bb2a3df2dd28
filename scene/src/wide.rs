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
//! **Traversal** (`trace::Tracer::with_wide`, single rays): per node, the
//! `node` unit's transaction (`golden_model::node_reorigin`, through
//! [`crate::units::Units::node`]: every valid slot tested conservatively
//! against its decoded box from the parent's entry on, the slots returned
//! sorted, hits first and nearer first; [`Boxes::Node`]), the earlier
//! window-and-anchors model (`golden_model::node`, [`Boxes::Anchored`]), or
//! as the baseline the conservative slab
//! (`golden_model::slab::eval_conservative`, binary32) on every exact
//! binary32 child box, hits sorted by entry ([`Boxes::Exact`]). A
//! conservative test never misses a child the ray truly reaches, and the
//! decoded box contains the exact one, so both find the same nearest hit as
//! the binary BVH (docs/scene.md §3's argument; tested).

use crate::bvh::Accel;
use crate::oracle::Oracle;
use crate::render::Cam;
use crate::scene::Scene;
use crate::stats::{KindStats, RayKind, Stats};
use crate::tester::Exact;
use crate::trace::{bits3, Hit, TRay, TraceOpts, Tracer};
use crate::units::NodeTestIn;
use golden_model::cull::bvh::Mesh;
use golden_model::cull::bvh::{Bvh, NodeKind};
use golden_model::cull::tester::slab_reciprocal;
use golden_model::float::FloatFormat;
use golden_model::node::{self, Bound, Dyadic, NodeIn, NodeOut, NodeParams, Ray as NodeRay};
use golden_model::node_reorigin::{self, ExtraAxis, ReoriginParams};
use golden_model::slab::{eval_conservative, SlabIn};
use golden_model::wide::{encode, ChildBox, ChildKind, ChildRef, Node, WideFormat, MAX_CHILDREN};
use rayon::prelude::*;
use std::rc::Rc;

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
            let area = crate::bvh::area(node.min.into(), node.max.into());
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
            w.nodes.push(node);
            w.exact.push(exact);
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
    /// the cull-plane study (docs/node.md §11): per mesh, per BLAS node, the
    /// extents of its slots' triangles along [`DOP_DIRS`]; empty when not built
    pub dop: Vec<Vec<DopNode>>,
    /// the culling oracle's maps (hit primitive → depth of its leaf slot's node)
    pub oracle: Oracle,
}

/// The shape of the TLAS nodes: `format` with `tlas_box_bits` bits per integer.
pub fn tlas_format(format: WideFormat, tlas_box_bits: u32) -> Result<WideFormat, String> {
    WideFormat::new(format.fmt(), format.children(), tlas_box_bits)
        .map_err(|e| format!("TLAS box bits {tlas_box_bits}: {e}"))
}

/// The default q of TLAS nodes. Instance boxes in world space are often thin (walls,
/// panels, fins: 0.004 thick in a node 1 wide), and a child thinner than one q-bit step
/// decodes a whole step thick: every shadow or ambient-occlusion ray leaving such a surface
/// enters its own instance again (docs/node.md §9). The TLAS has few nodes, so 16 bits there
/// cost little memory; a node unit of q = 16 also tests q = 8 nodes exactly (integers shifted
/// left by 8 with the scale exponent lowered by 8 decode to the same planes).
pub const TLAS_BOX_BITS: u32 = 16;

impl WideAccel {
    /// Collapses and encodes every BLAS (meshes in parallel) in `format` and the TLAS in
    /// `format` with `tlas_box_bits` bits per integer ([`TLAS_BOX_BITS`] by default).
    pub fn build(
        accel: &Accel,
        format: WideFormat,
        tlas_box_bits: u32,
    ) -> Result<WideAccel, String> {
        let tlas_format = tlas_format(format, tlas_box_bits)?;
        let blas = accel
            .blas
            .par_iter()
            .enumerate()
            .map(|(m, b)| WideBvh::build(&b.bvh, format).map_err(|e| format!("mesh {m}: {e}")))
            .collect::<Result<Vec<_>, _>>()?;
        let tlas = WideBvh::build(&accel.tlas, tlas_format).map_err(|e| format!("TLAS: {e}"))?;
        Ok(WideAccel {
            format,
            oracle: Oracle::new(accel, &tlas, &blas),
            tlas,
            blas,
            dop: Vec::new(),
        })
    }

    /// Adds the k-DOP extents of every BLAS slot along the directions `select`
    /// gives each node (the study of docs/node.md §11).
    pub fn with_dop(mut self, meshes: &[&Mesh], select: DopSelect) -> WideAccel {
        self.dop = self
            .blas
            .iter()
            .zip(meshes)
            .map(|(b, m)| dop_tree(b, m, select))
            .collect();
        self
    }

    /// Nodes of every tree.
    pub fn nodes(&self) -> u64 {
        self.tlas.nodes.len() as u64 + self.blas.iter().map(|b| b.nodes.len() as u64).sum::<u64>()
    }

    /// Bytes of every tree's node records.
    pub fn node_bytes(&self) -> u64 {
        self.tlas.node_bytes() + self.blas.iter().map(WideBvh::node_bytes).sum::<u64>()
    }
}

/// Which boxes a traversal tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Boxes {
    /// the compressed node, tested by the window-and-anchors model
    /// (`golden_model::node`, docs/node.md §1-9; no RTL)
    Anchored,
    /// the exact binary32 child boxes (an uncompressed node of the same tree)
    Exact,
    /// the compressed node, tested by the `node` unit
    /// (`golden_model::node_reorigin`, docs/node.md §10, §12): each node gets
    /// the parent's entry for it as its start, the root the entry of a
    /// conservative slab on its box
    Node,
    /// the `node` unit's test with the ray's position carried down from the parent
    /// (`node_reorigin::eval_carried`, the carried-position study of docs/node.md §12; the
    /// model only): the root's position from the ray, each other node's from its parent's
    /// bounds by exact arithmetic, every one rounded outward to `2^−(g + F)` steps, `F` the
    /// field
    Carried(u32),
}

/// The ray's position at a node's start as the carried-position study hands it to the
/// node's children: the start `T`, per axis the bounds from the node's frame origin (whole
/// multiples of `2^(e − g − F)`), and that origin.
#[derive(Debug)]
struct Carry {
    t: Dyadic,
    x: [(Dyadic, Dyadic); 3],
    origin: [Dyadic; 3],
}

impl Tracer<'_> {
    /// Traces one ray (id `id`) through the wide BVH, counting into `st`.
    pub(crate) fn trace_wide(
        &self,
        wide: &WideAccel,
        boxes: Boxes,
        r: &mut TRay,
        id: u64,
        st: &mut KindStats,
    ) {
        let (o, d) = (bits3(r.o_w), bits3(r.d_w));
        let inv_d = slab_reciprocal(FloatFormat::BINARY32, &d);
        let tlas_tests = st.tlas_node_visits;
        self.walk(
            &wide.tlas,
            true,
            None,
            boxes,
            o,
            d,
            inv_d,
            r,
            st,
            &mut |r, insts, st| {
                for &inst in insts {
                    let x = &self.accel.instances[inst as usize];
                    st.transforms += 1;
                    self.enter_model(r, x, id);
                    let (o, d, inv_d) = (r.o, r.d, r.inv_d);
                    let mesh = self.meshes[x.mesh];
                    self.walk(
                        &wide.blas[x.mesh],
                        false,
                        wide.dop.get(x.mesh).map(Vec::as_slice),
                        boxes,
                        o,
                        d,
                        inv_d,
                        r,
                        st,
                        &mut |r, tris, st| self.leaf(r, inst, mesh, tris, st),
                    );
                    if r.done {
                        return;
                    }
                }
            },
        );
        // the TLAS root's node test, if made, is its first
        wide.oracle.count(r, st.tlas_node_visits > tlas_tests, st);
    }

    /// Depth-first walk of one wide tree with the ray `(o, inv_d)` of its
    /// space, a stack of the hit children not yet visited; `leaf` handles
    /// the primitives of a hit leaf slot (leaves of a node first, nearest
    /// first, then its inner children, nearest on top of the stack).
    #[allow(clippy::too_many_arguments)]
    fn walk(
        &self,
        bvh: &WideBvh,
        tlas: bool,
        dop: Option<&[DopNode]>,
        boxes: Boxes,
        o: [u64; 3],
        d: [u64; 3],
        inv_d: [u64; 3],
        r: &mut TRay,
        st: &mut KindStats,
        leaf: &mut dyn FnMut(&mut TRay, &[u32], &mut KindStats),
    ) {
        if bvh.nodes.is_empty() {
            return;
        }
        let n = bvh.format.children();
        let params = NodeParams::new(FloatFormat::BINARY32, n, bvh.format.box_bits())
            .expect("a wide format is a valid node shape");
        let study = ReoriginParams::new(FloatFormat::BINARY32, n, bvh.format.box_bits());
        let bytes = match boxes {
            Boxes::Anchored | Boxes::Node | Boxes::Carried(_) => bvh.format.record_bytes(),
            Boxes::Exact => bvh.format.baseline_bytes(),
        } as u64;
        // the start of each node's test (re-origin study): the root's from a box test
        let root_start = match boxes {
            Boxes::Node | Boxes::Carried(_) => {
                let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
                for (i, (l, h)) in bvh.exact[0].iter().enumerate() {
                    if bvh.nodes[0].valid >> i & 1 == 1 {
                        for a in 0..3 {
                            lo[a] = lo[a].min(l[a]);
                            hi[a] = hi[a].max(h[a]);
                        }
                    }
                }
                // an origin inside the root's box starts at t_min = 0 (what the box test
                // would give): six comparisons instead of a box test, as for a shadow or
                // ambient-occlusion ray leaving a surface of the tree
                let at = |a: usize| f32::from_bits(o[a] as u32);
                if (0..3).all(|a| lo[a] <= at(a) && at(a) <= hi[a]) {
                    0
                } else {
                    let out = box_test((lo, hi), o, inv_d, r.box_t_max());
                    st.child_tests += 1; // the root box test, counted as one child test
                    st.root_box_tests += 1;
                    if !out.hit {
                        return;
                    }
                    out.t_enter
                }
            }
            _ => 0,
        };
        let mut stack: Vec<(u32, u64, Option<Rc<Carry>>)> = vec![(0, root_start, None)];
        let mut order: Vec<usize> = Vec::with_capacity(n);
        let mut starts = [0u64; MAX_CHILDREN];
        while let Some((id, t_start, carried)) = stack.pop() {
            if r.done {
                return;
            }
            let id = id as usize;
            let node = &bvh.nodes[id];
            st.node_visits += 1;
            st.tlas_node_visits += u64::from(tlas);
            st.node_bytes += bytes;
            st.child_tests += node.valid.count_ones() as u64;
            let ray = NodeRay {
                o,
                inv_d,
                t_min: 0,
                t_max: r.box_t_max(),
            };
            order.clear();
            // the position this node hands its children (the carried-position study)
            let mut carry_next = None;
            match boxes {
                Boxes::Anchored => {
                    // the node tester: slots sorted, hits first, nearer first
                    let out = node::eval(params, &ray, &NodeIn::from_wide(node));
                    order.extend(out.slots.iter().filter(|s| s.hit).map(|s| s.child as usize));
                }
                Boxes::Node => {
                    let node_in = NodeIn::from_wide(node);
                    let out = match dop {
                        // the cull-plane study's extra axes: the model only
                        Some(t) => node_reorigin::eval_with(
                            &study,
                            &ray,
                            d,
                            t_start,
                            &node_in,
                            &dop_axes(&t[id], o, d),
                        ),
                        // the `node` unit
                        None => self.units.node(&NodeTestIn {
                            params: &study,
                            ray: &ray,
                            d: &d,
                            t_start,
                            node: &node_in,
                        }),
                    };
                    take_hits(&out, &mut order, &mut starts);
                }
                Boxes::Carried(frac) => {
                    let (g, frac) = (i64::from(study.pos_frac), i64::from(frac));
                    let value = |b: u64| dyadic(f32::from_bits(b as u32) as f64);
                    let origin = node.frame.origin.map(value);
                    let exp = node.frame.exp.map(i64::from);
                    // the bounds at T, whole multiples of 2^(e − g − F): the root's from
                    // the exact position, a child's from its parent's, each rounded outward
                    let position = |t: &Dyadic, a: usize| -> (Dyadic, Dyadic) {
                        let unit = exp[a] - g - frac;
                        let outward = |v: &Dyadic| {
                            (
                                Dyadic::new(v.div_pow2_round(unit, false), unit),
                                Dyadic::new(v.div_pow2_round(unit, true), unit),
                            )
                        };
                        let moved = t.mul(&value(d[a]));
                        match &carried {
                            None => outward(&value(o[a]).add(&moved).sub(&origin[a])),
                            Some(c) => {
                                let shift = c.origin[a]
                                    .sub(&origin[a])
                                    .add(&moved)
                                    .sub(&c.t.mul(&value(d[a])));
                                let (lo, hi) = &c.x[a];
                                (outward(&lo.add(&shift)).0, outward(&hi.add(&shift)).1)
                            }
                        }
                    };
                    // onto the position grid, outward (inward for a parallel axis)
                    let at = |t: &Dyadic, a: usize, parallel: bool| {
                        let (lo, hi) = position(t, a);
                        let grid = exp[a] - g;
                        (
                            lo.div_pow2_round(grid, parallel),
                            hi.div_pow2_round(grid, !parallel),
                        )
                    };
                    let out = node_reorigin::eval_carried(
                        &study,
                        &ray,
                        d,
                        t_start,
                        &NodeIn::from_wide(node),
                        &at,
                    );
                    carry_next = match &out.t_base {
                        Bound::Fin(t) => Some(Rc::new(Carry {
                            t: t.clone(),
                            x: [0, 1, 2].map(|a| position(t, a)),
                            origin,
                        })),
                        Bound::NegInf => None,
                    };
                    take_hits(&out, &mut order, &mut starts);
                }
                Boxes::Exact => {
                    let mut hits: Vec<(u32, usize)> = (0..n)
                        .filter(|&i| node.valid >> i & 1 == 1)
                        .filter_map(|i| {
                            let out = box_test(bvh.exact[id][i], o, inv_d, ray.t_max);
                            // entry distances (non-negative here) order as their bits
                            out.hit.then_some((out.t_enter as u32 & 0x7fff_ffff, i))
                        })
                        .collect();
                    hits.sort_unstable();
                    order.extend(hits.iter().map(|&(_, i)| i));
                }
            }
            for &i in &order {
                if let ChildRef::Leaf { first, count } = node.child(i) {
                    st.leaf_visits += 1;
                    leaf(r, &bvh.prims[first as usize..(first + count) as usize], st);
                    if r.done {
                        return;
                    }
                }
            }
            for &i in order.iter().rev() {
                if let ChildRef::Inner(c) = node.child(i) {
                    stack.push((c, starts[i], carry_next.clone()));
                }
            }
        }
    }
}

/// A node test's hit slots in its order into `order`, and each one's entry, rounded down to
/// binary32, into `starts` (the start of that child's own test).
fn take_hits(out: &NodeOut, order: &mut Vec<usize>, starts: &mut [u64; MAX_CHILDREN]) {
    for s in out.slots.iter().filter(|s| s.hit) {
        order.push(s.child as usize);
        starts[s.child as usize] = match out.entry_value(s) {
            Bound::Fin(v) => f32_down(&v),
            Bound::NegInf => 0,
        };
    }
}

/// The camera's primary rays of a `w`×`h` image through `wide` (rows in
/// parallel): per pixel, row-major, the nearest hit, and the counters.
pub fn primary(
    scene: &Scene,
    accel: &Accel,
    wide: &WideAccel,
    boxes: Boxes,
    w: u32,
    h: u32,
) -> (Vec<Hit>, KindStats) {
    let tracer = Tracer::new(scene, accel, &Exact, TraceOpts::default()).with_wide(wide, boxes);
    let cam = Cam::new(scene, w, h);
    let rows: Vec<(Vec<Hit>, Stats)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut st = Stats::default();
            let mut rays: Vec<TRay> = (0..w)
                .map(|x| TRay::new(cam.o, cam.dir(x, y), f64::INFINITY, false))
                .collect();
            let idx: Vec<usize> = (0..rays.len()).collect();
            tracer.trace(&mut rays, &idx, RayKind::Primary, &mut st);
            (rays.iter().map(|r| r.hit).collect(), st)
        })
        .collect();
    let mut st = Stats::default();
    let mut hits = Vec::with_capacity((w * h) as usize);
    for (row, s) in rows {
        hits.extend(row);
        st.add(&s);
    }
    (hits, st.total())
}

/// One row of [`report`]: a scene's wide BVH of one shape and its camera rays.
#[derive(Debug, Clone)]
pub struct ReportRow {
    /// the node shape of the BLAS
    pub format: WideFormat,
    /// q of the TLAS nodes
    pub tlas_box_bits: u32,
    /// wide nodes (TLAS and every BLAS)
    pub nodes: u64,
    /// bytes of all node records
    pub node_bytes: u64,
    /// the traversal with the node tester on the compressed nodes
    pub compressed: KindStats,
    /// the same tree with exact binary32 child boxes
    pub exact: KindStats,
    /// both traversals found the same nearest hit on every pixel
    pub same_hits: bool,
    /// when asked for: the tile and the bundle bound of the camera rays
    /// ([`crate::wide_bundle`])
    pub bundle: Option<(u32, crate::wide_bundle::BundleBound)>,
}

impl ReportRow {
    /// Child tests per ray with the decoded boxes over those with exact binary32 boxes.
    pub fn child_test_ratio(&self) -> f64 {
        self.compressed.per_ray(self.compressed.child_tests)
            / self.exact.per_ray(self.exact.child_tests)
    }
}

/// Builds the wide BVH of every shape and traces the `w`×`h` camera rays
/// through it twice (decoded boxes, exact binary32 boxes), and with
/// `bundle_tile` a third time for the bundle bound of that tile.
pub fn report(
    scene: &Scene,
    accel: &Accel,
    shapes: &[WideFormat],
    tlas_box_bits: u32,
    w: u32,
    h: u32,
    bundle_tile: Option<u32>,
) -> Result<Vec<ReportRow>, String> {
    shapes
        .iter()
        .map(|&format| {
            let wide = WideAccel::build(accel, format, tlas_box_bits)?;
            let (hq, sq) = primary(scene, accel, &wide, Boxes::Node, w, h);
            let (he, se) = primary(scene, accel, &wide, Boxes::Exact, w, h);
            let key = |h: &Hit| (h.inst, h.prim, h.t.to_bits());
            Ok(ReportRow {
                format,
                tlas_box_bits,
                nodes: wide.nodes(),
                node_bytes: wide.node_bytes(),
                compressed: sq,
                exact: se,
                same_hits: hq.iter().map(key).eq(he.iter().map(key)),
                bundle: bundle_tile.map(|t| {
                    (
                        t,
                        crate::wide_bundle::bundle_bound(scene, accel, &wide, w, h, t),
                    )
                }),
            })
        })
        .collect()
}

/// The table of [`report`] rows of several scenes (markdown), then one line
/// per row `child tests per ray q=<q> / binary32 (N=<n>): <scene> <ratio>`.
pub fn report_table(rows: &[(String, ReportRow)]) -> String {
    let mut s = String::from(
        "| scene | N | q | TLAS q | nodes | bytes/node (BLAS) | node bytes | node visits/ray | bytes/ray | child tests/ray | binary32 boxes: bytes/node | bytes/ray | child tests/ray | child tests q / binary32 | same hits |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (name, r) in rows {
        let (c, e) = (&r.compressed, &r.exact);
        let f = r.format;
        s += &format!(
            "| {name} | {} | {} | {} | {} | {} | {} | {:.2} | {:.0} | {:.2} | {} | {:.0} | {:.2} | {:.4} | {} |\n",
            f.children(),
            f.box_bits(),
            r.tlas_box_bits,
            r.nodes,
            f.record_bytes(),
            r.node_bytes,
            c.per_ray(c.node_visits),
            c.per_ray(c.node_bytes),
            c.per_ray(c.child_tests),
            f.baseline_bytes(),
            e.per_ray(e.node_bytes),
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

/// The binary32 bits of the largest value at or below `v` (non-negative
/// here: a start of `t`), saturating at the largest finite value.
fn f32_down(v: &Dyadic) -> u64 {
    let x = v.round(24, false);
    let f = f64::from(i32::try_from(&x.m).unwrap_or(i32::MAX)) * (x.e as f64).exp2();
    if f <= 0.0 {
        return 0;
    }
    let mut g = f as f32;
    if g as f64 > f {
        g = g.next_down();
    }
    g.min(f32::MAX).to_bits() as u64
}

/// The golden conservative slab (binary32) on an exact box, segment `[0, t_max]`.
fn box_test(b: Box32, o: [u64; 3], inv_d: [u64; 3], t_max: u64) -> golden_model::slab::SlabOut {
    eval_conservative(
        FloatFormat::BINARY32,
        &SlabIn {
            p_min: b.0.map(|v| v.to_bits() as u64),
            p_max: b.1.map(|v| v.to_bits() as u64),
            o,
            inv_d,
            t_min: 0,
            t_max,
        },
    )
}

/// The k-DOP directions of the cull-plane study (docs/node.md §11): the four
/// body diagonals, then the six face diagonals (with the box axes a 26-DOP).
/// [`DopSelect::All`] gives every BLAS node the first four (a 14-DOP).
pub const DOP_DIRS: [[i32; 3]; 10] = [
    [1, 1, 1],
    [1, 1, -1],
    [1, -1, 1],
    [-1, 1, 1],
    [1, 1, 0],
    [1, -1, 0],
    [1, 0, 1],
    [1, 0, -1],
    [0, 1, 1],
    [0, 1, -1],
];

/// Which directions a BLAS node carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DopSelect {
    /// the four body diagonals at every node
    All,
    /// one direction per node, of all ten [`DOP_DIRS`], chosen by the builder: the one
    /// that shrinks its slots most where rays and triangles are ([`direction_score`])
    One,
    /// one direction per node, chosen as `One` does from the ten and from the node's own
    /// normals: the area-weighted mean normal of each slot's triangles and of all of
    /// them, quantised to integer components in `-NORMAL_STEPS..=NORMAL_STEPS` (issue
    /// 37's per-node normals, against `One`'s fixed palette)
    Normal,
}

/// The largest component of a quantised per-node normal ([`DopSelect::Normal`]): a
/// direction of small integers keeps `n·o` and `n·d` sums of shifted components.
pub const NORMAL_STEPS: i32 = 4;

/// One BLAS node's extra axes, one per carried direction.
#[derive(Debug, Clone)]
pub struct DopNode {
    /// the carried directions
    pub axes: Vec<DopAxis>,
}

/// One carried direction of a node: a frame `U + [0, Q]·2^e` along it and
/// per slot the q-bit extent of its triangles, outward.
#[derive(Debug, Clone)]
pub struct DopAxis {
    /// the direction (small integers: one of [`DOP_DIRS`] or a quantised normal)
    pub dir: [i32; 3],
    /// frame origin `U`
    pub origin: Dyadic,
    /// frame step exponent `e`
    pub exp: i64,
    /// per slot the lower integer
    pub lo: [u16; MAX_CHILDREN],
    /// per slot the upper integer
    pub hi: [u16; MAX_CHILDREN],
}

/// A finite binary64 value, exactly.
fn dyadic(v: f64) -> Dyadic {
    match golden_model::exact::ray_box::decode(FloatFormat::BINARY64, v.to_bits()) {
        golden_model::exact::ray_box::Exact::Fin { m, e } => Dyadic::new(m.into(), e as i64),
        _ => panic!("a finite coordinate"),
    }
}

/// `n·v` of an f32 point, rounded down and up. Each term `n_a·v_a` is exact in
/// binary64 (a 24-bit significand times a small integer); the two additions round
/// by at most `2^−53` of the sum of magnitudes each, so the bounds widen by
/// `2^−51` of it (a fixed number of steps from the result, as before 2026-12-07,
/// is too few when terms cancel: `2^60 + 1 − 2^60` sums to 0).
fn along(n: [i32; 3], v: [f32; 3]) -> (f64, f64) {
    let terms = (0..3).map(|a| n[a] as f64 * v[a] as f64);
    let x: f64 = terms.clone().sum();
    let slack = terms.map(f64::abs).sum::<f64>() * f64::powi(2.0, -51);
    ((x - slack).next_down(), (x + slack).next_up())
}

/// Extents of a slot's triangles: along [`DOP_DIRS`], along the axes, and how
/// many triangles.
#[derive(Debug, Clone, Copy)]
struct SlotExtent {
    lo: [f64; DOP_DIRS.len()],
    hi: [f64; DOP_DIRS.len()],
    box_lo: [f64; 3],
    box_hi: [f64; 3],
    triangles: u64,
}

impl SlotExtent {
    const NONE: SlotExtent = SlotExtent {
        lo: [f64::INFINITY; DOP_DIRS.len()],
        hi: [f64::NEG_INFINITY; DOP_DIRS.len()],
        box_lo: [f64::INFINITY; 3],
        box_hi: [f64::NEG_INFINITY; 3],
        triangles: 0,
    };

    fn add_point(&mut self, v: [f32; 3]) {
        for (j, n) in DOP_DIRS.iter().enumerate() {
            let (lo, hi) = along(*n, v);
            self.lo[j] = self.lo[j].min(lo);
            self.hi[j] = self.hi[j].max(hi);
        }
        for a in 0..3 {
            self.box_lo[a] = self.box_lo[a].min(v[a] as f64);
            self.box_hi[a] = self.box_hi[a].max(v[a] as f64);
        }
    }

    fn merge(&mut self, o: &SlotExtent) {
        for j in 0..DOP_DIRS.len() {
            self.lo[j] = self.lo[j].min(o.lo[j]);
            self.hi[j] = self.hi[j].max(o.hi[j]);
        }
        for a in 0..3 {
            self.box_lo[a] = self.box_lo[a].min(o.box_lo[a]);
            self.box_hi[a] = self.box_hi[a].max(o.box_hi[a]);
        }
        self.triangles += o.triangles;
    }
}

/// What direction `j` is worth at a node: over its slots, the slot's surface
/// area (how often a ray visits it) times its triangles (the work below it)
/// times how much the extent along `j` shrinks the slot's box projected on
/// `j` (`1 − extent / projection`): a SAH-like proxy of the tests it cuts.
fn direction_score(slots: &[SlotExtent], n: [i32; 3], extent: &[(f64, f64)]) -> f64 {
    slots
        .iter()
        .zip(extent)
        .filter(|(s, _)| s.triangles > 0)
        .map(|(s, &(lo, hi))| {
            let e: Vec<f64> = (0..3).map(|a| s.box_hi[a] - s.box_lo[a]).collect();
            let area = 2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
            let projection: f64 = (0..3).map(|a| n[a].abs() as f64 * e[a]).sum();
            let shrink = if projection > 0.0 {
                (1.0 - (hi - lo) / projection).max(0.0)
            } else {
                0.0
            };
            area * s.triangles as f64 * shrink
        })
        .sum()
}

/// The extent along `n` of triangles `tris` of `mesh`, outward (`(∞, −∞)` for none).
fn extent_along(n: [i32; 3], mesh: &Mesh, tris: &[u32]) -> (f64, f64) {
    let mut e = (f64::INFINITY, f64::NEG_INFINITY);
    for &t in tris {
        for v in mesh.corners(t) {
            let (lo, hi) = along(n, v);
            e = (e.0.min(lo), e.1.max(hi));
        }
    }
    e
}

/// The sum of triangles `tris`' normals weighted by area (twice the area: the cross
/// products of their edges, one orientation).
fn normal_sum(mesh: &Mesh, tris: &[u32]) -> [f64; 3] {
    let mut sum = [0f64; 3];
    for &t in tris {
        let [a, b, c] = mesh.corners(t).map(|v| v.map(f64::from));
        let (u, w) = (
            [0, 1, 2].map(|k| b[k] - a[k]),
            [0, 1, 2].map(|k| c[k] - a[k]),
        );
        let cross = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        // a mesh's neighbours face the same side: one orientation, summed
        for k in 0..3 {
            sum[k] += cross[k];
        }
    }
    sum
}

/// A normal sum ([`normal_sum`]) as a direction: quantised to integer components of
/// at most [`NORMAL_STEPS`] (the sign of a direction does not matter to an extent, so
/// it is made canonical); `None` when it is zero.
fn quantised(sum: [f64; 3]) -> Option<[i32; 3]> {
    let big = sum.iter().fold(0f64, |m, x| m.max(x.abs()));
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    let mut n = sum.map(|x| (x / big * f64::from(NORMAL_STEPS)).round() as i32);
    if let Some(&first) = n.iter().find(|&&x| x != 0) {
        if first < 0 {
            n = n.map(|x| -x);
        }
    }
    (n != [0; 3]).then_some(n)
}

/// The triangles below every node of `bvh`, bottom-up (the per-node normal study).
fn triangles_below(bvh: &WideBvh) -> Vec<Vec<u32>> {
    let mut below: Vec<Vec<u32>> = vec![Vec::new(); bvh.nodes.len()];
    for id in (0..bvh.nodes.len()).rev() {
        let mut all = Vec::new();
        for i in 0..MAX_CHILDREN {
            match bvh.nodes[id].child(i) {
                ChildRef::Leaf { first, count } => {
                    all.extend_from_slice(&bvh.prims[first as usize..(first + count) as usize])
                }
                ChildRef::Inner(c) => all.extend_from_slice(&below[c as usize]),
                ChildRef::Empty => {}
            }
        }
        below[id] = all;
    }
    below
}

/// A direction a node may carry, with each slot's extent along it (outward).
type Carried = ([i32; 3], Vec<(f64, f64)>);

/// The k-DOP extents of every node of `bvh` (a BLAS of `mesh`), bottom-up.
fn dop_tree(bvh: &WideBvh, mesh: &Mesh, select: DopSelect) -> Vec<DopNode> {
    let q_max = bvh.format.q_max() as i64;
    let mut node_extent = vec![SlotExtent::NONE; bvh.nodes.len()];
    let mut out: Vec<Option<DopNode>> = vec![None; bvh.nodes.len()];
    let below = match select {
        DopSelect::Normal => triangles_below(bvh),
        _ => Vec::new(),
    };
    for id in (0..bvh.nodes.len()).rev() {
        let node = &bvh.nodes[id];
        // each slot's triangles (the per-node normal study only)
        let slot_tris = |i: usize| -> &[u32] {
            match node.child(i) {
                ChildRef::Leaf { first, count } => {
                    &bvh.prims[first as usize..(first + count) as usize]
                }
                ChildRef::Inner(c) => &below[c as usize],
                ChildRef::Empty => &[],
            }
        };
        let mut slots = [SlotExtent::NONE; MAX_CHILDREN];
        for (i, slot) in slots.iter_mut().enumerate() {
            match node.child(i) {
                ChildRef::Leaf { first, count } => {
                    for &t in &bvh.prims[first as usize..(first + count) as usize] {
                        for v in mesh.corners(t) {
                            slot.add_point(v);
                        }
                    }
                    slot.triangles = u64::from(count);
                }
                ChildRef::Inner(c) => *slot = node_extent[c as usize],
                ChildRef::Empty => {}
            }
        }
        let mut ext = SlotExtent::NONE;
        for sl in &slots {
            ext.merge(sl);
        }
        node_extent[id] = ext;
        // per carried direction, the slots' extents along it
        let palette = |j: usize| -> Carried {
            (
                DOP_DIRS[j],
                slots.iter().map(|s| (s.lo[j], s.hi[j])).collect(),
            )
        };
        let best = |candidates: Vec<Carried>| {
            candidates
                .into_iter()
                .map(|(n, e)| (direction_score(&slots, n, &e), n, e))
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, n, e)| (n, e))
                .expect("ten directions at least")
        };
        let dirs: Vec<Carried> = match select {
            DopSelect::All => (0..4).map(palette).collect(),
            DopSelect::One => vec![best((0..DOP_DIRS.len()).map(palette).collect())],
            DopSelect::Normal => {
                let mut candidates: Vec<_> = (0..DOP_DIRS.len()).map(palette).collect();
                // each slot's normal sum, and the node's as theirs added (its triangles
                // are the slots')
                let sums: Vec<[f64; 3]> = (0..MAX_CHILDREN)
                    .map(|i| normal_sum(mesh, slot_tris(i)))
                    .collect();
                let node_sum = sums
                    .iter()
                    .fold([0f64; 3], |a, s| [a[0] + s[0], a[1] + s[1], a[2] + s[2]]);
                let mut normals: Vec<[i32; 3]> = sums
                    .into_iter()
                    .chain([node_sum])
                    .filter_map(quantised)
                    .collect();
                normals.sort_unstable();
                normals.dedup();
                for n in normals {
                    let e = (0..MAX_CHILDREN)
                        .map(|i| extent_along(n, mesh, slot_tris(i)))
                        .collect();
                    candidates.push((n, e));
                }
                vec![best(candidates)]
            }
        };
        let mut dop = DopNode { axes: Vec::new() };
        for (n, slot_ext) in dirs {
            let (ext_lo, ext_hi) = slot_ext
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &(a, b)| {
                    (l.min(a), h.max(b))
                });
            let origin = dyadic(if ext_lo.is_finite() { ext_lo } else { 0.0 });
            let range = ext_hi - ext_lo;
            let exp = if range.is_finite() && range > 0.0 {
                // the least e with Q·2^e ≥ range (rounded up in f64 once more), searched
                // up from below it (range/Q underflows to 0 for the few-subnormal range of
                // an extent at 0, which a flat patch through the origin has)
                let mut e = range.log2().floor() as i64 - i64::from(bvh.format.box_bits()) - 1;
                while (q_max as f64) * (e as f64).exp2() < range.next_up() {
                    e += 1;
                }
                e
            } else {
                -60
            };
            let mut lo = [0u16; MAX_CHILDREN];
            let mut hi = [0u16; MAX_CHILDREN];
            for (i, &(sl_lo, sl_hi)) in slot_ext.iter().enumerate() {
                if !sl_lo.is_finite() {
                    continue;
                }
                let rel = |v: f64, up: bool| {
                    let k = dyadic(v).sub(&origin).div_pow2_round(exp, up);
                    i64::try_from(k).unwrap_or(q_max).clamp(0, q_max) as u16
                };
                lo[i] = rel(sl_lo, false);
                hi[i] = rel(sl_hi, true);
            }
            dop.axes.push(DopAxis {
                dir: n,
                origin,
                exp,
                lo,
                hi,
            });
        }
        out[id] = Some(dop);
    }
    out.into_iter().map(|n| n.expect("every node")).collect()
}

/// The extra axes of one node for the ray `(o, d)` (raw binary32 bits).
fn dop_axes(dop: &DopNode, o: [u64; 3], d: [u64; 3]) -> Vec<ExtraAxis> {
    let val = |b: u64| dyadic(f32::from_bits(b as u32) as f64);
    let (o, d) = (o.map(val), d.map(val));
    dop.axes
        .iter()
        .map(|axis| {
            let n = axis.dir;
            // n·v exactly: the components are small integers
            let dot = |v: &[Dyadic; 3]| {
                (0..3).fold(dyadic(0.0), |acc, a| {
                    acc.add(&v[a].mul(&dyadic(f64::from(n[a]))))
                })
            };
            ExtraAxis {
                o: dot(&o),
                d: dot(&d),
                origin: axis.origin.clone(),
                exp: axis.exp,
                lo: axis.lo,
                hi: axis.hi,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `along` bounds `n·v` when its terms cancel (a fixed number of steps from the rounded
    /// sum did not: `2^60 + 1 − 2^60` sums to 0 in binary64) and for the largest components.
    #[test]
    fn along_bounds_the_exact_dot_product() {
        let big = 2f32.powi(60);
        for (n, v, exact) in [
            ([1, 1, 1], [big, 1.0, -big], 1.0),
            ([4, -3, 2], [1.5, 0.25, -0.125], 5.0),
            ([0, 0, 4], [7.0, -7.0, 0.0], 0.0),
            ([1, 1, -1], [f32::MAX, f32::MAX, f32::MAX], f32::MAX as f64),
        ] {
            let (lo, hi) = along(n, v);
            assert!(
                lo <= exact && exact <= hi,
                "{n:?}·{v:?} = {exact} in [{lo}, {hi}]"
            );
        }
    }

    /// A per-node normal is the canonical quantised direction of the triangles' mean normal.
    #[test]
    fn a_flat_patch_has_its_own_normal() {
        // a square at z = 2, wound clockwise seen from above: the normal points down and
        // is made canonical (first nonzero component positive)
        let square = Mesh {
            vertices: vec![
                [0.0, 0.0, 2.0],
                [0.0, 1.0, 2.0],
                [1.0, 1.0, 2.0],
                [1.0, 0.0, 2.0],
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        assert_eq!(
            quantised(normal_sum(&square, &[0, 1])),
            Some([0, 0, NORMAL_STEPS])
        );
        // a tilted one keeps its proportions to the nearest step: (1, 0, 2) → (2, 0, 4)
        let tilted = Mesh {
            vertices: vec![[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, -1.0]],
            triangles: vec![[0, 1, 2]],
        };
        assert_eq!(quantised(normal_sum(&tilted, &[0])), Some([2, 0, 4]));
        // a degenerate triangle has none
        let line = Mesh {
            vertices: vec![[0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]],
            triangles: vec![[0, 1, 2]],
        };
        assert_eq!(quantised(normal_sum(&line, &[0])), None);
    }
}
