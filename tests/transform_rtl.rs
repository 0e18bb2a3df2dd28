//! The two-step inverse transform unit (issue #5) in Verilator: bit-exact
//! against the golden model on 1,000,000 vectors per configuration (corner
//! cases first, then seeded random vectors), after `verilator --lint-only
//! -Wall` and 2,000 vectors through the IR evaluator.
//!
//! Seven configurations (each harness build takes two to four minutes on two
//! cores, then it is cached): both sources of `R⁻¹` with every dot style,
//! both throughputs, all four rounding modes, binary32 and binary16,
//! combinational and pipelined.

mod common;

use common::generate;

/// The seven configurations: test name, parameters.
const CONFIGS: [(&str, &[&str]); 7] = [
    (
        "xf_fma",
        &["dot=fma", "throughput=full", "round=rne", "stages=8"],
    ),
    (
        "xf_sep",
        &["dot=separate", "throughput=half", "round=rdn", "stages=5"],
    ),
    (
        "xf_dot3",
        &["dot=dot3", "throughput=full", "round=rup", "stages=3"],
    ),
    (
        "xf_hw_dot3",
        &[
            "inverse=hw",
            "dot=dot3",
            "throughput=full",
            "round=rne",
            "stages=12",
        ],
    ),
    (
        "xf_hw_h_fma",
        &[
            "exp_bits=5",
            "frac_bits=10",
            "inverse=hw",
            "dot=fma",
            "throughput=half",
            "round=rtz",
            "stages=0",
            "id_bits=64",
        ],
    ),
    (
        "xf_hw_h_sep",
        &[
            "exp_bits=5",
            "frac_bits=10",
            "inverse=hw",
            "dot=separate",
            "throughput=full",
            "round=rdn",
            "stages=6",
            "id_bits=9",
        ],
    ),
    (
        "xf_wide",
        &["dot=wide", "throughput=half", "round=rne", "stages=4"],
    ),
];

fn check(k: usize) {
    let (test, params) = CONFIGS[k];
    common::check_unit(test, "transform", params, 2_000, 1_000_000, 11);
}

/// The IR evaluator of every configuration against the golden model, no
/// Verilator build (the mutation check's fast test, scripts/mutants.sh).
#[test]
fn transform_evaluator_matches_golden_model() {
    for (test, params) in CONFIGS {
        let (g, _) = generate(&format!("{test}_eval"), "transform", params);
        let r = g.evaluate(g.testbench().as_ref(), 2_000, 11);
        assert_eq!(
            (r.vectors, r.mismatches),
            (2_000, 0),
            "{}: {r}",
            g.module.name
        );
    }
}

#[test]
fn binary32_fma_full_rne_8_stages() {
    check(0);
}

#[test]
fn binary32_separate_half_rdn_5_stages() {
    check(1);
}

#[test]
fn binary32_dot3_full_rup_3_stages() {
    check(2);
}

#[test]
fn hw_inverse_binary32_dot3_full_rne_12_stages() {
    check(3);
}

#[test]
fn hw_inverse_binary16_fma_half_rtz_combinational() {
    check(4);
}

#[test]
fn hw_inverse_binary16_separate_full_rdn_6_stages() {
    check(5);
}

#[test]
fn binary32_wide_half_rne_4_stages() {
    check(6);
}

#[test]
fn generated_verilog_compiles_in_icarus() {
    let (g, dir) = generate(
        "xf_icarus",
        "transform",
        &["exp_bits=5", "frac_bits=10", "inverse=hw", "stages=2"],
    );
    let files: Vec<String> = g
        .ports
        .files
        .iter()
        .map(|f| dir.join(f).display().to_string())
        .collect();
    let iv = std::process::Command::new("iverilog")
        .args(["-g2005", "-Wall", "-o"])
        .arg(dir.join("sim.vvp"))
        .args(&files)
        .output()
        .expect("iverilog runs");
    assert!(
        iv.status.success(),
        "iverilog: {}",
        String::from_utf8_lossy(&iv.stderr)
    );
    let warnings = String::from_utf8_lossy(&iv.stderr);
    assert!(warnings.trim().is_empty(), "iverilog warnings: {warnings}");
}
