//! `slab`: the classic slab ray/box tester, the baseline most ray-tracing
//! hardware uses, generated with the same operators as `silhouette` so cost
//! and accuracy can be compared side by side (issue #4, docs/silhouette.md §6).
//!
//! The reciprocal direction `inv_d` is an input (precomputed, `1/±0 = ±∞`).
//! Per axis `u = p_min − o`, `v = p_max − o`, `t0 = u·inv_d`, `t1 = v·inv_d`
//! (all rounded to nearest even), `near = minimum(t0, t1)`, `far =
//! maximum(t0, t1)` (IEEE 754-2019: a NaN propagates); then `t_enter` is the
//! maximum of `t_min` and the three `near`, `t_exit` the minimum of `t_max`
//! and the three `far`, and `hit = t_enter <= t_exit`. The golden twin is
//! `golden_model::slab`. (Maximum and minimum are associative and commutative
//! on these values, with −0 below +0 and a canonical NaN, so the tree here
//! gives the golden model's left-to-right chain bit for bit.)
//!
//! `rounding=conservative` builds the conservative slab instead (the design
//! RAABB publishes; docs/silhouette.md §6, twin
//! `golden_model::slab::eval_conservative`): `inv_d` is `1/d` rounded toward
//! zero, read as the interval `|inv_d| ≤ |1/d| ≤ next_up(|inv_d|)`; each
//! axis is mirrored by the sign bit of `inv_d` so the reciprocal is ≥ 0, the
//! entry difference `p_min − o` is rounded down and the exit difference
//! `p_max − o` up, each is multiplied by the interval end that keeps the
//! bound conservative (the upper end for a negative entry or positive exit
//! difference, the lower end otherwise) rounded down (entry) or up (exit);
//! `inv_d = ±∞` (a zero direction component) selects `−∞..+∞` if
//! `p_min ≤ o ≤ p_max` and the empty `+∞..−∞` otherwise, so no `0·∞` is
//! formed. The test then never misses a hit of the exact segment.
//!
//! Pipelining: `stages` registers spread over 14 logical steps: the
//! differences (6), the products (5), min/max (or the parallel-slab select),
//! the reduction tree and the final comparison.

use super::ports::{self, Record, Visit, Walk};
use super::{Description, AXES};
use crate::arith::float::add::{add_module, ADD_RAW_STEPS};
use crate::arith::float::compare::compare;
use crate::arith::float::minmax::min_max;
use crate::arith::float::mul::{mul_module, MUL_RAW_STEPS};
use crate::arith::float::round::ROUND_STEPS;
use crate::arith::float::{spread_over, Format, Rounding};
use crate::arith::ports::{rounded, Pair};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;
use std::sync::Arc;

/// The `slab` unit.
pub struct Slab;

/// A slab unit's configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// the float format
    pub fmt: Format,
    /// nearest or conservative
    pub rounding: SlabRounding,
    /// pipeline stages
    pub stages: u32,
}

crate::choice! {
    /// Rounding policy of the slab.
    pub enum SlabRounding {
        /// every operation RNE, min/max of the two plane parameters (the classic slab)
        Nearest = "nearest",
        /// directed rounding, interval reciprocal, parallel slabs handled: never misses
        Conservative = "conservative",
    }
}

crate::params! {
    /// The slab unit's parameters.
    pub struct SlabParams {
        /// exponent bits E of the format
        exp_bits: u32 [2..=11] = 8,
        /// fraction bits F of the format (1 + E + F <= 64)
        frac_bits: u32 [1..=52] = 23,
        /// nearest: inv_d = RNE(1/d), all RNE (classic, misses hits); conservative: inv_d =
        /// RTZ(1/d), directed rounding, d = 0 handled, never misses a hit
        rounding: SlabRounding = SlabRounding::Nearest,
        /// pipeline stages (latency in cycles), spread over differences, products, min/max,
        /// reduction, comparison
        stages: u32 [0..=32] = 4,
    }
}

/// Logical steps of a difference (adder and rounder).
pub const DIFF_STEPS: u32 = ADD_RAW_STEPS + ROUND_STEPS;
/// Logical steps of a product (multiplier and rounder).
pub const PRODUCT_STEPS: u32 = MUL_RAW_STEPS + ROUND_STEPS;
/// Logical steps per phase, in the order of [`StagePlan`]'s fields:
/// differences, products, min/max, reduction tree, comparison.
pub const PHASES: [u32; 5] = [DIFF_STEPS, PRODUCT_STEPS, 1, 1, 1];

