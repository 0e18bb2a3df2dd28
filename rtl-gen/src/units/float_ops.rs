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

/// A float operator as a unit: its parameters, their one parse into a
/// [`FloatConfig`], and the operator module it wraps with the handshake.
pub struct FloatOp {
    /// unit name
    pub name: &'static str,
    /// one line for `rtl-gen list`
    pub summary: &'static str,
    /// the parameters
    pub params: &'static [ParamSpec],
    /// the operator's own parameters (besides format and stages)
    pub op: fn(&Params) -> Result<OpConfig, ParamError>,
}

/// A float operator's configuration, parsed once from its parameters; the
/// testbench (`rtl_flow::float_ops`) takes the same value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FloatConfig {
    /// the operands' format (`fcvt`: the source format)
    pub fmt: Format,
    /// pipeline stages
    pub stages: u32,
    /// the operator and its own parameters
    pub op: OpConfig,
}

/// Which operator, with the parameters only it has (`round`: the rounding
/// mode, fixed or the `rm` input).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpConfig {
    /// `funpack`
    Unpack,
    /// `fadd`
    Add {
        /// rounding
        round: RoundSel,
        /// `a - b` instead of `a + b`
        sub: bool,
    },
    /// `fadd_down_up`
    AddDownUp,
    /// `fmul`
    Mul {
        /// rounding
        round: RoundSel,
    },
    /// `fmul_exact`
    MulExact,
    /// `fcmp`
    Cmp,
    /// `fminmax`
    MinMax,
    /// `fcvt`
    Cvt {
        /// the result format
        to: Format,
        /// rounding
        round: RoundSel,
    },
    /// `ffma`
    Fma {
        /// rounding
        round: RoundSel,
    },
    /// `fdot3`
    Dot3 {
        /// rounding
        round: RoundSel,
    },
    /// `frecip`
    Recip {
        /// the fixed rounding mode (no `rm` input)
        round: Rounding,
    },
}

impl OpConfig {
    /// The rounding of an operator that rounds once in a mode chosen by
    /// `round` (fixed, or the `rm` input); `None` for the others.
    pub fn round(&self) -> Option<RoundSel> {
        match *self {
            OpConfig::Add { round, .. }
            | OpConfig::Mul { round }
            | OpConfig::Cvt { round, .. }
            | OpConfig::Fma { round }
            | OpConfig::Dot3 { round } => Some(round),
            _ => None,
        }
    }
}

impl FloatOp {
    /// The configuration of resolved parameters, or why they are impossible.
    pub fn config(&self, p: &Params) -> Result<FloatConfig, ParamError> {
        Ok(FloatConfig {
            fmt: format(p, self.name)?,
            stages: p.u32("stages"),
            op: (self.op)(p)?,
        })
    }
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
        Ok(wrap(operator(&self.config(p)?)?))
    }
}

/// The operator module of a configuration.
fn operator(c: &FloatConfig) -> Result<Arc<Module>, ParamError> {
    let (f, s) = (c.fmt, c.stages);
    Ok(match c.op {
        OpConfig::Unpack => unpack::unpack_module(f, s),
        OpConfig::Add { round, sub } => add::add_module(f, round, sub, s),
        OpConfig::AddDownUp => add_down_up::add_down_up_module(f, s),
        OpConfig::Mul { round } => mul::mul_module(f, round, s),
        OpConfig::MulExact => {
            mul_exact::exact_product_format(f)
                .map_err(|e| ParamError::Combination(format!("fmul_exact: {e}")))?;
            mul_exact::mul_exact_module(f, s)
        }
        OpConfig::Cmp => compare::compare_module(f, s),
        OpConfig::MinMax => minmax::min_max_module(f, s),
        OpConfig::Cvt { to, round } => convert::convert_module(f, to, round, s),
        OpConfig::Fma { round } => fma::fma_module(f, round, s),
        OpConfig::Dot3 { round } => dot3::dot3_module(f, round, s),
        OpConfig::Recip { round } => recip_module(f, round, s),
    })
}

