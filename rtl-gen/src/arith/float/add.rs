//! Addition and subtraction: the exact sum with guard, round and sticky
//! bits, then the shared rounder.
//!
//! The operand of larger magnitude (compared as encodings without the sign)
//! is `big`; `small` is shifted right by the exponent difference into
//! F + 4 bits (hidden bit, fraction, guard, round, and a jammed sticky bit),
//! then added or subtracted: the F + 5-bit result is never negative. If the
//! shift lost bits, the difference of exponents is at least 2, so the sum
//! loses at most one leading bit and the jammed bit stays two places below
//! the rounding position: rounding the jammed sum equals rounding the exact
//! one in every mode. An exact zero from opposite signs is -0 in RDN, +0
//! otherwise; equal-signed zeros keep their sign.

use super::bits::{add_const, shr_jam, shr_jam_tz};
use super::round::{class_of, finish_rounded_range, Range, Raw, ROUND_STEPS};
use super::unpack::unpack;
use super::{sint_width, spread, Format, Rm, RoundSel, Rounding};
use crate::arith::int::zext;
use crate::arith::ports::{Pair, PairPorts};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Logical steps of the exact sum: compare and swap; align; add.
pub const ADD_RAW_STEPS: u32 = 3;

/// The registers of a rounded adder of `stages`, spread evenly over the
/// exact sum's [`ADD_RAW_STEPS`] and the rounding's [`ROUND_STEPS`]: after
/// each step of the sum, and in all inside the rounding.
pub fn rounded_add_plan(stages: u32) -> (Vec<u32>, u32) {
    let plan = spread(stages, ADD_RAW_STEPS + ROUND_STEPS);
    let (raw, round) = plan.split_at(ADD_RAW_STEPS as usize);
    (raw.to_vec(), round.iter().sum())
}

/// The exact sum as a raw value, before the mode-dependent sign of an exact zero.
#[derive(Debug, Clone, Copy)]
pub struct SumRaw {
    /// the raw value; its sign is the sign of the larger operand
    pub raw: Raw,
    /// Bool: the sum is an exact zero of operands with opposite signs, whose
    /// sign is decided by the rounding mode (-0 in RDN, +0 otherwise)
    pub cancel: Sig,
}

impl SumRaw {
    /// The raw value with the sign of an exact zero fixed for the mode `rm`.
    #[track_caller]
    pub fn for_rm(&self, m: &mut ModuleBuilder, rm: &Rm) -> Raw {
        let zero_sign = rm.is(m, Rounding::Rdn);
        let sign = m.mux(self.cancel, zero_sign, self.raw.sign);
        Raw { sign, ..self.raw }
    }

    /// The raw value with the sign of an exact zero fixed for `mode`.
    #[track_caller]
    pub fn for_mode(&self, m: &mut ModuleBuilder, mode: Rounding) -> Raw {
        let zero_sign = m.bool(mode == Rounding::Rdn);
        let sign = m.mux(self.cancel, zero_sign, self.raw.sign);
        Raw { sign, ..self.raw }
    }
}

/// Width of the exponent of [`add_raw`]'s result.
pub fn add_exp_width(fmt: Format) -> u32 {
    let k = fmt.bias() + fmt.frac_bits as i64 + 3;
    sint_width(1 - k, fmt.exp_ones() as i64 - k)
}

/// Builds `a + b` (or `a - b` if `negate_b`) exactly, inserting `cuts[i]`
/// pipeline registers after step `i` of [`ADD_RAW_STEPS`].
#[track_caller]
pub fn add_raw(
    m: &mut ModuleBuilder,
    fmt: Format,
    a: Sig,
    b: Sig,
    negate_b: bool,
    cuts: &[u32],
) -> SumRaw {
    add_raw_with(m, fmt, a, b, negate_b, cuts, Shape::General)
}

/// How [`add_raw_with`] builds the exact sum.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Shape {
    /// [`add_raw`]
    General,
    /// the same value built for area (the normal-range operators): the
    /// alignment's sticky bit from the trailing zeros of the smaller
    /// significand ([`shr_jam_tz`]) instead of a shifted mask, one adder
    /// with the smaller operand complemented for an effective subtraction
    /// instead of a sum, a difference and a choice, and one exponent
    /// difference after the selection instead of two before it
    Lean,
    /// `Lean` for operands of one sign (or zeros): the magnitudes
    /// added, never subtracted ([`add_same_sign_normal_module`])
    SameSign,
}

