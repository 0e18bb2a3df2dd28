//! The float operators in the IR evaluator against the golden model: every
//! input of tiny formats in every rounding mode, and the units' own stimulus
//! (corners, then exponent-biased random vectors) through pipelined modules
//! of binary32, binary16, bfloat16 and (6,9). Seconds, not minutes; the
//! Verilator cross-check is `tests/float_rtl.rs`.

use golden_model::float as g;
use rtl_gen::arith::float::{self as fl, Format, RoundSel, Rounding};
use rtl_gen::eval::Evaluator;
use rtl_gen::ir::Module;

fn gmode(r: Rounding) -> g::RoundingMode {
    rtl_flow::fstim::golden_mode(r)
}

fn gfmt(f: Format) -> g::FloatFormat {
    rtl_flow::fstim::golden_format(f)
}

/// Every combination of `arity` encodings of `fmt` through the combinational
/// `module` (inputs: operands, then `rm` if `dyn`), in all four modes when
/// `dyn`; `want(operands, mode)` gives the expected outputs.
fn exhaustive(
    module: &Module,
    fmt: Format,
    arity: u32,
    dyn_mode: bool,
    want: impl Fn(&[u64], Rounding) -> Vec<u64>,
) {
    assert_eq!(module.latency, 0);
    let mut ev = Evaluator::new(module);
    let n = 1u64 << fmt.width();
    let modes: &[Rounding] = if dyn_mode {
        &Rounding::ALL
    } else {
        &[Rounding::Rne]
    };
    let mut bad = 0;
    let mut ops = vec![0u64; arity as usize];
    for k in 0..n.pow(arity) {
        let mut x = k;
        for o in ops.iter_mut() {
            *o = x % n;
            x /= n;
        }
        for &mode in modes {
            let mut inp: Vec<u128> = ops.iter().map(|&o| o as u128).collect();
            if dyn_mode {
                inp.push(mode.rm_code());
            }
            let got: Vec<u64> = ev.eval(&inp).iter().map(|&v| v as u64).collect();
            let w = want(&ops, mode);
            if got != w {
                bad += 1;
                if bad <= 5 {
                    eprintln!(
                        "{} {mode} {ops:#x?}: got {got:#x?}, want {w:#x?}",
                        module.name
                    );
                }
            }
        }
    }
    assert_eq!(bad, 0, "{}: {bad} mismatches", module.name);
}

const E4M3: Format = Format {
    exp_bits: 4,
    frac_bits: 3,
};

#[test]
fn add_sub_every_pair_of_e4m3_in_every_mode() {
    let f = gfmt(E4M3);
    for sub in [false, true] {
        let m = fl::add::add_module(E4M3, RoundSel::Port, sub, 0);
        exhaustive(&m, E4M3, 2, true, |o, r| {
            vec![if sub {
                g::sub(f, o[0], o[1], gmode(r))
            } else {
                g::add(f, o[0], o[1], gmode(r))
            }]
        });
    }
    let m = fl::add_down_up::add_down_up_module(E4M3, 0);
    exhaustive(&m, E4M3, 2, false, |o, _| {
        let r = g::add_down_up(f, o[0], o[1]);
        vec![r.down, r.up]
    });
}

#[test]
fn fixed_mode_adders_of_tiny_formats() {
    for (e, fr) in [(2, 1), (3, 2), (2, 4), (5, 2)] {
        let fmt = Format::new(e, fr).unwrap();
        for mode in Rounding::ALL {
            let m = fl::add::add_module(fmt, mode, false, 0);
            exhaustive(&m, fmt, 2, false, |o, _| {
                vec![g::add(gfmt(fmt), o[0], o[1], gmode(mode))]
            });
        }
    }
}

#[test]
fn mul_exact_mul_compare_min_max_every_pair_of_e4m3() {
    let f = gfmt(E4M3);
    let m = fl::mul::mul_module(E4M3, RoundSel::Port, 0);
    exhaustive(&m, E4M3, 2, true, |o, r| {
        vec![g::mul(f, o[0], o[1], gmode(r))]
    });
    let p = g::ExactProductFormat::new(f).unwrap();
    let m = fl::mul_exact::mul_exact_module(E4M3, 0);
    exhaustive(&m, E4M3, 2, false, |o, _| vec![g::mul_exact(p, o[0], o[1])]);
    let m = fl::compare::compare_module(E4M3, 0);
    exhaustive(&m, E4M3, 2, false, |o, _| {
        vec![
            g::lt(f, o[0], o[1]) as u64,
            g::le(f, o[0], o[1]) as u64,
            g::eq(f, o[0], o[1]) as u64,
        ]
    });
    let m = fl::minmax::min_max_module(E4M3, 0);
    exhaustive(&m, E4M3, 2, false, |o, _| {
        vec![g::min(f, o[0], o[1]), g::max(f, o[0], o[1])]
    });
}

