//! Testbench of `fminmax`: the `fcmp` stimulus; golden `float::min`, `max`.

use super::fcmp::compare_partner;
use super::fstim::{golden_format, FloatStim};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::format;

/// The `fminmax` testbench.
pub struct FMinMaxBench {
    stim: FloatStim,
}

impl FMinMaxBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "fminmax").expect("parameters were checked when building");
        FMinMaxBench {
            stim: FloatStim::new(fmt),
        }
    }
}

impl sim::Golden for FMinMaxBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        let f = golden_format(self.stim.fmt);
        o[0] = g::min(f, i[0], i[1]);
        o[1] = g::max(f, i[0], i[1]);
    }
}

impl sim::Stimulus for FMinMaxBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        if self.stim.corner(index, v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        let a = self.stim.any(&mut r);
        v[0] = a;
        v[1] = compare_partner(&self.stim, &mut r, a);
    }
}

impl Testbench for FMinMaxBench {}