/// `funpack`.
pub static FUNPACK: FloatOp = FloatOp {
    name: "funpack",
    summary: "float unpack/classify: sign, class (0 zero, 1 finite, 2 inf, 3 NaN), exponent of the lsb, significand",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    op: |_| Ok(OpConfig::Unpack),
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
    op: |p| {
        Ok(OpConfig::Add {
            round: rounding(p),
            sub: p.word("op") == "sub",
        })
    },
};

/// `fadd_down_up`.
pub static FADD_DOWN_UP: FloatOp = FloatOp {
    name: "fadd_down_up",
    summary: "float a + b rounded toward -inf (down) and +inf (up) from one exact sum",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    op: |_| Ok(OpConfig::AddDownUp),
};

/// `fmul`.
pub static FMUL: FloatOp = FloatOp {
    name: "fmul",
    summary: "float a * b, rounded once",
    params: &[EXP_BITS, FRAC_BITS, ROUND, STAGES],
    op: |p| Ok(OpConfig::Mul { round: rounding(p) }),
};

/// `fmul_exact`.
pub static FMUL_EXACT: FloatOp = FloatOp {
    name: "fmul_exact",
    summary: "exact float product a * b as a value of the format (E + 2, 2F + 1)",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    op: |_| Ok(OpConfig::MulExact),
};

/// `fcmp`.
pub static FCMP: FloatOp = FloatOp {
    name: "fcmp",
    summary: "float comparisons lt, le, eq (IEEE quiet: NaN unordered, -0 == +0)",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    op: |_| Ok(OpConfig::Cmp),
};

/// `fminmax`.
pub static FMINMAX: FloatOp = FloatOp {
    name: "fminmax",
    summary: "float minimum and maximum (IEEE 754-2019: NaN if either is NaN, -0 < +0)",
    params: &[EXP_BITS, FRAC_BITS, STAGES],
    op: |_| Ok(OpConfig::MinMax),
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
    op: |p| {
        Ok(OpConfig::Cvt {
            to: format_of(p, "fcvt", "to_exp_bits", "to_frac_bits")?,
            round: rounding(p),
        })
    },
};

/// `ffma`.
pub static FFMA: FloatOp = FloatOp {
    name: "ffma",
    summary: "fused float multiply-add a * b + c, rounded once",
    params: &[EXP_BITS, FRAC_BITS, ROUND, STAGES],
    op: |p| Ok(OpConfig::Fma { round: rounding(p) }),
};

/// `fdot3`.
pub static FDOT3: FloatOp = FloatOp {
    name: "fdot3",
    summary: "fused float dot product a0*b0 + a1*b1 + a2*b2, exact, rounded once",
    params: &[EXP_BITS, FRAC_BITS, ROUND, STAGES],
    op: |p| Ok(OpConfig::Dot3 { round: rounding(p) }),
};

/// `round` of `frecip`: the four modes (no `dyn`).
const RECIP_ROUND: ParamSpec = ParamSpec {
    name: "round",
    doc: "rounding mode: to nearest even, toward zero, toward +inf, toward -inf",
    kind: ParamKind::Choice(Rounding::WORDS),
    default: "rne",
};

/// `frecip`: the slab tester's per-ray reciprocal, so its cost can be
/// charted beside the box test (issue #19).
pub static FRECIP: FloatOp = FloatOp {
    name: "frecip",
    summary: "float 1 / x, rounded once (restoring division)",
    params: &[EXP_BITS, FRAC_BITS, RECIP_ROUND, STAGES],
    op: |p| {
        Ok(OpConfig::Recip {
            round: Rounding::parse(p.word("round")).expect("round is a declared choice"),
        })
    },
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
fn rounding(p: &Params) -> RoundSel {
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
    let outs = m.instance("u_op", &op, &ins);
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
