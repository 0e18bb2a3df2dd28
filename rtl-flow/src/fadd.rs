//! Testbench of `fadd`: all pairs of special values, then random pairs
//! whose second operand has a close exponent, an alignment shift around F,
//! (near) cancellation, or is random; golden `float::add` / `float::sub`.

use super::fstim::{golden_format, FloatStim, ModeIn};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::{format, rounding};

/// The `fadd` testbench.
pub struct FAddBench {
    stim: FloatStim,
    mode: ModeIn,
    sub: bool,
}

impl FAddBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "fadd").expect("parameters were checked when building");
        FAddBench {
            stim: FloatStim::new(fmt),
            mode: ModeIn { sel: rounding(p) },
            sub: p.word("op") == "sub",
        }
    }
}

impl sim::Golden for FAddBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        let (f, m) = (golden_format(self.stim.fmt), self.mode.golden(i));
        o[0] = if self.sub {
            g::sub(f, i[0], i[1], m)
        } else {
            g::add(f, i[0], i[1], m)
        };
    }
}

impl sim::Stimulus for FAddBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let v = self.mode.fill(index, v);
        if self.stim.corner(self.mode.data_index(index), v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        let a = self.stim.any(&mut r);
        let b = self.stim.addend_for(&mut r, a);
        v[0] = a;
        v[1] = if self.sub { self.stim.neg(b) } else { b };
    }
}

impl Testbench for FAddBench {}