#[test]
fn fma_every_triple_of_five_bit_formats() {
    for (e, fr) in [(2, 2), (3, 1)] {
        let fmt = Format::new(e, fr).unwrap();
        let m = fl::fma::fma_module(fmt, RoundSel::Port, 0);
        exhaustive(&m, fmt, 3, true, |o, r| {
            vec![g::fma(gfmt(fmt), o[0], o[1], o[2], gmode(r))]
        });
    }
}

#[test]
fn dot3_of_four_bit_formats_every_operand_tuple() {
    // (2,1): 4-bit values, 16^6 = 16.7 M tuples: every tuple with a2 = b2 = ±1
    // or a random third product would do; take every (a0, b0, a1, b1) and a
    // third product cycling through all 256 pairs.
    let fmt = Format::new(2, 1).unwrap();
    let f = gfmt(fmt);
    let m = fl::dot3::dot3_module(fmt, RoundSel::Port, 0);
    let mut ev = Evaluator::new(&m);
    let mut bad = 0;
    for k in 0..65_536u64 {
        let (a0, b0, a1, b1) = (k & 15, (k >> 4) & 15, (k >> 8) & 15, (k >> 12) & 15);
        let third = (k.wrapping_mul(0x9e37_79b9) >> 7) & 255;
        let (a2, b2) = (third & 15, third >> 4);
        let mode = Rounding::ALL[(k % 4) as usize];
        let inp = [a0, b0, a1, b1, a2, b2].map(|v| v as u128);
        let mut inp = inp.to_vec();
        inp.push(mode.rm_code());
        let got = ev.eval(&inp)[0] as u64;
        let want = g::dot3(f, [a0, a1, a2], [b0, b1, b2], gmode(mode));
        if got != want {
            bad += 1;
            eprintln!(
                "{mode} a={:?} b={:?}: got {got:#x}, want {want:#x}",
                [a0, a1, a2],
                [b0, b1, b2]
            );
        }
    }
    assert_eq!(bad, 0);
}

#[test]
fn convert_every_value_of_small_formats() {
    let fmts = [(2u32, 1u32), (4, 3), (3, 6), (6, 2), (5, 10)];
    for &(e1, f1) in &fmts[..4] {
        for &(e2, f2) in &fmts {
            let (from, to) = (Format::new(e1, f1).unwrap(), Format::new(e2, f2).unwrap());
            let m = fl::convert::convert_module(from, to, RoundSel::Port, 0);
            exhaustive(&m, from, 1, true, |o, r| {
                vec![g::convert(gfmt(from), gfmt(to), o[0], gmode(r))]
            });
        }
    }
}

#[test]
fn unpack_every_value_of_e4m3_and_e5m10() {
    for fmt in [E4M3, Format::BINARY16] {
        let m = fl::unpack::unpack_module(fmt, 0);
        let xw = fl::unpack::lsb_exp_width(fmt);
        exhaustive(&m, fmt, 1, false, |o, _| {
            let r = g::unpack(gfmt(fmt), o[0]);
            vec![
                r.sign as u64,
                r.class as u64,
                (r.exp as i64 as u64) & ((1 << xw) - 1),
                r.sig as u64,
            ]
        });
    }
}

/// The units' testbenches (corners, then biased random vectors) through the
/// pipelined top modules in the evaluator.
fn units(unit: &str, extra: &[&str], vectors: u64) {
    let formats: [&[&str]; 4] = [
        &["exp_bits=8", "frac_bits=23", "stages=3"],
        &["exp_bits=5", "frac_bits=10", "stages=1"],
        &["exp_bits=8", "frac_bits=7", "stages=0"],
        &["exp_bits=6", "frac_bits=9", "stages=6"],
    ];
    for f in formats {
        let params: Vec<String> = f.iter().chain(extra).map(|s| s.to_string()).collect();
        let gen = rtl_flow::generate(unit, &params).unwrap_or_else(|e| panic!("{unit}: {e}"));
        let r = gen.evaluate(gen.testbench().as_ref(), vectors, 5);
        assert_eq!(
            (r.vectors, r.mismatches),
            (vectors, 0),
            "{} {params:?}: {r}",
            gen.module.name
        );
    }
}

