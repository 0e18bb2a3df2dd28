//! Testbench of `fmul`: all pairs of special values, then random pairs
//! whose product lands in the normal range, near overflow, near or inside
//! the subnormal range, or anywhere; golden `float::mul`.

use super::fstim::{golden_format, FloatStim, ModeIn};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::{format, rounding};

/// The `fmul` testbench.
pub struct FMulBench {
    stim: FloatStim,
    mode: ModeIn,
}

impl FMulBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "fmul").expect("parameters were checked when building");
        FMulBench {
            stim: FloatStim::new(fmt),
            mode: ModeIn { sel: rounding(p) },
        }
    }
}

impl sim::Golden for FMulBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        o[0] = g::mul(
            golden_format(self.stim.fmt),
            i[0],
            i[1],
            self.mode.golden(i),
        );
    }
}

impl sim::Stimulus for FMulBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let v = self.mode.fill(index, v);
        if self.stim.corner(self.mode.data_index(index), v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        let a = self.stim.any(&mut r);
        v[0] = a;
        v[1] = self.stim.factor_for(&mut r, a);
    }
}

impl Testbench for FMulBench {}
