//! One testbench for every float operator (`rtl_gen::units::float_ops`):
//! corner vectors first ([`FloatStim::corner`], repeated in the four modes
//! when the rounding is an input), then seeded random vectors drawn for the
//! operator ([`FloatOpBench::draw`]); the golden model is `golden_model::float` (and
//! `golden_model::transform::recip`).
//!
//! Random operands per operator: sums take a second operand with a close
//! exponent, an alignment shift around F, or (near) cancellation; products
//! a factor whose product lands near overflow, in the subnormal range or
//! anywhere; comparisons a partner equal, negated, one ulp away or random;
//! fused operations an addend near the product, far below it or cancelling;
//! conversions values near the target's overflow, underflow and subnormal
//! range.

use super::fstim::{golden_format, golden_mode, FloatStim, ModeIn};
use super::stimulus::{mask, VectorRng};
use super::Testbench;
use golden_model::float as g;
use rtl_gen::arith::float::unpack::lsb_exp_width;
use rtl_gen::units::float_ops::{FloatConfig, OpConfig};

/// The testbench of one float operator.
pub struct FloatOpBench {
    stim: FloatStim,
    /// the operator and its own parameters (the unit's configuration)
    op: OpConfig,
    /// the rounding, for operators that round (fixed or an input)
    mode: Option<ModeIn>,
    /// `fmul_exact`'s exact-product format
    exact_product: Option<g::ExactProductFormat>,
    /// `funpack`: the width of its exponent output
    exp_width: u32,
}

impl FloatOpBench {
    /// The testbench of a float operator's configuration.
    pub fn new(c: &FloatConfig) -> Self {
        let exact_product = (c.op == OpConfig::MulExact).then(|| {
            g::ExactProductFormat::new(golden_format(c.fmt))
                .expect("the exact-product format was checked when building")
        });
        FloatOpBench {
            stim: FloatStim::new(c.fmt),
            op: c.op,
            mode: c.op.round().map(|sel| ModeIn { sel }),
            exact_product,
            exp_width: lsb_exp_width(c.fmt),
        }
    }
}

impl sim::Golden for FloatOpBench {
    fn eval(&self, i: &[u64], o: &mut [u64]) {
        let f = golden_format(self.stim.fmt);
        let mode = || self.mode.expect("a rounding operator").golden(i);
        match self.op {
            OpConfig::Add { sub: false, .. } => o[0] = g::add(f, i[0], i[1], mode()),
            OpConfig::Add { sub: true, .. } => o[0] = g::sub(f, i[0], i[1], mode()),
            OpConfig::AddDownUp => {
                let r = g::add_down_up(f, i[0], i[1]);
                (o[0], o[1]) = (r.down, r.up);
            }
            OpConfig::Mul { .. } => o[0] = g::mul(f, i[0], i[1], mode()),
            OpConfig::MulExact => {
                let pair = self.exact_product.expect("made for fmul_exact");
                o[0] = g::mul_exact(pair, i[0], i[1]);
            }
            OpConfig::Cmp => {
                o[0] = g::lt(f, i[0], i[1]) as u64;
                o[1] = g::le(f, i[0], i[1]) as u64;
                o[2] = g::eq(f, i[0], i[1]) as u64;
            }
            OpConfig::MinMax => (o[0], o[1]) = (g::min(f, i[0], i[1]), g::max(f, i[0], i[1])),
            OpConfig::Cvt { to, .. } => o[0] = g::convert(f, golden_format(to), i[0], mode()),
            OpConfig::Fma { .. } => o[0] = g::fma(f, i[0], i[1], i[2], mode()),
            OpConfig::Dot3 { .. } => {
                o[0] = g::dot3(f, [i[0], i[2], i[4]], [i[1], i[3], i[5]], mode())
            }
            OpConfig::Recip { round } => {
                o[0] = golden_model::transform::recip(f, i[0], golden_mode(round))
            }
            OpConfig::Unpack => {
                let r = g::unpack(f, i[0]);
                o[0] = r.sign as u64;
                o[1] = r.class as u64;
                o[2] = r.exp as i64 as u64 & mask(self.exp_width);
                o[3] = r.sig as u64;
            }
        }
    }
}

impl sim::Stimulus for FloatOpBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let (v, data_index) = match self.mode {
            Some(m) => (m.fill(index, v), m.data_index(index)),
            None => (v, index),
        };
        let corner = match self.op {
            OpConfig::Dot3 { .. } => dot3_corner(&self.stim, data_index, v),
            _ => self.stim.corner(data_index, v),
        };
        if !corner {
            self.draw(&mut VectorRng::new(seed, index), v);
        }
    }
}

