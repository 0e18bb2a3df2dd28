//! `cull`: the cull-plane tester's per-child unit (seed 001, issue #13).
//! Once per child of a BVH node: the child's K plane distances `w`, the
//! parent's ray terms (from [`super::cull_ray`]) and the box interval
//! `[t_lo, t_hi]` of the conservative slab beside it give `keep` (the
//! segment may meet the part of the box on the non-empty side of every
//! plane) and `invalid` (then `keep = 1`).
//!
//! The specification is `docs/cull.md`, the bit-exact twin
//! `golden_model::cull::tester::eval`; this generator performs its steps
//! with the DSL's float operators:
//!
//! 1. `invalid` (a NaN anywhere, an infinite `w`, `no_lo = +∞`) and
//!    `planes_on = !(t_lo < 0)`;
//! 2. per plane (one `cull_plane_*` block each, [`plane_module`])
//!    `D = RUP(w − no_lo)` in the ray format (the adder's exact sum and the
//!    shared rounder), `w` widened exactly ([`widen`]: zero-padding,
//!    rebias, a subnormal of the plane format normalised);
//! 3. `q = RUP(D · rcp)`, `rcp = D > 0 ? rcp_hi : rcp_lo`, by the
//!    mixed-width multiply ([`mul_mixed_raw`]: a `(F + 1) × (Fc + 1)`
//!    significand product of the ray-format `D` and the crossing-format
//!    `rcp`, rounded into the ray format: the golden model's product of
//!    the widened `rcp`, bit for bit, without an `(F + 1)²` multiplier);
//! 4. the golden model folds exits `q` into `hi = min(t_hi, …)` and entries
//!    `−q` into `lo = max(t_lo, …)` by compare and select and asks
//!    `lo ≤ hi`. With no NaN left (a NaN `q` leaves its plane out, any
//!    other NaN is `invalid`) that is `l ≤ h` for every entry bound `l` and
//!    exit bound `h`, which this unit checks side by side (one comparison
//!    level instead of a chain of K): `t_lo ≤ t_hi`, `t_lo ≤ q_j` per exit,
//!    `−q_j ≤ t_hi` per entry, and one comparison `−q_i ≤ q_j` per pair of
//!    planes (it equals `−q_j ≤ q_i`, so it serves whichever is the exit).
//!    Comparisons are of order keys (the encoding with the magnitude
//!    complemented when negative; `−v` is the complement of `v`'s key) with
//!    both zeros equal, the IEEE `≤` the golden model uses. The planes off
//!    (`t_lo < 0`), every plane check passes and `t_lo ≤ t_hi` remains;
//! 5. `keep` = every check holds and no parallel plane has `D < 0`, or
//!    `invalid`.
//!
//! Pipelining: `stages` registers are spread ([`spread_over`]) over the 13
//! logical steps of [`PHASES`]; one register goes to the outputs first. The
//! latency is `stages`.
//!
//! Also here, shared with [`super::cull_ray`]: the parameters, the
//! configuration and the port layout of both units.

use super::ports::{self, Record, Visit, Walk};
use super::Description;
use crate::arith::float::add::{add_raw, ADD_RAW_STEPS};
use crate::arith::float::bits::add_const;
use crate::arith::float::classify::{
    all_of, any_of, is_nan, is_negative, is_positive, is_special, is_zero,
};
use crate::arith::float::convert::convert_module;
use crate::arith::float::mul::{mul_mixed_raw, MUL_RAW_STEPS};
use crate::arith::float::round::{round, ROUND_STEPS};
use crate::arith::float::unpack::{normalize, unpack};
use crate::arith::float::{spread_over, Format, Rounding};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;
use std::sync::Arc;

/// The `cull` unit.
pub struct Cull;

crate::params! {
    /// The parameters of `cull` and `cull_ray`.
    pub struct CullParams {
        /// ray/box format exponent bits E
        exp_bits: u32 [2..=9] = 8,
        /// ray/box format fraction bits F
        frac_bits: u32 [1..=25] = 23,
        /// plane format exponent bits Ep (<= E)
        plane_exp_bits: u32 [2..=9] = 5,
        /// plane format fraction bits Fp (<= F); the crossing format is (E, min(F, Fp + 8))
        plane_frac_bits: u32 [1..=25] = 10,
        /// planes (shared normals) per node
        k: u32 [1..=8] = 4,
        /// pipeline stages (latency in cycles), spread over the datapath's steps
        stages: u32 [0..=64] = 0,
    }
}

