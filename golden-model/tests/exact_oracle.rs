//! The exact big-integer oracle (dashu) for dot3, the exact multiply,
//! comparisons and min/max, in every mode and the formats (8,23), (5,10),
//! (8,7), (8,15), (6,9), (11,52).

mod common;

use common::exact::{self, V};
use common::{formats, mode_name, operand, operand_near, specials, Rng, Tally};
use golden_model::float::{self as fp, ExactProductFormat, FloatFormat, RoundingMode};
use std::cmp::Ordering;

/// Whether two exact values are the same (same sign for zeros and infinities).
fn same_value(x: &V, y: &V) -> bool {
    match (x, y) {
        (
            V::Fin {
                neg: n1,
                mag: m1,
                exp: e1,
            },
            V::Fin {
                neg: n2,
                mag: m2,
                exp: e2,
            },
        ) => n1 == n2 && exact::cmp_mag(m1, *e1, m2, *e2) == Ordering::Equal,
        _ => x == y,
    }
}

/// Three products whose sum often cancels: the third is (nearly) minus the
/// sum of the first two, or products far apart, or random.
fn dot3_operands(rng: &mut Rng, fmt: FloatFormat, sp: &[u64], i: usize) -> ([u64; 3], [u64; 3]) {
    let mut a = [0; 3].map(|_| operand(rng, fmt, sp));
    let mut b = [0; 3].map(|_| operand(rng, fmt, sp));
    match i % 5 {
        0 => {
            // a2·b2 ≈ -(a0·b0 + a1·b1)
            let s = fp::dot3(
                fmt,
                [a[0], a[1], 0],
                [b[0], b[1], 0],
                RoundingMode::TowardZero,
            );
            a[2] = operand_near(rng, fmt, s, 1) | (!s & fmt.sign_bit());
            b[2] = if rng.bool() {
                fmt.one(false)
            } else {
                operand_near(rng, fmt, fmt.one(false), 1)
            };
        }
        1 => {
            // a1·b1 = -a0·b0 exactly, a2·b2 anything: the sum is a2·b2.
            a[1] = a[0] ^ fmt.sign_bit();
            b[1] = b[0];
        }
        2 => {
            // All three products near each other in magnitude.
            a[1] = operand_near(rng, fmt, a[0], 2);
            a[2] = operand_near(rng, fmt, a[0], 2);
            b[1] = operand_near(rng, fmt, b[0], 2);
            b[2] = operand_near(rng, fmt, b[0], 2);
        }
        3 => {
            // Products far apart (up to ~3 significand widths): the exact
            // sum needs more than 128 bits and the sticky bit decides.
            let gap = rng.range(fmt.frac_bits() as i64, 3 * fmt.frac_bits() as i64 + 12);
            let e0 = ((a[0] >> fmt.frac_bits()) & fmt.exp_all_ones()) as i64;
            let e1 = (e0 - gap).max(0) as u64;
            a[1] = (a[1] & !(fmt.exp_all_ones() << fmt.frac_bits())) | (e1 << fmt.frac_bits());
            b[1] = operand_near(rng, fmt, b[0], 2);
            if rng.bool() {
                b[2] = b[0];
                a[2] = operand_near(rng, fmt, a[0], 0) | (!a[0] & fmt.sign_bit());
            }
        }
        _ => {}
    }
    (a, b)
}

#[test]
fn dot3_against_exact_sum() {
    const PER_FORMAT_MODE: usize = 250_000;
    for fmt in formats() {
        let sp = specials(fmt);
        for (mi, mode) in RoundingMode::ALL.into_iter().enumerate() {
            let mut t = Tally::new(format!("{fmt} dot3 {} vs exact", mode_name(mode)));
            let mut rng = Rng::new(400 + mi as u64 + 64 * fmt.frac_bits() as u64);
            // Zero-sign cases: every combination of signed zero products.
            let z = [fmt.zero(false), fmt.zero(true)];
            let zero_cases = (0..64).map(|k| {
                let bit = |j: usize| z[(k >> j) & 1];
                ([bit(0), bit(1), bit(2)], [bit(3), bit(4), bit(5)])
            });
            let randoms = (0..PER_FORMAT_MODE).map(|i| dot3_operands(&mut rng, fmt, &sp, i));
            for (a, b) in zero_cases.collect::<Vec<_>>().into_iter().chain(randoms) {
                let ours = fp::dot3(fmt, a, b, mode);
                let terms: Vec<V> = (0..3)
                    .map(|j| exact::mul(&exact::decode(fmt, a[j]), &exact::decode(fmt, b[j])))
                    .collect();
                let want = exact::round(fmt, &exact::sum(&terms, mode), mode);
                t.check(ours == want, || {
                    format!("dot3({a:x?}, {b:x?}) = {ours:#x}, exact {want:#x}")
                });
            }
            t.finish();
        }
    }
}

