//! Floating-point reciprocal `1 / x`, correctly rounded: the one division
//! of the transform unit's hardware inversion (`docs/transform.md` §3). Its
//! golden twin is `golden_model::transform::recip`.
//!
//! Built like the operators of [`crate::arith::float`]: the exact quotient
//! with a sticky bit, then the shared rounder. The operand is normalised
//! (`x = d · 2^(e − F)`, `2^F ≤ d < 2^(F+1)`); restoring division produces
//! `q = floor(2^(2F+3) / d)` (F + 3 or F + 4 bits, so at least F + 2 as the
//! rounder requires with a sticky bit), one quotient bit per step, and the
//! remainder's OR is the sticky bit: `1/x = (q + σ) · 2^(−e − F − 3)`.
//! Specials: NaN → NaN, `1/±0 = ±inf`, `1/±inf = ±0`.
//!
//! [`recip_down_up_module`] rounds one quotient both toward −∞ and toward
//! +∞ (the cull unit's reciprocal bracket), as `add_down_up` does for sums.

use crate::arith::float::bits::{add_const, to_sint};
use crate::arith::float::round::{class_of, round, round_down_up, Raw, ROUND_STEPS};
use crate::arith::float::unpack::{normalize, unpack};
use crate::arith::float::{finish_operator, sint_width, spread, Format, Rounding};
use crate::arith::int::zext;
use crate::arith::ports::{DownUp, Operand, Rounded};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Logical steps before the rounder: normalise, then F + 4 division steps
/// (one quotient bit each).
pub fn recip_raw_steps(fmt: Format) -> u32 {
    1 + fmt.frac_bits + 4
}

/// Module name of the reciprocal.
pub fn recip_name(fmt: Format, mode: Rounding, stages: u32) -> String {
    format!("frecip_{}_{mode}_s{stages}", fmt.tag())
}

/// The exact reciprocal of the `fmt` encoding `x` as a raw value: the
/// quotient `q` (F + 3 or F + 4 bits) with the remainder's OR as the sticky
/// bit, `1/x = (q + σ) · 2^exp`; NaN → NaN, `1/±0 = ±∞`, `1/±∞ = ±0`.
/// `cuts[i]` registers go after step `i` of [`recip_raw_steps`] (the
/// normalisation, then one quotient bit each); the raw value belongs to the
/// stage after them.
#[track_caller]
pub fn recip_raw(m: &mut ModuleBuilder, fmt: Format, x: Sig, cuts: &[u32]) -> Raw {
    let f = fmt.frac_bits;
    let steps = recip_raw_steps(fmt);
    assert_eq!(cuts.len(), steps as usize, "one cut count per step");
    let u = m.scope("x", |m| unpack(m, fmt, x));
    // 1/NaN = NaN, 1/0 = inf, 1/inf = 0 (a finite raw value with sig 0 is a zero)
    let class = class_of(m, u.nan, u.zero);
    let n = m.scope("x", |m| normalize(m, fmt, &u));
    let xw = sint_width(-fmt.emax() - f as i64 - 4, -fmt.emin() + 2 * f as i64 + 4);
    let e = to_sint(m, n.exp, xw);
    let zero = m.sint(xw, 0);
    let neg_e = m.sub(zero, e);
    let exp = add_const(m, neg_e, -(f as i64) - 3, xw);
    let exp = m.name(exp, "recip_exp");
    let rw = f + 2;
    let d = zext(m, n.sig, rw);
    let d = m.name(d, "divisor");
    for _ in 0..cuts[0] {
        m.stage();
    }

    // restoring division: the dividend prefix 2^F gives quotient bit F + 3,
    // then each step doubles the remainder (r < d < 2^(F+1), so 2r fits F + 2 bits)
    let mut r = m.uint(rw, 1u128 << f);
    let mut bits = Vec::with_capacity(steps as usize);
    for step in 0..steps - 1 {
        // step 0 is quotient bit F + 3 (weight of the dividend prefix 2^F)
        if step > 0 {
            let zero_bit = m.uint(1, 0);
            let low = m.slice(r, rw - 2, 0);
            r = m.cat(&[low, zero_bit]);
        }
        // one subtraction per step: its borrow is the quotient bit (a
        // separate comparison would be a second carry chain on the path)
        let diff = m.sub(r, d);
        let diff = m.as_uint(diff);
        let borrow = m.bit_at(diff, rw);
        let ge = m.not(borrow);
        let diff = m.slice(diff, rw - 1, 0);
        r = m.mux(ge, diff, r);
        r = m.name(r, &format!("rem{step}"));
        bits.push(m.as_uint(ge));
        for _ in 0..cuts[1 + step as usize] {
            m.stage();
        }
    }
    let q = m.cat(&bits);
    let q = m.name(q, "quotient");
    let sticky = m.any_set(r);
    // 1/inf: a finite raw zero (the quotient of the infinity's significand is not used)
    let zero_q = m.uint(q.width(), 0);
    let q = m.mux(u.inf, zero_q, q);
    let no = m.bool(false);
    let sticky = m.mux(u.inf, no, sticky);
    Raw {
        sign: u.sign,
        class,
        exp,
        sig: q,
        sticky,
    }
}

