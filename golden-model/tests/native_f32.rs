//! binary32, round-to-nearest-even, against Rust's native `f32` (the
//! hardware's IEEE 754 arithmetic): +, -, *, mul_add, <, <=, ==, and
//! minimum/maximum semantics, on specials and millions of random operands.

mod common;

use common::{operand, operand_near, specials, Rng, Tally};
use golden_model::float::{self as fp, FloatFormat, RoundingMode::NearestEven as RNE};

const F32: FloatFormat = FloatFormat::BINARY32;
const RANDOM: usize = 8_000_000;

fn f(x: u64) -> f32 {
    f32::from_bits(x as u32)
}

/// Bit-exact match, except that a NaN must be matched by our canonical NaN.
fn same(ours: u64, native: f32) -> bool {
    if native.is_nan() {
        ours == F32.canonical_nan()
    } else {
        ours == native.to_bits() as u64
    }
}

/// Operand pairs: all pairs of specials, then random and near-random pairs.
fn pairs(seed: u64) -> impl Iterator<Item = (u64, u64)> {
    let sp = specials(F32);
    let all: Vec<(u64, u64)> = sp
        .iter()
        .flat_map(|&a| sp.iter().map(move |&b| (a, b)))
        .collect();
    let mut rng = Rng::new(seed);
    let sp2 = sp.clone();
    all.into_iter().chain((0..RANDOM).map(move |i| {
        let a = operand(&mut rng, F32, &sp2);
        let b = if i % 2 == 0 {
            operand_near(&mut rng, F32, a, 26)
        } else {
            operand(&mut rng, F32, &sp2)
        };
        (a, b)
    }))
}

fn show(op: &str, a: u64, b: u64, ours: u64, native: f32) -> String {
    format!(
        "{op}({a:#010x}, {b:#010x}) = ours {ours:#010x}, native {:#010x}",
        native.to_bits()
    )
}

#[test]
fn add_sub_mul_match_native() {
    let mut t_add = Tally::new("f32 add RNE vs native");
    let mut t_sub = Tally::new("f32 sub RNE vs native");
    let mut t_mul = Tally::new("f32 mul RNE vs native");
    for (a, b) in pairs(1) {
        let (r, n) = (fp::add(F32, a, b, RNE), f(a) + f(b));
        t_add.check(same(r, n), || show("add", a, b, r, n));
        let (r, n) = (fp::sub(F32, a, b, RNE), f(a) - f(b));
        t_sub.check(same(r, n), || show("sub", a, b, r, n));
        let (r, n) = (fp::mul(F32, a, b, RNE), f(a) * f(b));
        t_mul.check(same(r, n), || show("mul", a, b, r, n));
    }
    t_add.finish();
    t_sub.finish();
    t_mul.finish();
}

#[test]
fn fma_matches_native_mul_add() {
    let mut t = Tally::new("f32 fma RNE vs native mul_add");
    let sp = specials(F32);
    let mut rng = Rng::new(2);
    for &a in &sp {
        for &b in &sp {
            for &c in &sp {
                let (r, n) = (fp::fma(F32, a, b, c, RNE), f(a).mul_add(f(b), f(c)));
                t.check(same(r, n), || {
                    format!(
                        "fma({a:#x}, {b:#x}, {c:#x}) = {r:#x}, native {:#x}",
                        n.to_bits()
                    )
                });
            }
        }
    }
    for i in 0..RANDOM {
        let a = operand(&mut rng, F32, &sp);
        let b = operand(&mut rng, F32, &sp);
        // Half the time put c near a·b so that the sum cancels deeply.
        let c = if i % 2 == 0 {
            let p = fp::mul(F32, a, b, RNE) ^ (rng.bool() as u64) << 31;
            operand_near(&mut rng, F32, p, 3)
        } else {
            operand(&mut rng, F32, &sp)
        };
        let (r, n) = (fp::fma(F32, a, b, c, RNE), f(a).mul_add(f(b), f(c)));
        t.check(same(r, n), || {
            format!(
                "fma({a:#x}, {b:#x}, {c:#x}) = {r:#x}, native {:#x}",
                n.to_bits()
            )
        });
    }
    t.finish();
}

#[test]
fn compare_and_min_max_match_native() {
    let mut t_cmp = Tally::new("f32 lt/le/eq vs native");
    let mut t_mm = Tally::new("f32 min/max vs native (+ NaN and signed-zero rules)");
    for (a, b) in pairs(3) {
        let (x, y) = (f(a), f(b));
        let ours = (fp::lt(F32, a, b), fp::le(F32, a, b), fp::eq(F32, a, b));
        let native = (x < y, x <= y, x == y);
        t_cmp.check(ours == native, || {
            format!("cmp({a:#x}, {b:#x}): ours {ours:?}, native {native:?}")
        });

        // f32::minimum/maximum are not stable: native min/max agree with
        // IEEE 754-2019 minimum/maximum except on NaN and on ±0 pairs.
        let (mn, mx) = (fp::min(F32, a, b), fp::max(F32, a, b));
        let (emn, emx) = if x.is_nan() || y.is_nan() {
            (F32.canonical_nan(), F32.canonical_nan())
        } else if x == 0.0 && y == 0.0 {
            let neg = |z: u64| z >> 31 == 1;
            let zero = |n: bool| if n { 0x8000_0000 } else { 0 };
            (zero(neg(a) || neg(b)), zero(neg(a) && neg(b)))
        } else {
            (x.min(y).to_bits() as u64, x.max(y).to_bits() as u64)
        };
        t_mm.check((mn, mx) == (emn, emx), || {
            format!("min/max({a:#x}, {b:#x}) = ({mn:#x}, {mx:#x}), expected ({emn:#x}, {emx:#x})")
        });
    }
    t_cmp.finish();
    t_mm.finish();
}
