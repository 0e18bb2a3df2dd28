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

use super::{port_at, port_at3, Description};
use crate::arith::float::add::{add_raw, ADD_RAW_STEPS};
use crate::arith::float::bits::add_const;
use crate::arith::float::classify::{all_of, any_of, is_nan, is_special, is_zero};
use crate::arith::float::convert::convert_module;
use crate::arith::float::mul::{mul_mixed_raw, MUL_RAW_STEPS};
use crate::arith::float::round::{round, ROUND_STEPS};
use crate::arith::float::unpack::{normalize, unpack};
use crate::arith::float::{spread_over, Format, Rounding};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::{ParamError, ParamKind, ParamSpec, Params};
use std::sync::Arc;

/// The `cull` unit.
pub struct Cull;

/// The parameters of `cull` and `cull_ray`.
pub const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        name: "exp_bits",
        doc: "ray/box format exponent bits E",
        kind: ParamKind::Int { min: 2, max: 9 },
        default: "8",
    },
    ParamSpec {
        name: "frac_bits",
        doc: "ray/box format fraction bits F",
        kind: ParamKind::Int { min: 1, max: 25 },
        default: "23",
    },
    ParamSpec {
        name: "plane_exp_bits",
        doc: "plane format exponent bits Ep (<= E)",
        kind: ParamKind::Int { min: 2, max: 9 },
        default: "5",
    },
    ParamSpec {
        name: "plane_frac_bits",
        doc: "plane format fraction bits Fp (<= F); the crossing format is (E, min(F, Fp + 8))",
        kind: ParamKind::Int { min: 1, max: 25 },
        default: "10",
    },
    ParamSpec {
        name: "k",
        doc: "planes (shared normals) per node",
        kind: ParamKind::Int { min: 1, max: 8 },
        default: "4",
    },
    ParamSpec {
        name: "stages",
        doc: "pipeline stages (latency in cycles), spread over the datapath's steps",
        kind: ParamKind::Int { min: 0, max: 64 },
        default: "0",
    },
];

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

/// The fields of one normal's ray terms: what `cull_ray` outputs and `cull`
/// reads per plane, in port order (`no_lo<j>`, `rcp_lo<j>`, `rcp_hi<j>`, `dir<j>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TermField {
    /// `≤ n·(o − r)`, ray format (NaN: invalid ray or normal)
    NoLo = 0,
    /// `≤ 1/|b_lo|`, crossing format
    RcpLo = 1,
    /// `≥ 1/|b_lo|`, crossing format
    RcpHi = 2,
    /// the sign of `b_lo` (`golden_model::cull::tester::Crossing::code`), UInt(2)
    Dir = 3,
}

impl TermField {
    /// Every field, in port order.
    pub const ALL: [TermField; 4] = [
        TermField::NoLo,
        TermField::RcpLo,
        TermField::RcpHi,
        TermField::Dir,
    ];

    /// The port name of this field of normal `j`.
    pub fn port(self, j: usize) -> String {
        let base = match self {
            TermField::NoLo => "no_lo",
            TermField::RcpLo => "rcp_lo",
            TermField::RcpHi => "rcp_hi",
            TermField::Dir => "dir",
        };
        format!("{base}{j}")
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

/// The axis suffixes of vector ports.
pub const AXES: [&str; 3] = ["x", "y", "z"];

/// Fraction bits the crossing format has beyond the plane format (at most
/// the ray format's): `golden_model::cull::tester::CROSSING_GUARD_BITS`,
/// checked by the flow.
pub const CROSSING_GUARD_BITS: u32 = 8;

/// The `cull` data outputs in port order.
pub const CHILD_OUTPUT_NAMES: [&str; 2] = ["keep", "invalid"];

/// The positions of the `cull` unit's inputs, looked up by name (see
/// [`Config::child_ports`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChildPorts {
    /// the box interval's entry `t_lo`
    pub t_lo: usize,
    /// the box interval's exit `t_hi`
    pub t_hi: usize,
    /// `w<j>`
    pub w: Vec<usize>,
    /// per normal, each [`TermField`]'s input
    pub terms: Vec<[usize; 4]>,
}

/// The positions of the `cull_ray` unit's inputs and outputs, looked up by
/// name (see [`Config::ray_ports`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RayPorts {
    /// origin `o_*`
    pub o: [usize; 3],
    /// direction `d_*`
    pub d: [usize; 3],
    /// the parent box's lower corner `r_*`
    pub r: [usize; 3],
    /// `n<j>_*`
    pub n: Vec<[usize; 3]>,
    /// per normal, each [`TermField`]'s output
    pub terms: Vec<[usize; 4]>,
}

