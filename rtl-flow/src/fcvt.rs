//! Testbench of `fcvt`: every special value of the source format, then
//! random values whose exponent lies near the target's overflow threshold,
//! its smallest normal, its subnormal range and below it, around 1, or
//! anywhere (fractions with runs of zeros and ones give halfway cases);
//! golden `float::convert`.

use super::fstim::{golden_format, FloatStim, ModeIn};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::arith::float::Format;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::{format_of, rounding};

/// The `fcvt` testbench.
pub struct FCvtBench {
    stim: FloatStim,
    to: Format,
    mode: ModeIn,
}

impl FCvtBench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let from = format_of(p, "fcvt", "exp_bits", "frac_bits").expect("checked when building");
        let to =
            format_of(p, "fcvt", "to_exp_bits", "to_frac_bits").expect("checked when building");
        FCvtBench {
            stim: FloatStim::new(from),
            to,
            mode: ModeIn { sel: rounding(p) },
        }
    }
}

impl sim::Golden for FCvtBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        o[0] = g::convert(
            golden_format(self.stim.fmt),
            golden_format(self.to),
            i[0],
            self.mode.golden(i),
        );
    }
}

impl sim::Stimulus for FCvtBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let v = self.mode.fill(index, v);
        if self.stim.corner(self.mode.data_index(index), v) {
            return;
        }
        let mut r = VectorRng::new(seed, index);
        let to = self.to;
        let target = match r.below(6) {
            0 => to.emax() + 1 - r.below(3) as i64,
            1 => to.emin() + 1 - r.below(3) as i64,
            2 => to.emin() - r.below(to.frac_bits as u64 + 3) as i64,
            3 => r.below(5) as i64 - 2,
            _ => {
                v[0] = self.stim.any(&mut r);
                return;
            }
        };
        v[0] = self.stim.near(&mut r, target + self.stim.fmt.bias(), 0);
    }
}

impl Testbench for FCvtBench {}
