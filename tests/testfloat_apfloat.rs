//! TestFloat-format case files written from rustc_apfloat (an oracle
//! independent of our golden model) for the directed rounding modes, checked
//! through `flow::testfloat` against the Verilated RTL and the golden model.

mod common;

use common::{generate, scratch};
use rtl_flow::testfloat::{read_cases, run, Mapping};
use rustc_apfloat::ieee::{Half, Single};
use rustc_apfloat::{Float, Round};

/// Operand bits of `width` bits: mostly random, some specials, some
/// subnormals, some near overflow.
fn operand(i: u64, k: u64, exp_bits: u32, frac_bits: u32) -> u64 {
    let mut z = (i * 3 + k + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 31)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z ^= z >> 29;
    let width = 1 + exp_bits + frac_bits;
    let mask = (1u64 << width) - 1;
    let frac = (1u64 << frac_bits) - 1;
    let sign = (z >> 62 & 1) << (width - 1);
    let exp_max = (1u64 << exp_bits) - 1;
    match (z >> 56) % 10 {
        0 => {
            sign | [0, exp_max << frac_bits, (exp_max << frac_bits) | 1, 1][(z >> 50) as usize % 4]
        }
        1 => sign | (z & frac),
        2 => sign | ((exp_max - 1 - (z >> 40) % 3) << frac_bits) | (z & frac),
        _ => z & mask,
    }
}

fn file_of(lines: Vec<String>, dir: &std::path::Path, name: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path
}

fn check(unit: &str, params: &[&str], path: &std::path::Path) {
    let (g, dir) = generate("testfloat_apfloat", unit, params);
    let h = sim::Harness::build(&g.ports, &dir, &sim::default_cache_root()).unwrap();
    let map = Mapping::for_unit(&g, None).unwrap();
    let f = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let name = path.display().to_string();
    let cases = read_cases(f, &name, &g.ports.inputs, &g.ports.outputs[map.result]).unwrap();
    let o = run(&g, &h, g.testbench().as_ref(), &map, &cases, &name, false).unwrap();
    assert_eq!(o.cases, cases.len() as u64);
    assert_eq!(o.mismatches, 0, "{unit} {params:?}:\n{o}");
    assert!(o.report.passed);
    // The file's NaNs are apfloat's; ours are canonical: only --nan-exact
    // would tell, and only in the NaN class.
    let exact = run(&g, &h, g.testbench().as_ref(), &map, &cases, &name, true).unwrap();
    assert!(
        exact.classes.keys().all(|c| c.to_string() == "NaN"),
        "{exact}"
    );
}

#[test]
fn binary32_mul_round_down_matches_apfloat_cases() {
    let dir = scratch("testfloat_apfloat_mul");
    let lines = (0..20_000)
        .map(|i| {
            let (a, b) = (operand(i, 0, 8, 23), operand(i, 1, 8, 23));
            let r = Single::from_bits(a as u128)
                .mul_r(Single::from_bits(b as u128), Round::TowardNegative)
                .value
                .to_bits();
            format!("{a:08X} {b:08X} {r:08X} 00")
        })
        .collect();
    let path = file_of(lines, &dir, "f32_mul_rdn.txt");
    check("fmul", &["exp_bits=8", "frac_bits=23", "round=rdn"], &path);
}

#[test]
fn half_sub_round_up_matches_apfloat_cases() {
    let dir = scratch("testfloat_apfloat_sub");
    let lines = (0..20_000)
        .map(|i| {
            let (a, b) = (operand(i, 0, 5, 10), operand(i, 1, 5, 10));
            let r = Half::from_bits(a as u128)
                .sub_r(Half::from_bits(b as u128), Round::TowardPositive)
                .value
                .to_bits();
            format!("{a:04X} {b:04X} {r:04X} 00")
        })
        .collect();
    let path = file_of(lines, &dir, "f16_sub_rup.txt");
    check(
        "fadd",
        &["exp_bits=5", "frac_bits=10", "round=rup", "op=sub"],
        &path,
    );
}