#[track_caller]
fn add_raw_with(
    m: &mut ModuleBuilder,
    fmt: Format,
    a: Sig,
    b: Sig,
    negate_b: bool,
    cuts: &[u32],
    shape: Shape,
) -> SumRaw {
    let lean = shape != Shape::General;
    let (e, f) = (fmt.exp_bits, fmt.frac_bits);
    let w = fmt.width();
    let ua = m.scope("a", |m| unpack(m, fmt, a));
    let ub = m.scope("b", |m| unpack(m, fmt, b));
    let sign_b = if negate_b { m.not(ub.sign) } else { ub.sign };

    // step 1: order by magnitude, exponent difference, specials
    let mag_a = m.slice(a, w - 2, 0);
    let mag_b = m.slice(b, w - 2, 0);
    let a_big = m.ge(mag_a, mag_b);
    let a_big = m.name(a_big, "a_big");
    let sig_big = m.mux(a_big, ua.sig, ub.sig);
    let sig_small = m.mux(a_big, ub.sig, ua.sig);
    let exp_big = m.mux(a_big, ua.eff_exp, ub.eff_exp);
    let sign_big = m.mux(a_big, ua.sign, sign_b);
    let sign_big = m.name(sign_big, "sign_big");
    // the non-negative difference's low E bits
    let diff = if lean {
        // one subtraction after the selection: smaller, one step longer
        let exp_small = m.mux(a_big, ub.eff_exp, ua.eff_exp);
        let d = m.sub(exp_big, exp_small);
        m.slice(d, e - 1, 0)
    } else {
        // both differences beside the comparison, then a selection (not
        // the subtraction after the selection)
        let diff_ab = m.sub(ua.eff_exp, ub.eff_exp);
        let diff_ab = m.slice(diff_ab, e - 1, 0);
        let diff_ba = m.sub(ub.eff_exp, ua.eff_exp);
        let diff_ba = m.slice(diff_ba, e - 1, 0);
        m.mux(a_big, diff_ab, diff_ba)
    };
    let diff = m.name(diff, "exp_diff");
    let eff_sub = if shape == Shape::SameSign {
        m.bool(false)
    } else {
        m.xor(ua.sign, sign_b)
    };
    let eff_sub = m.name(eff_sub, "eff_sub");
    let both_inf = m.and(ua.inf, ub.inf);
    let inf_minus_inf = m.and(both_inf, eff_sub);
    let any_nan = m.or(ua.nan, ub.nan);
    let nan = m.or(any_nan, inf_minus_inf);
    let nan = m.name(nan, "nan");
    let inf = m.or(ua.inf, ub.inf);
    let inf = m.name(inf, "inf");
    let class = class_of(m, nan, inf);
    let xw = add_exp_width(fmt);
    let exp = add_const(m, exp_big, -(fmt.bias() + f as i64 + 3), xw);
    let exp = m.name(exp, "sum_exp");
    for _ in 0..cuts[0] {
        m.stage();
    }

    // step 2: align the smaller significand, jamming what is shifted out
    let grs = m.uint(3, 0);
    let big_ext = m.cat(&[sig_big, grs]);
    let small_ext = m.cat(&[sig_small, grs]);
    let small_al = if lean {
        shr_jam_tz(m, small_ext, diff)
    } else {
        shr_jam(m, small_ext, diff)
    };
    let small_al = m.name(small_al, "small_aligned");
    for _ in 0..cuts[1] {
        m.stage();
    }

    // step 3: add or subtract (never negative: big >= small)
    let sum = if shape == Shape::SameSign {
        m.add(big_ext, small_al)
    } else if lean {
        // big + (small ^ -eff_sub) + eff_sub in one adder: the carry in as a
        // low bit added to a one ({big, 1} + {small', eff_sub}), modulo
        // 2^(F + 5) (a difference is never negative)
        let sw = big_ext.width() + 1;
        let big_w = zext(m, big_ext, sw);
        let small_w = zext(m, small_al, sw);
        let ones = m.uint(sw, (1u128 << sw) - 1);
        let zeros = m.uint(sw, 0);
        let flip = m.mux(eff_sub, ones, zeros);
        let small_c = m.xor(small_w, flip);
        let one = m.uint(1, 1);
        let carry_in = m.as_uint(eff_sub);
        let lhs = m.cat(&[big_w, one]);
        let rhs = m.cat(&[small_c, carry_in]);
        let s = m.add(lhs, rhs);
        m.slice(s, sw, 1)
    } else {
        let s_add = m.add(big_ext, small_al);
        let s_sub = m.sub(big_ext, small_al);
        let s_sub = m.as_uint(s_sub);
        m.mux(eff_sub, s_sub, s_add)
    };
    let sum = m.name(sum, "sum");
    let sum_any = m.any_set(sum);
    let sum_zero = m.not(sum_any);
    let cancel = m.and(sum_zero, eff_sub);
    let no_sticky = m.bool(false);
    for _ in 0..cuts[2] {
        m.stage();
    }
    SumRaw {
        raw: Raw {
            sign: sign_big,
            class,
            exp,
            sig: sum,
            sticky: no_sticky,
        },
        cancel,
    }
}

