//! Shared by the IR-evaluator tests: generate a unit, and cross-check
//! vectors from the start (the corner list) and from far beyond it against
//! the golden model.

use rtl_flow::{self, Generated, Skipped};

pub fn gen(unit: &str, params: &[&str]) -> Generated {
    let p: Vec<String> = params.iter().map(|s| s.to_string()).collect();
    rtl_flow::generate(unit, &p).unwrap_or_else(|e| panic!("generate {unit} {params:?}: {e}"))
}

/// `corners` vectors from the start (strided over the whole corner list)
/// and `random` vectors from far beyond the corners.
pub fn check(unit: &str, params: &[&str], stages: u32, corners: u64, random: u64) {
    let g = gen(unit, params);
    assert_eq!(g.module.latency, stages, "{}", g.module.name);
    let tb = g.testbench();
    for (first, n) in [(0, corners), (1_000_000, random)] {
        let r = g.evaluate(
            &Skipped {
                of: tb.as_ref(),
                first,
            },
            n,
            5,
        );
        eprintln!("{} from {first}: {r}", g.module.name);
        assert_eq!(
            (r.vectors, r.mismatches),
            (n, 0),
            "{} from vector {first}: {r}",
            g.module.name
        );
    }
}
