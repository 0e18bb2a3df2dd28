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
use crate::scene::{Camera, Light, Scene};
use crate::stats::{RayKind, Stats};
use crate::tester::BoxTester;
use crate::trace::{TRay, TraceOpts, Tracer};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// Tile edge in pixels (rays of a tile are bundled together).
pub const TILE: u32 = 8;

/// Pinhole camera basis.
#[derive(Debug, Clone, Copy)]
pub struct Cam {
    /// eye
    pub o: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan: f32,
    w: u32,
    h: u32,
}

/// `v` divided by its length. glam's `normalize` multiplies by the
/// reciprocal of the length instead (two roundings): the camera basis, the
/// shading normal, the AO frame, the bundles' direction spreads and the
/// icosphere's vertices are normalised by division so that the rays and
/// boxes handed to the units keep their bits (`docs/scene.md` §3.2).
macro_rules! unit_by_division {
    ($v:expr) => {{
        let v = $v;
        v / v.length()
    }};
}
pub(crate) use unit_by_division;

/// The unnormalised face normal `(v1 − v0) × (v2 − v0)` of a triangle in
/// f64: what an RT hit and a rasterised sample shade with alike.
pub(crate) fn face_normal64(v: &[[f32; 3]; 3]) -> DVec3 {
    let [v0, v1, v2] = v.map(|p| Vec3::from(p).as_dvec3());
    (v1 - v0).cross(v2 - v0)
}

/// The camera's unit `(forward, right, up)` in binary32 (the scene file checks it is finite).
pub(crate) fn camera_basis(c: &Camera) -> (Vec3, Vec3, Vec3) {
    let forward = unit_by_division!(Vec3::from(c.look_at) - Vec3::from(c.position));
    let right = unit_by_division!(forward.cross(c.up.into()));
    (forward, right, right.cross(forward))
}

impl Cam {
    /// The scene's camera for a `w`×`h` image.
    pub fn new(scene: &Scene, w: u32, h: u32) -> Cam {
        let c = &scene.camera;
        let o = Vec3::from(c.position);
        let (forward, right, up) = camera_basis(c);
        Cam {
            o,
            forward,
            right,
            up,
            tan: (c.fov_y.to_radians() / 2.0).tan(),
            w,
            h,
        }
    }
    /// `(forward, right, up, tan(fov_y / 2))`.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3, f64) {
        (self.forward, self.right, self.up, self.tan as f64)
    }
    /// Direction through the centre of pixel `(x, y)` (not normalised).
    pub fn dir(&self, x: u32, y: u32) -> Vec3 {
        let aspect = self.w as f32 / self.h as f32;
        let sx = (2.0 * (x as f32 + 0.5) / self.w as f32 - 1.0) * self.tan * aspect;
        let sy = (1.0 - 2.0 * (y as f32 + 0.5) / self.h as f32) * self.tan;
        self.forward + self.right * sx + self.up * sy
    }
}

/// A visible surface at a pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// world position
    pub pos: DVec3,
    /// unit geometric normal, facing the viewer
    pub normal: DVec3,
    /// diffuse albedo
    pub albedo: Vec3,
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
    pub o: Vec3,
    /// direction (to the light sample, or AO direction × AO distance)
    pub d: Vec3,
    /// segment end
    pub t_max: f64,
    /// radiance added when the ray is unoccluded
    pub weight: Vec3,
}

/// Surface of an RT hit: world position from the world ray, normal of the
/// model triangle through `R⁻ᵀ`.
pub fn surface_of_hit(
    scene: &Scene,
    accel: &Accel,
    o: Vec3,
    d: Vec3,
    t: f64,
    inst: u32,
    prim: u32,
) -> Surface {
    let x = &accel.instances[inst as usize];
    let nm = face_normal64(&scene.meshes[x.mesh].1.corners(prim));
    let pos = o.as_dvec3() + d.as_dvec3() * t;
    make_surface(pos, x.normal_m * nm, d, x.color, x.size, (inst, prim))
}

