//! Triangle meshes: Wavefront OBJ through `tobj`, and the procedural shapes the
//! shipped scenes use (quad, box, icosphere, a grass/hair patch of long thin blades).
//! Meshes are `golden_model::cull::bvh::Mesh` (f32 vertices, index triples), the
//! type the cull-plane builder takes.

use crate::render::unit_by_division;
use glam::DVec3;
use golden_model::cull::bvh::Mesh;
use std::path::Path;

/// Loads an OBJ file (every object merged, polygons fanned into triangles by `tobj`).
/// A vertex with a NaN or infinite coordinate is an error naming it (index in
/// the merged mesh, coordinates).
pub fn load_obj(path: &Path) -> Result<Mesh, String> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _) = tobj::load_obj(path, &opts).map_err(|e| e.to_string())?;
    let mut mesh = Mesh::default();
    for m in models {
        let base = mesh.vertices.len() as u32;
        let p = &m.mesh.positions;
        for v in p.chunks_exact(3) {
            mesh.vertices.push([v[0], v[1], v[2]]);
        }
        for t in m.mesh.indices.chunks_exact(3) {
            mesh.triangles.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    if mesh.triangles.is_empty() {
        return Err("no triangles".into());
    }
    mesh.check_finite()?;
    Ok(mesh)
}

/// The unit square `[-1, 1]²` in the plane y = 0, normal +y (two triangles).
pub fn quad() -> Mesh {
    Mesh {
        vertices: vec![
            [-1.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [1.0, 0.0, 1.0],
            [-1.0, 0.0, 1.0],
        ],
        triangles: vec![[0, 2, 1], [0, 3, 2]],
    }
}

/// The box `[-1, 1]³` (12 triangles).
pub fn cube() -> Mesh {
    let mut vertices = Vec::new();
    for i in 0..8u32 {
        vertices.push([0, 1, 2].map(|a| if i >> a & 1 == 1 { 1.0 } else { -1.0 }));
    }
    // faces as corner quads (bit patterns)
    let faces = [
        [0, 2, 6, 4],
        [1, 5, 7, 3],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 6, 7, 5],
    ];
    let mut triangles = Vec::new();
    for f in faces {
        triangles.push([f[0], f[1], f[2]]);
        triangles.push([f[0], f[2], f[3]]);
    }
    Mesh {
        vertices,
        triangles,
    }
}

/// Unit icosphere with `subdivisions` rounds of 4:1 splitting (20·4^s triangles).
pub fn icosphere(subdivisions: u32) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<DVec3> = vec![
        DVec3::new(-1.0, t, 0.0),
        DVec3::new(1.0, t, 0.0),
        DVec3::new(-1.0, -t, 0.0),
        DVec3::new(1.0, -t, 0.0),
        DVec3::new(0.0, -1.0, t),
        DVec3::new(0.0, 1.0, t),
        DVec3::new(0.0, -1.0, -t),
        DVec3::new(0.0, 1.0, -t),
        DVec3::new(t, 0.0, -1.0),
        DVec3::new(t, 0.0, 1.0),
        DVec3::new(-t, 0.0, -1.0),
        DVec3::new(-t, 0.0, 1.0),
    ];
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mid = std::collections::HashMap::new();
        let mut nf = Vec::with_capacity(f.len() * 4);
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<DVec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *mid.entry(key).or_insert_with(|| {
                v.push((v[a as usize] + v[b as usize]) / 2.0);
                v.len() as u32 - 1
            })
        };
        for [a, b, c] in f {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            nf.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = nf;
    }
    Mesh {
        vertices: v
            .into_iter()
            .map(|p| unit_by_division!(p).as_vec3().to_array())
            .collect(),
        triangles: f,
    }
}

/// splitmix64 step, for reproducible procedural geometry and sampling.
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Uniform in [0, 1) from a hash of `(seed, k)`.
pub fn unit(seed: u64, k: u64) -> f64 {
    (mix(seed ^ mix(k)) >> 11) as f64 / (1u64 << 53) as f64
}

/// A patch `[-size, size]²` (y = 0 up) of `blades` grass blades / hairs: each a
/// strip of `segments` quads, `height` tall, `width` wide at the root tapering to
/// a point, leaning and curving in a random direction. Long, thin, tilted
/// triangles: their boxes are mostly empty, the worst case for box tests and
/// the best for cull planes.
pub fn grass(blades: u32, segments: u32, height: f32, width: f32, size: f32, seed: u64) -> Mesh {
    let mut m = Mesh::default();
    let segs = segments.max(1);
    for b in 0..blades as u64 {
        let r = |k: u64| unit(seed, b * 16 + k);
        let x = (2.0 * r(0) - 1.0) * size as f64;
        let z = (2.0 * r(1) - 1.0) * size as f64;
        let h = height as f64 * (0.6 + 0.8 * r(2));
        let lean_dir = 2.0 * std::f64::consts::PI * r(3);
        let lean = 0.15 + 0.6 * r(4); // horizontal offset at the tip, in units of h
        let face = 2.0 * std::f64::consts::PI * r(5);
        let (wx, wz) = (
            face.cos() * width as f64 / 2.0,
            face.sin() * width as f64 / 2.0,
        );
        let base = m.vertices.len() as u32;
        for s in 0..=segs {
            let f = s as f64 / segs as f64;
            let off = lean * h * f * f; // curved
            let cx = x + lean_dir.cos() * off;
            let cz = z + lean_dir.sin() * off;
            let y = h * f * (1.0 - 0.25 * lean * f);
            let taper = 1.0 - f * 0.95;
            m.vertices
                .push([(cx - wx * taper) as f32, y as f32, (cz - wz * taper) as f32]);
            m.vertices
                .push([(cx + wx * taper) as f32, y as f32, (cz + wz * taper) as f32]);
        }
        for s in 0..segs {
            let a = base + 2 * s;
            m.triangles.push([a, a + 1, a + 3]);
            m.triangles.push([a, a + 3, a + 2]);
        }
    }
    m
}

/// Number of triangles and bounds, for reports.
pub fn describe(m: &Mesh) -> String {
    let (lo, hi) = m.bounds();
    format!(
        "{} triangles, {} vertices, bounds [{:.3}, {:.3}, {:.3}]..[{:.3}, {:.3}, {:.3}]",
        m.triangles.len(),
        m.vertices.len(),
        lo[0],
        lo[1],
        lo[2],
        hi[0],
        hi[1],
        hi[2]
    )
}
