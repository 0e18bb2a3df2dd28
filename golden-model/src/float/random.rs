//! Random values of a format for stimulus: the helpers the golden-model
//! tests and the flow's testbenches share. Each caller brings its own
//! random source ([`Random`]), so the same helper draws the caller's stream.

use super::format::FloatFormat;
use super::order::{self, from_f64, ordered};

/// A source of random bits.
pub trait Random {
    /// The next 64 random bits.
    fn next_u64(&mut self) -> u64;
    /// A uniform value in `0..n` (`n > 0`).
    fn below(&mut self, n: u64) -> u64;
    /// True with probability `num / den`.
    fn chance(&mut self, num: u64, den: u64) -> bool {
        self.below(den) < num
    }
    /// A uniform value in `[0, 1)` with 53 random bits.
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// A uniform integer in `lo..=hi`.
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + self.below((hi - lo + 1) as u64) as i64
    }
}

/// A uniform draw among the encodings from `lo` to `hi` in the total order
/// ([`order::between`] with `rng`).
pub fn between(fmt: FloatFormat, rng: &mut impl Random, lo: u64, hi: u64) -> u64 {
    order::between(fmt, lo, hi, |n| rng.below(n))
}

/// A finite value around `2^scale` (± `spread` binades), random sign,
/// sometimes a zero of either sign; saturates at the largest finite value.
pub fn rand_val(fmt: FloatFormat, rng: &mut impl Random, scale: i32, spread: i32) -> u64 {
    if rng.chance(1, 40) {
        return fmt.zero(rng.chance(1, 2));
    }
    let k = scale + rng.range(-(spread as i64), spread as i64) as i32;
    let v = (1.0 + rng.unit()) * 2f64.powi(k.clamp(-1070, 1020));
    let negative = rng.chance(1, 2);
    let r = from_f64(fmt, if negative { -v } else { v });
    if r & !fmt.sign_bit() == fmt.inf(false) {
        fmt.max_finite(negative)
    } else {
        r
    }
}

/// The scale of one case: mostly moderate, sometimes near overflow, in the
/// subnormals or around the smallest normal.
pub fn rand_scale(fmt: FloatFormat, rng: &mut impl Random) -> i32 {
    let lowest = fmt.emin() - fmt.frac_bits() as i32;
    match rng.below(10) {
        0 => fmt.emax() - rng.range(0, 3) as i32,
        1 => lowest + rng.range(0, 6) as i32,
        2 => fmt.emin() + rng.range(-2, 4) as i32,
        _ => rng.range(-6, 6) as i32,
    }
}

/// A random nonempty box at `scale`, `(lower, upper)` corners; an axis is
/// sometimes flat.
pub fn rand_box(fmt: FloatFormat, rng: &mut impl Random, scale: i32) -> ([u64; 3], [u64; 3]) {
    let mut lo = [0; 3];
    let mut hi = [0; 3];
    for i in 0..3 {
        let a = rand_val(fmt, rng, scale, 2);
        let b = if rng.chance(1, 12) {
            a
        } else {
            rand_val(fmt, rng, scale, 2)
        };
        (lo[i], hi[i]) = ordered(fmt, a, b);
    }
    (lo, hi)
}

/// A point of the box `[lo, hi]`: on a bound along the axes set in
/// `boundary` (either bound at random), anywhere between them along the
/// others.
pub fn point_of_box(
    fmt: FloatFormat,
    rng: &mut impl Random,
    lo: &[u64; 3],
    hi: &[u64; 3],
    boundary: u32,
) -> [u64; 3] {
    [0, 1, 2].map(|i| {
        if boundary >> i & 1 == 1 {
            if rng.chance(1, 2) {
                lo[i]
            } else {
                hi[i]
            }
        } else {
            between(fmt, rng, lo[i], hi[i])
        }
    })
}
