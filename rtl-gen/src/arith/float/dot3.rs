//! Fused three-term dot product `a0·b0 + a1·b1 + a2·b2`, exact, rounded once.
//!
//! The exact sum of three products can need thousands of bits (binary64's
//! exponent range); the datapath here is 2F + 10 bits wide, exact where
//! exactness matters, jammed where it does not:
//!
//! 1. normalise the six operands and form the three exact products
//!    `T = sig_a · sig_b` (2F + 2 bits, leading one at bit 2F + 1 or 2F),
//!    each with the weight of its top bit; a zero product gets an exponent
//!    below every real one ([`zero_term_exp`]);
//! 2. sort them by exponent, `e1 >= e2 >= e3`;
//! 3. if `e1 - e2 <= 3` (the two largest may cancel), add `T1 + T2` first:
//!    in the 2F + 6-bit window of [`sum_two`] nothing is lost, the partial
//!    sum is exact; then add `T3`. Otherwise add `T2 + T3` first (bits of
//!    `T3` far below are jammed: the partial sum lies in the right interval
//!    of its last bit), then `T1`, which dominates (`|T2 + T3| < |T1|/4`);
//! 4. normalise the partial sum R (leading-zero count, left shift) and add
//!    the third product in a 2F + 10-bit window: both terms are exact
//!    normalised values (or R is jammed, and then the third term dominates),
//!    so the two-term argument of `sum.rs` applies: bits are lost only from
//!    a term at least three places below the other, the sum keeps its
//!    leading one within two places of the anchor and the jammed bit at
//!    least F + 5 places below the rounding position; nested jams keep the
//!    exact sum's interval.
//!
//! 2F + 10 = 114 bits for binary64, within the DSL's 128-bit values. An exact
//! zero sum is the zero of sign s if all three products are zeros of sign
//! s, otherwise +0 (-0 in RDN).

use super::bits::{add_const, lzc, to_sint};
use super::fma::{fused_exp_width, zero_term_exp};
use super::round::{class_of, finish_rounded, ROUND_STEPS};
use super::sum::{sum_two, Term};
use super::unpack::{normalize, unpack, Unpacked};
use super::{spread, Format, Rm, RoundSel, Rounding};
use crate::arith::int::umul_module;
use crate::arith::ports::{product, DotTerms};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Logical steps before the rounder: normalise; multiply (2); sort and
/// align; add; normalise the partial sum; align; add.
pub const DOT3_RAW_STEPS: u32 = 8;

/// Module name of the dot product.
pub fn dot3_name(fmt: Format, mode: RoundSel, stages: u32) -> String {
    format!("fdot3_{}_{mode}_s{stages}", fmt.tag())
}

/// One product: sign, significand product, top exponent.
#[derive(Clone, Copy)]
struct Prod {
    sign: Sig,
    sig: Sig,
    top: Sig,
}

/// `t0` if `s0`, else `t1` if `s1`, else `t2`, field by field.
fn pick(m: &mut ModuleBuilder, s0: Sig, s1: Sig, t: [Prod; 3]) -> Prod {
    let f = |m: &mut ModuleBuilder, g: fn(&Prod) -> Sig| {
        let inner = m.mux(s1, g(&t[1]), g(&t[2]));
        m.mux(s0, g(&t[0]), inner)
    };
    Prod {
        sign: f(m, |p| p.sign),
        sig: f(m, |p| p.sig),
        top: f(m, |p| p.top),
    }
}

/// `a` if `sel`, else `b`, field by field.
fn pick2(m: &mut ModuleBuilder, sel: Sig, a: Prod, b: Prod) -> Prod {
    Prod {
        sign: m.mux(sel, a.sign, b.sign),
        sig: m.mux(sel, a.sig, b.sig),
        top: m.mux(sel, a.top, b.top),
    }
}

