//! Integer helpers (extension, resizing, counters) and the pipelined unsigned
//! multiplier.

use crate::arith::ports::{Pair, PairPorts, Product};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::ports::{declare_inputs, declare_outputs};
use std::sync::Arc;

/// `a` zero-extended (or cut) to `w` bits, as UInt.
#[track_caller]
pub fn zext(m: &mut ModuleBuilder, a: Sig, w: u32) -> Sig {
    let a = m.as_uint(a);
    match a.width() {
        aw if aw == w => a,
        aw if aw > w => m.slice(a, w - 1, 0),
        aw => {
            let zeros = m.uint(w - aw, 0);
            m.cat(&[zeros, a])
        }
    }
}

/// `a` sign-extended to `w >= width(a)` bits, as SInt.
#[track_caller]
pub fn sext(m: &mut ModuleBuilder, a: Sig, w: u32) -> Sig {
    let aw = a.width();
    if aw >= w {
        let cut = m.slice(a, w - 1, 0);
        return m.as_sint(cut);
    }
    let sign = m.msb(a);
    let sign = m.as_uint(sign);
    let mut parts = vec![sign; (w - aw) as usize];
    parts.push(m.as_uint(a));
    let v = m.cat(&parts);
    m.as_sint(v)
}

/// Bits needed to hold values `0..=max`.
pub fn bits_for(max: u64) -> u32 {
    (64 - max.leading_zeros()).max(1)
}

/// `a + 1`, wrapping at the width of `a` (UInt).
#[track_caller]
pub fn inc(m: &mut ModuleBuilder, a: Sig) -> Sig {
    let one = m.uint(a.width(), 1);
    let s = m.add(a, one);
    m.slice(s, a.width() - 1, 0)
}

/// `a − 1`, wrapping at the width of `a` (UInt).
#[track_caller]
pub fn dec(m: &mut ModuleBuilder, a: Sig) -> Sig {
    let one = m.uint(a.width(), 1);
    let s = m.sub(a, one);
    m.slice(s, a.width() - 1, 0)
}

/// `a == k` for a UInt constant `k`.
#[track_caller]
pub fn is(m: &mut ModuleBuilder, a: Sig, k: u64) -> Sig {
    let k = m.uint(a.width(), k as u128);
    m.eq(a, k)
}

/// The module name of a `width_a × width_b` unsigned multiplier with `stages` registers.
pub fn umul_name(width_a: u32, width_b: u32, stages: u32) -> String {
    format!("umul_{width_a}x{width_b}_s{stages}")
}

/// Builds an unsigned `width_a × width_b → width_a + width_b` multiplier with
/// `stages` pipeline registers (latency = `stages`, II = 1).
///
/// Stage plan: `b` is split into `2^(stages−1)` slices (at most one per bit);
/// stage 0 forms the partial products `a · b_slice`, each following stage adds
/// one level of the pairwise adder tree, and the last stage registers the
/// product. Stages beyond the tree's depth register the product again (for
/// retiming by the synthesis tool).
pub fn umul_module(width_a: u32, width_b: u32, stages: u32) -> Arc<Module> {
    let name = umul_name(width_a, width_b, stages);
    let mut m = ModuleBuilder::new(&name);
    m.describe(format!(
        "Unsigned {width_a} x {width_b} multiplier, full {}-bit product, {stages} pipeline stage(s).",
        width_a + width_b
    ));
    m.param("width_a", width_a)
        .param("width_b", width_b)
        .param("stages", stages);
    let ports = PairPorts {
        a: Ty::UInt(width_a),
        b: Ty::UInt(width_b),
        rm: false,
    };
    let Pair { a, b, .. } = declare_inputs(&mut m, &ports);
    let levels = stages.saturating_sub(1).min(31 - width_b.leading_zeros());
    let slices = 1u32 << levels;
    // (value, lowest bit of b it covers, highest bit): value < 2^(width_a + hi − lo + 1)
    let mut terms: Vec<(Sig, u32, u32)> = (0..slices)
        .map(|i| {
            let lo = i * width_b / slices;
            let hi = (i + 1) * width_b / slices - 1;
            let chunk = m.slice(b, hi, lo);
            let pp = m.mul(a, chunk);
            (m.name(pp, &format!("pp{i}")), lo, hi)
        })
        .collect();
    let mut used = 0;
    let mut level = 0;
    while terms.len() > 1 {
        m.stage();
        used += 1;
        level += 1;
        terms = terms
            .chunks(2)
            .enumerate()
            .map(|(i, pair)| {
                let ((x, lo, _), (y, lo2, hi)) = (pair[0], pair[1]);
                let w = width_a + hi - lo + 1;
                let zeros = m.uint(lo2 - lo, 0);
                let y_weighted = m.cat(&[y, zeros]);
                let s = m.add(x, y_weighted);
                // the sum of the covered partial products fits w bits: the carry out is zero
                let s = zext(&mut m, s, w);
                (m.name(s, &format!("l{level}_sum{i}")), lo, hi)
            })
            .collect();
    }
    let p = m.name(terms[0].0, "product");
    while used < stages {
        m.stage();
        used += 1;
    }
    declare_outputs(&mut m, &p.ty(), &Product { p });
    Arc::new(
        m.finish()
            .expect("multiplier generator is type-correct for every width"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Evaluator;

    /// `umul_module` delays the full product by exactly `stages` cycles at every depth,
    /// including the stages past its adder tree's depth (registers that only delay: a
    /// mutant that dropped them kept every product and lost the latency).
    #[test]
    fn the_multiplier_has_its_latency_and_its_product() {
        for (wa, wb) in [(1, 1), (5, 3), (8, 8), (11, 24), (24, 24)] {
            for stages in 1..=6 {
                let m = umul_module(wa, wb, stages);
                assert_eq!(m.latency, stages, "{wa}x{wb} s{stages}");
                let mut e = Evaluator::new(&m);
                let mut x = 0x0123_4567_89ab_cdefu128 ^ u128::from(wa * 31 + wb * 7 + stages);
                let mut sent = Vec::new();
                for t in 0..40 {
                    x = x.wrapping_mul(0x9e37_79b9_7f4a_7c15).wrapping_add(1);
                    let (a, b) = ((x >> 7) & ((1 << wa) - 1), (x >> 70) & ((1 << wb) - 1));
                    sent.push(a * b);
                    let out = e.step(&[a, b]);
                    if t >= stages as usize {
                        let want = sent[t - stages as usize];
                        assert_eq!(out, vec![want], "{wa}x{wb} s{stages} cycle {t}");
                    }
                }
            }
        }
    }
}
