//! The two-level acceleration structure: one bottom-level BVH per mesh (binned
//! SAH, with cull planes placed by `golden_model::cull::builder`), one top-level
//! BVH over the instances' world boxes (binned SAH, one instance per leaf).
//!
//! Both levels use `golden_model::cull::bvh::Bvh` (parent before children,
//! root 0), so the cull-plane builder runs on our SAH trees unchanged.
//!
//! Boxes are padded outward by a relative 2⁻²⁰ (bottom level) so that a hit the
//! f64 triangle test reports always lies inside every box above it, whatever
//! box tester is used; this makes "identical image with exact box tests" a
//! property of the construction, not of luck at grazing rays. World boxes of
//! instances are padded by 2⁻¹⁶ relative to their size and translation, which
//! covers the rounding of the transform unit (model-space rays are computed by
//! it, world-space boxes are not).

use crate::scene::{builder_inverse, forward_affine, Scene};
use glam::{DAffine3, DMat3, DVec3, Vec3};
use golden_model::cull::builder::{build_planes, BuildParams, CullPlanes};
use golden_model::cull::bvh::{Bvh, Mesh, Node, NodeKind};
use golden_model::float::{convert, FloatFormat, RoundingMode};
use std::time::{Duration, Instant};

/// Planes per node and their format (the cull unit's defaults, `docs/cull.md`).
pub const PLANES_K: usize = 4;
/// Plane format: binary16.
pub const PLANE_FMT: FloatFormat = FloatFormat::BINARY16;

const BINS: usize = 16;

/// f32 at or below `v`.
pub fn f32_down(v: f64) -> f32 {
    let x = v as f32;
    if x as f64 > v {
        x.next_down()
    } else {
        x
    }
}

/// f32 at or above `v`.
pub fn f32_up(v: f64) -> f32 {
    let x = v as f32;
    if (x as f64) < v {
        x.next_up()
    } else {
        x
    }
}

/// The box `[lo, hi]` grown by `(max(|lo|, |hi|) + (hi − lo))·rel + extra` on
/// each axis (in f64), rounded outward to f32.
fn pad_box(lo: Vec3, hi: Vec3, rel: f64, extra: f64) -> ([f32; 3], [f32; 3]) {
    let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
    let p = (lo.abs().max(hi.abs()) + (hi - lo)) * rel + extra;
    (
        (lo - p).to_array().map(f32_down),
        (hi + p).to_array().map(f32_up),
    )
}

/// The centre of the box `[lo, hi]`, in f64 rounded to f32.
pub(crate) fn centre(lo: Vec3, hi: Vec3) -> Vec3 {
    ((lo.as_dvec3() + hi.as_dvec3()) / 2.0).as_vec3()
}

#[derive(Clone, Copy)]
struct Prim {
    lo: Vec3,
    hi: Vec3,
    c: Vec3,
}

/// Surface area of the box `[lo, hi]` in f64 (an empty axis counts 0): the
/// SAH cost of binary and wide nodes alike.
pub(crate) fn area(lo: Vec3, hi: Vec3) -> f64 {
    let e = (hi.as_dvec3() - lo.as_dvec3()).max(DVec3::ZERO);
    2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
}

/// Grows the box `a` by the box `[lo, hi]`. The running bound is min/max's
/// second operand: glam keeps it on ties (±0) and when the new value is NaN.
fn merge(a: &mut (Vec3, Vec3), lo: Vec3, hi: Vec3) {
    *a = (lo.min(a.0), hi.max(a.1));
}

const EMPTY: (Vec3, Vec3) = (Vec3::INFINITY, Vec3::NEG_INFINITY);

/// Binned SAH build over primitive boxes; leaves of at most `max_leaf`
/// primitives (split whenever SAH says so and always above `max_leaf`).
fn sah_build(prims: &[Prim], max_leaf: usize, pad_rel: f64) -> Bvh {
    let mut order: Vec<u32> = (0..prims.len() as u32).collect();
    let mut bvh = Bvh {
        nodes: Vec::new(),
        tri_order: Vec::new(),
    };
    if prims.is_empty() {
        return bvh;
    }
    split(&mut bvh, prims, &mut order, 0, max_leaf.max(1), pad_rel);
    bvh.tri_order = order;
    bvh
}

