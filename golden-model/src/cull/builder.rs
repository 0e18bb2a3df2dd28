//! The builder that places cull planes (software, seed 001 FIG. 13), in the
//! seed's layout (claims 7-8): every inner node stores K **shared normals**
//! for the planes of its two children, and every child stores one distance
//! per normal, measured from the parent box's lower corner `r`:
//! `n·(x − r) ≤ w` is the child's non-empty side.
//!
//! Candidate normals: at a leaf, its triangle normals (both ways) and 98
//! fixed directions (every integer vector with components in -2..=2, at
//! least two of them nonzero, in lowest terms; axis directions cut nothing
//! off a tight box), each quantised to the plane format (round to
//! nearest: any normal is valid); the best of each octant of directions is
//! the leaf's *preferred* set. An inner node's preferred set is the best per
//! octant of its children's preferred normals, judged on its own box. The
//! shared normals of an inner node are chosen from its children's preferred
//! normals: each scored by the fraction of each child's box it cuts off
//! (sampled on a grid, weighted by the child box's surface area, the chance a
//! ray meets it), the best per octant, then the `k` best.
//!
//! Every stored distance is **fitted exactly**: `w = max over the child's
//! vertices (its whole subtree) of n·(v − r)` in dyadic arithmetic (an `f64`
//! pass only shortlists the vertices within its error bound of the maximum),
//! **rounded up** to the plane format. So no vertex lies strictly on the
//! empty side of a stored plane; one may lie on it.

use super::bvh::{Bvh, Mesh, NodeKind};
use super::exact::Dyadic;
use crate::float::{convert, to_f64, FloatFormat, RoundingMode};

/// Builder parameters.
#[derive(Debug, Clone, Copy)]
pub struct BuildParams {
    /// plane format
    pub plane: FloatFormat,
    /// planes per node (1..=8)
    pub k: usize,
    /// sample points per box axis for the empty-volume score
    pub samples: usize,
}

/// The planes of every node (same indices as [`Bvh::nodes`]), best first.
#[derive(Debug, Clone, Default)]
pub struct CullPlanes {
    /// per node, the normals its children's planes share (plane format;
    /// empty for leaves and where no normal cuts anything)
    pub normals: Vec<Vec<[u64; 3]>>,
    /// the root's normals (kept beside the tree: the root has no parent;
    /// its distances are measured from its own box's lower corner)
    pub root_normals: Vec<[u64; 3]>,
    /// the root's scores
    pub root_scores: Vec<f64>,
    /// per node, its distance per normal of its parent (plane format),
    /// measured from the parent box's lower corner (the root: per root normal,
    /// from its own lower corner)
    pub w: Vec<Vec<u64>>,
    /// per inner node and normal, the area-weighted fraction of the
    /// children's boxes the normal cuts off (estimate)
    pub scores: Vec<Vec<f64>>,
}

impl CullPlanes {
    /// Planes stored in all: one distance per child and shared normal.
    pub fn plane_count(&self) -> usize {
        self.w.iter().map(Vec::len).sum()
    }
    /// Shared normals stored in all (the root's included).
    pub fn normal_count(&self) -> usize {
        self.root_normals.len() + self.normals.iter().map(Vec::len).sum::<usize>()
    }
    /// The normals node `id`'s distances refer to, and the lower corner of
    /// the box they are measured from: its parent's (or the root's own).
    pub fn normals_of<'a>(
        &'a self,
        bvh: &Bvh,
        id: usize,
        parent: Option<usize>,
    ) -> (&'a [[u64; 3]], [f32; 3]) {
        match parent {
            Some(p) => (&self.normals[p], bvh.nodes[p].min),
            None => (&self.root_normals, bvh.nodes[id].min),
        }
    }
}

/// The point the children's distances are measured from: the lower corner
/// of the parent's box, exact.
pub fn reference(min: &[f32; 3]) -> [Dyadic; 3] {
    min.map(Dyadic::from_f32)
}

