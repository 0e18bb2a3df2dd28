//! Records end-to-end cross-check throughput (golden model + Verilator +
//! comparison) in vectors per second, on one harness process and on one per
//! core (`CheckOptions::jobs`, what `rtl-gen check --jobs` sets). Prints
//! figures; the targets are read by people, not asserted.
//!
//! `cargo bench -p rtl-flow --bench check_throughput [-- VECTORS]`

use rtl_flow::{self, regress};
use std::time::Instant;

fn main() {
    let vectors: u64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(20_000_000);
    let cache = sim::default_cache_root();
    let cores = regress::all_cores();
    println!("{cores} cores; {vectors} vectors per run (fadd: a tenth)");
    println!(
        "{:<28} {:>5} {:>12} {:>9} {:>14}  per worker",
        "module", "jobs", "vectors", "seconds", "vectors/s"
    );
    let configs: [(&str, &[&str]); 4] = [
        ("mulcmp", &["stages=2", "a_width=16", "b_width=16"]),
        ("mulcmp", &["stages=0", "a_width=8", "b_width=8"]),
        ("mulcmp", &["stages=4", "a_width=32", "b_width=32"]),
        ("fadd", &["exp_bits=8", "frac_bits=23", "stages=2"]),
    ];
    for (unit, params) in configs {
        let params: Vec<String> = params.iter().map(|s| s.to_string()).collect();
        let g = rtl_flow::generate(unit, &params).expect("generate");
        let dir = std::env::temp_dir().join(format!("rtl-gen-bench-{}", g.module.name));
        g.write(&dir, 10.0).expect("write");
        let h = sim::Harness::build(&g.ports, &dir, &cache).expect("harness");
        let tb = g.testbench();
        let n = if unit == "fadd" {
            vectors / 10
        } else {
            vectors
        };
        let mut job_counts = vec![1, cores];
        job_counts.dedup();
        for jobs in job_counts {
            let opts = sim::CheckOptions {
                vectors: n,
                seed: 1,
                jobs,
                ..Default::default()
            };
            let t = Instant::now();
            let report = sim::cross_check(&h, tb.as_ref(), tb.as_ref(), &opts).expect("check");
            let secs = t.elapsed().as_secs_f64();
            assert_eq!(report.mismatches, 0, "{report}");
            let each: Vec<String> = report
                .workers
                .iter()
                .map(|w| format!("{:.1}M", w.vectors_per_sec() / 1e6))
                .collect();
            println!(
                "{:<28} {:>5} {:>12} {:>9.2} {:>14.0}  {}",
                g.module.name,
                jobs,
                n,
                secs,
                n as f64 / secs,
                each.join(" ")
            );
        }
    }
}
