//! Hybrid rasterisation + ray tracing with depth-based ray culling (seed 002).
//!
//! The raster pass finds the visible surface of each sample (one sample per
//! pixel, at its centre): coverage and depth of a triangle at a sample are the
//! edge functions and `t` of the camera ray through the sample
//! ([`crate::trace::intersect`], i.e. homogeneous 2D rasterisation), the depth
//! test is LESS on `(t, instance, triangle)`, so ties are broken by the
//! primitive id and the final surface does not depend on the primitive order.
//!
//! **Asynchronous mode** ([`render_async`]): primitives are rasterised in a
//! given order; whenever a primitive becomes the visible surface of a sample,
//! the sample's generation (3 bits, FIG. 14 layout `pixel 26 | sample 3 |
//! generation 3`) is incremented and the surface is shaded at once: it emits
//! its shadow and AO rays, each tagged with the sample, the generation and the
//! depth of the emitting surface. After each primitive a ray processor takes
//! up to `rays_per_step` rays from the queue and
//!
//! 1. **tile stage** (claim 1): culls a ray whose depth lies outside its
//!    8×8 tile's current `[min, max]` depth range (only `depth > max` can occur
//!    with a LESS test; both sides are checked), no per-sample lookup;
//! 2. **sample stage** (claims 5-8): culls a ray whose sample is now closer
//!    than the ray's depth, or, at equal depth, whose generation differs
//!    (a tie broken by primitive id);
//! 3. traces the survivors (bundled, through the golden models);
//! 4. **contribution check** (the description's verification logic): a result
//!    is stored only if the ray's emitting surface (full instance/triangle id,
//!    not the wrapping 3-bit generation) is still the sample's surface; a later
//!    change of surface discards the sample's stored results.
//!
//! When all primitives are done, the queue is drained the same way and each
//! sample combines the results of its final surface's rays in emission order.
//! **Synchronous mode** ([`render_sync`]): rasterise everything, shade the
//! final surfaces, trace, combine. Both produce the same bits for every
//! primitive order and interleaving (test `hybrid_identical.rs`).

use crate::bvh::Accel;
use crate::render::{
    combine, emit, emit_into, face_normal64, make_surface, trace_secondary, Cam, Frame, SecRay,
    Surface,
};
use crate::scene::Scene;
use crate::stats::Stats;
use crate::tester::BoxTester;
use crate::trace::{intersect, TraceOpts, Tracer, NONE};
use std::collections::VecDeque;
use std::time::Instant;

/// Tile edge (pixels) of the depth ranges.
pub const TILE: u32 = 8;
/// Generation bits of a ray id (FIG. 14).
pub const GEN_BITS: u32 = 3;

/// A triangle in world space with its identity and material.
#[derive(Debug, Clone, Copy)]
pub struct WorldTri {
    /// vertices
    pub v: [[f32; 3]; 3],
    /// (instance, triangle)
    pub key: (u32, u32),
    /// albedo
    pub color: [f32; 3],
    /// instance world size
    pub size: f32,
}

/// Every instance's triangles in world space (forward transform in f64, rounded to f32).
pub fn world_triangles(scene: &Scene, accel: &Accel) -> Vec<WorldTri> {
    let mut out = Vec::new();
    for (i, x) in accel.instances.iter().enumerate() {
        let m = &scene.meshes[x.mesh].1;
        let f = x.fwd;
        let xf = |p: [f32; 3]| {
            [0, 1, 2].map(|r| {
                ((0..3).map(|c| f[r][c] as f64 * p[c] as f64).sum::<f64>() + f[r][3] as f64) as f32
            })
        };
        for t in 0..m.triangles.len() as u32 {
            out.push(WorldTri {
                v: m.corners(t).map(xf),
                key: (i as u32, t),
                color: x.color,
                size: x.size,
            });
        }
    }
    out
}

