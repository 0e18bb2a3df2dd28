//! The node tester's RTL blocks end to end: generate, lint (`verilator
//! --lint-only -Wall`), simulate in Verilator and compare every output bit
//! with the golden model; the IR evaluator runs 3,000 vectors of every
//! configuration as the third opinion.
//!
//! `node_sort` (`golden_model::node::sort`): the default (N = 4, q = 8,
//! 1 stage) on 200,000 vectors and N = 8 on 50,000 in Verilator, N = 2 and
//! q = 12, 16 at other stage counts in the evaluator. `node_child`
//! (`golden_model::node::child`): the default (q = 8, 2 stages) on 200,000
//! vectors and q = 12 on 30,000 in Verilator, q = 4 in the evaluator; and
//! its stimulus reaches hits, misses and entries away from the window
//! start. `rtl-gen check` runs the others at 10^6 (docs/node.md §7-8).
//! `node` (`golden_model::node_reorigin::eval`, the unit a wide render
//! uses): N = 4, 8, 2 at q = 8, 8, 12 on 10^6 vectors each in Verilator,
//! five more shapes and formats (e3m2 and e5m10 among them) in the evaluator,
//! and its stimulus reaches every kind of answer.

mod common;

use common::{cross_checked, evaluated, generate, golden_vectors};
use rtl_gen::units::node_child::{Config as ChildConfig, NodeChildOut};
use rtl_gen::units::ports;

/// (children, box_bits, stages, Verilator vectors; 0: the evaluator only,
/// to keep the Verilator builds few)
type Case = (u32, u32, u32, u64);

const CASES: &[Case] = &[
    (4, 8, 1, 200_000),
    (2, 8, 0, 0),
    (8, 8, 2, 50_000),
    (4, 12, 0, 0),
    (8, 16, 4, 0),
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
        let (g, _) = generate("node_sort_eval", "node_sort", &params(c));
        assert_eq!(g.module.latency, c.2);
        assert_eq!(
            g.module.name,
            format!("node_sort_n{}_q{}_s{}", c.0, c.1, c.2)
        );
        evaluated(&g, 3_000, 11);
    }
}

#[test]
fn node_sort_matches_golden_model_in_verilator() {
    for c in CASES.iter().filter(|c| c.3 > 0) {
        let (g, dir) = generate("node_sort_verilator", "node_sort", &params(c));
        cross_checked(&g, &dir, c.3, 7);
    }
}

/// (box_bits, stages, Verilator vectors; 0: the evaluator only)
const CHILD_CASES: &[(u32, u32, u64)] = &[(8, 2, 200_000), (4, 0, 0), (12, 5, 30_000)];

fn child_params(c: &(u32, u32, u64)) -> Vec<String> {
    vec![format!("box_bits={}", c.0), format!("stages={}", c.1)]
}

#[test]
fn node_child_evaluator_matches_golden_model() {
    for c in CHILD_CASES {
        let (g, _) = generate("node_child_eval", "node_child", &child_params(c));
        assert_eq!(g.module.latency, c.1);
        assert_eq!(g.module.name, format!("node_child_q{}_s{}", c.0, c.1));
        evaluated(&g, 3_000, 11);
    }
}

#[test]
fn node_child_matches_golden_model_in_verilator() {
    for c in CHILD_CASES.iter().filter(|c| c.2 > 0) {
        let (g, dir) = generate("node_child_verilator", "node_child", &child_params(c));
        cross_checked(&g, &dir, c.2, 7);
    }
}

/// The stimulus is not all misses: the golden outputs of 20,000 vectors
/// hold hits (some with an entry past the window start) and misses.
#[test]
fn node_child_stimulus_reaches_hits_misses_and_entries() {
    let (g, _) = generate::<&str>("node_child_cover", "node_child", &[]);
    let cfg = ChildConfig {
        box_bits: 8,
        stages: 2,
    };
    let (mut hits, mut far_entries) = (0, 0);
    let total = 20_000;
    for (_, out) in golden_vectors(&g, 3, total) {
        let o: NodeChildOut<u64> = ports::unpack(&cfg, &out);
        if o.hit == 1 {
            hits += 1;
            far_entries += (o.entry > 0) as u64;
        }
    }
    eprintln!("node_child stimulus: {hits} hits of {total}, {far_entries} with entry > 0");
    assert!(
        hits > total / 20 && hits < total * 19 / 20,
        "{hits} hits of {total}"
    );
    assert!(
        far_entries > total / 100,
        "{far_entries} hits with entry > 0"
    );
}

/// `node` (children, box_bits, slope_bits, start_bits, format, stages, products,
/// Verilator vectors; 0: the evaluator only). Both product structures: `whole` shifts each
/// slope once per node, `split` each distance per child; start bits below the format's
/// precision (binary32 at 18, 17 and 9, e5m10 at 6) round the start down.
type NodeCase = (u32, u32, u32, u32, &'static str, u32, &'static str, u64);

