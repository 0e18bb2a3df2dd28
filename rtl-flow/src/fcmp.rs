//! Testbench of `fcmp`: all pairs of special values, then random pairs:
//! equal, negated, one encoding apart, close, or random; golden
//! `float::lt`, `le`, `eq`.

use super::fstim::{golden_format, FloatStim};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::format;

/// The `fcmp` testbench.
pub struct FCmpBench {
    stim: FloatStim,
}

impl FCmpBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "fcmp").expect("parameters were checked when building");
        FCmpBench {
            stim: FloatStim::new(fmt),
        }
    }
}

/// A second operand to compare with `a`.
pub fn compare_partner(s: &FloatStim, r: &mut VectorRng, a: u64) -> u64 {
    let m = (1u64 << (s.fmt.width() - 1)) * 2 - 1;
    match r.below(6) {
        0 => a,
        1 => s.neg(a),
        2 => a.wrapping_add(1) & m,
        3 => a.wrapping_sub(1) & m,
        4 => s.addend_for(r, a),
        _ => s.any(r),
    }
}

impl sim::Golden for FCmpBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        let f = golden_format(self.stim.fmt);
        o[0] = g::lt(f, i[0], i[1]) as u64;
        o[1] = g::le(f, i[0], i[1]) as u64;
        o[2] = g::eq(f, i[0], i[1]) as u64;
    }
}

impl sim::Stimulus for FCmpBench {
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

impl Testbench for FCmpBench {}