/// Module name of the adder (`fadd_…`) or subtractor (`fsub_…`).
pub fn add_name(fmt: Format, mode: RoundSel, sub: bool, stages: u32) -> String {
    let op = if sub { "fsub" } else { "fadd" };
    format!("{op}_{}_{mode}_s{stages}", fmt.tag())
}

/// `z = a + b` (or `a - b` if `sub`) in `fmt`, rounded in `mode`, with
/// `stages` pipeline registers (latency `stages`).
pub fn add_module(fmt: Format, mode: impl Into<RoundSel>, sub: bool, stages: u32) -> Arc<Module> {
    add_range_module(fmt, mode, sub, AddRange::Any, stages)
}

/// [`add_module`] for a sum that is zero or normal, never subnormal nor
/// overflowing (the caller guarantees it; outside that the result is
/// unspecified): the rounder builds no right shift for subnormal results.
/// Equal to [`add_module`] wherever the guarantee holds. Name `…_normal_s…`.
pub fn add_normal_module(
    fmt: Format,
    mode: impl Into<RoundSel>,
    sub: bool,
    stages: u32,
) -> Arc<Module> {
    add_range_module(fmt, mode, sub, AddRange::Normal, stages)
}

/// [`add_normal_module`]'s `a + b` for operands of one sign (either may be
/// a zero of any sign): the magnitudes are added, never subtracted, so the
/// sum has at most one leading zero and the rounder shifts by one bit at
/// most. For operands of opposite signs the result is unspecified (a
/// caller that ignores it there: the triangle unit's `det`, which matters
/// only when the three edge functions agree in sign), and a zero sum may
/// have either sign. Name `fadd_…_samesign_s…`.
pub fn add_same_sign_normal_module(fmt: Format, mode: Rounding, stages: u32) -> Arc<Module> {
    add_range_module(fmt, mode, false, AddRange::SameSign, stages)
}

/// What an adder's caller guarantees.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum AddRange {
    /// nothing
    Any,
    /// a sum that is zero or normal
    Normal,
    /// that, and operands of one sign
    SameSign,
}

