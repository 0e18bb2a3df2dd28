//! The float operator units (`funpack`, `fadd`, `fadd_down_up`, `fmul`,
//! `fmul_exact`, `fcmp`, `fminmax`, `fcvt`, `ffma`, `fdot3`, `frecip`): one
//! description each ([`FloatOp`]: name, summary, parameters, the operator
//! of [`crate::arith::float`] it instantiates), the same handshake wrapper
//! around each ([`wrap`]); the latency is the operator's `stages`.

use super::Unit;
use crate::arith::float::{
    add, add_down_up, compare, convert, dot3, fma, minmax, mul, mul_exact, unpack, Format,
    RoundSel, Rounding,
};
use crate::arith::recip::recip_module;
use crate::builder::ModuleBuilder;
use crate::ir::Module;
use crate::params::{ParamError, ParamKind, ParamSpec, Params};
use std::sync::Arc;

/// A float operator as a unit: its parameters and the operator module it
/// wraps with the handshake.
pub struct FloatOp {
    /// unit name
    pub name: &'static str,
    /// one line for `rtl-gen list`
    pub summary: &'static str,
    /// the parameters
    pub params: &'static [ParamSpec],
    /// the operator module for checked parameters and their format
    /// (`exp_bits`, `frac_bits`)
    pub operator: fn(&Params, Format) -> Result<Arc<Module>, ParamError>,
}

impl Unit for FloatOp {
    fn name(&self) -> &'static str {
        self.name
    }
    fn summary(&self) -> &'static str {
        self.summary
    }
    fn params(&self) -> &'static [ParamSpec] {
        self.params
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        let fmt = format(p, self.name)?;
        Ok(wrap((self.operator)(p, fmt)?))
    }
}

fn stages(p: &Params) -> u32 {
    p.u32("stages")
}

/// `funpack`.
pub static FUNPACK: FloatOp = FloatOp {
    name: "funpack",
    summary: "float unpack/classify: sign, class (0 zero, 1 finite, 2 inf, 3 NaN), exponent of the lsb, significand",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    operator: |p, f| Ok(unpack::unpack_module(f, stages(p))),
};

/// `fadd`: `a + b`, or `a - b` with `op=sub`.
pub static FADD: FloatOp = FloatOp {
    name: "fadd",
    summary: "float a + b or a - b, rounded once",
    params: &[
        EXP_BITS,
        FRAC_BITS,
        ROUND,
        ParamSpec {
            name: "op",
            doc: "add: a + b; sub: a - b",
            kind: ParamKind::Choice(&["add", "sub"]),
            default: "add",
        },
        STAGES,
    ],
    operator: |p, f| {
        let sub = p.word("op") == "sub";
        Ok(add::add_module(f, rounding(p), sub, stages(p)))
    },
};

/// `fadd_down_up`.
pub static FADD_DOWN_UP: FloatOp = FloatOp {
    name: "fadd_down_up",
    summary: "float a + b rounded toward -inf (down) and +inf (up) from one exact sum",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    operator: |p, f| Ok(add_down_up::add_down_up_module(f, stages(p))),
};

/// `fmul`.
pub static FMUL: FloatOp = FloatOp {
    name: "fmul",
    summary: "float a * b, rounded once",
    params: &[EXP_BITS, FRAC_BITS, ROUND, STAGES],
    operator: |p, f| Ok(mul::mul_module(f, rounding(p), stages(p))),
};

/// `fmul_exact`.
pub static FMUL_EXACT: FloatOp = FloatOp {
    name: "fmul_exact",
    summary: "exact float product a * b as a value of the format (E + 2, 2F + 1)",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    operator: |p, f| {
        mul_exact::exact_product_format(f)
            .map_err(|e| ParamError::Combination(format!("fmul_exact: {e}")))?;
        Ok(mul_exact::mul_exact_module(f, stages(p)))
    },
};

/// `fcmp`.
pub static FCMP: FloatOp = FloatOp {
    name: "fcmp",
    summary: "float comparisons lt, le, eq (IEEE quiet: NaN unordered, -0 == +0)",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    operator: |p, f| Ok(compare::compare_module(f, stages(p))),
};

/// `fminmax`.
pub static FMINMAX: FloatOp = FloatOp {
    name: "fminmax",
    summary: "float minimum and maximum (IEEE 754-2019: NaN if either is NaN, -0 < +0)",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    operator: |p, f| Ok(minmax::min_max_module(f, stages(p))),
};

/// `fcvt`: from (`exp_bits`, `frac_bits`) to (`to_exp_bits`, `to_frac_bits`).
pub static FCVT: FloatOp = FloatOp {
    name: "fcvt",
    summary: "float format conversion, rounded once",
    params: &[
        EXP_BITS,
        FRAC_BITS,
        ParamSpec {
            name: "to_exp_bits",
            doc: "exponent bits of the result format",
            kind: ParamKind::Int { min: 2, max: 11 },
            default: "5",
        },
        ParamSpec {
            name: "to_frac_bits",
            doc: "fraction bits of the result format",
            kind: ParamKind::Int { min: 1, max: 52 },
            default: "10",
        },
        ROUND,
        STAGES,
    ],
    operator: |p, from| {
        let to = format_of(p, "fcvt", "to_exp_bits", "to_frac_bits")?;
        Ok(convert::convert_module(from, to, rounding(p), stages(p)))
    },
};