/// `z = 1 / x` in `fmt`, rounded once in `mode`, `stages` pipeline registers.
pub fn recip_module(fmt: Format, mode: Rounding, stages: u32) -> Arc<Module> {
    let f = fmt.frac_bits;
    let mut m = ModuleBuilder::new(recip_name(fmt, mode, stages));
    m.describe(format!(
        "Floating-point reciprocal 1 / x in {}, rounded once {mode} (restoring division).",
        fmt.tag()
    ));
    m.param("exp_bits", fmt.exp_bits)
        .param("frac_bits", f)
        .param("round", mode)
        .param("stages", stages);
    let Operand { x } = declare_inputs(&mut m, &fmt.ty());
    let steps = recip_raw_steps(fmt);
    let plan = spread(stages, steps + ROUND_STEPS);
    let raw = recip_raw(&mut m, fmt, x, &plan[..steps as usize]);
    let rs: u32 = plan[steps as usize..].iter().sum();
    let z = round(&mut m, fmt, mode, &raw, rs, "u_round");
    finish_operator(m, rs, &fmt.ty(), &Rounded { z }, "reciprocal")
}

/// Module name of the down/up reciprocal.
pub fn recip_down_up_name(fmt: Format, stages: u32) -> String {
    format!("frecip_down_up_{}_s{stages}", fmt.tag())
}

/// `down = RDN(1 / x)`, `up = RUP(1 / x)` in `fmt` from one exact quotient
/// (one division, one normalisation of the shared rounder), `stages` pipeline
/// registers (the plan of [`recip_module`]).
pub fn recip_down_up_module(fmt: Format, stages: u32) -> Arc<Module> {
    let mut m = ModuleBuilder::new(recip_down_up_name(fmt, stages));
    m.describe(format!(
        "Floating-point reciprocal 1 / x in {} rounded toward -inf (down) and toward +inf (up) \
         from one exact quotient (restoring division).",
        fmt.tag()
    ));
    m.param("exp_bits", fmt.exp_bits)
        .param("frac_bits", fmt.frac_bits)
        .param("stages", stages);
    let Operand { x } = declare_inputs(&mut m, &fmt.ty());
    let steps = recip_raw_steps(fmt);
    let plan = spread(stages, steps + ROUND_STEPS);
    let raw = recip_raw(&mut m, fmt, x, &plan[..steps as usize]);
    let rs: u32 = plan[steps as usize..].iter().sum();
    let (down, up) = round_down_up(&mut m, fmt, &raw, raw.sign, raw.sign, rs, "u_round");
    finish_operator(m, rs, &fmt.ty(), &DownUp { down, up }, "down/up reciprocal")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Evaluator;
    use crate::golden_twin::golden_mode;
    use golden_model::float::{FloatFormat, RoundingMode};

    /// Every encoding of (4,3) in every mode, of (5,10) in RNE, random values
    /// otherwise and for binary32, against the golden reciprocal.
    #[test]
    fn matches_the_golden_reciprocal() {
        for (e, f, exhaustive) in [(4, 3, true), (5, 10, true), (8, 23, false)] {
            let fmt = Format::new(e, f).unwrap();
            let gf = FloatFormat::new(e, f).unwrap();
            for mode in Rounding::ALL {
                for stages in [0, 3] {
                    let module = recip_module(fmt, mode, stages);
                    let mut ev = Evaluator::new(&module);
                    let exhaustive =
                        exhaustive && (fmt.width() <= 8 || (mode == Rounding::Rne && stages == 0));
                    let n: u64 = if exhaustive { 1 << fmt.width() } else { 4_000 };
                    let mut s = 0x9e37_79b9_7f4a_7c15u64;
                    let mut inputs = Vec::new();
                    for i in 0..n {
                        s = s
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        inputs.push(if exhaustive { i } else { (s >> 32) & gf.mask() });
                    }
                    // feed back to back; outputs appear `stages` cycles later
                    let mut got = Vec::new();
                    for c in 0..inputs.len() + stages as usize {
                        let x = inputs.get(c).copied().unwrap_or(0);
                        let out = ev.step(&[x as u128]);
                        if c >= stages as usize {
                            got.push(out[0] as u64);
                        }
                    }
                    for (x, z) in inputs.iter().zip(got) {
                        let want = golden_model::transform::recip(gf, *x, golden_mode(mode));
                        assert_eq!(z, want, "{fmt} {mode} s{stages}: 1/{x:#x}");
                    }
                }
            }
        }
    }

    /// The down/up pair against the golden reciprocal in both directions:
    /// every encoding of (5,10), random binary32 values.
    #[test]
    fn down_up_pair_matches_the_golden_reciprocal() {
        for (e, f, n) in [(5, 10, 1u64 << 16), (8, 18, 30_000)] {
            let fmt = Format::new(e, f).unwrap();
            let gf = FloatFormat::new(e, f).unwrap();
            let module = recip_down_up_module(fmt, 0);
            let mut ev = Evaluator::new(&module);
            let mut s = 0x9e37_79b9_7f4a_7c15u64;
            for i in 0..n {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let x = if n == 1 << 16 {
                    i
                } else {
                    (s >> 32) & gf.mask()
                };
                let out = ev.eval(&[x as u128]);
                let down = golden_model::transform::recip(gf, x, RoundingMode::Down);
                let up = golden_model::transform::recip(gf, x, RoundingMode::Up);
                assert_eq!(
                    (out[0] as u64, out[1] as u64),
                    (down, up),
                    "{fmt}: 1/{x:#x}"
                );
            }
        }
    }
}
