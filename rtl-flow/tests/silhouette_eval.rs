//! IR-evaluator cross-check of `silhouette` and `slab` against their golden
//! models (no Verilator): every origin mode and rounding policy, five
//! formats, stage counts from 0 to 9, corner cases and random vectors, plus
//! structural checks (latency, ports, module names, determinism).
//!
//! The evaluator recomputes a submodule for every read of one of its outputs
//! and again at each clock, so a silhouette vector costs milliseconds here:
//! the counts are kept small (the million-vector checks are in Verilator,
//! `tests/silhouette_rtl.rs`).

mod evaluate;

use evaluate::{check, gen};

#[test]
fn silhouette_binary16_shared_conservative() {
    check(
        "silhouette",
        &["exp_bits=5", "frac_bits=10", "stages=4"],
        4,
        250,
        500,
    );
}

#[test]
fn silhouette_bfloat16_bounded_conservative() {
    let p = ["exp_bits=8", "frac_bits=7", "origin=bounded", "stages=3"];
    check("silhouette", &p, 3, 250, 500);
}

#[test]
fn silhouette_e4m3_shared_nearest_combinational() {
    let p = ["exp_bits=4", "frac_bits=3", "rounding=nearest", "stages=0"];
    check("silhouette", &p, 0, 250, 500);
}

#[test]
fn silhouette_e6m9_bounded_nearest_deep() {
    let p = [
        "exp_bits=6",
        "frac_bits=9",
        "origin=bounded",
        "rounding=nearest",
        "stages=9",
    ];
    check("silhouette", &p, 9, 200, 400);
}

#[test]
fn silhouette_binary32_shared_conservative() {
    check("silhouette", &["stages=2"], 2, 100, 200);
}

#[test]
fn silhouette_ray_mode_binary16_bfloat16_and_e4m3() {
    check(
        "silhouette",
        &["mode=ray", "exp_bits=5", "frac_bits=10", "stages=4"],
        4,
        250,
        500,
    );
    check(
        "silhouette",
        &["mode=ray", "exp_bits=8", "frac_bits=7", "stages=0"],
        0,
        250,
        500,
    );
    let p = [
        "mode=ray",
        "exp_bits=4",
        "frac_bits=3",
        "rounding=nearest",
        "stages=7",
    ];
    check("silhouette", &p, 7, 250, 500);
}

#[test]
fn slab_binary32_and_binary16() {
    check("slab", &["stages=4"], 4, 2000, 2000);
    check(
        "slab",
        &["exp_bits=5", "frac_bits=10", "stages=0"],
        0,
        2000,
        2000,
    );
}

#[test]
fn ports_names_latency_and_determinism() {
    let g = gen("silhouette", &["origin=bounded", "stages=5"]);
    assert_eq!(g.module.name, "silhouette_e8m23_bounded_cons_s5");
    let ins: Vec<&str> = g.ports.inputs.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(ins.len(), 20);
    assert_eq!(&ins[9..12], &["o_hi_x", "o_hi_y", "o_hi_z"]);
    assert!(g.ports.inputs.iter().all(|p| p.width == 32));
    let outs: Vec<&str> = g.ports.outputs.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(outs, ["all_hit", "any_hit", "nan", "invalid", "mixed_sign"]);
    let shared = gen("silhouette", &["exp_bits=5", "frac_bits=10", "stages=0"]);
    assert_eq!(shared.module.name, "silhouette_e5m10_shared_cons_s0");
    assert_eq!(shared.ports.inputs.len(), 17);
    assert!(!shared
        .ports
        .inputs
        .iter()
        .any(|p| p.name.starts_with("o_hi")));
    for s in 0..=32 {
        let g = gen(
            "silhouette",
            &["exp_bits=4", "frac_bits=3", &format!("stages={s}")],
        );
        assert_eq!(g.module.latency, s);
        let g = gen(
            "slab",
            &["exp_bits=4", "frac_bits=3", &format!("stages={s}")],
        );
        assert_eq!(g.module.latency, s);
    }
    let a = gen("silhouette", &["stages=3", "rounding=nearest"]);
    let b = gen("silhouette", &["rounding=nearest", "stages=3"]);
    assert_eq!(a.files, b.files);
    let top = a.files.last().unwrap();
    assert!(top.text.contains("u_tests") && top.text.contains("u_axis_z"));
    // ray mode: one origin, one direction, one hit bit; no bundle ports
    let ray = gen("silhouette", &["mode=ray", "stages=4"]);
    assert_eq!(ray.module.name, "silhouette_e8m23_ray_cons_s4");
    let ins: Vec<&str> = ray.ports.inputs.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(ins.len(), 14);
    assert_eq!(&ins[6..12], &["o_x", "o_y", "o_z", "d_x", "d_y", "d_z"]);
    let outs: Vec<&str> = ray.ports.outputs.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(outs, ["hit", "nan", "invalid"]);
    let err = rtl_flow::generate("silhouette", &["mode=ray".into(), "origin=bounded".into()])
        .err()
        .expect("a ray has one origin")
        .to_string();
    assert!(err.contains("origin=bounded needs mode=bundle"), "{err}");
    let slab = gen("slab", &[]);
    let outs: Vec<&str> = slab.ports.outputs.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(outs, ["hit", "t_enter", "t_exit"]);
}

#[test]
fn formats_without_an_exact_product_format_are_clear_errors() {
    let err = rtl_flow::generate("silhouette", &["exp_bits=9".into(), "frac_bits=26".into()])
        .err()
        .expect("must fail")
        .to_string();
    assert!(err.contains("frac_bits=26 is invalid"), "{err}");
    let err = rtl_flow::generate("silhouette", &["origin=both".into()])
        .err()
        .expect("must fail")
        .to_string();
    assert!(err.contains("one of shared, bounded"), "{err}");
}

#[test]
fn silhouette_extreme_formats() {
    // (2,1): the smallest format; (2,25): products below the wide format's
    // normal range (F > bias + 2); (9,1): the widest exponent, one fraction bit
    let p = ["exp_bits=2", "frac_bits=1", "stages=1"];
    check("silhouette", &p, 1, 150, 300);
    let p = ["exp_bits=2", "frac_bits=25", "origin=bounded", "stages=2"];
    check("silhouette", &p, 2, 150, 300);
    let p = ["exp_bits=9", "frac_bits=1", "rounding=nearest", "stages=0"];
    check("silhouette", &p, 0, 150, 300);
}