impl ChildPorts {
    /// The input of field `t` of plane `j`.
    pub fn term(&self, j: usize, t: TermField) -> usize {
        self.terms[j][t as usize]
    }
}

impl RayPorts {
    /// The output of field `t` of normal `j`.
    pub fn term(&self, j: usize, t: TermField) -> usize {
        self.terms[j][t as usize]
    }
}

fn port_names(ports: &[(String, u32)]) -> Vec<String> {
    ports.iter().map(|(n, _)| n.clone()).collect()
}

/// Per normal `j < k`, the positions of its [`TermField`] ports.
fn term_ports(names: &[String], k: usize) -> Vec<[usize; 4]> {
    (0..k)
        .map(|j| TermField::ALL.map(|t| port_at(names, &t.port(j))))
        .collect()
}

impl Config {
    /// The crossing format `(E, min(F, Fp + CROSSING_GUARD_BITS))`: `b_lo`
    /// and the reciprocals.
    pub fn crossing(&self) -> Format {
        Format {
            exp_bits: self.ray.exp_bits,
            frac_bits: (self.plane.frac_bits + CROSSING_GUARD_BITS).min(self.ray.frac_bits),
        }
    }

    /// The width of field `t`.
    pub fn term_width(&self, t: TermField) -> u32 {
        match t {
            TermField::NoLo => self.ray.width(),
            TermField::RcpLo | TermField::RcpHi => self.crossing().width(),
            TermField::Dir => DIR_WIDTH,
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

    /// Records the parameters in the module header.
    pub(super) fn describe_params(&self, m: &mut ModuleBuilder) {
        m.param("exp_bits", self.ray.exp_bits)
            .param("frac_bits", self.ray.frac_bits)
            .param("plane_exp_bits", self.plane.exp_bits)
            .param("plane_frac_bits", self.plane.frac_bits)
            .param("k", self.k)
            .param("stages", self.stages);
    }

    /// The `cull` data inputs (name, width), in port order: `t_lo`, `t_hi`,
    /// `w<j>` for every j, then per j the [`TermField`]s.
    pub fn child_inputs(&self) -> Vec<(String, u32)> {
        let k = self.k as usize;
        let mut v = vec![
            ("t_lo".to_string(), self.ray.width()),
            ("t_hi".to_string(), self.ray.width()),
        ];
        v.extend((0..k).map(|j| (format!("w{j}"), self.plane.width())));
        for j in 0..k {
            v.extend(TermField::ALL.map(|t| (t.port(j), self.term_width(t))));
        }
        v
    }

    /// The `cull_ray` data inputs (name, width), in port order: `o_*`,
    /// `d_*`, `r_*` (ray format), then `n<j>_*` (plane format).
    pub fn ray_inputs(&self) -> Vec<(String, u32)> {
        let mut v = Vec::new();
        for p in ["o", "d", "r"] {
            v.extend(AXES.map(|a| (format!("{p}_{a}"), self.ray.width())));
        }
        for j in 0..self.k as usize {
            v.extend(AXES.map(|a| (format!("n{j}_{a}"), self.plane.width())));
        }
        v
    }

    /// The `cull_ray` data outputs (name, width), in port order: per
    /// normal the [`TermField`]s.
    pub fn ray_outputs(&self) -> Vec<(String, u32)> {
        (0..self.k as usize)
            .flat_map(|j| TermField::ALL.map(|t| (t.port(j), self.term_width(t))))
            .collect()
    }

    /// Where each `cull` input is among [`Config::child_inputs`], by name.
    pub fn child_ports(&self) -> ChildPorts {
        let names = port_names(&self.child_inputs());
        let k = self.k as usize;
        ChildPorts {
            t_lo: port_at(&names, "t_lo"),
            t_hi: port_at(&names, "t_hi"),
            w: (0..k).map(|j| port_at(&names, &format!("w{j}"))).collect(),
            terms: term_ports(&names, k),
        }
    }

    /// Where each `cull_ray` input is among [`Config::ray_inputs`] and each
    /// output among [`Config::ray_outputs`], by name.
    pub fn ray_ports(&self) -> RayPorts {
        let names = port_names(&self.ray_inputs());
        let k = self.k as usize;
        RayPorts {
            o: port_at3(&names, "o"),
            d: port_at3(&names, "d"),
            r: port_at3(&names, "r"),
            n: (0..k).map(|j| port_at3(&names, &format!("n{j}"))).collect(),
            terms: term_ports(&port_names(&self.ray_outputs()), k),
        }
    }
}

/// The configuration of resolved parameters, or why it cannot be built.
pub fn config(p: &Params) -> Result<Config, ParamError> {
    let ray =
        Format::new(p.u32("exp_bits"), p.u32("frac_bits")).map_err(ParamError::Combination)?;
    let plane = Format::new(p.u32("plane_exp_bits"), p.u32("plane_frac_bits"))
        .map_err(ParamError::Combination)?;
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
        k: p.u32("k"),
        stages: p.u32("stages"),
    })
}

