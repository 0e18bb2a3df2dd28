//! Testbench of `fadd_down_up`: the `fadd` stimulus; golden `float::add_down_up`.

use super::fstim::{golden_format, FloatStim};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::format;

/// The `fadd_down_up` testbench.
pub struct FAddDownUpBench {
    stim: FloatStim,
}

impl FAddDownUpBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "fadd_down_up").expect("parameters were checked when building");
        FAddDownUpBench {
            stim: FloatStim::new(fmt),
        }
    }
}

impl sim::Golden for FAddDownUpBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        let r = g::add_down_up(golden_format(self.stim.fmt), i[0], i[1]);
        o[0] = r.down;
        o[1] = r.up;
    }
}

impl sim::Stimulus for FAddDownUpBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        if self.stim.corner(index, v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        let a = self.stim.any(&mut r);
        v[0] = a;
        v[1] = self.stim.addend_for(&mut r, a);
    }
}

impl Testbench for FAddDownUpBench {}
