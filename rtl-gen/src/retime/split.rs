//! Products split into DSP blocks: unsigned products wider than a block's
//! 18 bits become the products of their pieces summed with their weights, so
//! that registers can go between the blocks and the sum.

use super::flatten::{push, FlatNode};
use crate::ir::{NodeId, Op, Ty};

/// Operand width of one DSP block: ECP5's MULT18X18D, the device the model is
/// calibrated on (a 7-series DSP48E1 takes 25x18, so there a 24x24 product
/// may take more blocks split this way than whole).
const DSP_BITS: u32 = 18;

/// Delay of the route between the fabric and a DSP block on ECP5 (about
/// 3.2 ns: the blocks sit in rows of their own), in LUT levels.
pub(super) const DSP_ROUTE: f64 = 1.8;

/// Widest remainder pieces of a split product whose block is summed in LUTs
/// instead of a DSP block: a 24x24 product's 6x6 corner is a few dozen LUT4s
/// of partial products, against a quarter of its four blocks (Yosys would
/// put a written `*` of it on a block).
const CORNER_BITS: u32 = 6;

/// True when a `wa x wb` product goes to a DSP block rather than LUTs.
pub(super) fn on_dsp(wa: u32, wb: u32) -> bool {
    wa.min(wb) > 4
}

/// `a · b` on one DSP block, its product behind a [`DSP_ROUTE`] wire that
/// starts a stage: a register at the block's output pins (the block's own
/// output register, in effect), so no stage holds the route in, the block,
/// the route out and the logic after it. The route in is part of the block's
/// [`delay`].
fn dsp_block(nodes: &mut Vec<FlatNode>, a: usize, b: usize, ty: Ty, name: &str) -> usize {
    let p = push(
        nodes,
        Op::Mul(NodeId(a as u32), NodeId(b as u32)),
        ty,
        format!("{name}_dsp"),
    );
    if !on_dsp(nodes[a].ty.width(), nodes[b].ty.width()) {
        nodes[p].name = name.to_string();
        return p;
    }
    let w = push(nodes, Op::Cast(NodeId(p as u32)), ty, name.to_string());
    nodes[w].wire = true;
    w
}

/// `a · b` as one node, or, for unsigned operands wider than [`DSP_BITS`],
/// as the products of their 18-bit pieces summed with their weights: the
/// same exact product, with places for registers between blocks and sums.
pub(super) fn split_product(
    nodes: &mut Vec<FlatNode>,
    a: usize,
    b: usize,
    ty: Ty,
    name: &str,
) -> usize {
    let (ta, tb) = (nodes[a].ty, nodes[b].ty);
    let unsigned = |t: Ty| matches!(t, Ty::UInt(_));
    if !unsigned(ta) || !unsigned(tb) || ta.width().max(tb.width()) <= DSP_BITS {
        return dsp_block(nodes, a, b, ty, name);
    }
    let pieces = |nodes: &mut Vec<FlatNode>, x: usize, tag: &str| -> Vec<(usize, u32)> {
        let w = nodes[x].ty.width();
        (0..w.div_ceil(DSP_BITS))
            .map(|i| {
                let lo = i * DSP_BITS;
                let hi = (lo + DSP_BITS).min(w) - 1;
                let op = Op::Slice(NodeId(x as u32), hi, lo);
                (
                    push(nodes, op, Ty::UInt(hi - lo + 1), format!("{name}_{tag}{i}")),
                    lo,
                )
            })
            .collect()
    };
    let pa = pieces(nodes, a, "a");
    let pb = pieces(nodes, b, "b");
    // (node, weight): every block product, then pairwise sums of equal-width terms
    let mut terms: Vec<(usize, u32)> = Vec::new();
    for &(x, wx) in &pa {
        for &(y, wy) in &pb {
            let (xw, yw) = (nodes[x].ty.width(), nodes[y].ty.width());
            let block = format!("{name}_block{}x{}", wx / DSP_BITS, wy / DSP_BITS);
            let p = if xw.max(yw) <= CORNER_BITS {
                lut_product(nodes, x, y, Ty::UInt(xw + yw), &block)
            } else {
                dsp_block(nodes, x, y, Ty::UInt(xw + yw), &block)
            };
            terms.push((p, wx + wy));
        }
    }
    sum_terms(nodes, terms, ty, name)
}

