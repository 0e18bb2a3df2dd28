//! Every rounding mode, formats (8,23), (5,10), (8,7), (8,15), (6,9),
//! (11,52): add, sub, mul, fma and conversions against rustc_apfloat.
//! NaN results are compared as "is NaN" on the oracle's side and as "is the
//! canonical NaN" on ours.

mod common;

use common::{apfloat as ap, formats, mode_name, operand, operand_near, specials, Rng, Tally};
use golden_model::float::{self as fp, FloatFormat, RoundingMode};

const RANDOM: usize = 1_000_000;

fn same(fmt: FloatFormat, ours: u64, oracle: u64) -> bool {
    if fmt.is_nan(oracle) {
        ours == fmt.canonical_nan()
    } else {
        ours == oracle
    }
}

fn binary_ops(fmt: FloatFormat) -> u64 {
    let sp = specials(fmt);
    let mut total = 0;
    for (mi, mode) in RoundingMode::ALL.into_iter().enumerate() {
        let m = mode_name(mode);
        let mut t_add = Tally::new(format!("{fmt} add {m} vs apfloat"));
        let mut t_sub = Tally::new(format!("{fmt} sub {m} vs apfloat"));
        let mut t_mul = Tally::new(format!("{fmt} mul {m} vs apfloat"));
        let mut rng = Rng::new(100 + mi as u64 + 7 * fmt.frac_bits() as u64);
        let spread = fmt.frac_bits() as i64 + 3;
        let randoms = (0..RANDOM).map(|i| {
            let a = operand(&mut rng, fmt, &sp);
            let b = if i % 2 == 0 {
                operand_near(&mut rng, fmt, a, spread)
            } else {
                operand(&mut rng, fmt, &sp)
            };
            (a, b)
        });
        let all_special: Vec<(u64, u64)> = sp
            .iter()
            .flat_map(|&a| sp.iter().map(move |&b| (a, b)))
            .collect();
        for (a, b) in all_special.into_iter().chain(randoms) {
            let show =
                |op: &str, r: u64, o: u64| format!("{op}({a:#x}, {b:#x}) = {r:#x}, apfloat {o:#x}");
            let (r, o) = (fp::add(fmt, a, b, mode), ap::add(fmt, a, b, mode));
            t_add.check(same(fmt, r, o), || show("add", r, o));
            let (r, o) = (fp::sub(fmt, a, b, mode), ap::sub(fmt, a, b, mode));
            t_sub.check(same(fmt, r, o), || show("sub", r, o));
            let (r, o) = (fp::mul(fmt, a, b, mode), ap::mul(fmt, a, b, mode));
            t_mul.check(same(fmt, r, o), || show("mul", r, o));
        }
        total += t_add.finish() + t_sub.finish() + t_mul.finish();
    }
    total
}

fn fma_op(fmt: FloatFormat) -> u64 {
    let sp = specials(fmt);
    let mut total = 0;
    for (mi, mode) in RoundingMode::ALL.into_iter().enumerate() {
        let m = mode_name(mode);
        let mut t = Tally::new(format!("{fmt} fma {m} vs apfloat"));
        let mut rng = Rng::new(200 + mi as u64 + 7 * fmt.frac_bits() as u64);
        let mut check = |a: u64, b: u64, c: u64| {
            let (r, o) = (fp::fma(fmt, a, b, c, mode), ap::fma(fmt, a, b, c, mode));
            t.check(same(fmt, r, o), || {
                format!("fma({a:#x}, {b:#x}, {c:#x}) = {r:#x}, apfloat {o:#x}")
            });
        };
        for &a in &sp {
            for &b in &sp {
                for &c in &sp {
                    check(a, b, c);
                }
            }
        }
        for i in 0..RANDOM {
            let a = operand(&mut rng, fmt, &sp);
            let b = operand(&mut rng, fmt, &sp);
            let c = match i % 3 {
                // c near ±a·b: deep cancellation; near a·b's exponent ± F.
                0 => {
                    let p = fp::mul(fmt, a, b, RoundingMode::TowardZero)
                        ^ (rng.bool() as u64 * fmt.sign_bit());
                    operand_near(&mut rng, fmt, p, 2)
                }
                1 => {
                    let p = fp::mul(fmt, a, b, RoundingMode::TowardZero);
                    operand_near(&mut rng, fmt, p, 2 * fmt.frac_bits() as i64 + 4)
                }
                _ => operand(&mut rng, fmt, &sp),
            };
            check(a, b, c);
        }
        total += t.finish();
    }
    total
}

macro_rules! per_format {
    ($($name:ident: $e:expr, $f:expr;)*) => {$(
        #[test]
        fn $name() {
            let fmt = FloatFormat::new($e, $f).unwrap();
            let n = binary_ops(fmt) + fma_op(fmt);
            println!("{fmt}: {n} vectors in all");
        }
    )*};
}

per_format! {
    e8m23: 8, 23;
    e5m10: 5, 10;
    e8m7: 8, 7;
    e8m15: 8, 15;
    e6m9: 6, 9;
    e11m52: 11, 52;
}

#[test]
fn conversions_between_all_pairs() {
    const PER_PAIR_MODE: usize = 50_000;
    let mut total = 0;
    for from in formats() {
        let sp = specials(from);
        for to in formats() {
            for (mi, mode) in RoundingMode::ALL.into_iter().enumerate() {
                let mut t = Tally::new(format!(
                    "convert {from} -> {to} {} vs apfloat",
                    mode_name(mode)
                ));
                let mut rng = Rng::new(
                    300 + mi as u64 + from.frac_bits() as u64 * 64 + to.frac_bits() as u64,
                );
                let randoms = (0..PER_PAIR_MODE).map(|_| operand(&mut rng, from, &sp));
                for x in sp.iter().copied().chain(randoms) {
                    let (r, o) = (
                        fp::convert(from, to, x, mode),
                        ap::convert(from, to, x, mode),
                    );
                    t.check(same(to, r, o), || {
                        format!("convert({x:#x}) = {r:#x}, apfloat {o:#x}")
                    });
                }
                total += t.checked;
                t.finish();
            }
        }
    }
    println!("conversions: {total} vectors in all");
}
