//! Testbench of `ffma`: all triples of special values, then random triples:
//! `a · b` steered like `fmul`, `c` near the product's exponent (up to 2F + 6
//! places below or a few above), the negated rounded product with its low
//! bits perturbed (massive cancellation), or random; golden `float::fma`.

use super::fstim::{golden_format, FloatStim, ModeIn};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::{format, rounding};

/// The `ffma` testbench.
pub struct FFmaBench {
    stim: FloatStim,
    mode: ModeIn,
}

impl FFmaBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "ffma").expect("parameters were checked when building");
        FFmaBench {
            stim: FloatStim::new(fmt),
            mode: ModeIn { sel: rounding(p) },
        }
    }
}

/// An addend for the product `a · b`: near it, far below, cancelling, or random.
pub fn addend_for_product(s: &FloatStim, r: &mut VectorRng, a: u64, b: u64) -> u64 {
    let gf = golden_format(s.fmt);
    let f = s.fmt.frac_bits as i64;
    let p = g::mul(gf, a, b, g::RoundingMode::TowardZero);
    let ep = s.exp_of(p);
    match r.below(8) {
        0 | 1 => s.near(r, ep, 3),
        2 | 3 => {
            let d = r.below(2 * f as u64 + 8) as i64;
            s.near(r, ep - d, 0)
        }
        4 => s.neg(p) ^ (r.next_u64() & 3),
        5 => s.neg(p) ^ r.bits(s.fmt.frac_bits.min(10)),
        _ => s.any(r),
    }
}

impl sim::Golden for FFmaBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        o[0] = g::fma(
            golden_format(self.stim.fmt),
            i[0],
            i[1],
            i[2],
            self.mode.golden(i),
        );
    }
}

impl sim::Stimulus for FFmaBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let v = self.mode.fill(index, v);
        if self.stim.corner(self.mode.data_index(index), v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        let a = self.stim.any(&mut r);
        let b = self.stim.factor_for(&mut r, a);
        v[0] = a;
        v[1] = b;
        v[2] = addend_for_product(&self.stim, &mut r, a, b);
    }
}

impl Testbench for FFmaBench {}
