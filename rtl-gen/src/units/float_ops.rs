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
use crate::params::{ParamError, ParamSet, ParamSpec, Params};
use std::sync::Arc;

/// A float operator as a unit: its typed parameters `P` (one of the tables
/// below), their one check into a [`FloatConfig`], and the operator module
/// it wraps with the handshake.
pub struct FloatOp<P: 'static> {
    /// unit name
    pub name: &'static str,
    /// one line for `rtl-gen list`
    pub summary: &'static str,
    /// the operator and its own parameters (besides format and stages)
    pub op: fn(&P) -> Result<OpConfig, ParamError>,
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

impl<P: FloatParams> FloatOp<P> {
    /// The configuration of typed parameters, or why they are impossible.
    pub fn config(&self, p: &P) -> Result<FloatConfig, ParamError> {
        let (exp_bits, frac_bits, stages) = p.format_and_stages();
        Ok(FloatConfig {
            fmt: format(exp_bits, frac_bits, self.name)?,
            stages,
            op: (self.op)(p)?,
        })
    }

    /// The configuration of checked parameters.
    pub fn configured(&self, p: &Params) -> Result<FloatConfig, ParamError> {
        self.config(&P::from_params(p))
    }
}

impl<P: FloatParams> Unit for FloatOp<P> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn summary(&self) -> &'static str {
        self.summary
    }
    fn params(&self) -> &'static [ParamSpec] {
        P::SPECS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        self.build_typed(P::from_params(p))
    }
    fn build_datapath(&self, p: &Params) -> Result<Option<Module>, ParamError> {
        let mut typed = P::from_params(p);
        match typed.stages_mut() {
            Some(stages) => *stages = 0,
            None => return Ok(None),
        }
        self.build_typed(typed).map(Some)
    }
}

