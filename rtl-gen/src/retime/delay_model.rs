//! The delay model: one operation's delay in LUT levels of a 4-input-LUT
//! FPGA with carry chains and 18x18 multipliers.

use super::split::{on_dsp, DSP_ROUTE};
use crate::ir::{NodeId, Op, Ty};

/// Delay of one operation in LUT levels of a 4-input-LUT FPGA with carry
/// chains and 18x18 multipliers (ECP5, iCE40, 7-series alike to first order).
/// Wiring (slices, concatenations, casts) and constants cost nothing.
pub fn delay(op: &Op, ty: Ty, operand_ty: impl Fn(NodeId) -> Ty) -> f64 {
    let w = |id: NodeId| operand_ty(id).width() as f64;
    let carry = |bits: f64| 1.0 + bits / 16.0;
    let tree = |bits: f64| bits.max(2.0).log(4.0).ceil();
    match op {
        Op::Input(_) | Op::Const(_) | Op::Reg(_) | Op::InstOut { .. } => 0.0,
        Op::Not(_) | Op::Slice(..) | Op::Concat(_) | Op::Cast(_) => 0.0,
        Op::Bit(..) => 0.5,
        Op::Mux(..) => 0.7,
        Op::Reduce(_, a) => tree(w(*a)),
        Op::Add(a, b) | Op::Sub(a, b) => carry(w(*a).max(w(*b))),
        Op::Cmp(crate::ir::CmpOp::Eq, a, b) => 1.0 + tree(w(*a).max(w(*b))),
        Op::Cmp(_, a, b) => carry(w(*a).max(w(*b))),
        Op::Shl(a, k) | Op::Shr(a, k) => {
            // one 4:1 mux level per two amount bits, at most what the width needs
            let levels = w(*k).min(w(*a).log2().ceil() + 1.0);
            (levels / 2.0).ceil() * 1.2
        }
        Op::Mul(a, b) => {
            let (x, y) = (w(*a), w(*b));
            if !on_dsp(x as u32, y as u32) {
                // a few partial products: an adder tree of LUTs
                1.0 + carry(x.max(y)) * x.min(y).log2().max(1.0)
            } else {
                // 18x18 blocks: the route in and the block (3.2 + 3.9 ns on
                // ECP5-6; the route out is a wire of its own), the blocks of a
                // wider signed product summed by carry chains
                let blocks = (x / 18.0).ceil() * (y / 18.0).ceil();
                DSP_ROUTE + 2.3 + blocks.log2() * carry(ty.width() as f64)
            }
        }
    }
}