#[test]
fn add_units_random() {
    units("fadd", &["round=dyn"], 30_000);
    units("fadd", &["round=rdn", "op=sub"], 10_000);
    units("fadd_down_up", &[], 10_000);
}

#[test]
fn mul_units_random() {
    units("fmul", &["round=dyn"], 30_000);
    units("fmul", &["round=rtz"], 5_000);
    units("fmul_exact", &[], 10_000);
}

#[test]
fn compare_units_random() {
    units("fcmp", &[], 20_000);
    units("fminmax", &[], 20_000);
    units("funpack", &[], 5_000);
}

#[test]
fn convert_units_random() {
    units(
        "fcvt",
        &["round=dyn", "to_exp_bits=5", "to_frac_bits=10"],
        20_000,
    );
    units(
        "fcvt",
        &["round=dyn", "to_exp_bits=11", "to_frac_bits=52"],
        5_000,
    );
    units(
        "fcvt",
        &["round=rup", "to_exp_bits=8", "to_frac_bits=7"],
        5_000,
    );
}

#[test]
fn fused_units_random() {
    units("ffma", &["round=dyn"], 10_000);
    units("fdot3", &["round=dyn"], 5_000);
}

#[test]
fn binary64_fused_and_sum_random() {
    for unit in ["fadd", "fmul", "ffma", "fdot3"] {
        let params: Vec<String> = ["exp_bits=11", "frac_bits=52", "stages=4", "round=dyn"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let gen = rtl_flow::generate(unit, &params).unwrap();
        let r = gen.evaluate(gen.testbench().as_ref(), 10_000, 9);
        assert_eq!(r.mismatches, 0, "{}: {r}", gen.module.name);
    }
}

#[test]
fn latency_is_the_stage_count_and_names_carry_parameters() {
    for stages in 0..=9 {
        let fmt = Format::BINARY32;
        let mods = [
            fl::add::add_module(fmt, Rounding::Rne, false, stages),
            fl::mul::mul_module(fmt, Rounding::Rup, stages),
            fl::fma::fma_module(fmt, RoundSel::Port, stages),
            fl::dot3::dot3_module(fmt, Rounding::Rdn, stages),
            fl::convert::convert_module(fmt, Format::BINARY16, Rounding::Rtz, stages),
            fl::compare::compare_module(fmt, stages),
            fl::add_down_up::add_down_up_module(fmt, stages),
        ];
        for m in &mods {
            assert_eq!(m.latency, stages, "{}", m.name);
            assert!(
                m.name.contains("e8m23") && m.name.ends_with(&format!("_s{stages}")),
                "{}",
                m.name
            );
        }
    }
    assert_eq!(
        fl::add::add_module(Format::BINARY16, Rounding::Rtz, true, 2).name,
        "fsub_e5m10_rtz_s2"
    );
    assert_eq!(
        fl::fma::fma_module(Format::BFLOAT16, RoundSel::Port, 3).name,
        "ffma_e8m7_dyn_s3"
    );
}

#[test]
fn rounder_ports_match_the_documented_raw_format() {
    // the table in round.rs and docs/float.md "RTL notes": sign, cls, exp, sig, sticky (, rm)
    let m = fl::round::round_module(Format::BINARY32, 28, 10, Rounding::Rne, 1);
    let ports: Vec<(String, u32, bool)> = m
        .inputs
        .iter()
        .map(|p| (p.name.clone(), p.ty.width(), p.ty.is_signed()))
        .collect();
    let want = [
        ("sign", 1, false),
        ("cls", 2, false),
        ("exp", 10, true),
        ("sig", 28, false),
        ("sticky", 1, false),
    ];
    let want: Vec<(String, u32, bool)> = want
        .iter()
        .map(|(n, w, s)| (n.to_string(), *w, *s))
        .collect();
    assert_eq!(ports, want);
    assert_eq!(m.outputs.len(), 1);
    assert_eq!(m.outputs[0].0.name, "z");
    let d = fl::round::round_module(Format::BINARY32, 28, 10, RoundSel::Port, 1);
    assert_eq!(d.inputs.last().unwrap().name, "rm");
    let codes = [
        fl::unpack::CLASS_ZERO,
        fl::unpack::CLASS_FINITE,
        fl::unpack::CLASS_INF,
        fl::unpack::CLASS_NAN,
    ];
    let classes = [
        g::Class::Zero,
        g::Class::Finite,
        g::Class::Inf,
        g::Class::NaN,
    ];
    for (c, k) in codes.iter().zip(classes) {
        assert_eq!(*c, k as u128);
    }
    for r in Rounding::ALL {
        assert_eq!(r.rm_code(), gmode(r) as u128);
    }
}
