//! Hybrid rasterisation + ray tracing with depth-based ray culling (seed 002),
//! every cull decision by the golden model of the `raycull` unit
//! (`golden_model::raycull`, docs/raycull.md).
//!
//! The raster pass finds the visible surface of each sample (one sample per
//! pixel, at its centre): coverage and `t` of a triangle at a sample are the
//! edge functions and `t` of the camera ray through the sample
//! ([`crate::trace::intersect`], i.e. homogeneous 2D rasterisation); the
//! depth is the **quantised code** of its view-space depth between the scene's
//! near and far planes ([`depth_planes`], [`golden_model::raycull::quantize`];
//! unorm16, unorm24 or binary32), and the depth test is LESS on `(code,
//! primitive index)`, so ties are broken by the primitive and the final
//! surface does not depend on the primitive order.
//!
//! **Asynchronous mode** ([`render_async`]): primitives are rasterised in a
//! given order into one [`golden_model::raycull::TileBuffer`] per 8×8 tile;
//! whenever a primitive becomes the visible surface of a sample, the sample's
//! generation (3 bits, FIG. 14 layout `pixel 26 | sample 3 | generation 3`) is
//! incremented and the surface is shaded at once: it emits its shadow and AO
//! rays, each tagged with the depth code, the generation and the primitive.
//! After each primitive a ray processor takes up to `rays_per_step` rays from
//! the queue, in groups of up to G consecutive rays of one tile, and asks the
//! unit: stage 1 (tile range, per ray and per group), stage 2 (sample depth,
//! and generation at equal depth); it traces the survivors (bundled, through
//! the golden models); when a result arrives the unit's **contribution
//! check** (full primitive id and generation of the sample then) decides
//! whether it is stored; a later change of surface discards the sample's
//! stored results.
//!
//! When all primitives are done, the queue is drained the same way and each
//! sample combines the results of its final surface's rays in emission order.
//! **Synchronous mode** ([`render_sync`]): rasterise everything (the same
//! codes), shade the final surfaces, trace, combine. Both produce the same bits
//! for every primitive order and interleaving (tests `hybrid_identical.rs`,
//! `hybrid_rtl.rs`). [`render_async_with`] takes any answerer for the unit's
//! transactions (`crate::hybrid_rtl`: the Verilated unit).

use crate::bvh::Accel;
use crate::render::{
    combine, emit, emit_into, face_normal64, make_surface, trace_secondary, Cam, Frame, SecRay,
    Surface,
};
use crate::scene::Scene;
use crate::stats::Stats;
use crate::tester::BoxTester;
use crate::trace::{intersect, TraceOpts, Tracer, NONE};
use glam::Vec3;
use golden_model::raycull::{
    cull, quantize, Compare, Config, CullIn, CullOut, DepthFormat, RayTag, Slot, TileBuffer,
};
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
    pub color: Vec3,
    /// instance world size
    pub size: f32,
}