/// `x` of `from` widened exactly into `to` (`from`'s exponent and fraction
/// no wider than `to`'s). Equal exponent widths: the fraction padded with
/// zeros. Otherwise the exponent is rebiased and a subnormal of `from`
/// normalised (a leading-zero count over Fp + 1 bits), or, where a
/// subnormal of `from` can stay subnormal in `to`, the converter
/// (`inst`). Infinities and zeros keep their sign; a NaN stays a NaN (its
/// payload padded, not made canonical).
#[track_caller]
pub fn widen(m: &mut ModuleBuilder, from: Format, to: Format, x: Sig, inst: &str) -> Sig {
    assert!(from.exp_bits <= to.exp_bits && from.frac_bits <= to.frac_bits);
    let pad = to.frac_bits - from.frac_bits;
    let pad_frac = |m: &mut ModuleBuilder, v: Sig| -> Sig {
        if pad == 0 {
            v
        } else {
            let z = m.uint(pad, 0);
            m.cat(&[v, z])
        }
    };
    if from.exp_bits == to.exp_bits {
        return pad_frac(m, x);
    }
    if from.emin() - (from.frac_bits as i64) < to.emin() {
        let cv = convert_module(from, to, Rounding::Rne, 0);
        return m.instance(inst, &cv, &[("a", x)]).get("z").expect("z");
    }
    let (e, f) = (to.exp_bits, from.frac_bits);
    let u = unpack(m, from, x);
    let n = normalize(m, from, &u);
    let exp = add_const(m, n.exp, to.bias(), e + 2);
    let exp = m.slice(exp, e - 1, 0);
    let frac = m.slice(n.sig, f - 1, 0);
    let frac = pad_frac(m, frac);
    let ones = m.uint(e, to.exp_ones());
    let zero_e = m.uint(e, 0);
    let special = m.or(u.inf, u.nan);
    let exp = m.mux(special, ones, exp);
    let exp = m.mux(u.zero, zero_e, exp);
    let raw_frac = pad_frac(m, u.frac);
    let frac = m.mux(special, raw_frac, frac);
    let sign = m.as_uint(u.sign);
    let v = m.cat(&[sign, exp, frac]);
    m.name(v, "widened")
}

/// `v < 0` (false for NaN and both zeros).
#[track_caller]
fn is_neg(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let s = m.msb(v);
    let z = is_zero(m, fmt, v);
    let nz = m.not(z);
    let nan = is_nan(m, fmt, v);
    let ok = m.not(nan);
    let r = m.and(s, nz);
    m.and(r, ok)
}

