//! Stimulus and golden-model adapter for `mulcmp`.

use super::stimulus::{mask, unsigned_corners, VectorRng};
use super::Testbench;
use rtl_gen::units::mulcmp::{Config, MulCmpIn, MulCmpOut};
use rtl_gen::units::ports;

/// Vectors: first every combination of corner values of a, b, c, d; then
/// random vectors mixing uniform operands, equal products (swapped or
/// re-factored operands), products one apart, and small operands.
pub struct MulCmpBench {
    corners_a: Vec<u64>,
    corners_b: Vec<u64>,
    unit: Config,
}

impl MulCmpBench {
    /// The testbench of a `mulcmp` configuration.
    pub fn new(u: &Config) -> Self {
        MulCmpBench {
            corners_a: unsigned_corners(u.a_width),
            corners_b: unsigned_corners(u.b_width),
            unit: *u,
        }
    }

    fn corner_count(&self) -> u64 {
        (self.corners_a.len() * self.corners_b.len()).pow(2) as u64
    }
}

impl sim::Golden for MulCmpBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let MulCmpIn { a, b, c, d } = ports::unpack(&self.unit, inputs);
        let r = golden_model::mulcmp::eval(a, b, c, d);
        let out = MulCmpOut {
            lt: r.lt as u64,
            eq: r.eq as u64,
            ab: r.ab as u64,
        };
        ports::pack(&self.unit, &out, outputs)
    }
}

impl sim::Stimulus for MulCmpBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let (aw, bw) = (self.unit.a_width, self.unit.b_width);
        if index < self.corner_count() {
            let (na, nb) = (self.corners_a.len() as u64, self.corners_b.len() as u64);
            let mut k = index;
            let [a, b, c, d] = [
                (na, &self.corners_a),
                (nb, &self.corners_b),
                (na, &self.corners_a),
                (nb, &self.corners_b),
            ]
            .map(|(n, corners)| {
                let x = corners[(k % n) as usize];
                k /= n;
                x
            });
            return ports::pack(&self.unit, &MulCmpIn { a, b, c, d }, v);
        }
        let mut rng = VectorRng::new(seed, index);
        let (a, b) = (rng.bits(aw), rng.bits(bw));
        let (c, d) = match rng.below(8) {
            // equal products: the same operands, or a factor of 2 moved across
            0 => (a, b),
            1 if a & 1 == 0 && (b << 1) & !mask(bw) == 0 => (a >> 1, b << 1),
            // products one unit apart where possible
            2 => (a, b.wrapping_add(1) & mask(bw)),
            3 => (a, b.wrapping_sub(1) & mask(bw)),
            // small operands, many equal products
            4 => {
                let [a, b, c, d] = [aw, bw, aw, bw].map(|w| rng.bits(w.min(3)));
                return ports::pack(&self.unit, &MulCmpIn { a, b, c, d }, v);
            }
            _ => (rng.bits(aw), rng.bits(bw)),
        };
        ports::pack(&self.unit, &MulCmpIn { a, b, c, d }, v)
    }
}

impl Testbench for MulCmpBench {}
