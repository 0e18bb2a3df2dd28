//! Testbench of `fmul_exact`: the `fmul` stimulus; golden `float::mul_exact`.

use super::fstim::{golden_format, FloatStim};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::format;

/// The `fmul_exact` testbench.
pub struct FMulExactBench {
    stim: FloatStim,
    pair: g::ExactProductFormat,
}

impl FMulExactBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "fmul_exact").expect("parameters were checked when building");
        let pair = g::ExactProductFormat::new(golden_format(fmt)).expect("checked when building");
        FMulExactBench {
            stim: FloatStim::new(fmt),
            pair,
        }
    }
}

impl sim::Golden for FMulExactBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        o[0] = g::mul_exact(self.pair, i[0], i[1]);
    }
}

impl sim::Stimulus for FMulExactBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        if self.stim.corner(index, v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        let a = self.stim.any(&mut r);
        v[0] = a;
        v[1] = self.stim.factor_for(&mut r, a);
    }
}

impl Testbench for FMulExactBench {}
