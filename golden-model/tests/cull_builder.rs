//! The cull-plane builder (issue #6): after quantisation, no triangle vertex
//! lies strictly on the empty side of any stored plane (exact arithmetic),
//! and rays traced through the BVH with the planes never skip a triangle
//! they hit (exact segment / triangle test on every culled leaf).
//!
//! Meshes: a procedural torus, a random triangle soup, and the shared
//! scenes `teapot.obj` and `suzanne.obj` when `../shared/scenes` exists.

use golden_model::cull::builder::{build_planes, centroid, height, BuildParams};
use golden_model::cull::bvh::{parse_obj, Bvh, Mesh};
use golden_model::cull::exact::Dyadic;
use golden_model::cull::stats::{random_rays, trace, Counts, Rng};
use golden_model::cull::tester::Config;
use golden_model::float::FloatFormat;

fn torus(n: usize, m: usize) -> Mesh {
    let mut mesh = Mesh::default();
    for i in 0..n {
        for j in 0..m {
            let (u, v) = (
                i as f64 / n as f64 * std::f64::consts::TAU,
                j as f64 / m as f64 * std::f64::consts::TAU,
            );
            let r = 3.0 + v.cos();
            mesh.vertices
                .push([(r * u.cos()) as f32, (r * u.sin()) as f32, v.sin() as f32]);
        }
    }
    for i in 0..n {
        for j in 0..m {
            let a = (i * m + j) as u32;
            let b = (((i + 1) % n) * m + j) as u32;
            let c = (((i + 1) % n) * m + (j + 1) % m) as u32;
            let d = (i * m + (j + 1) % m) as u32;
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    mesh
}

fn soup(n: usize, seed: u64) -> Mesh {
    let mut rng = Rng(seed);
    let mut mesh = Mesh::default();
    for t in 0..n {
        let c = [0, 1, 2].map(|_| (rng.unit() * 20.0 - 10.0) as f32);
        for _ in 0..3 {
            let s = if t % 7 == 0 { 1e-3 } else { 1.0 };
            mesh.vertices
                .push([0, 1, 2].map(|i| c[i] + ((rng.unit() - 0.5) * s) as f32));
        }
        let b = (3 * t) as u32;
        mesh.triangles.push([b, b + 1, b + 2]);
    }
    mesh
}

fn meshes() -> Vec<(String, Mesh)> {
    let mut v = vec![
        ("torus".to_string(), torus(48, 24)),
        ("soup".to_string(), soup(1500, 7)),
    ];
    for name in ["teapot.obj", "suzanne.obj"] {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../shared/scenes")
            .join(name);
        if let Ok(text) = std::fs::read_to_string(&p) {
            v.push((name.to_string(), parse_obj(&text).expect("valid OBJ")));
        }
    }
    v
}

#[test]
fn no_vertex_lies_strictly_on_the_empty_side_of_any_stored_plane() {
    let formats = [
        FloatFormat::BINARY16,
        FloatFormat::BFLOAT16,
        FloatFormat::new(4, 3).unwrap(),
    ];
    for (name, mesh) in meshes() {
        let bvh = Bvh::build(&mesh, 4);
        for pf in formats {
            let cp = build_planes(
                &mesh,
                &bvh,
                &BuildParams {
                    plane: pf,
                    k: 8,
                    samples: 6,
                },
            );
            let (mut checked, mut stored, mut touching) = (0u64, 0u64, 0u64);
            for id in 0..bvh.nodes.len() {
                let node = bvh.nodes[id];
                let c = centroid(&node.min, &node.max);
                let mut verts: Vec<u32> = bvh
                    .subtree_tris(id)
                    .iter()
                    .flat_map(|&t| mesh.triangles[t as usize])
                    .collect();
                verts.sort_unstable();
                verts.dedup();
                let vd: Vec<[Dyadic; 3]> = verts
                    .iter()
                    .map(|&v| mesh.vertices[v as usize].map(Dyadic::from_f32))
                    .collect();
                assert!(cp.planes[id].len() <= 8);
                for p in &cp.planes[id] {
                    stored += 1;
                    let w = Dyadic::from_bits(pf, p.w).expect("finite stored distance");
                    for v in &vd {
                        let h = height(pf, &p.n, v, &c);
                        let o = h.cmp(&w);
                        assert!(
                            o.is_le(),
                            "{name} {pf}: node {id} plane {p:x?}: vertex {v:?} at {} above w = {}",
                            h.to_f64(),
                            w.to_f64()
                        );
                        touching += o.is_eq() as u64;
                        checked += 1;
                    }
                }
            }
            eprintln!(
                "{name} {pf}: {} nodes, {stored} planes stored, {checked} (plane, vertex) pairs checked exactly, {touching} vertices exactly on a plane, 0 on an empty side",
                bvh.nodes.len()
            );
            assert!(
                stored > bvh.nodes.len() as u64,
                "{name} {pf}: too few planes"
            );
        }
    }
}

#[test]
fn traversal_with_planes_never_skips_a_hit_triangle() {
    for (name, mesh) in meshes() {
        let bvh = Bvh::build(&mesh, 4);
        for (pf, k) in [
            (FloatFormat::BINARY16, 8),
            (FloatFormat::BFLOAT16, 4),
            (FloatFormat::new(4, 3).unwrap(), 2),
        ] {
            let cp = build_planes(
                &mesh,
                &bvh,
                &BuildParams {
                    plane: pf,
                    k,
                    samples: 6,
                },
            );
            let cfg = Config::new(FloatFormat::BINARY32, pf, k).unwrap();
            let mut total = Counts::default();
            for r in random_rays(&mesh, 1500, 3) {
                total.add(&trace(&cfg, &mesh, &bvh, &cp, &r, true));
            }
            eprintln!(
                "{name} {pf} k={k}: leaf visits {} -> {} ({:.1} % removed), {} culled leaves checked exactly, {} wrongful",
                total.leaf_visits,
                total.leaf_visits_planes,
                100.0 * total.leaf_saving(),
                total.checked_leaves,
                total.wrongful_culls
            );
            assert_eq!(total.wrongful_culls, 0, "{name} {pf} k={k}");
            assert!(
                total.leaf_saving() > 0.05,
                "{name} {pf} k={k}: planes remove almost nothing"
            );
        }
    }
}
