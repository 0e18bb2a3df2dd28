//! IR-evaluator cross-check of the conservative `slab` (`rounding=conservative`)
//! against its golden twin `golden_model::slab::eval_conservative` (no
//! Verilator): four formats, stage counts 0 to 9, the corner list and random
//! vectors; plus its structure (module names, ports, latency, the parameter
//! default that keeps the classic slab). The million-vector checks are in
//! Verilator, `tests/silhouette_rtl.rs`.

mod evaluate;

use rtl_flow::Generated;

fn gen(params: &[&str]) -> Generated {
    evaluate::gen("slab", params)
}

fn check(params: &[&str], stages: u32, corners: u64, random: u64) {
    evaluate::check("slab", params, stages, corners, random)
}

#[test]
fn conservative_binary32_four_stages() {
    check(&["rounding=conservative", "stages=4"], 4, 2000, 2000);
}

#[test]
fn conservative_bfloat16_and_binary16() {
    let p = [
        "rounding=conservative",
        "exp_bits=8",
        "frac_bits=7",
        "stages=2",
    ];
    check(&p, 2, 2000, 2000);
    let p = [
        "rounding=conservative",
        "exp_bits=5",
        "frac_bits=10",
        "stages=0",
    ];
    check(&p, 0, 2000, 2000);
}

#[test]
fn conservative_e4m3_deep() {
    let p = [
        "rounding=conservative",
        "exp_bits=4",
        "frac_bits=3",
        "stages=9",
    ];
    check(&p, 9, 2000, 2000);
}

#[test]
fn names_ports_latency_and_default() {
    let c = gen(&["rounding=conservative", "stages=4"]);
    assert_eq!(c.module.name, "slab_e8m23_cons_s4");
    let n = gen(&["stages=4"]);
    assert_eq!(n.module.name, "slab_e8m23_s4", "nearest stays the default");
    let names = |g: &Generated| {
        let i: Vec<String> = g.ports.inputs.iter().map(|p| p.name.clone()).collect();
        let o: Vec<String> = g.ports.outputs.iter().map(|p| p.name.clone()).collect();
        (i, o)
    };
    // same ports as the classic slab: inv_d is one value per axis
    assert_eq!(names(&c), names(&n));
    let (ins, outs) = names(&c);
    assert_eq!(ins.len(), 14);
    assert_eq!(&ins[9..12], &["inv_d_x", "inv_d_y", "inv_d_z"]);
    assert_eq!(outs, ["hit", "t_enter", "t_exit"]);
    let text: String = c.files.iter().map(|f| f.text.as_str()).collect();
    for sub in [
        "fsub_e8m23_rdn",
        "fsub_e8m23_rup",
        "fmul_e8m23_rdn",
        "fmul_e8m23_rup",
    ] {
        assert!(text.contains(sub), "conservative slab instantiates {sub}");
    }
    assert!(
        !text.contains("_rne_"),
        "the conservative slab rounds nothing to nearest"
    );
    for s in 0..=32 {
        let g = gen(&[
            "rounding=conservative",
            "exp_bits=4",
            "frac_bits=3",
            &format!("stages={s}"),
        ]);
        assert_eq!(g.module.latency, s);
    }
    let a = gen(&["rounding=conservative", "stages=3"]);
    let b = gen(&["stages=3", "rounding=conservative"]);
    assert_eq!(a.files, b.files);
}
