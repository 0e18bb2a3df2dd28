//! Exact rational arithmetic for the transform: the scene builder's inverse
//! (`R⁻¹` and the conventional `u = −R⁻¹·T`, each entry the exact rational
//! value rounded once) and the reference `fl(R⁻¹·(O_w − T))` of the accuracy
//! study. Big integers (`dashu`); the only float code used is the shared
//! rounder, fed an exact quotient with a sticky bit.
//!
//! Every finite value of a format is `m · 2^e` with integer `m`. The nine
//! entries of `R` are brought to their smallest exponent `E0`
//! (`R = A · 2^E0`, `A` integer), so `det R = det A · 2^(3·E0)` and
//! `R⁻¹ = adj(A) / det(A) · 2^(−E0)` exactly.

use dashu::base::{BitTest, UnsignedAbs};
use dashu::integer::IBig;

use crate::float::{round, Class, FloatFormat, RawFloat, RoundingMode};

/// A finite format value as `m · 2^e`; `None` for inf and NaN.
pub fn decode(fmt: FloatFormat, bits: u64) -> Option<(IBig, i64)> {
    match crate::exact::ray_box::decode(fmt, bits) {
        crate::exact::ray_box::Exact::Fin { m, e } => Some((IBig::from(m), e as i64)),
        _ => None,
    }
}

/// Brings `m_k · 2^(e_k)` to the smallest exponent: integers `a_k` and `E`
/// with `value_k = a_k · 2^E`.
pub fn align(vals: &[(IBig, i64)]) -> (Vec<IBig>, i64) {
    let e0 = vals.iter().map(|v| v.1).min().unwrap_or(0);
    let ints = vals
        .iter()
        .map(|(m, e)| m.clone() << ((e - e0) as usize))
        .collect();
    (ints, e0)
}

/// `num / den · 2^e` rounded once to `fmt` in `mode` (`den ≠ 0`); an exact
/// zero is +0.
pub fn round_ratio(fmt: FloatFormat, mode: RoundingMode, num: &IBig, den: &IBig, e: i64) -> u64 {
    assert!(!den.is_zero(), "round_ratio: zero denominator");
    if num.is_zero() {
        return fmt.zero(false);
    }
    let negative =
        (num.sign() == dashu::base::Sign::Negative) != (den.sign() == dashu::base::Sign::Negative);
    let (n, d) = (num.unsigned_abs(), den.unsigned_abs());
    // quotient with F + 3 .. F + 5 bits
    let b = n.bit_len() as i64 - d.bit_len() as i64;
    let s = fmt.frac_bits() as i64 + 4 - b;
    let (q, r) = if s >= 0 {
        let n = n << (s as usize);
        (&n / &d, &n % &d)
    } else {
        let d = d << ((-s) as usize);
        (&n / &d, &n % &d)
    };
    let sig = u128::try_from(&q).expect("quotient has at most F + 5 bits");
    let exp = (e - s).clamp(i32::MIN as i64 / 2, i32::MAX as i64 / 2) as i32;
    round(
        fmt,
        RawFloat {
            sign: negative,
            class: Class::Finite,
            exp,
            sig,
            sticky: !r.is_zero(),
        },
        mode,
    )
}

/// The exact inverse of a finite, nonsingular `R`:
/// `R⁻¹[i][j] = adj[i][j] / det · 2^(−e0)`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExactInverse {
    /// integer adjugate of the aligned matrix, row-major
    pub adj: [IBig; 9],
    /// integer determinant of the aligned matrix (nonzero)
    pub det: IBig,
    /// the exponent `E0` of the alignment
    pub e0: i64,
}

/// The exact inverse of `R` (row-major, bits of `fmt`); `None` if an entry
/// is not finite or `R` is singular.
pub fn exact_inverse(fmt: FloatFormat, r: &[u64; 9]) -> Option<ExactInverse> {
    let vals: Option<Vec<_>> = r.iter().map(|&x| decode(fmt, x)).collect();
    let (a, e0) = align(&vals?);
    let at = |i: usize, j: usize| &a[3 * (i % 3) + (j % 3)];
    let adj: [IBig; 9] = std::array::from_fn(|k| {
        let (i, j) = (k / 3, k % 3);
        at(j + 1, i + 1) * at(j + 2, i + 2) - at(j + 1, i + 2) * at(j + 2, i + 1)
    });
    let det = &a[0] * &adj[0] + &a[1] * &adj[3] + &a[2] * &adj[6];
    if det.is_zero() {
        return None;
    }
    Some(ExactInverse { adj, det, e0 })
}

/// What the scene builder stores for [`super::InverseSource::PreInverted`]:
/// every entry of the exact `R⁻¹` rounded once to `fmt` in `mode`. A
/// singular or non-finite `R` gives nine canonical NaNs (which raise the
/// unit's `singular` flag).
pub fn scene_builder_inverse(fmt: FloatFormat, mode: RoundingMode, r: &[u64; 9]) -> [u64; 9] {
    match exact_inverse(fmt, r) {
        Some(inv) => inverse_entries(fmt, mode, &inv),
        None => [fmt.canonical_nan(); 9],
    }
}

/// The nine entries of an exact inverse, each rounded once.
pub fn inverse_entries(fmt: FloatFormat, mode: RoundingMode, inv: &ExactInverse) -> [u64; 9] {
    std::array::from_fn(|k| round_ratio(fmt, mode, &inv.adj[k], &inv.det, -inv.e0))
}