/// `0 < v` (false for NaN and both zeros).
#[track_caller]
fn is_pos(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let s = m.msb(v);
    let ns = m.not(s);
    let z = is_zero(m, fmt, v);
    let nz = m.not(z);
    let nan = is_nan(m, fmt, v);
    let ok = m.not(nan);
    let r = m.and(ns, nz);
    m.and(r, ok)
}

/// `!cond | invalid`: a check that does not apply.
#[track_caller]
fn unless(m: &mut ModuleBuilder, cond: Sig, invalid: Sig) -> Sig {
    let nc = m.not(cond);
    m.or(nc, invalid)
}

/// A non-NaN bound of the interval for comparisons: its order key (an
/// unsigned integer of the encoding's width whose order is the order of
/// the values, except that −0 sits just below +0:
/// `{!sign, sign ? !magnitude : magnitude}`) and whether it is ±0.
#[derive(Debug, Clone, Copy)]
struct Bound {
    key: Sig,
    zero: Sig,
}

impl Bound {
    #[track_caller]
    fn of(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Bound {
        let w = fmt.width();
        let s = m.msb(v);
        let mag = m.slice(v, w - 2, 0);
        let flipped = m.not(mag);
        let low = m.mux(s, flipped, mag);
        let ns = m.not(s);
        let top = m.as_uint(ns);
        Bound {
            key: m.cat(&[top, low]),
            zero: is_zero(m, fmt, v),
        }
    }

    /// The bound of `−v`: the key complemented.
    #[track_caller]
    fn negated(&self, m: &mut ModuleBuilder) -> Bound {
        Bound {
            key: m.not(self.key),
            zero: self.zero,
        }
    }

    /// IEEE `self <= other` (one unsigned comparison of the keys, the two
    /// zeros equal), or `pass`.
    #[track_caller]
    fn le(&self, m: &mut ModuleBuilder, other: &Bound, pass: Sig, name: &str) -> Sig {
        let le = m.le(self.key, other.key);
        let zeros = m.and(self.zero, other.zero);
        let early = m.or(zeros, pass);
        let r = m.or(le, early);
        m.name(r, name)
    }
}

/// The logical steps of `cull`: the widening of `w`; the adder's exact sum
/// ([`ADD_RAW_STEPS`]) and its rounder ([`ROUND_STEPS`]); the pick of the
/// reciprocal with the multiplier's unpacking, then its significand
/// product ([`MUL_RAW_STEPS`]); the product's rounder, whose last step also
/// holds the comparisons and the verdict. The steps are of about equal
/// logic depth, so [`spread_over`] balances the stages (at 4: the widening and
/// exact sum | the sum's rounding | the product | its rounding and the
/// comparisons). Per phase, in the order of [`StagePlan`]'s fields: the
/// widening, each of the exact sum's steps (its registers are placed per
/// step), the sum's rounder, the pick and the product, the product's rounder
/// but its last step, and that step (the outputs).
pub const PHASES: [u32; 8] = [
    1,
    1,
    1,
    1,
    ROUND_STEPS,
    1 + MUL_RAW_STEPS,
    ROUND_STEPS - 1,
    1,
];

/// How `cull`'s `stages` registers are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StagePlan {
    /// after the widening of `w`
    pub widen: u32,
    /// after each step of the exact sum `w − no_lo`
    pub add_raw: [u32; ADD_RAW_STEPS as usize],
    /// inside the sum's rounder
    pub add_round: u32,
    /// inside the significand multiplier
    pub mul_raw: u32,
    /// inside the product's rounder
    pub mul_round: u32,
    /// after the verdict (the outputs)
    pub out: u32,
}

impl StagePlan {
    /// The plan for `stages` registers ([`spread_over`] the [`PHASES`]).
    pub fn new(stages: u32) -> StagePlan {
        let [widen, add_0, add_1, add_2, add_round, mul_raw, mul_round, out] =
            spread_over(stages, PHASES);
        StagePlan {
            widen,
            add_raw: [add_0, add_1, add_2],
            add_round,
            mul_raw,
            mul_round,
            out,
        }
    }