fn split(
    bvh: &mut Bvh,
    prims: &[Prim],
    order: &mut [u32],
    first: usize,
    max_leaf: usize,
    pad_rel: f64,
) -> u32 {
    let me = bvh.nodes.len() as u32;
    let mut bx = EMPTY;
    let mut cb = EMPTY;
    for &p in order.iter() {
        let p = &prims[p as usize];
        merge(&mut bx, p.lo, p.hi);
        merge(&mut cb, p.c, p.c);
    }
    let (lo, hi) = pad_box(bx.0, bx.1, pad_rel, 0.0);
    bvh.nodes.push(Node {
        min: lo,
        max: hi,
        kind: NodeKind::Leaf {
            first: first as u32,
            count: order.len() as u32,
        },
    });
    let n = order.len();
    if n <= 1 {
        return me;
    }
    // best binned SAH split over the three axes
    let parent_area = area(bx.0, bx.1).max(1e-300);
    let mut best: Option<(f64, usize, f32, f32, usize)> = None; // cost, axis, cmin, scale, bin
    for axis in 0..3 {
        let (cmin, cmax) = (cb.0[axis], cb.1[axis]);
        if cmax <= cmin {
            continue;
        }
        let scale = BINS as f32 / (cmax - cmin);
        if let Some((sah, bin)) = cheapest_bin(prims, order, axis, cmin, scale) {
            let cost = 1.0 + sah / parent_area;
            if best.is_none_or(|(c, ..)| cost < c) {
                best = Some((cost, axis, cmin, scale, bin));
            }
        }
    }
    let mid = match best {
        Some((cost, axis, cmin, scale, best_bin)) if cost < n as f64 || n > max_leaf => {
            // partition by the chosen bin boundary
            let mut i = 0;
            for j in 0..n {
                let c = prims[order[j] as usize].c[axis];
                let b = (((c - cmin) * scale) as usize).min(BINS - 1);
                if b <= best_bin {
                    order.swap(i, j);
                    i += 1;
                }
            }
            if i == 0 || i == n {
                n / 2
            } else {
                i
            }
        }
        None if n > max_leaf => {
            // all centroids coincide: split in the middle of the list
            n / 2
        }
        _ => return me,
    };
    let (l, r) = order.split_at_mut(mid);
    let left = split(bvh, prims, l, first, max_leaf, pad_rel);
    let right = split(bvh, prims, r, first + mid, max_leaf, pad_rel);
    bvh.nodes[me as usize].kind = NodeKind::Inner { left, right };
    me
}

/// The cheapest binned SAH partition of `order` on `axis` (bins of width
/// `1 / scale` from `cmin`): its cost `area_l · n_l + area_r · n_r` and the
/// last bin on its left side (the first such bin among equal costs); `None`
/// when every partition leaves a side empty.
fn cheapest_bin(
    prims: &[Prim],
    order: &[u32],
    axis: usize,
    cmin: f32,
    scale: f32,
) -> Option<(f64, usize)> {
    let mut bins = [(EMPTY, 0usize); BINS];
    for &p in order {
        let p = &prims[p as usize];
        let b = (((p.c[axis] - cmin) * scale) as usize).min(BINS - 1);
        merge(&mut bins[b].0, p.lo, p.hi);
        bins[b].1 += 1;
    }
    let mut right = [(0.0f64, 0usize); BINS];
    let mut acc = (EMPTY, 0usize);
    for b in (1..BINS).rev() {
        merge(&mut acc.0, bins[b].0 .0, bins[b].0 .1);
        acc.1 += bins[b].1;
        right[b] = (area(acc.0 .0, acc.0 .1), acc.1);
    }
    let mut left = (EMPTY, 0usize);
    let mut best: Option<(f64, usize)> = None;
    for b in 0..BINS - 1 {
        merge(&mut left.0, bins[b].0 .0, bins[b].0 .1);
        left.1 += bins[b].1;
        let (ra, rn) = right[b + 1];
        if left.1 == 0 || rn == 0 {
            continue;
        }
        let cost = area(left.0 .0, left.0 .1) * left.1 as f64 + ra * rn as f64;
        if best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, b));
        }
    }
    best
}