/// One configuration of `cull` / `cull_ray`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// ray and box format (E, F)
    pub ray: Format,
    /// plane format (Ep, Fp), Ep <= E, Fp <= F
    pub plane: Format,
    /// planes per node, 1..=8
    pub k: u32,
    /// pipeline registers (the latency)
    pub stages: u32,
}

/// One normal's ray terms: what `cull_ray` outputs and `cull` reads per
/// plane, in port order (`no_lo<j>`, `rcp_lo<j>`, `rcp_hi<j>`, `dir<j>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Terms<T> {
    /// `≤ n·(o − r)`, ray format (NaN: invalid ray or normal)
    pub no_lo: T,
    /// `≤ 1/|b_lo|`, crossing format
    pub rcp_lo: T,
    /// `≥ 1/|b_lo|`, crossing format
    pub rcp_hi: T,
    /// the sign of `b_lo` (`golden_model::cull::tester::Crossing::code`),
    /// [`DIR_WIDTH`] bits
    pub dir: T,
}

impl<T: Copy> Terms<T> {
    /// The ports of normal `j`'s terms; `of` reads them from a record.
    fn walk<R, V: Visit<T>>(
        cfg: &Config,
        j: usize,
        w: &mut Walk<'_, T, R, V>,
        of: impl Fn(&R) -> Terms<T> + Copy,
    ) -> Self {
        let ray = Ty::UInt(cfg.ray.width());
        let crossing = Ty::UInt(cfg.crossing().width());
        Terms {
            no_lo: w.one(format_args!("no_lo{j}"), ray, move |r| of(r).no_lo),
            rcp_lo: w.one(format_args!("rcp_lo{j}"), crossing, move |r| of(r).rcp_lo),
            rcp_hi: w.one(format_args!("rcp_hi{j}"), crossing, move |r| of(r).rcp_hi),
            dir: w.one(format_args!("dir{j}"), Ty::UInt(DIR_WIDTH), move |r| {
                of(r).dir
            }),
        }
    }
}

/// The `cull` data inputs: `t_lo`, `t_hi` (ray format), `w<j>` (plane
/// format) for every j, then per j the [`Terms`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CullIn<T> {
    /// the box interval's entry
    pub t_lo: T,
    /// the box interval's exit
    pub t_hi: T,
    /// the child's plane distances
    pub w: Vec<T>,
    /// the parent's ray terms, per normal
    pub terms: Vec<Terms<T>>,
}

impl<T: Copy> Record<T> for CullIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let k = cfg.k as usize;
        let ray = Ty::UInt(cfg.ray.width());
        let plane = Ty::UInt(cfg.plane.width());
        CullIn {
            t_lo: w.one("t_lo", ray, |r| r.t_lo),
            t_hi: w.one("t_hi", ray, |r| r.t_hi),
            w: (0..k)
                .map(|j| w.one(format_args!("w{j}"), plane, move |r| r.w[j]))
                .collect(),
            terms: (0..k)
                .map(|j| Terms::walk(cfg, j, w, move |r: &Self| r.terms[j]))
                .collect(),
        }
    }
}

/// The `cull` data outputs: `keep invalid`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CullOut<T> {
    /// the segment may meet the child's kept part (0 culls the child)
    pub keep: T,
    /// a NaN input, an infinite distance or `no_lo = +∞` (then `keep`)
    pub invalid: T,
}

impl<T: Copy> Record<T> for CullOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(_: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        CullOut {
            keep: w.one("keep", Ty::Bool, |r| r.keep),
            invalid: w.one("invalid", Ty::Bool, |r| r.invalid),
        }
    }
}

/// The `cull_ray` data inputs: `o_*`, `d_*`, `r_*` (ray format), then
/// `n<j>_*` (plane format).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CullRayIn<T> {
    /// the ray's origin
    pub o: [T; 3],
    /// the ray's direction
    pub d: [T; 3],
    /// the parent box's lower corner
    pub r: [T; 3],
    /// the shared normals
    pub n: Vec<[T; 3]>,
}

