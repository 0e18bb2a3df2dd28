//! The ray-traced renderer: primary rays, shading that emits shadow rays (point
//! and area lights) and ambient-occlusion rays, bundles, tiles in parallel,
//! PNG output.
//!
//! Shading is a pure function of the visible surface and the pixel
//! ([`emit`] then [`combine`]), shared with the hybrid renderer, so the two
//! renderers (and every traversal variant) can be compared pixel for pixel.

use crate::bundle::build_bundles;
use crate::bvh::Accel;
use crate::mesh::unit;
use crate::scene::{Light, Scene};
use crate::stats::{RayKind, Stats};
use crate::tester::BoxTester;
use crate::trace::{TRay, TraceOpts, Tracer};
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// Tile edge in pixels (rays of a tile are bundled together).
pub const TILE: u32 = 8;

/// Pinhole camera basis.
#[derive(Debug, Clone, Copy)]
pub struct Cam {
    /// eye
    pub o: [f32; 3],
    forward: [f32; 3],
    right: [f32; 3],
    up: [f32; 3],
    tan: f32,
    w: u32,
    h: u32,
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn normalize(a: [f32; 3]) -> [f32; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    a.map(|x| x / l)
}
fn dot64(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm64(a: [f64; 3]) -> [f64; 3] {
    let l = dot64(a, a).sqrt();
    a.map(|x| x / l)
}
fn cross64(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The unnormalised face normal `(v1 − v0) × (v2 − v0)` of a triangle in
/// f64: what an RT hit and a rasterised sample shade with alike.
pub(crate) fn face_normal64(v: &[[f32; 3]; 3]) -> [f64; 3] {
    let v = v.map(|p| p.map(|c| c as f64));
    let e1 = [0, 1, 2].map(|i| v[1][i] - v[0][i]);
    let e2 = [0, 1, 2].map(|i| v[2][i] - v[0][i]);
    cross64(e1, e2)
}

impl Cam {
    /// The scene's camera for a `w`×`h` image.
    pub fn new(scene: &Scene, w: u32, h: u32) -> Cam {
        let c = &scene.camera;
        let forward = normalize(sub(c.look_at, c.position));
        let right = normalize(cross(forward, c.up));
        let up = cross(right, forward);
        Cam {
            o: c.position,
            forward,
            right,
            up,
            tan: (c.fov_y.to_radians() / 2.0).tan(),
            w,
            h,
        }
    }
    /// `(forward, right, up, tan(fov_y / 2))`.
    pub fn basis(&self) -> ([f32; 3], [f32; 3], [f32; 3], f64) {
        (self.forward, self.right, self.up, self.tan as f64)
    }
    /// Direction through the centre of pixel `(x, y)` (not normalised).
    pub fn dir(&self, x: u32, y: u32) -> [f32; 3] {
        let aspect = self.w as f32 / self.h as f32;
        let sx = (2.0 * (x as f32 + 0.5) / self.w as f32 - 1.0) * self.tan * aspect;
        let sy = (1.0 - 2.0 * (y as f32 + 0.5) / self.h as f32) * self.tan;
        [0, 1, 2].map(|i| self.forward[i] + sx * self.right[i] + sy * self.up[i])
    }
}

/// A visible surface at a pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// world position
    pub pos: [f64; 3],
    /// unit geometric normal, facing the viewer
    pub normal: [f64; 3],
    /// diffuse albedo
    pub albedo: [f32; 3],
    /// world size of the instance (for the ray offset)
    pub size: f32,
    /// instance and triangle
    pub key: (u32, u32),
}

/// A secondary ray emitted by shading, and what it adds if unoccluded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SecRay {
    /// shadow or AO
    pub kind: RayKind,
    /// origin (offset from the surface along the normal)
    pub o: [f32; 3],
    /// direction (to the light sample, or AO direction × AO distance)
    pub d: [f32; 3],
    /// segment end
    pub t_max: f64,
    /// radiance added when the ray is unoccluded
    pub weight: [f32; 3],
}

/// Surface of an RT hit: world position from the world ray, normal of the
/// model triangle through `R⁻ᵀ`.
pub fn surface_of_hit(
    scene: &Scene,
    accel: &Accel,
    o: [f32; 3],
    d: [f32; 3],
    t: f64,
    inst: u32,
    prim: u32,
) -> Surface {
    let x = &accel.instances[inst as usize];
    let nm = face_normal64(&scene.meshes[x.mesh].1.corners(prim));
    let nw = [0, 1, 2].map(|i| dot64(x.normal_m[i], nm));
    let pos = [0, 1, 2].map(|i| o[i] as f64 + t * d[i] as f64);
    make_surface(pos, nw, d, x.color, x.size, (inst, prim))
}

/// A surface with its normal normalised and turned toward the viewer.
pub fn make_surface(
    pos: [f64; 3],
    n: [f64; 3],
    view_d: [f32; 3],
    albedo: [f32; 3],
    size: f32,
    key: (u32, u32),
) -> Surface {
    let mut n = norm64(n);
    if !n[0].is_finite() {
        n = [0.0, 1.0, 0.0];
    }
    if dot64(n, view_d.map(|x| x as f64)) > 0.0 {
        n = n.map(|x| -x);
    }
    Surface {
        pos,
        normal: n,
        albedo,
        size,
        key,
    }
}

/// Rays a shading of `s` at pixel `pix` emits (deterministic: hashed from
/// the pixel and the sample index).
pub fn emit(scene: &Scene, s: &Surface, pix: u64) -> Vec<SecRay> {
    let mut out = Vec::new();
    emit_into(scene, s, pix, &mut out);
    out
}

/// [`emit`], appending to `out` (a tile's list: no allocation per pixel).
pub fn emit_into(scene: &Scene, s: &Surface, pix: u64, out: &mut Vec<SecRay>) {
    let mag = s.pos.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let eps = 1e-4 * s.size as f64 + mag * 1e-6;
    let o64 = [0, 1, 2].map(|i| s.pos[i] + s.normal[i] * eps);
    let o = o64.map(|x| x as f32);
    let alb = s.albedo;
    for (li, l) in scene.lights.iter().enumerate() {
        match l {
            Light::Point { position, color } => {
                let dl = [0, 1, 2].map(|i| position[i] as f64 - o64[i]);
                let d2 = dot64(dl, dl);
                let cs = dot64(s.normal, dl) / d2.sqrt();
                if cs <= 0.0 {
                    continue;
                }
                let k = (cs / d2) as f32;
                out.push(SecRay {
                    kind: RayKind::Shadow,
                    o,
                    d: dl.map(|x| x as f32),
                    t_max: 0.999,
                    weight: [0, 1, 2].map(|c| alb[c] * color[c] * k),
                });
            }
            Light::Area {
                corner,
                edge_u,
                edge_v,
                color,
                samples,
            } => {
                let eu = edge_u.map(|x| x as f64);
                let ev = edge_v.map(|x| x as f64);
                let ln = cross64(eu, ev);
                let area = dot64(ln, ln).sqrt();
                let ln = ln.map(|x| x / area);
                for k in 0..*samples as u64 {
                    let key = pix << 16 | (li as u64) << 8 | k;
                    // stratified in u
                    let u = (k as f64 + unit(0xA11, key)) / *samples as f64;
                    let v = unit(0xA12, key);
                    let q = [0, 1, 2].map(|i| corner[i] as f64 + u * eu[i] + v * ev[i]);
                    let dl = [0, 1, 2].map(|i| q[i] - o64[i]);
                    let d2 = dot64(dl, dl);
                    let dist = d2.sqrt();
                    let cs = dot64(s.normal, dl) / dist;
                    let cl = -dot64(ln, dl) / dist;
                    if cs <= 0.0 || cl <= 0.0 {
                        continue;
                    }
                    let k = (cs * cl * area / (std::f64::consts::PI * d2 * *samples as f64)) as f32;
                    out.push(SecRay {
                        kind: RayKind::Shadow,
                        o,
                        d: dl.map(|x| x as f32),
                        t_max: 0.999,
                        weight: [0, 1, 2].map(|c| alb[c] * color[c] * k),
                    });
                }
            }
        }
    }
    let r = &scene.render;
    let n = s.normal;
    // tangent frame
    let a = if n[0].abs() > 0.9 {
        [0.0, 1.0, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let t1 = norm64(cross64(a, n));
    let t2 = cross64(n, t1);
    for k in 0..r.ao_rays as u64 {
        let key = pix << 16 | 0xF000 | k;
        // cosine-weighted hemisphere, stratified in the angle
        let u1 = unit(0xA0, key);
        let phi = 2.0 * std::f64::consts::PI * (k as f64 + unit(0xA1, key)) / r.ao_rays as f64;
        let rr = u1.sqrt();
        let (x, y, z) = (rr * phi.cos(), rr * phi.sin(), (1.0 - u1).sqrt());
        let dir = [0, 1, 2].map(|i| (x * t1[i] + y * t2[i] + z * n[i]) * r.ao_distance as f64);
        out.push(SecRay {
            kind: RayKind::Ao,
            o,
            d: dir.map(|x| x as f32),
            t_max: 1.0,
            weight: alb.map(|c| c * r.ambient / r.ao_rays as f32),
        });
    }
}

/// The pixel colour from its emitted rays and whether each was occluded
/// (summed in emission order, so every renderer gets the same bits).
pub fn combine(scene: &Scene, s: &Surface, rays: &[SecRay], occluded: &[bool]) -> [f32; 3] {
    let mut c = if scene.render.ao_rays == 0 {
        s.albedo.map(|a| a * scene.render.ambient)
    } else {
        [0.0; 3]
    };
    for (r, &occ) in rays.iter().zip(occluded) {
        if !occ {
            for k in 0..3 {
                c[k] += r.weight[k];
            }
        }
    }
    c
}

/// A rendered frame.
#[derive(Debug, Clone)]
pub struct Frame {
    /// width
    pub w: u32,
    /// height
    pub h: u32,
    /// linear colour, row-major
    pub color: Vec<[f32; 3]>,
    /// per pixel the primary hit (instance, triangle), `NONE` on a miss
    pub ids: Vec<(u32, u32)>,
    /// per pixel the primary hit's `t` bits
    pub t: Vec<u64>,
    /// traversal counters
    pub stats: Stats,
    /// wall time
    pub time: Duration,
}

impl Frame {
    /// 8-bit sRGB-ish bytes (clamp, gamma 2.2).
    pub fn rgb8(&self) -> Vec<u8> {
        self.color
            .iter()
            .flat_map(|c| c.map(|x| (x.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0 + 0.5) as u8))
            .collect()
    }
    /// Writes a PNG.
    pub fn save_png(&self, path: &std::path::Path) -> Result<(), String> {
        image::save_buffer(
            path,
            &self.rgb8(),
            self.w,
            self.h,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| format!("{}: {e}", path.display()))
    }
    /// The primary hits as text (`render --dump-hits`): a `#` header, then
    /// one line per pixel, row-major from the top-left pixel,
    /// `x y instance primitive t` with `t` the hit distance in units of the
    /// camera ray's direction (`look_at − position` normalised, plus the
    /// pixel offset on the image plane at distance 1: the direction of
    /// [`Cam::dir`], not normalised) as a decimal and its binary64 bits in
    /// hex; a miss is `x y - - -`. `x` grows to the right, `y` downwards.
    pub fn hits_text(&self, header: &str) -> String {
        use std::fmt::Write as _;
        let mut s = String::with_capacity(40 * self.ids.len() + 256);
        for line in header.lines() {
            let _ = writeln!(s, "# {line}");
        }
        let _ = writeln!(s, "# width {} height {}", self.w, self.h);
        let _ = writeln!(s, "# x y instance primitive t t_bits(binary64 hex)");
        for (k, (&(inst, prim), &t)) in self.ids.iter().zip(&self.t).enumerate() {
            let (x, y) = (k as u32 % self.w, k as u32 / self.w);
            if inst == crate::trace::NONE {
                let _ = writeln!(s, "{x} {y} - - -");
            } else {
                let _ = writeln!(s, "{x} {y} {inst} {prim} {:e} {t:016x}", f64::from_bits(t));
            }
        }
        s
    }
    /// The same primary hits (instance, primitive and `t` of every pixel).
    pub fn same_hits(&self, other: &Frame) -> bool {
        self.w == other.w && self.h == other.h && self.ids == other.ids && self.t == other.t
    }
    /// Every pixel's primary hit, `t` and colour (bits) equal `other`'s.
    pub fn same_image(&self, other: &Frame) -> bool {
        self.ids == other.ids
            && self.t == other.t
            && self
                .color
                .iter()
                .zip(&other.color)
                .all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits))
    }

    /// Total rays traced.
    pub fn rays(&self) -> u64 {
        self.stats.total().rays
    }
}

/// Traces secondary rays (bundled per type) and returns whether each was occluded.
pub fn trace_secondary(tracer: &Tracer, scale: f32, sec: &[SecRay], st: &mut Stats) -> Vec<bool> {
    let mut rays: Vec<TRay> = sec
        .iter()
        .map(|s| TRay::new(s.o, s.d, s.t_max, true))
        .collect();
    for kind in [RayKind::Shadow, RayKind::Ao] {
        let idx: Vec<usize> = (0..sec.len()).filter(|&i| sec[i].kind == kind).collect();
        for b in build_bundles(&rays, &idx, &tracer.opts.bundles, scale) {
            tracer.trace(&mut rays, &b, kind, st);
        }
    }
    rays.iter().map(|r| r.hit.is_hit()).collect()
}

struct TileOut {
    x0: u32,
    y0: u32,
    tw: u32,
    th: u32,
    color: Vec<[f32; 3]>,
    ids: Vec<(u32, u32)>,
    t: Vec<u64>,
    stats: Stats,
}

/// Renders the scene at `w`×`h` with ray tracing only (tiles in parallel;
/// a progress bar on stderr when `progress`).
pub fn render(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn BoxTester,
    opts: TraceOpts,
    w: u32,
    h: u32,
    progress: bool,
) -> Frame {
    render_with(
        scene,
        accel,
        &Tracer::new(scene, accel, tester, opts),
        w,
        h,
        progress,
    )
}

/// [`render`] with a tracer of the caller's (e.g. over a wide BVH,
/// `Tracer::with_wide`).
pub fn render_with(
    scene: &Scene,
    accel: &Accel,
    tracer: &Tracer,
    w: u32,
    h: u32,
    progress: bool,
) -> Frame {
    let start = Instant::now();
    let cam = Cam::new(scene, w, h);
    let tiles: Vec<(u32, u32)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..w.div_ceil(TILE)).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    let pb = if progress {
        let pb = indicatif::ProgressBar::new(tiles.len() as u64);
        pb.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} tiles {elapsed} (eta {eta})",
            )
            .unwrap(),
        );
        pb
    } else {
        indicatif::ProgressBar::hidden()
    };
    let outs: Vec<TileOut> = tiles
        .par_iter()
        .map(|&(x0, y0)| {
            let out = render_tile(scene, accel, tracer, &cam, x0, y0, w, h);
            pb.inc(1);
            out
        })
        .collect();
    pb.finish_and_clear();
    let n = (w * h) as usize;
    let mut f = Frame {
        w,
        h,
        color: vec![[0.0; 3]; n],
        ids: vec![(crate::trace::NONE, crate::trace::NONE); n],
        t: vec![0; n],
        stats: Stats::default(),
        time: Duration::ZERO,
    };
    for o in outs {
        for j in 0..o.th {
            for i in 0..o.tw {
                let src = (j * o.tw + i) as usize;
                let dst = ((o.y0 + j) * w + o.x0 + i) as usize;
                f.color[dst] = o.color[src];
                f.ids[dst] = o.ids[src];
                f.t[dst] = o.t[src];
            }
        }
        f.stats.add(&o.stats);
    }
    f.time = start.elapsed();
    f
}