/// The samples a triangle covers and their depth `t`.
pub fn rasterize(cam: &Cam, tri: &WorldTri, w: u32, h: u32) -> Vec<(u32, f64)> {
    let (fw, rt, up, tan) = cam.basis();
    let aspect = w as f64 / h as f64;
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let mut behind = false;
    for p in &tri.v {
        let v = [0, 1, 2].map(|i| p[i] as f64 - cam.o[i] as f64);
        let dot = |a: [f32; 3]| (0..3).map(|i| v[i] * a[i] as f64).sum::<f64>();
        let z = dot(fw);
        if z <= 1e-6 {
            behind = true;
            continue;
        }
        let x = dot(rt) / (z * tan * aspect);
        let y = dot(up) / (z * tan);
        let px = (x + 1.0) / 2.0 * w as f64 - 0.5;
        let py = (1.0 - y) / 2.0 * h as f64 - 0.5;
        lo = [lo[0].min(px), lo[1].min(py)];
        hi = [hi[0].max(px), hi[1].max(py)];
    }
    let (x0, x1, y0, y1) = if behind {
        // crosses the eye plane: scan the whole screen (coverage decides)
        (0, w as i64 - 1, 0, h as i64 - 1)
    } else {
        (
            (lo[0].floor() as i64 - 1).max(0),
            (hi[0].ceil() as i64 + 1).min(w as i64 - 1),
            (lo[1].floor() as i64 - 1).max(0),
            (hi[1].ceil() as i64 + 1).min(h as i64 - 1),
        )
    };
    let mut out = Vec::new();
    let o = cam.o.map(|x| x as f64);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let d = cam.dir(x as u32, y as u32).map(|c| c as f64);
            if let Some(t) = intersect(&o, &d, &tri.v, f64::INFINITY) {
                out.push((y as u32 * w + x as u32, t));
            }
        }
    }
    out
}

fn surface(cam: &Cam, tri: &WorldTri, pix: u32, w: u32, t: f64) -> Surface {
    let d = cam.dir(pix % w, pix / w);
    let n = face_normal64(&tri.v);
    let pos = [0, 1, 2].map(|i| cam.o[i] as f64 + t * d[i] as f64);
    make_surface(pos, n, d, tri.color, tri.size, tri.key)
}

/// Counts of the asynchronous path.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HybridCounts {
    /// primitives rasterised
    pub primitives: u64,
    /// times a sample's visible surface changed (each one shades and emits)
    pub surface_changes: u64,
    /// rays emitted by shading
    pub emitted: u64,
    /// culled by the tile depth range (stage 1)
    pub culled_tile: u64,
    /// culled by the sample depth (stage 2)
    pub culled_depth: u64,
    /// culled by the generation id at equal depth (stage 2)
    pub culled_generation: u64,
    /// traced
    pub traced: u64,
    /// traced, but the result was rejected by the contribution check (stale)
    pub discarded: u64,
    /// results kept then dropped because the sample's surface changed later
    pub superseded: u64,
    /// rays whose results make the final image (= the synchronous render's ray count)
    pub used: u64,
}

/// Options of the asynchronous path.
#[derive(Debug, Clone)]
pub struct HybridOpts {
    /// order in which the primitives (indices into [`world_triangles`]) are rasterised
    pub order: Vec<usize>,
    /// rays the ray processor handles after each primitive (0: only at the end)
    pub rays_per_step: usize,
    /// primitives rasterised while a traced batch's results are in flight: the
    /// contribution check sees the depth buffer that many primitives after the
    /// cull did (0: the same one), as a ray unit with latency would
    pub result_latency: usize,
}

/// The sample's depth-buffer entry.
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: f64,
    key: (u32, u32),
    gen: u8,
}

struct QRay {
    /// pixel 26 | sample 3 | generation 3
    id: u32,
    depth: f64,
    key: (u32, u32),
    slot: usize,
    ray: SecRay,
}

/// Packs a ray id (FIG. 14): pixel 26 bits, sample 3, generation 3.
pub fn ray_id(pixel: u32, sample: u32, gen: u8) -> u32 {
    (pixel & 0x03FF_FFFF) << 6 | (sample & 7) << 3 | (gen as u32 & 7)
}

fn frame(w: u32, h: u32, bg: [f32; 3]) -> Frame {
    let n = (w * h) as usize;
    Frame {
        w,
        h,
        color: vec![bg; n],
        ids: vec![(NONE, NONE); n],
        t: vec![0; n],
        stats: Stats::default(),
        time: Default::default(),
    }
}