/// A bottom-level tree: BVH over one mesh, cull planes in the shared-normal
/// layout (normals with the parent, a distance per child, `docs/cull.md`).
#[derive(Debug, Clone)]
pub struct Blas {
    /// the SAH tree (padded boxes)
    pub bvh: Bvh,
    /// up to [`PLANES_K`] shared normals per inner node (binary16), a
    /// distance per node and normal of its parent
    pub planes: CullPlanes,
}

/// An instance as the traversal needs it.
#[derive(Debug, Clone)]
pub struct InstanceXf {
    /// mesh / BLAS index
    pub mesh: usize,
    /// forward transform `[R | T]` (the binary32 entries, in f64)
    pub fwd: DAffine3,
    /// `R⁻¹`, row-major binary32 bits: the exact inverse rounded once
    /// (`scene_builder_inverse`, the transform unit's `inverse=pre`)
    pub inv_bits: [u64; 9],
    /// `T`, binary32 bits
    pub t_bits: [u64; 3],
    /// `R⁻ᵀ` in f64, for normals (shading only)
    pub normal_m: DMat3,
    /// diffuse albedo
    pub color: Vec3,
    /// diagonal of the instance's world box (for ray offsets)
    pub size: f32,
}

/// Build times, for the report.
#[derive(Debug, Clone, Default)]
pub struct BuildTimes {
    /// SAH trees of all meshes
    pub blas_sah: Duration,
    /// cull-plane placement of all meshes
    pub planes: Duration,
    /// instance inverses, world boxes and the top-level tree
    pub tlas: Duration,
}

/// The whole acceleration structure.
#[derive(Debug, Clone)]
pub struct Accel {
    /// one per mesh
    pub blas: Vec<Blas>,
    /// top-level tree; `tri_order` holds instance indices
    pub tlas: Bvh,
    /// per instance
    pub instances: Vec<InstanceXf>,
    /// build times
    pub times: BuildTimes,
    /// scene scale: length of the world box diagonal
    pub scale: f32,
}

/// Bottom-level SAH tree over a mesh (leaves of at most `max_leaf` triangles).
pub fn build_blas_bvh(mesh: &Mesh, max_leaf: usize) -> Bvh {
    let prims: Vec<Prim> = (0..mesh.triangles.len() as u32)
        .map(|t| {
            let [a, b, c] = mesh.corners(t).map(Vec3::from);
            // the earlier corner wins ties (±0), as min/max keep their second operand
            let (lo, hi) = (c.min(b.min(a)), c.max(b.max(a)));
            Prim {
                lo,
                hi,
                c: centre(lo, hi),
            }
        })
        .collect();
    sah_build(&prims, max_leaf, 1.0 / (1u64 << 20) as f64)
}

/// Widens each plane's distance by a relative 2⁻²⁰ of the size of the box it
/// is measured from (its parent's; the root's own), rounded up in the plane
/// format, so the f64 triangle test's last-bit hits never fall on an empty
/// side. A distance that overflows becomes +∞, which the cull unit flags as
/// invalid and keeps (never a cull).
fn pad_planes(bvh: &Bvh, planes: &mut CullPlanes) {
    let mut reference = vec![0usize; bvh.nodes.len()];
    for (id, n) in bvh.nodes.iter().enumerate() {
        if let NodeKind::Inner { left, right } = n.kind {
            reference[left as usize] = id;
            reference[right as usize] = id;
        }
    }
    for (id, ws) in planes.w.iter_mut().enumerate() {
        let n = bvh.nodes[reference[id]];
        let (lo, hi) = (Vec3::from(n.min).as_dvec3(), Vec3::from(n.max).as_dvec3());
        let size = ((hi - lo).abs() + hi.abs()).element_sum();
        for w in ws.iter_mut() {
            let v = f64::from_bits(convert(
                PLANE_FMT,
                FloatFormat::BINARY64,
                *w,
                RoundingMode::NearestEven,
            ));
            *w = convert(
                FloatFormat::BINARY64,
                PLANE_FMT,
                (v + size / (1u64 << 20) as f64).to_bits(),
                RoundingMode::Up,
            );
        }
    }
}