/// A surface with its normal normalised and turned toward the viewer.
pub fn make_surface(
    pos: DVec3,
    n: DVec3,
    view_d: Vec3,
    albedo: Vec3,
    size: f32,
    key: (u32, u32),
) -> Surface {
    let mut n = unit_by_division!(n);
    if !n.x.is_finite() {
        n = DVec3::Y;
    }
    if n.dot(view_d.as_dvec3()) > 0.0 {
        n = -n;
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
    let mag = s.pos.abs().max_element();
    let eps = 1e-4 * s.size as f64 + mag * 1e-6;
    let o64 = s.pos + s.normal * eps;
    let o = o64.as_vec3();
    let alb = s.albedo;
    let f64_of = |p: &[f32; 3]| Vec3::from(*p).as_dvec3();
    for (li, l) in scene.lights.iter().enumerate() {
        match l {
            Light::Point { position, color } => {
                let dl = f64_of(position) - o64;
                let d2 = dl.length_squared();
                let cs = s.normal.dot(dl) / d2.sqrt();
                if cs <= 0.0 {
                    continue;
                }
                let k = (cs / d2) as f32;
                out.push(SecRay {
                    kind: RayKind::Shadow,
                    o,
                    d: dl.as_vec3(),
                    t_max: 0.999,
                    weight: alb * Vec3::from(*color) * k,
                });
            }
            Light::Area {
                corner,
                edge_u,
                edge_v,
                color,
                samples,
            } => {
                let (eu, ev) = (f64_of(edge_u), f64_of(edge_v));
                let ln = eu.cross(ev);
                let area = ln.length();
                let ln = ln / area;
                for k in 0..*samples as u64 {
                    let key = pix << 16 | (li as u64) << 8 | k;
                    // stratified in u
                    let u = (k as f64 + unit(0xA11, key)) / *samples as f64;
                    let v = unit(0xA12, key);
                    let q = f64_of(corner) + eu * u + ev * v;
                    let dl = q - o64;
                    let d2 = dl.length_squared();
                    let dist = d2.sqrt();
                    let cs = s.normal.dot(dl) / dist;
                    let cl = -ln.dot(dl) / dist;
                    if cs <= 0.0 || cl <= 0.0 {
                        continue;
                    }
                    let k = (cs * cl * area / (std::f64::consts::PI * d2 * *samples as f64)) as f32;
                    out.push(SecRay {
                        kind: RayKind::Shadow,
                        o,
                        d: dl.as_vec3(),
                        t_max: 0.999,
                        weight: alb * Vec3::from(*color) * k,
                    });
                }
            }
        }
    }
    let r = &scene.render;
    let n = s.normal;
    // tangent frame
    let a = if n.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
    let t1 = unit_by_division!(a.cross(n));
    let t2 = n.cross(t1);
    for k in 0..r.ao_rays as u64 {
        let key = pix << 16 | 0xF000 | k;
        // cosine-weighted hemisphere, stratified in the angle
        let u1 = unit(0xA0, key);
        let phi = 2.0 * std::f64::consts::PI * (k as f64 + unit(0xA1, key)) / r.ao_rays as f64;
        let rr = u1.sqrt();
        let (x, y, z) = (rr * phi.cos(), rr * phi.sin(), (1.0 - u1).sqrt());
        let dir = (t1 * x + t2 * y + n * z) * r.ao_distance as f64;
        out.push(SecRay {
            kind: RayKind::Ao,
            o,
            d: dir.as_vec3(),
            t_max: 1.0,
            weight: alb * r.ambient / r.ao_rays as f32,
        });
    }
}

/// The pixel colour from its emitted rays and whether each was occluded
/// (summed in emission order, so every renderer gets the same bits).
pub fn combine(scene: &Scene, s: &Surface, rays: &[SecRay], occluded: &[bool]) -> Vec3 {
    let mut c = if scene.render.ao_rays == 0 {
        s.albedo * scene.render.ambient
    } else {
        Vec3::ZERO
    };
    for (r, &occ) in rays.iter().zip(occluded) {
        if !occ {
            c += r.weight;
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
    pub color: Vec<Vec3>,
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
            .flat_map(|c| {
                c.to_array()
                    .map(|x| (x.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0 + 0.5) as u8)
            })
            .collect()
    }
    /// Writes a PNG.
    pub fn save_png(&self, path: &std::path::Path) -> Result<(), String> {
        // PNG whatever the name ends with: the CLI writes to a temporary name first
        image::save_buffer_with_format(
            path,
            &self.rgb8(),
            self.w,
            self.h,
            image::ExtendedColorType::Rgb8,
            image::ImageFormat::Png,
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
    /// The binary32 bits of pixel `p`'s colour (what identity tests compare).
    pub fn color_bits(&self, p: usize) -> [u32; 3] {
        self.color[p].to_array().map(f32::to_bits)
    }
    /// Every pixel's primary hit, `t` and colour (bits) equal `other`'s.
    pub fn same_image(&self, other: &Frame) -> bool {
        self.ids == other.ids
            && self.t == other.t
            && (0..self.color.len()).all(|p| self.color_bits(p) == other.color_bits(p))
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
    color: Vec<Vec3>,
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
        color: vec![Vec3::ZERO; n],
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
    let mut color = vec![Vec3::from(scene.render.background); rays.len()];
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
