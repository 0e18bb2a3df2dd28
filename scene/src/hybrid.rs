//! Hybrid rasterisation + ray tracing with depth-based ray culling (seed 002),
//! every cull decision by the golden model of the `raycull` unit
//! (`golden_model::raycull`, docs/raycull.md).
//!
//! The raster pass finds the visible surfaces of each sample (one sample per
//! pixel, at its centre): coverage and `t` of a triangle at a sample are the
//! edge functions and `t` of the camera ray through the sample
//! ([`crate::trace::intersect`], i.e. homogeneous 2D rasterisation); the
//! depth is the **quantised code** of its view-space depth between the scene's
//! near and far planes ([`depth_planes`], [`golden_model::raycull::quantize`];
//! unorm16, unorm24 or binary32; reversed under `greater`/`gequal`), and the
//! depth test is [`HybridOpts::compare`] on `(code, primitive index)`: with
//! `less` and `greater` ties go to the smaller primitive and the final
//! surface does not depend on the primitive order.
//!
//! **Translucency**: a sample keeps its nearest opaque surface and the
//! nearest translucent one in front of it (instance opacity below 1) and
//! blends them; the front one is the unit's sample state, with drop-farther
//! 0 when translucent, so the unit keeps the rays of the surface behind.
//!
//! **Asynchronous mode** ([`render_async`]): primitives are rasterised in a
//! given order into one [`golden_model::raycull::TileBuffer`] per 8×8 tile;
//! whenever a primitive takes a layer of a sample, the sample's generation
//! (3 bits, FIG. 14 layout `pixel 26 | sample 3 | generation 3`) is
//! incremented, and at the end of the partial render ([`Mode`]: immediate,
//! after this primitive) the layer is shaded: it emits its shadow and AO
//! rays, each tagged with the depth code, the generation and the primitive.
//! After each primitive a ray processor takes up to `rays_per_step` rays from
//! the queue, in groups of up to G consecutive rays of one tile, and asks the
//! unit: stage 1 (tile range, per ray and per group), stage 2 (sample depth,
//! and generation at equal depth); it traces the survivors (bundled, through
//! the golden models); when a result arrives the unit's **contribution
//! check** (full primitive id and generation of the ray's layer then)
//! decides whether it is stored; a later change of the layer discards its
//! stored results.
//!
//! When all primitives are done, the queue is drained the same way and each
//! layer combines the results of its final surface's rays in emission order.
//! **Synchronous mode** ([`render_sync`]): rasterise everything (the same
//! codes and test), shade the final layers, trace, blend. Both produce the
//! same bits for every primitive order, mode and interleaving (tests
//! `hybrid_identical.rs`, `hybrid_modes.rs`, `hybrid_rtl.rs`).
//! [`render_async_with`] takes any answerer for the unit's transactions
//! (`crate::hybrid_rtl`: the Verilated unit).

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
    /// instance opacity (below 1: translucent)
    pub opacity: f32,
}

impl WorldTri {
    /// The surface is translucent.
    pub fn translucent(&self) -> bool {
        self.opacity < 1.0
    }
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
                opacity: scene.instances[i].opacity,
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
    /// times a sample's surface (opaque or translucent layer) changed
    pub surface_changes: u64,
    /// surfaces shaded (each emits its rays)
    pub shaded: u64,
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
    /// rays the unit kept although their sample's front surface was another,
    /// translucent one (the "OK to drop farther" rule)
    pub kept_translucent: u64,
    /// traced
    pub traced: u64,
    /// traced, but the result was rejected by the contribution check (stale)
    pub discarded: u64,
    /// results kept then dropped because the sample's surface changed later
    pub superseded: u64,
    /// rays whose results make the final image (= the synchronous render's ray count)
    pub used: u64,
    /// rays of a final surface without a result (a false cull; 0 unless the unit is wrong)
    pub lost: u64,
    /// transactions of the ray-cull unit (cull groups and contribution checks)
    pub unit_calls: u64,
}

/// When surfaces are shaded (and emit their rays) relative to rasterisation
/// (the description's modes; docs/raycull.md §6).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// a surface is shaded as soon as it becomes a sample's surface
    Immediate,
    /// partial renders of N primitives: hidden surface removal over a
    /// partial render's geometry completes, then the surfaces it left
    /// visible (and changed) are shaded
    Partial(usize),
    /// one render of all the geometry before shading: only final surfaces
    /// are shaded (the synchronous render; nothing to cull)
    Deferred,
}