/// `n·(v − c)` exactly, `n` in the plane format (`c` the reference point).
pub fn height(pf: FloatFormat, n: &[u64; 3], v: &[Dyadic; 3], c: &[Dyadic; 3]) -> Dyadic {
    let mut s = Dyadic::zero();
    for i in 0..3 {
        let ni = Dyadic::from_bits(pf, n[i]).expect("finite normal");
        s = s.add(&ni.mul(&v[i].sub(&c[i])));
    }
    s
}

fn fixed_directions() -> Vec<[f64; 3]> {
    let mut v: Vec<[f64; 3]> = Vec::new();
    for x in -2i32..=2 {
        for y in -2i32..=2 {
            for z in -2i32..=2 {
                let nz = (x != 0) as u32 + (y != 0) as u32 + (z != 0) as u32;
                let g = gcd(gcd(x.unsigned_abs(), y.unsigned_abs()), z.unsigned_abs());
                if nz >= 2 && g == 1 {
                    v.push([x as f64, y as f64, z as f64]);
                }
            }
        }
    }
    v
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

fn quantise(pf: FloatFormat, n: [f64; 3]) -> [u64; 3] {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    n.map(|c| {
        convert(
            FloatFormat::BINARY64,
            pf,
            (c / len).to_bits(),
            RoundingMode::NearestEven,
        )
    })
}

fn octant(pf: FloatFormat, n: &[u64; 3]) -> usize {
    (0..3)
        .map(|i| ((n[i] & pf.sign_bit() != 0) as usize) << i)
        .sum()
}

/// Fraction of grid sample points of the box `[min, max]` strictly on the
/// empty side of `n·(x − r) > w` (f64 estimate, only used to choose).
fn score(
    n: &[f64; 3],
    r: &[f64; 3],
    w: f64,
    min: &[f32; 3],
    max: &[f32; 3],
    samples: usize,
) -> f64 {
    let mut cut = 0usize;
    for_each_sample(n, r, w, min, max, samples, |is_cut| cut += is_cut as usize);
    cut as f64 / samples.max(1).pow(3) as f64
}

/// The grid sample points of the box strictly on the empty side, as a bit set.
fn cut_mask(
    n: &[f64; 3],
    r: &[f64; 3],
    w: f64,
    min: &[f32; 3],
    max: &[f32; 3],
    samples: usize,
) -> Vec<u64> {
    let mut mask = vec![0u64; samples.max(1).pow(3).div_ceil(64)];
    let mut bit = 0usize;
    for_each_sample(n, r, w, min, max, samples, |is_cut| {
        mask[bit / 64] |= (is_cut as u64) << (bit % 64);
        bit += 1;
    });
    mask
}

/// Walks the `samples`³ grid points of the box `[min, max]` (cell centres,
/// x slowest) and tells `visit` whether each is strictly on the empty side
/// of `n·(x − r) > w`: the one sampling [`score`] and [`cut_mask`] share.
#[inline(always)]
fn for_each_sample(
    n: &[f64; 3],
    r: &[f64; 3],
    w: f64,
    min: &[f32; 3],
    max: &[f32; 3],
    samples: usize,
    mut visit: impl FnMut(bool),
) {
    let s = samples.max(1);
    let coord = |i: usize, j: usize| {
        min[i] as f64 + (max[i] as f64 - min[i] as f64) * (j as f64 + 0.5) / s as f64 - r[i]
    };
    for a in 0..s {
        let ha = n[0] * coord(0, a);
        for b in 0..s {
            let hb = ha + n[1] * coord(1, b);
            for k in 0..s {
                visit(hb + n[2] * coord(2, k) > w);
            }
        }
    }
}

fn area(min: &[f32; 3], max: &[f32; 3]) -> f64 {
    let e = [0, 1, 2].map(|i| max[i] as f64 - min[i] as f64);
    e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
}

/// The vertices of one subtree, exact and in f64.
struct Verts {
    exact: Vec<[Dyadic; 3]>,
    float: Vec<[f64; 3]>,
}

impl Verts {
    fn of(mesh: &Mesh, ids: &[u32]) -> Verts {
        Verts {
            exact: ids
                .iter()
                .map(|&v| mesh.vertices[v as usize].map(Dyadic::from_f32))
                .collect(),
            float: ids
                .iter()
                .map(|&v| mesh.vertices[v as usize].map(|x| x as f64))
                .collect(),
        }
    }
    /// `max n·(v − r)` in f64 (an estimate) and the indices within its error bound.
    fn max_f64(&self, n: &[f64; 3], r: &[f64; 3]) -> (f64, Vec<usize>) {
        let h: Vec<f64> = self
            .float
            .iter()
            .map(|v| n[0] * (v[0] - r[0]) + n[1] * (v[1] - r[1]) + n[2] * (v[2] - r[2]))
            .collect();
        let hmax = h.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let scale = self
            .float
            .iter()
            .map(|v| (0..3).map(|i| (v[i] - r[i]).abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let tol = 1e-6 * (1.0 + scale);
        let near = (0..h.len()).filter(|&j| h[j] >= hmax - tol).collect();
        (hmax, near)
    }
    /// The exact `max n·(v − r)` rounded up to the plane format, or `None` on overflow.
    fn fit(&self, pf: FloatFormat, n: &[u64; 3], r: &[Dyadic; 3], rf: &[f64; 3]) -> Option<u64> {
        let nf = n.map(|b| to_f64(pf, b));
        let (_, near) = self.max_f64(&nf, rf);
        let bound = near
            .iter()
            .map(|&j| height(pf, n, &self.exact[j], r))
            .reduce(|a, b| if b.cmp_exact(&a).is_gt() { b } else { a })?;
        let w = bound.round_to(pf, RoundingMode::Up);
        (w & !pf.sign_bit() != pf.inf(false)).then_some(w)
    }
}

/// The best per octant by score, best first; scores of 0 dropped.
fn best_per_octant(pf: FloatFormat, scored: Vec<([u64; 3], f64)>) -> Vec<([u64; 3], f64)> {
    let mut best: [Option<([u64; 3], f64)>; 8] = [None; 8];
    for (n, sc) in scored {
        if sc <= 0.0 {
            continue;
        }
        let o = octant(pf, &n);
        if best[o].is_none_or(|(_, b)| sc > b) {
            best[o] = Some((n, sc));
        }
    }
    let mut v: Vec<([u64; 3], f64)> = best.into_iter().flatten().collect();
    v.sort_by(|a, b| b.1.total_cmp(&a.1));
    v
}

/// How many normals a node hands up to its parent as candidates.
const PREFERRED: usize = 16;

/// A node's preferred normals: the best of each octant, then the next best
/// of any octant, [`PREFERRED`] in all.
fn preferred_of(pf: FloatFormat, mut scored: Vec<([u64; 3], f64)>) -> Vec<[u64; 3]> {
    let mut v: Vec<[u64; 3]> = best_per_octant(pf, scored.clone())
        .into_iter()
        .map(|x| x.0)
        .collect();
    scored.retain(|x| x.1 > 0.0 && !v.contains(&x.0));
    scored.sort_by(|a, b| b.1.total_cmp(&a.1));
    for (n, _) in scored {
        if v.len() >= PREFERRED {
            break;
        }
        if !v.contains(&n) {
            v.push(n);
        }
    }
    v
}

/// Places up to `params.k` shared normals on every inner node of `bvh` and
/// the distances on its children; panics with [`try_build_planes`]'s message
/// on a mesh with a non-finite vertex.
pub fn build_planes(mesh: &Mesh, bvh: &Bvh, params: &BuildParams) -> CullPlanes {
    try_build_planes(mesh, bvh, params).unwrap_or_else(|e| panic!("cull-plane builder: {e}"))
}

/// Places the planes, or `Err` naming the first vertex of `mesh` with a NaN
/// or infinite coordinate (the exact arithmetic has no value for it) — see
/// [`Mesh::check_finite`].
pub fn try_build_planes(
    mesh: &Mesh,
    bvh: &Bvh,
    params: &BuildParams,
) -> Result<CullPlanes, String> {
    mesh.check_finite()?;
    let pf = params.plane;
    let nn = bvh.nodes.len();
    let mut out = CullPlanes {
        normals: vec![Vec::new(); nn],
        root_normals: Vec::new(),
        root_scores: Vec::new(),
        w: vec![Vec::new(); nn],
        scores: vec![Vec::new(); nn],
    };
    // per node: its subtree's vertex indices and its preferred normals
    let mut verts: Vec<Vec<u32>> = vec![Vec::new(); nn];
    let mut preferred: Vec<Vec<[u64; 3]>> = vec![Vec::new(); nn];
    let dirs = fixed_directions();
    let own_score = |n: &[u64; 3], vs: &Verts, min: &[f32; 3], max: &[f32; 3]| {
        let nf = n.map(|b| to_f64(pf, b));
        let rf = min.map(|x| x as f64);
        let (w, _) = vs.max_f64(&nf, &rf);
        score(&nf, &rf, w, min, max, params.samples)
    };
    for id in (0..nn).rev() {
        let node = bvh.nodes[id];
        match node.kind {
            NodeKind::Leaf { .. } => {
                let tris = bvh.leaf_tris(id);
                let mut v: Vec<u32> = tris
                    .iter()
                    .flat_map(|&t| mesh.triangles[t as usize])
                    .collect();
                v.sort_unstable();
                v.dedup();
                let vs = Verts::of(mesh, &v);
                let mut normals: Vec<[f64; 3]> = Vec::new();
                for &t in tris {
                    let p = mesh.corners(t).map(|v| v.map(|x| x as f64));
                    let a = [0, 1, 2].map(|i| p[1][i] - p[0][i]);
                    let b = [0, 1, 2].map(|i| p[2][i] - p[0][i]);
                    let n = [
                        a[1] * b[2] - a[2] * b[1],
                        a[2] * b[0] - a[0] * b[2],
                        a[0] * b[1] - a[1] * b[0],
                    ];
                    if n.iter().any(|x| *x != 0.0) {
                        normals.push(n);
                        normals.push(n.map(|x| -x));
                    }
                }
                normals.extend(dirs.iter().copied());
                let scored = normals
                    .into_iter()
                    .map(|n| quantise(pf, n))
                    .filter(|nq| nq.iter().any(|&b| b & !pf.sign_bit() != 0))
                    .map(|nq| (nq, own_score(&nq, &vs, &node.min, &node.max)))
                    .collect();
                preferred[id] = preferred_of(pf, scored);
                verts[id] = v;
            }
            NodeKind::Inner { left, right } => {
                let (l, r) = (left as usize, right as usize);
                let mut cands: Vec<[u64; 3]> = preferred[l].clone();
                for n in preferred[r].iter().copied() {
                    if !cands.contains(&n) {
                        cands.push(n);
                    }
                }
                let kids = [l, r].map(|c| Verts::of(mesh, &verts[c]));
                let set = share(
                    pf,
                    params,
                    bvh,
                    &node.min,
                    &[(l, &kids[0]), (r, &kids[1])],
                    &cands,
                );
                out.normals[id] = set.normals;
                out.scores[id] = set.scores;
                let [wl, wr]: [Vec<u64>; 2] = set.w.try_into().expect("two children");
                out.w[l] = wl;
                out.w[r] = wr;
                // this node's own preferred normals, judged on its own box
                let mut v = verts[l].clone();
                v.extend_from_slice(&verts[r]);
                v.sort_unstable();
                v.dedup();
                let vs = Verts::of(mesh, &v);
                let scored = cands
                    .iter()
                    .map(|n| (*n, own_score(n, &vs, &node.min, &node.max)))
                    .collect();
                preferred[id] = preferred_of(pf, scored);
                verts[id] = v;
                verts[l] = Vec::new();
                verts[r] = Vec::new();
            }
        }
    }
    // the root's planes: normals kept beside the tree, the root's own box as reference
    if nn > 0 {
        let mut cands = preferred[0].clone();
        for n in dirs.iter().map(|d| quantise(pf, *d)) {
            if !cands.contains(&n) {
                cands.push(n);
            }
        }
        let vs = Verts::of(mesh, &verts[0]);
        let set = share(pf, params, bvh, &bvh.nodes[0].min, &[(0, &vs)], &cands);
        out.root_normals = set.normals;
        out.root_scores = set.scores;
        out.w[0] = set.w.into_iter().next().expect("one child");
    }
    Ok(out)
}

/// Shared normals chosen for a set of sibling nodes, and their distances.
struct SharedSet {
    normals: Vec<[u64; 3]>,
    scores: Vec<f64>,
    /// per sibling, one distance per normal
    w: Vec<Vec<u64>>,
}

/// Chooses up to `k` normals among `cands` for the siblings `kids` (node id
/// and subtree vertices), distances measured from `r_min`, greedily: each
/// normal adds the most sample points of the siblings' boxes (weighted by
/// box surface area) not yet cut off by the normals before it. Distances
/// are fitted exactly and rounded up; a normal whose distance overflows the
/// plane format for some sibling is dropped.
fn share(
    pf: FloatFormat,
    params: &BuildParams,
    bvh: &Bvh,
    r_min: &[f32; 3],
    kids: &[(usize, &Verts)],
    cands: &[[u64; 3]],
) -> SharedSet {
    let rd = reference(r_min);
    let rf = r_min.map(|x| x as f64);
    let weight: Vec<f64> = kids
        .iter()
        .map(|&(c, _)| area(&bvh.nodes[c].min, &bvh.nodes[c].max))
        .collect();
    let total = weight.iter().sum::<f64>().max(f64::MIN_POSITIVE);
    let cells = (params.samples.max(1).pow(3)) as f64;
    let masks: Vec<Vec<Vec<u64>>> = cands
        .iter()
        .map(|n| {
            let nf = n.map(|b| to_f64(pf, b));
            kids.iter()
                .map(|&(c, vs)| {
                    let (w, _) = vs.max_f64(&nf, &rf);
                    let b = &bvh.nodes[c];
                    cut_mask(&nf, &rf, w, &b.min, &b.max, params.samples)
                })
                .collect()
        })
        .collect();
    let words = cut_mask(
        &[0.0; 3],
        &[0.0; 3],
        0.0,
        &[0.0; 3],
        &[0.0; 3],
        params.samples,
    )
    .len();
    let mut covered: Vec<Vec<u64>> = vec![vec![0u64; words]; kids.len()];
    let mut chosen: Vec<([u64; 3], f64)> = Vec::new();
    while chosen.len() < params.k {
        let gain = |m: &Vec<Vec<u64>>| -> f64 {
            (0..kids.len())
                .map(|j| {
                    let new: u32 = m[j]
                        .iter()
                        .zip(&covered[j])
                        .map(|(a, c)| (a & !c).count_ones())
                        .sum();
                    weight[j] / total * new as f64 / cells
                })
                .sum()
        };
        let Some((best, g)) = masks
            .iter()
            .enumerate()
            .map(|(i, m)| (i, gain(m)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
        else {
            break;
        };
        if g <= 0.0 {
            break;
        }
        for (c, m) in covered.iter_mut().zip(&masks[best]) {
            for (x, a) in c.iter_mut().zip(m) {
                *x |= a;
            }
        }
        chosen.push((cands[best], g));
    }
    let mut set = SharedSet {
        normals: Vec::new(),
        scores: Vec::new(),
        w: vec![Vec::new(); kids.len()],
    };
    for (n, sc) in chosen {
        let w: Option<Vec<u64>> = kids
            .iter()
            .map(|(_, vs)| vs.fit(pf, &n, &rd, &rf))
            .collect();
        if let Some(w) = w {
            set.normals.push(n);
            set.scores.push(sc);
            for (dst, v) in set.w.iter_mut().zip(w) {
                dst.push(v);
            }
        }
    }
    set
}
