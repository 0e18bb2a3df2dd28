//! The builder that places cull planes (software, seed 001 FIG. 13).
//!
//! Leaves: candidate normals are the leaf's triangle normals (both ways) and
//! 20 fixed directions (the 8 cube diagonals and 12 edge diagonals; axis
//! directions cut nothing off a tight box). Each candidate normal is
//! quantised to the plane format (round to nearest: any normal is valid),
//! then its distance is fitted exactly: `w = max over the leaf's vertices of
//! n·(v − c)`, computed in exact dyadic arithmetic and **rounded up** to the
//! plane format, so the quantised plane leaves every vertex on or below it.
//! Its score is the fraction of the box it cuts off (estimated on a grid of
//! sample points). The best plane of each octant of normal directions is
//! kept, then the `k` best of those.
//!
//! Inner nodes: the children's planes are propagated up with their normals
//! unchanged and only the distance re-fitted: around the child the plane
//! came from, `w_child + n·(c_child − c_parent)` (exact), and around the
//! other child its box's 8 corners; the maximum is rounded up. Then the best
//! per octant and the `k` best, as for leaves.

use super::bvh::{Bvh, Mesh, NodeKind};
use super::exact::Dyadic;
use super::tester::Plane;
use crate::float::{convert, FloatFormat, RoundingMode};

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
#[derive(Debug, Clone)]
pub struct CullPlanes {
    /// per node, up to `k` planes
    pub planes: Vec<Vec<Plane>>,
    /// per node, the fraction of the box each plane cuts off (estimate)
    pub scores: Vec<Vec<f64>>,
}

/// The box centroid `(min + max) / 2`, exact.
pub fn centroid(min: &[f32; 3], max: &[f32; 3]) -> [Dyadic; 3] {
    [0, 1, 2].map(|i| {
        Dyadic::from_f32(min[i])
            .add(&Dyadic::from_f32(max[i]))
            .half()
    })
}

/// `n·(v − c)` exactly, `n` in the plane format.
pub fn height(pf: FloatFormat, n: &[u64; 3], v: &[Dyadic; 3], c: &[Dyadic; 3]) -> Dyadic {
    let mut s = Dyadic::zero();
    for i in 0..3 {
        let ni = Dyadic::from_bits(pf, n[i]).expect("finite normal");
        s = s.add(&ni.mul(&v[i].sub(&c[i])));
    }
    s
}

