//! Shared test helpers: a PRNG, operand generators, and the oracles.
#![allow(dead_code)]

pub mod apfloat;
pub mod exact;

use golden_model::float::{FloatFormat, RoundingMode};

/// SplitMix64: small, fast, deterministic.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x9e37_79b9_7f4a_7c15)
    }
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in `0..n` (n > 0; slight bias is irrelevant here).
    pub fn below(&mut self, n: u64) -> u64 {
        ((self.next() as u128 * n as u128) >> 64) as u64
    }
    pub fn bool(&mut self) -> bool {
        self.next() & 1 == 1
    }
    /// Uniform in `lo..=hi`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + self.below((hi - lo + 1) as u64) as i64
    }
}

/// Interesting values of a format: zeros, infinities, several NaNs, the
/// subnormal and normal extremes, one and its neighbours, both signs.
pub fn specials(fmt: FloatFormat) -> Vec<u64> {
    let f = fmt.frac_bits();
    let one = fmt.one(false);
    let mut mags = vec![
        0,
        1,
        2,
        3,
        fmt.frac_mask() - 1,
        fmt.frac_mask(),
        fmt.min_normal(false),
        fmt.min_normal(false) + 1,
        fmt.max_finite(false),
        fmt.max_finite(false) - 1,
        one,
        one + 1,
        one - 1,
        one + fmt.frac_mask(),
        fmt.inf(false),
        fmt.canonical_nan(),
        fmt.inf(false) + 1,
        fmt.inf(false) | fmt.frac_mask(),
    ];
    if f >= 2 {
        mags.push(fmt.inf(false) | (1 << (f - 2)));
    }
    let mut v: Vec<u64> = mags.iter().flat_map(|&m| [m, m | fmt.sign_bit()]).collect();
    v.sort();
    v.dedup();
    v
}

/// A random operand: a mix of uniformly random bit patterns, specials, and
/// finite values with structured fractions (runs of ones or zeros, few
/// bits set, trailing zeros) that make halfway and carry cases likely.
pub fn operand(rng: &mut Rng, fmt: FloatFormat, specials: &[u64]) -> u64 {
    match rng.below(16) {
        0..=4 => rng.next() & fmt.mask(),
        5 => specials[rng.below(specials.len() as u64) as usize],
        _ => {
            let biased = match rng.below(8) {
                0 => 0,
                1 => 1 + rng.below(3),
                2 => fmt.exp_all_ones() - 1 - rng.below(3),
                _ => 1 + rng.below(fmt.exp_all_ones() - 1),
            };
            let sign = rng.bool();
            fmt.with_sign(sign, (biased << fmt.frac_bits()) | fraction(rng, fmt))
        }
    }
}

/// A finite operand whose exponent is within `spread` of `near`'s (if `near`
/// is finite nonzero), for cancellation and alignment cases.
pub fn operand_near(rng: &mut Rng, fmt: FloatFormat, near: u64, spread: i64) -> u64 {
    let f = fmt.frac_bits();
    let biased = ((near >> f) & fmt.exp_all_ones()) as i64;
    let max_biased = fmt.exp_all_ones() as i64 - 1;
    let e = (biased + rng.range(-spread, spread)).clamp(0, max_biased) as u64;
    let mut frac = fraction(rng, fmt);
    if rng.below(4) == 0 {
        // Same fraction as `near` but for a few low bits: deep cancellation.
        frac = (near & fmt.frac_mask()) ^ (rng.next() & 0x7 & fmt.frac_mask());
    }
    fmt.with_sign(rng.bool(), (e << f) | frac)
}

/// A fraction field with structure.
pub fn fraction(rng: &mut Rng, fmt: FloatFormat) -> u64 {
    let f = fmt.frac_bits();
    let m = fmt.frac_mask();
    match rng.below(8) {
        0 => 0,
        1 => m,
        2 => 1 << rng.below(f as u64),
        3 => m ^ (1 << rng.below(f as u64)),
        4 => (rng.next() & m) >> rng.below(f as u64 + 1),
        5 => (rng.next() & m) & !((1 << rng.below(f as u64 + 1)) - 1),
        _ => rng.next() & m,
    }
}

/// The formats checked against the oracles (other than the exhaustive ones).
pub fn formats() -> Vec<FloatFormat> {
    [(8, 23), (5, 10), (8, 7), (8, 15), (6, 9), (11, 52)]
        .iter()
        .map(|&(e, f)| FloatFormat::new(e, f).unwrap())
        .collect()
}

pub fn mode_name(m: RoundingMode) -> &'static str {
    match m {
        RoundingMode::NearestEven => "RNE",
        RoundingMode::TowardZero => "RTZ",
        RoundingMode::Down => "RDN",
        RoundingMode::Up => "RUP",
    }
}

/// Counts mismatches and keeps the first few, printed in hex on failure.
pub struct Tally {
    pub what: String,
    pub checked: u64,
    pub failed: u64,
    pub examples: Vec<String>,
}

impl Tally {
    pub fn new(what: impl Into<String>) -> Tally {
        Tally {
            what: what.into(),
            checked: 0,
            failed: 0,
            examples: Vec::new(),
        }
    }
    pub fn check(&mut self, ok: bool, describe: impl FnOnce() -> String) {
        self.checked += 1;
        if !ok {
            self.failed += 1;
            if self.examples.len() < 20 {
                self.examples.push(describe());
            }
        }
    }
    /// Prints the count (visible with `--nocapture`) and fails on mismatches.
    pub fn finish(self) -> u64 {
        println!("{}: {} vectors checked", self.what, self.checked);
        assert!(
            self.failed == 0,
            "{}: {} of {} mismatched; first ones:\n{}",
            self.what,
            self.failed,
            self.checked,
            self.examples.join("\n")
        );
        self.checked
    }
}

/// The binary32 triangle unit's input for the ray `o + t·d`, `t` in
/// `[0, ∞]`, against the triangle `tri` (shear constants from `d`).
pub fn triangle_ray(o: [f32; 3], d: [f32; 3], tri: [[f32; 3]; 3]) -> golden_model::triangle::TriIn {
    let bits = |x: f32| x.to_bits() as u64;
    let (kz, s) = golden_model::triangle::shear(FloatFormat::BINARY32, d.map(bits));
    golden_model::triangle::TriIn {
        o: o.map(bits),
        kz,
        s,
        a: tri[0].map(bits),
        b: tri[1].map(bits),
        c: tri[2].map(bits),
        t_min: bits(0.0),
        t_max: bits(f32::INFINITY),
    }
}