/// How the `stages` registers are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StagePlan {
    /// inside the subtractors
    pub diff: u32,
    /// inside the multipliers
    pub product: u32,
    /// after the per-axis min/max
    pub min_max: u32,
    /// after the reduction to `t_enter`, `t_exit`
    pub reduce: u32,
    /// after the final comparison
    pub compare: u32,
}

impl StagePlan {
    /// The plan for `stages` registers ([`spread_over`] the [`PHASES`]).
    pub fn new(stages: u32) -> StagePlan {
        let [diff, product, min_max, reduce, compare] = spread_over(stages, PHASES);
        StagePlan {
            diff,
            product,
            min_max,
            reduce,
            compare,
        }
    }
}

/// The data inputs: `p_min_* p_max_* o_* inv_d_* t_min t_max` (`*` = x, y, z).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlabIn<T> {
    /// the box's lower corner
    pub p_min: [T; 3],
    /// the box's upper corner
    pub p_max: [T; 3],
    /// the ray's origin
    pub o: [T; 3],
    /// the reciprocal of the ray's direction
    pub inv_d: [T; 3],
    /// the segment's start
    pub t_min: T,
    /// the segment's end
    pub t_max: T,
}

impl<T: Copy> Record<T> for SlabIn<T> {
    type Config = Format;
    fn walk<V: Visit<T>>(fmt: &Format, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(fmt.width());
        SlabIn {
            p_min: w.xyz("p_min", ty, |r| r.p_min),
            p_max: w.xyz("p_max", ty, |r| r.p_max),
            o: w.xyz("o", ty, |r| r.o),
            inv_d: w.xyz("inv_d", ty, |r| r.inv_d),
            t_min: w.one("t_min", ty, |r| r.t_min),
            t_max: w.one("t_max", ty, |r| r.t_max),
        }
    }
}

/// The data outputs: `hit t_enter t_exit`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlabOut<T> {
    /// `t_enter <= t_exit`
    pub hit: T,
    /// the largest entry parameter (and `t_min`)
    pub t_enter: T,
    /// the smallest exit parameter (and `t_max`)
    pub t_exit: T,
}

impl<T: Copy> Record<T> for SlabOut<T> {
    type Config = Format;
    fn walk<V: Visit<T>>(fmt: &Format, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(fmt.width());
        SlabOut {
            hit: w.one("hit", Ty::Bool, |r| r.hit),
            t_enter: w.one("t_enter", ty, |r| r.t_enter),
            t_exit: w.one("t_exit", ty, |r| r.t_exit),
        }
    }
}

/// The inputs of a per-axis block: the slab's planes, the origin and the
/// reciprocal direction on that axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlabAxisIn<T> {
    /// the lower plane
    pub p_min: T,
    /// the upper plane
    pub p_max: T,
    /// the origin
    pub o: T,
    /// the reciprocal direction
    pub inv_d: T,
}

impl<T: Copy> Record<T> for SlabAxisIn<T> {
    type Config = Format;
    fn walk<V: Visit<T>>(fmt: &Format, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = fmt.ty();
        SlabAxisIn {
            p_min: w.one("p_min", ty, |r| r.p_min),
            p_max: w.one("p_max", ty, |r| r.p_max),
            o: w.one("o", ty, |r| r.o),
            inv_d: w.one("inv_d", ty, |r| r.inv_d),
        }
    }
}

/// The outputs of a per-axis block: the slab's entry and exit parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlabAxisOut<T> {
    /// entry
    pub t_near: T,
    /// exit
    pub t_far: T,
}

impl<T: Copy> Record<T> for SlabAxisOut<T> {
    type Config = Format;
    fn walk<V: Visit<T>>(fmt: &Format, w: &mut Walk<'_, T, Self, V>) -> Self {
        SlabAxisOut {
            t_near: w.one("t_near", fmt.ty(), |r| r.t_near),
            t_far: w.one("t_far", fmt.ty(), |r| r.t_far),
        }
    }
}

