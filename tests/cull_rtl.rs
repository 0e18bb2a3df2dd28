//! The cull-plane tester's two units, end to end: generate, lint
//! (`verilator --lint-only -Wall`), simulate in Verilator and compare every
//! output bit with the golden model (`golden_model::cull::tester`); the IR
//! evaluator runs 3,000 vectors of every configuration as the third opinion.
//!
//! `cull` (per child) at K = 1, 2, 4, 8 and `cull_ray` (per ray and parent)
//! at K = 1, 4, 8: the binary32-ray / e5m10-plane K = 4 configuration at
//! 4 stages on 1,000,000 vectors each, the others (one with e5m10 rays and
//! e4m3 planes, other stage counts) on 200,000 to keep CI time low.

mod common;

use common::{cross_checked, evaluated, generate};

/// (exp_bits, frac_bits, plane_exp_bits, plane_frac_bits, k, stages, vectors)
type Case = (u32, u32, u32, u32, u32, u32, u64);

const CULL: &[Case] = &[
    (8, 23, 5, 10, 4, 4, 1_000_000),
    (8, 23, 8, 7, 1, 1, 200_000),
    (5, 10, 4, 3, 2, 0, 200_000),
    (8, 23, 5, 10, 8, 6, 200_000),
];

const CULL_RAY: &[Case] = &[
    (8, 23, 5, 10, 4, 4, 1_000_000),
    (5, 10, 4, 3, 1, 2, 200_000),
    (8, 23, 8, 7, 8, 9, 200_000),
    (8, 23, 6, 15, 2, 3, 200_000),
];

fn params(c: &Case) -> Vec<String> {
    vec![
        format!("exp_bits={}", c.0),
        format!("frac_bits={}", c.1),
        format!("plane_exp_bits={}", c.2),
        format!("plane_frac_bits={}", c.3),
        format!("k={}", c.4),
        format!("stages={}", c.5),
    ]
}

fn evaluate(unit: &str, cases: &[Case]) {
    for c in cases {
        let (g, _) = generate(&format!("{unit}_eval"), unit, &params(c));
        assert_eq!(g.module.latency, c.5);
        assert!(
            g.module.name.contains(&format!("_k{}_s{}", c.4, c.5)),
            "{}",
            g.module.name
        );
        evaluated(&g, 3_000, 11);
    }
}

fn verilate(unit: &str, cases: &[Case], seed: u64) {
    for c in cases {
        let (g, dir) = generate(&format!("{unit}_verilator"), unit, &params(c));
        cross_checked(&g, &dir, c.6, seed);
    }
}

#[test]
fn cull_evaluator_matches_golden_model() {
    evaluate("cull", CULL);
}

#[test]
fn cull_ray_evaluator_matches_golden_model() {
    evaluate("cull_ray", CULL_RAY);
}

#[test]
fn cull_matches_golden_model_in_verilator() {
    verilate("cull", CULL, 7);
}

#[test]
fn cull_ray_matches_golden_model_in_verilator() {
    verilate("cull_ray", CULL_RAY, 17);
}
