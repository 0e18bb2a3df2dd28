//! Helpers shared by the integration tests: generate a unit into a fresh
//! directory, build its harness (cached), cross-check it.
#![allow(dead_code)] // each test file uses a subset

use rtl_flow::{self, Generated};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh directory under the target dir for one test's outputs.
pub fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// Generates `unit` with `params` and writes it into a scratch directory
/// private to `test` (tests run in parallel).
pub fn generate<S: AsRef<str>>(test: &str, unit: &str, params: &[S]) -> (Generated, PathBuf) {
    let params: Vec<String> = params.iter().map(|s| s.as_ref().to_string()).collect();
    let g = rtl_flow::generate(unit, &params)
        .unwrap_or_else(|e| panic!("generate {unit} {params:?}: {e}"));
    let dir = scratch(&format!("{test}/{}", g.module.name));
    g.write(&dir, 10.0).expect("write generated files");
    (g, dir)
}

/// Vectors `0..total` of the unit's seeded stimulus with the golden model's
/// answers, as (inputs, outputs): what a test of the stimulus's reach reads.
pub fn golden_vectors(
    g: &Generated,
    seed: u64,
    total: u64,
) -> impl Iterator<Item = (Vec<u64>, Vec<u64>)> {
    let tb = g.testbench();
    let (n_in, n_out) = (g.ports.inputs.len(), g.ports.outputs.len());
    (0..total).map(move |i| {
        let mut v = vec![0u64; n_in];
        let mut out = vec![0u64; n_out];
        tb.vector(seed, i, &mut v);
        tb.eval(&v, &mut out);
        (v, out)
    })
}

/// Lints, builds and cross-checks `vectors` vectors; returns the report.
pub fn cross_check(
    g: &Generated,
    dir: &std::path::Path,
    vectors: u64,
    seed: u64,
) -> sim::CheckReport {
    sim::lint(&g.ports, dir).unwrap_or_else(|e| panic!("lint {}: {e}", g.module.name));
    let h = sim::Harness::build(&g.ports, dir, &sim::default_cache_root()).expect("build harness");
    let tb = g.testbench();
    let opts = sim::CheckOptions {
        vectors,
        seed,
        progress: false,
        ..Default::default()
    };
    sim::cross_check(&h, tb.as_ref(), tb.as_ref(), &opts).expect("cross-check runs")
}

/// Runs `vectors` vectors of the unit's stimulus through the IR evaluator
/// against its golden model; panics on any mismatch.
pub fn evaluated(g: &Generated, vectors: u64, seed: u64) {
    let r = g.evaluate(g.testbench().as_ref(), vectors, seed);
    assert_eq!(
        (r.vectors, r.mismatches),
        (vectors, 0),
        "{}: IR evaluator: {r}",
        g.module.name
    );
}

/// Lints, builds and cross-checks `vectors` vectors in Verilator against the
/// golden model ([`cross_check`]); panics on any mismatch, prints the report.
pub fn cross_checked(
    g: &Generated,
    dir: &std::path::Path,
    vectors: u64,
    seed: u64,
) -> sim::CheckReport {
    let report = cross_check(g, dir, vectors, seed);
    assert_eq!(report.vectors, vectors);
    assert_eq!(report.mismatches, 0, "{}\n{report}", g.module.name);
    eprintln!("{}: {report}", g.module.name);
    report
}

/// The whole check of one configuration: `eval_vectors` vectors through the
/// IR evaluator, then lint, build and `vectors` vectors through Verilator,
/// each compared with the golden model; panics on any mismatch.
pub fn check_unit(
    test: &str,
    unit: &str,
    params: &[&str],
    eval_vectors: u64,
    vectors: u64,
    seed: u64,
) -> (Generated, sim::CheckReport) {
    let (g, dir) = generate(test, unit, params);
    evaluated(&g, eval_vectors, seed);
    let report = cross_checked(&g, &dir, vectors, seed);
    (g, report)
}

/// Writes the testbench `bench` as `<name>.v` into `dir`, compiles it with
/// `sources` in Icarus (`flags` first) and runs it; returns what it printed.
/// A missing Icarus fails the test with a message.
pub fn icarus(dir: &Path, name: &str, bench: &str, sources: &[PathBuf], flags: &[&str]) -> String {
    let tb = dir.join(format!("{name}.v"));
    std::fs::write(&tb, bench).expect("write the testbench");
    let exe = dir.join(format!("{name}.vvp"));
    let out = Command::new("iverilog")
        .args(flags)
        .arg("-o")
        .arg(&exe)
        .arg(&tb)
        .args(sources)
        .output()
        .unwrap_or_else(|e| panic!("iverilog (Icarus Verilog) is needed for this test: {e}"));
    assert!(
        out.status.success(),
        "iverilog: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = Command::new("vvp")
        .arg("-n")
        .arg(&exe)
        .output()
        .expect("vvp runs");
    String::from_utf8_lossy(&run.stdout).into_owned()
}
