//! Records end-to-end cross-check throughput (golden model + Verilator +
//! comparison) for the demo unit, in vectors per second. Prints figures; the
//! targets are read by people, not asserted.
//!
//! `cargo bench -p rtl-gen --bench check_throughput [-- VECTORS]`

use rtl_gen::flow;
use std::time::Instant;

fn main() {
    let vectors: u64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(20_000_000);
    let cache = sim::default_cache_root();
    println!(
        "{:<22} {:>12} {:>10} {:>14}",
        "module", "vectors", "seconds", "vectors/s"
    );
    for params in [
        ["stages=2", "a_width=16", "b_width=16"],
        ["stages=0", "a_width=8", "b_width=8"],
        ["stages=4", "a_width=32", "b_width=32"],
    ] {
        let params: Vec<String> = params.iter().map(|s| s.to_string()).collect();
        let g = flow::generate("mulcmp", &params).expect("generate");
        let dir = std::env::temp_dir().join(format!("rtl-gen-bench-{}", g.module.name));
        g.write(&dir, 10.0).expect("write");
        let h = sim::Harness::build(&g.ports, &dir, &cache).expect("harness");
        let tb = g.testbench();
        let opts = sim::CheckOptions {
            vectors,
            seed: 1,
            ..Default::default()
        };
        let t = Instant::now();
        let report = sim::cross_check(&h, tb.as_ref(), tb.as_ref(), &opts).expect("check");
        let secs = t.elapsed().as_secs_f64();
        assert_eq!(report.mismatches, 0, "{report}");
        println!(
            "{:<22} {:>12} {:>10.2} {:>14.0}",
            g.module.name,
            vectors,
            secs,
            vectors as f64 / secs
        );
    }
}