fn add_range_module(
    fmt: Format,
    mode: impl Into<RoundSel>,
    sub: bool,
    guarantee: AddRange,
    stages: u32,
) -> Arc<Module> {
    let mode: RoundSel = mode.into();
    let what = if sub { "a - b" } else { "a + b" };
    let op = if sub { "fsub" } else { "fadd" };
    let (name, range, promise) = match guarantee {
        AddRange::Any => (add_name(fmt, mode, sub, stages), Range::Any, ""),
        AddRange::Normal => (
            format!("{op}_{}_{mode}_normal_s{stages}", fmt.tag()),
            Range::Normal { lead: u32::MAX },
            " The sum is zero or normal (guaranteed by the caller).",
        ),
        AddRange::SameSign => (
            format!("{op}_{}_{mode}_samesign_s{stages}", fmt.tag()),
            Range::Normal { lead: 1 },
            " The operands have one sign and the sum is zero or normal (guaranteed by the \
             caller); the sign of a zero sum is unspecified.",
        ),
    };
    let shape = match guarantee {
        AddRange::Any => Shape::General,
        AddRange::Normal => Shape::Lean,
        AddRange::SameSign => Shape::SameSign,
    };
    let mut m = fmt.operator_module(
        name,
        format!(
            "Floating-point {what} in {}, rounded {mode}.{promise}",
            fmt.tag()
        ),
        stages,
    );
    m.param("round", mode);
    let Pair { a, b, rm } = declare_inputs(&mut m, &PairPorts::rounded(fmt.ty(), mode));
    let rm = Rm::new(mode, rm);
    let (raw_cuts, rs) = rounded_add_plan(stages);
    let s = add_raw_with(&mut m, fmt, a, b, sub, &raw_cuts, shape);
    let raw = s.for_rm(&mut m, &rm);
    finish_rounded_range(m, fmt, &rm, &raw, range, rs, "adder")
}

/// Module name of the widening subtractor.
pub fn sub_widening_name(fmt: Format, to: Format, mode: Rounding, stages: u32) -> String {
    format!("fsub_{}_to_{}_{mode}_s{stages}", fmt.tag(), to.tag())
}

/// `z = a - b` for `a`, `b` in `fmt`, the exact difference rounded once
/// into `to` (the same fraction width or wider, an exponent range at least
/// `fmt`'s) in `mode`, `stages` registers (the plan of [`add_module`]).
/// Equal to widening both operands exactly into `to` and subtracting there;
/// with a wider exponent the difference never overflows.
pub fn sub_widening_module(fmt: Format, to: Format, mode: Rounding, stages: u32) -> Arc<Module> {
    sub_widening_range_module(fmt, to, mode, false, stages)
}

/// [`sub_widening_module`] into a `to` whose normal range holds every
/// nonzero difference of two `fmt` values (its smallest normal at most
/// `fmt`'s smallest subnormal; asserted): no right shift for subnormal
/// results. Name `…_normal_s…`.
pub fn sub_widening_normal_module(
    fmt: Format,
    to: Format,
    mode: Rounding,
    stages: u32,
) -> Arc<Module> {
    assert!(
        to.emin() <= fmt.emin() - fmt.frac_bits as i64 && to.emax() > fmt.emax(),
        "{}'s normal range holds every difference of {} values",
        to.tag(),
        fmt.tag()
    );
    sub_widening_range_module(fmt, to, mode, true, stages)
}

