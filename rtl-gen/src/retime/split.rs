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

#[cfg(test)]
mod tests {
    //! The split proved for every width, not sampled: each node it builds is
    //! evaluated symbolically over the operands' bits (a value is a polynomial
    //! in them, exact as long as it fits its wire, which every node checks),
    //! and the result must be the whole product's polynomial. Distributivity
    //! is the whole argument; what can break it is a piece or weight off by
    //! one, or a wire too narrow for its sum, and both change the polynomial
    //! or fail the check.
    use super::*;
    use crate::ir::BitOp;

    /// A value as a polynomial in the bits `a_i` of `a` and `b_j` of `b`, at
    /// most bilinear: `k + Σ ca_i·a_i + Σ cb_j·b_j + Σ cab_ij·a_i·b_j`. The
    /// coefficients are never negative (the split only adds), so the value's
    /// maximum is the sum of the coefficients.
    #[derive(Clone, PartialEq, Debug)]
    struct Poly {
        k: u128,
        a: Vec<u128>,
        b: Vec<u128>,
        ab: Vec<u128>,
    }

    impl Poly {
        fn zero(wa: u32, wb: u32) -> Poly {
            Poly {
                k: 0,
                a: vec![0; wa as usize],
                b: vec![0; wb as usize],
                ab: vec![0; (wa * wb) as usize],
            }
        }
        fn coefficients(&self) -> impl Iterator<Item = u128> + '_ {
            std::iter::once(self.k).chain(self.a.iter().chain(&self.b).chain(&self.ab).copied())
        }
        fn max(&self) -> Option<u128> {
            self.coefficients().try_fold(0u128, |s, c| s.checked_add(c))
        }
        fn fits(&self, width: u32) -> bool {
            self.max()
                .is_some_and(|m| width >= 128 || m < 1u128 << width)
        }
        fn zip(&self, o: &Poly, f: impl Fn(u128, u128) -> Option<u128>) -> Option<Poly> {
            let v = |x: &[u128], y: &[u128]| -> Option<Vec<u128>> {
                x.iter().zip(y).map(|(&p, &q)| f(p, q)).collect()
            };
            Some(Poly {
                k: f(self.k, o.k)?,
                a: v(&self.a, &o.a)?,
                b: v(&self.b, &o.b)?,
                ab: v(&self.ab, &o.ab)?,
            })
        }
        fn add(&self, o: &Poly) -> Option<Poly> {
            self.zip(o, u128::checked_add)
        }
        fn shl(&self, s: u32) -> Option<Poly> {
            let up =
                |c: u128| (c == 0 || (s < 128 && c.leading_zeros() >= s)).then(|| c << s.min(127));
            self.zip(self, |c, _| up(c))
        }
        /// Bits `hi..=lo`: exact when the value is below `2^(hi+1)` and `lo`
        /// is 0, or when it is a set of disjoint bit fields (every term a
        /// distinct power of two of one monomial, as a slice of an operand).
        fn slice(&self, hi: u32, lo: u32) -> Option<Poly> {
            if lo == 0 && self.fits(hi + 1) {
                return Some(self.clone());
            }
            // the constant's bits are fields of their own (always 1)
            let mut seen = self.k;
            for c in self.a.iter().chain(&self.b).chain(&self.ab).copied() {
                if c != 0 && (!c.is_power_of_two() || seen & c != 0) {
                    return None;
                }
                seen |= c;
            }
            let keep = |c: u128| -> Option<u128> {
                let field = if hi >= 127 {
                    c
                } else {
                    c & ((1u128 << (hi + 1)) - 1)
                };
                Some(field >> lo)
            };
            self.zip(self, |c, _| keep(c))
        }
    }

    /// The symbolic value of every node, in order (operands come first).
    fn evaluate(nodes: &[FlatNode], wa: u32, wb: u32) -> Result<Vec<Poly>, String> {
        let mut vals: Vec<Poly> = Vec::with_capacity(nodes.len());
        for (i, n) in nodes.iter().enumerate() {
            let v = |id: &NodeId| &vals[id.0 as usize];
            let width = n.ty.width();
            let val = match &n.op {
                _ if n.ty.is_signed() => None,
                Op::Input(0) => Some(Poly {
                    a: (0..wa).map(|i| 1u128 << i).collect(),
                    ..Poly::zero(wa, wb)
                }),
                Op::Input(1) => Some(Poly {
                    b: (0..wb).map(|j| 1u128 << j).collect(),
                    ..Poly::zero(wa, wb)
                }),
                Op::Const(c) => Some(Poly {
                    k: *c,
                    ..Poly::zero(wa, wb)
                }),
                Op::Cast(x) => Some(v(x).clone()),
                Op::Slice(x, hi, lo) => v(x).slice(*hi, *lo),
                Op::Add(x, y) => v(x).add(v(y)),
                Op::Concat(parts) => {
                    let mut acc = Some(Poly::zero(wa, wb));
                    let mut at = 0;
                    for p in parts.iter().rev() {
                        acc = acc.and_then(|s| s.add(&v(p).shl(at)?));
                        at += nodes[p.0 as usize].ty.width();
                    }
                    acc
                }
                Op::Mul(x, y) => bilinear(v(x), v(y)).or_else(|| bilinear(v(y), v(x))),
                Op::Bit(BitOp::And, x, y) => {
                    gate(v(x), v(y), width).or_else(|| gate(v(y), v(x), width))
                }
                _ => None,
            };
            let val = val.filter(|p| p.fits(width)).ok_or_else(|| {
                format!("node {i} `{}` ({:?}, {}): not exact", n.name, n.op, n.ty)
            })?;
            vals.push(val);
        }
        Ok(vals)
    }

    /// `x · y` for `x` linear in `a`'s bits and `y` linear in `b`'s.
    fn bilinear(x: &Poly, y: &Poly) -> Option<Poly> {
        let only_a = |p: &Poly| p.k == 0 && p.b.iter().chain(&p.ab).all(|&c| c == 0);
        let only_b = |p: &Poly| p.k == 0 && p.a.iter().chain(&p.ab).all(|&c| c == 0);
        if !only_a(x) || !only_b(y) {
            return None;
        }
        let mut r = Poly::zero(x.a.len() as u32, y.b.len() as u32);
        for (i, &ca) in x.a.iter().enumerate() {
            for (j, &cb) in y.b.iter().enumerate() {
                r.ab[i * y.b.len() + j] = ca.checked_mul(cb)?;
            }
        }
        Some(r)
    }

    /// `x AND y` where `y` is one bit `b_j` copied to all `width` bits
    /// (`b_j·(2^width − 1)`) and `x` is linear in `a`'s bits and fits the
    /// width: `x·b_j`.
    fn gate(x: &Poly, y: &Poly, width: u32) -> Option<Poly> {
        let ones = if width >= 128 {
            u128::MAX
        } else {
            (1u128 << width) - 1
        };
        let nonzero: Vec<usize> = (0..y.b.len()).filter(|&j| y.b[j] != 0).collect();
        let single = y.k == 0 && y.a.iter().chain(&y.ab).all(|&c| c == 0);
        let [j] = nonzero[..] else { return None };
        if !single || y.b[j] != ones || !x.fits(width) {
            return None;
        }
        let mut bit = Poly::zero(x.a.len() as u32, y.b.len() as u32);
        bit.b[j] = 1;
        bilinear(x, &bit)
    }

    /// `Ok` when the split of a `wa × wb` product is the product.
    fn prove_split(wa: u32, wb: u32, plant: impl Fn(&mut Vec<FlatNode>)) -> Result<(), String> {
        let mut nodes = Vec::new();
        let a = push(&mut nodes, Op::Input(0), Ty::UInt(wa), "a".into());
        let b = push(&mut nodes, Op::Input(1), Ty::UInt(wb), "b".into());
        let p = split_product(&mut nodes, a, b, Ty::UInt(wa + wb), "p");
        plant(&mut nodes);
        let vals = evaluate(&nodes, wa, wb)?;
        let mut whole = Poly::zero(wa, wb);
        for i in 0..wa {
            for j in 0..wb {
                whole.ab[(i * wb + j) as usize] = 1u128 << (i + j);
            }
        }
        match vals[p] == whole {
            true => Ok(()),
            false => Err(format!("{wa}x{wb}: the split is not the product")),
        }
    }

    #[test]
    fn every_split_product_is_the_whole_product_at_every_width() {
        let mut split = 0;
        for wa in 1..=64 {
            for wb in 1..=64 {
                prove_split(wa, wb, |_| {}).unwrap_or_else(|e| panic!("{wa}x{wb}: {e}"));
                split += usize::from(wa.max(wb) > DSP_BITS);
            }
        }
        // the products the proof covers that are split at all (not one block)
        assert_eq!(split, 64 * 64 - 18 * 18);
    }

    #[test]
    fn a_wrong_split_is_not_proved() {
        // a piece one bit short, a weight one bit off, a sum too narrow
        let piece = |nodes: &mut Vec<FlatNode>| {
            let n = nodes.iter_mut().find(|n| n.name == "p_a0").unwrap();
            n.op = Op::Slice(NodeId(0), 16, 0);
        };
        let weight = |nodes: &mut Vec<FlatNode>| {
            let n = nodes.iter_mut().find(|n| n.name == "p_l1_shift0").unwrap();
            let Op::Concat(parts) = n.op.clone() else {
                panic!()
            };
            let zeros = parts[1].0 as usize;
            nodes[zeros].ty = Ty::UInt(nodes[zeros].ty.width() - 1);
        };
        // (`p_l1_sum0`, 18x18 + 6x18·2^18, needs 42 of its 43 bits: the
        // carry bit is spare there, and dropping it is still exact)
        let narrow = |bits: u32| {
            move |nodes: &mut Vec<FlatNode>| {
                let n = nodes.iter_mut().find(|n| n.name == "p_l1_sum0").unwrap();
                n.ty = Ty::UInt(n.ty.width() - bits);
            }
        };
        assert!(prove_split(24, 24, |_| {}).is_ok());
        assert!(prove_split(24, 24, piece).is_err());
        assert!(prove_split(24, 24, weight).is_err());
        assert!(prove_split(24, 24, narrow(1)).is_ok());
        assert!(prove_split(24, 24, narrow(2)).is_err());
    }
}