/// Module name of the per-axis block.
pub fn slab_axis_name(fmt: Format, diff: u32, product: u32) -> String {
    format!("slab_axis_{}_d{diff}_p{product}", fmt.tag())
}

/// One axis: `near = minimum(t0, t1)`, `far = maximum(t0, t1)` with
/// `t0 = (p_min − o)·inv_d`, `t1 = (p_max − o)·inv_d` (RNE); `diff + product`
/// cycles of latency.
pub fn slab_axis_module(fmt: Format, diff: u32, product: u32) -> Arc<Module> {
    let mut m = ModuleBuilder::new(slab_axis_name(fmt, diff, product));
    m.describe(
        "One slab of the slab tester: t0 = (p_min - o) * inv_d, t1 = (p_max - o) * inv_d (RNE), \
         near = minimum(t0, t1), far = maximum(t0, t1).",
    );
    m.param("exp_bits", fmt.exp_bits)
        .param("frac_bits", fmt.frac_bits)
        .param("diff_stages", diff)
        .param("product_stages", product);
    let SlabAxisIn {
        p_min,
        p_max,
        o,
        inv_d,
    } = ports::declare_inputs(&mut m, &fmt);
    let sub = add_module(fmt, Rounding::Rne, true, diff);
    let mul = mul_module(fmt, Rounding::Rne, product);
    let u = rounded(&mut m, "u_sub_lo", &sub, &Pair::new(p_min, o));
    let v = rounded(&mut m, "u_sub_hi", &sub, &Pair::new(p_max, o));
    for _ in 0..diff {
        m.stage();
    }
    let t0 = rounded(&mut m, "u_mul_lo", &mul, &Pair::new(u, inv_d));
    let t1 = rounded(&mut m, "u_mul_hi", &mul, &Pair::new(v, inv_d));
    for _ in 0..product {
        m.stage();
    }
    let (t_near, t_far) = m.scope("t", |m| min_max(m, fmt, t0, t1));
    ports::declare_outputs(&mut m, &fmt, &SlabAxisOut { t_near, t_far });
    Arc::new(
        m.finish()
            .expect("slab axis generator is type-correct for every format"),
    )
}

/// Module name of the per-axis block of the conservative slab.
pub fn slab_axis_cons_name(fmt: Format, diff: u32, product: u32) -> String {
    format!("slab_axis_cons_{}_d{diff}_p{product}", fmt.tag())
}

/// `x` with its sign bit inverted when `flip` (a negation, NaN included).
#[track_caller]
fn negate_if(m: &mut ModuleBuilder, fmt: Format, x: Sig, flip: Sig) -> Sig {
    let w = fmt.width();
    let sign = m.msb(x);
    let sign = m.xor(sign, flip);
    let mag = m.slice(x, w - 2, 0);
    m.cat(&[sign, mag])
}

