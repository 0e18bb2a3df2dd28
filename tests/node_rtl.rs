//! The node tester's sort network `node_sort`, end to end: generate, lint
//! (`verilator --lint-only -Wall`), simulate in Verilator and compare every
//! output bit with the golden model (`golden_model::node::sort`); the IR
//! evaluator runs 3,000 vectors of every configuration as the third opinion.
//!
//! The default configuration (N = 4, q = 8, 1 stage) on 200,000 vectors,
//! N = 2, 8 and q = 12, 16 at other stage counts on 50,000 each.

mod common;

use common::{cross_check, generate};

/// (children, box_bits, stages, vectors)
type Case = (u32, u32, u32, u64);

const CASES: &[Case] = &[
    (4, 8, 1, 200_000),
    (2, 8, 0, 50_000),
    (8, 8, 2, 50_000),
    (4, 12, 0, 50_000),
    (8, 16, 4, 50_000),
];

fn params(c: &Case) -> Vec<String> {
    vec![
        format!("children={}", c.0),
        format!("box_bits={}", c.1),
        format!("stages={}", c.2),
    ]
}

#[test]
fn node_sort_evaluator_matches_golden_model() {
    for c in CASES {
        let p = params(c);
        let p: Vec<&str> = p.iter().map(String::as_str).collect();
        let (g, _) = generate("node_sort_eval", "node_sort", &p);
        assert_eq!(g.module.latency, c.2);
        assert_eq!(
            g.module.name,
            format!("node_sort_n{}_q{}_s{}", c.0, c.1, c.2)
        );
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
fn node_sort_matches_golden_model_in_verilator() {
    for c in CASES {
        let p = params(c);
        let p: Vec<&str> = p.iter().map(String::as_str).collect();
        let (g, dir) = generate("node_sort_verilator", "node_sort", &p);
        let report = cross_check(&g, &dir, c.3, 7);
        assert_eq!(report.vectors, c.3);
        assert_eq!(report.mismatches, 0, "{}\n{report}", g.module.name);
        eprintln!("{}: {report}", g.module.name);
    }
}