/// `ffma`.
pub static FFMA: FloatOp = FloatOp {
    name: "ffma",
    summary: "fused float multiply-add a * b + c, rounded once",
    params: &[EXP_BITS, FRAC_BITS, ROUND, STAGES],
    operator: |p, f| Ok(fma::fma_module(f, rounding(p), stages(p))),
};

/// `fdot3`.
pub static FDOT3: FloatOp = FloatOp {
    name: "fdot3",
    summary: "fused float dot product a0*b0 + a1*b1 + a2*b2, exact, rounded once",
    params: &[EXP_BITS, FRAC_BITS, ROUND, STAGES],
    operator: |p, f| Ok(dot3::dot3_module(f, rounding(p), stages(p))),
};

/// `round` of `frecip`: the four modes (no `dyn`).
const RECIP_ROUND: ParamSpec = ParamSpec {
    name: "round",
    doc: "rounding mode: to nearest even, toward zero, toward +inf, toward -inf",
    kind: ParamKind::Choice(Rounding::WORDS),
    default: "rne",
};

/// The rounding mode of `frecip`'s `round`.
pub fn recip_mode(p: &Params) -> Rounding {
    Rounding::parse(p.word("round")).expect("round is a declared choice")
}

/// `frecip`: the slab tester's per-ray reciprocal, so its cost can be
/// charted beside the box test (issue #19).
pub static FRECIP: FloatOp = FloatOp {
    name: "frecip",
    summary: "float 1 / x, rounded once (restoring division)",
    params: &[EXP_BITS, FRAC_BITS, RECIP_ROUND, STAGES],
    operator: |p, f| Ok(recip_module(f, recip_mode(p), stages(p))),
};

/// `exp_bits`: E.
pub const EXP_BITS: ParamSpec = ParamSpec {
    name: "exp_bits",
    doc: "exponent bits E (2..=11)",
    kind: ParamKind::Int { min: 2, max: 11 },
    default: "8",
};

/// `frac_bits`: F.
pub const FRAC_BITS: ParamSpec = ParamSpec {
    name: "frac_bits",
    doc: "fraction bits F (1 + E + F <= 64)",
    kind: ParamKind::Int { min: 1, max: 52 },
    default: "23",
};

/// `round`: the rounding mode.
pub const ROUND: ParamSpec = ParamSpec {
    name: "round",
    doc: "rounding mode: to nearest even, toward zero, toward +inf, toward -inf, or dyn (a 2-bit input rm: 0 rne, 1 rtz, 2 rdn, 3 rup)",
    kind: ParamKind::Choice(RoundSel::WORDS),
    default: "rne",
};

/// `stages`: pipeline registers (latency).
pub const STAGES: ParamSpec = ParamSpec {
    name: "stages",
    doc: "pipeline stages (latency in cycles), spread over the operator's steps",
    kind: ParamKind::Int { min: 0, max: 32 },
    default: "2",
};

/// The format of `exp_bits`/`frac_bits` (or the keys given), or why it is unsupported.
pub fn format_of(
    p: &Params,
    unit: &str,
    exp_key: &str,
    frac_key: &str,
) -> Result<Format, ParamError> {
    Format::new(p.u32(exp_key), p.u32(frac_key))
        .map_err(|e| ParamError::Combination(format!("{unit}: {e}")))
}

/// The format of `exp_bits` and `frac_bits`.
pub fn format(p: &Params, unit: &str) -> Result<Format, ParamError> {
    format_of(p, unit, "exp_bits", "frac_bits")
}

/// The rounding mode of `round` (fixed, or the `rm` port for `dyn`).
pub fn rounding(p: &Params) -> RoundSel {
    RoundSel::parse(p.word("round")).expect("round is a declared choice")
}

/// A top module `<op>_top` with the handshake around the operator `op`:
/// the same data ports, latency `op.latency`.
pub fn wrap(op: Arc<Module>) -> Module {
    let mut m = ModuleBuilder::with_handshake(format!("{}_top", op.name));
    m.describe(format!(
        "{} With the in_valid/out_valid handshake.",
        op.description
    ));
    for (k, v) in &op.params {
        m.param(k.clone(), v);
    }
    let ins: Vec<_> = op
        .inputs
        .iter()
        .map(|p| (p.name.clone(), m.input(&p.name, p.ty)))
        .collect();
    let conn: Vec<(&str, _)> = ins.iter().map(|(n, s)| (n.as_str(), *s)).collect();
    let outs = m.instance("u_op", &op, &conn);
    let outs: Vec<_> = op
        .outputs
        .iter()
        .map(|(p, _)| (p.name.clone(), outs.get(&p.name).expect("operator output")))
        .collect();
    for _ in 0..op.latency {
        m.stage();
    }
    for (n, s) in outs {
        m.output(&n, s);
    }
    m.finish()
        .expect("wrapper is type-correct for every operator")
}