/// Synchronous reference: rasterise everything, shade the final surfaces, trace, combine.
pub fn render_sync(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn BoxTester,
    opts: TraceOpts,
    w: u32,
    h: u32,
) -> Frame {
    let start = Instant::now();
    let cam = Cam::new(scene, w, h);
    let tris = world_triangles(scene, accel);
    let mut depth: Vec<Option<(f64, (u32, u32), usize)>> = vec![None; (w * h) as usize];
    for (k, tri) in tris.iter().enumerate() {
        for (p, t) in rasterize(&cam, tri, w, h) {
            let cur = &mut depth[p as usize];
            if cur.is_none_or(|(ct, ck, _)| (t, tri.key) < (ct, ck)) {
                *cur = Some((t, tri.key, k));
            }
        }
    }
    let tracer = Tracer::new(scene, accel, tester, opts);
    let mut f = frame(w, h, scene.render.background);
    let mut sec = Vec::new();
    let mut owners = Vec::new();
    for (p, e) in depth.iter().enumerate() {
        if let Some((t, key, k)) = *e {
            let s = surface(&cam, &tris[k], p as u32, w, t);
            let first = sec.len();
            emit_into(scene, &s, p as u64, &mut sec);
            owners.push((p, s, first, sec.len() - first));
            f.ids[p] = key;
            f.t[p] = t.to_bits();
        }
    }
    let occ = trace_secondary(&tracer, accel.scale, &sec, &mut f.stats);
    for (p, s, first, n) in owners {
        f.color[p] = combine(scene, &s, &sec[first..first + n], &occ[first..first + n]);
    }
    f.time = start.elapsed();
    f
}

/// Asynchronous render with depth-based ray culling; returns the frame and the counts.
pub fn render_async(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn BoxTester,
    opts: TraceOpts,
    w: u32,
    h: u32,
    hopts: &HybridOpts,
) -> (Frame, HybridCounts) {
    let start = Instant::now();
    let cam = Cam::new(scene, w, h);
    let tris = world_triangles(scene, accel);
    let tracer = Tracer::new(scene, accel, tester, opts);
    let n = (w * h) as usize;
    let tw = w.div_ceil(TILE);
    let ntiles = (tw * h.div_ceil(TILE)) as usize;
    let tile_of = |p: usize| ((p as u32 / w) / TILE * tw + (p as u32 % w) / TILE) as usize;
    let mut samples: Vec<Option<Sample>> = vec![None; n];
    let mut surf: Vec<Option<Surface>> = vec![None; n];
    // per sample: the current surface's emitted rays and their results
    let mut emitted: Vec<Vec<SecRay>> = vec![Vec::new(); n];
    let mut results: Vec<Vec<Option<bool>>> = vec![Vec::new(); n];
    let mut tile_range: Vec<(f64, f64)> = vec![(f64::INFINITY, f64::INFINITY); ntiles];
    let mut queue: VecDeque<QRay> = VecDeque::new();
    let mut c = HybridCounts::default();
    let mut f = frame(w, h, scene.render.background);

    let update_tile = |tile: usize, samples: &[Option<Sample>], tile_range: &mut [(f64, f64)]| {
        let tx = (tile as u32 % tw) * TILE;
        let ty = (tile as u32 / tw) * TILE;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for y in ty..(ty + TILE).min(h) {
            for x in tx..(tx + TILE).min(w) {
                let d = samples[(y * w + x) as usize].map_or(f64::INFINITY, |s| s.t);
                lo = lo.min(d);
                hi = hi.max(d);
            }
        }
        tile_range[tile] = (lo, hi);
    };

    // the ray processor: cull, trace, check contributions
    let process = |limit: usize,
                   queue: &mut VecDeque<QRay>,
                   samples: &[Option<Sample>],
                   tile_range: &[(f64, f64)],
                   c: &mut HybridCounts,
                   st: &mut Stats|
     -> Vec<(QRay, bool)> {
        let mut batch = Vec::new();
        while batch.len() < limit {
            let Some(q) = queue.pop_front() else { break };
            let pix = (q.id >> 6) as usize;
            let (lo, hi) = tile_range[tile_of(pix)];
            if q.depth > hi || q.depth < lo {
                c.culled_tile += 1;
                continue;
            }
            let s = samples[pix].expect("a ray's sample has a surface");
            if s.t < q.depth {
                c.culled_depth += 1;
                continue;
            }
            if s.gen != (q.id & 7) as u8 {
                c.culled_generation += 1;
                continue;
            }
            batch.push(q);
        }
        if batch.is_empty() {
            return Vec::new();
        }
        c.traced += batch.len() as u64;
        let rays: Vec<SecRay> = batch.iter().map(|q| q.ray).collect();
        let occ = trace_secondary(&tracer, accel.scale, &rays, st);
        batch.into_iter().zip(occ).collect::<Vec<_>>()
    };
    // contribution check, when a batch's results arrive: the full surface id,
    // never the wrapping generation
    let check = |done: Vec<(QRay, bool)>,
                 samples: &[Option<Sample>],
                 results: &mut [Vec<Option<bool>>],
                 c: &mut HybridCounts| {
        for (q, o) in done {
            let pix = (q.id >> 6) as usize;
            if samples[pix].map(|s| s.key) == Some(q.key) {
                results[pix][q.slot] = Some(o);
            } else {
                c.discarded += 1;
            }
        }
    };
    // traced batches in flight: (primitive index at which they arrive, results)
    let mut in_flight: VecDeque<(usize, Vec<(QRay, bool)>)> = VecDeque::new();

    for (step, &k) in hopts.order.iter().enumerate() {
        while in_flight.front().is_some_and(|b| b.0 <= step) {
            let (_, done) = in_flight.pop_front().expect("front checked");
            check(done, &samples, &mut results, &mut c);
        }
        let tri = &tris[k];
        c.primitives += 1;
        let mut touched = Vec::new();
        for (p, t) in rasterize(&cam, tri, w, h) {
            let p = p as usize;
            let wins = samples[p].is_none_or(|s| (t, tri.key) < (s.t, s.key));
            if !wins {
                continue;
            }
            let gen = samples[p].map_or(0, |s| (s.gen + 1) & ((1 << GEN_BITS) - 1));
            if !results[p].is_empty() {
                c.superseded += results[p].iter().filter(|r| r.is_some()).count() as u64;
            }
            samples[p] = Some(Sample {
                t,
                key: tri.key,
                gen,
            });
            c.surface_changes += 1;
            // shade now: the surface emits its rays before geometry is complete
            let s = surface(&cam, tri, p as u32, w, t);
            let rays = emit(scene, &s, p as u64);
            results[p] = vec![None; rays.len()];
            for (slot, r) in rays.iter().enumerate() {
                queue.push_back(QRay {
                    id: ray_id(p as u32, 0, gen),
                    depth: t,
                    key: tri.key,
                    slot,
                    ray: *r,
                });
            }
            c.emitted += rays.len() as u64;
            emitted[p] = rays;
            surf[p] = Some(s);
            touched.push(tile_of(p));
        }
        touched.sort_unstable();
        touched.dedup();
        for tile in touched {
            update_tile(tile, &samples, &mut tile_range);
        }
        if hopts.rays_per_step > 0 {
            let done = process(
                hopts.rays_per_step,
                &mut queue,
                &samples,
                &tile_range,
                &mut c,
                &mut f.stats,
            );
            if hopts.result_latency == 0 {
                check(done, &samples, &mut results, &mut c);
            } else {
                in_flight.push_back((step + hopts.result_latency, done));
            }
        }
    }
    // geometry complete: the batches in flight arrive, then the queue drains
    for (_, done) in in_flight.drain(..) {
        check(done, &samples, &mut results, &mut c);
    }
    while !queue.is_empty() {
        let done = process(
            4096,
            &mut queue,
            &samples,
            &tile_range,
            &mut c,
            &mut f.stats,
        );
        check(done, &samples, &mut results, &mut c);
    }
    for p in 0..n {
        if let (Some(s), Some(sf)) = (samples[p], surf[p]) {
            let occ: Vec<bool> = results[p]
                .iter()
                .map(|r| r.expect("every ray of a final surface is traced"))
                .collect();
            c.used += occ.len() as u64;
            f.color[p] = combine(scene, &sf, &emitted[p], &occ);
            f.ids[p] = s.key;
            f.t[p] = s.t.to_bits();
        }
    }
    f.time = start.elapsed();
    (f, c)
}

