//! `raycull` (seed 002's ray-cull unit, `docs/raycull.md`) end to end:
//! generate, lint (`verilator --lint-only -Wall`), simulate in Verilator and
//! compare every output of every valid cycle with
//! `golden_model::raycull::cull` on 10^6 vectors per configuration for three
//! configurations (each depth format, a strict and a non-strict mode, both
//! directions, groups of 1, 2 and 4, 0-2 stages); the IR evaluator runs
//! 20,000 vectors of every format × compare mode. The stimulus reaches every
//! verdict (test below), so the comparisons are not all of idle outputs.

mod common;

use common::{cross_checked, evaluated, generate};
use rtl_gen::units::ports;
use rtl_gen::units::raycull::{Compare, Config, Depth, RayCullIn, RayCullOut};

/// (depth, compare, gen_bits, prim_bits, group, stages)
type Case = (&'static str, &'static str, u32, u32, u32, u32);

const VERILATED: &[Case] = &[
    ("unorm24", "less", 3, 20, 4, 1),
    ("binary32", "greater", 3, 16, 2, 2),
    ("unorm16", "lequal", 1, 8, 1, 0),
];

fn params(c: &Case) -> Vec<String> {
    vec![
        format!("depth={}", c.0),
        format!("compare={}", c.1),
        format!("gen_bits={}", c.2),
        format!("prim_bits={}", c.3),
        format!("group={}", c.4),
        format!("stages={}", c.5),
    ]
}

fn gen(test: &str, c: &Case) -> (rtl_flow::Generated, std::path::PathBuf) {
    let p = params(c);
    let p: Vec<&str> = p.iter().map(String::as_str).collect();
    generate(test, "raycull", &p)
}

#[test]
fn raycull_evaluator_matches_golden_model_in_every_format_and_mode() {
    for (i, depth) in ["unorm16", "unorm24", "binary32"].iter().enumerate() {
        for (j, cmp) in ["less", "lequal", "greater", "gequal"].iter().enumerate() {
            let c: Case = (
                depth,
                cmp,
                1 + (i + j) as u32 % 4,
                12,
                1 + (i + 2 * j) as u32 % 4,
                (i + j) as u32 % 3,
            );
            let (g, _) = gen("raycull_eval", &c);
            assert_eq!(g.module.latency, c.5);
            evaluated(&g, 20_000, 5);
        }
    }
}

#[test]
fn raycull_matches_golden_model_in_verilator() {
    for c in VERILATED {
        let (g, dir) = gen("raycull_verilator", c);
        cross_checked(&g, &dir, 1_000_000, 3);
    }
}

/// The golden outputs of 20,000 stimulus vectors hold every verdict: tile,
/// depth and generation culls, group culls, current and stale slots, bad
/// slots (binary32), and kept (not culled) valid slots.
#[test]
fn raycull_stimulus_reaches_every_verdict() {
    for (depth, cmp) in [("binary32", "less"), ("unorm16", "gequal")] {
        let c: Case = (depth, cmp, 3, 12, 4, 1);
        let (g, _) = gen("raycull_cover", &c);
        let tb = g.testbench();
        let cfg = Config {
            depth: if depth == "binary32" {
                Depth::Binary32
            } else {
                Depth::Unorm16
            },
            compare: if cmp == "less" {
                Compare::Less
            } else {
                Compare::GEqual
            },
            gen_bits: 3,
            prim_bits: 12,
            group: 4,
            stages: 1,
        };
        let n_in = ports::list::<RayCullIn<()>>(&cfg).len();
        let n_out = ports::list::<RayCullOut<()>>(&cfg).len();
        let mut seen = [0u64; 7];
        let total = 20_000;
        for i in 0..total {
            let mut v = vec![0u64; n_in];
            let mut out = vec![0u64; n_out];
            tb.vector(3, i, &mut v);
            tb.eval(&v, &mut out);
            let o: RayCullOut<u64> = ports::unpack(&cfg, &out);
            seen[0] += o.group_cull;
            for k in 0..4 {
                seen[1] += o.tile_cull[k];
                seen[2] += o.depth_cull[k];
                seen[3] += o.generation_cull[k];
                seen[4] += o.current[k];
                seen[5] += o.bad.as_ref().map_or(0, |b| b[k]);
                seen[6] += 1 - o.cull[k];
            }
        }
        eprintln!("{depth} {cmp}: group, tile, depth, generation, current, bad, kept = {seen:?}");
        for (k, &s) in seen.iter().enumerate() {
            if k == 5 && depth != "binary32" {
                assert!(o_has_no_flags(&cfg), "unorm codes are never bad");
                continue;
            }
            assert!(s > total / 100, "verdict {k}: {seen:?}");
        }
    }
}

