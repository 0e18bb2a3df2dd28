//! Testbench of `frecip`: every special value, then operands of any
//! exponent (normal, subnormal, near the reciprocal's overflow and
//! underflow); golden `transform::recip`.

use super::fstim::{golden_format, golden_mode, FloatStim};
use super::stimulus::VectorRng;
use super::Testbench;
use rtl_gen::arith::float::Rounding;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::format;
use rtl_gen::units::float_ops::recip_mode;

/// The `frecip` testbench.
pub struct FRecipBench {
    stim: FloatStim,
    mode: Rounding,
}

impl FRecipBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "frecip").expect("parameters were checked when building");
        FRecipBench {
            stim: FloatStim::new(fmt),
            mode: recip_mode(p),
        }
    }
}

impl sim::Golden for FRecipBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        o[0] = golden_model::transform::recip(
            golden_format(self.stim.fmt),
            i[0],
            golden_mode(self.mode),
        );
    }
}

impl sim::Stimulus for FRecipBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        if self.stim.corner(index, v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        v[0] = self.stim.any(&mut r);
    }
}

impl Testbench for FRecipBench {}