/// Every instance's triangles in world space (forward transform in f64, rounded to f32).
pub fn world_triangles(scene: &Scene, accel: &Accel) -> Vec<WorldTri> {
    let mut out = Vec::new();
    for (i, x) in accel.instances.iter().enumerate() {
        let m = &scene.meshes[x.mesh].1;
        let xf = |p: [f32; 3]| {
            x.fwd
                .transform_point3(Vec3::from(p).as_dvec3())
                .as_vec3()
                .to_array()
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
        let v = Vec3::from(*p).as_dvec3() - cam.o.as_dvec3();
        let dot = |a: Vec3| v.dot(a.as_dvec3());
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
    let o = cam.o.as_dvec3();
    for y in y0..=y1 {
        for x in x0..=x1 {
            let d = cam.dir(x as u32, y as u32).as_dvec3();
            if let Some(t) = intersect(o, d, &tri.v, f64::INFINITY) {
                out.push((y as u32 * w + x as u32, t));
            }
        }
    }
    out
}

fn surface(cam: &Cam, tri: &WorldTri, pix: u32, w: u32, t: f64) -> Surface {
    let d = cam.dir(pix % w, pix / w);
    let pos = cam.o.as_dvec3() + d.as_dvec3() * t;
    make_surface(pos, face_normal64(&tri.v), d, tri.color, tri.size, tri.key)
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
    /// groups of rays culled whole by their depth range against the tile's
    pub culled_groups: u64,
    /// rays in those groups
    pub culled_group_rays: u64,
    /// traced
    pub traced: u64,
    /// traced, but the result was rejected by the contribution check (stale)
    pub discarded: u64,
    /// results kept then dropped because the sample's surface changed later
    pub superseded: u64,
    /// rays whose results make the final image (= the synchronous render's ray count)
    pub used: u64,
    /// transactions of the ray-cull unit (cull groups and contribution checks)
    pub unit_calls: u64,
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
    /// depth code format of the raster and the ray-cull unit
    pub depth: DepthFormat,
    /// rays per cull group G (consecutive queued rays of one tile)
    pub group: usize,
    /// the culling switch (off: every ray is traced, the contribution check still runs)
    pub cull: bool,
}

impl Default for HybridOpts {
    fn default() -> Self {
        HybridOpts {
            order: Vec::new(),
            rays_per_step: 64,
            result_latency: 0,
            depth: DepthFormat::Unorm24,
            group: 4,
            cull: true,
        }
    }
}

/// The near and far planes of the depth codes: `far` is 1.01 × the largest
/// view-space depth of any triangle vertex, `near = far / 4096` (fragments
/// outside are clipped, in the synchronous render too).
pub fn depth_planes(cam: &Cam, tris: &[WorldTri]) -> (f64, f64) {
    let (fw, ..) = cam.basis();
    let mut far: f64 = 1e-3;
    for t in tris {
        for p in &t.v {
            let z = (Vec3::from(*p).as_dvec3() - cam.o.as_dvec3()).dot(fw.as_dvec3());
            far = far.max(z);
        }
    }
    let far = far * 1.01;
    (far / 4096.0, far)
}

/// The depth code of the fragment at pixel `p` and camera-ray parameter `t`:
/// its view-space depth `z = t·(d·forward)` ([`golden_model::raycull::quantize`],
/// LESS: 0 at near, the far code at far); `None` when clipped.
fn depth_code(
    cam: &Cam,
    fmt: DepthFormat,
    planes: (f64, f64),
    p: u32,
    w: u32,
    t: f64,
) -> Option<u32> {
    let (fw, ..) = cam.basis();
    let d = cam.dir(p % w, p / w);
    let z = t * d.as_dvec3().dot(fw.as_dvec3());
    quantize(fmt, false, z, planes.0, planes.1)
}

/// The ray-cull unit's configuration the renderer uses: LESS, 3-bit
/// generations (FIG. 14), primitive ids wide enough for every triangle.
pub fn unit_config(depth: DepthFormat, group: usize, primitives: usize) -> Config {
    Config {
        format: depth,
        compare: Compare::Less,
        gen_bits: GEN_BITS,
        prim_bits: (usize::BITS - primitives.max(2).leading_zeros()).max(1),
        group: group.max(1),
    }
}

/// The sample's current surface (the unit's view is in its tile's buffer).
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: f64,
    key: (u32, u32),
}

struct QRay {
    /// pixel 26 | sample 3 | generation 3
    id: u32,
    tag: RayTag,
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
        color: vec![bg.into(); n],
        ids: vec![(NONE, NONE); n],
        t: vec![0; n],
        stats: Stats::default(),
        time: Default::default(),
    }
}