impl<T: Copy> Record<T> for CullRayIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ray = Ty::UInt(cfg.ray.width());
        let plane = Ty::UInt(cfg.plane.width());
        CullRayIn {
            o: w.xyz("o", ray, |r| r.o),
            d: w.xyz("d", ray, |r| r.d),
            r: w.xyz("r", ray, |r| r.r),
            n: (0..cfg.k as usize)
                .map(|j| w.xyz(format_args!("n{j}"), plane, move |r| r.n[j]))
                .collect(),
        }
    }
}

/// The `cull_ray` data outputs: per normal the [`Terms`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CullRayOut<T> {
    /// per normal
    pub terms: Vec<Terms<T>>,
}

impl<T: Copy> Record<T> for CullRayOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        CullRayOut {
            terms: (0..cfg.k as usize)
                .map(|j| Terms::walk(cfg, j, w, move |r: &Self| r.terms[j]))
                .collect(),
        }
    }
}

/// Width of the crossing code `dir<j>`.
pub const DIR_WIDTH: u32 = 2;
/// `dir` code: parallel (`b_lo = 0`; 3 reads as parallel too).
pub const DIR_PARALLEL: u128 = 0;
/// `dir` code: exit (`b_lo > 0`).
pub const DIR_EXIT: u128 = 1;
/// `dir` code: entry (`b_lo < 0`).
pub const DIR_ENTRY: u128 = 2;

/// Fraction bits the crossing format has beyond the plane format (at most
/// the ray format's): `golden_model::cull::tester::CROSSING_GUARD_BITS`,
/// checked by the flow.
pub const CROSSING_GUARD_BITS: u32 = 8;

impl Config {
    /// The crossing format `(E, min(F, Fp + CROSSING_GUARD_BITS))`: `b_lo`
    /// and the reciprocals.
    pub fn crossing(&self) -> Format {
        Format {
            exp_bits: self.ray.exp_bits,
            frac_bits: (self.plane.frac_bits + CROSSING_GUARD_BITS).min(self.ray.frac_bits),
        }
    }

    /// The name tag of both units, e.g. `e8m23_pe5m10_k4_s4`.
    pub fn tag(&self) -> String {
        format!(
            "{}_p{}_k{}_s{}",
            self.ray.tag(),
            self.plane.tag(),
            self.k,
            self.stages
        )
    }
}

/// The configuration of typed parameters, or why it cannot be built.
pub fn config(p: &CullParams) -> Result<Config, ParamError> {
    let ray = Format::new(p.exp_bits, p.frac_bits).map_err(ParamError::Combination)?;
    let plane =
        Format::new(p.plane_exp_bits, p.plane_frac_bits).map_err(ParamError::Combination)?;
    if plane.exp_bits > ray.exp_bits || plane.frac_bits > ray.frac_bits {
        return Err(ParamError::Combination(format!(
            "plane format {} (plane_exp_bits={}, plane_frac_bits={}) must not have more exponent \
             or fraction bits than the ray format {} (exp_bits={}, frac_bits={})",
            plane.tag(),
            plane.exp_bits,
            plane.frac_bits,
            ray.tag(),
            ray.exp_bits,
            ray.frac_bits
        )));
    }
    Ok(Config {
        ray,
        plane,
        k: p.k,
        stages: p.stages,
    })
}

mod child;

pub use child::{build, cull_name, plane_module, plane_name, widen, StagePlan, PHASES};

