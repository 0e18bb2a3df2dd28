//! Parameters and the handshake wrapper shared by the float operator units
//! (`funpack`, `fadd`, `fadd_down_up`, `fmul`, `fmul_exact`, `fcmp`,
//! `fminmax`, `fcvt`, `ffma`, `fdot3`): each unit is one operator of
//! [`crate::arith::float`] instantiated in a top module with the
//! `in_valid`/`out_valid` handshake; the latency is the operator's `stages`.

use crate::arith::float::{Format, RoundSel};
use crate::builder::ModuleBuilder;
use crate::ir::Module;
use crate::params::{ParamError, ParamKind, ParamSpec, Params};
use std::sync::Arc;

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