impl Mode {
    /// `immediate`, `partial:N` (N ≥ 1) or `deferred`.
    pub fn parse(word: &str) -> Result<Mode, String> {
        let n = word.strip_prefix("partial:").map(str::parse::<usize>);
        match (word, n) {
            ("immediate", _) => Ok(Mode::Immediate),
            ("deferred", _) => Ok(Mode::Deferred),
            (_, Some(Ok(n))) if n >= 1 => Ok(Mode::Partial(n)),
            _ => Err(format!(
                "`{word}` is not a mode (immediate, partial:N with N >= 1, deferred)"
            )),
        }
    }

    /// Primitives per partial render when the frame has `n` primitives
    /// (immediate: each primitive is its own partial render).
    pub fn primitives_per_render(self, n: usize) -> usize {
        match self {
            Mode::Immediate => 1,
            Mode::Partial(k) => k,
            Mode::Deferred => n.max(1),
        }
    }
}

/// Options of the asynchronous path.
#[derive(Debug, Clone)]
pub struct HybridOpts {
    /// order in which the primitives (indices into [`world_triangles`]) are
    /// rasterised (the synchronous render too; empty there: as stored)
    pub order: Vec<usize>,
    /// rays the ray processor handles after each primitive (0: only at the end)
    pub rays_per_step: usize,
    /// primitives rasterised while a traced batch's results are in flight: the
    /// contribution check sees the depth buffer that many primitives after the
    /// cull did (0: the same one), as a ray unit with latency would
    pub result_latency: usize,
    /// depth code format of the raster and the ray-cull unit
    pub depth: DepthFormat,
    /// depth test of the raster and the unit (greater, gequal: reversed depth)
    pub compare: Compare,
    /// when surfaces are shaded
    pub mode: Mode,
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
            compare: Compare::Less,
            mode: Mode::Immediate,
            group: 4,
            cull: true,
        }
    }
}