impl Description for Cull {
    type Params = CullParams;
    type Config = Config;
    const NAME: &'static str = "cull";
    const SUMMARY: &'static str = "cull-plane tester per child: box interval folded with K planes' crossings from the parent's ray terms (keep, invalid)";
    fn config(&self, p: &CullParams) -> Result<Config, ParamError> {
        config(p)
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(k: u32) -> Config {
        Config {
            ray: Format::BINARY32,
            plane: Format::BINARY16,
            k,
            stages: 4,
        }
    }

    #[test]
    fn stage_plan_covers_every_register_and_registers_outputs_first() {
        for s in 0..=64 {
            let p = StagePlan::new(s);
            assert_eq!(p.plane() + p.out, s);
        }
        assert_eq!(StagePlan::new(1).out, 1);
        // 4 stages: exact sum | its rounding | the product | its rounding and the verdict
        let p4 = StagePlan::new(4);
        let want = StagePlan {
            widen: 0,
            add_raw: [0, 0, 1],
            add_round: 1,
            mul_raw: 1,
            mul_round: 0,
            out: 1,
        };
        assert_eq!(p4, want);
    }

    /// Every encoding of the plane format through [`widen`] against the
    /// golden model's conversion (a NaN only has to stay a NaN): the
    /// normalising path, zero-padding alone, and the converter fallback.
    #[test]
    fn widen_is_the_exact_conversion() {
        use crate::eval::Evaluator;
        use crate::golden_twin::golden_format;
        use golden_model::float::{classify, convert, Class, RoundingMode};
        let f = |e, m| Format::new(e, m).unwrap();
        for (from, to) in [
            (f(5, 10), f(8, 23)),
            (f(4, 3), f(5, 10)),
            (f(5, 10), f(5, 23)),
            (f(2, 3), f(3, 5)),
        ] {
            let mut m = ModuleBuilder::new("widen_test");
            let a = m.input("a", Ty::UInt(from.width()));
            let z = widen(&mut m, from, to, a, "u_convert");
            m.output("z", z);
            let module = m.finish().unwrap();
            let mut ev = Evaluator::new(&module);
            let (gf, gt) = (golden_format(from), golden_format(to));
            for x in 0..1u64 << from.width() {
                let got = ev.eval(&[x as u128])[0] as u64;
                let want = convert(gf, gt, x, RoundingMode::NearestEven);
                if classify(gt, want) == Class::NaN {
                    assert_eq!(classify(gt, got), Class::NaN, "{from} -> {to}: {x:#x}");
                } else {
                    assert_eq!(got, want, "{from} -> {to}: {x:#x}");
                }
            }
        }
    }

    /// For every k, each record names every port once: 2 + 5k `cull`
    /// inputs ending in `dir<k-1>`, 9 + 3k `cull_ray` inputs, 4k outputs.
    #[test]
    fn records_name_every_port_once() {
        use crate::units::ports::list;
        for k in 1..=8 {
            let c = cfg(k);
            let k = k as usize;
            let names = |ports: Vec<(String, Ty)>| -> Vec<String> {
                let names: Vec<String> = ports.into_iter().map(|(n, _)| n).collect();
                let mut unique = names.clone();
                unique.sort();
                unique.dedup();
                assert_eq!(unique.len(), names.len(), "{names:?}");
                names
            };
            let child = names(list::<CullIn<()>>(&c));
            assert_eq!(child.len(), 2 + 5 * k);
            assert_eq!(child.last(), Some(&format!("dir{}", k - 1)));
            assert_eq!(names(list::<CullRayIn<()>>(&c)).len(), 9 + 3 * k);
            let outs = names(list::<CullRayOut<()>>(&c));
            assert_eq!(outs.len(), 4 * k);
            assert_eq!(outs.last(), Some(&format!("dir{}", k - 1)));
        }
    }

    #[test]
    fn module_ports_follow_the_layout() {
        let c = cfg(4);
        let m = build(&c);
        let names: Vec<(String, u32)> = m
            .data_inputs()
            .iter()
            .map(|p| (p.name.clone(), p.ty.width()))
            .collect();
        let mut want = vec![("t_lo".to_string(), 32), ("t_hi".to_string(), 32)];
        want.extend((0..4).map(|j| (format!("w{j}"), 16)));
        for j in 0..4 {
            want.extend(
                [("no_lo", 32), ("rcp_lo", 27), ("rcp_hi", 27), ("dir", 2)]
                    .map(|(t, w)| (format!("{t}{j}"), w)),
            );
        }
        assert_eq!(names, want);
        assert_eq!(m.name, "cull_e8m23_pe5m10_k4_s4");
        assert_eq!(m.latency, 4);
    }
}
