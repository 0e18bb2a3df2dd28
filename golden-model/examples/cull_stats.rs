//! Cull-plane figures on a mesh: the fraction of leaf visits and triangle
//! tests the planes remove, per K, for random rays (issue #6).
//!
//! ```text
//! cargo run --release -p golden-model --example cull_stats -- MESH.obj
//!     [--rays N] [--leaf L] [--plane E,F] [--seed S] [--check]
//! ```
//! Rays start on a sphere around the mesh and aim at a uniform point of its
//! box; the segment is `[0, +inf)` and every leaf it may reach is counted
//! (see `golden_model::cull::stats`). `--check` tests every culled leaf
//! exactly against its triangles and reports wrongful culls (must be 0).

use golden_model::cull::builder::{build_planes, BuildParams};
use golden_model::cull::bvh::{parse_obj, Bvh};
use golden_model::cull::stats::{random_rays, trace, Counts};
use golden_model::cull::tester::Config;
use golden_model::float::FloatFormat;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut path = None;
    let mut rays = 20_000usize;
    let mut leaf = 4usize;
    let mut plane = FloatFormat::BINARY16;
    let mut seed = 1u64;
    let mut check = false;
    let mut i = 0;
    while i < args.len() {
        let val = |i: usize| args.get(i + 1).cloned().unwrap_or_else(|| usage());
        match args[i].as_str() {
            "--rays" => {
                rays = val(i).parse().unwrap_or_else(|_| usage());
                i += 1;
            }
            "--leaf" => {
                leaf = val(i).parse().unwrap_or_else(|_| usage());
                i += 1;
            }
            "--seed" => {
                seed = val(i).parse().unwrap_or_else(|_| usage());
                i += 1;
            }
            "--plane" => {
                let v = val(i);
                let (e, f) = v.split_once(',').unwrap_or_else(|| usage());
                plane = FloatFormat::new(
                    e.parse().unwrap_or_else(|_| usage()),
                    f.parse().unwrap_or_else(|_| usage()),
                )
                .unwrap_or_else(|e| {
                    eprintln!("{e}");
                    std::process::exit(2)
                });
                i += 1;
            }
            "--check" => check = true,
            "-h" | "--help" => usage(),
            p if path.is_none() => path = Some(p.to_string()),
            _ => usage(),
        }
        i += 1;
    }
    let path = path.unwrap_or_else(|| usage());
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        eprintln!("{path}: {e}");
        std::process::exit(2)
    });
    let mesh = parse_obj(&text).unwrap_or_else(|e| {
        eprintln!("{path}: {e}");
        std::process::exit(2)
    });
    let t0 = Instant::now();
    let bvh = Bvh::build(&mesh, leaf);
    let leaves = bvh
        .nodes
        .iter()
        .filter(|n| matches!(n.kind, golden_model::cull::bvh::NodeKind::Leaf { .. }))
        .count();
    println!(
        "{path}: {} vertices, {} triangles; BVH {} nodes, {} leaves (median split, <= {leaf} triangles), built in {:.2} s",
        mesh.vertices.len(),
        mesh.triangles.len(),
        bvh.nodes.len(),
        leaves,
        t0.elapsed().as_secs_f64()
    );
    println!(
        "{rays} random rays (seed {seed}), rays binary32, planes e{}m{}{}",
        plane.exp_bits(),
        plane.frac_bits(),
        if check {
            ", culled leaves checked exactly"
        } else {
            ""
        }
    );
    println!();
    println!("| K | leaf visits (box only) | with planes | removed | triangle tests (box only) | with planes | removed | nodes culled | plane build s |{}", if check { " wrongful culls |" } else { "" });
    println!(
        "|---|---|---|---|---|---|---|---|---|{}",
        if check { "---|" } else { "" }
    );
    let rs = random_rays(&mesh, rays, seed);
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    for k in [2usize, 4, 8] {
        let t1 = Instant::now();
        let planes = build_planes(
            &mesh,
            &bvh,
            &BuildParams {
                plane,
                k,
                samples: 6,
            },
        );
        let build_s = t1.elapsed().as_secs_f64();
        let cfg = Config::new(FloatFormat::BINARY32, plane, k).expect("valid configuration");
        let mut total = Counts::default();
        std::thread::scope(|s| {
            let handles: Vec<_> = rs
                .chunks(rs.len().div_ceil(threads).max(1))
                .map(|chunk| {
                    let (cfg, mesh, bvh, planes) = (&cfg, &mesh, &bvh, &planes);
                    s.spawn(move || {
                        let mut c = Counts::default();
                        for r in chunk {
                            c.add(&trace(cfg, mesh, bvh, planes, r, check));
                        }
                        c
                    })
                })
                .collect();
            for h in handles {
                total.add(&h.join().expect("worker"));
            }
        });
        println!(
            "| {k} | {} | {} | {:.1} % | {} | {} | {:.1} % | {} | {build_s:.1} |{}",
            total.leaf_visits,
            total.leaf_visits_planes,
            100.0 * total.leaf_saving(),
            total.tri_tests,
            total.tri_tests_planes,
            100.0 * total.tri_saving(),
            total.culled_nodes,
            if check {
                format!(" {} of {} |", total.wrongful_culls, total.checked_leaves)
            } else {
                String::new()
            }
        );
        if check && total.wrongful_culls != 0 {
            std::process::exit(1);
        }
    }
}

fn usage() -> ! {
    eprintln!(
        "usage: cull_stats MESH.obj [--rays N] [--leaf L] [--plane E,F] [--seed S] [--check]"
    );
    std::process::exit(2)
}
