//! Walking the encodings of a format in value order, and their exact values
//! as binary64: what stimulus generators and property tests use to place
//! values next to each other (one ulp above a bound, between two values).

use super::convert::convert;
use super::format::{FloatFormat, RoundingMode};

/// `v` rounded to nearest (ties to even) in `fmt`.
pub fn from_f64(fmt: FloatFormat, v: f64) -> u64 {
    convert(
        FloatFormat::BINARY64,
        fmt,
        v.to_bits(),
        RoundingMode::NearestEven,
    )
}

/// A uniform draw among the encodings from `lo` to `hi` (either order) in
/// the total order of [`total_key`]; `below(n)` draws uniformly from `0..n`
/// (each generator passes its own random source).
pub fn between(fmt: FloatFormat, lo: u64, hi: u64, below: impl FnOnce(u64) -> u64) -> u64 {
    let (a, b) = (total_key(fmt, lo), total_key(fmt, hi));
    let (a, b) = (a.min(b), a.max(b));
    from_total_key(fmt, a + below((b - a + 1) as u64) as i64)
}

/// The value of `bits` as binary64 (exact for every supported format).
pub fn to_f64(fmt: FloatFormat, bits: u64) -> f64 {
    f64::from_bits(convert(
        fmt,
        FloatFormat::BINARY64,
        bits,
        RoundingMode::NearestEven,
    ))
}

/// Position of the non-NaN encoding `bits` in the total order of `fmt`'s
/// encodings, `−0` one place below `+0`: the magnitude bits, or
/// `−magnitude − 1` when negative ([`from_total_key`] inverts it).
pub const fn total_key(fmt: FloatFormat, bits: u64) -> i64 {
    let magnitude = (bits & fmt.mask() & !fmt.sign_bit()) as i64;
    if bits & fmt.sign_bit() != 0 {
        -magnitude - 1
    } else {
        magnitude
    }
}

/// `a` and `b` in [`total_key`] order (the smaller first; `a` first when
/// they are the same value): the bounds of an interval drawn as two values.
pub const fn ordered(fmt: FloatFormat, a: u64, b: u64) -> (u64, u64) {
    if total_key(fmt, a) <= total_key(fmt, b) {
        (a, b)
    } else {
        (b, a)
    }
}

/// The encoding at position `k` of [`total_key`].
pub const fn from_total_key(fmt: FloatFormat, k: i64) -> u64 {
    if k < 0 {
        (-(k + 1)) as u64 | fmt.sign_bit()
    } else {
        k as u64
    }
}

/// `bits` moved by `n` places in the total order (through both zeros),
/// clamped to the finite values.
pub fn nudge(fmt: FloatFormat, bits: u64, n: i64) -> u64 {
    let top = total_key(fmt, fmt.max_finite(false));
    from_total_key(fmt, (total_key(fmt, bits) + n).clamp(-top - 1, top))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_total_order_walks_every_finite_encoding_once() {
        let f = FloatFormat::new(3, 2).unwrap();
        let top = total_key(f, f.max_finite(false));
        let mut prev = f64::NEG_INFINITY;
        for k in -top - 1..=top {
            let b = from_total_key(f, k);
            assert_eq!(total_key(f, b), k);
            let v = to_f64(f, b);
            // −0 then +0 compare equal; every other step increases
            assert!(
                v > prev || (v == 0.0 && prev == 0.0),
                "{k}: {v} after {prev}"
            );
            prev = v;
        }
        assert_eq!(nudge(f, f.max_finite(false), 1), f.max_finite(false));
        assert_eq!(nudge(f, f.zero(false), -1), f.zero(true));
        assert_eq!(nudge(f, f.zero(true), -1), f.min_subnormal(true));
    }
}
