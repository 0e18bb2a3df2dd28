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