#[allow(clippy::too_many_arguments)]
fn render_tile(
    scene: &Scene,
    accel: &Accel,
    tracer: &Tracer,
    cam: &Cam,
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
) -> TileOut {
    let tw = TILE.min(w - x0);
    let th = TILE.min(h - y0);
    let mut st = Stats::default();
    let mut rays = Vec::new();
    for j in 0..th {
        for i in 0..tw {
            rays.push(TRay::new(
                cam.o,
                cam.dir(x0 + i, y0 + j),
                f64::INFINITY,
                false,
            ));
        }
    }
    let idx: Vec<usize> = (0..rays.len()).collect();
    for b in build_bundles(&rays, &idx, &tracer.opts.bundles, accel.scale) {
        tracer.trace(&mut rays, &b, RayKind::Primary, &mut st);
    }
    let mut color = vec![scene.render.background; rays.len()];
    let mut ids = vec![(crate::trace::NONE, crate::trace::NONE); rays.len()];
    let mut ts = vec![0u64; rays.len()];
    // shading: every hit pixel emits its rays, traced together per type
    let mut sec = Vec::new();
    let mut owners = Vec::new();
    let mut surfs = Vec::new();
    for (k, r) in rays.iter().enumerate() {
        if !r.hit.is_hit() {
            continue;
        }
        ids[k] = (r.hit.inst, r.hit.prim);
        ts[k] = r.hit.t.to_bits();
        let pix = ((y0 + k as u32 / tw) * w + x0 + k as u32 % tw) as u64;
        let s = surface_of_hit(scene, accel, r.o_w, r.d_w, r.hit.t, r.hit.inst, r.hit.prim);
        let first = sec.len();
        emit_into(scene, &s, pix, &mut sec);
        owners.push((k, first, sec.len() - first));
        surfs.push(s);
    }
    let occ = trace_secondary(tracer, accel.scale, &sec, &mut st);
    for ((k, first, n), s) in owners.into_iter().zip(&surfs) {
        color[k] = combine(scene, s, &sec[first..first + n], &occ[first..first + n]);
    }
    TileOut {
        x0,
        y0,
        tw,
        th,
        color,
        ids,
        t: ts,
        stats: st,
    }
}