    /// Registers inside the per-plane block.
    pub fn plane(&self) -> u32 {
        self.widen
            + self.add_raw.iter().sum::<u32>()
            + self.add_round
            + self.mul_raw
            + self.mul_round
    }

    /// The tag of the per-plane block's name, e.g. `w0a001r1m1p0`.
    fn tag(&self) -> String {
        let a: String = self.add_raw.iter().map(|c| c.to_string()).collect();
        format!(
            "w{}a{a}r{}m{}p{}",
            self.widen, self.add_round, self.mul_raw, self.mul_round
        )
    }
}

/// Module name of the per-plane block.
pub fn plane_name(cfg: &Config, plan: &StagePlan) -> String {
    format!(
        "cull_plane_{}_p{}_{}",
        cfg.ray.tag(),
        cfg.plane.tag(),
        plan.tag()
    )
}

/// The per-plane block: `D = RUP(w − no_lo)` with `w` widened exactly,
/// `rcp = D > 0 ? rcp_hi : rcp_lo`, `q = RUP(D · rcp)` (the exact product
/// of a ray-format and a crossing-format significand, one rounding).
/// Inputs `w` (plane format), `no_lo` (ray), `rcp_lo`, `rcp_hi`
/// (crossing); outputs `q` and `dist_neg` (`D < 0`), [`StagePlan::plane`]
/// cycles later.
pub fn plane_module(cfg: &Config, plan: &StagePlan) -> Arc<Module> {
    let (f, pf, cf) = (cfg.ray, cfg.plane, cfg.crossing());
    let mut m = ModuleBuilder::new(plane_name(cfg, plan));
    m.describe(
        "One cull plane: D = RUP(w - no_lo) (w widened exactly into the ray format), \
         q = RUP(D * (D > 0 ? rcp_hi : rcp_lo)) from the exact product of a ray-format and a \
         crossing-format significand; dist_neg = D < 0.",
    );
    m.param("exp_bits", f.exp_bits)
        .param("frac_bits", f.frac_bits)
        .param("plane_exp_bits", pf.exp_bits)
        .param("plane_frac_bits", pf.frac_bits)
        .param("stages", plan.plane());
    let w = m.input("w", Ty::UInt(pf.width()));
    let no_lo = m.input("no_lo", Ty::UInt(f.width()));
    let rcp_lo = m.input("rcp_lo", Ty::UInt(cf.width()));
    let rcp_hi = m.input("rcp_hi", Ty::UInt(cf.width()));
    let wf = widen(&mut m, pf, f, w, "u_widen");
    for _ in 0..plan.widen {
        m.stage();
    }
    let sum = add_raw(&mut m, f, wf, no_lo, true, &plan.add_raw);
    let raw = sum.for_mode(&mut m, Rounding::Rup);
    let d = round(
        &mut m,
        f,
        Rounding::Rup,
        &raw,
        plan.add_round,
        "u_round_dist",
    );
    for _ in 0..plan.add_round {
        m.stage();
    }
    let d = m.name(d, "dist_up");
    let pos = is_pos(&mut m, f, d);
    let neg = is_neg(&mut m, f, d);
    let rcp = m.mux(pos, rcp_hi, rcp_lo);
    let rcp = m.name(rcp, "rcp");
    let raw = mul_mixed_raw(&mut m, f, cf, d, rcp, plan.mul_raw, "u_mul");
    let q = round(&mut m, f, Rounding::Rup, &raw, plan.mul_round, "u_round_q");
    for _ in 0..plan.mul_round {
        m.stage();
    }
    m.output("q", q);
    m.output("dist_neg", neg);
    Arc::new(
        m.finish()
            .expect("cull plane generator is type-correct for every accepted configuration"),
    )
}

/// Module name of `cull`, e.g. `cull_e8m23_pe5m10_k4_s4`.
pub fn cull_name(cfg: &Config) -> String {
    format!("cull_{}", cfg.tag())
}