/// A unorm configuration has no bad flags (every code is valid).
fn o_has_no_flags(cfg: &Config) -> bool {
    !ports::list::<RayCullOut<()>>(cfg)
        .iter()
        .any(|p| p.0.ends_with("bad"))
}

/// `tilerange` (the tile's depth range that `raycull`'s tile stage reads,
/// `golden_model::raycull::tile_range`): the IR evaluator in every format
/// with 1, 5 and 64 samples at 0-2 stages (20,000 vectors each), Verilator
/// at 10^6 vectors for a 4x4 tile of unorm24 codes (the 8x8 tile's 10^6 take
/// 8 s: `rtl-gen check tilerange`, docs/raycull.md §5); and the stimulus makes
/// every position the minimum and the maximum and both drop-farther values.
#[test]
fn tilerange_matches_golden_model() {
    use rtl_gen::units::tilerange::{Config as TConfig, TileRangeIn, TileRangeOut};
    for (i, depth) in ["unorm16", "unorm24", "binary32"].iter().enumerate() {
        for (j, n) in [1u32, 5, 64].iter().enumerate() {
            let p = [
                format!("depth={depth}"),
                format!("samples={n}"),
                format!("stages={}", (i + j) % 3),
            ];
            let p: Vec<&str> = p.iter().map(String::as_str).collect();
            let (g, _) = generate("tilerange_eval", "tilerange", &p);
            evaluated(&g, 20_000, 5);
        }
    }
    let (g, dir) = generate("tilerange_verilator", "tilerange", &["samples=16"]);
    cross_checked(&g, &dir, 1_000_000, 3);

    let cfg = TConfig {
        depth: Depth::Unorm16,
        samples: 64,
        stages: 1,
    };
    let (n_in, n_out) = (
        ports::list::<TileRangeIn<()>>(&cfg).len(),
        ports::list::<TileRangeOut<()>>(&cfg).len(),
    );
    let (g16, _) = generate("tilerange_cover", "tilerange", &["depth=unorm16"]);
    let tb16 = g16.testbench();
    let (mut min_at, mut max_at) = (vec![false; 64], vec![false; 64]);
    let mut opaque = [0u64; 2];
    for k in 0..20_000 {
        let (mut v, mut out) = (vec![0u64; n_in], vec![0u64; n_out]);
        tb16.vector(3, k, &mut v);
        tb16.eval(&v, &mut out);
        let x: TileRangeIn<u64> = ports::unpack(&cfg, &v);
        let o: TileRangeOut<u64> = ports::unpack(&cfg, &out);
        let (lo, hi) = (x.depth.iter().min().unwrap(), x.depth.iter().max().unwrap());
        if lo < hi {
            let only = |c: &u64| x.depth.iter().filter(|&d| d == c).count() == 1;
            if only(lo) {
                min_at[x.depth.iter().position(|d| d == lo).unwrap()] = true;
            }
            if only(hi) {
                max_at[x.depth.iter().position(|d| d == hi).unwrap()] = true;
            }
        }
        opaque[o.tile_drop_farther as usize] += 1;
    }
    assert!(min_at.iter().all(|&b| b) && max_at.iter().all(|&b| b));
    assert!(
        opaque.iter().all(|&n| n > 1_000),
        "drop-farther 0/1: {opaque:?}"
    );
}