fn fixed_directions() -> Vec<[f64; 3]> {
    let mut v = Vec::new();
    for x in [-1.0, 0.0, 1.0] {
        for y in [-1.0, 0.0, 1.0] {
            for z in [-1.0f64, 0.0, 1.0] {
                let nz = (x != 0.0) as u32 + (y != 0.0) as u32 + (z != 0.0) as u32;
                if nz >= 2 {
                    v.push([x, y, z]);
                }
            }
        }
    }
    v
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

fn to_f64(pf: FloatFormat, b: u64) -> f64 {
    f64::from_bits(convert(
        pf,
        FloatFormat::BINARY64,
        b,
        RoundingMode::NearestEven,
    ))
}

fn octant(pf: FloatFormat, n: &[u64; 3]) -> usize {
    (0..3)
        .map(|i| ((n[i] & pf.sign_bit() != 0) as usize) << i)
        .sum()
}

/// Fraction of grid sample points of the box strictly on the empty side.
fn score(pf: FloatFormat, p: &Plane, min: &[f32; 3], max: &[f32; 3], samples: usize) -> f64 {
    let n = p.n.map(|b| to_f64(pf, b));
    let w = to_f64(pf, p.w);
    let c = [0, 1, 2].map(|i| (min[i] as f64 + max[i] as f64) / 2.0);
    let s = samples.max(1);
    let coord = |i: usize, j: usize| {
        min[i] as f64 + (max[i] as f64 - min[i] as f64) * (j as f64 + 0.5) / s as f64 - c[i]
    };
    let mut cut = 0usize;
    for a in 0..s {
        let ha = n[0] * coord(0, a);
        for b in 0..s {
            let hb = ha + n[1] * coord(1, b);
            for k in 0..s {
                if hb + n[2] * coord(2, k) > w {
                    cut += 1;
                }
            }
        }
    }
    cut as f64 / (s * s * s) as f64
}

/// Keeps the best plane per octant, then the `k` best; drops useless ones.
fn select(
    pf: FloatFormat,
    cands: Vec<Plane>,
    min: &[f32; 3],
    max: &[f32; 3],
    params: &BuildParams,
) -> (Vec<Plane>, Vec<f64>) {
    let mut best: [Option<(f64, Plane)>; 8] = [None; 8];
    for p in cands {
        let sc = score(pf, &p, min, max, params.samples);
        if sc <= 0.0 {
            continue;
        }
        let o = octant(pf, &p.n);
        if best[o].is_none_or(|(b, _)| sc > b) {
            best[o] = Some((sc, p));
        }
    }
    let mut v: Vec<(f64, Plane)> = best.into_iter().flatten().collect();
    v.sort_by(|a, b| b.0.total_cmp(&a.0));
    v.truncate(params.k);
    (
        v.iter().map(|x| x.1).collect(),
        v.iter().map(|x| x.0).collect(),
    )
}

/// Places up to `params.k` planes on every node of `bvh`; panics with
/// [`try_build_planes`]'s message on a mesh with a non-finite vertex.
pub fn build_planes(mesh: &Mesh, bvh: &Bvh, params: &BuildParams) -> CullPlanes {
    try_build_planes(mesh, bvh, params).unwrap_or_else(|e| panic!("cull-plane builder: {e}"))
}

/// Places up to `params.k` planes on every node of `bvh`, or `Err` naming the
/// first vertex of `mesh` with a NaN or infinite coordinate (the exact
/// arithmetic has no value for it) — see [`Mesh::check_finite`].
pub fn try_build_planes(
    mesh: &Mesh,
    bvh: &Bvh,
    params: &BuildParams,
) -> Result<CullPlanes, String> {
    mesh.check_finite()?;
    let pf = params.plane;
    let nn = bvh.nodes.len();
    let mut planes: Vec<Vec<Plane>> = vec![Vec::new(); nn];
    let mut scores: Vec<Vec<f64>> = vec![Vec::new(); nn];
    let dirs = fixed_directions();
    let fit = |n: [u64; 3], bound: Dyadic| -> Option<Plane> {
        let w = bound.round_to(pf, RoundingMode::Up);
        (w & !pf.sign_bit() != pf.inf(false)).then_some(Plane { n, w })
    };
    for id in (0..nn).rev() {
        let node = bvh.nodes[id];
        let c = centroid(&node.min, &node.max);
        let mut cands = Vec::new();
        match node.kind {
            NodeKind::Leaf { .. } => {
                let tris = bvh.leaf_tris(id);
                let mut verts: Vec<u32> = tris
                    .iter()
                    .flat_map(|&t| mesh.triangles[t as usize])
                    .collect();
                verts.sort_unstable();
                verts.dedup();
                let vd: Vec<[Dyadic; 3]> = verts
                    .iter()
                    .map(|&v| mesh.vertices[v as usize].map(Dyadic::from_f32))
                    .collect();
                let vf: Vec<[f64; 3]> = verts
                    .iter()
                    .map(|&v| mesh.vertices[v as usize].map(|x| x as f64))
                    .collect();
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
                for n in normals {
                    let nq = quantise(pf, n);
                    if nq.iter().all(|&b| b & !pf.sign_bit() == 0) {
                        continue;
                    }
                    // the exact maximum: f64 picks the candidates, dyadic decides
                    let nf = nq.map(|b| to_f64(pf, b));
                    let h: Vec<f64> = vf
                        .iter()
                        .map(|v| nf[0] * v[0] + nf[1] * v[1] + nf[2] * v[2])
                        .collect();
                    let hmax = h.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                    let tol = 1e-6
                        * (1.0
                            + vf.iter()
                                .map(|v| v[0].abs() + v[1].abs() + v[2].abs())
                                .fold(0.0, f64::max));
                    let mut bound: Option<Dyadic> = None;
                    for (j, v) in vd.iter().enumerate() {
                        if h[j] >= hmax - tol {
                            let hv = height(pf, &nq, v, &c);
                            if bound.as_ref().is_none_or(|b| hv.cmp(b).is_gt()) {
                                bound = Some(hv);
                            }
                        }
                    }
                    if let Some(p) = bound.and_then(|b| fit(nq, b)) {
                        cands.push(p);
                    }
                }
            }
            NodeKind::Inner { left, right } => {
                for (from, other) in [
                    (left as usize, right as usize),
                    (right as usize, left as usize),
                ] {
                    let cf = centroid(&bvh.nodes[from].min, &bvh.nodes[from].max);
                    let ob = bvh.nodes[other];
                    for p in &planes[from] {
                        let wf = Dyadic::from_bits(pf, p.w).expect("finite distance");
                        let mut bound = wf.add(&height(pf, &p.n, &cf, &c));
                        for corner in 0..8 {
                            let v = [0, 1, 2].map(|i| {
                                Dyadic::from_f32(if corner >> i & 1 == 1 {
                                    ob.max[i]
                                } else {
                                    ob.min[i]
                                })
                            });
                            let hv = height(pf, &p.n, &v, &c);
                            if hv.cmp(&bound).is_gt() {
                                bound = hv;
                            }
                        }
                        if let Some(q) = fit(p.n, bound) {
                            cands.push(q);
                        }
                    }
                }
            }
        }
        let (p, s) = select(pf, cands, &node.min, &node.max, params);
        planes[id] = p;
        scores[id] = s;
    }
    Ok(CullPlanes { planes, scores })
}