/// Builds the per-child tester.
pub fn build(cfg: &Config) -> Module {
    let (f, pf, cf) = (cfg.ray, cfg.plane, cfg.crossing());
    let k = cfg.k as usize;
    let plan = StagePlan::new(cfg.stages);
    let mut m = ModuleBuilder::with_handshake(cull_name(cfg));
    m.describe(
        "Cull-plane tester, per child (docs/cull.md): keep = the ray segment [t_lo, t_hi] (the box \
         interval) may meet the part of the child's box on the non-empty side of every plane \
         n.(x - r) <= w (keep = 0 culls the child); invalid = a NaN input, an infinite distance or \
         no_lo = +inf (then keep = 1). Per plane D = RUP(w - no_lo), q = RUP(D * rcp), exits lower \
         the exit, entries raise the entry; every rounding widens the interval.",
    );
    cfg.describe_params(&mut m);
    let ports: Vec<Sig> = cfg
        .child_inputs()
        .iter()
        .map(|(name, w)| m.input(name, Ty::UInt(*w)))
        .collect();
    let at = cfg.child_ports();
    let t_lo = ports[at.t_lo];
    let t_hi = ports[at.t_hi];
    let w: Vec<Sig> = at.w.iter().map(|&i| ports[i]).collect();
    let term = |j: usize, t: TermField| ports[at.term(j, t)];

    // Step 1: classify.
    let mut bad = vec![is_nan(&mut m, f, t_lo), is_nan(&mut m, f, t_hi)];
    let pinf = m.uint(f.width(), f.inf_bits());
    for j in 0..k {
        bad.push(is_special(&mut m, pf, w[j]));
        let no_lo = term(j, TermField::NoLo);
        bad.push(is_nan(&mut m, f, no_lo));
        bad.push(m.eq(no_lo, pinf));
        bad.push(is_nan(&mut m, cf, term(j, TermField::RcpLo)));
        bad.push(is_nan(&mut m, cf, term(j, TermField::RcpHi)));
    }
    let invalid = any_of(&mut m, &bad, "invalid");
    let t_lo_neg = is_neg(&mut m, f, t_lo);
    let planes_on = m.not(t_lo_neg);
    let planes_on = m.name(planes_on, "planes_on");

    // Steps 2 and 3, per plane: D, the pick of the reciprocal, q.
    let block = plane_module(cfg, &plan);
    let mut qs = Vec::new();
    let mut par = Vec::new();
    for j in 0..k {
        let out = m.instance(
            &format!("u_plane{j}"),
            &block,
            &[
                ("w", w[j]),
                ("no_lo", term(j, TermField::NoLo)),
                ("rcp_lo", term(j, TermField::RcpLo)),
                ("rcp_hi", term(j, TermField::RcpHi)),
            ],
        );
        qs.push(out.get("q").expect("q"));
        let dir = term(j, TermField::Dir);
        let c_exit = m.uint(DIR_WIDTH, DIR_EXIT);
        let c_entry = m.uint(DIR_WIDTH, DIR_ENTRY);
        let is_exit = m.eq(dir, c_exit);
        let is_entry = m.eq(dir, c_entry);
        par.push((out.get("dist_neg").expect("dist_neg"), is_exit, is_entry));
    }
    for _ in 0..plan.plane() {
        m.stage();
    }
    let par: Vec<(Sig, Sig, Sig)> = par
        .into_iter()
        .enumerate()
        .map(|(j, (neg, is_exit, is_entry))| {
            let crossing = m.or(is_exit, is_entry);
            let parallel = m.not(crossing);
            let pc = m.and(parallel, neg);
            (m.name(pc, &format!("par_cull{j}")), is_exit, is_entry)
        })
        .collect();

    // Step 4: every bound of the entry against every bound of the exit.
    // `keep` needs max(entries) <= min(exits), i.e. l <= h for each pair;
    // one entry -q_i against one exit q_j is -q_i <= q_j, which is
    // -q_j <= q_i: one comparison per pair of planes, whichever is the
    // exit. A pair that does not apply, and an invalid input, pass.
    let lo = Bound::of(&mut m, f, t_lo);
    let hi = Bound::of(&mut m, f, t_hi);
    let mut ok = vec![lo.le(&mut m, &hi, invalid, "box_ok")];
    let mut planes = Vec::new();
    for j in 0..k {
        let q = m.name(qs[j], &format!("q{j}"));
        let (pc, is_exit, is_entry) = par[j];
        let nan = is_nan(&mut m, f, q);
        let usable = m.not(nan);
        let usable = m.and(usable, planes_on);
        let ex = m.and(is_exit, usable);
        let ex = m.name(ex, &format!("exit{j}"));
        let en = m.and(is_entry, usable);
        let en = m.name(en, &format!("entry{j}"));
        let exit = Bound::of(&mut m, f, q);
        let entry = exit.negated(&mut m);
        let skip = unless(&mut m, ex, invalid);
        ok.push(lo.le(&mut m, &exit, skip, &format!("exit{j}_ok")));
        let skip = unless(&mut m, en, invalid);
        ok.push(entry.le(&mut m, &hi, skip, &format!("entry{j}_ok")));
        let pc = m.and(pc, planes_on);
        let npc = m.not(pc);
        ok.push(m.or(npc, invalid));
        planes.push((ex, en, exit, entry));
    }
    for j in 0..k {
        for i in 0..j {
            let (ex_i, en_i, _, entry_i) = planes[i];
            let (ex_j, en_j, exit_j, _) = planes[j];
            let ij = m.and(en_i, ex_j);
            let ji = m.and(en_j, ex_i);
            let pair = m.or(ij, ji);
            let skip = unless(&mut m, pair, invalid);
            ok.push(entry_i.le(&mut m, &exit_j, skip, &format!("pair{i}{j}_ok")));
        }
    }

    // Step 5: the verdict.
    let keep = all_of(&mut m, &ok, "keep_all");
    for _ in 0..plan.out {
        m.stage();
    }
    for (name, v) in CHILD_OUTPUT_NAMES.into_iter().zip([keep, invalid]) {
        m.output(name, v);
    }
    m.finish()
        .expect("cull generator is type-correct for every accepted configuration")
}

