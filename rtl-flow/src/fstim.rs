//! Stimulus shared by the float operator testbenches, and the adapters to
//! the golden model's `golden_model::float` types.
//!
//! Every testbench starts with corner vectors built from [`FloatStim::specials`]
//! (±0, ±inf, NaNs with several payloads and signs, smallest and largest
//! subnormal and normal, values around 1 and 2, carries out of rounding),
//! then seeded random vectors whose exponents are biased per operator so
//! that the interesting cases are common: close exponents and exact
//! cancellation for sums, alignment shifts around F for rounding, products
//! near overflow and in the subnormal range, addends near the product for
//! fused operations, and fractions with long runs of zeros or ones (halfway
//! cases and carries).

use super::stimulus::VectorRng;
use golden_model::float::{FloatFormat, RoundingMode};
use rtl_gen::arith::float::{Format, RoundSel, Rounding};

/// The golden model's format for `fmt`.
pub fn golden_format(fmt: Format) -> FloatFormat {
    FloatFormat::new(fmt.exp_bits, fmt.frac_bits).expect("formats agree on validity")
}

/// The golden model's rounding mode for `mode`.
pub fn golden_mode(mode: Rounding) -> RoundingMode {
    match mode {
        Rounding::Rne => RoundingMode::NearestEven,
        Rounding::Rtz => RoundingMode::TowardZero,
        Rounding::Rup => RoundingMode::Up,
        Rounding::Rdn => RoundingMode::Down,
    }
}

/// The rounding mode of a testbench: fixed, or carried by the last input
/// (`rm`) of each vector, cycling through the four modes (vector `i` has
/// mode `i % 4`; corner vectors are each repeated in the four modes).
#[derive(Debug, Clone, Copy)]
pub struct ModeIn {
    /// fixed or `dyn`
    pub sel: RoundSel,
}

impl ModeIn {
    /// The index of the data part of vector `index` (for corner tables).
    pub fn data_index(&self, index: u64) -> u64 {
        match self.sel {
            RoundSel::Port => index / 4,
            RoundSel::Fixed(_) => index,
        }
    }

    /// Sets the `rm` input of vector `index` (if any) and returns the data inputs.
    pub fn fill<'a>(&self, index: u64, v: &'a mut [u64]) -> &'a mut [u64] {
        match self.sel {
            RoundSel::Port => {
                let n = v.len() - 1;
                v[n] = Rounding::ALL[(index % 4) as usize].rm_code() as u64;
                &mut v[..n]
            }
            RoundSel::Fixed(_) => v,
        }
    }

    /// The golden model's mode for a vector with these inputs.
    pub fn golden(&self, inputs: &[u64]) -> RoundingMode {
        match self.sel {
            RoundSel::Fixed(r) => golden_mode(r),
            RoundSel::Port => match inputs[inputs.len() - 1] {
                0 => RoundingMode::NearestEven,
                1 => RoundingMode::TowardZero,
                2 => RoundingMode::Down,
                _ => RoundingMode::Up,
            },
        }
    }
}

/// Operand generator of one format.
#[derive(Debug, Clone)]
pub struct FloatStim {
    /// the format
    pub fmt: Format,
    /// special and corner encodings
    pub specials: Vec<u64>,
}

impl FloatStim {
    /// The generator for `fmt`.
    pub fn new(fmt: Format) -> FloatStim {
        let s = FloatStim {
            fmt,
            specials: Vec::new(),
        };
        let (f, ones) = (fmt.frac_bits, fmt.exp_ones() as u64);
        let bias = fmt.bias() as u64;
        let fm = (1u64 << f) - 1;
        let mut v = Vec::new();
        for sign in [0, 1] {
            v.extend([
                s.pack(sign, 0, 0),                           // zero
                s.pack(sign, ones, 0),                        // infinity
                s.pack(sign, 0, 1),                           // smallest subnormal
                s.pack(sign, 0, fm),                          // largest subnormal
                s.pack(sign, 1, 0),                           // smallest normal
                s.pack(sign, 1, 1),                           // just above it
                s.pack(sign, ones - 1, fm),                   // largest finite
                s.pack(sign, ones - 1, fm - (fm > 0) as u64), // one ulp below
                s.pack(sign, bias, 0),                        // 1
                s.pack(sign, bias, 1),                        // 1 + ulp
                s.pack(sign, bias - 1, fm), // 1 - ulp/2 (or a subnormal for tiny E)
                s.pack(sign, bias, fm),     // 2 - ulp
                s.pack(sign, bias, 1u64 << (f - 1)), // 1.5
            ]);
        }
        v.extend([
            fmt.nan_bits() as u64,
            s.pack(0, ones, 1),
            s.pack(1, ones, fm),
            s.pack(1, ones, 1u64 << (f - 1)),
        ]);
        v.sort_unstable();
        v.dedup();
        FloatStim { fmt, specials: v }
    }

    /// The encoding of sign, biased exponent and fraction.
    pub fn pack(&self, sign: u64, exp: u64, frac: u64) -> u64 {
        let (e, f) = (self.fmt.exp_bits, self.fmt.frac_bits);
        (sign << (e + f)) | ((exp & ((1 << e) - 1)) << f) | (frac & ((1u64 << f) - 1))
    }

