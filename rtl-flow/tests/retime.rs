//! `pipeline=balanced`: the re-timed module computes what the golden model
//! does, with the unit's latency, and its modelled clock period is shorter
//! than the unit's own plan (so a pass that places registers worse fails).

mod evaluate;

use rtl_gen::retime;

/// (unit, parameters without `pipeline`, latency, required period ratio
/// after/before, register bits allowed against the plan's)
const CASES: &[(&str, &[&str], u32, f64, f64)] = &[
    ("mulcmp", &["stages=3"], 3, 1.0, 0.9),
    (
        "fadd",
        &["exp_bits=8", "frac_bits=23", "stages=3"],
        3,
        0.7,
        1.7,
    ),
    (
        "fmul",
        &["exp_bits=5", "frac_bits=10", "stages=2"],
        2,
        0.6,
        1.65,
    ),
    (
        "ffma",
        &["exp_bits=8", "frac_bits=7", "stages=4"],
        4,
        0.68,
        1.7,
    ),
    (
        "silhouette",
        &["exp_bits=8", "frac_bits=7", "mode=ray", "stages=6"],
        6,
        0.66,
        1.35,
    ),
    (
        "silhouette",
        &["exp_bits=5", "frac_bits=4", "stages=3"],
        3,
        0.5,
        1.25,
    ),
    (
        "silhouette",
        &["exp_bits=5", "frac_bits=6", "origin=bounded", "stages=0"],
        0,
        1.0,
        1.0,
    ),
    (
        "slab",
        &[
            "exp_bits=8",
            "frac_bits=7",
            "rounding=conservative",
            "stages=5",
        ],
        5,
        0.9,
        1.5,
    ),
    (
        "transform",
        &["exp_bits=8", "frac_bits=7", "stages=6"],
        6,
        0.5,
        1.7,
    ),
    ("cull", &["k=2", "stages=4"], 4, 0.9, 1.65),
    ("cull_ray", &["k=2", "stages=4"], 4, 0.9, 2.0),
];

#[test]
fn balanced_pipelines_match_the_golden_model_with_the_same_latency() {
    for (unit, params, stages, _, _) in CASES {
        let mut p: Vec<&str> = params.to_vec();
        p.push("pipeline=balanced");
        evaluate::check(unit, &p, *stages, 400, 1_600);
        let g = evaluate::gen(unit, &p);
        assert!(
            g.module.instances.is_empty(),
            "{}: a balanced module is flat",
            g.module.name
        );
    }
}

#[test]
fn balancing_shortens_the_modelled_period() {
    for (unit, params, _, ratio, _) in CASES {
        let plan = evaluate::gen(unit, params);
        let mut p: Vec<&str> = params.to_vec();
        p.push("pipeline=balanced");
        let balanced = evaluate::gen(unit, &p);
        let before = plan.modelled_period().expect("a pipeline");
        let after = balanced.modelled_period().expect("a pipeline");
        eprintln!(
            "{}: modelled period {before:.1} -> {after:.1} LUT levels",
            plan.module.name
        );
        assert!(
            after <= before * ratio + 1e-9,
            "{}: period {before:.2} -> {after:.2}, expected at most {:.0} % of the plan's",
            plan.module.name,
            ratio * 100.0
        );
    }
}

/// Products wider than a DSP block are split into 18x18 blocks, the corner
/// of two narrow remainders summed in LUTs (evaluated against the golden
/// model above at binary32 too).
/// Registers go where values are narrow: a balanced pipeline carries at most
/// a set multiple of the plan's flip-flops (placing them at the delay
/// alone, before the boundaries were moved by minimum cuts, carried 1.8 to
/// 3.9 times the plan's on these cases). The rounder's stop mask (a
/// comparison fewer after the leading-zero count; routed `fadd` binary32 at
/// 5 stages 88.9 → 113.1 MHz) moved the modelled balanced periods by −9 to
/// +10 % (fadd −9, ffma −6, fmul e5m10 +10, the units −3 to −4) and the
/// register bits by up to +0.25 of the plan's: these bounds were raised by
/// 0.05-0.2 and the period ratios above tightened to the new periods.
#[test]
fn balanced_registers_stay_near_the_plans() {
    for (unit, params, _, _, allowed) in CASES {
        let plan = evaluate::gen(unit, params);
        let mut p: Vec<&str> = params.to_vec();
        p.push("pipeline=balanced");
        let balanced = evaluate::gen(unit, &p);
        let (before, after) = (register_bits(&plan.module), register_bits(&balanced.module));
        eprintln!("{}: register bits {before} -> {after}", plan.module.name);
        assert!(
            after as f64 <= before as f64 * allowed,
            "{}: {after} register bits against the plan's {before}, at most {allowed}x allowed",
            plan.module.name
        );
    }
}

#[test]
fn wide_products_are_split_into_dsp_blocks() {
    let g = evaluate::gen(
        "fmul",
        &[
            "exp_bits=8",
            "frac_bits=23",
            "stages=4",
            "pipeline=balanced",
        ],
    );
    let muls: Vec<u32> = g
        .module
        .nodes
        .iter()
        .filter_map(|n| match n.op {
            rtl_gen::ir::Op::Mul(a, b) => {
                Some(g.module.node(a).ty.width().max(g.module.node(b).ty.width()))
            }
            _ => None,
        })
        .collect();
    // 18x18, 18x6 and 6x18 on blocks; the 6x6 corner as partial products in LUTs
    assert_eq!(muls.len(), 3, "24x24 = three blocks: {muls:?}");
    assert!(muls.iter().all(|&w| w <= 18), "{muls:?}");
    evaluate::check(
        "fmul",
        &[
            "exp_bits=8",
            "frac_bits=23",
            "stages=4",
            "pipeline=balanced",
        ],
        4,
        400,
        4_000,
    );
}

/// Flip-flops of a module and everything it instantiates.
fn register_bits(m: &rtl_gen::ir::Module) -> u64 {
    let own: u64 = m.registers.iter().map(|r| u64::from(r.ty.width())).sum();
    own + m
        .instances
        .iter()
        .map(|i| register_bits(&i.module))
        .sum::<u64>()
}

#[test]
fn state_is_refused() {
    use rtl_gen::builder::ModuleBuilder;
    use rtl_gen::ir::Ty;
    let mut m = ModuleBuilder::new("counter");
    let r = m.reg("count", Ty::UInt(4), Some(0));
    let one = m.uint(4, 1);
    let next = m.add(r.q, one);
    let next = m.slice(next, 3, 0);
    m.set_next(r, next, None);
    m.output("count", r.q);
    let module = m.finish().expect("builds");
    let e = retime::balance(&module, 2).unwrap_err();
    assert!(e.contains("holds state"), "{e}");
}
