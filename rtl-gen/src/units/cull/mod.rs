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

use super::{port_at, port_at3, xyz, Description};
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
            v.extend(xyz(p).map(|n| (n, self.ray.width())));
        }
        for j in 0..self.k as usize {
            v.extend(xyz(&format!("n{j}")).map(|n| (n, self.plane.width())));
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

mod child;

pub use child::{build, cull_name, plane_module, plane_name, widen, StagePlan, PHASES};

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
