//! Verilator cross-check of the `silhouette` tester and the `slab` baseline,
//! bit for bit against the golden models, 1,000,000 vectors per
//! configuration, streamed back to back (the harness checks `out_valid`
//! against the latency on every cycle, so II = 1 is shown), one
//! configuration also with random idle cycles (bubbles). Every design is
//! linted with `verilator --lint-only -Wall` first.
//!
//! Configurations (chosen to keep Verilator builds few):
//! - binary32, shared origin (single rays and shared-origin bundles), conservative, 4 stages;
//! - binary32, bounded origin (bundles), conservative, 2 stages;
//! - bfloat16 (8,7), shared, conservative, 1 stage;
//! - (6,9), bounded, conservative, 6 stages, with bubbles;
//! - binary16 (5,10), bounded, nearest, combinational (0 stages);
//! - ray mode: binary32 conservative, 4 stages; bfloat16 nearest, 2 stages, with bubbles;
//! - slab: binary32, 4 stages; bfloat16, 0 stages;
//! - conservative slab: binary32, 4 stages; bfloat16, 2 stages;
//! - `pipeline=balanced`: ray mode bfloat16, 12 stages, with bubbles; the same at 14 stages
//!   with `dsp=ecp5` (products in MULT18X18D blocks, behavioural branch).

mod common;

use common::generate;

const VECTORS: u64 = 1_000_000;

fn run(test: &str, unit: &str, params: &[&str], stages: u32, bubbles: Option<u64>) {
    let (g, dir) = generate(test, unit, params);
    assert_eq!(g.module.latency, stages, "{}", g.module.name);
    sim::lint(&g.ports, &dir).unwrap_or_else(|e| panic!("lint {}: {e}", g.module.name));
    let h = sim::Harness::build(&g.ports, &dir, &sim::default_cache_root()).expect("build harness");
    let tb = g.testbench();
    let opts = sim::CheckOptions {
        vectors: VECTORS,
        seed: 11,
        progress: false,
        bubbles,
        replay_hint: Some(format!(
            "rtl-gen replay {unit} {} --seed 11 --index {{index}}",
            g.param_args()
        )),
        ..Default::default()
    };
    let report = sim::cross_check(&h, tb.as_ref(), tb.as_ref(), &opts).expect("cross-check runs");
    eprintln!(
        "{}: {report} (harness build {:.1?}{})",
        g.module.name,
        h.build_time(),
        if h.was_cached() { ", cached" } else { "" }
    );
    assert_eq!(report.vectors, VECTORS, "{}", g.module.name);
    assert_eq!(report.mismatches, 0, "{}\n{report}", g.module.name);
    if bubbles.is_some() {
        assert!(report.bubbles > 0, "bubbles were inserted");
    } else {
        // back to back: one vector per clock, plus reset and drain cycles only
        assert_eq!(report.bubbles, 0);
        assert!(
            report.cycles <= VECTORS + stages as u64 + 16,
            "{} cycles",
            report.cycles
        );
    }
}

#[test]
fn silhouette_binary32_shared_single_rays_and_bundles() {
    let p = ["exp_bits=8", "frac_bits=23", "origin=shared", "stages=4"];
    run("sil_b32_shared", "silhouette", &p, 4, None);
}

#[test]
fn silhouette_binary32_bounded_bundles() {
    let p = ["exp_bits=8", "frac_bits=23", "origin=bounded", "stages=2"];
    run("sil_b32_bounded", "silhouette", &p, 2, None);
}

#[test]
fn silhouette_bfloat16_shared() {
    let p = ["exp_bits=8", "frac_bits=7", "origin=shared", "stages=1"];
    run("sil_bf16_shared", "silhouette", &p, 1, None);
}

#[test]
fn silhouette_e6m9_bounded_with_bubbles() {
    let p = ["exp_bits=6", "frac_bits=9", "origin=bounded", "stages=6"];
    run("sil_e6m9_bounded", "silhouette", &p, 6, Some(3));
}

#[test]
fn silhouette_binary16_bounded_nearest_combinational() {
    let p = [
        "exp_bits=5",
        "frac_bits=10",
        "origin=bounded",
        "rounding=nearest",
        "stages=0",
    ];
    run("sil_b16_near", "silhouette", &p, 0, None);
}

#[test]
fn silhouette_ray_mode_binary32() {
    let p = ["mode=ray", "exp_bits=8", "frac_bits=23", "stages=4"];
    run("sil_ray_b32", "silhouette", &p, 4, None);
}

#[test]
fn silhouette_ray_mode_bfloat16_nearest_with_bubbles() {
    let p = [
        "mode=ray",
        "exp_bits=8",
        "frac_bits=7",
        "rounding=nearest",
        "stages=2",
    ];
    run("sil_ray_bf16_near", "silhouette", &p, 2, Some(3));
}

#[test]
fn slab_binary32() {
    run(
        "slab_b32",
        "slab",
        &["exp_bits=8", "frac_bits=23", "stages=4"],
        4,
        None,
    );
}

#[test]
fn slab_bfloat16_combinational() {
    run(
        "slab_bf16",
        "slab",
        &["exp_bits=8", "frac_bits=7", "stages=0"],
        0,
        None,
    );
}

/// The conservative slab (`rounding=conservative`, issue 19 item 3): binary32, 4 stages.
#[test]
fn slab_conservative_binary32() {
    let p = [
        "rounding=conservative",
        "exp_bits=8",
        "frac_bits=23",
        "stages=4",
    ];
    run("slab_cons_b32", "slab", &p, 4, None);
}

/// The conservative slab: bfloat16, 2 stages.
#[test]
fn slab_conservative_bfloat16() {
    let p = [
        "rounding=conservative",
        "exp_bits=8",
        "frac_bits=7",
        "stages=2",
    ];
    run("slab_cons_bf16", "slab", &p, 2, None);
}

/// `pipeline=balanced` (registers re-placed by the delay model, one flat
/// module): the ray tester at bfloat16 and 12 stages, the configuration that
/// routes at 100 MHz on the ECP5-85F-6, with bubbles.
#[test]
fn silhouette_ray_mode_bfloat16_balanced_12_stages_with_bubbles() {
    let p = [
        "mode=ray",
        "exp_bits=8",
        "frac_bits=7",
        "stages=12",
        "pipeline=balanced",
    ];
    run("sil_ray_bf16_bal", "silhouette", &p, 12, Some(3));
}

/// `dsp=ecp5` (each registered product in an ECP5 MULT18X18D with its own
/// registers; here the behavioural branch Verilator reads): the ray tester
/// at bfloat16 balanced to 14 stages, the configuration routed on the
/// ECP5-85F-6, with bubbles. The products really moved into the blocks.
#[test]
fn silhouette_ray_mode_bfloat16_balanced_ecp5_dsp_blocks_with_bubbles() {
    let p = [
        "mode=ray",
        "exp_bits=8",
        "frac_bits=7",
        "stages=14",
        "pipeline=balanced",
        "dsp=ecp5",
    ];
    let (g, _) = generate("sil_ray_bf16_dsp_probe", "silhouette", &p);
    let blocks = g
        .module
        .instances
        .iter()
        .filter(|i| i.module.vendor.is_some())
        .count();
    assert!(blocks >= 9, "{}: {blocks} MULT18X18D blocks", g.module.name);
    run("sil_ray_bf16_dsp", "silhouette", &p, 14, Some(3));
}