/// The primitive orders the tests and the report use: as stored, reversed,
/// front to back, back to front (by the nearest vertex distance), and a
/// seeded shuffle.
pub fn orders(scene: &Scene, accel: &Accel, seed: u64) -> Vec<(&'static str, Vec<usize>)> {
    let tris = world_triangles(scene, accel);
    let n = tris.len();
    let fwd: Vec<usize> = (0..n).collect();
    let rev: Vec<usize> = (0..n).rev().collect();
    let cam = scene.camera.position;
    let dist = |t: &WorldTri| {
        t.v.iter()
            .map(|p| {
                (0..3)
                    .map(|i| (p[i] - cam[i]) as f64 * (p[i] - cam[i]) as f64)
                    .sum::<f64>()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut f2b = fwd.clone();
    f2b.sort_by(|&a, &b| dist(&tris[a]).total_cmp(&dist(&tris[b])));
    let b2f: Vec<usize> = f2b.iter().rev().copied().collect();
    let mut sh = fwd.clone();
    for i in (1..n).rev() {
        let j = (crate::mesh::mix(seed ^ i as u64) % (i as u64 + 1)) as usize;
        sh.swap(i, j);
    }
    vec![
        ("stored", fwd),
        ("reversed", rev),
        ("front-to-back", f2b),
        ("back-to-front", b2f),
        ("shuffled", sh),
    ]
}