impl Accel {
    /// Builds every BLAS (SAH + planes, meshes in parallel) and the TLAS.
    pub fn build(scene: &Scene, with_planes: bool) -> Accel {
        use rayon::prelude::*;
        let mut times = BuildTimes::default();
        let t0 = Instant::now();
        let bvhs: Vec<Bvh> = scene
            .meshes
            .par_iter()
            .map(|(_, m)| build_blas_bvh(m, 4))
            .collect();
        times.blas_sah = t0.elapsed();
        let t1 = Instant::now();
        let planes: Vec<CullPlanes> = scene
            .meshes
            .par_iter()
            .zip(&bvhs)
            .map(|((_, m), bvh)| {
                if !with_planes {
                    return CullPlanes {
                        normals: vec![Vec::new(); bvh.nodes.len()],
                        w: vec![Vec::new(); bvh.nodes.len()],
                        scores: vec![Vec::new(); bvh.nodes.len()],
                        ..CullPlanes::default()
                    };
                }
                let mut p = build_planes(
                    m,
                    bvh,
                    &BuildParams {
                        plane: PLANE_FMT,
                        k: PLANES_K,
                        samples: 6,
                    },
                );
                pad_planes(bvh, &mut p);
                p
            })
            .collect();
        times.planes = t1.elapsed();
        let blas: Vec<Blas> = bvhs
            .into_iter()
            .zip(planes)
            .map(|(bvh, planes)| Blas { bvh, planes })
            .collect();
        let t2 = Instant::now();
        let b32 = |x: f32| x.to_bits() as u64;
        let mut instances = Vec::new();
        let mut prims = Vec::new();
        let mut world = EMPTY;
        for inst in &scene.instances {
            let f = inst.transform;
            let inv_bits = builder_inverse(&f);
            let inv: [f64; 9] = inv_bits.map(|b| f32::from_bits(b as u32) as f64);
            // the row-major R⁻¹ read as columns is R⁻ᵀ
            let normal_m = DMat3::from_cols_array(&inv);
            let fwd = forward_affine(&f);
            let root = blas[inst.mesh].bvh.nodes[0];
            let (rmin, rmax) = (
                Vec3::from(root.min).as_dvec3(),
                Vec3::from(root.max).as_dvec3(),
            );
            let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for c in 0..8 {
                let corner = DVec3::select(
                    glam::BVec3::new(c & 1 == 1, c & 2 == 2, c & 4 == 4),
                    rmax,
                    rmin,
                );
                let w = fwd.transform_point3(corner);
                (lo, hi) = (w.min(lo), w.max(hi));
            }
            let p =
                ((hi - lo) + fwd.translation.abs() + lo.abs().max(hi.abs())) / (1u64 << 16) as f64;
            let (blo, bhi) = (
                Vec3::from((lo - p).to_array().map(f32_down)),
                Vec3::from((hi + p).to_array().map(f32_up)),
            );
            merge(&mut world, blo, bhi);
            prims.push(Prim {
                lo: blo,
                hi: bhi,
                c: centre(blo, bhi),
            });
            instances.push(InstanceXf {
                mesh: inst.mesh,
                fwd,
                inv_bits,
                t_bits: [0, 1, 2].map(|i| b32(f[i][3])),
                normal_m,
                color: inst.color.into(),
                size: (hi - lo).length() as f32,
            });
        }
        let tlas = sah_build(&prims, 1, 0.0);
        times.tlas = t2.elapsed();
        let scale = (world.1 - world.0).as_dvec3().length() as f32;
        Accel {
            blas,
            tlas,
            instances,
            times,
            scale,
        }
    }

    /// Nodes and planes, for the report.
    pub fn describe(&self) -> String {
        let nodes: usize = self.blas.iter().map(|b| b.bvh.nodes.len()).sum();
        let planes: usize = self.blas.iter().map(|b| b.planes.plane_count()).sum();
        format!(
            "{} BLAS ({} nodes, {} cull planes), TLAS {} nodes over {} instances; build: SAH {:.3} s, planes {:.3} s, TLAS {:.3} s",
            self.blas.len(),
            nodes,
            planes,
            self.tlas.nodes.len(),
            self.instances.len(),
            self.times.blas_sah.as_secs_f64(),
            self.times.planes.as_secs_f64(),
            self.times.tlas.as_secs_f64()
        )
    }
}
