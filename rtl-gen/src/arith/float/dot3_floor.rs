//! A lower bound of a three-term dot product of mixed formats, rounded down
//! once (the cull-plane ray unit's `n·(o − r)` and `n·d`, docs/cull.md
//! §3.2). Golden twin: `golden_model::float::dot3_floor`.
//!
//! Much cheaper than the correctly rounded [`super::dot3`] and than two
//! rounded adders after three rounded products: no operand normalisation,
//! no sort, one rounder.
//!
//! 1. the three exact significand products `M_i` (`(Fa + 1) × (Fb + 1)`
//!    bits, `W` wide) with lsb exponents `e_i` (a zero product takes an
//!    exponent below every real one);
//! 2. `L = max e_i`; each product as a `W + 1`-bit two's complement value
//!    shifted right arithmetically by `L − e_i` (at most `W`): the floor at
//!    `2^L`, so the product at `L` is exact and the others lose only bits
//!    below it, toward −∞;
//! 3. the exact sum (`W + 3` bits), its magnitude and sign, rounded down into
//!    the output format at exponent `L`.
//!
//! Specials as the golden model: a NaN operand gives NaN; a product with a
//! zero factor is 0 (also `0 · ∞`: operands stand for reals, ∞ for an
//! unbounded one); another product with an infinite factor is ±∞, and the
//! result that infinity (both signs: NaN).