/// `Σ_j adj[i][j] · v_j` for the three rows, with `v = v_int · 2^ev`.
fn adj_times(inv: &ExactInverse, v: &[IBig]) -> [IBig; 3] {
    std::array::from_fn(|i| {
        &inv.adj[3 * i] * &v[0] + &inv.adj[3 * i + 1] * &v[1] + &inv.adj[3 * i + 2] * &v[2]
    })
}

/// The conventional inverse's translation column `u = −R⁻¹·T`, each entry
/// exact and rounded once (the best the conventional method can be given).
/// `None` if `T` is not finite.
pub fn scene_builder_translation(
    fmt: FloatFormat,
    mode: RoundingMode,
    inv: &ExactInverse,
    t: [u64; 3],
) -> Option<[u64; 3]> {
    let vals: Option<Vec<_>> = t.iter().map(|&x| decode(fmt, x)).collect();
    let (ti, et) = align(&vals?);
    let s = adj_times(inv, &ti);
    Some(s.map(|x| round_ratio(fmt, mode, &(-x), &inv.det, et - inv.e0)))
}

/// The reference model-space origin: `R⁻¹·(O_w − T)` computed exactly (the
/// subtraction too) and rounded once per component. `None` if `O_w` or `T`
/// is not finite.
pub fn reference_origin(
    fmt: FloatFormat,
    mode: RoundingMode,
    inv: &ExactInverse,
    t: [u64; 3],
    o: [u64; 3],
) -> Option<[u64; 3]> {
    let vals: Option<Vec<_>> = o.iter().chain(t.iter()).map(|&x| decode(fmt, x)).collect();
    let (v, e1) = align(&vals?);
    let d = [0, 1, 2].map(|k| &v[k] - &v[k + 3]);
    let s = adj_times(inv, &d);
    Some(s.map(|x| round_ratio(fmt, mode, &x, &inv.det, e1 - inv.e0)))
}

/// `M·(O_w − T)` for the stored (rounded) matrix `m`, computed exactly and
/// given as `f64` (relative error below 1e-15): what a correctly rounded
/// unit would round, to measure an output's error against the real value.
/// `None` if an input is not finite.
pub fn stored_product(
    fmt: FloatFormat,
    m: &[u64; 9],
    t: [u64; 3],
    o: [u64; 3],
) -> Option<[f64; 3]> {
    let vals: Option<Vec<_>> = o
        .iter()
        .chain(t.iter())
        .chain(m.iter())
        .map(|&x| decode(fmt, x))
        .collect();
    let vals = vals?;
    let (v, e_vec) = align(&vals[..6]);
    let (a, e_mat) = align(&vals[6..]);
    let d = [0, 1, 2].map(|k| &v[k] - &v[k + 3]);
    let to_f64 = |x: &IBig| {
        let shift = x.bit_len().saturating_sub(60);
        let head = i64::try_from(&(x >> shift)).expect("60 bits fit");
        head as f64 * (shift as f64 + (e_vec + e_mat) as f64).exp2()
    };
    Some([0, 1, 2].map(|i| {
        let s = &a[3 * i] * &d[0] + &a[3 * i + 1] * &d[1] + &a[3 * i + 2] * &d[2];
        to_f64(&s)
    }))
}

/// The reference model-space direction `R⁻¹·D_w`, exact, rounded once.
pub fn reference_dir(
    fmt: FloatFormat,
    mode: RoundingMode,
    inv: &ExactInverse,
    d: [u64; 3],
) -> Option<[u64; 3]> {
    let vals: Option<Vec<_>> = d.iter().map(|&x| decode(fmt, x)).collect();
    let (v, e1) = align(&vals?);
    let s = adj_times(inv, &v);
    Some(s.map(|x| round_ratio(fmt, mode, &x, &inv.det, e1 - inv.e0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_ratio_matches_f32_division_of_small_integers() {
        let f = FloatFormat::BINARY32;
        for n in -50i64..50 {
            for d in [1i64, 3, 7, -9, 10, 1 << 20, 12345] {
                let got = round_ratio(
                    f,
                    RoundingMode::NearestEven,
                    &IBig::from(n),
                    &IBig::from(d),
                    -3,
                );
                let want = (n as f64 / d as f64 / 8.0) as f32; // f64 quotient exact enough here
                let want = if want == 0.0 { 0.0f32 } else { want };
                assert_eq!(got, want.to_bits() as u64, "{n}/{d}/8");
            }
        }
    }

    #[test]
    fn inverse_of_a_scaled_permutation_is_exact() {
        let f = FloatFormat::BINARY32;
        let b = |x: f32| x.to_bits() as u64;
        let r = [0, b(2.0), 0, 0, 0, b(-4.0), b(0.5), 0, 0];
        let inv = scene_builder_inverse(f, RoundingMode::NearestEven, &r);
        assert_eq!(inv, [0, 0, b(2.0), b(0.5), 0, 0, 0, b(-0.25), 0]);
        let sing = [b(1.0), b(2.0), b(3.0), b(2.0), b(4.0), b(6.0), 0, 0, b(1.0)];
        assert!(exact_inverse(f, &sing).is_none());
    }
}
