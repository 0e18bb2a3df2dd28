//! IEEE 754-2019 `minimum` and `maximum`: the canonical NaN if either operand
//! is NaN; otherwise the smaller (larger) operand with -0 ordered below +0.

use super::compare::SignMagnitude;
use super::{finish_operator, Format};
use crate::arith::ports::MinMax;
use crate::arith::ports::{Pair, PairPorts};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// `(min, max)` of `a` and `b` (encodings of `fmt`).
#[track_caller]
pub fn min_max(m: &mut ModuleBuilder, fmt: Format, a: Sig, b: Sig) -> (Sig, Sig) {
    let w = fmt.width();
    let SignMagnitude {
        sa,
        sb,
        mag_a,
        mag_b,
        any_nan,
    } = SignMagnitude::of(m, fmt, a, b);
    // a <= b in the total order of non-NaN values with -0 < +0
    let not_sa = m.not(sa);
    let not_sb = m.not(sb);
    let neg_pos = m.and(sa, not_sb);
    let both_pos = m.and(not_sa, not_sb);
    // one magnitude comparison (a carry chain) and one equality (a LUT
    // tree): le and ge from them, not a second chain
    let mag_lt = m.lt(mag_a, mag_b);
    let mag_eq = m.eq(mag_a, mag_b);
    let mag_le = m.or(mag_lt, mag_eq);
    let pos_le = m.and(both_pos, mag_le);
    let both_neg = m.and(sa, sb);
    let mag_ge = m.not(mag_lt);
    let neg_le = m.and(both_neg, mag_ge);
    let a_le_b = m.or(neg_pos, pos_le);
    let a_le_b = m.or(a_le_b, neg_le);
    let a_le_b = m.name(a_le_b, "a_le_b");
    let nan = m.uint(w, fmt.nan_bits());
    let lo = m.mux(a_le_b, a, b);
    let hi = m.mux(a_le_b, b, a);
    let min = m.mux(any_nan, nan, lo);
    let max = m.mux(any_nan, nan, hi);
    (m.name(min, "min"), m.name(max, "max"))
}

/// Module name of the min/max operator.
pub fn min_max_name(fmt: Format, stages: u32) -> String {
    format!("fminmax_{}_s{stages}", fmt.tag())
}

/// Outputs `min` and `max` of two `fmt` values; `stages` registers at the outputs.
pub fn min_max_module(fmt: Format, stages: u32) -> Arc<Module> {
    let mut m = fmt.operator_module(
        min_max_name(fmt, stages),
        format!(
            "IEEE 754-2019 minimum and maximum of two {} values (NaN if either is NaN, -0 < +0).",
            fmt.tag()
        ),
        stages,
    );
    let Pair { a, b, .. } = declare_inputs(&mut m, &PairPorts::same(fmt.ty()));
    let (min, max) = m.scope("ab", |m| min_max(m, fmt, a, b));
    finish_operator(m, stages, &fmt.ty(), &MinMax { min, max }, "min/max")
}
