//! The cull-plane tester, end to end: generate, lint (`verilator -Wall`),
//! simulate 1,000,000 vectors per configuration in Verilator (K = 2 and 4;
//! 200,000 for the extra K = 1 and 8, to keep CI time low) and compare every
//! output bit with the golden model; the IR evaluator runs a shorter stream
//! as the third opinion.

mod common;

use common::{cross_check, generate};

/// (exp_bits, frac_bits, plane_exp_bits, plane_frac_bits, k, stages)
const CONFIGS: &[(u32, u32, u32, u32, u32, u32)] = &[(5, 10, 4, 3, 2, 0), (8, 23, 5, 10, 4, 3)];

/// The other ends of K: one plane (bfloat16 planes) and eight (the
/// binary32 / e5m10 cost configuration at 4 stages), 200,000 vectors each.
const EXTRA_CONFIGS: &[(u32, u32, u32, u32, u32, u32)] =
    &[(8, 23, 8, 7, 1, 1), (8, 23, 5, 10, 8, 4)];
const EXTRA_VECTORS: u64 = 200_000;

fn params(c: &(u32, u32, u32, u32, u32, u32)) -> Vec<String> {
    vec![
        format!("exp_bits={}", c.0),
        format!("frac_bits={}", c.1),
        format!("plane_exp_bits={}", c.2),
        format!("plane_frac_bits={}", c.3),
        format!("k={}", c.4),
        format!("stages={}", c.5),
    ]
}

#[test]
fn cull_evaluator_matches_golden_model() {
    for c in CONFIGS.iter().chain(EXTRA_CONFIGS) {
        let p = params(c);
        let p: Vec<&str> = p.iter().map(String::as_str).collect();
        let (g, _) = generate("cull_eval", "cull", &p);
        assert_eq!(g.module.latency, c.5);
        let r = g.evaluate(g.testbench().as_ref(), 3_000, 11);
        assert_eq!(
            (r.vectors, r.mismatches),
            (3_000, 0),
            "{}: {r}",
            g.module.name
        );
    }
}

#[test]
fn cull_matches_golden_model_on_a_million_vectors_per_configuration() {
    for c in CONFIGS {
        let p = params(c);
        let p: Vec<&str> = p.iter().map(String::as_str).collect();
        let (g, dir) = generate("cull_million", "cull", &p);
        let report = cross_check(&g, &dir, 1_000_000, 7);
        assert_eq!(report.vectors, 1_000_000);
        assert_eq!(report.mismatches, 0, "{}\n{report}", g.module.name);
        eprintln!("{}: {report}", g.module.name);
    }
}

#[test]
fn cull_k1_and_k8_match_golden_model() {
    for c in EXTRA_CONFIGS {
        let p = params(c);
        let p: Vec<&str> = p.iter().map(String::as_str).collect();
        let (g, dir) = generate("cull_k1_k8", "cull", &p);
        assert_eq!(g.module.latency, c.5);
        assert!(
            g.module.name.contains(&format!("_k{}_", c.4)),
            "{}",
            g.module.name
        );
        let report = cross_check(&g, &dir, EXTRA_VECTORS, 17);
        assert_eq!(report.vectors, EXTRA_VECTORS);
        assert_eq!(report.mismatches, 0, "{}\n{report}", g.module.name);
        eprintln!("{}: {report}", g.module.name);
    }
}
