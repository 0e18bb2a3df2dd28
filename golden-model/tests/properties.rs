//! proptest properties across formats and modes.

mod common;

use common::exact::{self, V};
use golden_model::float::{self as fp, ExactProductFormat, FloatFormat, RoundingMode};
use proptest::prelude::*;
use std::cmp::Ordering;

const FORMATS: [(u32, u32); 8] = [
    (8, 23),
    (5, 10),
    (8, 7),
    (8, 15),
    (6, 9),
    (11, 52),
    (4, 3),
    (2, 1),
];

fn format() -> impl Strategy<Value = FloatFormat> {
    prop::sample::select(FORMATS.to_vec()).prop_map(|(e, f)| FloatFormat::new(e, f).unwrap())
}

fn mode() -> impl Strategy<Value = RoundingMode> {
    prop::sample::select(RoundingMode::ALL.to_vec())
}

/// Raw 64-bit patterns: the model must ignore bits above the format.
fn bits() -> impl Strategy<Value = u64> {
    prop_oneof![
        any::<u64>(),
        // small magnitudes / subnormals / specials by exponent field
        (any::<u64>(), 0u32..64).prop_map(|(x, s)| x >> s),
    ]
}

fn neg(f: FloatFormat, x: u64) -> u64 {
    x ^ f.sign_bit()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 50_000, .. ProptestConfig::default() })]

    /// down <= a + b <= up, equal exactly when the sum is representable,
    /// and they are the RDN and RUP results of `add`.
    #[test]
    fn add_down_up_brackets_the_exact_sum(f in format(), a in bits(), b in bits()) {
        let r = fp::add_down_up(f, a, b);
        prop_assert_eq!(r.down, fp::add(f, a, b, RoundingMode::Down));
        prop_assert_eq!(r.up, fp::add(f, a, b, RoundingMode::Up));
        let s = exact::sum(&[exact::decode(f, a), exact::decode(f, b)], RoundingMode::NearestEven);
        if s == V::NaN {
            prop_assert!(r.down == f.canonical_nan() && r.up == f.canonical_nan());
        } else {
            let (dn, up) = (exact::decode(f, r.down), exact::decode(f, r.up));
            prop_assert_ne!(exact::cmp(&dn, &s), Some(Ordering::Greater));
            prop_assert_ne!(exact::cmp(&up, &s), Some(Ordering::Less));
            let representable = exact::round(f, &s, RoundingMode::Down) == exact::round(f, &s, RoundingMode::Up)
                || matches!(s, V::Zero(_));
            prop_assert_eq!(fp::eq(f, r.down, r.up), representable);
            // No representable value strictly between them.
            if !representable && !f.is_nan(r.down) {
                prop_assert!(fp::lt(f, r.down, r.up));
            }
        }
    }

    /// a + b = b + a, a·b = b·a, fma and dot3 are symmetric, in every mode.
    #[test]
    fn commutative(f in format(), m in mode(), a in bits(), b in bits(), c in bits(),
                   x in any::<[u64; 3]>(), y in any::<[u64; 3]>(), perm in 0usize..6) {
        prop_assert_eq!(fp::add(f, a, b, m), fp::add(f, b, a, m));
        prop_assert_eq!(fp::mul(f, a, b, m), fp::mul(f, b, a, m));
        prop_assert_eq!(fp::fma(f, a, b, c, m), fp::fma(f, b, a, c, m));
        let p = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]][perm];
        let (xp, yp) = (p.map(|i| x[i]), p.map(|i| y[i]));
        prop_assert_eq!(fp::dot3(f, x, y, m), fp::dot3(f, xp, yp, m));
        prop_assert_eq!(fp::dot3(f, x, y, m), fp::dot3(f, y, x, m));
    }

    /// Negating both operands mirrors the result and the directed modes.
    #[test]
    fn sign_symmetry(f in format(), a in bits(), b in bits()) {
        let r = fp::add(f, a, b, RoundingMode::Down);
        let mirrored = fp::add(f, neg(f, a), neg(f, b), RoundingMode::Up);
        if f.is_nan(r) {
            prop_assert_eq!(mirrored, f.canonical_nan());
        } else {
            prop_assert_eq!(mirrored, neg(f, r) & f.mask());
        }
        prop_assert_eq!(fp::sub(f, a, b, RoundingMode::TowardZero), fp::add(f, a, neg(f, b), RoundingMode::TowardZero));
    }

    /// Rounding the exact product once more is the rounded product.
    #[test]
    fn mul_exact_then_convert_is_mul(f in format(), m in mode(), a in bits(), b in bits()) {
        if let Ok(p) = ExactProductFormat::new(f) {
            let wide = fp::mul_exact(p, a, b);
            prop_assert_eq!(fp::convert(p.wide(), f, wide, m), fp::mul(f, a, b, m));
        }
    }

    /// fma(a, b, zero) = a·b with the zero that leaves signs alone.
    #[test]
    fn fma_with_neutral_zero_is_mul(f in format(), m in mode(), a in bits(), b in bits()) {
        let zero = f.zero(m != RoundingMode::Down);
        prop_assert_eq!(fp::fma(f, a, b, zero, m), fp::mul(f, a, b, m));
        // dot3 with two zero terms likewise (as `(p + z) + z`).
        prop_assert_eq!(fp::dot3(f, [a, zero, zero], [b, f.zero(false), f.zero(false)], m), fp::mul(f, a, b, m));
    }

    /// Widening then narrowing is the identity (NaN becomes canonical), and
    /// unpack + round is the identity on every non-NaN encoding.
    #[test]
    fn round_trips(f in format(), m in mode(), x in bits()) {
        let x = x & f.mask();
        let expect = if f.is_nan(x) { f.canonical_nan() } else { x };
        prop_assert_eq!(fp::round(f, fp::unpack(f, x), m), expect);
        let wide = FloatFormat::BINARY64;
        if f.exp_bits() <= 11 && f.frac_bits() <= 52 {
            prop_assert_eq!(fp::convert(wide, f, fp::convert(f, wide, x, m), m), expect);
        }
    }

    /// Comparisons are a consistent order; min and max are symmetric.
    #[test]
    fn order_consistency(f in format(), a in bits(), b in bits()) {
        let unordered = f.is_nan(a) || f.is_nan(b);
        let (lt, gt, eq) = (fp::lt(f, a, b), fp::lt(f, b, a), fp::eq(f, a, b));
        prop_assert_eq!(lt as u8 + gt as u8 + eq as u8, if unordered { 0 } else { 1 });
        prop_assert_eq!(fp::le(f, a, b), lt || eq);
        prop_assert_eq!(fp::min(f, a, b), fp::min(f, b, a));
        prop_assert_eq!(fp::max(f, a, b), fp::max(f, b, a));
        if !unordered {
            prop_assert!(fp::le(f, fp::min(f, a, b), fp::max(f, a, b)));
        }
    }
}
