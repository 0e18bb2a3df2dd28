//! Exact multiplication: the full product as a value of the wider format
//! (E + 2, 2F + 1), never rounded.
//!
//! Every product of two (E, F) values is representable there: the 2F + 2
//! significant bits of the product fit 2F + 1 fraction bits plus the hidden
//! bit, the largest product is below `2^(2·emax + 2) <= 2^(emax')`, and the
//! smallest, `2^(2·(emin - F))`, is a multiple of the wide format's smallest
//! subnormal. The shared rounder of the wide format normalises and packs it
//! (its rounding logic sees a zero round bit and no sticky, so any mode gives
//! the same bits; RNE is used).

use super::mul::{mul_raw, MUL_RAW_STEPS};
use super::round::{round, ROUND_STEPS};
use super::{finish_operator, spread, Format, Rounding};
use crate::arith::ports::Rounded;
use crate::arith::ports::{Pair, PairPorts};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// The exact-product format (E + 2, 2F + 1) of `fmt`, if supported.
pub fn exact_product_format(fmt: Format) -> Result<Format, String> {
    Format::new(fmt.exp_bits + 2, 2 * fmt.frac_bits + 1)
        .map_err(|e| format!("the exact product of {} needs {e}", fmt.tag()))
}

/// Module name of the exact multiplier.
pub fn mul_exact_name(fmt: Format, stages: u32) -> String {
    format!("fmul_exact_{}_s{stages}", fmt.tag())
}

/// `z = a · b` exactly, `a`, `b` in `fmt`, `z` in [`exact_product_format`];
/// `stages` pipeline registers. Panics if the wide format is unsupported.
pub fn mul_exact_module(fmt: Format, stages: u32) -> Arc<Module> {
    let wide = exact_product_format(fmt).expect("exact product format must be supported");
    let mut m = fmt.operator_module(
        mul_exact_name(fmt, stages),
        format!(
            "Exact floating-point product of two {} values as a {} value (no rounding).",
            fmt.tag(),
            wide.tag()
        ),
        stages,
    );
    let Pair { a, b, .. } = declare_inputs(&mut m, &PairPorts::same(fmt.ty()));
    let plan = spread(stages, MUL_RAW_STEPS + ROUND_STEPS);
    let (raw_cuts, round_cuts) = plan.split_at(MUL_RAW_STEPS as usize);
    let raw = mul_raw(&mut m, fmt, a, b, raw_cuts.iter().sum(), "u_mul");
    let rs: u32 = round_cuts.iter().sum();
    let z = round(&mut m, wide, Rounding::Rne, &raw, rs, "u_pack");
    finish_operator(m, rs, &wide.ty(), &Rounded { z }, "exact multiplier")
}
