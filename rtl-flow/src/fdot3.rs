//! Testbench of `fdot3`: special values in every operand position (all
//! triples over the `a`s with the `b`s ±1, and the converse), then random
//! vectors: products with close, spread or far exponents, pairs that cancel
//! exactly or nearly (leaving the third product, or nothing), and random
//! operands; golden `float::dot3`. Ports: a0, b0, a1, b1, a2, b2.

use super::ffma::addend_for_product;
use super::fstim::{golden_format, FloatStim, ModeIn};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float as g;
use rtl_gen::params::Params;
use rtl_gen::units::float_ops::{format, rounding};

/// The `fdot3` testbench.
pub struct FDot3Bench {
    stim: FloatStim,
    mode: ModeIn,
}

impl FDot3Bench {
    /// The testbench for resolved parameters.
    pub fn new(p: &Params) -> Self {
        let fmt = format(p, "fdot3").expect("parameters were checked when building");
        FDot3Bench {
            stim: FloatStim::new(fmt),
            mode: ModeIn { sel: rounding(p) },
        }
    }
}

impl sim::Golden for FDot3Bench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        o[0] = g::dot3(
            golden_format(self.stim.fmt),
            [i[0], i[2], i[4]],
            [i[1], i[3], i[5]],
            self.mode.golden(i),
        );
    }
}

impl sim::Stimulus for FDot3Bench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let v = self.mode.fill(index, v);
        let data_index = self.mode.data_index(index);
        let s = &self.stim;
        let one = s.pack(0, s.fmt.bias() as u64, 0);
        let mut three = [0u64; 3];
        let n3 = s.n().pow(3);
        if data_index < 2 * n3 && s.corner(data_index % n3, &mut three) {
            let (sp, fix) = if data_index < n3 { (0, 1) } else { (1, 0) };
            for k in 0..3 {
                v[2 * k + sp] = three[k];
                v[2 * k + fix] = if (data_index >> k) & 1 == 1 {
                    s.neg(one)
                } else {
                    one
                };
            }
            return;
        }
        let mut r = VectorRng::new(seed, index);
        let a0 = s.any(&mut r);
        let b0 = s.factor_for(&mut r, a0);
        v[0] = a0;
        v[1] = b0;
        for k in 1..3 {
            let (a, b) = match r.below(6) {
                // cancel a previous product exactly or nearly
                0 => (s.neg(v[0]), v[1] ^ (r.next_u64() & 1)),
                1 => (v[1], s.neg(v[0])),
                // a product near, or far below, a previous one
                2 | 3 => {
                    let a = s.any(&mut r);
                    let b = s.factor_for(&mut r, a);
                    let target = addend_for_product(s, &mut r, v[0], v[1]);
                    // steer a·b toward the exponent of target
                    let ea = s.exp_of(a).max(1);
                    let et = s.exp_of(target);
                    let bb = s.near(&mut r, et - ea + s.fmt.bias(), 1);
                    (a, if r.below(4) == 0 { b } else { bb })
                }
                _ => {
                    let a = s.any(&mut r);
                    (a, s.factor_for(&mut r, a))
                }
            };
            v[2 * k] = a;
            v[2 * k + 1] = b;
        }
    }
}

impl Testbench for FDot3Bench {}