impl Description for Cull {
    type Config = Config;
    const NAME: &'static str = "cull";
    const SUMMARY: &'static str = "cull-plane tester per child: box interval folded with K planes' crossings from the parent's ray terms (keep, invalid)";
    const PARAMS: &'static [ParamSpec] = PARAMS;
    fn config(&self, p: &Params) -> Result<Config, ParamError> {
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

    #[test]
    fn ports_by_name_cover_every_port_once() {
        for k in 1..=8 {
            let c = cfg(k);
            let at = c.child_ports();
            let mut seen: Vec<usize> = [at.t_lo, at.t_hi].into();
            seen.extend(&at.w);
            seen.extend(at.terms.iter().flatten());
            seen.sort_unstable();
            assert_eq!(seen, (0..c.child_inputs().len()).collect::<Vec<_>>());
            assert_eq!(
                c.child_inputs()[at.term(k as usize - 1, TermField::Dir)].0,
                format!("dir{}", k - 1)
            );
            let at = c.ray_ports();
            let mut seen: Vec<usize> = at.o.into_iter().chain(at.d).chain(at.r).collect();
            seen.extend(at.n.iter().flatten());
            seen.sort_unstable();
            assert_eq!(seen, (0..c.ray_inputs().len()).collect::<Vec<_>>());
            let mut outs: Vec<usize> = at.terms.iter().flatten().copied().collect();
            outs.sort_unstable();
            assert_eq!(outs, (0..c.ray_outputs().len()).collect::<Vec<_>>());
        }
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

    #[test]
    fn module_ports_follow_the_layout() {
        let c = cfg(4);
        let m = build(&c);
        let names: Vec<(String, u32)> = m
            .data_inputs()
            .iter()
            .map(|p| (p.name.clone(), p.ty.width()))
            .collect();
        assert_eq!(names, c.child_inputs());
        assert_eq!(m.name, "cull_e8m23_pe5m10_k4_s4");
        assert_eq!(m.latency, 4);
    }
}