#[test]
fn mul_exact_is_exact_and_compare_on_wide_products() {
    const PER_FORMAT: usize = 500_000;
    for fmt in formats() {
        let Ok(p) = ExactProductFormat::new(fmt) else {
            assert_eq!(
                fmt,
                FloatFormat::BINARY64,
                "only binary64 lacks an exact product format"
            );
            continue;
        };
        let wide = p.wide();
        let sp = specials(fmt);
        let mut rng = Rng::new(500 + fmt.frac_bits() as u64);
        let mut t_mul = Tally::new(format!("{fmt} mul_exact -> {wide} vs exact product"));
        let mut t_cmp = Tally::new(format!(
            "{wide} lt/le/eq/min/max of exact products vs exact"
        ));
        let all_special: Vec<(u64, u64)> = sp
            .iter()
            .flat_map(|&a| sp.iter().map(move |&b| (a, b)))
            .collect();
        let mut prev = (fmt.zero(false), fmt.zero(false), fmt.zero(false));
        let randoms: Vec<(u64, u64)> = (0..PER_FORMAT)
            .map(|i| {
                let a = operand(&mut rng, fmt, &sp);
                let b = if i % 2 == 0 {
                    operand_near(&mut rng, fmt, a, 3)
                } else {
                    operand(&mut rng, fmt, &sp)
                };
                (a, b)
            })
            .collect();
        for (a, b) in all_special.into_iter().chain(randoms) {
            let ours = fp::mul_exact(p, a, b);
            let want = exact::mul(&exact::decode(fmt, a), &exact::decode(fmt, b));
            let ok = match want {
                V::NaN => ours == wide.canonical_nan(),
                _ => same_value(&exact::decode(wide, ours), &want),
            };
            t_mul.check(ok, || {
                format!("mul_exact({a:#x}, {b:#x}) = {ours:#x}, exact {want:?}")
            });
            // Compare this product with the previous one (and with a
            // product of a rearranged pair: equal products, different bits).
            let (pa, pb, prev_prod) = prev;
            let x = ours;
            for y in [
                prev_prod,
                fp::mul_exact(p, pa, b),
                fp::mul_exact(p, a ^ fmt.sign_bit(), b),
            ] {
                check_compare(&mut t_cmp, wide, x, y);
            }
            prev = (a, pb, ours);
        }
        t_mul.finish();
        t_cmp.finish();
    }
}

/// Checks lt, le, eq, min and max of `x` and `y` in `fmt` against the exact order.
fn check_compare(t: &mut Tally, fmt: FloatFormat, x: u64, y: u64) {
    let (vx, vy) = (exact::decode(fmt, x), exact::decode(fmt, y));
    let ord = exact::cmp(&vx, &vy);
    let want = (
        ord == Some(Ordering::Less),
        matches!(ord, Some(Ordering::Less | Ordering::Equal)),
        ord == Some(Ordering::Equal),
    );
    let got = (fp::lt(fmt, x, y), fp::le(fmt, x, y), fp::eq(fmt, x, y));
    let (want_min, want_max) = match ord {
        None => (fmt.canonical_nan(), fmt.canonical_nan()),
        Some(Ordering::Less) => (x, y),
        Some(Ordering::Greater) => (y, x),
        Some(Ordering::Equal) => {
            // Equal values: only ±0 differ in bits; -0 is the smaller.
            let x_neg = x & fmt.sign_bit() != 0;
            if x_neg {
                (x, y)
            } else {
                (y, x)
            }
        }
    };
    let got_mm = (fp::min(fmt, x, y), fp::max(fmt, x, y));
    t.check(got == want && got_mm == (want_min, want_max), || {
        format!("cmp({x:#x}, {y:#x}): (lt,le,eq) {got:?} want {want:?}; (min,max) {got_mm:x?} want ({want_min:#x}, {want_max:#x})")
    });
}

#[test]
fn compare_min_max_every_format() {
    const PER_FORMAT: usize = 500_000;
    for fmt in formats() {
        let sp = specials(fmt);
        let mut t = Tally::new(format!("{fmt} lt/le/eq/min/max vs exact"));
        for &a in &sp {
            for &b in &sp {
                check_compare(&mut t, fmt, a, b);
            }
        }
        let mut rng = Rng::new(600 + fmt.frac_bits() as u64);
        for i in 0..PER_FORMAT {
            let a = operand(&mut rng, fmt, &sp);
            let b = match i % 3 {
                0 => operand_near(&mut rng, fmt, a, 1),
                1 => a ^ (rng.below(4)),
                _ => operand(&mut rng, fmt, &sp),
            };
            check_compare(&mut t, fmt, a, b);
        }
        t.finish();
    }
}
