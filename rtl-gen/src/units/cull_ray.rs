//! `cull_ray`: the cull-plane tester's per-ray unit (seed 001, issue #13).
//! Once per ray and BVH parent: for each of the parent's K shared normals
//! `n`, the ray terms that `cull` reads for every child: `no_lo ≤ n·(o −
//! r)` (ray format; `r` is the parent box's lower corner), the sign `dir` of
//! `b_lo ≤ n·d` and `rcp_lo ≤ 1/|b_lo| ≤ rcp_hi` (crossing format (E, Fp)).
//!
//! The specification is `docs/cull.md`, the bit-exact twin
//! `golden_model::cull::tester::ray_terms`; this generator performs its
//! steps with the DSL's float operators:
//!
//! 1. `u = o − r` per axis rounded down and up (one exact sum,
//!    [`add_down_up_module`]);
//! 2. per normal both dot products as lower bounds, each one fused operator
//!    ([`dot3_floor_module`]: three exact `(Fp + 1) × (F + 1)` significand
//!    products, truncated toward −∞ at the lsb of the product whose lsb
//!    weighs most, summed exactly, rounded down once): `no_lo` from `n` and
//!    the factor of `u` picked by the sign of `n_i` (ray format), `b_lo` from
//!    `n` and `d` (crossing format); the plane-format normal is never widened;
//! 3. `dir` from `b_lo` (0 parallel for ±0, 1 exit for a clear sign bit, 2
//!    entry), `rcp_lo = RDN(1/|b_lo|)`, `rcp_hi = RUP(1/|b_lo|)`
//!    (one division rounded both ways, [`recip_down_up_module`]; both +∞
//!    for `b_lo = 0`);
//! 4. a NaN or infinity in `o`, `d`, `r` or a normal (`invalid`) makes
//!    every `no_lo` the canonical NaN (so `cull` keeps).
//!
//! Pipelining: `stages` registers are spread ([`spread_over`]) over the steps
//! of the longer path, the crossing one: the difference (6), the dot product
//! (7), the reciprocal ([`recip_steps`]: its rounder's 3 and one per two of
//! its normalisation and Fc + 4 division steps). One register goes to the
//! outputs first. The latency is `stages`.

use super::cull::{config, Config, CullParams, CullRayIn, CullRayOut, Terms, DIR_WIDTH};
use super::ports;
use super::Description;
use crate::arith::float::add::ADD_RAW_STEPS;
use crate::arith::float::add_down_up::add_down_up_module;
use crate::arith::float::classify::{any_of, is_special, is_zero};
use crate::arith::float::dot3_floor::{
    dot3_floor_instance, dot3_floor_module, DOT3_FLOOR_RAW_STEPS,
};
use crate::arith::float::round::ROUND_STEPS;
use crate::arith::float::{spread_over, Format};
use crate::arith::ports::{call, DownUp, Operand, Pair};
use crate::arith::recip::{recip_down_up_module, recip_raw_steps};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::params::ParamError;

/// The `cull_ray` unit.
pub struct CullRay;

/// Logical steps of the difference `o − r`.
pub const DIFF_STEPS: u32 = ADD_RAW_STEPS + ROUND_STEPS;
/// Logical steps of a dot product.
pub const DOT_STEPS: u32 = DOT3_FLOOR_RAW_STEPS + ROUND_STEPS;

/// Logical steps the reciprocal in the crossing format `cf` counts for:
/// its rounder's, and one per two of its division steps (a division step,
/// one compare-and-subtract of Fc + 2 bits, is about half as deep as an
/// adder's step), so that [`spread_over`] balances the stages.
pub fn recip_steps(cf: Format) -> u32 {
    recip_raw_steps(cf).div_ceil(2) + ROUND_STEPS
}

/// How `cull_ray`'s `stages` registers are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StagePlan {
    /// inside the differences
    pub diff: u32,
    /// inside the dot products
    pub dot: u32,
    /// inside the reciprocals
    pub recip: u32,
}

impl StagePlan {
    /// The plan for `stages` registers over the steps of crossing format `cf`.
    pub fn new(stages: u32, cf: Format) -> StagePlan {
        let [diff, dot, recip] = spread_over(stages, [DIFF_STEPS, DOT_STEPS, recip_steps(cf)]);
        StagePlan { diff, dot, recip }
    }
}

/// Module name of `cull_ray`, e.g. `cull_ray_e8m23_pe5m10_k4_s4`.
pub fn cull_ray_name(cfg: &Config) -> String {
    format!("cull_ray_{}", cfg.tag())
}