const NODE_CASES: &[NodeCase] = &[
    (4, 8, 9, 18, "binary32", 4, "whole", 1_000_000),
    (8, 8, 9, 18, "binary32", 2, "split", 1_000_000),
    (2, 12, 8, 17, "binary32", 1, "split", 1_000_000),
    (2, 8, 8, 9, "binary32", 0, "split", 0),
    (8, 8, 9, 18, "binary32", 0, "whole", 0),
    (4, 12, 12, 17, "binary32", 0, "whole", 0),
    (4, 16, 8, 17, "binary32", 3, "split", 0),
    (4, 16, 8, 17, "binary32", 3, "whole", 0),
    (4, 8, 8, 6, "e5m10", 1, "whole", 0),
    (2, 4, 8, 17, "e3m2", 2, "split", 0),
    (2, 4, 8, 17, "e3m2", 2, "whole", 0),
];

fn node_params(c: &NodeCase) -> Vec<String> {
    let (e, f) = match c.4 {
        "binary32" => (8, 23),
        "e5m10" => (5, 10),
        "e3m2" => (3, 2),
        other => panic!("format {other}"),
    };
    vec![
        format!("children={}", c.0),
        format!("box_bits={}", c.1),
        format!("slope_bits={}", c.2),
        format!("start_bits={}", c.3),
        format!("exp_bits={e}"),
        format!("frac_bits={f}"),
        format!("stages={}", c.5),
        format!("products={}", c.6),
    ]
}

#[test]
fn node_evaluator_matches_golden_model() {
    for c in NODE_CASES {
        let (g, _) = generate("node_eval", "node", &node_params(c));
        assert_eq!(g.module.latency, c.5);
        evaluated(&g, 3_000, 11);
    }
}

/// The `node` stimulus reaches every kind of answer: bad input, nodes where
/// every slot misses, hits with entries past `T` and on the cap, misses
/// beside hits in one node, frames at both ends of the format, and position
/// windows both at their floor and above it (under their largest term).
#[test]
fn node_stimulus_reaches_every_kind_of_answer() {
    use rtl_gen::units::node::{Config as NodeConfig, NodeIn, NodeOut, POS_FRAC, WINDOW_FLOOR};
    let (g, _) = generate::<&str>("node_cover", "node", &[]);
    let cfg = NodeConfig {
        fmt: rtl_gen::arith::float::Format::new(8, 23).unwrap(),
        children: 4,
        box_bits: 8,
        slope_bits: 9,
        start_bits: 18,
        stages: 4,
        products: rtl_gen::retime::Products::Split,
    };
    let cap = 1u64 << cfg.cap_bits();
    let (mut bad, mut empty, mut hits, mut inner, mut capped, mut mixed) = (0, 0, 0, 0, 0, 0);
    // position windows surely above their floor: a term beyond 2^(e − g − f + W + 1), where
    // the window rides under its largest term (the path the e3m2 split proof never reaches);
    // surely at the floor: every term below 2^(e − g − f + W − 2)
    let above_floor = (cfg.window_bits() - POS_FRAC - WINDOW_FLOOR + 1) as i32;
    let exp_bits = cfg.frame_exp_bits();
    let (mut riding, mut grounded) = (0, 0);
    let total = 20_000;
    for (v, out) in golden_vectors(&g, 3, total) {
        let o: NodeOut<u64> = ports::unpack(&cfg, &out);
        let r: NodeIn<u64> = ports::unpack(&cfg, &v);
        if o.bad == 1 {
            bad += 1;
            continue;
        }
        let f = |bits: u64| f64::from(f32::from_bits(bits as u32));
        let t = f(r.t_min).max(f(r.t_start));
        for a in 0..3 {
            let e = ((r.exp[a] << (64 - exp_bits)) as i64 >> (64 - exp_bits)) as i32;
            let td = if t.is_finite() { t * f(r.d[a]) } else { 0.0 };
            let largest = f(r.o[a]).abs().max(f(r.origin[a]).abs()).max(td.abs());
            riding += (largest > 2f64.powi(e + above_floor)) as u64;
            grounded += (largest < 2f64.powi(e + above_floor - 3)) as u64;
        }
        let n_hits = o.hit.iter().filter(|&&h| h == 1).count();
        hits += n_hits;
        empty += (n_hits == 0) as u64;
        mixed += (n_hits > 0 && n_hits < r.valid.count_ones() as usize) as u64;
        for j in 0..n_hits {
            inner += (o.entry[j] > 0 && o.entry[j] < cap) as u64;
            capped += (o.entry[j] == cap) as u64;
        }
    }
    eprintln!(
        "node stimulus of {total}: {bad} bad, {empty} with no hit, {hits} hits ({inner} inside the window, {capped} at the cap), {mixed} nodes with hits and misses"
    );
    assert!(bad > total / 50 && bad < total / 4, "{bad} bad of {total}");
    assert!(empty > total / 20, "{empty} nodes without a hit");
    assert!(inner > total / 10, "{inner} hits inside the window");
    assert!(capped > 0, "no hit at the cap");
    assert!(mixed > total / 10, "{mixed} nodes with hits and misses");
    eprintln!("position windows: {riding} above their floor, {grounded} at it");
    assert!(
        riding > total / 50,
        "{riding} position windows above their floor"
    );
    assert!(
        grounded > total,
        "{grounded} position windows at their floor"
    );
}

#[test]
fn node_matches_golden_model_in_verilator() {
    for c in NODE_CASES.iter().filter(|c| c.7 > 0) {
        let (g, dir) = generate("node_verilator", "node", &node_params(c));
        cross_checked(&g, &dir, c.7, 7);
    }
}