/// Synchronous reference: rasterise everything (LESS on the depth code, ties
/// to the smaller primitive index), shade the final surfaces, trace, combine.
pub fn render_sync(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn BoxTester,
    opts: TraceOpts,
    w: u32,
    h: u32,
    depth_format: DepthFormat,
) -> Frame {
    let start = Instant::now();
    let cam = Cam::new(scene, w, h);
    let tris = world_triangles(scene, accel);
    let planes = depth_planes(&cam, &tris);
    let mut depth: Vec<Option<(u32, usize, f64)>> = vec![None; (w * h) as usize];
    for (k, tri) in tris.iter().enumerate() {
        for (p, t) in rasterize(&cam, tri, w, h) {
            let Some(code) = depth_code(&cam, depth_format, planes, p, w, t) else {
                continue;
            };
            let cur = &mut depth[p as usize];
            if cur.is_none_or(|(c, ck, _)| (code, k) < (c, ck)) {
                *cur = Some((code, k, t));
            }
        }
    }
    let tracer = Tracer::new(scene, accel, tester, opts);
    let mut f = frame(w, h, scene.render.background);
    let mut sec = Vec::new();
    let mut owners = Vec::new();
    for (p, e) in depth.iter().enumerate() {
        if let Some((_, k, t)) = *e {
            let s = surface(&cam, &tris[k], p as u32, w, t);
            let first = sec.len();
            emit_into(scene, &s, p as u64, &mut sec);
            owners.push((p, s, first, sec.len() - first));
            f.ids[p] = tris[k].key;
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

/// Asynchronous render with depth-based ray culling, every cull and
/// contribution check answered by the golden model of the ray-cull unit;
/// returns the frame and the counts.
pub fn render_async(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn BoxTester,
    opts: TraceOpts,
    w: u32,
    h: u32,
    hopts: &HybridOpts,
) -> (Frame, HybridCounts) {
    let tris = world_triangles(scene, accel).len();
    let cfg = unit_config(hopts.depth, hopts.group, tris);
    render_async_with(scene, accel, tester, opts, w, h, hopts, &mut |x| {
        cull(&cfg, x)
    })
}

/// [`render_async`] with every ray-cull unit transaction (`G` slots, the
/// configuration of [`unit_config`]) answered by `unit`: the golden model, or
/// the Verilated unit's recorded outputs.
#[allow(clippy::too_many_arguments)]
pub fn render_async_with(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn BoxTester,
    opts: TraceOpts,
    w: u32,
    h: u32,
    hopts: &HybridOpts,
    unit: &mut dyn FnMut(&CullIn) -> CullOut,
) -> (Frame, HybridCounts) {
    let start = Instant::now();
    let cam = Cam::new(scene, w, h);
    let tris = world_triangles(scene, accel);
    let planes = depth_planes(&cam, &tris);
    let cfg = unit_config(hopts.depth, hopts.group, tris.len());
    let g = cfg.group;
    let tracer = Tracer::new(scene, accel, tester, opts);
    let n = (w * h) as usize;
    let tw = w.div_ceil(TILE);
    let ntiles = (tw * h.div_ceil(TILE)) as usize;
    // pixel -> (tile, index in the tile)
    let locate = |p: usize| {
        let (x, y) = (p as u32 % w, p as u32 / w);
        let (tx, ty) = (x / TILE, y / TILE);
        let tile_w = (w - tx * TILE).min(TILE);
        (
            (ty * tw + tx) as usize,
            ((y % TILE) * tile_w + x % TILE) as usize,
        )
    };
    let mut tiles: Vec<TileBuffer> = (0..ntiles as u32)
        .map(|t| {
            let (tx, ty) = (t % tw, t / tw);
            let size = (w - tx * TILE).min(TILE) * (h - ty * TILE).min(TILE);
            TileBuffer::new(cfg, size as usize)
        })
        .collect();
    let mut samples: Vec<Option<Sample>> = vec![None; n];
    let mut surf: Vec<Option<Surface>> = vec![None; n];
    // per sample: the current surface's emitted rays and their results
    let mut emitted: Vec<Vec<SecRay>> = vec![Vec::new(); n];
    let mut results: Vec<Vec<Option<bool>>> = vec![Vec::new(); n];
    let mut queue: VecDeque<QRay> = VecDeque::new();
    let mut c = HybridCounts::default();
    let mut f = frame(w, h, scene.render.background);

    let slot_of = |q: &QRay, tiles: &[TileBuffer]| {
        let (t, i) = locate((q.id >> 6) as usize);
        Slot {
            valid: true,
            ray: q.tag,
            sample: tiles[t].samples[i].state,
        }
    };
    let pad = |mut slots: Vec<Slot>| {
        slots.resize(g, Slot::default());
        slots
    };

    // the ray processor: cull (groups of up to G consecutive rays of one
    // tile), trace the survivors
    let process = |limit: usize,
                   queue: &mut VecDeque<QRay>,
                   tiles: &[TileBuffer],
                   c: &mut HybridCounts,
                   st: &mut Stats,
                   unit: &mut dyn FnMut(&CullIn) -> CullOut|
     -> Vec<(QRay, bool)> {
        let mut batch = Vec::new();
        let mut taken = 0;
        while taken < limit {
            let Some(first) = queue.front() else { break };
            let tile = locate((first.id >> 6) as usize).0;
            let mut group = Vec::new();
            while group.len() < g && taken < limit {
                match queue.front() {
                    Some(q) if locate((q.id >> 6) as usize).0 == tile => {
                        group.push(queue.pop_front().expect("front checked"));
                        taken += 1;
                    }
                    _ => break,
                }
            }
            let x = CullIn {
                enable: hopts.cull,
                tile: tiles[tile].range,
                slots: pad(group.iter().map(|q| slot_of(q, tiles)).collect()),
            };
            let out = unit(&x);
            c.unit_calls += 1;
            if out.group_cull {
                c.culled_groups += 1;
                c.culled_group_rays += group.len() as u64;
            }
            for (q, v) in group.into_iter().zip(&out.slots) {
                if v.tile_cull {
                    c.culled_tile += 1;
                } else if v.depth_cull {
                    c.culled_depth += 1;
                } else if v.generation_cull {
                    c.culled_generation += 1;
                } else {
                    batch.push(q);
                }
            }
        }
        if batch.is_empty() {
            return Vec::new();
        }
        c.traced += batch.len() as u64;
        let rays: Vec<SecRay> = batch.iter().map(|q| q.ray).collect();
        let occ = trace_secondary(&tracer, accel.scale, &rays, st);
        batch.into_iter().zip(occ).collect::<Vec<_>>()
    };
    // contribution check, when a batch's results arrive: the unit's `current`
    // with the sample's state then (full primitive id and generation)
    let check = |done: Vec<(QRay, bool)>,
                 tiles: &[TileBuffer],
                 results: &mut [Vec<Option<bool>>],
                 c: &mut HybridCounts,
                 unit: &mut dyn FnMut(&CullIn) -> CullOut| {
        for (q, o) in done {
            let pix = (q.id >> 6) as usize;
            let x = CullIn {
                enable: hopts.cull,
                tile: tiles[locate(pix).0].range,
                slots: pad(vec![slot_of(&q, tiles)]),
            };
            c.unit_calls += 1;
            if unit(&x).slots[0].current {
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
            check(done, &tiles, &mut results, &mut c, unit);
        }
        let tri = &tris[k];
        c.primitives += 1;
        for (p, t) in rasterize(&cam, tri, w, h) {
            let Some(code) = depth_code(&cam, hopts.depth, planes, p, w, t) else {
                continue;
            };
            let p = p as usize;
            let (tile, i) = locate(p);
            let gen = match tiles[tile].write(i, code, k as u32, false) {
                Ok(Some(gen)) => gen,
                Ok(None) => continue,
                Err(e) => unreachable!("a quantised depth and a primitive index in range: {e:?}"),
            };
            if !results[p].is_empty() {
                c.superseded += results[p].iter().filter(|r| r.is_some()).count() as u64;
            }
            samples[p] = Some(Sample { t, key: tri.key });
            c.surface_changes += 1;
            // shade now: the surface emits its rays before geometry is complete
            let s = surface(&cam, tri, p as u32, w, t);
            let rays = emit(scene, &s, p as u64);
            results[p] = vec![None; rays.len()];
            for (slot, r) in rays.iter().enumerate() {
                queue.push_back(QRay {
                    id: ray_id(p as u32, 0, gen as u8),
                    tag: RayTag {
                        depth: code,
                        gen,
                        prim: k as u32,
                    },
                    slot,
                    ray: *r,
                });
            }
            c.emitted += rays.len() as u64;
            emitted[p] = rays;
            surf[p] = Some(s);
        }
        if hopts.rays_per_step > 0 {
            let done = process(
                hopts.rays_per_step,
                &mut queue,
                &tiles,
                &mut c,
                &mut f.stats,
                unit,
            );
            if hopts.result_latency == 0 {
                check(done, &tiles, &mut results, &mut c, unit);
            } else {
                in_flight.push_back((step + hopts.result_latency, done));
            }
        }
    }
    // geometry complete: the batches in flight arrive, then the queue drains
    for (_, done) in in_flight.drain(..) {
        check(done, &tiles, &mut results, &mut c, unit);
    }
    while !queue.is_empty() {
        let done = process(4096, &mut queue, &tiles, &mut c, &mut f.stats, unit);
        check(done, &tiles, &mut results, &mut c, unit);
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
    let cam = Vec3::from(scene.camera.position);
    let dist = |t: &WorldTri| {
        t.v.iter()
            .map(|&p| (Vec3::from(p) - cam).as_dvec3().length_squared())
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