/// Builds the per-ray unit.
pub fn build(cfg: &Config) -> Module {
    let (f, pf, cf) = (cfg.ray, cfg.plane, cfg.crossing());
    let k = cfg.k as usize;
    let plan = StagePlan::new(cfg.stages, cf);
    let mut m = ModuleBuilder::with_handshake(cull_ray_name(cfg));
    m.describe(
        "Cull-plane ray terms, per ray and BVH parent (docs/cull.md): for each shared normal n, \
         no_lo <= n.(o - r) (r the parent box's lower corner), the sign dir of b_lo <= n.d \
         (0 parallel, 1 exit, 2 entry) and rcp_lo <= 1/|b_lo| <= rcp_hi in the crossing format \
         (ray exponent, plane fraction + 8 guard bits, at most the ray fraction); a NaN or \
         infinite input makes every no_lo NaN.",
    );
    let CullRayIn { o, d, r, n } = ports::declare_inputs(&mut m, cfg);
    let ax = super::AXES;

    // Step 1: classify; u = o − r down and up.
    let mut bad: Vec<Sig> = o
        .iter()
        .chain(&d)
        .chain(&r)
        .map(|&v| is_special(&mut m, f, v))
        .collect();
    bad.extend(n.iter().flatten().map(|&v| is_special(&mut m, pf, v)));
    let invalid = any_of(&mut m, &bad, "invalid");
    let sb = m.uint(f.width(), 1u128 << (f.width() - 1));
    let adu = add_down_up_module(f, plan.diff);
    let mut u_dn = Vec::new();
    let mut u_up = Vec::new();
    for i in 0..3 {
        let neg_r = m.xor(r[i], sb);
        let name = format!("u_u_{}", ax[i]);
        let u: DownUp<Sig> = call(&mut m, &name, &adu, &Pair::new(o[i], neg_r), &f.ty());
        u_dn.push(u.down);
        u_up.push(u.up);
    }
    for _ in 0..plan.diff {
        m.stage();
    }

    // Step 2: the dot products as lower bounds, the factor of u picked by the sign of n_i.
    let dot_u = dot3_floor_module(pf, f, f, plan.dot);
    let dot_d = dot3_floor_module(pf, f, cf, plan.dot);
    let mut no_lo = Vec::new();
    let mut b_lo = Vec::new();
    for (j, nj) in n.iter().enumerate() {
        let u_lo = [0, 1, 2].map(|i| {
            let neg = m.msb(nj[i]);
            let uu = m.mux(neg, u_up[i], u_dn[i]);
            m.name(uu, &format!("u_lo_factor{j}_{}", ax[i]))
        });
        no_lo.push(dot3_floor_instance(
            &mut m,
            &dot_u,
            &format!("u_no_lo{j}"),
            *nj,
            u_lo,
        ));
        b_lo.push(dot3_floor_instance(
            &mut m,
            &dot_d,
            &format!("u_b_lo{j}"),
            *nj,
            d,
        ));
    }
    for _ in 0..plan.dot {
        m.stage();
    }

    // Step 3: the crossing's direction and reciprocals; invalid rays.
    let rcp = recip_down_up_module(cf, plan.recip);
    let abs_mask = m.uint(cf.width(), (1u128 << (cf.width() - 1)) - 1);
    let nan = m.uint(f.width(), f.nan_bits());
    let mut terms = Vec::new();
    for j in 0..k {
        let b = m.name(b_lo[j], &format!("b_lo{j}"));
        let mag = m.and(b, abs_mask);
        let r: DownUp<Sig> = call(
            &mut m,
            &format!("u_rcp{j}"),
            &rcp,
            &Operand { x: mag },
            &cf.ty(),
        );
        let bz = is_zero(&mut m, cf, b);
        let nbz = m.not(bz);
        let s = m.msb(b);
        let ns = m.not(s);
        let exit = m.and(nbz, ns);
        let entry = m.and(nbz, s);
        let exit = m.as_uint(exit);
        let entry = m.as_uint(entry);
        let dir = m.cat(&[entry, exit]);
        debug_assert_eq!(dir.width(), DIR_WIDTH);
        let nl = m.name(no_lo[j], &format!("no_lo_raw{j}"));
        let nl = m.mux(invalid, nan, nl);
        terms.push(Terms {
            no_lo: nl,
            rcp_lo: r.down,
            rcp_hi: r.up,
            dir,
        });
    }
    for _ in 0..plan.recip {
        m.stage();
    }
    ports::declare_outputs(&mut m, cfg, &CullRayOut { terms });
    m.finish()
        .expect("cull_ray generator is type-correct for every accepted configuration")
}

impl Description for CullRay {
    type Params = CullParams;
    type Config = Config;
    const NAME: &'static str = "cull_ray";
    const SUMMARY: &'static str = "cull-plane ray terms per ray and parent: no_lo, crossing direction and reciprocal bounds for K shared normals";
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

    #[test]
    fn stage_plan_covers_every_register() {
        let cf = Format::new(8, 10).unwrap();
        for s in 0..=64 {
            let p = StagePlan::new(s, cf);
            assert_eq!(p.diff + p.dot + p.recip, s);
        }
        assert_eq!(StagePlan::new(1, cf).recip, 1);
    }

    #[test]
    fn module_ports_follow_the_layout() {
        let c = Config {
            ray: Format::BINARY32,
            plane: Format::BINARY16,
            k: 3,
            stages: 4,
        };
        let m = build(&c);
        let ins: Vec<String> = m.data_inputs().iter().map(|p| p.name.clone()).collect();
        let mut want: Vec<String> = ["o", "d", "r", "n0", "n1", "n2"]
            .iter()
            .flat_map(|g| crate::units::AXES.map(|a| format!("{g}_{a}")))
            .collect();
        assert_eq!(ins, want);
        let outs: Vec<(String, u32)> = m
            .data_outputs()
            .iter()
            .map(|(p, _)| (p.name.clone(), p.ty.width()))
            .collect();
        want = (0..3)
            .flat_map(|j| ["no_lo", "rcp_lo", "rcp_hi", "dir"].map(|t| format!("{t}{j}")))
            .collect();
        let names: Vec<&String> = outs.iter().map(|(n, _)| n).collect();
        assert_eq!(names, want.iter().collect::<Vec<_>>());
        // ray format, crossing format (e8m18: plane fraction + 8 guard bits), 2-bit code
        let widths: Vec<u32> = outs[..4].iter().map(|(_, w)| *w).collect();
        assert_eq!(widths, [32, 27, 27, 2]);
        assert_eq!(m.name, "cull_ray_e8m23_pe5m10_k3_s4");
        assert_eq!(m.latency, 4);
    }
}