/// One axis of the conservative slab: mirrored by the sign of `inv_d`,
/// `u = RDN(lo − o)`, `v = RUP(hi − o)`, `near = RDN(u · r_u)`,
/// `far = RUP(v · r_v)` with `r_u`, `r_v` the ends of `|inv_d| ..
/// next_up(|inv_d|)` that keep each bound conservative; `inv_d = ±∞` gives
/// `near, far = −∞, +∞` if `lo ≤ o ≤ hi`, else `+∞, −∞`. Latency
/// `diff + product`; the select is combinational after the products.
pub fn slab_axis_cons_module(fmt: Format, diff: u32, product: u32) -> Arc<Module> {
    let mut m = ModuleBuilder::new(slab_axis_cons_name(fmt, diff, product));
    m.describe(
        "One slab of the conservative slab tester: mirrored by the sign of inv_d; \
         u = RDN(lo - o), v = RUP(hi - o); near = RDN(u * r_u), far = RUP(v * r_v) with r_u, r_v \
         the ends of |inv_d| .. next_up(|inv_d|) that keep the bounds conservative; \
         inv_d = +-inf (d = 0): near, far = -inf, +inf if lo <= o <= hi, else +inf, -inf.",
    );
    m.param("exp_bits", fmt.exp_bits)
        .param("frac_bits", fmt.frac_bits)
        .param("diff_stages", diff)
        .param("product_stages", product);
    let w = fmt.width();
    let SlabAxisIn {
        p_min,
        p_max,
        o,
        inv_d,
    } = ports::declare_inputs(&mut m, &fmt);

    // mirror so that the reciprocal is >= 0: lo = -p_max, hi = -p_min, o = -o
    let mirror = m.msb(inv_d);
    let mirror = m.name(mirror, "mirror");
    let lo = m.mux(mirror, p_max, p_min);
    let lo = negate_if(&mut m, fmt, lo, mirror);
    let lo = m.name(lo, "lo");
    let hi = m.mux(mirror, p_min, p_max);
    let hi = negate_if(&mut m, fmt, hi, mirror);
    let hi = m.name(hi, "hi");
    let om = negate_if(&mut m, fmt, o, mirror);
    let om = m.name(om, "o_mirrored");

    // the reciprocal interval r_lo = |inv_d| ..= r_hi = next_up(|inv_d|)
    let mag = m.slice(inv_d, w - 2, 0);
    let inf = m.uint(w - 1, fmt.inf_bits());
    let parallel = m.eq(mag, inf);
    let parallel = m.name(parallel, "parallel");
    let finite = m.lt(mag, inf);
    let one = m.uint(w - 1, 1);
    let up = m.add(mag, one);
    let up = m.slice(up, w - 2, 0);
    let hi_mag = m.mux(finite, up, mag);
    let plus = m.bool(false);
    let r_lo = m.cat(&[plus, mag]);
    let r_lo = m.name(r_lo, "r_lo");
    let r_hi = m.cat(&[plus, hi_mag]);
    let r_hi = m.name(r_hi, "r_hi");

    let sub_dn = add_module(fmt, Rounding::Rdn, true, diff);
    let sub_up = add_module(fmt, Rounding::Rup, true, diff);
    let u = rounded(&mut m, "u_sub_lo", &sub_dn, &Pair::new(lo, om));
    let v = rounded(&mut m, "u_sub_hi", &sub_up, &Pair::new(hi, om));
    for _ in 0..diff {
        m.stage();
    }
    let u = m.name(u, "u");
    let v = m.name(v, "v");
    let zero = m.uint(w, 0);
    let (u_neg, u_le0, _) = m.scope("u_sign", |m| compare(m, fmt, u, zero));
    let (v_pos, v_ge0, _) = m.scope("v_sign", |m| compare(m, fmt, zero, v));
    let r_u = m.mux(u_neg, r_hi, r_lo);
    let r_v = m.mux(v_pos, r_hi, r_lo);
    let inside = m.and(u_le0, v_ge0);
    let inside = m.name(inside, "in_slab");
    let mul_dn = mul_module(fmt, Rounding::Rdn, product);
    let mul_up = mul_module(fmt, Rounding::Rup, product);
    let t0 = rounded(&mut m, "u_mul_lo", &mul_dn, &Pair::new(u, r_u));
    let t1 = rounded(&mut m, "u_mul_hi", &mul_up, &Pair::new(v, r_v));
    for _ in 0..product {
        m.stage();
    }
    let pos_inf = m.uint(w, fmt.inf_bits());
    let neg_inf = m.uint(w, fmt.inf_bits() | 1u128 << (w - 1));
    let open_near = m.mux(inside, neg_inf, pos_inf);
    let open_far = m.mux(inside, pos_inf, neg_inf);
    let t_near = m.mux(parallel, open_near, t0);
    let t_far = m.mux(parallel, open_far, t1);
    ports::declare_outputs(&mut m, &fmt, &SlabAxisOut { t_near, t_far });
    Arc::new(
        m.finish()
            .expect("conservative slab axis generator is type-correct for every format"),
    )
}

/// Module name of the top: `slab_e8m23_s4` (nearest), `slab_e8m23_cons_s4`.
pub fn slab_name(fmt: Format, rounding: SlabRounding, stages: u32) -> String {
    match rounding {
        SlabRounding::Nearest => format!("slab_{}_s{stages}", fmt.tag()),
        SlabRounding::Conservative => format!("slab_{}_cons_s{stages}", fmt.tag()),
    }
}