impl FloatOpBench {
    /// A random vector's data inputs.
    fn draw(&self, r: &mut VectorRng, v: &mut [u64]) {
        let s = &self.stim;
        match self.op {
            OpConfig::Add { sub, .. } => {
                let a = s.any(r);
                let b = s.addend_for(r, a);
                v[0] = a;
                v[1] = if sub { s.neg(b) } else { b };
            }
            OpConfig::AddDownUp => {
                let a = s.any(r);
                v[0] = a;
                v[1] = s.addend_for(r, a);
            }
            OpConfig::Mul { .. } | OpConfig::MulExact => {
                let a = s.any(r);
                v[0] = a;
                v[1] = s.factor_for(r, a);
            }
            OpConfig::Cmp | OpConfig::MinMax => {
                let a = s.any(r);
                v[0] = a;
                v[1] = compare_partner(s, r, a);
            }
            OpConfig::Cvt { to, .. } => {
                let target = match r.below(6) {
                    0 => to.emax() + 1 - r.below(3) as i64,
                    1 => to.emin() + 1 - r.below(3) as i64,
                    2 => to.emin() - r.below(to.frac_bits as u64 + 3) as i64,
                    3 => r.below(5) as i64 - 2,
                    _ => {
                        v[0] = s.any(r);
                        return;
                    }
                };
                v[0] = s.near(r, target + s.fmt.bias(), 0);
            }
            OpConfig::Fma { .. } => {
                let a = s.any(r);
                let b = s.factor_for(r, a);
                v[0] = a;
                v[1] = b;
                v[2] = addend_for_product(s, r, a, b);
            }
            OpConfig::Dot3 { .. } => dot3_draw(s, r, v),
            OpConfig::Recip { .. } | OpConfig::Unpack => v[0] = s.any(r),
        }
    }
}

impl Testbench for FloatOpBench {}

/// A second operand to compare with `a`.
fn compare_partner(s: &FloatStim, r: &mut VectorRng, a: u64) -> u64 {
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

/// An addend for the product `a · b`: near it, far below, cancelling, or random.
fn addend_for_product(s: &FloatStim, r: &mut VectorRng, a: u64, b: u64) -> u64 {
    let gf = golden_format(s.fmt);
    let f = s.fmt.frac_bits as i64;
    let p = g::mul(gf, a, b, g::RoundingMode::TowardZero);
    let ep = s.exp_of(p);
    match r.below(8) {
        0 | 1 => s.near(r, ep, 3),
        2 | 3 => {
            let d = r.below(2 * f as u64 + 8) as i64;
            s.near(r, ep - d, 0)
        }
        4 => s.neg(p) ^ (r.next_u64() & 3),
        5 => s.neg(p) ^ r.bits(s.fmt.frac_bits.min(10)),
        _ => s.any(r),
    }
}

/// `fdot3`'s corner vectors: every triple of specials on one side of the
/// products, the other side ±1 (signs from the vector index); false past them.
fn dot3_corner(s: &FloatStim, data_index: u64, v: &mut [u64]) -> bool {
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
        return true;
    }
    false
}

/// `fdot3`'s random vectors: products that cancel a previous one exactly or
/// nearly, land near or far below it, or are random.
fn dot3_draw(s: &FloatStim, r: &mut VectorRng, v: &mut [u64]) {
    let a0 = s.any(r);
    let b0 = s.factor_for(r, a0);
    v[0] = a0;
    v[1] = b0;
    for k in 1..3 {
        let (a, b) = match r.below(6) {
            // cancel a previous product exactly or nearly
            0 => (s.neg(v[0]), v[1] ^ (r.next_u64() & 1)),
            1 => (v[1], s.neg(v[0])),
            // a product near, or far below, a previous one
            2 | 3 => {
                let a = s.any(r);
                let b = s.factor_for(r, a);
                let target = addend_for_product(s, r, v[0], v[1]);
                // steer a·b toward the exponent of target
                let ea = s.exp_of(a).max(1);
                let et = s.exp_of(target);
                let bb = s.near(r, et - ea + s.fmt.bias(), 1);
                (a, if r.below(4) == 0 { b } else { bb })
            }
            _ => {
                let a = s.any(r);
                (a, s.factor_for(r, a))
            }
        };
        v[2 * k] = a;
        v[2 * k + 1] = b;
    }
}
