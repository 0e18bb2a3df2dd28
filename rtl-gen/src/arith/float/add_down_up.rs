//! One exact sum rounded both toward -inf (RDN) and toward +inf (RUP): the
//! adder's exact part once, the shared rounder's normalisation once
//! ([`round_down_up`]).

use super::add::{add_raw, rounded_add_plan};
use super::round::round_down_up;
use super::{finish_operator, Format, Rounding};
use crate::arith::ports::DownUp;
use crate::arith::ports::{Pair, PairPorts};
use crate::ir::Module;
use crate::ports::declare_inputs;
use std::sync::Arc;

/// Module name of the down/up adder.
pub fn add_down_up_name(fmt: Format, stages: u32) -> String {
    format!("fadd_down_up_{}_s{stages}", fmt.tag())
}

/// `down = RDN(a + b)`, `up = RUP(a + b)` in `fmt`, `stages` pipeline
/// registers. `down == up` exactly when the sum is representable (both NaN
/// for a NaN sum); an exact zero of opposite-signed operands is -0 down and +0 up.
pub fn add_down_up_module(fmt: Format, stages: u32) -> Arc<Module> {
    let mut m = fmt.operator_module(
        add_down_up_name(fmt, stages),
        format!(
            "a + b in {} rounded toward -inf (down) and toward +inf (up) from one exact sum.",
            fmt.tag()
        ),
        stages,
    );
    let Pair { a, b, .. } = declare_inputs(&mut m, &PairPorts::same(fmt.ty()));
    let (raw_cuts, rs) = rounded_add_plan(stages);
    let s = add_raw(&mut m, fmt, a, b, false, &raw_cuts);
    let raw_down = s.for_mode(&mut m, Rounding::Rdn);
    let raw_up = s.for_mode(&mut m, Rounding::Rup);
    let (down, up) = round_down_up(
        &mut m,
        fmt,
        &raw_down,
        raw_down.sign,
        raw_up.sign,
        rs,
        "u_round",
    );
    finish_operator(m, rs, &fmt.ty(), &DownUp { down, up }, "down/up adder")
}