/// Builds the slab tester for `fmt` with `rounding` and `stages` pipeline registers.
pub fn build(fmt: Format, rounding: SlabRounding, stages: u32) -> Module {
    let plan = StagePlan::new(stages);
    let mut m = ModuleBuilder::with_handshake(slab_name(fmt, rounding, stages));
    m.describe(match rounding {
        SlabRounding::Nearest => {
            "Classic slab ray/box tester (baseline): t = (p - o) * inv_d per plane, entry = max of \
             t_min and the near planes, exit = min of t_max and the far planes, hit = entry <= exit; \
             every operation RNE, min/max IEEE 754-2019 (NaN propagates)."
        }
        SlabRounding::Conservative => {
            "Conservative slab ray/box tester: inv_d = RTZ(1/d) widened to |inv_d| .. \
             next_up(|inv_d|), entry parameters rounded down and exit parameters up, a zero \
             direction component (inv_d = +-inf) tested as a parallel slab; entry = max of t_min \
             and the entries, exit = min of t_max and the exits, hit = entry <= exit. Never \
             misses a hit of the exact segment."
        }
    });
    let SlabIn {
        p_min,
        p_max,
        o,
        inv_d,
        t_min,
        t_max,
    } = ports::declare_inputs(&mut m, &fmt);

    let axis = match rounding {
        SlabRounding::Nearest => slab_axis_module(fmt, plan.diff, plan.product),
        SlabRounding::Conservative => slab_axis_cons_module(fmt, plan.diff, plan.product),
    };
    let mut near = Vec::new();
    let mut far = Vec::new();
    for i in 0..3 {
        let slab = SlabAxisIn {
            p_min: p_min[i],
            p_max: p_max[i],
            o: o[i],
            inv_d: inv_d[i],
        };
        let name = format!("u_slab_{}", AXES[i]);
        let out: SlabAxisOut<Sig> = ports::instance(&mut m, &name, &axis, &fmt, &slab, &fmt);
        near.push(out.t_near);
        far.push(out.t_far);
    }
    for _ in 0..plan.diff + plan.product + plan.min_max {
        m.stage();
    }
    // each min/max in the scope of what it reduces
    let max =
        |m: &mut ModuleBuilder, at: &str, a: Sig, b: Sig| m.scope(at, |m| min_max(m, fmt, a, b).1);
    let min =
        |m: &mut ModuleBuilder, at: &str, a: Sig, b: Sig| m.scope(at, |m| min_max(m, fmt, a, b).0);
    let e0 = max(&mut m, "enter_tx", t_min, near[0]);
    let e1 = max(&mut m, "enter_yz", near[1], near[2]);
    let t_enter = max(&mut m, "enter_all", e0, e1);
    let t_enter = m.name(t_enter, "t_enter");
    let x0 = min(&mut m, "exit_tx", t_max, far[0]);
    let x1 = min(&mut m, "exit_yz", far[1], far[2]);
    let t_exit = min(&mut m, "exit_all", x0, x1);
    let t_exit = m.name(t_exit, "t_exit");
    for _ in 0..plan.reduce {
        m.stage();
    }
    let hit = m.scope("order", |m| compare(m, fmt, t_enter, t_exit).1);
    let hit = m.name(hit, "hit");
    for _ in 0..plan.compare {
        m.stage();
    }
    let outputs = SlabOut {
        hit,
        t_enter,
        t_exit,
    };
    ports::declare_outputs(&mut m, &fmt, &outputs);
    m.finish()
        .expect("slab generator is type-correct for every format")
}

impl Description for Slab {
    type Params = SlabParams;
    type Config = Config;
    const NAME: &'static str = "slab";
    const SUMMARY: &'static str = "slab ray/box tester (baseline for silhouette): precomputed inv_d, RNE or conservative, hit/t_enter/t_exit";
    fn config(&self, p: &SlabParams) -> Result<Config, ParamError> {
        Ok(Config {
            fmt: Format::new(p.exp_bits, p.frac_bits).map_err(ParamError::Combination)?,
            rounding: p.rounding,
            stages: p.stages,
        })
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg.fmt, cfg.rounding, cfg.stages)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stage_plan_covers_every_register() {
        for s in 0..=32 {
            let p = StagePlan::new(s);
            assert_eq!(p.diff + p.product + p.min_max + p.reduce + p.compare, s);
        }
        assert_eq!(StagePlan::new(1).compare, 1);
    }
}