fn sub_widening_range_module(
    fmt: Format,
    to: Format,
    mode: Rounding,
    normal: bool,
    stages: u32,
) -> Arc<Module> {
    assert!(
        to.frac_bits >= fmt.frac_bits && to.exp_bits >= fmt.exp_bits,
        "{} holds every {} value",
        to.tag(),
        fmt.tag()
    );
    let (name, range) = if normal {
        let name = format!("fsub_{}_to_{}_{mode}_normal_s{stages}", fmt.tag(), to.tag());
        (name, Range::Normal { lead: u32::MAX })
    } else {
        (sub_widening_name(fmt, to, mode, stages), Range::Any)
    };
    let mut m = ModuleBuilder::new(name);
    m.describe(format!(
        "Floating-point a - b of two {} values, rounded {mode} into {}.",
        fmt.tag(),
        to.tag()
    ));
    m.param("exp_bits", fmt.exp_bits)
        .param("frac_bits", fmt.frac_bits)
        .param("to_exp_bits", to.exp_bits)
        .param("to_frac_bits", to.frac_bits)
        .param("round", mode)
        .param("stages", stages);
    let Pair { a, b, .. } = declare_inputs(&mut m, &PairPorts::same(fmt.ty()));
    let (raw_cuts, rs) = rounded_add_plan(stages);
    let shape = if normal { Shape::Lean } else { Shape::General };
    let s = add_raw_with(&mut m, fmt, a, b, true, &raw_cuts, shape);
    let raw = s.for_mode(&mut m, mode);
    finish_rounded_range(
        m,
        to,
        &Rm::fixed(mode),
        &raw,
        range,
        rs,
        "widening subtractor",
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Evaluator;
    use crate::golden_twin::{golden_format, golden_mode};
    use golden_model::float::{add, classify, convert, sub, Class, RoundingMode};

    /// The sum's exponent (the larger biased exponent, 1 ..= 2^E − 1, less
    /// bias + F + 3) takes no more bits than its range: binary32 spans −152
    /// to 102 (9 signed bits), e5m10 −27 to 3 (6), e2m1 −4 to −2 (3).
    #[test]
    fn the_sum_exponent_is_as_narrow_as_its_range() {
        let f = |e, m| Format::new(e, m).unwrap();
        assert_eq!(add_exp_width(f(8, 23)), 9);
        assert_eq!(add_exp_width(f(5, 10)), 6);
        assert_eq!(add_exp_width(f(2, 1)), 3);
    }

    /// A rounded adder's registers are spread evenly over its six steps
    /// (three of the exact sum, three of the rounding): one after every
    /// second step at 3 stages, one after each at 6, the last step's
    /// boundary taking what is left beyond six.
    #[test]
    fn a_rounded_adder_spreads_its_registers_over_sum_and_rounding() {
        assert_eq!(rounded_add_plan(0), (vec![0, 0, 0], 0));
        assert_eq!(rounded_add_plan(1), (vec![0, 0, 0], 1));
        assert_eq!(rounded_add_plan(3), (vec![0, 1, 0], 2));
        assert_eq!(rounded_add_plan(6), (vec![1, 1, 1], 3));
        assert_eq!(rounded_add_plan(8), (vec![1, 1, 1], 5));
    }

    /// The widening difference against the golden difference of both
    /// operands widened exactly: every pair of a small format in every
    /// mode, random pairs of binary32 and e5m10 into the triangle unit's
    /// internal formats.
    #[test]
    fn widening_difference_is_the_widened_difference() {
        let f = |e, m| Format::new(e, m).unwrap();
        let cases = [
            (f(3, 2), f(5, 2), true),
            (f(2, 3), f(4, 3), true),
            (f(8, 23), f(11, 23), false),
            (f(5, 10), f(9, 10), false),
        ];
        let mut s = 0x2545_f491_4f6c_dd1du64;
        for (fa, to, exhaustive) in cases {
            let (ga, gt) = (golden_format(fa), golden_format(to));
            for mode in Rounding::ALL {
                let module = sub_widening_module(fa, to, mode, 0);
                let mut ev = Evaluator::new(&module);
                let n: u64 = if exhaustive {
                    1 << (2 * fa.width())
                } else {
                    20_000
                };
                for i in 0..n {
                    let (a, b) = if exhaustive {
                        (i & ga.mask(), i >> fa.width())
                    } else {
                        s ^= s << 13;
                        s ^= s >> 7;
                        s ^= s << 17;
                        // near operands half the time (cancellation)
                        let b = (s >> 32) & ga.mask();
                        let a = if s & 1 == 0 {
                            b ^ (s >> 8 & 0xff)
                        } else {
                            s & ga.mask()
                        };
                        (a, b)
                    };
                    let got = ev.eval(&[a as u128, b as u128])[0] as u64;
                    let wa = convert(ga, gt, a, RoundingMode::NearestEven);
                    let wb = convert(ga, gt, b, RoundingMode::NearestEven);
                    let want = sub(gt, wa, wb, golden_mode(mode));
                    assert_eq!(got, want, "{}: {a:#x} - {b:#x}", module.name);
                }
            }
        }
    }

    /// The normal-range adders (the lean exact sum) against the golden sum
    /// on operands whose sum stays normal: random exponents in the middle of
    /// the range, near operands (cancellation, down to an exact zero), zeros
    /// of either sign; the one-sign adder on operands of one sign, up to the
    /// sign of a zero sum, which it leaves unspecified. Every mode, e11m23 and
    /// e9m10 (the triangle unit's internal formats).
    #[test]
    fn normal_range_adders_are_the_golden_sum() {
        let f = |e, m| Format::new(e, m).unwrap();
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for fmt in [f(11, 23), f(9, 10)] {
            let g = golden_format(fmt);
            let (fb, bias) = (fmt.frac_bits, fmt.bias() as u64);
            // a value with a biased exponent within 2^(E-2) of the bias, or zero
            let value = |r: u64| {
                if r.is_multiple_of(16) {
                    return (r >> 8 & 1) << (fmt.width() - 1);
                }
                let span = 1u64 << (fmt.exp_bits - 2);
                let exp = bias - span / 2 + (r >> 8) % span;
                let frac = (r >> 20) & ((1 << fb) - 1);
                (r >> 63) << (fmt.width() - 1) | exp << fb | frac
            };
            for mode in Rounding::ALL {
                let gm = golden_mode(mode);
                for (sub_op, same_sign) in [(false, false), (true, false), (false, true)] {
                    let module = if same_sign {
                        add_same_sign_normal_module(fmt, mode, 0)
                    } else {
                        add_normal_module(fmt, mode, sub_op, 0)
                    };
                    let mut ev = Evaluator::new(&module);
                    for _ in 0..20_000 {
                        let (ra, rb) = (next(), next());
                        let a = value(ra);
                        let sign = 1u64 << (fmt.width() - 1);
                        let mut b = if ra & 2 == 0 && a & !sign != 0 {
                            // near a: cancellation when the signs differ
                            a ^ (rb & 0xff) ^ ((rb >> 40 & 1) * sign)
                        } else {
                            value(rb)
                        };
                        if same_sign {
                            b = (b & !sign) | (a & sign);
                        }
                        let got = ev.eval(&[a as u128, b as u128])[0] as u64;
                        let want = if sub_op {
                            sub(g, a, b, gm)
                        } else {
                            add(g, a, b, gm)
                        };
                        if same_sign && classify(g, want) == Class::Zero {
                            assert_eq!(got & !sign, 0, "{}: {a:#x} + {b:#x}", module.name);
                        } else {
                            assert_eq!(got, want, "{}: {a:#x}, {b:#x}", module.name);
                        }
                    }
                }
            }
        }
    }

    /// The normal-range adders are built as [`Shape::Lean`] says (the same
    /// values as the general adder, so only their structure tells): no mask
    /// shifted for the sticky bit, one exponent difference and one adder of
    /// significands (no subtraction beside it); the one-sign adder no
    /// complement either.
    #[test]
    fn normal_range_adders_are_built_lean() {
        use crate::ir::Op;
        let fmt = Format::new(11, 23).unwrap();
        let count =
            |m: &Module, pick: fn(&Op) -> bool| m.nodes.iter().filter(|n| pick(&n.op)).count();
        let shl = |op: &Op| matches!(op, Op::Shl(..));
        let subs = |op: &Op| matches!(op, Op::Sub(..));
        let xors = |op: &Op| matches!(op, Op::Bit(crate::ir::BitOp::Xor, ..));
        for sub_op in [false, true] {
            let general = add_module(fmt, Rounding::Rne, sub_op, 0);
            let lean = add_normal_module(fmt, Rounding::Rne, sub_op, 0);
            assert!(
                count(&general, shl) >= 1,
                "{}: the mask shift",
                general.name
            );
            assert_eq!(count(&lean, shl), 0, "{}: no mask shift", lean.name);
            // general: two exponent differences and the significands' difference
            assert_eq!(count(&general, subs), 3, "{}", general.name);
            assert_eq!(
                count(&lean, subs),
                1,
                "{}: one exponent difference",
                lean.name
            );
        }
        let widening =
            sub_widening_normal_module(Format::new(8, 23).unwrap(), fmt, Rounding::Rne, 0);
        assert_eq!(count(&widening, shl), 0, "{}", widening.name);
        assert_eq!(count(&widening, subs), 1, "{}", widening.name);
        let lean = add_normal_module(fmt, Rounding::Rne, false, 0);
        let one_sign = add_same_sign_normal_module(fmt, Rounding::Rne, 0);
        assert!(
            count(&one_sign, xors) < count(&lean, xors),
            "{}: no complement",
            one_sign.name
        );
    }
}
