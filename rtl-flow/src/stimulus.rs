//! Counter-based random numbers for stimulus: vector `index` of seed `seed`
//! is computed directly, so any vector can be regenerated alone (replay,
//! sharding) and generation parallelises without shared state.

use golden_model::float::random::Random;
use golden_model::float::{from_f64, FloatFormat};
use sim::mix64;

/// A small generator for one vector, seeded by (seed, index).
#[derive(Debug, Clone)]
pub struct VectorRng {
    state: u64,
}

impl VectorRng {
    /// The generator of vector `index` under `seed`.
    pub fn new(seed: u64, index: u64) -> Self {
        VectorRng {
            state: mix64(seed ^ mix64(index)),
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        mix64(self.state)
    }

    /// A uniform value below `n` (n > 0); the tiny modulo bias is irrelevant for stimulus.
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    /// A random value of `width` bits (1..=64).
    pub fn bits(&mut self, width: u32) -> u64 {
        self.next_u64() & mask(width)
    }
}

/// The low `width` bits set (width 1..=64).
pub fn mask(width: u32) -> u64 {
    if width >= 64 {
        u64::MAX
    } else {
        (1u64 << width) - 1
    }
}

/// Interesting values of an unsigned `width`-bit operand: 0, 1, 2, the
/// largest, one less, the top bit alone, and just below it.
pub fn unsigned_corners(width: u32) -> Vec<u64> {
    let m = mask(width);
    let top = 1u64 << (width - 1);
    let mut v = vec![0, 1, 2, m, m.wrapping_sub(1), top, top.wrapping_sub(1)];
    v.iter_mut().for_each(|x| *x &= m);
    v.sort_unstable();
    v.dedup();
    v
}

impl Random for VectorRng {
    fn next_u64(&mut self) -> u64 {
        VectorRng::next_u64(self)
    }
    fn below(&mut self, n: u64) -> u64 {
        VectorRng::below(self, n)
    }
}

/// Special values of `fmt`: zeros, infinities, NaNs (with payload and
/// sign), the smallest and largest subnormal, the smallest normal, the
/// largest finite value, ±1.
pub fn specials(fmt: FloatFormat) -> Vec<u64> {
    let one = from_f64(fmt, 1.0);
    let mut v = Vec::new();
    for neg in [false, true] {
        v.extend([
            fmt.zero(neg),
            fmt.inf(neg),
            fmt.min_subnormal(neg),
            fmt.max_subnormal(neg),
            fmt.min_normal(neg),
            fmt.max_finite(neg),
            fmt.with_sign(neg, one),
        ]);
    }
    v.push(fmt.canonical_nan());
    v.push(fmt.canonical_nan() | fmt.sign_bit() | 1);
    v
}
