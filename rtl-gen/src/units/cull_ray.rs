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
//!    [`add_down_up_module`]); `d` rounded down and up into the crossing
//!    format ([`convert_module`]; nothing when Fc = F);
//! 2. per normal and axis the products `n_i·u_i` (ray format) and `n_i·d_i`
//!    (crossing format), rounded down, the factor picked by the sign of
//!    `n_i`, by the mixed-width multiplier ([`mul_mixed_module`]: the
//!    plane-format normal is never widened, its `(Fp + 1)`-bit significand
//!    meets the other factor's directly; the rounding equals the golden
//!    model's product of the widened normal); a zero `n_i` gives +0;
//! 3. both three-term sums, left to right, rounded down ([`add_module`]);
//! 4. `dir` from `b_lo` (0 parallel for ±0, 1 exit for a clear sign bit, 2
//!    entry), `rcp_lo = RDN(1/|b_lo|)`, `rcp_hi = RUP(1/|b_lo|)`
//!    (one division rounded both ways, [`recip_down_up_module`]; both +∞
//!    for `b_lo = 0`);
//! 5. a NaN or infinity in `o`, `d`, `r` or a normal (`invalid`) makes
//!    every `no_lo` the canonical NaN (so `cull` keeps).
//!
//! Pipelining: `stages` registers are spread ([`spread`]) over the steps
//! of the longer path, the crossing one: the difference (6), the products
//! (5), two sums (6 each), the reciprocal ([`recip_steps`]: its rounder's 3
//! and one per two of its normalisation and Fc + 4 division steps). One
//! register goes to the outputs first. The latency is `stages`.

use super::cull::{any_of, config, is_special, is_zero, Config, TermField, DIR_WIDTH, PARAMS};
use super::Unit;
use crate::arith::float::add::{add_module, ADD_RAW_STEPS};
use crate::arith::float::add_down_up::add_down_up_module;
use crate::arith::float::convert::convert_module;
use crate::arith::float::mul::{mul_mixed_module, MUL_RAW_STEPS};
use crate::arith::float::round::ROUND_STEPS;
use crate::arith::float::{spread, Format, Rounding};
use crate::arith::recip::{recip_down_up_module, recip_raw_steps};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::{ParamError, ParamSpec, Params};

/// The `cull_ray` unit.
pub struct CullRay;

/// Logical steps of the difference `o − r` (and the conversions of `d`).
pub const DIFF_STEPS: u32 = ADD_RAW_STEPS + ROUND_STEPS;
/// Logical steps of the products.
pub const PROD_STEPS: u32 = MUL_RAW_STEPS + ROUND_STEPS;
/// Logical steps of one sum.
pub const SUM_STEPS: u32 = ADD_RAW_STEPS + ROUND_STEPS;

/// Logical steps the reciprocal in the crossing format `cf` counts for:
/// its rounder's, and one per two of its division steps (a division step,
/// one compare-and-subtract of Fc + 2 bits, is about half as deep as an
/// adder's step), so that [`spread`] balances the stages.
pub fn recip_steps(cf: Format) -> u32 {
    recip_raw_steps(cf).div_ceil(2) + ROUND_STEPS
}

/// How `cull_ray`'s `stages` registers are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StagePlan {
    /// inside the differences and conversions
    pub diff: u32,
    /// inside the multipliers
    pub prod: u32,
    /// inside the first adders
    pub sum1: u32,
    /// inside the second adders
    pub sum2: u32,
    /// inside the reciprocals
    pub recip: u32,
}

impl StagePlan {
    /// The plan for `stages` registers over the steps of crossing format `cf`.
    pub fn new(stages: u32, cf: Format) -> StagePlan {
        let segs = [
            DIFF_STEPS,
            PROD_STEPS,
            SUM_STEPS,
            SUM_STEPS,
            recip_steps(cf),
        ];
        let c = spread(stages, segs.iter().sum());
        let mut at = 0usize;
        let sums: Vec<u32> = segs
            .iter()
            .map(|&n| {
                let s = c[at..at + n as usize].iter().sum();
                at += n as usize;
                s
            })
            .collect();
        StagePlan {
            diff: sums[0],
            prod: sums[1],
            sum1: sums[2],
            sum2: sums[3],
            recip: sums[4],
        }
    }
}