use super::bits::{abs, add_const, sadd, ssub, to_sint};
use super::mul::mixed_format_params;
use super::round::{class_of, finish_rounded, Raw, ROUND_STEPS};
use super::unpack::unpack;
use super::{sint_width, spread, Format, Rm, Rounding};
use crate::arith::int::umul_module;
use crate::arith::ports::{product, rounded, DotTerms};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Logical steps before the rounder: the product (2, inside the integer
/// multiplier), the alignment, the sum and its magnitude.
pub const DOT3_FLOOR_RAW_STEPS: u32 = 4;

/// Instantiates `module` (a [`dot3_floor_module`]) as `inst` on the factors
/// `a` and `b` and returns its result `z`.
#[track_caller]
pub fn dot3_floor_instance(
    m: &mut ModuleBuilder,
    module: &Arc<Module>,
    inst: &str,
    a: [Sig; 3],
    b: [Sig; 3],
) -> Sig {
    rounded(m, inst, module, &DotTerms::new(a, b))
}

/// Module name of the operator.
pub fn dot3_floor_name(fa: Format, fb: Format, to: Format, stages: u32) -> String {
    format!(
        "fdot3_floor_{}_x_{}_to_{}_s{stages}",
        fa.tag(),
        fb.tag(),
        to.tag()
    )
}

/// `z ≤ a0·b0 + a1·b1 + a2·b2` for `a_i` in `fa`, `b_i` in `fb`, `z` in
/// `to` (see the module documentation), `stages` pipeline registers. Needs
/// `(Fa + 1) + (Fb + 1) ≥ Fto` (the rounder's input is at least F + 2 wide).
pub fn dot3_floor_module(fa: Format, fb: Format, to: Format, stages: u32) -> Arc<Module> {
    let w = fa.frac_bits + fb.frac_bits + 2;
    assert!(
        w >= to.frac_bits && w + 3 <= 128,
        "dot3_floor: product width {w} against {}",
        to.tag()
    );
    let mut m = ModuleBuilder::new(dot3_floor_name(fa, fb, to, stages));
    m.describe(format!(
        "Lower bound of a0*b0 + a1*b1 + a2*b2, a_i in {}, b_i in {}: exact {} x {} significand \
         products, each truncated toward -inf at the lsb of the product whose lsb weighs most, \
         summed exactly, rounded down once into {}.",
        fa.tag(),
        fb.tag(),
        fa.frac_bits + 1,
        fb.frac_bits + 1,
        to.tag()
    ));
    mixed_format_params(&mut m, fa, fb, to).param("stages", stages);
    let terms: DotTerms<Sig> = declare_inputs(&mut m, &(fa.ty(), fb.ty(), false));
    let ins: Vec<(Sig, Sig)> = (0..3).map(|i| (terms.a[i], terms.b[i])).collect();
    let plan = spread(stages, DOT3_FLOOR_RAW_STEPS + ROUND_STEPS);

    // specials and the product exponents. Product i's lsb exponent is
    // e_i = eff_a + eff_b − C, one constant C (biases and fraction widths)
    // for all three, so the window is chosen and the shifts computed on the
    // sums s_i = eff_a + eff_b alone (one adder before the comparisons, not
    // three); C enters once, after the selection. A zero product takes
    // s = 1, below every real sum (each eff_exp >= 1): e = lo − 1.
    let lo = fa.emin() - fa.frac_bits as i64 + fb.emin() - fb.frac_bits as i64;
    let hi = fa.emax() - fa.frac_bits as i64 + fb.emax() - fb.frac_bits as i64;
    let xw = sint_width(lo - 1, hi);
    let c = fa.bias() + fa.frac_bits as i64 + fb.bias() + fb.frac_bits as i64;
    let below_all = m.uint(fa.exp_bits.max(fb.exp_bits) + 1, 1);
    let mut nan = m.bool(false);
    let mut pos_inf = m.bool(false);
    let mut neg_inf = m.bool(false);
    let mut terms = Vec::new();
    for (i, &(a, b)) in ins.iter().enumerate() {
        let ua = m.scope(&format!("a{i}"), |m| unpack(m, fa, a));
        let ub = m.scope(&format!("b{i}"), |m| unpack(m, fb, b));
        let p = format!("p{i}");
        let n = m.or(ua.nan, ub.nan);
        let n = m.name(n, &format!("{p}_nan"));
        nan = m.or(nan, n);
        let zero = m.or(ua.zero, ub.zero);
        let zero = m.name(zero, &format!("{p}_zero"));
        let inf = m.or(ua.inf, ub.inf);
        let nz = m.not(zero);
        let inf = m.and(inf, nz);
        let inf = m.name(inf, &format!("{p}_inf"));
        let sign = m.xor(ua.sign, ub.sign);
        let sign = m.name(sign, &format!("{p}_sign"));
        let pos = m.not(sign);
        let pi = m.and(inf, pos);
        let pi = m.name(pi, &format!("{p}_pos_inf"));
        let ni = m.and(inf, sign);
        let ni = m.name(ni, &format!("{p}_neg_inf"));
        pos_inf = m.or(pos_inf, pi);
        neg_inf = m.or(neg_inf, ni);
        let e = m.add(ua.eff_exp, ub.eff_exp);
        let e = m.mux(zero, below_all, e);
        let e = m.name(e, &format!("exp_sum{i}"));
        terms.push((sign, ua.sig, ub.sig, e));
    }
    let pos_inf = m.name(pos_inf, "pos_inf");
    let neg_inf = m.name(neg_inf, "neg_inf");
    let both = m.and(pos_inf, neg_inf);
    let nan = m.or(nan, both);
    let nan = m.name(nan, "nan");
    let inf = m.or(pos_inf, neg_inf);
    let inf = m.name(inf, "inf");
    let class = class_of(&mut m, nan, inf);
    // the largest of the three: the three comparisons side by side, then
    // one selection (not two compare-and-select steps in a row)
    let [e0, e1, e2] = [terms[0].3, terms[1].3, terms[2].3];
    let ge01 = m.ge(e0, e1);
    let ge02 = m.ge(e0, e2);
    let ge12 = m.ge(e1, e2);
    let e0_top = m.and(ge01, ge02);
    let lt01 = m.not(ge01);
    let e1_top = m.and(lt01, ge12);
    let e12 = m.mux(e1_top, e1, e2);
    let lsb = m.mux(e0_top, e0, e12);
    let lsb = m.name(lsb, "window_exp_sum");

    // step 1: the exact products
    let mul_stages = plan[0] + plan[1];
    let mul = umul_module(fa.frac_bits + 1, fb.frac_bits + 1, mul_stages);
    let prods: Vec<Sig> = terms
        .iter()
        .enumerate()
        .map(|(i, &(_, sa, sb, _))| product(&mut m, &format!("u_mul{i}"), &mul, sa, sb))
        .collect();
    for _ in 0..mul_stages {
        m.stage();
    }

    // step 2: two's complement, floored at the window's lsb
    let shw = 32 - w.leading_zeros();
    let max_shift = m.uint(shw, w as u128);
    let zero = m.sint(w + 1, 0);
    let mut aligned = Vec::new();
    for (i, (&(sign, _, _, e), &p)) in terms.iter().zip(&prods).enumerate() {
        let t = to_sint(&mut m, p, w + 1);
        let neg = ssub(&mut m, zero, t, w + 1);
        let t = m.mux(sign, neg, t);
        let d = m.sub(lsb, e);
        let d = m.as_uint(d);
        let far = {
            let lim = m.uint(d.width(), w as u128);
            m.gt(d, lim)
        };
        let d = m.slice(d, shw - 1, 0);
        let d = m.mux(far, max_shift, d);
        let t = m.shr(t, d);
        aligned.push(m.name(t, &format!("floored{i}")));
    }
    for _ in 0..plan[2] {
        m.stage();
    }

    // step 3: the exact sum, rounded down at the window's lsb
    let s01 = sadd(&mut m, aligned[0], aligned[1], w + 2);
    let sum = sadd(&mut m, s01, aligned[2], w + 3);
    let sum = m.name(sum, "floored_sum");
    let negative = m.msb(sum);
    let mag = abs(&mut m, sum, w + 2);
    let sign = m.mux(inf, neg_inf, negative);
    let no_sticky = m.bool(false);
    let lsb_exp = add_const(&mut m, lsb, -c, xw);
    let lsb_exp = m.name(lsb_exp, "window_lsb_exp");
    let raw = Raw {
        sign,
        class,
        exp: lsb_exp,
        sig: mag,
        sticky: no_sticky,
    };
    for _ in 0..plan[3] {
        m.stage();
    }
    let rs: u32 = plan[DOT3_FLOOR_RAW_STEPS as usize..].iter().sum();
    finish_rounded(m, to, &Rm::fixed(Rounding::Rdn), &raw, rs, "dot3_floor")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Evaluator;
    use crate::golden_twin::golden_format;

    /// Against the golden operator: random operands of small formats (a
    /// third of them special or zero), and of the cull unit's formats, at
    /// stages 0 and 3, and at one register per step plus one (registers inside
    /// the multiplier and past the last step, which 3 stages never place).
    #[test]
    fn matches_the_golden_operator() {
        let f = |e, m| Format::new(e, m).unwrap();
        let cases = [
            (f(3, 2), f(4, 3), f(4, 3), 200_000),
            (f(5, 10), f(8, 23), f(8, 23), 20_000),
            (f(5, 10), f(8, 23), f(8, 18), 20_000),
            (f(4, 3), f(5, 10), f(5, 10), 20_000),
        ];
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for (fa, fb, to, n) in cases {
            let (ga, gb, gt) = (golden_format(fa), golden_format(fb), golden_format(to));
            let one_per_step = DOT3_FLOOR_RAW_STEPS + ROUND_STEPS + 1;
            for stages in [0u32, 3, one_per_step] {
                let n = if stages > 3 { n / 10 } else { n };
                let module = dot3_floor_module(fa, fb, to, stages);
                let mut ev = Evaluator::new(&module);
                let mut pick = |g: golden_model::float::FloatFormat| {
                    let r = next();
                    match r % 12 {
                        0 => 0,
                        1 => g.sign_bit(),
                        2 => g.inf(r & 64 != 0),
                        3 => g.canonical_nan(),
                        4 => (r >> 8) & g.frac_mask(),
                        _ => (r >> 8) & g.mask(),
                    }
                };
                let inputs: Vec<([u64; 3], [u64; 3])> = (0..n)
                    .map(|_| {
                        let a = [0, 1, 2].map(|_| pick(ga));
                        let b = [0, 1, 2].map(|_| pick(gb));
                        (a, b)
                    })
                    .collect();
                let mut got = Vec::new();
                for c in 0..inputs.len() + stages as usize {
                    let (a, b) = inputs.get(c).copied().unwrap_or_default();
                    let x: Vec<u128> = (0..3).flat_map(|i| [a[i] as u128, b[i] as u128]).collect();
                    let out = ev.step(&x);
                    if c >= stages as usize {
                        got.push(out[0] as u64);
                    }
                }
                for ((a, b), z) in inputs.iter().zip(got) {
                    let want = golden_model::float::dot3_floor(ga, gb, gt, *a, *b);
                    assert_eq!(z, want, "{}: a {a:x?} b {b:x?}", module.name);
                }
            }
        }
    }
}
