//! IEEE 754 quiet comparisons `lt`, `le`, `eq`: a NaN operand makes every
//! comparison false (unordered); -0 == +0. Compares the encodings as
//! sign-magnitude integers; no unpacking is needed.

use super::{finish_operator, Format};
use crate::arith::ports::Comparison;
use crate::arith::ports::{Pair, PairPorts};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Two encodings read as sign and magnitude (the magnitude of an encoding
/// is monotonic in its value), with the NaN test: what comparisons and
/// min/max share.
pub(super) struct SignMagnitude {
    /// sign of a, sign of b
    pub sa: Sig,
    pub sb: Sig,
    /// the encodings without their sign bits
    pub mag_a: Sig,
    pub mag_b: Sig,
    /// a or b is NaN
    pub any_nan: Sig,
}

impl SignMagnitude {
    #[track_caller]
    pub fn of(m: &mut ModuleBuilder, fmt: Format, a: Sig, b: Sig) -> SignMagnitude {
        let w = fmt.width();
        let sa = m.msb(a);
        let sb = m.msb(b);
        let mag_a = m.slice(a, w - 2, 0);
        let mag_b = m.slice(b, w - 2, 0);
        let inf = m.uint(w - 1, fmt.inf_bits());
        let nan_a = m.gt(mag_a, inf);
        let nan_b = m.gt(mag_b, inf);
        let any_nan = m.or(nan_a, nan_b);
        SignMagnitude {
            sa,
            sb,
            mag_a,
            mag_b,
            any_nan,
        }
    }
}

/// The three comparisons of `a` and `b` (encodings of `fmt`): `(lt, le, eq)`.
#[track_caller]
pub fn compare(m: &mut ModuleBuilder, fmt: Format, a: Sig, b: Sig) -> (Sig, Sig, Sig) {
    let SignMagnitude {
        sa,
        sb,
        mag_a,
        mag_b,
        any_nan,
    } = SignMagnitude::of(m, fmt, a, b);
    let ordered = m.not(any_nan);
    let ordered = m.name(ordered, "ordered");
    let mag_or = m.or(mag_a, mag_b);
    let nonzero = m.any_set(mag_or);
    let both_zero = m.not(nonzero);
    // one magnitude comparison (a carry chain) and one equality (a LUT
    // tree): greater is neither, not a second chain
    let mag_lt = m.lt(mag_a, mag_b);
    let mag_eq = m.eq(mag_a, mag_b);
    let mag_lt_or_eq = m.or(mag_lt, mag_eq);
    let mag_gt = m.not(mag_lt_or_eq);
    let same_sign = m.eq(sa, sb);
    let not_sb = m.not(sb);
    let not_sa = m.not(sa);
    // a negative, b positive, not both zero
    let neg_pos = m.and(sa, not_sb);
    let neg_pos = m.and(neg_pos, nonzero);
    let both_pos = m.and(not_sa, not_sb);
    let pos_lt = m.and(both_pos, mag_lt);
    let pos_lt = m.name(pos_lt, "pos_lt");
    let both_neg = m.and(sa, sb);
    let neg_lt = m.and(both_neg, mag_gt);
    let neg_lt = m.name(neg_lt, "neg_lt");
    let lt = m.or(neg_pos, pos_lt);
    let lt = m.or(lt, neg_lt);
    let lt = m.and(lt, ordered);
    let same = m.and(mag_eq, same_sign);
    let eq = m.or(same, both_zero);
    let eq = m.and(eq, ordered);
    let le = m.or(lt, eq);
    (m.name(lt, "lt"), m.name(le, "le"), m.name(eq, "eq"))
}

/// Module name of the comparator.
pub fn compare_name(fmt: Format, stages: u32) -> String {
    format!("fcmp_{}_s{stages}", fmt.tag())
}

/// Outputs `lt = a < b`, `le = a <= b`, `eq = a == b` (IEEE quiet
/// comparisons) of two `fmt` values; `stages` registers at the outputs.
pub fn compare_module(fmt: Format, stages: u32) -> Arc<Module> {
    let mut m = fmt.operator_module(
        compare_name(fmt, stages),
        format!(
            "IEEE comparisons of two {} values: lt, le, eq (NaN unordered, -0 == +0).",
            fmt.tag()
        ),
        stages,
    );
    let Pair { a, b, .. } = declare_inputs(&mut m, &PairPorts::same(fmt.ty()));
    let (lt, le, eq) = m.scope("ab", |m| compare(m, fmt, a, b));
    finish_operator(m, stages, &(), &Comparison { lt, le, eq }, "comparator")
}