/// The sum of `terms` (node, weight in bits) as a `ty` value: pairwise, each
/// heavier term shifted onto the lighter one's weight; the lightest term has
/// weight 0 and the sum fits `ty`.
fn sum_terms(nodes: &mut Vec<FlatNode>, mut terms: Vec<(usize, u32)>, ty: Ty, name: &str) -> usize {
    let total = ty.width();
    let mut level = 0;
    while terms.len() > 1 {
        level += 1;
        let mut next = Vec::new();
        for (i, pair) in terms.chunks(2).enumerate() {
            if let [(x, wx), (y, wy)] = *pair {
                // align the heavier term onto the lighter one's weight
                let ((lo, wlo), (hi, whi)) = if wx <= wy {
                    ((x, wx), (y, wy))
                } else {
                    ((y, wy), (x, wx))
                };
                let shifted = if whi > wlo {
                    let z = push(
                        nodes,
                        Op::Const(0),
                        Ty::UInt(whi - wlo),
                        format!("k0_w{}", whi - wlo),
                    );
                    let w = nodes[hi].ty.width() + whi - wlo;
                    push(
                        nodes,
                        Op::Concat(vec![NodeId(hi as u32), NodeId(z as u32)]),
                        Ty::UInt(w),
                        format!("{name}_l{level}_shift{i}"),
                    )
                } else {
                    hi
                };
                let w = nodes[lo].ty.width().max(nodes[shifted].ty.width()) + 1;
                // the partial sums never exceed the product: keep at most its width
                let keep = total.saturating_sub(wlo);
                let sum_name = format!("{name}_l{level}_sum{i}");
                let sum = push(
                    nodes,
                    Op::Add(NodeId(lo as u32), NodeId(shifted as u32)),
                    Ty::UInt(w),
                    match w > keep {
                        true => format!("{sum_name}_carry"),
                        false => sum_name.clone(),
                    },
                );
                let sum = if w > keep {
                    push(
                        nodes,
                        Op::Slice(NodeId(sum as u32), keep - 1, 0),
                        Ty::UInt(keep),
                        sum_name,
                    )
                } else {
                    sum
                };
                next.push((sum, wlo));
            } else {
                next.push(pair[0]);
            }
        }
        terms = next;
    }
    let (p, weight) = terms[0];
    debug_assert_eq!(weight, 0, "the lowest block has weight 0");
    let w = nodes[p].ty.width();
    match w.cmp(&total) {
        std::cmp::Ordering::Equal => p,
        std::cmp::Ordering::Greater => push(
            nodes,
            Op::Slice(NodeId(p as u32), total - 1, 0),
            ty,
            name.to_string(),
        ),
        std::cmp::Ordering::Less => {
            let z = push(
                nodes,
                Op::Const(0),
                Ty::UInt(total - w),
                format!("k0_w{}", total - w),
            );
            push(
                nodes,
                Op::Concat(vec![NodeId(z as u32), NodeId(p as u32)]),
                ty,
                name.to_string(),
            )
        }
    }
}

/// `a · b` (unsigned) as its partial products `a · b_i · 2^i` summed in the
/// fabric ([`CORNER_BITS`]).
fn lut_product(nodes: &mut Vec<FlatNode>, a: usize, b: usize, ty: Ty, name: &str) -> usize {
    let wa = nodes[a].ty.width();
    let wb = nodes[b].ty.width();
    let terms = (0..wb)
        .map(|i| {
            // (a one-bit piece is its own bit: Verilog cannot select from a scalar)
            let bit = if wb == 1 {
                b
            } else {
                push(
                    nodes,
                    Op::Slice(NodeId(b as u32), i, i),
                    Ty::UInt(1),
                    format!("{name}_b{i}"),
                )
            };
            let spread = push(
                nodes,
                Op::Concat(vec![NodeId(bit as u32); wa as usize]),
                Ty::UInt(wa),
                format!("{name}_b{i}_all"),
            );
            let pp = push(
                nodes,
                Op::Bit(
                    crate::ir::BitOp::And,
                    NodeId(a as u32),
                    NodeId(spread as u32),
                ),
                Ty::UInt(wa),
                format!("{name}_pp{i}"),
            );
            (pp, i)
        })
        .collect();
    sum_terms(nodes, terms, ty, name)
}