/// `z = a0·b0 + a1·b1 + a2·b2` in `fmt`, rounded once in `mode`, `stages`
/// pipeline registers.
pub fn dot3_module(fmt: Format, mode: impl Into<RoundSel>, stages: u32) -> Arc<Module> {
    let mode: RoundSel = mode.into();
    let f = fmt.frac_bits;
    let mut m = fmt.operator_module(
        dot3_name(fmt, mode, stages),
        format!(
            "Fused dot product a0*b0 + a1*b1 + a2*b2 in {}, exact, rounded once {mode}.",
            fmt.tag()
        ),
        stages,
    );
    m.param("round", mode);
    let terms: DotTerms<Sig> = declare_inputs(&mut m, &(fmt.ty(), fmt.ty(), mode.is_port()));
    let ins: Vec<(Sig, Sig)> = (0..3).map(|i| (terms.a[i], terms.b[i])).collect();
    let rm = Rm::new(mode, terms.rm);
    let plan = spread(stages, DOT3_RAW_STEPS + ROUND_STEPS);
    let ups: Vec<(Unpacked, Unpacked)> = ins
        .iter()
        .enumerate()
        .map(|(k, &(a, b))| {
            let ua = m.scope(&format!("a{k}"), |m| unpack(m, fmt, a));
            let ub = m.scope(&format!("b{k}"), |m| unpack(m, fmt, b));
            (ua, ub)
        })
        .collect();

    // specials, signs, zero products
    let xw = fused_exp_width(fmt);
    let min = m.sint(xw, zero_term_exp(fmt) as i128);
    let mut nan = m.bool(false);
    let mut pos_inf = m.bool(false);
    let mut neg_inf = m.bool(false);
    let mut all_zero = m.bool(true);
    let mut signs = Vec::new();
    let mut zeros = Vec::new();
    for (k, (ua, ub)) in ups.iter().enumerate() {
        let p = format!("p{k}");
        let s = m.xor(ua.sign, ub.sign);
        let s = m.name(s, &format!("{p}_sign"));
        let inf_zero = m.and(ua.inf, ub.zero);
        let zero_inf = m.and(ua.zero, ub.inf);
        let bad = m.or(inf_zero, zero_inf);
        let n = m.or(ua.nan, ub.nan);
        let n = m.or(n, bad);
        let n = m.name(n, &format!("{p}_nan"));
        nan = m.or(nan, n);
        let inf = m.or(ua.inf, ub.inf);
        let inf = m.name(inf, &format!("{p}_inf"));
        let ns = m.not(s);
        let pi = m.and(inf, ns);
        let pi = m.name(pi, &format!("{p}_pos_inf"));
        let ni = m.and(inf, s);
        let ni = m.name(ni, &format!("{p}_neg_inf"));
        pos_inf = m.or(pos_inf, pi);
        neg_inf = m.or(neg_inf, ni);
        let z = m.or(ua.zero, ub.zero);
        let z = m.name(z, &format!("{p}_zero"));
        all_zero = m.and(all_zero, z);
        signs.push(s);
        zeros.push(z);
    }
    let pos_inf = m.name(pos_inf, "pos_inf");
    let neg_inf = m.name(neg_inf, "neg_inf");
    let all_zero = m.name(all_zero, "all_zero");
    let both_inf = m.and(pos_inf, neg_inf);
    let nan = m.or(nan, both_inf);
    let nan = m.name(nan, "nan");
    let inf = m.or(pos_inf, neg_inf);
    let inf = m.name(inf, "inf");
    let class = class_of(&mut m, nan, inf);
    let s01 = m.eq(signs[0], signs[1]);
    let s12 = m.eq(signs[1], signs[2]);
    let same = m.and(s01, s12);
    let zero_same = m.and(all_zero, same);

    // step 1: normalise, product exponents
    let mut tops = Vec::new();
    let mut sig_pairs = Vec::new();
    for (k, (ua, ub)) in ups.iter().enumerate() {
        let na = m.scope(&format!("a{k}"), |m| normalize(m, fmt, ua));
        let nb = m.scope(&format!("b{k}"), |m| normalize(m, fmt, ub));
        let esum = m.add(na.exp, nb.exp);
        let t = add_const(&mut m, esum, 1, xw);
        let t = m.mux(zeros[k], min, t);
        tops.push(m.name(t, &format!("top{k}")));
        sig_pairs.push((na.sig, nb.sig));
    }
    for _ in 0..plan[0] {
        m.stage();
    }

    // steps 2-3: the three exact products
    let mul_stages = plan[1] + plan[2];
    let mul = umul_module(f + 1, f + 1, mul_stages);
    let mut prods = Vec::new();
    for (k, &(sa, sb)) in sig_pairs.iter().enumerate() {
        let p = product(&mut m, &format!("u_mul{k}"), &mul, sa, sb);
        prods.push(p);
    }
    for _ in 0..mul_stages {
        m.stage();
    }
    let t: [Prod; 3] = std::array::from_fn(|k| Prod {
        sign: signs[k],
        sig: prods[k],
        top: tops[k],
    });

    // step 4: sort by exponent, choose the pair added first
    let c01 = m.ge(tops[0], tops[1]);
    let c02 = m.ge(tops[0], tops[2]);
    let c12 = m.ge(tops[1], tops[2]);
    let nc01 = m.not(c01);
    let nc12 = m.not(c12);
    let max0 = m.and(c01, c02);
    let max1 = m.and(nc01, c12);
    let min2 = m.and(c02, c12);
    let min1 = m.and(c01, nc12);
    let min0 = {
        let x = m.or(min1, min2);
        m.not(x)
    };
    // the middle one: neither the largest nor the smallest
    let not_max0 = m.not(max0);
    let not_min0 = m.not(min0);
    let mid0 = m.and(not_max0, not_min0);
    let not_max1 = m.not(max1);
    let not_min1 = m.not(min1);
    let mid1 = m.and(not_max1, not_min1);
    // the products by top exponent, largest first
    let t1 = m.scope("largest", |m| pick(m, max0, max1, t));
    let t2 = m.scope("middle", |m| pick(m, mid0, mid1, t));
    let t3 = m.scope("smallest", |m| pick(m, min0, min1, t));
    let gap = m.sub(t1.top, t2.top);
    let three = m.sint(gap.width(), 3);
    let close = m.le(gap, three);
    let close = m.name(close, "close");
    let x = m.scope("x", |m| pick2(m, close, t1, t2));
    let y = m.scope("y", |m| pick2(m, close, t2, t3));
    let z = m.scope("z", |m| pick2(m, close, t3, t1));

    // steps 4-5: first two-term sum, exact or with the smaller term jammed
    let w1 = 2 * f + 6;
    let r = m.scope("sum2", |m| {
        sum_two(
            m,
            Term {
                sign: x.sign,
                sig: x.sig,
                top: x.top,
            },
            Term {
                sign: y.sign,
                sig: y.sig,
                top: y.top,
            },
            w1,
            xw,
            plan[3],
        )
    });
    for _ in 0..plan[4] {
        m.stage();
    }

    // step 6: normalise the partial sum
    let lz = m.scope("partial", |m| lzc(m, r.sig));
    let rn = m.shl(r.sig, lz);
    let rn = m.name(rn, "partial_norm");
    let lz_s = to_sint(&mut m, lz, xw + 1);
    let rt = to_sint(&mut m, r.top, xw + 1);
    let er = m.sub(rt, lz_s);
    let er = to_sint(&mut m, er, xw);
    let r_any = m.any_set(r.sig);
    let r_zero = m.not(r_any);
    let er = m.mux(r_zero, min, er);
    let er = m.name(er, "partial_top");
    for _ in 0..plan[5] {
        m.stage();
    }

    // steps 7-8: add the third product
    let w2 = 2 * f + 10;
    let s = m.scope("sum3", |m| {
        sum_two(
            m,
            Term {
                sign: r.sign,
                sig: rn,
                top: er,
            },
            Term {
                sign: z.sign,
                sig: z.sig,
                top: z.top,
            },
            w2,
            xw,
            plan[6],
        )
    });
    let sum_any = m.any_set(s.sig);
    let sum_zero = m.not(sum_any);
    let zero_sign = rm.is(&mut m, Rounding::Rdn);
    let zero_sign = m.mux(zero_same, signs[0], zero_sign);
    let sign = m.mux(sum_zero, zero_sign, s.sign);
    let sign = m.mux(inf, neg_inf, sign);
    let sign = m.name(sign, "z_sign");
    let raw = s.to_raw(&mut m, sign, class, xw);
    for _ in 0..plan[7] {
        m.stage();
    }
    let rs: u32 = plan[8..].iter().sum();
    finish_rounded(m, fmt, &rm, &raw, rs, "dot3")
}