    /// The biased exponent field of `x`.
    pub fn exp_of(&self, x: u64) -> i64 {
        ((x >> self.fmt.frac_bits) & self.fmt.exp_ones() as u64) as i64
    }

    /// A fraction with a random structure: uniform, long runs of zeros or
    /// ones at the bottom (halfway cases, carries), sparse or dense bits.
    pub fn frac(&self, r: &mut VectorRng) -> u64 {
        let f = self.fmt.frac_bits;
        let fm = (1u64 << f) - 1;
        let k = r.below(f as u64 + 1) as u32;
        let low = if k == 0 { 0 } else { (1u64 << k) - 1 };
        match r.below(8) {
            0 | 1 => r.next_u64() & fm,
            2 => r.next_u64() & fm & !low,
            3 => (r.next_u64() | low) & fm,
            4 => r.next_u64() & r.next_u64() & r.next_u64() & fm,
            5 => (r.next_u64() | r.next_u64() | r.next_u64()) & fm,
            6 => (1u64 << r.below(f as u64)) & fm,
            _ => [0, fm, 1u64 << (f - 1), fm >> 1][r.below(4) as usize],
        }
    }

    /// A finite or special value with biased exponent `exp` clamped to the
    /// field (an exponent below 1 gives a subnormal or zero, above the
    /// largest finite one an infinity or NaN), random sign and fraction.
    pub fn with_exp(&self, r: &mut VectorRng, exp: i64) -> u64 {
        let e = exp.clamp(0, self.fmt.exp_ones() as i64) as u64;
        let sign = r.below(2);
        let frac = self.frac(r);
        self.pack(sign, e, frac)
    }

    /// A random operand: now and then a special value, a subnormal, or a
    /// random encoding; mostly a finite value with exponent near `center`
    /// (±`spread`).
    pub fn near(&self, r: &mut VectorRng, center: i64, spread: i64) -> u64 {
        match r.below(16) {
            0 => self.specials[r.below(self.specials.len() as u64) as usize],
            1 => self.with_exp(r, 0),
            2 => r.bits(self.fmt.width()),
            _ => {
                let d = r.below(2 * spread as u64 + 1) as i64 - spread;
                self.with_exp(r, center + d)
            }
        }
    }

    /// A random operand with a uniformly random exponent field.
    pub fn any(&self, r: &mut VectorRng) -> u64 {
        let c = r.below(self.fmt.exp_ones() as u64 + 1) as i64;
        self.near(r, c, 0)
    }

    /// The special value number `i` (cyclic).
    pub fn special(&self, i: u64) -> u64 {
        self.specials[(i % self.specials.len() as u64) as usize]
    }

    /// Number of special values.
    pub fn n(&self) -> u64 {
        self.specials.len() as u64
    }

    /// `x` negated.
    pub fn neg(&self, x: u64) -> u64 {
        x ^ (1u64 << (self.fmt.width() - 1))
    }

    /// Fills `v` with special values for corner vector `index` (the index
    /// read in base `n`), if `index < n^v.len()`.
    pub fn corner(&self, index: u64, v: &mut [u64]) -> bool {
        let n = self.n();
        let total = n.checked_pow(v.len() as u32).unwrap_or(u64::MAX);
        if index >= total {
            return false;
        }
        let mut k = index;
        for x in v.iter_mut() {
            *x = self.special(k % n);
            k /= n;
        }
        true
    }

    /// A second addend for `a`: close exponent, an alignment shift around F
    /// (rounding boundaries), exact or near cancellation, or random.
    pub fn addend_for(&self, r: &mut VectorRng, a: u64) -> u64 {
        let f = self.fmt.frac_bits as i64;
        let ea = self.exp_of(a);
        match r.below(8) {
            0 | 1 => self.near(r, ea, 2),
            2 => {
                let d = r.below(6) as i64;
                self.near(r, ea - f + 2 - d, 0)
            }
            3 => self.neg(a) ^ (r.next_u64() & 3),
            4 => self.neg(a) ^ r.bits(self.fmt.frac_bits.min(8)),
            5 => a ^ r.bits(3),
            6 => self.near(r, 1, 3),
            _ => self.any(r),
        }
    }

    /// A second factor for `a` steering the product's exponent to the
    /// normal range, near overflow, near or into the subnormal range, or
    /// anywhere.
    pub fn factor_for(&self, r: &mut VectorRng, a: u64) -> u64 {
        let (f, bias) = (self.fmt.frac_bits as i64, self.fmt.bias());
        let top = self.fmt.exp_ones() as i64 - 1;
        let ea = self.exp_of(a).max(1);
        let target = match r.below(6) {
            0 | 1 => r.below(2 * bias as u64 + 1) as i64,
            2 => top - r.below(3) as i64,
            3 => 1 - r.below(f as u64 + 3) as i64,
            4 => 2 - r.below(3) as i64,
            _ => return self.any(r),
        };
        self.near(r, target - ea + bias, 1)
    }
}