impl<P: FloatParams> FloatOp<P> {
    /// The wrapped operator of typed parameters, its header written from
    /// them (every parameter, `fadd`'s `op` too).
    fn build_typed(&self, p: P) -> Result<Module, ParamError> {
        let mut module = wrap(operator(&self.config(&p)?)?);
        module.params = p.header();
        Ok(module)
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

/// The rows every float operator has (its format, then its own rows, then
/// `stages`), written once; each table implements [`FloatParams`].
macro_rules! float_op_params {
    ($(#[$meta:meta])* $name:ident { $($own:tt)* }) => {
        crate::params! {
            $(#[$meta])*
            pub struct $name {
                /// exponent bits E (2..=11)
                exp_bits: u32 [2..=11] = 8,
                /// fraction bits F (1 + E + F <= 64)
                frac_bits: u32 [1..=52] = 23,
                $($own)*
                /// pipeline stages (latency in cycles), spread over the operator's steps
                stages: u32 [0..=32] = 2,
            }
        }
        impl FloatParams for $name {
            fn format_and_stages(&self) -> (u32, u32, u32) {
                (self.exp_bits, self.frac_bits, self.stages)
            }
        }
    };
}

/// A float operator's parameters: the format and depth every one has.
pub trait FloatParams: ParamSet {
    /// `exp_bits`, `frac_bits`, `stages`
    fn format_and_stages(&self) -> (u32, u32, u32);
}

float_op_params! {
    /// Parameters of an operator with no rounding of its own.
    FormatParams {}
}

float_op_params! {
    /// Parameters of an operator that rounds once.
    RoundedParams {
        /// rounding mode: to nearest even, toward zero, toward +inf, toward -inf, or dyn (a
        /// 2-bit input rm: 0 rne, 1 rtz, 2 rdn, 3 rup)
        round: RoundSel = RoundSel::Fixed(Rounding::Rne),
    }
}

crate::choice! {
    /// `fadd`'s operation.
    pub enum AddOp {
        /// a + b
        Add = "add",
        /// a - b
        Sub = "sub",
    }
}

float_op_params! {
    /// `fadd`'s parameters.
    AddParams {
        /// rounding mode: to nearest even, toward zero, toward +inf, toward -inf, or dyn (a
        /// 2-bit input rm: 0 rne, 1 rtz, 2 rdn, 3 rup)
        round: RoundSel = RoundSel::Fixed(Rounding::Rne),
        /// add: a + b; sub: a - b
        op: AddOp = AddOp::Add,
    }
}

float_op_params! {
    /// `fcvt`'s parameters: the source format, the result format.
    CvtParams {
        /// exponent bits of the result format
        to_exp_bits: u32 [2..=11] = 5,
        /// fraction bits of the result format
        to_frac_bits: u32 [1..=52] = 10,
        /// rounding mode: to nearest even, toward zero, toward +inf, toward -inf, or dyn (a
        /// 2-bit input rm: 0 rne, 1 rtz, 2 rdn, 3 rup)
        round: RoundSel = RoundSel::Fixed(Rounding::Rne),
    }
}

float_op_params! {
    /// `frecip`'s parameters: the four fixed modes (no `dyn`).
    RecipParams {
        /// rounding mode: to nearest even, toward zero, toward +inf, toward -inf
        round: Rounding = Rounding::Rne,
    }
}

/// `funpack`.
pub static FUNPACK: FloatOp<FormatParams> = FloatOp {
    name: "funpack",
    summary: "float unpack/classify: sign, class (0 zero, 1 finite, 2 inf, 3 NaN), exponent of the lsb, significand",
    op: |_| Ok(OpConfig::Unpack),
};

/// `fadd`: `a + b`, or `a - b` with `op=sub`.
pub static FADD: FloatOp<AddParams> = FloatOp {
    name: "fadd",
    summary: "float a + b or a - b, rounded once",
    op: |p| {
        Ok(OpConfig::Add {
            round: p.round,
            sub: p.op == AddOp::Sub,
        })
    },
};

/// `fadd_down_up`.
pub static FADD_DOWN_UP: FloatOp<FormatParams> = FloatOp {
    name: "fadd_down_up",
    summary: "float a + b rounded toward -inf (down) and +inf (up) from one exact sum",
    op: |_| Ok(OpConfig::AddDownUp),
};

/// `fmul`.
pub static FMUL: FloatOp<RoundedParams> = FloatOp {
    name: "fmul",
    summary: "float a * b, rounded once",
    op: |p| Ok(OpConfig::Mul { round: p.round }),
};

/// `fmul_exact`.
pub static FMUL_EXACT: FloatOp<FormatParams> = FloatOp {
    name: "fmul_exact",
    summary: "exact float product a * b as a value of the format (E + 2, 2F + 1)",
    op: |_| Ok(OpConfig::MulExact),
};

/// `fcmp`.
pub static FCMP: FloatOp<FormatParams> = FloatOp {
    name: "fcmp",
    summary: "float comparisons lt, le, eq (IEEE quiet: NaN unordered, -0 == +0)",
    op: |_| Ok(OpConfig::Cmp),
};

/// `fminmax`.
pub static FMINMAX: FloatOp<FormatParams> = FloatOp {
    name: "fminmax",
    summary: "float minimum and maximum (IEEE 754-2019: NaN if either is NaN, -0 < +0)",
    op: |_| Ok(OpConfig::MinMax),
};

/// `fcvt`: from (`exp_bits`, `frac_bits`) to (`to_exp_bits`, `to_frac_bits`).
pub static FCVT: FloatOp<CvtParams> = FloatOp {
    name: "fcvt",
    summary: "float format conversion, rounded once",
    op: |p| {
        Ok(OpConfig::Cvt {
            to: format(p.to_exp_bits, p.to_frac_bits, "fcvt")?,
            round: p.round,
        })
    },
};

/// `ffma`.
pub static FFMA: FloatOp<RoundedParams> = FloatOp {
    name: "ffma",
    summary: "fused float multiply-add a * b + c, rounded once",
    op: |p| Ok(OpConfig::Fma { round: p.round }),
};

/// `fdot3`.
pub static FDOT3: FloatOp<RoundedParams> = FloatOp {
    name: "fdot3",
    summary: "fused float dot product a0*b0 + a1*b1 + a2*b2, exact, rounded once",
    op: |p| Ok(OpConfig::Dot3 { round: p.round }),
};

/// `frecip`: the slab tester's per-ray reciprocal, so its cost can be
/// charted beside the box test (issue #19).
pub static FRECIP: FloatOp<RecipParams> = FloatOp {
    name: "frecip",
    summary: "float 1 / x, rounded once (restoring division)",
    op: |p| Ok(OpConfig::Recip { round: p.round }),
};

/// The format of `exp_bits` and `frac_bits`, or why `unit` cannot have it.
pub fn format(exp_bits: u32, frac_bits: u32, unit: &str) -> Result<Format, ParamError> {
    Format::new(exp_bits, frac_bits).map_err(|e| ParamError::Combination(format!("{unit}: {e}")))
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
    for _ in 0..op.latency {
        m.stage();
    }
    for (name, value) in outs.named() {
        m.output(name, value);
    }
    m.finish()
        .expect("wrapper is type-correct for every operator")
}
