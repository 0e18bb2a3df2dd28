//! Testbench of `funpack`: every special value, then random encodings
//! (biased exponents, structured fractions); golden `float::unpack`.

use super::fstim::{golden_format, FloatStim};
use super::stimulus::{mask, VectorRng};
use super::Testbench;
use golden_model::float as g;
use rtl_gen::arith::float::unpack::lsb_exp_width;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::format;

/// The `funpack` testbench.
pub struct FUnpackBench {
    stim: FloatStim,
    exp_width: u32,
}

impl FUnpackBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "funpack").expect("parameters were checked when building");
        FUnpackBench {
            stim: FloatStim::new(fmt),
            exp_width: lsb_exp_width(fmt),
        }
    }
}

impl sim::Golden for FUnpackBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        let r = g::unpack(golden_format(self.stim.fmt), i[0]);
        o[0] = r.sign as u64;
        o[1] = r.class as u64;
        o[2] = r.exp as i64 as u64 & mask(self.exp_width);
        o[3] = r.sig as u64;
    }
}

impl sim::Stimulus for FUnpackBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        if self.stim.corner(index, v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        v[0] = self.stim.any(&mut r);
    }
}

impl Testbench for FUnpackBench {}