/// Module name of `cull_ray`, e.g. `cull_ray_e8m23_pe5m10_k4_s4`.
pub fn cull_ray_name(cfg: &Config) -> String {
    format!("cull_ray_{}", cfg.tag())
}

fn z(
    m: &mut ModuleBuilder,
    inst: &str,
    module: &std::sync::Arc<Module>,
    ins: &[(&str, Sig)],
) -> Sig {
    m.instance(inst, module, ins)
        .get("z")
        .expect("operator has output z")
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
    cfg.describe_params(&mut m);
    let ports: Vec<Sig> = cfg
        .ray_inputs()
        .iter()
        .map(|(name, w)| m.input(name, Ty::UInt(*w)))
        .collect();
    let o: Vec<Sig> = (0..3).map(|i| ports[cfg.ray_o(i)]).collect();
    let d: Vec<Sig> = (0..3).map(|i| ports[cfg.ray_d(i)]).collect();
    let r: Vec<Sig> = (0..3).map(|i| ports[cfg.ray_r(i)]).collect();
    let n: Vec<[Sig; 3]> = (0..k)
        .map(|j| [0, 1, 2].map(|i| ports[cfg.ray_n(j, i)]))
        .collect();
    let ax = super::cull::AXES;

    // Step 1: classify; u = o − r down and up; d down and up in the crossing format.
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
    let narrow = (cf != f).then(|| {
        (
            convert_module(f, cf, Rounding::Rdn, plan.diff),
            convert_module(f, cf, Rounding::Rup, plan.diff),
        )
    });
    let mut u_dn = Vec::new();
    let mut u_up = Vec::new();
    let mut d_dn = Vec::new();
    let mut d_up = Vec::new();
    for i in 0..3 {
        let neg_r = m.xor(r[i], sb);
        let u = m.instance(
            &format!("u_u_{}", ax[i]),
            &adu,
            &[("a", o[i]), ("b", neg_r)],
        );
        u_dn.push(u.get("down").expect("down"));
        u_up.push(u.get("up").expect("up"));
        match &narrow {
            Some((dn, up)) => {
                d_dn.push(z(&mut m, &format!("u_d_lo_{}", ax[i]), dn, &[("a", d[i])]));
                d_up.push(z(&mut m, &format!("u_d_hi_{}", ax[i]), up, &[("a", d[i])]));
            }
            None => {
                d_dn.push(d[i]);
                d_up.push(d[i]);
            }
        }
    }
    for _ in 0..plan.diff {
        m.stage();
    }

    // Step 2: the products, the factor picked by the sign of n_i.
    let mul_u = mul_mixed_module(pf, f, f, Rounding::Rdn, plan.prod);
    let mul_d = mul_mixed_module(pf, cf, cf, Rounding::Rdn, plan.prod);
    let mut no_p: Vec<[Sig; 3]> = Vec::new();
    let mut b_p: Vec<[Sig; 3]> = Vec::new();
    let mut n_zero: Vec<[Sig; 3]> = Vec::new();
    for j in 0..k {
        let mut np = [sb; 3];
        let mut bp = [sb; 3];
        let mut nz = [sb; 3];
        for i in 0..3 {
            let v = n[j][i];
            let neg = m.msb(v);
            let uu = m.mux(neg, u_up[i], u_dn[i]);
            let dd = m.mux(neg, d_up[i], d_dn[i]);
            np[i] = z(
                &mut m,
                &format!("u_nu{j}_{}", ax[i]),
                &mul_u,
                &[("a", v), ("b", uu)],
            );
            bp[i] = z(
                &mut m,
                &format!("u_nd{j}_{}", ax[i]),
                &mul_d,
                &[("a", v), ("b", dd)],
            );
            nz[i] = is_zero(&mut m, pf, v);
        }
        no_p.push(np);
        b_p.push(bp);
        n_zero.push(nz);
    }
    for _ in 0..plan.prod {
        m.stage();
    }

    // Step 3: zero guards; the sums, left to right, rounded down.
    let add_f = add_module(f, Rounding::Rdn, false, plan.sum1);
    let add_c = add_module(cf, Rounding::Rdn, false, plan.sum1);
    let zero_f = m.uint(f.width(), 0);
    let zero_c = m.uint(cf.width(), 0);
    let mut no01 = Vec::new();
    let mut b01 = Vec::new();
    for j in 0..k {
        for i in 0..3 {
            no_p[j][i] = m.mux(n_zero[j][i], zero_f, no_p[j][i]);
            no_p[j][i] = m.name(no_p[j][i], &format!("no_p{j}_{}", ax[i]));
            b_p[j][i] = m.mux(n_zero[j][i], zero_c, b_p[j][i]);
            b_p[j][i] = m.name(b_p[j][i], &format!("b_p{j}_{}", ax[i]));
        }
        no01.push(z(
            &mut m,
            &format!("u_no01_{j}"),
            &add_f,
            &[("a", no_p[j][0]), ("b", no_p[j][1])],
        ));
        b01.push(z(
            &mut m,
            &format!("u_b01_{j}"),
            &add_c,
            &[("a", b_p[j][0]), ("b", b_p[j][1])],
        ));
    }
    for _ in 0..plan.sum1 {
        m.stage();
    }
    let add_f = add_module(f, Rounding::Rdn, false, plan.sum2);
    let add_c = add_module(cf, Rounding::Rdn, false, plan.sum2);
    let mut no_lo = Vec::new();
    let mut b_lo = Vec::new();
    for j in 0..k {
        let s = z(
            &mut m,
            &format!("u_no_lo{j}"),
            &add_f,
            &[("a", no01[j]), ("b", no_p[j][2])],
        );
        no_lo.push(s);
        let s = z(
            &mut m,
            &format!("u_b_lo{j}"),
            &add_c,
            &[("a", b01[j]), ("b", b_p[j][2])],
        );
        b_lo.push(s);
    }
    for _ in 0..plan.sum2 {
        m.stage();
    }

    // Step 4: the crossing's direction and reciprocals; invalid rays.
    let rcp = recip_down_up_module(cf, plan.recip);
    let abs_mask = m.uint(cf.width(), (1u128 << (cf.width() - 1)) - 1);
    let nan = m.uint(f.width(), f.nan_bits());
    let mut outs: Vec<(TermField, usize, Sig)> = Vec::new();
    for j in 0..k {
        let b = m.name(b_lo[j], &format!("b_lo{j}"));
        let mag = m.and(b, abs_mask);
        let r = m.instance(&format!("u_rcp{j}"), &rcp, &[("x", mag)]);
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
        outs.push((TermField::NoLo, j, nl));
        outs.push((TermField::RcpLo, j, r.get("down").expect("down")));
        outs.push((TermField::RcpHi, j, r.get("up").expect("up")));
        outs.push((TermField::Dir, j, dir));
    }
    for _ in 0..plan.recip {
        m.stage();
    }
    for (t, j, v) in outs {
        m.output(&t.port(j), v);
    }
    m.finish()
        .expect("cull_ray generator is type-correct for every accepted configuration")
}

impl Unit for CullRay {
    fn name(&self) -> &'static str {
        "cull_ray"
    }
    fn summary(&self) -> &'static str {
        "cull-plane ray terms per ray and parent: no_lo, crossing direction and reciprocal bounds for K shared normals"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        Ok(build(&config(p)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stage_plan_covers_every_register() {
        let cf = Format::new(8, 10).unwrap();
        for s in 0..=16 {
            let p = StagePlan::new(s, cf);
            assert_eq!(p.diff + p.prod + p.sum1 + p.sum2 + p.recip, s);
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
        let ins: Vec<(String, u32)> = m
            .data_inputs()
            .iter()
            .map(|p| (p.name.clone(), p.ty.width()))
            .collect();
        assert_eq!(ins, c.ray_inputs());
        let outs: Vec<(String, u32)> = m
            .data_outputs()
            .iter()
            .map(|(p, _)| (p.name.clone(), p.ty.width()))
            .collect();
        assert_eq!(outs, c.ray_outputs());
        assert_eq!(m.name, "cull_ray_e8m23_pe5m10_k3_s4");
        assert_eq!(m.latency, 4);
    }
}