impl HybridOpts {
    /// The ray-cull unit's configuration the renderer uses: its depth format
    /// and compare mode, 3-bit generations (FIG. 14), primitive ids wide
    /// enough for `primitives` triangles, groups of G.
    pub fn unit_config(&self, primitives: usize) -> Config {
        Config {
            format: self.depth,
            compare: self.compare,
            gen_bits: GEN_BITS,
            prim_bits: (usize::BITS - primitives.max(2).leading_zeros()).max(1),
            group: self.group.max(1),
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
/// its view-space depth `z = t·(d·forward)` ([`golden_model::raycull::quantize`];
/// 0 at near and the far code at far, the other way round when reversed);
/// `None` when clipped.
fn depth_code(
    cam: &Cam,
    fmt: DepthFormat,
    compare: Compare,
    planes: (f64, f64),
    p: u32,
    w: u32,
    t: f64,
) -> Option<u32> {
    let (fw, ..) = cam.basis();
    let d = cam.dir(p % w, p / w);
    let z = t * d.as_dvec3().dot(fw.as_dvec3());
    quantize(fmt, compare.reversed(), z, planes.0, planes.1)
}

/// A sample's surface: the fragment that holds one of its layers.
#[derive(Debug, Clone, Copy)]
struct Frag {
    code: u32,
    /// primitive index (the unit's primitive id)
    k: usize,
    t: f64,
    /// the sample's generation when the fragment took the layer
    gen: u32,
}

/// The two surfaces a sample may show.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layer {
    Opaque = 0,
    Translucent = 1,
}

/// A sample's surfaces: the nearest opaque one, and the nearest translucent
/// one when it is in front of it (then it is the **front** surface, whose
/// state the ray-cull unit reads, with drop-farther 0). The final colour
/// blends the translucent surface over the opaque one (or the background).
#[derive(Debug, Clone, Copy, Default)]
struct Layers {
    opaque: Option<Frag>,
    translucent: Option<Frag>,
}

/// What a fragment changed.
struct Change {
    layer: Layer,
    /// it is the new front surface
    front: bool,
    /// an opaque front surface removed the translucent one
    removed_translucent: bool,
}

impl Layers {
    fn get(&self, l: Layer) -> Option<Frag> {
        match l {
            Layer::Opaque => self.opaque,
            Layer::Translucent => self.translucent,
        }
    }

    fn front(&self) -> Option<Frag> {
        self.translucent.or(self.opaque)
    }

    /// Rasterises a fragment with the depth test `cmp` against each layer
    /// (the front test equals the tile buffer's: a fragment that passes the
    /// translucent surface passes the opaque one behind it). `None`: hidden.
    fn write(&mut self, cmp: Compare, frag: Frag, translucent: bool) -> Option<Change> {
        let passes = |l: Option<Frag>| {
            l.is_none_or(|f| cmp.passes(frag.code, frag.k as u32, f.code, f.k as u32))
        };
        let before_translucent = passes(self.translucent);
        if !passes(self.opaque) || (translucent && !before_translucent) {
            return None;
        }
        if translucent {
            self.translucent = Some(frag);
            return Some(Change {
                layer: Layer::Translucent,
                front: true,
                removed_translucent: false,
            });
        }
        self.opaque = Some(frag);
        let removed_translucent = before_translucent && self.translucent.take().is_some();
        Some(Change {
            layer: Layer::Opaque,
            front: self.translucent.is_none(),
            removed_translucent,
        })
    }
}

/// A pixel's colour from its layers' shaded colours: the translucent
/// surface's colour × opacity over (1 − opacity) × the opaque one's (or
/// the background).
fn blend(bg: [f32; 3], opaque: Option<Vec3>, translucent: Option<(Vec3, f32)>) -> Vec3 {
    let back = opaque.unwrap_or(Vec3::from(bg));
    match translucent {
        Some((c, a)) => a * c + (1.0 - a) * back,
        None => back,
    }
}

/// Every sample's layers after rasterising `order` (empty: as stored).
fn rasterize_all(
    cam: &Cam,
    tris: &[WorldTri],
    planes: (f64, f64),
    w: u32,
    h: u32,
    hopts: &HybridOpts,
) -> Vec<Layers> {
    let mut px = vec![Layers::default(); (w * h) as usize];
    let stored: Vec<usize>;
    let order = if hopts.order.is_empty() {
        stored = (0..tris.len()).collect();
        &stored
    } else {
        &hopts.order
    };
    for &k in order {
        let tri = &tris[k];
        for (p, t) in rasterize(cam, tri, w, h) {
            if let Some(code) = depth_code(cam, hopts.depth, hopts.compare, planes, p, w, t) {
                let frag = Frag { code, k, t, gen: 0 };
                px[p as usize].write(hopts.compare, frag, tri.translucent());
            }
        }
    }
    px
}

/// Packs a ray id (FIG. 14): pixel 26 bits, sample 3, generation 3.
pub fn ray_id(pixel: u32, sample: u32, gen: u8) -> u32 {
    (pixel & 0x03FF_FFFF) << 6 | (sample & 7) << 3 | (gen as u32 & 7)
}

struct QRay {
    /// pixel 26 | sample 3 | generation 3
    id: u32,
    layer: Layer,
    tag: RayTag,
    slot: usize,
    ray: SecRay,
}

/// A layer's shaded surface, its rays and their results so far.
#[derive(Clone, Default)]
struct Shaded {
    surface: Option<Surface>,
    rays: Vec<SecRay>,
    results: Vec<Option<bool>>,
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

/// Synchronous reference: rasterise everything in `hopts.order` (as stored
/// when empty; with `less` and `greater` the surfaces do not depend on the
/// order) with the same depth codes and test, shade the final surfaces,
/// trace, blend.
pub fn render_sync(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn BoxTester,
    opts: TraceOpts,
    w: u32,
    h: u32,
    hopts: &HybridOpts,
) -> Frame {
    let start = Instant::now();
    let cam = Cam::new(scene, w, h);
    let tris = world_triangles(scene, accel);
    let planes = depth_planes(&cam, &tris);
    let px = rasterize_all(&cam, &tris, planes, w, h, hopts);
    let tracer = Tracer::new(scene, accel, tester, opts);
    let mut f = frame(w, h, scene.render.background);
    let mut sec = Vec::new();
    let mut owners = Vec::new();
    for (p, l) in px.iter().enumerate() {
        for layer in [Layer::Opaque, Layer::Translucent] {
            if let Some(fr) = l.get(layer) {
                let s = surface(&cam, &tris[fr.k], p as u32, w, fr.t);
                let first = sec.len();
                emit_into(scene, &s, p as u64, &mut sec);
                owners.push((p, layer, s, first, sec.len() - first));
            }
        }
        if let Some(fr) = l.front() {
            f.ids[p] = tris[fr.k].key;
            f.t[p] = fr.t.to_bits();
        }
    }
    let occ = trace_secondary(&tracer, accel.scale, &sec, &mut f.stats);
    let mut shaded = vec![[None; 2]; px.len()];
    for (p, layer, s, first, n) in owners {
        shaded[p][layer as usize] = Some(combine(
            scene,
            &s,
            &sec[first..first + n],
            &occ[first..first + n],
        ));
    }
    for (p, l) in px.iter().enumerate() {
        let tr = l
            .translucent
            .map(|fr| (shaded[p][1].expect("shaded"), tris[fr.k].opacity));
        if l.front().is_some() {
            f.color[p] = blend(scene.render.background, shaded[p][0], tr);
        }
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
    let cfg = hopts.unit_config(world_triangles(scene, accel).len());
    render_async_with(scene, accel, tester, opts, w, h, hopts, &mut |x| {
        cull(&cfg, x)
    })
}

/// [`render_async`] with every ray-cull unit transaction (`G` slots, the
/// configuration of [`HybridOpts::unit_config`]) answered by `unit`: the
/// golden model, or the Verilated unit's recorded outputs.
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
    let cfg = hopts.unit_config(tris.len());
    let g = cfg.group;
    let per_render = hopts.mode.primitives_per_render(hopts.order.len());
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
    let mut layers: Vec<Layers> = vec![Layers::default(); n];
    // per sample and layer: the shaded surface, its rays and their results
    let mut shaded: Vec<[Shaded; 2]> = vec![Default::default(); n];
    // layers changed since the last partial render was shaded, in order
    let mut pending: Vec<(usize, Layer)> = Vec::new();
    let mut is_pending = vec![[false; 2]; n];
    let mut queue: VecDeque<QRay> = VecDeque::new();
    let mut c = HybridCounts::default();
    let mut f = frame(w, h, scene.render.background);

    // the unit's view of a ray's sample: the front surface's state (culls)
    let front_slot = |q: &QRay, tiles: &[TileBuffer]| {
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
            let slots: Vec<Slot> = group.iter().map(|q| front_slot(q, tiles)).collect();
            let x = CullIn {
                enable: hopts.cull,
                tile: tiles[tile].range,
                slots: pad(slots.clone()),
            };
            let out = unit(&x);
            c.unit_calls += 1;
            if out.group_cull {
                c.culled_groups += 1;
                c.culled_group_rays += group.len() as u64;
            }
            for ((q, v), s) in group.into_iter().zip(&out.slots).zip(&slots) {
                if v.tile_cull {
                    c.culled_tile += 1;
                } else if v.depth_cull {
                    c.culled_depth += 1;
                } else if v.generation_cull {
                    c.culled_generation += 1;
                } else {
                    let own = s.sample.prim == q.tag.prim && s.sample.gen == q.tag.gen;
                    c.kept_translucent += (!s.sample.drop_farther && !own) as u64;
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
    // with the state of the ray's layer then (full primitive id and
    // generation; no layer: the front state, another primitive)
    let check = |done: Vec<(QRay, bool)>,
                 tiles: &[TileBuffer],
                 layers: &[Layers],
                 shaded: &mut [[Shaded; 2]],
                 c: &mut HybridCounts,
                 unit: &mut dyn FnMut(&CullIn) -> CullOut| {
        for (q, o) in done {
            let pix = (q.id >> 6) as usize;
            let mut slot = front_slot(&q, tiles);
            if let Some(fr) = layers[pix].get(q.layer) {
                slot.sample.depth = fr.code;
                slot.sample.gen = fr.gen;
                slot.sample.prim = fr.k as u32;
            }
            let x = CullIn {
                enable: hopts.cull,
                tile: tiles[locate(pix).0].range,
                slots: pad(vec![slot]),
            };
            c.unit_calls += 1;
            if unit(&x).slots[0].current {
                shaded[pix][q.layer as usize].results[q.slot] = Some(o);
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
            check(done, &tiles, &layers, &mut shaded, &mut c, unit);
        }
        let tri = &tris[k];
        c.primitives += 1;
        for (p, t) in rasterize(&cam, tri, w, h) {
            let Some(code) = depth_code(&cam, hopts.depth, hopts.compare, planes, p, w, t) else {
                continue;
            };
            let p = p as usize;
            let (tile, i) = locate(p);
            // an opaque surface behind a translucent front continues the
            // previous opaque surface's generation (or the sample's)
            let behind_gen = layers[p]
                .opaque
                .map_or(tiles[tile].samples[i].state.gen, |f| f.gen);
            let frag = Frag { code, k, t, gen: 0 };
            let Some(ch) = layers[p].write(hopts.compare, frag, tri.translucent()) else {
                continue;
            };
            // the front surface is the tile buffer's (the unit's sample
            // state); an opaque surface behind a translucent one keeps its
            // own generation count (its rays' contribution check)
            let gen = if ch.front {
                match tiles[tile].write(i, code, k as u32, tri.translucent()) {
                    Ok(Some(gen)) => gen,
                    other => unreachable!("the layers and the tile buffer agree: {other:?}"),
                }
            } else {
                (behind_gen + 1) & cfg.gen_mask()
            };
            let slot = match ch.layer {
                Layer::Opaque => layers[p].opaque.as_mut(),
                Layer::Translucent => layers[p].translucent.as_mut(),
            };
            slot.expect("just written").gen = gen;
            c.surface_changes += 1;
            let mut drop = |l: Layer, c: &mut HybridCounts| {
                let sh = &mut shaded[p][l as usize];
                c.superseded += sh.results.iter().filter(|r| r.is_some()).count() as u64;
                *sh = Shaded::default();
            };
            drop(ch.layer, &mut c);
            if ch.removed_translucent {
                drop(Layer::Translucent, &mut c);
            }
            if !is_pending[p][ch.layer as usize] {
                is_pending[p][ch.layer as usize] = true;
                pending.push((p, ch.layer));
            }
        }
        // the end of a partial render (immediate: every primitive): shade
        // the surfaces it changed, which emit their rays
        if (step + 1) % per_render == 0 || step + 1 == hopts.order.len() {
            for (p, layer) in pending.drain(..) {
                is_pending[p][layer as usize] = false;
                let Some(fr) = layers[p].get(layer) else {
                    continue;
                };
                let s = surface(&cam, &tris[fr.k], p as u32, w, fr.t);
                let rays = emit(scene, &s, p as u64);
                for (slot, r) in rays.iter().enumerate() {
                    queue.push_back(QRay {
                        id: ray_id(p as u32, 0, fr.gen as u8),
                        layer,
                        tag: RayTag {
                            depth: fr.code,
                            gen: fr.gen,
                            prim: fr.k as u32,
                        },
                        slot,
                        ray: *r,
                    });
                }
                c.shaded += 1;
                c.emitted += rays.len() as u64;
                shaded[p][layer as usize] = Shaded {
                    surface: Some(s),
                    results: vec![None; rays.len()],
                    rays,
                };
            }
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
                check(done, &tiles, &layers, &mut shaded, &mut c, unit);
            } else {
                in_flight.push_back((step + hopts.result_latency, done));
            }
        }
    }
    // geometry complete: the batches in flight arrive, then the queue drains
    for (_, done) in in_flight.drain(..) {
        check(done, &tiles, &layers, &mut shaded, &mut c, unit);
    }
    while !queue.is_empty() {
        let done = process(4096, &mut queue, &tiles, &mut c, &mut f.stats, unit);
        check(done, &tiles, &layers, &mut shaded, &mut c, unit);
    }
    for p in 0..n {
        let Some(front) = layers[p].front() else {
            continue;
        };
        let mut colour = [None; 2];
        for layer in [Layer::Opaque, Layer::Translucent] {
            let sh = &shaded[p][layer as usize];
            let Some(s) = sh.surface else { continue };
            // a missing result is a false cull: counted, and the ray taken
            // as occluded so the image shows it
            let occ: Vec<bool> = sh.results.iter().map(|r| r.unwrap_or(true)).collect();
            c.lost += sh.results.iter().filter(|r| r.is_none()).count() as u64;
            c.used += occ.len() as u64;
            colour[layer as usize] = Some(combine(scene, &s, &sh.rays, &occ));
        }
        let tr = layers[p]
            .translucent
            .and_then(|fr| Some((colour[1]?, tris[fr.k].opacity)));
        f.color[p] = blend(scene.render.background, colour[0], tr);
        f.ids[p] = tris[front.k].key;
        f.t[p] = front.t.to_bits();
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
